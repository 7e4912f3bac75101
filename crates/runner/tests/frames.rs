//! The framed resume stream (issue 29, src/frames.rs): every field of a record survives the
//! round trip exactly; a stream cut at any byte reads as the whole frames before the cut
//! and says it was cut; a damaged frame with frames after it is an error; and a run of A*
//! on arena.map takes far fewer bytes than its JSON line; a failed conversion names the
//! file it writes.

use std::io::Cursor;

use planner_api::{Cell, Counters, Mark, Path, ReturnLeg, Series};
use planner_runner::frames::{encode_batch, FRAMED_FORMAT};
use planner_runner::record::{RunRecord, RunStatus};
use planner_runner::stream::{self, StreamHeader, StreamReader};

/// A record with every optional field set (`full`) or none.
fn record(run: u64, full: bool) -> RunRecord {
    let mut counters = Counters::new();
    counters.push("n_expanded", run * 7 + 1);
    counters.push(format!("own counter {run}"), u64::MAX - run);
    RunRecord {
        map: if run % 2 == 0 {
            "a.map"
        } else {
            "b \"é\".map"
        }
        .into(),
        problem: run as usize + 1,
        start: Cell::new(run as u32, 3),
        goal: Cell::new(u32::MAX, 0),
        planner: format!("label{}", run % 3),
        algorithm: "astar".into(),
        repeat: run as u32 % 5,
        seed: full.then_some(u64::MAX),
        status: [
            RunStatus::Found,
            RunStatus::NoPath,
            RunStatus::BudgetExhausted,
            RunStatus::InvalidProblem,
        ][run as usize % 4],
        error: full.then(|| "start (1, 2) is blocked\nsecond line".into()),
        steps: full.then_some(12),
        turns: full.then_some(0),
        score: full.then_some(300),
        length: full.then_some(std::f64::consts::PI * run as f64),
        optimal_length: full.then_some(-0.0),
        bucket: full.then_some(u32::MAX),
        valid: full.then_some(run % 2 == 0),
        admissible: full.then_some(false),
        counters,
        time_ms: 0.1 + run as f64 * 1e-9,
        setup_ms: f64::MIN_POSITIVE,
        peak_heap_bytes: run << 40,
        path: full.then(|| Path::new(vec![Cell::new(0, 0), Cell::new(1, 1)])),
        returns: full.then(|| vec![ReturnLeg { start: 0, end: 1 }]),
        marks: if full {
            vec![Mark::new(Cell::new(1, 1), "H1'")]
        } else {
            Vec::new()
        },
        series: if full {
            vec![Series {
                name: "best".into(),
                x: "iteration".into(),
                points: vec![[0.0, 1.5], [1.0, 1e300]],
            }]
        } else {
            Vec::new()
        },
        cost: full.then_some(2.25),
    }
}

fn header() -> StreamHeader {
    StreamHeader {
        format: FRAMED_FORMAT,
        experiment: "frames".into(),
        config: "c.toml".into(),
        config_hash: "0".into(),
        shard: 1,
        shards: 1,
        runs: 40,
        total_runs: 40,
        gridplan: Some("test".into()),
        inputs: None,
    }
}

/// A framed stream of `runs` in frames of `per_frame` runs.
fn framed(runs: &[(u64, RunRecord)], per_frame: usize) -> (Vec<u8>, Vec<usize>) {
    let mut bytes = header().to_line().unwrap();
    let mut ends = vec![bytes.len()];
    for chunk in runs.chunks(per_frame) {
        encode_batch(&mut bytes, chunk).unwrap();
        ends.push(bytes.len());
    }
    (bytes, ends)
}

/// The runs read (each with its index), whether the stream was cut, and the bytes read.
type Read = (Vec<(u64, RunRecord)>, bool, u64);

/// Everything a reader gets from `bytes`: the runs, whether it was cut, and the bytes of
/// its complete frames; or the error.
fn read(bytes: &[u8]) -> Result<Read, String> {
    let (_, mut reader) = StreamReader::new(Cursor::new(bytes), "s").map_err(|e| e.to_string())?;
    let mut runs = Vec::new();
    while let Some(run) = reader.next_run().map_err(|e| e.to_string())? {
        runs.push(run);
    }
    Ok((runs, reader.was_cut(), reader.complete_bytes()))
}

#[test]
fn every_field_survives_the_round_trip() {
    let runs: Vec<(u64, RunRecord)> = (0..40).map(|i| (i * 3, record(i, i % 3 != 1))).collect();
    let (bytes, ends) = framed(&runs, 16);
    let (back, cut, complete) = read(&bytes).unwrap();
    assert_eq!(back, runs);
    assert!(!cut);
    assert_eq!(complete, *ends.last().unwrap() as u64);
    // The JSON forms agree too (-0.0 and the largest floats included).
    assert_eq!(
        serde_json::to_string(&back.iter().map(|r| &r.1).collect::<Vec<_>>()).unwrap(),
        serde_json::to_string(&runs.iter().map(|r| &r.1).collect::<Vec<_>>()).unwrap()
    );
}

