#!/usr/bin/env bash
# Runs benchmarks/python_vs_peers.py in a throwaway venv with pinned peers.
#
#   benchmarks/run_peers.sh [--n N] [--ik-n N] [--seed S] [--quick] [...]   (arguments go to the script)
#
# Makes a venv in a temp dir, pip installs pinned numpy, maturin, roboticstoolbox-python and pin
# (Pinocchio) from PyPI, builds the kinema wheel from crates/kinema-py the way crates/kinema-py/ci.sh
# does (maturin build --release --locked), installs it, builds and installs the benchmark's native
# call floor `kinema_bare_call` from benchmarks/bare_call the same way (a reference for the timing,
# not part of kinema), and runs the benchmark, which ends with Markdown tables. A peer that fails
# to install is reported and then skipped by the benchmark. The venv, the pins and the kinema
# build are benchmarks/peers_env.sh (shared with run_ik_peers.sh).
# Cargo output of both goes to $KINEMA_PY_TARGET_DIR (default crates/kinema-py/target, as ci.sh).
# Needs Rust (cargo), a C compiler, Python >= 3.9 with venv ($PYTHON, default python3); the
# peers' wheels exist for CPython 3.9-3.13 on x86_64/aarch64 Linux and macOS.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

pipi "roboticstoolbox-python==$RTB_VERSION" || echo "!! roboticstoolbox-python $RTB_VERSION did not install: the benchmark skips it"
pipi "pin==$PIN_VERSION" || echo "!! pin $PIN_VERSION did not install: the benchmark skips Pinocchio"

build_kinema

echo "== maturin build --release benchmarks/bare_call (kinema_bare_call: the native call floor, not part of kinema)"
"$tmp/venv/bin/maturin" build --release --locked --quiet \
  --manifest-path "$here/bare_call/Cargo.toml" --interpreter "$py" --out "$tmp/wheels"
"$py" -m pip install --quiet --disable-pip-version-check --no-index --find-links "$tmp/wheels" kinema-bare-call

echo "== installed: $("$py" -m pip freeze --disable-pip-version-check | grep -Ei '^(kinema|kinema[-_]bare[-_]call|numpy|roboticstoolbox-python|pin|spatialmath-python)==' | tr '\n' ' ')"
echo "== python benchmarks/python_vs_peers.py $*"
# from the temp dir, so that the installed package is imported
cd "$tmp" && "$py" "$here/python_vs_peers.py" "$@"
