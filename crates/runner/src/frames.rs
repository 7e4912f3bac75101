//! The compact record stream (issue 29): the resume stream a sweep appends to, as
//! compressed binary batches with a checksum instead of JSON Lines.
//!
//! A framed stream file starts with the same [`StreamHeader`](crate::stream::StreamHeader)
//! JSON line as a JSON Lines stream, with `"format": 3` ([`FRAMED_FORMAT`]), then one
//! frame per batch:
//!
//! - 4 bytes: the length `n` of the compressed payload, little-endian (at most
//!   [`MAX_FRAME_BYTES`]);
//! - 4 bytes: the CRC-32 (ISO-HDLC, as zlib's) of those `n` bytes, little-endian;
//! - `n` bytes: the payload, compressed with Snappy's raw format (at most
//!   [`MAX_FRAME_BYTES`] once decompressed).
//!
//! The payload is the batch's string table (map names, labels, registry names, counter
//! names: a count, then each as a length and UTF-8 bytes), its record count, the byte
//! lengths of its [`COLUMNS`] columns, then the columns. Each field of a record goes to
//! its column (the run, the map, the cells, the repeat, the counters' values, the times,
//! ...), so a column holds like values: the deterministic columns of a problem's repeats
//! repeat themselves and compress to almost nothing, and the measured times, which are
//! noise, sit apart from them. Integers are LEB128 varints; the run and the repeat are
//! stored as their (zigzag) difference from the previous record's plus one, so a
//! sweep's consecutive runs store zeros. Floats are their 8 IEEE bytes (exact, as
//! JSON's shortest form is), except `time_ms` and `setup_ms`: a time that is a whole
//! number of nanoseconds `n` as the runner measures it (`n as f64 / 1e6`, bit for bit)
//! is stored as the varint `n + 1`, any other float as `0` followed by its 8 bytes in a
//! column of its own, so every record reads back exactly. A record's rarely present
//! parts (error text, path, return legs, marks, series) go as one JSON object in the
//! extras column when present.
//!
//! Snappy, not zstd or LZ4: the columns leave the compressor little but runs of repeated
//! bytes to find, which Snappy finds as well as the others at its speed, and it is
//! already built for runs.parquet (pure Rust, no C build, MSRV-safe); zstd's entropy
//! coding would save about one byte per run on the noisy time columns and costs a C
//! build.
//!
//! A frame is appended whole and flushed, so a process killed mid-write leaves complete
//! frames and at most one cut frame at the end: [`FrameReader`] stops at a short frame,
//! or at a last frame whose checksum fails, and reports it (`FrameReader::cut_bytes`);
//! a bad checksum with frames after it is an error, never dropped silently. A frame, or
//! a decompressed payload, longer than [`MAX_FRAME_BYTES`] is refused before anything is
//! allocated for it. Streams of format 2 (the frames of the previous version: the same
//! fields in record order, uncompressed, runs, repeats and times stored as they are) are
//! still read.

use std::collections::VecDeque;
use std::io::{BufRead, Read};

use planner_api::{Cell, Counters, Mark, Path, ReturnLeg, Series};
use serde::{Deserialize, Serialize};

use crate::record::{RunRecord, RunStatus};
use crate::stream::{Place, StreamError, StreamProblem};
use crate::RunnerError;

/// The stream header's `format` of a framed stream as this version writes it (a JSON
/// Lines stream's is 1, the uncompressed frames of the previous version 2).
pub const FRAMED_FORMAT: u32 = 3;

/// The stream header's `format` of the previous version's uncompressed frames, still read.
pub const ROW_FRAMED_FORMAT: u32 = 2;

/// The longest frame payload a reader accepts, compressed or not: 256 MiB (as a JSON Lines
/// stream's line).
pub const MAX_FRAME_BYTES: u32 = 256 << 20;

/// The parts of a record that most runs lack, as JSON after the record when present.
#[derive(Serialize, Deserialize, Default)]
struct Extras {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    error: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    path: Option<Path>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    returns: Option<Vec<ReturnLeg>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    marks: Vec<Mark>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    series: Vec<Series>,
}

// Flags of a record: which optional fields follow, and the booleans.
const SEED: u16 = 1;
const STEPS: u16 = 1 << 1;
const TURNS: u16 = 1 << 2;
const SCORE: u16 = 1 << 3;
const LENGTH: u16 = 1 << 4;
const OPTIMAL: u16 = 1 << 5;
const BUCKET: u16 = 1 << 6;
const VALID: u16 = 1 << 7;
const VALID_TRUE: u16 = 1 << 8;
const ADMISSIBLE: u16 = 1 << 9;
const ADMISSIBLE_TRUE: u16 = 1 << 10;
const COST: u16 = 1 << 11;
const EXTRAS: u16 = 1 << 12;

