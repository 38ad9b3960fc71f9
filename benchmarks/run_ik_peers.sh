#!/usr/bin/env bash
# Runs benchmarks/ik_peers.py (kinema checked against Pinocchio, the toolbox and IK-Geo; analytic
# IK timed against IK-Geo) in a throwaway venv with pinned peers.
#
#   benchmarks/run_ik_peers.sh [--n N] [--ik-n N] [--speed-n N] [--seed S] [--quick]   (arguments go to the script)
#
# The venv, the pins and the kinema wheel come from benchmarks/peers_env.sh (as run_peers.sh):
# pip installs pinned pin (Pinocchio, required: the oracle), roboticstoolbox-python, ik-geo and
# example-robot-data (its URDFs) from PyPI into the temp venv only, builds and installs kinema from
# crates/kinema-py, and runs the check. Exits with the script's status: non-zero if an FK/Jacobian
# difference exceeds 1e-12 or kinema returns a wrong IK solution.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

pipi "pin==$PIN_VERSION"
pipi "roboticstoolbox-python==$RTB_VERSION" || echo "!! roboticstoolbox-python $RTB_VERSION did not install: the check skips it"
pipi "ik-geo==$IK_GEO_VERSION" || echo "!! ik-geo $IK_GEO_VERSION did not install: the speed comparison is skipped"
pipi "example-robot-data==$ERD_VERSION" || echo "!! example-robot-data $ERD_VERSION did not install: its URDFs are skipped"

build_kinema

echo "== installed: $("$py" -m pip freeze --disable-pip-version-check | grep -Ei '^(kinema|numpy|roboticstoolbox-python|pin|ik-geo|example-robot-data)==' | tr '\n' ' ')"
echo "== python benchmarks/ik_peers.py $*"
# from the temp dir, so that the installed package is imported
cd "$tmp" && "$py" "$here/ik_peers.py" "$@"
