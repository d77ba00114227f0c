"""Fixtures: the command-line binary the Python results are compared with."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _binary() -> pathlib.Path:
    target = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return pathlib.Path(os.environ.get("STICKSLIP_BIN", target / "release" / "stickslip"))


@pytest.fixture(scope="session")
def cli(tmp_path_factory):
    """Runs `stickslip ARGS --json` and returns the parsed JSON (and the
    exit status), with its files in a temporary directory."""
    binary = _binary()
    if not binary.exists():
        pytest.fail(f"{binary} not built: run `cargo build --release` first (scripts/test does)")
    out = tmp_path_factory.mktemp("cli-out")

    def run(*args: str, expect: int = 0):
        cmd = [str(binary), *args, "--json"]
        if args[0] in ("cycles", "diagram", "simulate"):
            cmd += ["--out", str(out), "--force"]
        p = subprocess.run(cmd, capture_output=True, text=True, cwd=ROOT)
        assert p.returncode == expect, f"{cmd}: exit {p.returncode}\n{p.stderr}"
        return json.loads(p.stdout)

    return run


@pytest.fixture(scope="session")
def root() -> pathlib.Path:
    return ROOT
