#!/bin/bash
# Issue 29's acceptance at scale, measured (not a timed test): 8-connected A* on arena.map's
# 160 scenarios with repeats, paths off, figures off, through the release xtask binary.
#
#   scripts/scale.sh sizes [N ...]   per N runs (default 200000 1000000): wall, CPU per run,
#                                    peak RSS (/usr/bin/time -v), output bytes per run, with
#                                    outputs = ["parquet"] (and the resume stream's bytes
#                                    per run, read from a sweep killed at about half way)
#   scripts/scale.sh shards [N]      N runs (default 40000) in 4 shards merged equal one run,
#                                    row for row (runs.csv without time_ms, setup_ms and
#                                    peak_heap_bytes)
#   scripts/scale.sh kills [N] [K]   N runs (default 200000) killed with SIGKILL at random
#                                    moments K times (default 20), each time resumed, end
#                                    equal to an uninterrupted run (same comparison)
#   scripts/scale.sh all             the three, default sizes
#
# Work files go to $SCALE_DIR (default /tmp/gridplan-scale), removed as each step ends.
# Above 100,000 runs (sweep::HELD_RUNS) a sweep holds no record in memory: peak RSS should
# not grow with N.
# The machine's load average is printed with the figures: compare timings within one run.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$PWD"
work="${SCALE_DIR:-/tmp/gridplan-scale}"
mkdir -p "$work"
# $XTASK: a release xtask binary already built (e.g. with CI's profile); else one is built.
xtask="${XTASK:-}"
if [[ -z $xtask ]]; then
  cargo build --release -p xtask --quiet
  xtask="$root/target/release/xtask"
fi

# config NAME N OUTPUTS: writes $work/NAME.toml, N runs (a multiple of 160), and prints it.
config() {
  local name=$1 n=$2 outputs=$3
  if (( n % 160 != 0 || n < 160 )); then
    echo "scale.sh: $n runs is not a positive multiple of arena.map's 160 scenarios" >&2
    exit 2
  fi
  cat > "$work/$name.toml" <<EOF
name = "$name"
repeats = $(( n / 160 ))
figures = "none"
paths = "none"
outputs = $outputs
[[maps]]
files = ["$root/maps/movingai/arena.map"]
scen = "$root/maps/movingai/arena.map.scen"
[planners.octile]
planner = "astar"
moves = 8
heuristic = "octile"
EOF
  echo "$work/$name.toml"
}

# runs.csv's deterministic columns (all but time_ms, setup_ms, peak_heap_bytes: 18-20).
deterministic() {
  cut -d, -f1-17,21- "$1/runs.csv"
}

