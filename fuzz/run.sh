#!/usr/bin/env bash
# Runs one fuzz target for a bounded time: fuzz/run.sh TARGET SECONDS [extra libFuzzer flags]
#
# TARGET is one of: movingai scen seed003 csv ros_yaml image config stream frames weights gppc replan_config expanded edits (see README.md).
# Seeds are copied from ../maps (by extension) into seeds/TARGET; libFuzzer keeps what it
# finds in corpus/TARGET and writes crashing inputs to artifacts/TARGET. Both are ignored
# by git. Needs cargo-fuzz (`cargo install cargo-fuzz`); on a stable toolchain
# RUSTC_BOOTSTRAP=1 lets it pass the nightly flags (-Z sanitizer, coverage) it needs.
set -euo pipefail
cd "$(dirname "$0")"
if [ $# -lt 2 ]; then
  echo "usage: $0 TARGET SECONDS [libFuzzer flags...]" >&2
  exit 2
fi
target=$1
seconds=$2
shift 2
seeds=seeds/$target
mkdir -p "corpus/$target" "$seeds" "artifacts/$target"
copy() { # copy maps/ files matching $1 and smaller than $2 into the seed folder
  find ../maps -name "$1" -size "-$2" -exec cp {} "$seeds/" \;
}
# Stream files as `experiment --shard` writes them: a few shards of configs/paper.toml
# (every planner of seed 000), their framed shard.stream rewritten as JSON Lines by the
# runner's stream_seeds example, each cut to its first 16 KiB, after the bytes $1.
shard_streams() {
  streams=$(mktemp -d)
  for k in 1 2 3; do
    (cd .. && cargo run -q --release -p xtask -- experiment configs/paper.toml --shard "$k/40" \
      --output "$streams/s$k" --quiet >/dev/null)
    (cd .. && cargo run -q --release -p planner-runner --example stream_seeds -- \
      "$streams/s$k/shard.stream" "$streams/s$k.jsonl")
    { printf '%b' "$1"; head -c 16384 "$streams/s$k.jsonl"; } > "$seeds/shard-$k.jsonl"
    # The stream target reads framed streams too: the file as written, cut the same way.
    if [ -z "$1" ]; then
      head -c 16384 "$streams/s$k/shard.stream" > "$seeds/shard-$k.stream"
    fi
  done
  rm -rf "$streams"
}
max_len=16384
case $target in
  movingai) copy '*.map' 64k ;;
  scen) copy '*.scen' 64k ;;
  seed003) copy '*.txt' 64k ;;
  csv)
    # No .csv maps in maps/: the seed-003 maps as 0/1 matrices, and two by hand.
    for txt in ../maps/wpi/*.txt; do
      grep -v '^#' "$txt" | sed -e 's/\./1,/g' -e 's/X/0,/g' -e 's/,$//' \
        > "$seeds/$(basename "$txt" .txt).csv"
    done
    printf '1,0,1\n0,1,0\n' > "$seeds/small.csv"
    printf '# comment\n1 0 1\r\n1 1 1\r\n\n' > "$seeds/spaces.csv"
    ;;
  ros_yaml) copy '*.yaml' 64k ;;
  config)
    # Every experiment config and published-values file.
    find ../configs -name '*.toml' -exec cp {} "$seeds/" \;
    for published in ../maps/*/published.toml; do
      cp "$published" "$seeds/published-$(basename "$(dirname "$published")").toml"
    done
    ;;
  image)
    copy '*.pgm' 2M
    copy '*.png' 2M
    max_len=65536
    ;;
  weights)
    # Five header bytes (width - 1, height - 1, mode, lethal, unknown), then the weight
    # file or image: the arena weights (49 x 49) and the small PGM/PNG images.
    { printf '\x30\x30\x00\xfe\xff'; cat ../maps/weighted/arena-weights.csv; } > "$seeds/arena.bin"
    printf '\x02\x01\x01\xfd\xfa1, 2 3\n4 5,65535\n' > "$seeds/small.bin"
    for image in $(find ../maps -name '*.pgm' -size -64k); do
      { printf '\x09\x09\x00\xfe\xfa'; cat "$image"; } > "$seeds/$(basename "$image").bin"
    done
    max_len=65536
    ;;
  gppc)
    # A scenario, a NUL byte, then a patch file (fuzz_targets/gppc.rs): the module docs'
    # tiny pair, and the start of the sample scenario alone (read as both files).
    printf 'version 2\nheight 3\nwidth 4\ncost 1 octile\npatch tiny.patch\ncommands\nP 0 0 0 0\nQ 0 0 0 3 2 4.4142135624\nP 1 1 2 1\nQ 1 0 0 3 2 -1\n\0type patch\npatches 2\npatch 0\nheight 3\nwidth 4\nmap\n....\n....\n....\npatch 1\nheight 2\nwidth 2\nmap\n@@\n@@\n' > "$seeds/tiny.bin"
    head -c 16384 ../maps/gppc-dynamic/switch_sc1_Aurora_TheFrozenSea.scen > "$seeds/sample.scen"
    ;;
  replan_config) find ../configs/replan -name '*.toml' -exec cp {} "$seeds/" \; ;;
  expanded)
    # A sweep's expanded.jsonl: configs/movingai.toml's, cut to its first 16 KiB.
    out=$(mktemp -d)
    (cd .. && cargo run -q --release -p xtask -- experiment configs/movingai.toml \
      --output "$out/m" --quiet >/dev/null)
    head -c 16384 "$out/m/expanded.jsonl" > "$seeds/movingai.jsonl"
    rm -rf "$out"
    ;;
  stream) shard_streams "" ;;
  frames)
    # Shape byte 2 (see fuzz_targets/frames.rs): the shard streams, framed by the target;
    # shape 1: two payloads by hand (no strings and no records; one string, no records);
    # shape 0: an empty frame with its checksum, and a frame stating 2^32 - 1 bytes.
    shard_streams '\x02'
    printf '\x01\x00\x00' > "$seeds/empty-payload.bin"
    printf '\x01\x01\x03map\x00' > "$seeds/one-string.bin"
    printf '\x00\x00\x00\x00\x00\x00\x00\x00\x00' > "$seeds/empty-frame.bin"
    printf '\x00\xff\xff\xff\xff\x00\x00\x00\x00' > "$seeds/huge-frame.bin"
    ;;
  edits)
    # Planner byte, size 12 x 9, weighted, a few blocked cells (14 bytes of bits), start
    # (0,0), goal (11,8), then two batches of edits: block (3,2), free (4,4) | weight 3 at
    # (5,5), toggle (6,3) (fuzz_targets/edits.rs).
    body='\x0b\x08\x01\x10\x20\x00\x44\x00\x81\x00\x10\x00\x02\x00\x00\x00\x00'
    body="$body"'\x00\x00\x0b\x08\x03\x02\x00\x04\x04\x81\x05\x05\x0a\x06\x03\x83'
    for planner in $(seq 0 40); do
      printf "\\x$(printf %02x "$planner")$body" > "$seeds/planner-$planner.bin"
    done
    # Long enough for a 24 x 24 grid with weights' batches of edits (4 + 72 + 4 + 288 bytes).
    max_len=1024
    ;;
  *)
    echo "unknown target $target (movingai scen seed003 csv ros_yaml image config stream frames weights gppc replan_config expanded edits)" >&2
    exit 2
    ;;
esac
# -s none: the readers are safe Rust, so AddressSanitizer adds cost and no checks;
# -a: debug assertions and overflow checks on, so an overflow is a crash.
RUSTC_BOOTSTRAP=1 exec nice -n 10 cargo fuzz run -s none -a "$target" \
  "corpus/$target" "$seeds" -- \
  -max_total_time="$seconds" -max_len="$max_len" -rss_limit_mb=2048 \
  -artifact_prefix="artifacts/$target/" -print_final_stats=1 "$@"
