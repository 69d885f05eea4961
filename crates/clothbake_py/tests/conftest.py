"""Shared fixtures: the clothbake binary of the same build (the Rust side of every
comparison) and directions in the cloth frame."""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


@pytest.fixture(scope="session")
def cli():
    """Runs a clothbake command with JSON lines in and out: the Rust library's answer."""
    binary = pathlib.Path(os.environ.get("CLOTHBAKE_BIN", ROOT / "target" / "ci" / "clothbake"))
    assert binary.is_file(), f"{binary}: build it first (scripts/test.sh does)"

    def run(args, records=None):
        text = "".join(json.dumps(r) + "\n" for r in records or [])
        done = subprocess.run(
            [str(binary), *args], input=text, capture_output=True, text=True, cwd=ROOT
        )
        assert done.returncode == 0, done.stderr
        return done.stdout

    return run


def unit_rows(rng, n, upper=False):
    """n directions uniform on the sphere (or on the upper hemisphere), shape (n, 3)."""
    w = rng.normal(size=(n, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    if upper:
        w[:, 2] = np.abs(w[:, 2])
    return w


@pytest.fixture
def rng():
    return np.random.default_rng(20261203)