sizes() {
  local ns=("$@")
  (( ${#ns[@]} )) || ns=(200000 1000000)
  echo "load: $(uptime)"
  printf '%10s %8s %10s %12s %12s %14s\n' runs wall_s cpu_us/run peak_rss_MB out_B/run stream_B/run
  for n in "${ns[@]}"; do
    local cfg out
    cfg=$(config "scale-$n" "$n" '["parquet"]')
    out="$work/out-$n"
    /usr/bin/time -v "$xtask" experiment "$cfg" --threads 2 --quiet --output "$out" \
      2> "$work/time-$n" || { cat "$work/time-$n"; exit 1; }
    local wall cpu rss bytes
    wall=$(awk -F': ' '/Elapsed/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; print s}' "$work/time-$n")
    cpu=$(awk -F': ' '/User time|System time/ {s += $2} END {print s}' "$work/time-$n")
    rss=$(awk -F': ' '/Maximum resident/ {print $2}' "$work/time-$n")
    bytes=$(du -sb "$out" | cut -f1)
    # The resume stream: a second sweep killed at about half the first one's wall time.
    "$xtask" experiment "$cfg" --threads 2 --quiet --output "$work/killed-$n" &
    local pid=$!
    sleep "$(awk -v w="$wall" 'BEGIN {print w / 2}')"
    kill -KILL "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
    local stream="$work/.killed-$n.stream/records.stream" stream_per_run="-"
    if [[ -f $stream ]]; then
      local size held
      size=$(stat -c %s "$stream")
      # Resuming says how many runs the stream held ("resuming: N of M runs ...").
      held=$("$xtask" experiment "$cfg" --threads 2 --quiet --resume --output "$work/killed-$n" 2>&1 \
        | sed -n 's/^resuming: \([0-9]*\) of.*/\1/p')
      if [[ -n $held && $held -gt 0 ]]; then
        stream_per_run=$(awk -v b="$size" -v h="$held" 'BEGIN {printf "%.1f", b / h}')
      fi
    fi
    printf '%10d %8.2f %10.2f %12.1f %12.2f %14s\n' "$n" "$wall" \
      "$(awk -v c="$cpu" -v n="$n" 'BEGIN {print c * 1e6 / n}')" \
      "$(awk -v r="$rss" 'BEGIN {print r / 1024}')" \
      "$(awk -v b="$bytes" -v n="$n" 'BEGIN {print b / n}')" "$stream_per_run"
    rm -rf "$out" "$work/killed-$n" "$work/.killed-$n.stream" "$work/time-$n" "$cfg"
  done
  echo "load: $(uptime)"
}

shards() {
  local n=${1:-40000} cfg
  cfg=$(config "scale-shards" "$n" '["csv", "parquet"]')
  "$xtask" experiment "$cfg" --threads 2 --quiet --output "$work/one"
  for k in 1 2 3 4; do
    "$xtask" experiment "$cfg" --threads 2 --quiet --shard "$k/4" --output "$work/s$k"
  done
  "$xtask" merge "$work/s1" "$work/s2" "$work/s3" "$work/s4" --output "$work/merged" >/dev/null
  if cmp -s <(deterministic "$work/one") <(deterministic "$work/merged"); then
    echo "shards: 4 shards of $n runs merged equal one run, row for row ($(($(wc -l < "$work/one/runs.csv") - 1)) rows)"
  else
    echo "shards: 4 shards of $n runs merged DIFFER from one run" >&2
    exit 1
  fi
  rm -rf "$work"/one "$work"/s[1-4] "$work"/merged "$cfg"
}

kills() {
  local n=${1:-200000} k=${2:-20} cfg out
  cfg=$(config "scale-kills" "$n" '["csv"]')
  out="$work/resumed"
  rm -rf "$out" "$work/.resumed.stream"
  "$xtask" experiment "$cfg" --threads 2 --quiet --output "$work/full"
  local killed=0 finished=0 resume=()
  for (( i = 1; i <= k; i++ )); do
    "$xtask" experiment "$cfg" --threads 2 --quiet "${resume[@]}" --output "$out" 2>>"$work/kills.log" &
    local pid=$!
    # A random moment between 0.2 s and 2.2 s into the process.
    sleep "$(awk -v r="$RANDOM" 'BEGIN {print 0.2 + 2 * r / 32767}')"
    if kill -KILL "$pid" 2>/dev/null; then
      killed=$((killed + 1))
    else
      finished=$((finished + 1))
    fi
    wait "$pid" 2>/dev/null || true
    resume=(--resume)
    if [[ -f $out/runs.csv ]]; then
      break
    fi
  done
  "$xtask" experiment "$cfg" --threads 2 --quiet --resume --output "$out" 2>>"$work/kills.log"
  local cut
  cut=$(grep -c "cut short" "$work/kills.log" || true)
  if cmp -s <(deterministic "$work/full") <(deterministic "$out"); then
    echo "kills: $n runs, $killed SIGKILLs ($cut of them mid-batch, the cut batch dropped and said), each resumed: equal to an uninterrupted run"
  else
    echo "kills: $n runs after $killed SIGKILLs DIFFER from an uninterrupted run" >&2
    exit 1
  fi
  rm -rf "$out" "$work/full" "$work/kills.log" "$cfg"
}

case "${1:-all}" in
  sizes) shift; sizes "$@" ;;
  shards) shift; shards "$@" ;;
  kills) shift; kills "$@" ;;
  all) sizes; shards; kills ;;
  *) echo "usage: scripts/scale.sh [sizes [N ...] | shards [N] | kills [N] [K] | all]" >&2; exit 2 ;;
esac
