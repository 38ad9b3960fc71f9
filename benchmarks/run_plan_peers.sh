#!/usr/bin/env bash
# Plans benchmarks/plan/'s problems with kinema's Python package and re-checks every path with
# Pinocchio + coal on the same shapes (benchmarks/plan_peers.py); with --ompl, OMPL's RRT-Connect
# plans them too with kinema's collision check, and the two are timed side by side. Exits non-zero
# if coal finds any of kinema's path samples colliding.
#
#   benchmarks/run_plan_peers.sh [--subset N] [--seed S] [--ompl] [--resolution R]   (default: all 100)
#   benchmarks/run_plan_peers.sh --urdf [--per-robot N] [--seed S] [--robots A,B]
#
# --urdf: `kinema plan` ($KINEMA_BIN, default target/release/kinema) on real URDFs instead
# (example-robot-data's Panda, UR5, Kinova; rtbdata's KUKA KR 16-2 and ABB IRB 140; seeded table and
# box scenes), each path re-checked by coal on the same collision meshes (benchmarks/plan_peers_urdf.py).
#
# The venv, the pins and the kinema wheel come from benchmarks/peers_env.sh (KINEMA_WHEELS=DIR to
# install a wheel already built; KINEMA_PEERS_IF_ONLINE=1 for a SKIP line without PyPI).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

OMPL_VERSION=2.0.1
if [ "${1:-}" = "--urdf" ]; then
  shift
  pipi "pin==$PIN_VERSION" "example-robot-data==$ERD_VERSION" "rtb-data==2.0.0"
  echo "== python benchmarks/plan_peers_urdf.py $*"
  cd "$here"
  "$py" plan_peers_urdf.py "${KINEMA_BIN:-$repo/target/release/kinema}" "$@"
  exit 0
fi
pipi "pin==$PIN_VERSION" "ompl==$OMPL_VERSION"
build_kinema

echo "== python benchmarks/plan_peers.py $*"
cd "$here"
"$py" plan_peers.py "$@"
