#!/usr/bin/env bash
# Builds the kinema Python package and runs its tests, in a throwaway venv.
#
#   crates/kinema-py/ci.sh            (from anywhere; the CI calls it from the repo root)
#
# Then installs it a second time the way the README says, `pip install ./crates/kinema-py`,
# and runs the README example and the model tests against that install. With KINEMA_PEERS=1 (as
# .ci/run sets it) it also runs benchmarks/run_ik_peers.sh on the wheel built here: kinema checked
# against Pinocchio and Corke's toolbox (FK, Jacobian, IK, and the Python dynamics calls), or a
# SKIP line if PyPI cannot be reached.
# Needs Rust (cargo), a C compiler and Python ≥ 3.9 with pip and venv (python3,
# or $PYTHON). Downloads pinned maturin/numpy/pytest (and matplotlib, spatialmath-python, dask[distributed]
# for the tests of the optional plots, SE3 poses and kinema.dask) from PyPI and the crates in
# Cargo.lock. Cargo output goes to crates/kinema-py/target (gitignored; reused
# between runs), or to $KINEMA_PY_TARGET_DIR. Exits non-zero on any failure.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
python="${PYTHON:-python3}"
export CARGO_TARGET_DIR="${KINEMA_PY_TARGET_DIR:-$here/target}"

MATURIN_VERSION=1.16.0
NUMPY_VERSION=2.4.6
PYTEST_VERSION=9.2.0
# Optional dependencies of kinema that its tests use: plots and spatialmath poses.
MATPLOTLIB_VERSION=3.11.2
SPATIALMATH_VERSION=1.1.18
# kinema.dask's tests run on a LocalCluster of two worker processes.
DASK_VERSION=2026.8.0

start=$(date +%s)
step_start=$start
step() {
  local now
  now=$(date +%s)
  echo "== kinema-py: $1 (after $((now - step_start)) s of the previous step, $((now - start)) s total)"
  step_start=$now
}

tmp="$(mktemp -d "${TMPDIR:-/tmp}/kinema-py-ci.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

step "venv in $tmp with $("$python" --version 2>&1)"
"$python" -m venv "$tmp/venv"
py="$tmp/venv/bin/python"
"$py" -m pip install --quiet --disable-pip-version-check \
  "maturin==$MATURIN_VERSION" "numpy==$NUMPY_VERSION" "pytest==$PYTEST_VERSION" \
  "matplotlib==$MATPLOTLIB_VERSION" "spatialmath-python==$SPATIALMATH_VERSION" \
  "dask[distributed]==$DASK_VERSION"

step "maturin build --release (CARGO_TARGET_DIR=$CARGO_TARGET_DIR)"
"$tmp/venv/bin/maturin" build --release --locked --quiet \
  --manifest-path "$here/Cargo.toml" --interpreter "$py" --out "$tmp/wheels"
"$py" -m pip install --quiet --disable-pip-version-check --no-index --find-links "$tmp/wheels" kinema

step "pytest"
# Run from the temp dir so that the installed package, not the source tree, is imported.
(cd "$tmp" && "$py" -m pytest -q -p no:cacheprovider "$here/tests")

step "pip install ./crates/kinema-py (the README's install command) into a second venv"
# pip builds the package itself (PEP 517, maturin in an isolated build environment, the same
# target directory); the constraints pin what it fetches to the versions above.
printf 'maturin==%s\nnumpy==%s\npytest==%s\n' "$MATURIN_VERSION" "$NUMPY_VERSION" "$PYTEST_VERSION" >"$tmp/constraints.txt"
"$python" -m venv "$tmp/venv-pip"
PIP_CONSTRAINT="$tmp/constraints.txt" PIP_BUILD_CONSTRAINT="$tmp/constraints.txt" "$tmp/venv-pip/bin/python" -m pip install --quiet --disable-pip-version-check "pytest==$PYTEST_VERSION" "$here"
(cd "$tmp" && "$tmp/venv-pip/bin/python" -m pytest -q -p no:cacheprovider "$here/tests/test_readme.py" "$here/tests/test_model_fk.py")

if [ "${KINEMA_PEERS:-0}" = 1 ]; then
  # kinema checked against Pinocchio and Corke's toolbox (and the analytic IK timed against IK-Geo,
  # a smoke run), the peers installed from PyPI into a venv of their own, the wheel built above
  # installed into it; then, in that venv, rne/inertia/coriolis/gravload/accel against the toolbox's
  # (benchmarks/dyn_corke.py) and the iiwa's inertials against Drake's (benchmarks/iiwa_inertials.py).
  # Fails on an FK/Jacobian difference over 1e-12, a wrong IK solution or a dynamics difference over
  # 1e-9 (relative); a SKIP line, not a failure, only if PyPI cannot be reached. About 1.5 min, most
  # of it pip.
  peers_args=(--n 200 --ik-n 100 --speed-n 200 --repeats 3 --lm-n 20)
  step "KINEMA_PEERS=1: benchmarks/run_ik_peers.sh ${peers_args[*]}"
  KINEMA_WHEELS="$tmp/wheels" KINEMA_PEERS_IF_ONLINE=1 KINEMA_PY_TARGET_DIR="$CARGO_TARGET_DIR" \
    "$here/../../benchmarks/run_ik_peers.sh" "${peers_args[@]}"
fi

step "done"
echo "kinema-py: all steps passed in $(( $(date +%s) - start )) s"
