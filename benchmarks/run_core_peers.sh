#!/usr/bin/env bash
# Per-call time of the core against Pinocchio's C++ and the `k` crate, side by side in one run
# (issue 26): the tool pose (FK), the tool Jacobian (6 x n, [v; w] in world axes), RNEA and CRBA,
# on the same URDFs, after checking that all three compute the same numbers.
#
#   benchmarks/run_core_peers.sh [--passes P] [--states N] [--seed S] [--ms MS]
#
# Defaults: 5 passes, 256 states per robot, seed 26, 800 ms per C++ operation and pass. Robots:
# example-robot-data's UR5 (tip tool0) and Panda (tip panda_link8, fingers locked at 0), and
# kinema's built-in PUMA 560 (its mass properties) and LBR iiwa 14 (no published masses: a
# placeholder body per link, for timing only) written as URDFs by `core-peers urdf`.
#
# Steps: a throwaway venv (benchmarks/peers_env.sh) with pinned `pin` (its C++ headers and shared
# libraries, a cmeel prefix), example-robot-data, and the Eigen and urdfdom headers the pin wheel
# does not ship; benchmarks/core_peers/pinocchio_bench.cpp compiled against them (g++ -O3, the
# defines Pinocchio's CMake targets carry, so the algorithms run from the wheel's prebuilt library);
# the Rust crate benchmarks/core_peers (kinema by path, k from crates.io; Criterion).
# pinocchio_bench writes seeded states and Pinocchio's results; `core-peers check` compares
# kinema (plain and fast dynamics) and k with them and stops the run above 1e-12. Then P passes,
# each timing every robot in C++ and in Rust (Criterion), the order of the two alternating; the
# table shows the median over passes of each one's per-pass median. Needs g++, cargo, Python >= 3.9.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
passes=5 nstates=256 seed=26 ms=800
while [ $# -gt 0 ]; do
  case "$1" in
    --passes) passes="$2"; shift 2 ;;
    --states) nstates="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --ms) ms="$2"; shift 2 ;;
    *) echo "usage: $0 [--passes P] [--states N] [--seed S] [--ms MS]" >&2; exit 2 ;;
  esac
done

KINEMA_WHEELS="${KINEMA_WHEELS:-none}" # no kinema wheel is needed: skips maturin in peers_env.sh
source "$here/peers_env.sh"
unset CARGO_TARGET_DIR # peers_env.sh points it at the Python crate's target
echo "== load average at start: $(cut -d' ' -f1-3 /proc/loadavg)"

# Eigen and the urdfdom headers: pin's C++ headers include them, its wheel does not ship them.
pipi "pin==$PIN_VERSION" "example-robot-data==$ERD_VERSION" cmeel-eigen==3.4.1 cmeel-urdfdom-headers==3.0.0
prefix="$("$py" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/cmeel.prefix"
erd="$prefix/share/example-robot-data/robots"

echo "== g++ pinocchio_bench.cpp (a few minutes)"
# The defines of Pinocchio's CMake targets pinocchio_default and pinocchio_parsers (urdfdom 3, coal):
# with PINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION the algorithms on double come from the wheel's
# prebuilt libpinocchio_default (its release build). No -march=native: the prebuilt libraries hand
# us the Model, and a program built with it (even with EIGEN_MAX_ALIGN_BYTES=16, with or without
# the instantiations) crashes in the Model's destructor — Eigen's types no longer match theirs.
g++ -std=c++17 -O3 -DNDEBUG \
  -DBOOST_MPL_LIMIT_LIST_SIZE=30 -DBOOST_MPL_LIMIT_VECTOR_SIZE=30 -DBOOST_MPL_CFG_NO_PREPROCESSED_HEADERS \
  -DBOOST_FUSION_INVOKE_MAX_ARITY=12 -DPINOCCHIO_ENABLE_TEMPLATE_INSTANTIATION -DPINOCCHIO_WITH_COLLISION \
  -DCOAL_BACKWARD_COMPATIBILITY_WITH_HPP_FCL -DCOAL_HAS_OCTOMAP -DCOAL_HAVE_OCTOMAP -DOCTOMAP_MAJOR_VERSION=1 \
  -DOCTOMAP_MINOR_VERSION=10 -DOCTOMAP_PATCH_VERSION=0 -DPINOCCHIO_WITH_URDFDOM \
  -DPINOCCHIO_URDFDOM_HEADERS_MAJOR_VERSION=3 -DPINOCCHIO_URDFDOM_HEADERS_MINOR_VERSION=0 \
  -DPINOCCHIO_URDFDOM_HEADERS_PATCH_VERSION=0 \
  -I"$prefix/include" -I"$prefix/include/pinocchio/deprecated" -I"$prefix/include/eigen3" \
  -I"$prefix/include/urdfdom_headers" "$here/core_peers/pinocchio_bench.cpp" -o "$tmp/pinocchio_bench" \
  -L"$prefix/lib" -Wl,-rpath,"$prefix/lib" -lpinocchio_parsers -lpinocchio_default -lurdfdom_model \
  -lboost_filesystem -lboost_serialization -w
