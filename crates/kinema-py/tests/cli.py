"""The `kinema` command line, to compare the Python package with it.

The binary is $KINEMA_BIN, else the newest of target/{release,debug}/kinema in this repository
(build it with `cargo build -p kinema-cli`); ci.sh builds only the wheel, so without one the
comparisons are skipped with that reason."""

import json
import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[3]


def kinema_binary():
    """The `kinema` command line built in this repository ($KINEMA_BIN, else the newest of target/{release,debug})."""
    if os.environ.get("KINEMA_BIN"):
        return pathlib.Path(os.environ["KINEMA_BIN"])
    built = [p for p in (ROOT / "target" / "release" / "kinema", ROOT / "target" / "debug" / "kinema") if p.exists()]
    return max(built, key=lambda p: p.stat().st_mtime) if built else None


needs_cli = pytest.mark.skipif(
    kinema_binary() is None, reason="the kinema command line is not built (cargo build -p kinema-cli)"
)


def cli_json(args, code=0):
    """Runs `kinema ARGS`, checks its exit code and returns its JSON output."""
    r = subprocess.run([str(kinema_binary()), *args], capture_output=True, text=True, timeout=300)
    assert r.returncode == code, (args, r.returncode, r.stderr)
    return json.loads(r.stdout)
