#!/usr/bin/env bash
# Compares kinema's boundary-state laws (kinema::traj::BoundaryLaw, sync_duration) with Ruckig.
#
#   benchmarks/run_ruckig.sh [--cases N] [--seed S]      (default 12000 cases, seed 25)
#
# Makes a venv in a temp dir with ruckig (pinned, from PyPI; not a dependency of kinema), writes
# seeded problems with Ruckig's durations (benchmarks/ruckig_cases.py), and runs the ignored test
# `ruckig_durations` of crates/kinema/tests/all/traj_boundary.rs on them: every kinema law is
# re-checked against the limits, and its duration must be at most Ruckig's + 1e-9 relative
# wherever both solve a case. Prints one line of figures per kind of problem.
# Needs Rust (cargo) and Python >= 3.9 with venv ($PYTHON, default python3).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
repo="$(dirname "$here")"
python="${PYTHON:-python3}"
RUCKIG_VERSION=0.19.4

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