/// The status column's value of a record whose outcome is the previous record's
/// ([`same_outcome`]); any other record stores its status code plus one, then its flags.
const SAME: u64 = 0;

// The columns of a payload, in the order they are stored.
/// The run (difference from the previous run plus one).
const C_RUN: usize = 0;
/// The map's string id.
const C_MAP: usize = 1;
/// The problem.
const C_PROBLEM: usize = 2;
/// The start's and the goal's coordinates.
const C_CELLS: usize = 3;
/// The planner's label and algorithm, as string ids.
const C_LABELS: usize = 4;
/// The repeat (difference from the previous repeat plus one).
const C_REPEAT: usize = 5;
/// The status plus one and the flags, or [`SAME`].
const C_STATUS: usize = 6;
/// The optional integers present (seed, steps, turns, score, bucket).
const C_INTS: usize = 7;
/// The optional floats present (length, optimal length, cost).
const C_FLOATS: usize = 8;
/// The counters' count and their names' string ids.
const C_COUNTER_NAMES: usize = 9;
/// The counters' values.
const C_COUNTER_VALUES: usize = 10;
/// `time_ms` and `setup_ms` as nanoseconds plus one (0: the float is in `C_RAW_TIMES`).
const C_TIMES: usize = 11;
/// The times that are not whole nanoseconds, as floats.
const C_RAW_TIMES: usize = 12;
/// `peak_heap_bytes`.
const C_HEAP: usize = 13;
/// The extras' JSON, each as a length and its bytes.
const C_EXTRAS: usize = 14;
/// How many columns a payload has.
pub const COLUMNS: usize = 15;

/// A batch's string table being built: each distinct string once.
#[derive(Default)]
struct Strings<'a> {
    list: Vec<&'a str>,
}

impl<'a> Strings<'a> {
    fn id(&mut self, text: &'a str) -> u64 {
        // A batch has a handful of distinct strings; a linear search beats hashing.
        match self.list.iter().rposition(|s| *s == text) {
            Some(i) => i as u64,
            None => {
                self.list.push(text);
                self.list.len() as u64 - 1
            }
        }
    }
}

fn put_varint(out: &mut Vec<u8>, mut value: u64) {
    while value >= 0x80 {
        out.push((value as u8 & 0x7f) | 0x80);
        value >>= 7;
    }
    out.push(value as u8);
}

fn put_f64(out: &mut Vec<u8>, value: f64) {
    out.extend_from_slice(&value.to_le_bytes());
}

/// `value - expected` (wrapping), zigzag-encoded: small either way round.
fn zigzag(value: u64, expected: u64) -> u64 {
    let d = value.wrapping_sub(expected) as i64;
    ((d << 1) ^ (d >> 63)) as u64
}

/// The value that [`zigzag`] encoded as `z` against `expected`.
fn unzigzag(z: u64, expected: u64) -> u64 {
    let d = ((z >> 1) as i64) ^ -((z & 1) as i64);
    expected.wrapping_add(d as u64)
}

/// `ms` as a whole number of nanoseconds `n` when `n as f64 / 1e6` is `ms` bit for bit
/// (as [`crate::run`] measures times), else `None`.
fn whole_nanoseconds(ms: f64) -> Option<u64> {
    let ns = (ms * 1e6).round();
    // Below 2^53, every whole number is a float.
    if !(0.0..9.0e15).contains(&ns) {
        return None;
    }
    let n = ns as u64;
    ((n as f64 / 1e6).to_bits() == ms.to_bits()).then_some(n)
}

fn status_code(status: RunStatus) -> u8 {
    match status {
        RunStatus::Found => 0,
        RunStatus::NoPath => 1,
        RunStatus::BudgetExhausted => 2,
        RunStatus::InvalidProblem => 3,
    }
}

/// A batch's columns being written, and the previous record's run and repeat.
struct Columns {
    columns: [Vec<u8>; COLUMNS],
    /// The run expected next (the previous one plus one).
    next_run: u64,
    /// The repeat expected next (the previous one plus one).
    next_repeat: u32,
}

impl Columns {
    fn new(runs: usize) -> Columns {
        Columns {
            columns: std::array::from_fn(|_| Vec::with_capacity(runs * 4)),
            next_run: 0,
            next_repeat: 0,
        }
    }

    fn varint(&mut self, column: usize, value: u64) {
        put_varint(&mut self.columns[column], value);
    }
}

