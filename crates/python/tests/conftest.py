"""Shared fixtures: the repository's fixtures and the `rappel` CLI binary the bindings are
checked against (``RAPPEL_BIN``, else ``target/debug/rappel``, else ``target/release/rappel``)."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
FIXTURES = ROOT / "fixtures"

#: Report fields that are wall-clock measurements: dropped before comparing two runs.
WALL_CLOCK = {"median_ns", "first_solution_s", "elapsed_s"}


def _bin() -> Path:
    env = os.environ.get("RAPPEL_BIN")
    if env:
        return Path(env)
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    for profile in ("debug", "release"):
        p = target / profile / "rappel"
        if p.exists():
            return p
    raise RuntimeError("no rappel binary: build it (cargo build -p rappel-cli) or set RAPPEL_BIN")


@pytest.fixture(scope="session")
def cli():
    """Runs ``rappel ARGS --json``: returns (exit code, parsed JSON or None, stderr)."""
    binary = _bin()

    def run(*args):
        p = subprocess.run([str(binary), *map(str, args), "--json"], capture_output=True, text=True)
        out = json.loads(p.stdout) if p.stdout.strip().startswith("{") else None
        return p.returncode, out, p.stderr

    return run


def no_clock(value):
    """``value`` without the wall-clock fields."""
    if isinstance(value, dict):
        return {k: no_clock(v) for k, v in value.items() if k not in WALL_CLOCK}
    if isinstance(value, list):
        return [no_clock(v) for v in value]
    return value
