#!/usr/bin/env bash
# Checks kinema-geometry's self-collision verdicts and distances against Pinocchio + coal, and times
# both on the Panda: benchmarks/coal_peers.py writes coal's verdict and distance per pair at seeded
# random configurations of example-robot-data's Panda and UR5 (collision meshes, pairs after their
# SRDFs) in a throwaway venv with pinned pin and example-robot-data; the ignored Rust test
# `coal::matches_coal` reads it and fails on a verdict that differs for a pair more than 1e-6 m from
# touching, or a distance that differs by more than 1e-6 m; the ignored test
# `coal::fast_paths_match_the_references_on_the_panda_meshes` checks the fast min_distance,
# collides and collides_fast against their plain references on the same Panda meshes. Then the Criterion bench `collision`
# times kinema on the same Panda configurations coal was timed on and the ratios are printed.
#
#   benchmarks/run_coal_peers.sh [--n N] [--seed S] [--no-timing]   (default 10000 configurations per robot)
#
# The venv and the pins come from benchmarks/peers_env.sh (no kinema wheel is needed).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
timing=1
args=()
for a in "$@"; do
  if [ "$a" = "--no-timing" ]; then timing=0; else args+=("$a"); fi
done
set -- "${args[@]+"${args[@]}"}"
caller_target="${CARGO_TARGET_DIR:-}"
source "$here/peers_env.sh"
# peers_env.sh points CARGO_TARGET_DIR at the Python crate's target; the test and bench are
# kinema-geometry's, so they build where the caller said, else in the workspace's target/.
if [ -n "$caller_target" ]; then export CARGO_TARGET_DIR="$caller_target"; else unset CARGO_TARGET_DIR; fi

pipi "pin==$PIN_VERSION" "example-robot-data==$ERD_VERSION"

timing_args=()
[ "$timing" = 1 ] && timing_args=(--timing 1000)
echo "== python benchmarks/coal_peers.py $* ${timing_args[*]+"${timing_args[*]}"}"
"$py" "$here/coal_peers.py" "$tmp/coal.csv" "$@" ${timing_args[@]+"${timing_args[@]}"} | tee "$tmp/coal.txt"
cd "$repo"
echo "== cargo test --release -p kinema-geometry --test all -- --ignored coal::"
KINEMA_COAL_CSV="$tmp/coal.csv" cargo test --release --locked -p kinema-geometry --test all -- \
  --ignored coal:: --nocapture

[ "$timing" = 1 ] || exit 0
echo "== KINEMA_COAL_CSV=... cargo bench -p kinema-geometry --bench collision"
KINEMA_COAL_CSV="$tmp/coal.csv" cargo bench --locked -p kinema-geometry --bench collision 2>/dev/null |
  awk '/^panda-self\// { name = $1 } /time:/ { sub(/.*time: *\[/, ""); print name, $3, $4 }' >"$tmp/kinema.txt"
cat "$tmp/kinema.txt"
# Lines `panda-self/NAME estimate unit`; the estimate in microseconds.
us() { awk -v n="panda-self/$1" '$1 == n { v = $2; if ($3 == "ms") v *= 1000; if ($3 == "ns") v /= 1000; print v }' "$tmp/kinema.txt"; }
coal_us() { sed -n "s/^coal $1: \([0-9.]*\) us.*/\1/p" "$tmp/coal.txt"; }
cc="$(coal_us computeCollisions)"
cd_="$(coal_us computeDistances)"
printf '%-44s %12s %12s %8s\n' "Panda self-collision, per configuration" "kinema us" "coal us" "ratio"
for row in "collides computeCollisions $cc" "min_distance computeDistances $cd_" \
  "min_distance_reference computeDistances $cd_" \
  "spheres_free computeCollisions $cc" "collides_fast computeCollisions $cc"; do
  set -- $row
  awk -v name="$1 vs $2" -v k="$(us "$1")" -v c="$3" 'BEGIN { printf "%-44s %12.2f %12.2f %8.3f\n", name, k, c, k / c }'
done
# Where the exact queries spend: forward kinematics and placement alone, and one exact mesh-mesh
# pair (the closest pair's distance and witness points, placement included).
printf '%-44s %12.2f\n' "place (FK and placement alone)" "$(us place)" \
  "closest_pair (one exact pair_distance)" "$(us closest_pair)"