/// Whether `r`'s fields after its run and repeat, its times and peak heap aside, are
/// those of `before` (floats bit for bit), and neither has extras: then `r` is stored as
/// "the same as the previous record" (a repeat of one problem usually is).
fn same_outcome(r: &RunRecord, before: &RunRecord) -> bool {
    let bits = |x: Option<f64>| x.map(f64::to_bits);
    let no_extras = |r: &RunRecord| {
        r.error.is_none()
            && r.path.is_none()
            && r.returns.is_none()
            && r.marks.is_empty()
            && r.series.is_empty()
    };
    no_extras(r)
        && no_extras(before)
        && r.map == before.map
        && r.problem == before.problem
        && r.start == before.start
        && r.goal == before.goal
        && r.planner == before.planner
        && r.algorithm == before.algorithm
        && r.seed == before.seed
        && r.status == before.status
        && (r.steps, r.turns, r.score, r.bucket)
            == (before.steps, before.turns, before.score, before.bucket)
        && (bits(r.length), bits(r.optimal_length), bits(r.cost))
            == (
                bits(before.length),
                bits(before.optimal_length),
                bits(before.cost),
            )
        && (r.valid, r.admissible) == (before.valid, before.admissible)
        && r.counters.len() == before.counters.len()
        && r.counters.iter().eq(before.counters.iter())
}

/// Appends run `run`'s `record` to `out`'s columns, its strings' ids from `strings`;
/// `before` is the batch's previous record.
fn put_record<'a>(
    out: &mut Columns,
    strings: &mut Strings<'a>,
    (run, r): (u64, &'a RunRecord),
    before: Option<&RunRecord>,
) -> Result<(), RunnerError> {
    out.varint(C_RUN, zigzag(run, out.next_run));
    out.next_run = run.wrapping_add(1);
    out.varint(
        C_REPEAT,
        zigzag(u64::from(r.repeat), u64::from(out.next_repeat)),
    );
    out.next_repeat = r.repeat.wrapping_add(1);
    if before.is_some_and(|before| same_outcome(r, before)) {
        out.varint(C_STATUS, SAME);
    } else {
        put_outcome(out, strings, r)?;
    }
    for ms in [r.time_ms, r.setup_ms] {
        match whole_nanoseconds(ms) {
            Some(n) => out.varint(C_TIMES, n + 1),
            None => {
                out.varint(C_TIMES, 0);
                put_f64(&mut out.columns[C_RAW_TIMES], ms);
            }
        }
    }
    out.varint(C_HEAP, r.peak_heap_bytes);
    Ok(())
}

/// Appends `r`'s fields but its run, repeat, times and peak heap to `out`'s columns.
fn put_outcome<'a>(
    out: &mut Columns,
    strings: &mut Strings<'a>,
    r: &'a RunRecord,
) -> Result<(), RunnerError> {
    let extras = r.error.is_some()
        || r.path.is_some()
        || r.returns.is_some()
        || !r.marks.is_empty()
        || !r.series.is_empty();
    let flag = |present: bool, bit: u16| if present { bit } else { 0 };
    let flags = flag(r.seed.is_some(), SEED)
        | flag(r.steps.is_some(), STEPS)
        | flag(r.turns.is_some(), TURNS)
        | flag(r.score.is_some(), SCORE)
        | flag(r.length.is_some(), LENGTH)
        | flag(r.optimal_length.is_some(), OPTIMAL)
        | flag(r.bucket.is_some(), BUCKET)
        | flag(r.valid.is_some(), VALID)
        | flag(r.valid == Some(true), VALID_TRUE)
        | flag(r.admissible.is_some(), ADMISSIBLE)
        | flag(r.admissible == Some(true), ADMISSIBLE_TRUE)
        | flag(r.cost.is_some(), COST)
        | flag(extras, EXTRAS);
    out.varint(C_STATUS, u64::from(status_code(r.status)) + 1);
    let map = strings.id(&r.map);
    out.varint(C_MAP, map);
    out.varint(C_PROBLEM, r.problem as u64);
    for value in [r.start.x, r.start.y, r.goal.x, r.goal.y] {
        out.varint(C_CELLS, u64::from(value));
    }
    let planner = strings.id(&r.planner);
    let algorithm = strings.id(&r.algorithm);
    out.varint(C_LABELS, planner);
    out.varint(C_LABELS, algorithm);
    out.varint(C_STATUS, u64::from(flags));
    for value in [r.seed, r.steps, r.turns, r.score, r.bucket.map(u64::from)]
        .into_iter()
        .flatten()
    {
        out.varint(C_INTS, value);
    }
    for value in [r.length, r.optimal_length, r.cost].into_iter().flatten() {
        put_f64(&mut out.columns[C_FLOATS], value);
    }
    out.varint(C_COUNTER_NAMES, r.counters.len() as u64);
    for (name, value) in r.counters.iter() {
        let id = strings.id(name);
        out.varint(C_COUNTER_NAMES, id);
        out.varint(C_COUNTER_VALUES, value);
    }
    if extras {
        let json = serde_json::to_vec(&Extras {
            error: r.error.clone(),
            path: r.path.clone(),
            returns: r.returns.clone(),
            marks: r.marks.clone(),
            series: r.series.clone(),
        })
        .map_err(RunnerError::Json)?;
        out.varint(C_EXTRAS, json.len() as u64);
        out.columns[C_EXTRAS].extend_from_slice(&json);
    }
    Ok(())
}

