//! The compact record stream (issue 29): the resume stream a sweep appends to, as binary
//! batches with a checksum instead of JSON Lines (about a fifth of the bytes).
//!
//! A framed stream file starts with the same [`StreamHeader`](crate::stream::StreamHeader) JSON line as a JSON Lines
//! stream, with `"format": 2` ([`FRAMED_FORMAT`]), then one frame per batch:
//!
//! - 4 bytes: the payload's length `n`, little-endian (at most [`MAX_FRAME_BYTES`]);
//! - 4 bytes: the payload's CRC-32 (ISO-HDLC, as zlib's), little-endian;
//! - `n` bytes: the payload: the batch's string table (map names, labels, registry names,
//!   counter names: a count, then each as a length and UTF-8 bytes), then its records
//!   (a count, then each record: `put_record`).
//!
//! Integers are LEB128 varints, floats their 8 IEEE bytes (exact, as JSON's shortest
//! form is). A record's rarely present parts (error text, path, return legs, marks,
//! series) go as one JSON object after it when present. A frame is appended whole and
//! flushed, so a process killed mid-write leaves complete frames and at most one cut frame
//! at the end: [`FrameReader`] stops at a short frame, or at a last frame whose checksum
//! fails, and reports it (`FrameReader::was_cut`); a bad checksum with frames after it
//! is an error, never dropped silently. A frame longer than [`MAX_FRAME_BYTES`] is refused
//! before anything is allocated for it.

use std::collections::VecDeque;
use std::io::{BufRead, Read};

use planner_api::{Cell, Counters, Mark, Path, ReturnLeg, Series};
use serde::{Deserialize, Serialize};

use crate::record::{RunRecord, RunStatus};
use crate::RunnerError;

/// The stream header's `format` of a framed stream (a JSON Lines stream's is 1).
pub const FRAMED_FORMAT: u32 = 2;

/// The longest frame payload a reader accepts: 256 MiB (as a JSON Lines stream's line).
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

fn status_code(status: RunStatus) -> u8 {
    match status {
        RunStatus::Found => 0,
        RunStatus::NoPath => 1,
        RunStatus::BudgetExhausted => 2,
        RunStatus::InvalidProblem => 3,
    }
}

/// Appends run `run`'s `record` to `out`, its strings' ids from `strings`.
fn put_record<'a>(
    out: &mut Vec<u8>,
    strings: &mut Strings<'a>,
    run: u64,
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
    put_varint(out, run);
    for id in [
        strings.id(&r.map),
        r.problem as u64,
        u64::from(r.start.x),
        u64::from(r.start.y),
        u64::from(r.goal.x),
        u64::from(r.goal.y),
        strings.id(&r.planner),
        strings.id(&r.algorithm),
        u64::from(r.repeat),
        u64::from(status_code(r.status)),
        u64::from(flags),
    ] {
        put_varint(out, id);
    }
    for value in [r.seed, r.steps, r.turns, r.score, r.bucket.map(u64::from)]
        .into_iter()
        .flatten()
    {
        put_varint(out, value);
    }
    for value in [r.length, r.optimal_length, r.cost].into_iter().flatten() {
        put_f64(out, value);
    }
    put_varint(out, r.counters.len() as u64);
    for (name, value) in r.counters.iter() {
        put_varint(out, strings.id(name));
        put_varint(out, value);
    }
    put_f64(out, r.time_ms);
    put_f64(out, r.setup_ms);
    put_varint(out, r.peak_heap_bytes);
    if extras {
        let json = serde_json::to_vec(&Extras {
            error: r.error.clone(),
            path: r.path.clone(),
            returns: r.returns.clone(),
            marks: r.marks.clone(),
            series: r.series.clone(),
        })
        .map_err(RunnerError::Json)?;
        put_varint(out, json.len() as u64);
        out.extend_from_slice(&json);
    }
    Ok(())
}

/// Appends `batch` (runs and their records) to `out` as one frame.
pub fn encode_batch(out: &mut Vec<u8>, batch: &[(u64, RunRecord)]) -> Result<(), RunnerError> {
    let mut strings = Strings::default();
    let mut records = Vec::with_capacity(batch.len() * 96);
    put_varint(&mut records, batch.len() as u64);
    for (run, record) in batch {
        put_record(&mut records, &mut strings, *run, record)?;
    }
    let mut payload = Vec::with_capacity(records.len() + 256);
    put_varint(&mut payload, strings.list.len() as u64);
    for text in &strings.list {
        put_varint(&mut payload, text.len() as u64);
        payload.extend_from_slice(text.as_bytes());
    }
    payload.extend_from_slice(&records);
    let length = u32::try_from(payload.len())
        .ok()
        .filter(|n| *n <= MAX_FRAME_BYTES)
        .ok_or_else(|| {
            RunnerError::Stream(format!(
                "a batch of {} runs takes {} bytes, more than a frame holds ({MAX_FRAME_BYTES})",
                batch.len(),
                payload.len()
            ))
        })?;
    out.extend_from_slice(&length.to_le_bytes());
    out.extend_from_slice(&crc32fast::hash(&payload).to_le_bytes());
    out.extend_from_slice(&payload);
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
}

