"""Shared helpers: the repository, the `dem2d` command line the Python runs are compared with,
and cases made small enough for a test."""

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def cli_path():
    """The `dem2d` binary: $DEM2D_BIN, else the release build of this repository (`cargo build
    --release`, which `cargo test --release` does first in CI)."""
    path = Path(os.environ.get("DEM2D_BIN", ROOT / "target" / "release" / "dem2d"))
    if not path.exists():
        pytest.fail(f"{path}: no dem2d binary; run `cargo build --release` or set DEM2D_BIN")
    return path


def cli(*args, check=True):
    """Runs `dem2d ARGS`; returns (exit code, stdout, stderr)."""
    p = subprocess.run(
        [str(cli_path()), *map(str, args)], capture_output=True, text=True, timeout=600
    )
    if check and p.returncode != 0:
        raise AssertionError(f"dem2d {' '.join(map(str, args))}: exit {p.returncode}: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


def case_dict(name):
    """A shipped case as a dict."""
    return json.loads((ROOT / "cases" / name).read_text(encoding="utf-8"))


@pytest.fixture
def root():
    return ROOT
