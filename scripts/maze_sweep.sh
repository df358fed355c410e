#!/usr/bin/env bash
# Explores seeded mazes FIRST..LAST (with islands, and with 8 corners cut at 45 degrees)
# with `laserlines simulate` and prints each run's coverage, largest pose error and stop
# reason, then the means and the runs below 0.90 coverage per kind.
#
#   scripts/maze_sweep.sh 30 109 [path/to/laserlines] > sweep.txt
set -euo pipefail
first=${1:?first maze seed}
last=${2:?last maze seed}
bin=${3:-target/release/laserlines}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
field() { sed -n "s/^  \"$1\": \"\{0,1\}\([^\",]*\)\"\{0,1\},\{0,1\}$/\1/p" "$2"; }
for kind in islands diagonals; do
  n=0 sum_c=0 sum_e=0 low=0
  for m in $(seq "$first" "$last"); do
    if [ "$kind" = islands ]; then args=(--islands); else args=(--diagonals 8); fi
    "$bin" simulate --maze "$m" "${args[@]}" -o "$out/run" > /dev/null
    c=$(field coverage "$out/run/metrics.json")
    e=$(field max_pose_error_m "$out/run/metrics.json")
    s=$(field stop "$out/run/metrics.json")
    echo "$kind $m coverage $c pose_error_m $e stop $s"
    n=$((n + 1))
    sum_c=$(awk -v a="$sum_c" -v b="$c" 'BEGIN { print a + b }')
    sum_e=$(awk -v a="$sum_e" -v b="$e" 'BEGIN { print a + b }')
    low=$((low + $(awk -v c="$c" 'BEGIN { print (c < 0.9) ? 1 : 0 }')))
  done
  awk -v k="$kind" -v n="$n" -v c="$sum_c" -v e="$sum_e" -v l="$low" \
    'BEGIN { printf "%s: %d runs, mean coverage %.4f, %d below 0.90, mean largest pose error %.3f m\n", k, n, c / n, l, e / n }'
done