/// The payload of `batch` (runs and their records), uncompressed.
fn batch_payload(batch: &[(u64, RunRecord)]) -> Result<Vec<u8>, RunnerError> {
    let mut strings = Strings::default();
    let mut columns = Columns::new(batch.len());
    let mut before = None;
    for (run, record) in batch {
        put_record(&mut columns, &mut strings, (*run, record), before)?;
        before = Some(record);
    }
    let total: usize = columns.columns.iter().map(Vec::len).sum();
    let mut payload = Vec::with_capacity(total + 256);
    put_varint(&mut payload, strings.list.len() as u64);
    for text in &strings.list {
        put_varint(&mut payload, text.len() as u64);
        payload.extend_from_slice(text.as_bytes());
    }
    put_varint(&mut payload, batch.len() as u64);
    for column in &columns.columns {
        put_varint(&mut payload, column.len() as u64);
    }
    for column in &columns.columns {
        payload.extend_from_slice(column);
    }
    Ok(payload)
}

/// Why a frame could not be written ([`RunnerError::Frame`]).
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    /// A payload longer than a frame holds, before or after compression.
    #[error("{0} bytes, more than a frame holds ({MAX_FRAME_BYTES})")]
    TooLarge(usize),
    /// The compressor refused the payload.
    #[error("compressing a frame: {0}")]
    Compress(snap::Error),
}

/// Appends `batch` (runs and their records) to `out` as one frame.
pub fn encode_batch(out: &mut Vec<u8>, batch: &[(u64, RunRecord)]) -> Result<(), RunnerError> {
    let payload = batch_payload(batch)?;
    encode_payload(out, &payload).map_err(|source| RunnerError::Frame {
        runs: batch.len(),
        source,
    })
}

/// Appends to `out` the frame holding `payload` (compressed, with its length and
/// checksum), as [`encode_batch`] does with a batch's payload; public for the fuzz target,
/// which sends any bytes through the payload decoder this way.
pub fn encode_payload(out: &mut Vec<u8>, payload: &[u8]) -> Result<(), FrameError> {
    let too_long = FrameError::TooLarge;
    if payload.len() > MAX_FRAME_BYTES as usize {
        return Err(too_long(payload.len()));
    }
    let start = out.len();
    out.resize(start + 8 + snap::raw::max_compress_len(payload.len()), 0);
    let n = snap::raw::Encoder::new()
        .compress(payload, &mut out[start + 8..])
        .map_err(FrameError::Compress)?;
    out.truncate(start + 8 + n);
    let length = u32::try_from(n)
        .ok()
        .filter(|n| *n <= MAX_FRAME_BYTES)
        .ok_or_else(|| too_long(n))?;
    let crc = crc32fast::hash(&out[start + 8..]);
    out[start..start + 4].copy_from_slice(&length.to_le_bytes());
    out[start + 4..start + 8].copy_from_slice(&crc.to_le_bytes());
    Ok(())
}

/// A payload being decoded; every read is bounds-checked (a checksum that matches by
/// chance, or a bug, gives an error, never a panic).
struct Payload<'a> {
    bytes: &'a [u8],
    at: usize,
}

/// Why a payload could not be decoded.
#[derive(Debug)]
struct Malformed(&'static str);

impl<'a> Payload<'a> {
    fn varint(&mut self) -> Result<u64, Malformed> {
        let mut value = 0u64;
        for shift in (0..64).step_by(7) {
            let byte = *self
                .bytes
                .get(self.at)
                .ok_or(Malformed("ends inside a number"))?;
            self.at += 1;
            value |= u64::from(byte & 0x7f) << shift;
            if byte & 0x80 == 0 {
                return Ok(value);
            }
        }
        Err(Malformed("a number longer than 64 bits"))
    }

    fn small<T: TryFrom<u64>>(&mut self) -> Result<T, Malformed> {
        T::try_from(self.varint()?).map_err(|_| Malformed("a number out of range"))
    }

    fn take(&mut self, n: usize) -> Result<&'a [u8], Malformed> {
        let end = self
            .at
            .checked_add(n)
            .filter(|end| *end <= self.bytes.len())
            .ok_or(Malformed("ends inside a value"))?;
        let bytes = &self.bytes[self.at..end];
        self.at = end;
        Ok(bytes)
    }

    fn f64(&mut self) -> Result<f64, Malformed> {
        let bytes: [u8; 8] = self
            .take(8)?
            .try_into()
            .map_err(|_| Malformed("ends inside a number"))?;
        Ok(f64::from_le_bytes(bytes))
    }

    fn is_done(&self) -> bool {
        self.at == self.bytes.len()
    }
}

