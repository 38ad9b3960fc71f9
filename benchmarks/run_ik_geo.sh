#!/usr/bin/env bash
# kinema's all-solutions analytic IK against IK-Geo's from Python (benchmarks/ik_geo_compare.py),
# in a throwaway venv with pinned ik-geo (benchmarks/peers_env.sh), then the same calls counted in
# instructions with callgrind when valgrind is installed: time on a shared machine moves with the
# load, instruction counts do not.
#
#   benchmarks/run_ik_geo.sh [time options: --n N --passes K --arms A --arm-targets M --seed S]
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/peers_env.sh"

pipi "ik-geo==$IK_GEO_VERSION"
build_kinema

cd "$tmp"
echo "== python benchmarks/ik_geo_compare.py time $*"
"$py" "$here/ik_geo_compare.py" time "$@"

if ! command -v valgrind >/dev/null || ! command -v callgrind_annotate >/dev/null; then
  echo "SKIP instruction counts: valgrind is not installed (apt-get install valgrind)"
  exit 0
fi
echo
echo "## Instructions per call (callgrind, inclusive count of the extension method, 300 calls)"
echo "| robot | kinema ik(T, all=True) | IK-Geo get_ik | kinema ÷ IK-Geo |"
echo "|---|---:|---:|---:|"
n=300
count() { # robot who method-pattern -> instructions per call
  PYTHONHASHSEED=0 valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" \
    "$py" "$here/ik_geo_compare.py" calls "$1" "$2" "$n" >/dev/null 2>&1
  callgrind_annotate --threshold=100 --inclusive=yes "$tmp/cg.out" 2>/dev/null |
    grep -m1 -E "$3" | awk -v n="$n" '{gsub(",", "", $1); printf "%.0f", $1 / n}'
}
for robot in puma560 ur5; do
  k=$(count "$robot" kinema '__pymethod_ik__')
  g=$(count "$robot" ik-geo '__pymethod_get_ik__')
  echo "| $robot | $k | $g | $(awk -v k="$k" -v g="$g" 'BEGIN {printf "%.2f", k / g}') |"
done
