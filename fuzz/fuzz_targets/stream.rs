//! Stream files (`records.stream` that `--resume` reads, `shard.stream` that `merge` reads,
//! framed or as JSON Lines):
//! `planner_runner::stream::StreamReader` never panics on any bytes, reads a header with
//! a shard count a command accepts, and stops at a cut last line or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_runner::shard::Shard;
use planner_runner::stream::StreamReader;

fuzz_target!(|data: &[u8]| {
    let Ok((header, mut reader)) = StreamReader::new(data, "fuzz") else {
        return;
    };
    assert!(
        Shard::new(header.shard, header.shards).is_ok(),
        "{header:?}"
    );
    let mut n = 0u64;
    while let Ok(Some(_)) = reader.next_run() {
        n += 1;
    }
    assert!(reader.complete_bytes() <= data.len() as u64);
    // A record takes more than one byte.
    assert!(n <= data.len() as u64);
});