/// A payload's records being decoded: one cursor per column, or (format 2) one cursor
/// for the whole record, every column read from it in turn.
struct Cursors<'a> {
    cursors: Vec<Payload<'a>>,
    /// Format 2: runs, repeats and times stored as they are, in one cursor.
    rows: bool,
    /// The run expected next (format 3).
    next_run: u64,
    /// The repeat expected next (format 3).
    next_repeat: u32,
}

impl<'a> Cursors<'a> {
    fn at(&mut self, column: usize) -> &mut Payload<'a> {
        let i = if self.rows { 0 } else { column };
        &mut self.cursors[i]
    }

    fn varint(&mut self, column: usize) -> Result<u64, Malformed> {
        self.at(column).varint()
    }

    fn small<T: TryFrom<u64>>(&mut self, column: usize) -> Result<T, Malformed> {
        self.at(column).small()
    }

    fn run(&mut self) -> Result<u64, Malformed> {
        let stored = self.varint(C_RUN)?;
        if self.rows {
            return Ok(stored);
        }
        let run = unzigzag(stored, self.next_run);
        self.next_run = run.wrapping_add(1);
        Ok(run)
    }

    fn repeat(&mut self) -> Result<u32, Malformed> {
        if self.rows {
            return self.small(C_REPEAT);
        }
        let stored = self.varint(C_REPEAT)?;
        let repeat = u32::try_from(unzigzag(stored, u64::from(self.next_repeat)))
            .map_err(|_| Malformed("a repeat out of range"))?;
        self.next_repeat = repeat.wrapping_add(1);
        Ok(repeat)
    }

    fn time(&mut self) -> Result<f64, Malformed> {
        if self.rows {
            return self.at(0).f64();
        }
        match self.varint(C_TIMES)? {
            0 => self.at(C_RAW_TIMES).f64(),
            n => Ok((n - 1) as f64 / 1e6),
        }
    }
}

/// The runs and records of one frame's decompressed payload `bytes`; `rows`: a format 2
/// payload.
fn decode_payload(bytes: &[u8], rows: bool) -> Result<Vec<(u64, RunRecord)>, Malformed> {
    let mut p = Payload { bytes, at: 0 };
    let n_strings: usize = p.small()?;
    // Every string takes at least its length byte: a count past the payload is refused
    // before anything is allocated for it.
    if n_strings > bytes.len() {
        return Err(Malformed("more strings than bytes"));
    }
    let mut strings = Vec::with_capacity(n_strings);
    for _ in 0..n_strings {
        let n: usize = p.small()?;
        let text = std::str::from_utf8(p.take(n)?).map_err(|_| Malformed("a string not UTF-8"))?;
        strings.push(text);
    }
    let n_records: usize = p.small()?;
    if n_records > bytes.len() {
        return Err(Malformed("more records than bytes"));
    }
    let cursors = if rows {
        vec![p]
    } else {
        let mut lengths = [0usize; COLUMNS];
        for length in &mut lengths {
            *length = p.small()?;
        }
        let mut cursors = Vec::with_capacity(COLUMNS);
        for length in lengths {
            cursors.push(Payload {
                bytes: p.take(length)?,
                at: 0,
            });
        }
        if !p.is_done() {
            return Err(Malformed("bytes after its last column"));
        }
        cursors
    };
    let mut cursors = Cursors {
        cursors,
        rows,
        next_run: 0,
        next_repeat: 0,
    };
    let mut records: Vec<(u64, RunRecord)> = Vec::with_capacity(n_records.min(FRAME_RUNS));
    for _ in 0..n_records {
        let record = decode_record(&mut cursors, &strings, records.last().map(|(_, r)| r))?;
        records.push(record);
    }
    if !cursors.cursors.iter().all(Payload::is_done) {
        return Err(Malformed("bytes after its last record"));
    }
    Ok(records)
}

/// The next record of `p`, its strings' ids into `strings`; `before` is the payload's
/// previous record.
fn decode_record(
    p: &mut Cursors<'_>,
    strings: &[&str],
    before: Option<&RunRecord>,
) -> Result<(u64, RunRecord), Malformed> {
    let run = p.run()?;
    if p.rows {
        return Ok((run, decode_outcome(p, strings, None)?));
    }
    let status = p.varint(C_STATUS)?;
    let repeat = p.repeat()?;
    let mut record = if status == SAME {
        let before = before.ok_or(Malformed("a first record stored as the previous one"))?;
        RunRecord {
            error: None,
            path: None,
            returns: None,
            marks: Vec::new(),
            series: Vec::new(),
            ..before.clone()
        }
    } else {
        decode_outcome(p, strings, Some(status - 1))?
    };
    record.repeat = repeat;
    record.time_ms = p.time()?;
    record.setup_ms = p.time()?;
    record.peak_heap_bytes = p.varint(C_HEAP)?;
    Ok((run, record))
}

