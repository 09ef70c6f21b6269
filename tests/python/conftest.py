# tests/python/conftest.py — where the pytest suite finds the fortu binary, the sources and
# the shared data (set by CTest: tests/python/python.cmake), and helpers that run the binary.
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

SOURCE_DIR = Path(os.environ.get("FORTU_SOURCE_DIR", Path(__file__).resolve().parents[2]))
BINARY = os.environ.get("FORTU_BINARY", str(SOURCE_DIR / "build/release/fortu"))
SHARED_DATA = Path(os.environ.get("FORTU_SHARED_DIR", SOURCE_DIR / "tests/shared")) / "data"
EXAMPLES = SOURCE_DIR / "examples"


def run_fortu(*args, check=True):
    """The fortu command's stdout, stderr and exit status."""
    done = subprocess.run([BINARY, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"fortu {' '.join(map(str, args))} exited {done.returncode}: {done.stderr}")
    return done


def cli_eval(path, *point):
    """`fortu eval`'s value and gradient, parsed from its lines."""
    lines = dict(line.split(": ", 1) for line in run_fortu("eval", path, *map(repr, point)).stdout.splitlines())
    gradient = lines["gradient"]
    return float(lines["value"]), None if gradient.startswith("undefined") else [float(g) for g in gradient.split()]


def cli_grid(path, tmp_path, *options):
    """What `fortu run -o x.npy` writes."""
    out = tmp_path / "cli.npy"
    run_fortu("run", path, *options, "-o", out)
    return np.load(out)


def same_bits(a, b):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and np.array_equal(a.view(np.uint64), b.view(np.uint64))


@pytest.fixture
def shared_data():
    return SHARED_DATA
