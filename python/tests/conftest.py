"""Shared by the Python module's tests: the articula binary, its CSVs, the real takes.

The tests compare the module with the command line, so they need the binary built from the
same sources: ARTICULA_BIN, else $CARGO_TARGET_DIR/release/articula (or target/release). No
binary is an error that says how to build one, never a skipped comparison.
"""

import csv
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
DEMO = REPO / "data" / "demo_walk.bvh"


def articula_bin() -> Path:
    given = os.environ.get("ARTICULA_BIN")
    if given:
        return Path(given)
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    return target / "release" / "articula"


@pytest.fixture(scope="session")
def cli():
    """Runs `articula ARGS…`; a failure fails the test with its standard error."""
    exe = articula_bin()
    if not exe.exists():
        pytest.fail(
            f"no articula binary at {exe}: `cargo build --release` first, or set ARTICULA_BIN"
        )

    def run(*args, check=True):
        p = subprocess.run(
            [str(exe), *map(str, args)], capture_output=True, text=True, cwd=REPO
        )
        if check and p.returncode != 0:
            pytest.fail(f"articula {' '.join(map(str, args))} failed:\n{p.stderr}")
        return p

    return run


def read_csv(path):
    """A CSV as (header, rows × columns float array): Python's float() reads the shortest
    round-trip numbers articula writes back to the same bits."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    values = np.array([[float(x) for x in r] for r in body], dtype=np.float64)
    return header, values.reshape(len(body), len(header))


def assert_same_table(result, path):
    """A Result equals the CLI's CSV at `path` bit for bit: columns, time and values."""
    header, values = read_csv(path)
    assert header[0] == "time"
    assert result.columns == header[1:]
    assert np.array_equal(result.time, values[:, 0])
    assert result.values.shape == values[:, 1:].shape
    # bit for bit: NaN where the CLI wrote NaN, every other number the same double
    assert np.array_equal(result.values, values[:, 1:], equal_nan=True)


def real_takes():
    """The shared takes of ARTICULA_REAL_TAKES (sorted), or [] when it is unset."""
    folder = os.environ.get("ARTICULA_REAL_TAKES")
    if not folder:
        return []
    takes = sorted(Path(folder).glob("*.bvh"))
    if not takes:
        raise RuntimeError(f"ARTICULA_REAL_TAKES={folder} holds no .bvh takes")
    return takes
