"""The skip accounting of conftest.py: with RELIEF_REQUIRE_CLIENTS=1 a session in which a test
was skipped fails; without it, the skip is reported as skipped and the session passes."""

import os
import subprocess
import sys
from pathlib import Path

TESTS = Path(__file__).resolve().parent


def _pytest(tmp_path, require):
    (tmp_path / "test_one_skip.py").write_text(
        "import pytest\n\n"
        "def test_runs():\n    pass\n\n"
        "def test_needs_a_client():\n"
        "    pytest.importorskip('relief_no_such_client_module')\n"
    )
    env = dict(os.environ, PYTHONPATH=str(TESTS), RELIEF_REQUIRE_CLIENTS=require)
    # This directory's conftest.py, loaded as a plugin by the run in tmp_path.
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "conftest", "-rs", "-p", "no:cacheprovider",
         str(tmp_path)],
        cwd=tmp_path, env=env, capture_output=True, text=True,
    )


def test_a_skip_is_reported_as_skipped(tmp_path):
    done = _pytest(tmp_path, "0")
    assert done.returncode == 0, done.stdout + done.stderr
    assert "1 passed, 1 skipped" in done.stdout, done.stdout


def test_a_skip_fails_the_session_when_clients_are_required(tmp_path):
    done = _pytest(tmp_path, "1")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "1 passed, 1 skipped" in done.stdout, done.stdout
    assert "RELIEF_REQUIRE_CLIENTS=1 requires their clients" in done.stdout, done.stdout
    assert "test_needs_a_client" in done.stdout, done.stdout
