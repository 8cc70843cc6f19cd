"""Fixtures of relief's Python tests: small deterministic terrains and the relief binary.

The binary is $RELIEF_BIN, else target/release/relief of this repository, built with
``cargo build --release -p relief-cli`` when it is missing.

A test whose client (rasterio, Pillow) is missing is skipped, and pytest reports it so
(``-rs`` lists the reasons). With RELIEF_REQUIRE_CLIENTS=1 (.ci/run sets it and installs the
clients) a session in which any test was skipped fails.
"""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]

_skipped = []


def pytest_runtest_logreport(report):
    """Notes every skipped test (an expected failure, xfail, is not a skip)."""
    if report.skipped and not hasattr(report, "wasxfail"):
        reason = report.longrepr[2] if isinstance(report.longrepr, tuple) else report.longrepr
        _skipped.append(f"{report.nodeid}: {reason}")


def pytest_sessionfinish(session, exitstatus):
    """With RELIEF_REQUIRE_CLIENTS=1, fails a session in which any test was skipped."""
    if os.environ.get("RELIEF_REQUIRE_CLIENTS") != "1" or not _skipped:
        return
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None:
        reporter.ensure_newline()
        reporter.write_line(
            f"{len(_skipped)} test(s) skipped, and RELIEF_REQUIRE_CLIENTS=1 requires their "
            "clients (.ci/run installs them):",
            red=True,
        )
        for line in _skipped:
            reporter.write_line(f"  {line}")
    if session.exitstatus == pytest.ExitCode.OK:
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


def hills(rows=40, cols=48):
    """A north-up float32 terrain of sines and a bump, 0 to about 12 units high."""
    r, c = np.mgrid[0:rows, 0:cols].astype(np.float64)
    h = 4.0 + 2.0 * np.sin(c / 5.0) * np.cos(r / 7.0)
    h += 6.0 * np.exp(-((c - 0.6 * cols) ** 2 + (r - 0.3 * rows) ** 2) / 60.0)
    return h.astype(np.float32)


@pytest.fixture
def terrain():
    return hills()


@pytest.fixture(scope="session")
def relief_bin():
    """Path of the relief command-line binary, built when needed."""
    path = Path(os.environ.get("RELIEF_BIN", ROOT / "target" / "release" / "relief"))
    if not path.exists():
        subprocess.run(
            ["cargo", "build", "--release", "--locked", "-p", "relief-cli"], cwd=ROOT, check=True
        )
    return path


@pytest.fixture
def run_relief(relief_bin):
    """Runs ``relief ARGS`` and returns the completed process (stderr as text)."""

    def run(*args, check=True):
        done = subprocess.run(
            [str(relief_bin), *map(str, args)], capture_output=True, text=True
        )
        if check and done.returncode != 0:
            raise AssertionError(f"relief {' '.join(map(str, args))} failed: {done.stderr}")
        return done

    return run
