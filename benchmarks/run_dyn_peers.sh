#!/usr/bin/env bash
# Checks kinema's dynamics (RNEA, mass matrix, ABA, Coriolis matrix) against Pinocchio at seeded
# random states: benchmarks/dyn_peers.py writes Pinocchio's numbers to a CSV in a throwaway venv
# with pinned pin and example-robot-data (its URDFs), then the ignored Rust test
# `dynamics_matches_pinocchio` reads it and fails on a difference above 1e-10.
#
#   benchmarks/run_dyn_peers.sh [--n N] [--seed S]          (arguments go to dyn_peers.py)
#
# The venv and the pins come from benchmarks/peers_env.sh (no kinema wheel is needed: the
# comparison runs in Rust).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"
unset CARGO_TARGET_DIR # peers_env.sh points it at the Python crate's target; the test is the core crate's

pipi "pin==$PIN_VERSION" "example-robot-data==$ERD_VERSION"

echo "== python benchmarks/dyn_peers.py $*"
"$py" "$here/dyn_peers.py" "$tmp/pinocchio.csv" "$@"
cd "$repo" && KINEMA_DYN_PEERS_CSV="$tmp/pinocchio.csv" \
    cargo test -p kinema --test all -- --ignored dynamics::dynamics_matches_pinocchio --nocapture