/// A record's fields but its run from `p`: format 3's `status` code read already (its
/// repeat, times and peak heap are then left for the caller), or `None` for a format 2
/// record, read whole in record order.
fn decode_outcome(
    p: &mut Cursors<'_>,
    strings: &[&str],
    status: Option<u64>,
) -> Result<RunRecord, Malformed> {
    let string = |id: u64| string_at(strings, id);
    let map = string(p.varint(C_MAP)?)?.to_string();
    let problem: usize = p.small(C_PROBLEM)?;
    let start = Cell::new(p.small(C_CELLS)?, p.small(C_CELLS)?);
    let goal = Cell::new(p.small(C_CELLS)?, p.small(C_CELLS)?);
    let planner = string(p.varint(C_LABELS)?)?.to_string();
    let algorithm = string(p.varint(C_LABELS)?)?.to_string();
    let (repeat, status) = match status {
        Some(status) => (0, status),
        None => (p.small(C_REPEAT)?, p.varint(C_STATUS)?),
    };
    let status = match status {
        0 => RunStatus::Found,
        1 => RunStatus::NoPath,
        2 => RunStatus::BudgetExhausted,
        3 => RunStatus::InvalidProblem,
        _ => return Err(Malformed("an unknown status")),
    };
    let flags: u16 = p.small(C_STATUS)?;
    let has = |bit: u16| flags & bit != 0;
    let mut number = |bit: u16| -> Result<Option<u64>, Malformed> {
        if has(bit) {
            p.varint(C_INTS).map(Some)
        } else {
            Ok(None)
        }
    };
    let seed = number(SEED)?;
    let steps = number(STEPS)?;
    let turns = number(TURNS)?;
    let score = number(SCORE)?;
    let bucket = number(BUCKET)?
        .map(u32::try_from)
        .transpose()
        .map_err(|_| Malformed("a bucket out of range"))?;
    let mut float = |bit: u16| -> Result<Option<f64>, Malformed> {
        if has(bit) {
            p.at(C_FLOATS).f64().map(Some)
        } else {
            Ok(None)
        }
    };
    let length = float(LENGTH)?;
    let optimal_length = float(OPTIMAL)?;
    let cost = float(COST)?;
    let boolean = |bit: u16, value: u16| has(bit).then(|| has(value));
    let counters = decode_counters(p, strings)?;
    // Format 2 stores the times and peak heap here, before the extras.
    let (time_ms, setup_ms, peak_heap_bytes) = if p.rows {
        (p.time()?, p.time()?, p.varint(C_HEAP)?)
    } else {
        (0.0, 0.0, 0)
    };
    let extras = if has(EXTRAS) {
        let n: usize = p.small(C_EXTRAS)?;
        serde_json::from_slice(p.at(C_EXTRAS).take(n)?)
            .map_err(|_| Malformed("its extras not JSON"))?
    } else {
        Extras::default()
    };
    Ok(RunRecord {
        map,
        problem,
        start,
        goal,
        planner,
        algorithm,
        repeat,
        seed,
        status,
        error: extras.error,
        steps,
        turns,
        score,
        length,
        optimal_length,
        bucket,
        valid: boolean(VALID, VALID_TRUE),
        admissible: boolean(ADMISSIBLE, ADMISSIBLE_TRUE),
        counters,
        time_ms,
        setup_ms,
        peak_heap_bytes,
        path: extras.path,
        returns: extras.returns,
        marks: extras.marks,
        series: extras.series,
        cost,
    })
}

/// String `id` of a batch's string table.
fn string_at<'s>(strings: &[&'s str], id: u64) -> Result<&'s str, Malformed> {
    usize::try_from(id)
        .ok()
        .and_then(|i| strings.get(i))
        .copied()
        .ok_or(Malformed("a string id past the table"))
}

/// A record's counters: a count, then (name id, value) pairs. The standard names are
/// static strings, as the planner reported them, not one allocation per record.
fn decode_counters(p: &mut Cursors<'_>, strings: &[&str]) -> Result<Counters, Malformed> {
    let n_counters: usize = p.small(C_COUNTER_NAMES)?;
    if n_counters > p.at(C_COUNTER_NAMES).bytes.len() {
        return Err(Malformed("more counters than bytes"));
    }
    let mut counters = Counters::new();
    for _ in 0..n_counters {
        let name = string_at(strings, p.varint(C_COUNTER_NAMES)?)?;
        let value = p.varint(C_COUNTER_VALUES)?;
        match planner_api::Counter::ALL.iter().find(|c| c.name() == name) {
            Some(standard) => counters.push(standard.name(), value),
            None => counters.push(name.to_string(), value),
        }
    }
    Ok(counters)
}

