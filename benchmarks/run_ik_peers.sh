#!/usr/bin/env bash
# Runs benchmarks/ik_peers.py (kinema checked against Pinocchio and Corke's Robotics Toolbox, two
# independent oracles; analytic IK timed against IK-Geo) in a throwaway venv with pinned peers.
#
#   benchmarks/run_ik_peers.sh [--n N] [--ik-n N] [--speed-n N] [--seed S] [--quick] [--no-timing]
#                                                                  (arguments go to the script)
#
# The venv, the pins and the kinema wheel come from benchmarks/peers_env.sh (as run_peers.sh):
# pip installs pinned pin (Pinocchio), roboticstoolbox-python (the toolbox), example-robot-data
# (its URDFs) and ik-geo from PyPI into the temp venv only, builds and installs kinema from
# crates/kinema-py (or installs the wheel in $KINEMA_WHEELS), and runs the check with
# --require-toolbox. Then, in the same venv, benchmarks/dyn_corke.py (kinema's Python dynamics,
# rne/inertia/coriolis/gravload/accel, against the toolbox's, 1e-9 relative) and
# benchmarks/iiwa_inertials.py (the iiwa built-in's inertials against Drake's, with Pinocchio), at
# their defaults; benchmarks/run_dyn_corke.sh runs those two alone. Last benchmarks/toolbox_names.py:
# Robot.from_dh against the toolbox's DHRobot on random arms, ctraj and jtraj against the toolbox's
# (1e-12). Exits non-zero if any of the four fails (an FK/Jacobian difference over 1e-12, a wrong IK
# solution, a dynamics difference over 1e-9) or if a required peer does not install; 0 with a SKIP line if KINEMA_PEERS_IF_ONLINE=1 and
# PyPI cannot be reached (peers_env.sh).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

# the two oracles and the URDFs: required
pipi "pin==$PIN_VERSION" "roboticstoolbox-python==$RTB_VERSION" "example-robot-data==$ERD_VERSION"
pipi "ik-geo==$IK_GEO_VERSION" || echo "!! ik-geo $IK_GEO_VERSION did not install: the speed comparison is skipped"

build_kinema

echo "== installed in $SECONDS s: $("$py" -m pip freeze --disable-pip-version-check | grep -Ei '^(kinema|numpy|roboticstoolbox-python|pin|ik-geo|example-robot-data)==' | tr '\n' ' ')"
echo "== python benchmarks/ik_peers.py $*"
# from the temp dir, so that the installed package is imported
cd "$tmp"
status=0
"$py" "$here/ik_peers.py" --require-toolbox "$@" || status=$?
# the dynamics checks need the same peers; all three run even if one fails
dyn_start=$SECONDS
echo "== python benchmarks/dyn_corke.py"
"$py" "$here/dyn_corke.py" || status=$?
echo "== python benchmarks/iiwa_inertials.py"
"$py" "$here/iiwa_inertials.py" || status=$?
echo "== the dynamics checks took $((SECONDS - dyn_start)) s"
echo "== python benchmarks/toolbox_names.py"
"$py" "$here/toolbox_names.py" || status=$?
exit "$status"