pinb="$tmp/pinocchio_bench"

echo "== cargo build (benchmarks/core_peers)"
cd "$here/core_peers"
cargo build --release --quiet --bin core-peers
cargo bench --quiet --no-run --bench core_peers
peers="$here/core_peers/target/release/core-peers"

"$peers" urdf puma560 "$tmp/puma560.urdf"
"$peers" urdf lbr-iiwa-14-r820 "$tmp/iiwa.urdf"
robots=(
  "ur5|$erd/ur_description/urdf/ur5_robot.urdf|tool0"
  "panda|$erd/panda_description/urdf/panda.urdf|panda_link8"
  "iiwa|$tmp/iiwa.urdf|tool"
  "puma560|$tmp/puma560.urdf|tool"
)
: >"$tmp/robots.tsv"
for r in "${robots[@]}"; do
  IFS='|' read -r name urdf tip <<<"$r"
  joints="$("$peers" joints "$urdf" "$tip")"
  "$pinb" states "$urdf" "$tip" "$joints" "$nstates" "$seed" "$tmp/$name.csv"
  echo "== check $name ($joints)"
  "$peers" check "$urdf" "$tip" "$tmp/$name.csv"
  printf '%s\t%s\t%s\t%s\n' "$name" "$urdf" "$tip" "$tmp/$name.csv" >>"$tmp/robots.tsv"
done

time_cpp() {
  for r in "${robots[@]}"; do
    IFS='|' read -r name urdf tip <<<"$r"
    "$pinb" time "$urdf" "$tip" "$("$peers" joints "$urdf" "$tip")" "$tmp/$name.csv" "$ms" |
      sed "s/^/$1 $name pinocchio-/" >>"$tmp/times.txt"
  done
}
time_rust() {
  rm -rf "$here/core_peers/target/criterion"
  CORE_PEERS_LIST="$tmp/robots.tsv" cargo bench --quiet --bench core_peers >"$tmp/criterion-$1.log" 2>&1
  "$py" - "$1" "$here/core_peers/target/criterion" >>"$tmp/times.txt" <<'PY'
import json, pathlib, sys
for est in sorted(pathlib.Path(sys.argv[2]).glob("*/*/new/estimates.json")):
    robot, op = est.parts[-4], est.parts[-3]
    print(sys.argv[1], robot, op, json.loads(est.read_text())["median"]["point_estimate"])
PY
}
: >"$tmp/times.txt"
for p in $(seq 1 "$passes"); do
  echo "== pass $p/$passes (load average $(cut -d' ' -f1-3 /proc/loadavg))"
  if [ $((p % 2)) = 1 ]; then time_cpp "$p"; time_rust "$p"; else time_rust "$p"; time_cpp "$p"; fi
done
echo "== load average at end: $(cut -d' ' -f1-3 /proc/loadavg)"

"$py" - "$tmp/times.txt" <<'PY'
import collections, statistics, sys
t = collections.defaultdict(list)
for line in open(sys.argv[1]):
    p, robot, op, ns = line.split()
    t[robot, op].append(float(ns))
med = {k: statistics.median(v) for k, v in t.items()}
robots = list(dict.fromkeys(r for r, _ in med))
print("\nns per call, median over passes (each pass: Criterion's median / the median of 256-call batches)\n")
print("| robot | operation | Pinocchio C++ | kinema | k | kinema ÷ Pinocchio | k ÷ Pinocchio |")
print("|---|---|---:|---:|---:|---:|---:|")
for r in robots:
    for op, pin_op in [("fk", "fk"), ("jacobian", "jacobian"), ("rnea", "rnea"), ("crba", "crba")]:
        pin = med[r, "pinocchio-" + pin_op]
        kin = med.get((r, op + "-kinema"))
        k = med.get((r, op + "-k"))
        f = lambda x: f"{x:.0f}" if x is not None else "—"
        ratio = lambda x: f"{x / pin:.2f}" if x is not None else "—"
        print(f"| {r} | {op} | {pin:.0f} | {f(kin)} | {f(k)} | {ratio(kin)} | {ratio(k)} |")
print("\nAlso timed (ns per call, median over passes):\n")
print("| robot | kinema rnea (plain) | kinema crba (plain) | Pinocchio crba WORLD | Pinocchio crba + lower triangle |")
print("|---|---:|---:|---:|---:|")
for r in robots:
    print(f"| {r} | {med[r, 'rnea-kinema-plain']:.0f} | {med[r, 'crba-kinema-plain']:.0f} | {med[r, 'pinocchio-crba-world']:.0f} | {med[r, 'pinocchio-crba-full']:.0f} |")
spread = max(max(v) / min(v) for v in t.values())
print(f"\nlargest max/min over passes of one figure: {spread:.2f}")
PY