/// Reads the frames of a framed stream after its header line.
pub struct FrameReader {
    records: VecDeque<(u64, RunRecord)>,
    payload: Vec<u8>,
    /// The decompressed payload (format 3).
    plain: Vec<u8>,
    /// Format 2: uncompressed frames of records in row order.
    rows: bool,
    /// Frames read so far.
    frames: u64,
    /// Bytes of complete frames read so far (the header's not counted).
    complete_bytes: u64,
    /// Bytes of a cut last frame (0 when none).
    cut_bytes: u64,
}

impl FrameReader {
    /// A reader at the first frame of a stream of [`FRAMED_FORMAT`].
    pub fn new() -> FrameReader {
        FrameReader {
            records: VecDeque::new(),
            payload: Vec::new(),
            plain: Vec::new(),
            rows: false,
            frames: 0,
            complete_bytes: 0,
            cut_bytes: 0,
        }
    }

    /// A reader at the first frame of a stream whose header states `format`:
    /// [`FRAMED_FORMAT`] or [`ROW_FRAMED_FORMAT`] (`None`: neither).
    pub fn for_format(format: u32) -> Option<FrameReader> {
        match format {
            FRAMED_FORMAT => Some(FrameReader::new()),
            ROW_FRAMED_FORMAT => Some(FrameReader {
                rows: true,
                ..FrameReader::new()
            }),
            _ => None,
        }
    }

    /// The next run and its record from `reader` (`what` names the stream in errors), or
    /// `None` at the end or at a cut last frame.
    pub fn next_run<R: BufRead>(
        &mut self,
        reader: &mut R,
        what: &str,
    ) -> Result<Option<(u64, RunRecord)>, RunnerError> {
        while self.records.is_empty() {
            if !self.next_frame(reader, what)? {
                return Ok(None);
            }
        }
        Ok(self.records.pop_front())
    }

    /// Reads and decodes the next frame; `false` at the end or at a cut last frame.
    fn next_frame<R: BufRead>(&mut self, reader: &mut R, what: &str) -> Result<bool, RunnerError> {
        if self.cut_bytes > 0 {
            return Ok(false);
        }
        let io = |e: std::io::Error| StreamError::new(what, Place::File, StreamProblem::Io(e));
        let mut head = [0u8; 8];
        let got = read_up_to(reader, &mut head).map_err(io)?;
        if got == 0 {
            return Ok(false);
        }
        if got < head.len() {
            self.cut_bytes = got as u64;
            return Ok(false);
        }
        let frame = self.frames + 1;
        let length = u32::from_le_bytes([head[0], head[1], head[2], head[3]]);
        let crc = u32::from_le_bytes([head[4], head[5], head[6], head[7]]);
        if length > MAX_FRAME_BYTES {
            let problem = StreamProblem::FrameTooLarge(length);
            return Err(StreamError::new(what, Place::Frame(frame), problem).into());
        }
        self.payload.clear();
        let n = (&mut *reader)
            .take(u64::from(length))
            .read_to_end(&mut self.payload)
            .map_err(io)?;
        if n < length as usize {
            self.cut_bytes = 8 + n as u64;
            return Ok(false);
        }
        if crc32fast::hash(&self.payload) != crc {
            let at_end = reader.fill_buf().map_err(io)?.is_empty();
            if at_end {
                // A last frame written only in part (the file grew before its bytes
                // landed): cut, like a short one.
                self.cut_bytes = 8 + u64::from(length);
                return Ok(false);
            }
            let problem = StreamProblem::Checksum(self.complete_bytes);
            return Err(StreamError::new(what, Place::Frame(frame), problem).into());
        }
        let malformed = |Malformed(why)| {
            StreamError::new(what, Place::Frame(frame), StreamProblem::Malformed(why))
        };
        let records = if self.rows {
            decode_payload(&self.payload, true).map_err(malformed)?
        } else {
            self.decompress().map_err(malformed)?;
            decode_payload(&self.plain, false).map_err(malformed)?
        };
        self.frames = frame;
        self.complete_bytes += 8 + u64::from(length);
        self.records.extend(records);
        Ok(true)
    }

    /// Decompresses the frame's payload into `plain`, refusing one that would be longer
    /// than [`MAX_FRAME_BYTES`] before allocating it.
    fn decompress(&mut self) -> Result<(), Malformed> {
        let n = snap::raw::decompress_len(&self.payload)
            .map_err(|_| Malformed("not a compressed payload"))?;
        if n > MAX_FRAME_BYTES as usize {
            return Err(Malformed("decompresses to more than a frame holds"));
        }
        // A Snappy element writes at most 64 bytes for 3 (a copy with a 2-byte offset): a
        // stated length beyond that ratio is refused before it is allocated.
        if n > self.payload.len().saturating_mul(22).saturating_add(64) {
            return Err(Malformed("states more bytes than it can decompress to"));
        }
        self.plain.clear();
        self.plain.resize(n, 0);
        let got = snap::raw::Decoder::new()
            .decompress(&self.payload, &mut self.plain)
            .map_err(|_| Malformed("not a compressed payload"))?;
        self.plain.truncate(got);
        Ok(())
    }

