#!/bin/sh
# SPDX-License-Identifier: MIT
# raycost-instr.sh [RAYCOST_BINARY [TOOL]] -- instructions a ray for each
# row of bench/raycost, counted by callgrind: what a query costs on a
# machine too busy for timings (a count does not depend on the load).
# TOOL: 0 libray (ray_intersect, ray_occluded), 1 Embree (rtc*1), 2
# tinybvh.  BENCH_QUICK's ray sets; the set-up's own queries (raycost
# makes its shadow rays and sorts camera rays with ray_intersect) are
# counted once with no row and taken off.  Needs valgrind.
set -eu
bin=${1:-build/bench/raycost}
tool=${2:-0}
data=${DATA:-data}
case $tool in
0) fns="--toggle-collect=ray_intersect --toggle-collect=ray_occluded" ;;
1) fns="--toggle-collect=rtc*1" ;;
2) fns="--toggle-collect=*tbvh*" ;;
*) echo "raycost-instr.sh: TOOL is 0, 1 or 2" >&2; exit 2 ;;
esac
out=$(mktemp)
trap 'rm -f "$out"' EXIT
count() {   # count ROWS -> instructions
    # shellcheck disable=SC2086
    RAYCOST_TOOLS=$tool RAYCOST_ROWS=$1 BENCH_QUICK=1 valgrind \
        --tool=callgrind --callgrind-out-file="$out" $fns "$bin" "$data" \
        > /dev/null 2>&1
    # No instruction counted (the set-up's pass of a tool that makes no
    # query of its own there: Embree's, tinybvh's) prints "." as the total.
    callgrind_annotate "$out" |
        awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print ($1 == "." ? 0 : $1)}'
}
# The rows' ray counts in BENCH_QUICK mode (raycost prints them) and its
# passes: a warm-up and three repetitions.
rays=$(RAYCOST_TOOLS=$tool BENCH_QUICK=1 "$bin" "$data" |
       awk -F'|' '/^\| [a-z]/ && $3 ~ /[0-9]/ {print $3 + 0}')
base=$(count 9)
row=0
for n in $rays; do
    total=$(count $row)
    echo "row $row: $(( (total - base) / (4 * n) )) instructions a ray"
    row=$((row + 1))
done
