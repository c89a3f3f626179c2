"""Shared helpers: the real command-line binary, the shipped studies, exact comparisons."""

import csv
import io
import json
import math
import os
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
STUDIES = sorted((REPO / "studies").glob("*.toml"))


def binary() -> Path:
    """The CLI binary built by `cargo build --release` (or $CRITSPEED_BIN)."""
    path = Path(os.environ.get("CRITSPEED_BIN", REPO / "target" / "release" / "critspeed"))
    if not path.is_file():
        pytest.fail(f"{path} does not exist: run `cargo build --release` first")
    return path


def cli(*args, cwd=None, check=True):
    """Runs the CLI; returns the completed process."""
    p = subprocess.run(
        [str(binary()), *map(str, args)], capture_output=True, text=True, cwd=cwd
    )
    if check and p.returncode != 0:
        pytest.fail(f"critspeed {' '.join(map(str, args))} failed: {p.stderr}")
    return p


def cli_json(*args, cwd=None):
    """The JSON object a CLI command prints."""
    return json.loads(cli(*args, cwd=cwd).stdout)


def same(a, b, where="$"):
    """Exact equality: same types (int/float/bool/str/None/list/dict), floats bit for bit."""
    assert type(a) is type(b), f"{where}: {type(a).__name__} vs {type(b).__name__}"
    if isinstance(a, float):
        assert struct.pack("<d", a) == struct.pack("<d", b), f"{where}: {a!r} vs {b!r}"
    elif isinstance(a, dict):
        assert a.keys() == b.keys(), f"{where}: keys {sorted(a)} vs {sorted(b)}"
        for k in a:
            same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), f"{where}: length {len(a)} vs {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{where}[{i}]")
    else:
        assert a == b, f"{where}: {a!r} vs {b!r}"


def read_csv(path: Path):
    """A CSV file the CLI wrote: (header, rows of strings), comment lines dropped."""
    text = "".join(l for l in io.StringIO(path.read_text()) if not l.startswith("#"))
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], rows[1:]


def same_as_csv(arrays, path: Path):
    """The arrays hold the CSV's columns, in order, with its length, cell for cell."""
    header, rows = read_csv(path)
    assert list(arrays) == header
    for j, name in enumerate(header):
        col = arrays[name]
        assert isinstance(col, np.ndarray), name
        assert len(col) == len(rows), name
        for i, row in enumerate(rows):
            cell, v = row[j], col[i]
            where = f"{path.name} row {i + 1} column {name}"
            if col.dtype == np.float64:
                want = math.nan if cell == "" else float(cell)
                if math.isnan(want):
                    assert math.isnan(v), where
                else:
                    assert struct.pack("<d", want) == struct.pack("<d", float(v)), where
            elif col.dtype == np.bool_:
                assert cell in ("true", "false") and bool(v) == (cell == "true"), where
            elif col.dtype == object:
                assert v == {"true": True, "false": False, "": None}[cell], where
            else:
                assert str(v) == cell, where
