//! The compact resume stream's frames (`records.stream` after its header line):
//! `planner_runner::frames::FrameReader` never panics on any bytes, and refuses a frame
//! whose stated length is over `frames::MAX_FRAME_BYTES` before reading it.
//!
//! The first byte picks the input's shape (its value modulo 3):
//! - 0: the rest is the frames as they are (a mutated checksum rarely matches, so this
//!   mostly exercises the frame layer); a first frame stating more than the limit is refused.
//! - 1: the rest is one payload, sent as a frame with its true length and checksum, so the
//!   payload decoder (string table, columns, records, varints, extras JSON) sees every
//!   mutation: compressed by `frames::encode_payload` (format 3), and as it is to a reader
//!   of format 2's uncompressed frames; the frame is then sent again with a length over the
//!   limit, which must be refused.
//! - 0 also goes to a reader of format 2, and both readers read Snappy-decompressed bytes
//!   of any shape through mode 1.
//! - 2: the rest is a JSON Lines stream (`shard.jsonl`); its runs, framed by
//!   `frames::encode_batch` as a sweep writes them, read back as the same runs and records.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_runner::frames::{
    encode_batch, encode_payload, FrameReader, MAX_FRAME_BYTES, ROW_FRAMED_FORMAT,
};
use planner_runner::stream::StreamReader;

/// Every run of `bytes` through a fresh reader of frames of `format`, with checks that
/// hold for any input.
fn read_format(bytes: &[u8], format: u32) -> Result<u64, String> {
    let Some(mut frames) = FrameReader::for_format(format) else {
        unreachable!("format {format} is read");
    };
    let mut reader = bytes;
    let mut n = 0u64;
    let end = loop {
        match frames.next_run(&mut reader, "fuzz") {
            Ok(Some(_)) => n += 1,
            Ok(None) => break Ok(n),
            Err(e) => break Err(e.to_string()),
        }
    };
    assert!(frames.complete_bytes() + frames.cut_bytes() <= bytes.len() as u64);
    // A record takes more than one byte.
    assert!(n <= bytes.len() as u64);
    end
}

/// Every run of `bytes` through a fresh reader of this version's frames.
fn read_all(bytes: &[u8]) -> Result<u64, String> {
    read_format(bytes, planner_runner::frames::FRAMED_FORMAT)
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    if mode % 3 == 2 {
        round_trip(rest);
        return;
    }
    if mode % 3 == 0 {
        let _ = read_format(rest, ROW_FRAMED_FORMAT);
        let result = read_all(rest);
        if rest.len() >= 8 {
            let stated = u32::from_le_bytes([rest[0], rest[1], rest[2], rest[3]]);
            if stated > MAX_FRAME_BYTES {
                let err = result.expect_err("a frame over the limit was accepted");
                assert!(err.contains("more than"), "{err}");
            }
        }
        return;
    }
    let Ok(length) = u32::try_from(rest.len()) else {
        return;
    };
    let mut rows = Vec::with_capacity(rest.len() + 8);
    rows.extend_from_slice(&length.to_le_bytes());
    rows.extend_from_slice(&crc32fast::hash(rest).to_le_bytes());
    rows.extend_from_slice(rest);
    let _ = read_format(&rows, ROW_FRAMED_FORMAT);
    let mut frame = Vec::new();
    if encode_payload(&mut frame, rest).is_err() {
        return;
    }
    let _ = read_all(&frame);
    // The same frame stating a length over the limit: refused, whatever follows.
    let over = MAX_FRAME_BYTES + 1 + u32::from(mode >> 1);
    frame[..4].copy_from_slice(&over.to_le_bytes());
    let err = read_all(&frame).expect_err("a frame over the limit was accepted");
    assert!(err.contains("more than"), "{err}");
});

/// The runs of the JSON Lines stream `text` (up to its first error), framed in batches of
/// up to 7 runs, read back unchanged.
fn round_trip(text: &[u8]) {
    let Ok((_, mut stream)) = StreamReader::new(text, "fuzz") else {
        return;
    };
    let mut runs = Vec::new();
    while let Ok(Some(run)) = stream.next_run() {
        runs.push(run);
    }
    let mut framed = Vec::new();
    for batch in runs.chunks(7) {
        if encode_batch(&mut framed, batch).is_err() {
            return;
        }
    }
    let mut frames = FrameReader::new();
    let mut reader = framed.as_slice();
    let mut back = Vec::with_capacity(runs.len());
    while let Some(run) = frames
        .next_run(&mut reader, "fuzz")
        .expect("a stream framed as a sweep writes it reads back")
    {
        back.push(run);
    }
    assert_eq!(frames.complete_bytes(), framed.len() as u64);
    assert_eq!(frames.cut_bytes(), 0);
    assert!(back == runs, "framed runs read back differently");
}