/// The runs and records of one frame's `payload`.
fn decode_payload(bytes: &[u8]) -> Result<Vec<(u64, RunRecord)>, Malformed> {
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
    let mut records = Vec::with_capacity(n_records);
    for _ in 0..n_records {
        records.push(decode_record(&mut p, &strings)?);
    }
    if p.at != bytes.len() {
        return Err(Malformed("bytes after its last record"));
    }
    Ok(records)
}

/// The next record of `p`, its strings' ids into `strings`.
fn decode_record(p: &mut Payload<'_>, strings: &[&str]) -> Result<(u64, RunRecord), Malformed> {
    let string = |id: u64| string_at(strings, id);
    {
        let run = p.varint()?;
        let map = string(p.varint()?)?.to_string();
        let problem: usize = p.small()?;
        let start = Cell::new(p.small()?, p.small()?);
        let goal = Cell::new(p.small()?, p.small()?);
        let planner = string(p.varint()?)?.to_string();
        let algorithm = string(p.varint()?)?.to_string();
        let repeat: u32 = p.small()?;
        let status = match p.varint()? {
            0 => RunStatus::Found,
            1 => RunStatus::NoPath,
            2 => RunStatus::BudgetExhausted,
            3 => RunStatus::InvalidProblem,
            _ => return Err(Malformed("an unknown status")),
        };
        let flags: u16 = p.small()?;
        let has = |bit: u16| flags & bit != 0;
        let mut number = |bit: u16| -> Result<Option<u64>, Malformed> {
            if has(bit) {
                p.varint().map(Some)
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
                p.f64().map(Some)
            } else {
                Ok(None)
            }
        };
        let length = float(LENGTH)?;
        let optimal_length = float(OPTIMAL)?;
        let cost = float(COST)?;
        let boolean = |bit: u16, value: u16| has(bit).then(|| has(value));
        let counters = decode_counters(p, strings)?;
        let time_ms = p.f64()?;
        let setup_ms = p.f64()?;
        let peak_heap_bytes = p.varint()?;
        let extras = if has(EXTRAS) {
            let n: usize = p.small()?;
            serde_json::from_slice(p.take(n)?).map_err(|_| Malformed("its extras not JSON"))?
        } else {
            Extras::default()
        };
        Ok((
            run,
            RunRecord {
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
            },
        ))
    }
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
fn decode_counters(p: &mut Payload<'_>, strings: &[&str]) -> Result<Counters, Malformed> {
    let n_counters: usize = p.small()?;
    if n_counters > p.bytes.len() {
        return Err(Malformed("more counters than bytes"));
    }
    let mut counters = Counters::new();
    for _ in 0..n_counters {
        let name = string_at(strings, p.varint()?)?;
        let value = p.varint()?;
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
    /// Frames read so far.
    frames: u64,
    /// Bytes of complete frames read so far (the header's not counted).
    complete_bytes: u64,
    /// Bytes of a cut last frame (0 when none).
    cut_bytes: u64,
}

impl FrameReader {
    /// A reader at the first frame.
    pub fn new() -> FrameReader {
        FrameReader {
            records: VecDeque::new(),
            payload: Vec::new(),
            frames: 0,
            complete_bytes: 0,
            cut_bytes: 0,
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
        let io = |e: std::io::Error| RunnerError::Stream(format!("{what}: {e}"));
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
            return Err(RunnerError::Stream(format!(
                "{what}: frame {frame} declares {length} bytes, more than {MAX_FRAME_BYTES}; not a gridplan stream"
            )));
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
            return Err(RunnerError::Stream(format!(
                "{what}: frame {frame} (at byte {} after the header) fails its checksum and frames follow it; the stream is damaged",
                self.complete_bytes
            )));
        }
        let records = decode_payload(&self.payload).map_err(|Malformed(why)| {
            RunnerError::Stream(format!("{what}: frame {frame}: {why}"))
        })?;
        self.frames = frame;
        self.complete_bytes += 8 + u64::from(length);
        self.records.extend(records);
        Ok(true)
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

/// Runs per frame when a sweep writes a batch (each frame is encoded on its own worker).
pub const FRAME_RUNS: usize = 256;

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

/// Writes the stream read from `reader` (`what` names it) to `out` as a JSON Lines stream
/// (format 1, as the `shard.jsonl` and `records.jsonl` of earlier versions), one record at a time; with `limit`, only its
/// first `limit` runs. Returns the runs written.
pub fn write_json_lines<R: BufRead>(
    reader: R,
    what: &str,
    out: &mut dyn std::io::Write,
    limit: Option<u64>,
) -> Result<u64, RunnerError> {
    let (header, mut reader) = crate::stream::StreamReader::new(reader, what)?;
    let header = crate::stream::StreamHeader {
        format: crate::stream::STREAM_FORMAT,
        ..header
    };
    let io = |e: std::io::Error| RunnerError::Stream(format!("{what}: {e}"));
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
/// Lines stream of an earlier version) to `out` as a framed stream, `header`'s format set
/// to [`FRAMED_FORMAT`], [`FRAME_RUNS`] runs a frame. Returns the bytes written.
pub fn write_framed<R: BufRead>(
    reader: R,
    what: &str,
    out: &mut dyn std::io::Write,
    limit: u64,
) -> Result<u64, RunnerError> {
    let (header, mut reader) = crate::stream::StreamReader::new(reader, what)?;
    let header = crate::stream::StreamHeader {
        format: FRAMED_FORMAT,
        ..header
    };
    let io = |e: std::io::Error| RunnerError::Stream(format!("{what}: {e}"));
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
