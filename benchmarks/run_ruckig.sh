#!/usr/bin/env bash
# Compares kinema's boundary-state laws (kinema::traj::BoundaryLaw, sync_duration) with Ruckig.
#
#   benchmarks/run_ruckig.sh [--cases N] [--seed S]      (default 12000 cases, seed 25)
#
# Makes a venv in a temp dir with ruckig (pinned, from PyPI; not a dependency of kinema), writes
# seeded problems with Ruckig's durations (benchmarks/ruckig_cases.py), and runs the ignored test
# `ruckig_durations` of crates/kinema/tests/all/traj_boundary.rs on them: every kinema law is
# re-checked against the limits, and its duration must be at most Ruckig's + 1e-9 relative
# wherever both solve a case. Prints one line of figures per kind of problem. Then times both on
# the same 256 seven-joint jerk-limited problems: Ruckig from Python (`ruckig_cases.py --timing`,
# Ruckig(7).calculate per problem) and kinema in Rust (the Criterion bench
# `boundary/sync-7dof-third/fast`, sync_duration per problem, reading the same file), and prints
# the ratio. --no-timing skips that part.
# Needs Rust (cargo) and Python >= 3.9 with venv ($PYTHON, default python3).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
python="${PYTHON:-python3}"
RUCKIG_VERSION=0.19.4

timing=1
args=()
for a in "$@"; do
  if [ "$a" = "--no-timing" ]; then timing=0; else args+=("$a"); fi
done
set -- "${args[@]+"${args[@]}"}"

tmp="$(mktemp -d "${TMPDIR:-/tmp}/kinema-ruckig.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT

echo "== venv in $tmp with $("$python" --version 2>&1), ruckig==$RUCKIG_VERSION"
"$python" -m venv "$tmp/venv"
"$tmp/venv/bin/python" -m pip install --quiet --disable-pip-version-check "ruckig==$RUCKIG_VERSION"
echo "== python benchmarks/ruckig_cases.py $*"
"$tmp/venv/bin/python" "$here/ruckig_cases.py" --out "$tmp/cases.csv" "$@"
echo "== cargo test --release -p kinema --test all -- --ignored traj_boundary::ruckig_durations"
cd "$repo"
KINEMA_RUCKIG_CSV="$tmp/cases.csv" cargo test --release -p kinema --test all -- \
  --ignored traj_boundary::ruckig_durations --nocapture

[ "$timing" = 1 ] || exit 0
echo "== python benchmarks/ruckig_cases.py --timing 256 --seed 25"
ruckig_line="$("$tmp/venv/bin/python" "$here/ruckig_cases.py" --timing 256 --seed 25 --out "$tmp/sync7.csv")"
echo "$ruckig_line"
ruckig_us="$(echo "$ruckig_line" | sed -n 's/.*: \([0-9.]*\) us per problem.*/\1/p')"
echo "== KINEMA_SYNC7_CSV=... cargo bench -p kinema --bench boundary -- sync-7dof-third/fast"
kinema_line="$(KINEMA_SYNC7_CSV="$tmp/sync7.csv" cargo bench -p kinema --bench boundary -- \
  sync-7dof-third/fast 2>/dev/null | grep -A1 'sync-7dof-third/fast' | grep 'time:')"
echo "kinema sync-7dof-third/fast $kinema_line"
# Criterion prints [low estimate high] with a unit; take the estimate in microseconds.
kinema_us="$(echo "$kinema_line" | awk '{ v = $4; u = $5; if (u == "ms") v *= 1000; if (u == "ns") v /= 1000; print v }')"
awk -v k="$kinema_us" -v r="$ruckig_us" \
  'BEGIN { printf "sync-7dof-third: kinema %.2f us, Ruckig %.2f us per problem: kinema/Ruckig = %.1f\n", k, r, k / r }'
