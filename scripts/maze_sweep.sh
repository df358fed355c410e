#!/usr/bin/env bash
# Explores seeded mazes FIRST..LAST (with islands, and with 8 corners cut at 45 degrees)
# with `laserlines simulate` (noise seed 0) and prints each run's coverage, largest pose
# error, stop reason, collisions and least clearance, then per kind the mean coverage, the
# runs below 0.90 and below 1.000, the mean largest pose error, the collisions and the least
# clearance of all runs.
#
#   scripts/maze_sweep.sh 30 109 [path/to/laserlines] [-- SIMULATE OPTIONS] > sweep.txt
#
# The binary defaults to the release build of this checkout (cargo build --release). Options
# after `--` go to every `laserlines simulate` run, e.g. `-- --params explorer.toml`.
set -euo pipefail
first=${1:?first maze seed}
last=${2:?last maze seed}
shift 2
root=$(cd "$(dirname "$0")/.." && pwd)
bin=$root/target/release/laserlines
if [ $# -gt 0 ] && [ "$1" != "--" ]; then
  bin=$1
  shift
fi
[ $# -gt 0 ] && [ "$1" = "--" ] && shift
extra=("$@")
[ -x "$bin" ] || { echo "maze_sweep: no laserlines binary at $bin (cargo build --release)" >&2; exit 2; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# A top-level number of metrics.json (pretty-printed, two spaces of indent); fails when absent
# or not a number.
number() {
  local v
  v=$(sed -n "s/^  \"$1\": \([-0-9.eE+]*\),\{0,1\}$/\1/p" "$2")
  [[ "$v" =~ ^-?[0-9.]+([eE][-+]?[0-9]+)?$ ]] || { echo "maze_sweep: $2: no number for $1" >&2; exit 1; }
  echo "$v"
}
for kind in islands diagonals; do
  n=0 sum_c=0 sum_e=0 low=0 short=0 hits=0 least=1
  for m in $(seq "$first" "$last"); do
    if [ "$kind" = islands ]; then args=(--islands); else args=(--diagonals 8); fi
    "$bin" simulate --maze "$m" "${args[@]}" ${extra[@]+"${extra[@]}"} -o "$out/run" > /dev/null
    c=$(number coverage "$out/run/metrics.json")
    e=$(number max_pose_error_m "$out/run/metrics.json")
    s=$(sed -n 's/^  "stop": "\([a-z_]*\)",\{0,1\}$/\1/p' "$out/run/metrics.json")
    h=$(number collisions "$out/run/metrics.json")
    k=$(number min_clearance_m "$out/run/metrics.json")
    echo "$kind $m coverage $c pose_error_m $e stop $s collisions $h min_clearance_m $k"
    n=$((n + 1))
    sum_c=$(awk -v a="$sum_c" -v b="$c" 'BEGIN { print a + b }')
    sum_e=$(awk -v a="$sum_e" -v b="$e" 'BEGIN { print a + b }')
    low=$((low + $(awk -v c="$c" 'BEGIN { print (c < 0.9) ? 1 : 0 }')))
    short=$((short + $(awk -v c="$c" 'BEGIN { print (c < 0.9995) ? 1 : 0 }')))
    hits=$((hits + h))
    least=$(awk -v a="$least" -v b="$k" 'BEGIN { print (b < a) ? b : a }')
  done
  awk -v k="$kind" -v n="$n" -v c="$sum_c" -v e="$sum_e" -v l="$low" -v s="$short" \
    -v h="$hits" -v m="$least" \
    'BEGIN { printf "%s: %d runs, mean coverage %.4f, %d below 0.90, %d below 1.000, mean largest pose error %.3f m, %d collisions, least clearance %.3f m\n", k, n, c / n, l, s, e / n, h, m }'
done