#[test]
fn a_stream_cut_anywhere_reads_as_its_whole_frames() {
    let runs: Vec<(u64, RunRecord)> = (0..12).map(|i| (i, record(i, i % 2 == 0))).collect();
    let (bytes, ends) = framed(&runs, 4);
    for cut_at in ends[0]..bytes.len() {
        let (back, cut, complete) = read(&bytes[..cut_at]).unwrap();
        // The frames that ended at or before the cut.
        let whole = ends.iter().filter(|&&e| e <= cut_at).count() - 1;
        assert_eq!(back.len(), whole * 4, "cut at {cut_at}");
        assert_eq!(back[..], runs[..whole * 4]);
        assert_eq!(complete, ends[whole] as u64, "cut at {cut_at}");
        assert_eq!(cut, !ends.contains(&cut_at), "cut at {cut_at}");
    }
}

#[test]
fn a_damaged_frame_is_dropped_only_at_the_end() {
    let runs: Vec<(u64, RunRecord)> = (0..8).map(|i| (i, record(i, true))).collect();
    let (bytes, ends) = framed(&runs, 4);
    // A byte of the last frame's payload flipped (its length intact): a torn last write.
    let mut last = bytes.clone();
    last[ends[2] - 3] ^= 0x40;
    let (back, cut, complete) = read(&last).unwrap();
    assert_eq!(back[..], runs[..4]);
    assert!(cut);
    assert_eq!(complete, ends[1] as u64);
    // The same in the first frame, with a frame after it: an error naming the frame.
    let mut first = bytes.clone();
    first[ends[1] - 3] ^= 0x40;
    let error = read(&first).unwrap_err();
    assert!(
        error.contains("frame 1") && error.contains("checksum"),
        "{error}"
    );
    // A length past the limit is refused before it is allocated.
    let mut huge = bytes[..ends[0]].to_vec();
    huge.extend_from_slice(&u32::MAX.to_le_bytes());
    huge.extend_from_slice(&[0; 4]);
    let error = read(&huge).unwrap_err();
    assert!(error.contains("more than"), "{error}");
}

/// The bytes per run of a typical sweep (A* on a scenario map, 8 counters, 100 repeats of
/// each problem, noisy times of whole nanoseconds) framed and as JSON lines: the framed
/// stream is under 8 bytes per run, at most a thirtieth of the JSON Lines one, and every
/// record reads back exactly.
#[test]
fn a_framed_run_is_a_fraction_of_its_json_line() {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(29);
    let runs: Vec<(u64, RunRecord)> = (0..8192)
        .map(|i| {
            let problem = i / 100;
            let mut counters = Counters::new();
            for (k, name) in [
                "n_expanded",
                "n_generated",
                "n_reopened",
                "n_open_max",
                "n_closed",
                "n_pushes",
                "n_pops",
                "n_stale",
            ]
            .into_iter()
            .enumerate()
            {
                counters.push(name, 1000 + problem * 37 + k as u64);
            }
            let r = RunRecord {
                map: "arena.map".into(),
                problem: problem as usize,
                start: Cell::new(10 + problem as u32 % 40, 20),
                goal: Cell::new(40, 8 + problem as u32 % 30),
                planner: "astar".into(),
                algorithm: "astar".into(),
                repeat: (i % 100) as u32,
                seed: None,
                status: RunStatus::Found,
                error: None,
                steps: Some(40),
                turns: Some(6),
                score: Some(46),
                length: Some(47.213_203_435_596_43 + problem as f64),
                optimal_length: Some(47.21320343 + problem as f64),
                bucket: Some(11),
                valid: Some(true),
                admissible: None,
                counters,
                time_ms: rng.gen_range(5_000u64..30_000) as f64 / 1e6,
                setup_ms: rng.gen_range(50u64..900) as f64 / 1e6,
                peak_heap_bytes: 123_456 + problem,
                path: None,
                returns: None,
                marks: Vec::new(),
                series: Vec::new(),
                cost: None,
            };
            (i, r)
        })
        .collect();
    let mut framed = header().to_line().unwrap();
    let header_bytes = framed.len();
    for chunk in runs.chunks(1024) {
        encode_batch(&mut framed, chunk).unwrap();
    }
    let mut lines = Vec::new();
    for (run, r) in &runs {
        stream::encode(&mut lines, *run, r).unwrap();
    }
    let (back, cut, _) = read(&framed).unwrap();
    assert!(!cut);
    assert!(back == runs, "the sweep's records read back differently");
    let framed = &framed[header_bytes..];
    let per_run = |bytes: &[u8]| bytes.len() as f64 / runs.len() as f64;
    println!(
        "framed {:.1} bytes per run, JSON Lines {:.1}",
        per_run(framed),
        per_run(&lines)
    );
    assert!(per_run(framed) < 8.0, "{}", per_run(framed));
    assert!(per_run(framed) * 30.0 < per_run(&lines));
}

