# Shared by benchmarks/run_peers.sh, run_ik_peers.sh, run_dyn_peers.sh and run_dyn_corke.sh (sourced,
# not run): a throwaway venv with pinned peers from PyPI and the kinema wheel built from crates/kinema-py.
#
#   source "$here/peers_env.sh"    # needs $here (benchmarks/); sets repo, py, tmp (removed on exit)
#   pipi PACKAGE==VERSION ...      # pip install under the constraints below
#   build_kinema                   # maturin build --release --locked, as crates/kinema-py/ci.sh; install
#
# Cargo output goes to $KINEMA_PY_TARGET_DIR (default crates/kinema-py/target, as ci.sh).
# KINEMA_WHEELS=DIR: install the kinema wheel already built in DIR (crates/kinema-py/ci.sh passes
# its own) instead of building one. KINEMA_PEERS_IF_ONLINE=1: if PyPI (pip's configured index)
# cannot be reached, print a SKIP line and exit 0 from the sourcing script instead of failing.
# Needs Rust (cargo), a C compiler, Python >= 3.9 with venv ($PYTHON, default python3); the
# peers' wheels exist for CPython 3.9-3.13 on x86_64/aarch64 Linux and macOS.

repo="$(dirname "$here")"
python="${PYTHON:-python3}"
export CARGO_TARGET_DIR="${KINEMA_PY_TARGET_DIR:-$repo/crates/kinema-py/target}"

MATURIN_VERSION=1.16.0
NUMPY_VERSION=2.4.6
RTB_VERSION=1.5.0
PIN_VERSION=4.1.0
IK_GEO_VERSION=1.0.3
ERD_VERSION=6.0.0

tmp="$(mktemp -d "${TMPDIR:-/tmp}/kinema-bench.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

# The peers' dependencies as resolved on 2026-11-23 (Python 3.11, Linux x86_64; ik-geo and
# example-robot-data added 2026-11-25), so that a rerun measures the same code. Used as pip
# constraints: a package not needed is not installed.
cat >"$tmp/constraints.txt" <<CONSTRAINTS
numpy==$NUMPY_VERSION
maturin==$MATURIN_VERSION
roboticstoolbox-python==$RTB_VERSION
pin==$PIN_VERSION
ik-geo==$IK_GEO_VERSION
example-robot-data==$ERD_VERSION
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
CONSTRAINTS

echo "== venv in $tmp with $("$python" --version 2>&1)"
"$python" -m venv "$tmp/venv"
py="$tmp/venv/bin/python"
# --no-compile: no .pyc for the thousands of files of scipy, matplotlib and the peers (imports
# compile what they use); saves a few seconds of a busy CPU
pipi() { "$py" -m pip install --quiet --disable-pip-version-check --no-compile -c "$tmp/constraints.txt" "$@"; }
if [ "${KINEMA_PEERS_IF_ONLINE:-0}" = 1 ]; then
  # The index page of one pinned peer, uncached: answers in about a second when PyPI is there.
  if ! "$py" -m pip index versions pin --no-cache-dir --timeout 15 --retries 1 --disable-pip-version-check \
    >/dev/null 2>"$tmp/probe.err"; then
    echo "SKIP: PyPI cannot be reached, so the peers cannot be installed: kinema is NOT checked against them"
    grep -v '^WARNING: pip index is currently an experimental' "$tmp/probe.err" | tail -n 3 | sed 's/^/    /'
    exit 0
  fi
fi
if [ -n "${KINEMA_WHEELS:-}" ]; then
  pipi "numpy==$NUMPY_VERSION"
else
  pipi "numpy==$NUMPY_VERSION" "maturin==$MATURIN_VERSION"
fi

build_kinema() {
  local wheels="$tmp/wheels"
  if [ -n "${KINEMA_WHEELS:-}" ]; then
    wheels="$KINEMA_WHEELS"
    echo "== kinema: the wheel already built in $wheels (KINEMA_WHEELS)"
  else
    echo "== maturin build --release (CARGO_TARGET_DIR=$CARGO_TARGET_DIR)"
    "$tmp/venv/bin/maturin" build --release --locked --quiet \
      --manifest-path "$repo/crates/kinema-py/Cargo.toml" --interpreter "$py" --out "$wheels"
  fi
  "$py" -m pip install --quiet --disable-pip-version-check --no-index --find-links "$wheels" kinema
}