    /// Bytes of the complete frames read so far (the header line's not counted).
    pub fn complete_bytes(&self) -> u64 {
        self.complete_bytes
    }

    /// Bytes of the cut last frame that reading stopped at (0: none).
    pub fn cut_bytes(&self) -> u64 {
        self.cut_bytes
    }
}

impl Default for FrameReader {
    fn default() -> FrameReader {
        FrameReader::new()
    }
}

/// Reads into `buf` until it is full or the reader ends; returns the bytes read.
fn read_up_to<R: BufRead>(reader: &mut R, buf: &mut [u8]) -> std::io::Result<usize> {
    let mut got = 0;
    while got < buf.len() {
        match reader.read(&mut buf[got..]) {
            Ok(0) => break,
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// The most runs in a frame: a sweep appends the runs [`crate::stream::run_stream`] hands
/// it as frames of at most this many (it hands them once this many are in order, or
/// sooner), and [`encode_frames`] encodes each frame of a longer batch on its own worker.
pub const FRAME_RUNS: usize = 1024;

/// `batch` as frames of at most [`FRAME_RUNS`] runs, encoded in parallel (on the calling
/// rayon pool).
pub fn encode_frames(batch: &[(u64, RunRecord)]) -> Result<Vec<u8>, RunnerError> {
    use rayon::prelude::*;
    let frames: Vec<Vec<u8>> = batch
        .par_chunks(FRAME_RUNS)
        .map(|chunk| {
            let mut frame = Vec::with_capacity(chunk.len() * 96 + 256);
            encode_batch(&mut frame, chunk).map(|()| frame)
        })
        .collect::<Result<_, _>>()?;
    Ok(frames.concat())
}

/// Writes the stream read from `reader` (`what` names it) to `out` (the file at
/// `out_path`, which a write error names) as a JSON Lines stream (format 1, as the
/// `shard.jsonl` and `records.jsonl` of earlier versions), one record at a time; with
/// `limit`, only its first `limit` runs. Returns the runs written.
pub fn write_json_lines<R: BufRead>(
    reader: R,
    what: &str,
    (out, out_path): (&mut dyn std::io::Write, &std::path::Path),
    limit: Option<u64>,
) -> Result<u64, RunnerError> {
    let (header, mut reader) = crate::stream::StreamReader::new(reader, what)?;
    let header = crate::stream::StreamHeader {
        format: crate::stream::STREAM_FORMAT,
        ..header
    };
    let io = |e: std::io::Error| RunnerError::io(out_path, e);
    out.write_all(&header.to_line()?).map_err(io)?;
    let mut line = Vec::with_capacity(512);
    let mut n = 0;
    while limit.is_none_or(|limit| n < limit) {
        let Some((run, record)) = reader.next_run()? else {
            break;
        };
        line.clear();
        crate::stream::encode(&mut line, run, &record)?;
        out.write_all(&line).map_err(io)?;
        n += 1;
    }
    Ok(n)
}

/// Writes the first `limit` runs of the stream read from `reader` (`what` names it; a JSON
/// Lines stream of an earlier version) to `out` (the file at `out_path`, which a write
/// error names) as a framed stream, `header`'s format set to [`FRAMED_FORMAT`],
/// [`FRAME_RUNS`] runs a frame. Returns the bytes written.
pub fn write_framed<R: BufRead>(
    reader: R,
    what: &str,
    (out, out_path): (&mut dyn std::io::Write, &std::path::Path),
    limit: u64,
) -> Result<u64, RunnerError> {
    let (header, mut reader) = crate::stream::StreamReader::new(reader, what)?;
    let header = crate::stream::StreamHeader {
        format: FRAMED_FORMAT,
        ..header
    };
    let io = |e: std::io::Error| RunnerError::io(out_path, e);
    let line = header.to_line()?;
    out.write_all(&line).map_err(io)?;
    let mut bytes = line.len() as u64;
    let mut batch = Vec::with_capacity(FRAME_RUNS);
    let mut frame = Vec::new();
    let mut n = 0;
    loop {
        let next = if n < limit { reader.next_run()? } else { None };
        let end = next.is_none();
        if let Some(run) = next {
            batch.push(run);
            n += 1;
        }
        if batch.len() == FRAME_RUNS || (end && !batch.is_empty()) {
            frame.clear();
            encode_batch(&mut frame, &batch)?;
            out.write_all(&frame).map_err(io)?;
            bytes += frame.len() as u64;
            batch.clear();
        }
        if end {
            return Ok(bytes);
        }
    }
}
