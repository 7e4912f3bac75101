#!/bin/bash
# Benchmark-scale sweep: configs/bench/arena-200k.toml (200,000 A* runs, no paths) through
# the release binary, measured with /usr/bin/time -v (wall, user+sys CPU, peak RSS) and
# the size of the results directory.
set -euo pipefail
cd "$(dirname "$0")/.."
# $XTASK: a release xtask binary already built; else one is built.
xtask="${XTASK:-}"
if [[ -z $xtask ]]; then
  cargo build --release -p xtask --quiet
  xtask=target/release/xtask
fi
out="${1:-/tmp/gridplan-bench-arena-200k}"
/usr/bin/time -v "$xtask" experiment configs/bench/arena-200k.toml \
    --threads 2 --quiet --output "$out" 2> "$out.time" || { cat "$out.time"; exit 1; }
grep -E "Elapsed|User time|System time|Maximum resident" "$out.time"
du -sb "$out" | awk '{printf "output: %.1f MB\n", $1 / 1e6}'
