"""Fixtures of relief's Python tests: small deterministic terrains and the relief binary.

The binary is $RELIEF_BIN, else target/release/relief of this repository, built with
``cargo build --release -p relief-cli`` when it is missing.
"""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[3]


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
