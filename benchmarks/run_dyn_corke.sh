#!/usr/bin/env bash
# Runs benchmarks/dyn_corke.py (kinema's Python dynamics against Corke's Robotics Toolbox) and
# benchmarks/iiwa_inertials.py (the iiwa built-in's inertials against Drake's, with Pinocchio) in a
# throwaway venv, without the FK/IK check that benchmarks/run_ik_peers.sh (and so the CI) runs
# before them.
#
#   benchmarks/run_dyn_corke.sh [--n N] [--seed S] [--bound B]     (arguments go to dyn_corke.py)
#
# The venv, the pins and the kinema wheel come from benchmarks/peers_env.sh, as run_ik_peers.sh:
# pinned pin and roboticstoolbox-python from PyPI, kinema built from crates/kinema-py (or the wheel
# in $KINEMA_WHEELS). Exits non-zero if either script fails; 0 with a SKIP line if
# KINEMA_PEERS_IF_ONLINE=1 and PyPI cannot be reached.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

pipi "pin==$PIN_VERSION" "roboticstoolbox-python==$RTB_VERSION"
build_kinema

echo "== installed in $SECONDS s: $("$py" -m pip freeze --disable-pip-version-check | grep -Ei '^(kinema|numpy|scipy|roboticstoolbox-python|pin)==' | tr '\n' ' ')"
cd "$tmp"
status=0
echo "== python benchmarks/dyn_corke.py $*"
"$py" "$here/dyn_corke.py" "$@" || status=$?
echo "== python benchmarks/iiwa_inertials.py"
"$py" "$here/iiwa_inertials.py" || status=$?
exit "$status"