/// A stream of the previous version's uncompressed frames (format 2: one record's fields
/// in record order, its run, repeat and times as they are) still reads.
#[test]
fn a_format_2_stream_still_reads() {
    let mut payload = vec![4];
    for text in ["m.map", "label", "astar", "n_expanded"] {
        payload.push(text.len() as u8);
        payload.extend_from_slice(text.as_bytes());
    }
    // One record: run 300 (two varint bytes), map 0, problem 2, start (1, 2), goal (3, 4),
    // labels 1 and 2, repeat 7, found, flags: a length.
    payload.extend_from_slice(&[1, 0xac, 0x02, 0, 2, 1, 2, 3, 4, 1, 2, 7, 0, 16]);
    payload.extend_from_slice(&2.5f64.to_le_bytes());
    // One counter (name 3) of 42, the times, the peak heap.
    payload.extend_from_slice(&[1, 3, 42]);
    payload.extend_from_slice(&0.1f64.to_le_bytes());
    payload.extend_from_slice(&(-0.0f64).to_le_bytes());
    payload.push(9);
    let mut bytes = StreamHeader {
        format: 2,
        ..header()
    }
    .to_line()
    .unwrap();
    bytes.extend_from_slice(&(payload.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    bytes.extend_from_slice(&payload);
    let (back, cut, complete) = read(&bytes).unwrap();
    assert!(!cut);
    assert_eq!(complete as usize, bytes.len());
    let [(run, r)] = &back[..] else {
        panic!("{back:?}")
    };
    assert_eq!(*run, 300);
    assert_eq!((r.map.as_str(), r.problem, r.repeat), ("m.map", 2, 7));
    assert_eq!((r.start, r.goal), (Cell::new(1, 2), Cell::new(3, 4)));
    assert_eq!(
        (r.planner.as_str(), r.algorithm.as_str()),
        ("label", "astar")
    );
    assert_eq!((r.status, r.length), (RunStatus::Found, Some(2.5)));
    assert_eq!(r.counters.get("n_expanded"), Some(42));
    assert_eq!(r.time_ms.to_bits(), 0.1f64.to_bits());
    assert_eq!(r.setup_ms.to_bits(), (-0.0f64).to_bits());
    assert_eq!(r.peak_heap_bytes, 9);
}

/// A frame whose compressed payload states a decompressed length it cannot reach (Snappy
/// writes at most 64 bytes for 3) is refused before that length is allocated.
#[test]
fn a_payload_stating_more_than_it_holds_is_refused() {
    let mut compressed = Vec::new();
    let mut stated: u64 = 200 << 20;
    while stated >= 0x80 {
        compressed.push((stated as u8 & 0x7f) | 0x80);
        stated >>= 7;
    }
    compressed.push(stated as u8);
    // One literal of 4 bytes.
    compressed.extend_from_slice(&[3 << 2, 1, 2, 3, 4]);
    let mut bytes = header().to_line().unwrap();
    bytes.extend_from_slice(&(compressed.len() as u32).to_le_bytes());
    bytes.extend_from_slice(&crc32fast::hash(&compressed).to_le_bytes());
    bytes.extend_from_slice(&compressed);
    let error = read(&bytes).unwrap_err();
    assert!(
        error.contains("frame 1") && error.contains("states more bytes"),
        "{error}"
    );
}

/// A writer that refuses every write, as a full disk would.
struct FullDisk;

impl std::io::Write for FullDisk {
    fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
        Err(std::io::Error::other("no space left on device"))
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// A copy that cannot be written names the file it writes, not the stream it reads: both
/// directions of the format conversion.
#[test]
fn a_failed_copy_names_the_file_written() {
    let runs: Vec<_> = (0..3).map(|run| (run, record(run, run % 2 == 0))).collect();
    let (bytes, _) = framed(&runs, 2);
    let out = std::path::Path::new("area/records.stream");
    let error = planner_runner::frames::write_json_lines(
        Cursor::new(&bytes),
        "in/shard.stream",
        (&mut FullDisk, out),
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("area/records.stream") && !error.contains("in/shard.stream"),
        "{error}"
    );
    let mut lines = Vec::new();
    planner_runner::frames::write_json_lines(
        Cursor::new(&bytes),
        "in/shard.stream",
        (&mut lines, out),
        None,
    )
    .unwrap();
    let error = planner_runner::frames::write_framed(
        Cursor::new(&lines),
        "in/records.jsonl",
        (&mut FullDisk, out),
        3,
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("area/records.stream") && !error.contains("in/records.jsonl"),
        "{error}"
    );
}
