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
# to install is reported and then skipped by the benchmark.
# Cargo output of both goes to $KINEMA_PY_TARGET_DIR (default crates/kinema-py/target, as ci.sh).
# Needs Rust (cargo), a C compiler, Python >= 3.9 with venv ($PYTHON, default python3); the
# peers' wheels exist for CPython 3.9-3.13 on x86_64/aarch64 Linux and macOS.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
python="${PYTHON:-python3}"
export CARGO_TARGET_DIR="${KINEMA_PY_TARGET_DIR:-$repo/crates/kinema-py/target}"

MATURIN_VERSION=1.16.0
NUMPY_VERSION=2.4.6
RTB_VERSION=1.5.0
PIN_VERSION=4.1.0

tmp="$(mktemp -d "${TMPDIR:-/tmp}/kinema-bench.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

# The peers' dependencies as resolved on 2026-11-23 (Python 3.11, Linux x86_64), so that a rerun
# measures the same code. Used as pip constraints: a package not needed is not installed.
cat >"$tmp/constraints.txt" <<EOF
numpy==$NUMPY_VERSION
maturin==$MATURIN_VERSION
roboticstoolbox-python==$RTB_VERSION
pin==$PIN_VERSION
spatialmath-python==1.1.18
spatialgeometry==1.4.2
ansitable==1.2.0
pgraph-python==1.0.0
rtb-data==2.0.0
scipy==1.17.1
matplotlib==3.11.2
libpinocchio==4.1.0
eigenpy==3.13.0
coal==3.0.3
libcoal==3.0.3
cmeel==0.62.0
cmeel-boost==1.90.0
cmeel-urdfdom==6.0.0
cmeel-console-bridge==1.0.2.3
cmeel-tinyxml2==11.0.0
cmeel-assimp==6.0.5
cmeel-octomap==1.10.0
cmeel-qhull==8.0.2.1
cmeel-zlib==1.3.2
EOF

echo "== venv in $tmp with $("$python" --version 2>&1)"
"$python" -m venv "$tmp/venv"
py="$tmp/venv/bin/python"
pipi() { "$py" -m pip install --quiet --disable-pip-version-check -c "$tmp/constraints.txt" "$@"; }
pipi "numpy==$NUMPY_VERSION" "maturin==$MATURIN_VERSION"
pipi "roboticstoolbox-python==$RTB_VERSION" || echo "!! roboticstoolbox-python $RTB_VERSION did not install: the benchmark skips it"
pipi "pin==$PIN_VERSION" || echo "!! pin $PIN_VERSION did not install: the benchmark skips Pinocchio"

echo "== maturin build --release (CARGO_TARGET_DIR=$CARGO_TARGET_DIR)"
"$tmp/venv/bin/maturin" build --release --locked --quiet \
  --manifest-path "$repo/crates/kinema-py/Cargo.toml" --interpreter "$py" --out "$tmp/wheels"
"$py" -m pip install --quiet --disable-pip-version-check --no-index --find-links "$tmp/wheels" kinema

echo "== maturin build --release benchmarks/bare_call (kinema_bare_call: the native call floor, not part of kinema)"
"$tmp/venv/bin/maturin" build --release --locked --quiet \
  --manifest-path "$here/bare_call/Cargo.toml" --interpreter "$py" --out "$tmp/wheels"
"$py" -m pip install --quiet --disable-pip-version-check --no-index --find-links "$tmp/wheels" kinema-bare-call

echo "== installed: $("$py" -m pip freeze --disable-pip-version-check | grep -Ei '^(kinema|kinema[-_]bare[-_]call|numpy|roboticstoolbox-python|pin|spatialmath-python)==' | tr '\n' ' ')"
echo "== python benchmarks/python_vs_peers.py $*"
# from the temp dir, so that the installed package is imported
cd "$tmp" && "$py" "$here/python_vs_peers.py" "$@"
