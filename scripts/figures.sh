#!/usr/bin/env bash
# Draws the pictures of docs/ again with the command-line tool, as the README's commands do:
#   docs/hough-split.svg         laserlines demo (scan 20 of the bundled excerpt)
#   docs/navigation-map.svg      laserlines simulate --arena data/arenas/maze_10m_x_14m.raf --seed 0
#   docs/navigation-sectors.svg  the same run's sectors
#   docs/navigation-fence.svg    laserlines simulate --arena rc_2015_arena_small.raf --fence --seed 0
#   docs/map-mit-csail.svg       laserlines map mit-csail.clf.gz
#   docs/map-exp1.svg, -exp2.svg laserlines map exp1.dat.gz, exp2.dat.gz
# The last four need the recorded data of ../shared/data beside the repository and are left
# as they are without it. The chart of docs/bench holds the times of the machine it ran on:
# `scripts/figures.sh --bench` draws it too (laserlines bench --repeat 3 -o docs/bench).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release -p laserlines-cli
ll=target/release/laserlines
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# A map's progress goes to a log of its own; the log is shown when the map fails.
quiet_map() {
    if ! "$ll" map "$1" -o "$2" 2> "$2.log"; then
        cat "$2.log" >&2
        return 1
    fi
}

"$ll" demo --repeat 1 -o "$tmp/demo" > /dev/null
cp "$tmp/demo/hough-split-scan20.svg" docs/hough-split.svg
"$ll" simulate --arena data/arenas/maze_10m_x_14m.raf --seed 0 -o "$tmp/maze" > /dev/null
cp "$tmp/maze/map.svg" docs/navigation-map.svg
cp "$tmp/maze/sectors.svg" docs/navigation-sectors.svg

shared=../shared/data
if [ -d "$shared" ]; then
    "$ll" simulate --arena "$shared/arenas/rc_2015_arena_small.raf" --fence --seed 0 \
        -o "$tmp/fence" > /dev/null
    cp "$tmp/fence/map.svg" docs/navigation-fence.svg
    quiet_map "$shared/real/mit-csail-clf/mit-csail.clf.gz" "$tmp/mit-csail"
    cp "$tmp/mit-csail/map.svg" docs/map-mit-csail.svg
    for run in exp1 exp2; do
        quiet_map "$shared/real/breezyslam-urg04lx/$run.dat.gz" "$tmp/$run"
        cp "$tmp/$run/map.svg" "docs/map-$run.svg"
    done
else
    echo "figures: $shared not found: the fenced arena and the maps of real logs are left as they are" >&2
fi

if [ "${1:-}" = "--bench" ]; then
    "$ll" bench --repeat 3 -o docs/bench
fi
echo "figures: docs/ drawn again"
