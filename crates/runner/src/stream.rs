//! Streamed sweeps: records handed out in run order, batch by batch, as JSON Lines.
//!
//! [`run_stream`] runs any increasing sequence of run indices (the whole run list, a
//! [`crate::shard::ShardRuns`] slice, or what a resumed sweep has left) in batches on a
//! rayon pool, each worker reusing its planners across batches, and hands each finished
//! batch to a sink in run order, so memory is bounded by the batch (a few records per
//! worker), not by the sweep. Paths the config does not keep
//! ([`crate::config::PathsMode`]) are dropped in the worker.
//!
//! A sweep's own resume stream is framed binary ([`crate::frames`], format 3, and the
//! previous version's format 2, read here too); the JSON Lines format (1) is that of
//! shard and results files, and of resume streams written before, which still read.
//! The JSON Lines format is one line per run, `{"run":INDEX,"record":RECORD}` ([`encode`]),
//! the [`RunRecord`] as serde writes it. A binary appends each batch to a file and flushes
//! it; a process killed mid-write leaves complete lines and at most one cut line at the
//! end, which [`StreamReader`] stops at (and reports, so a resumed sweep truncates it).
//! A stream file starts with a [`StreamHeader`] line naming the experiment, the shard and
//! the [`config_hash`] of the resolved config, so a resumed or merged stream from another
//! config is recognised, and the gridplan version that wrote it. [`check_record`] checks
//! each record read back against the config's run list (map, problem, label, repeat).
//!
//! The runner writes no file: the sink and the reader work on bytes and `std::io` traits.
//! [`open_regular`] opens a stream file for reading, refusing anything but a regular file
//! (a link to `/dev/zero`, a FIFO nobody writes), and [`StreamReader`] refuses a line
//! longer than [`MAX_LINE_BYTES`], so a reader's memory is bounded whatever the file holds.

use std::io::{BufRead, Read as _};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use planner_api::{Counter, Counters};

use crate::config::Experiment;
use crate::record::RunRecord;
use crate::run::{run_one, RunList, RunOptions, Workspace};
use crate::shard::Shard;
use crate::RunnerError;

/// A record stream (`records.stream`, `shard.stream`) or `expanded.jsonl` that cannot be
/// read, or whose records do not fit: the file, where in it, and what.
///
/// ```
/// use planner_runner::stream::{Place, StreamError, StreamProblem};
///
/// let error = StreamError::new("out/records.stream", Place::Line(7), StreamProblem::LineTooLong);
/// assert!(error.to_string().starts_with("out/records.stream line 7: longer than"));
/// ```
#[derive(Debug, thiserror::Error)]
#[error("{file}{place}: {problem}")]
pub struct StreamError {
    /// The file, as the reader was told to name it.
    pub file: String,
    /// Where in the file.
    pub place: Place,
    /// What is wrong there.
    pub problem: StreamProblem,
}

impl StreamError {
    /// The error `problem` at `place` of `file`.
    pub fn new(file: &str, place: Place, problem: StreamProblem) -> StreamError {
        StreamError {
            file: file.to_string(),
            place,
            problem,
        }
    }
}

/// Where in a stream a [`StreamError`] lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Place {
    /// The file as a whole.
    File,
    /// A 1-based line of a JSON Lines file (the header is line 1).
    Line(u64),
    /// A 1-based frame of a framed stream (after its header line).
    Frame(u64),
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Place::File => Ok(()),
            Place::Line(n) => write!(f, " line {n}"),
            Place::Frame(n) => write!(f, ": frame {n}"),
        }
    }
}

/// What is wrong with a stream ([`StreamError`]).
#[derive(Debug, thiserror::Error)]
pub enum StreamProblem {
    /// Reading the stream failed.
    #[error("{0}")]
    Io(std::io::Error),
    /// The first line is not a stream header.
    #[error("not a gridplan stream header: {0}")]
    NotAHeader(serde_json::Error),
    /// The file ends before its header line does.
    #[error("empty or cut before its header")]
    NoHeader,
    /// A header of a stream format this gridplan does not read.
    #[error(
        "stream format {0} (this gridplan reads {STREAM_FORMAT}, JSON Lines, and {rows} and {columns}, framed)",
        rows = crate::frames::ROW_FRAMED_FORMAT,
        columns = crate::frames::FRAMED_FORMAT
    )]
    Format(u32),
    /// The header's shard is not one a command accepts.
    #[error(transparent)]
    Shard(crate::shard::ShardError),
    /// A line longer than [`MAX_LINE_BYTES`].
    #[error("longer than {MAX_LINE_BYTES} bytes; not a gridplan stream")]
    LineTooLong,
    /// A line that is not the JSON it should be.
    #[error("{0}")]
    Json(serde_json::Error),
    /// A frame stating more bytes than [`crate::frames::MAX_FRAME_BYTES`].
    #[error("declares {0} bytes, more than {max}; not a gridplan stream", max = crate::frames::MAX_FRAME_BYTES)]
    FrameTooLarge(u32),
    /// A frame whose checksum fails with frames after it.
    #[error("at byte {0} after the header, fails its checksum and frames follow it; the stream is damaged")]
    Checksum(u64),
    /// A frame whose checksum holds but whose payload does not decode.
    #[error("{0}")]
    Malformed(&'static str),
    /// A complete-looking stream with fewer runs than its header declares.
    #[error("{recorded} of {declared} runs recorded")]
    Incomplete {
        /// Runs read.
        recorded: u64,
        /// Runs the header declares.
        declared: u64,
    },
    /// A second pass over the file read another number of runs than the first.
    #[error(
        "a pass over its records read {read} of {runs} (the file changed while the report read it)"
    )]
    Changed {
        /// Runs this pass read.
        read: u64,
        /// Runs the first pass read.
        runs: u64,
    },
}

/// The stream format's version.
pub const STREAM_FORMAT: u32 = 1;

/// Runs per worker in one batch.
const BATCH_PER_WORKER: usize = 512;

/// The longest line [`StreamReader`] reads: 256 MiB (a record keeps its path, about 14
/// bytes a cell, so this is a path of some 19 million cells). A longer line is an error,
/// not an allocation as large as the file.
pub const MAX_LINE_BYTES: u64 = 256 << 20;

/// Opens the stream file `path` for reading: only a regular file (after following
/// symbolic links), checked before it is opened, so that a FIFO cannot block the open and
/// a device cannot stream forever, and again on the open file. Anything else is an error
/// of kind [`std::io::ErrorKind::InvalidInput`] saying what the path is.
pub fn open_regular(path: &std::path::Path) -> std::io::Result<std::fs::File> {
    let check = |metadata: std::fs::Metadata| {
        if metadata.is_file() {
            Ok(())
        } else {
            Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                format!(
                    "not a regular file ({}): gridplan reads streams from regular files only",
                    planner_maps::file_kind(&metadata.file_type())
                ),
            ))
        }
    };
    check(std::fs::metadata(path)?)?;
    let file = std::fs::File::open(path)?;
    check(file.metadata()?)?;
    Ok(file)
}

/// The first line of a stream file.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StreamHeader {
    /// [`STREAM_FORMAT`].
    pub format: u32,
    /// The experiment's name.
    pub experiment: String,
    /// The config file as given to the command.
    pub config: String,
    /// [`config_hash`] of the resolved config.
    pub config_hash: String,
    /// 1-based shard number.
    pub shard: u64,
    /// Number of shards.
    pub shards: u64,
    /// Runs in this shard.
    pub runs: u64,
    /// Runs in the whole sweep.
    pub total_runs: u64,
    /// The gridplan version that wrote the stream (absent in streams written before the
    /// field existed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gridplan: Option<String>,
}

impl StreamHeader {
    /// The header of `shard` of `experiment`, which holds `runs` runs.
    pub fn new(experiment: &Experiment, shard: Shard, runs: u64) -> StreamHeader {
        StreamHeader {
            format: STREAM_FORMAT,
            experiment: experiment.name.clone(),
            config: experiment.source.display().to_string(),
            config_hash: config_hash(experiment),
            shard: shard.index,
            shards: shard.count,
            runs,
            total_runs: RunList::new(experiment).len(),
            gridplan: Some(env!("CARGO_PKG_VERSION").to_string()),
        }
    }

    /// The header as one JSON line.
    pub fn to_line(&self) -> Result<Vec<u8>, RunnerError> {
        let mut line = serde_json::to_vec(self).map_err(RunnerError::Json)?;
        line.push(b'\n');
        Ok(line)
    }
}

/// A 64-bit FNV-1a hash (hex) of everything that decides an experiment's records and
/// outputs: name, repeats, seed, budget-bearing planner settings (label, registry name,
/// parameters, budget, compare), figures, paths and sections, and every map's name, size,
/// free cells and problems (start, goal, stated optimum, invalidity). Worker threads,
/// the output directory and the config's own path are left out: they change no record.
pub fn config_hash(experiment: &Experiment) -> String {
    let mut h = Fnv::default();
    h.text(&experiment.name);
    h.text(&experiment.repeats.to_string());
    h.text(&experiment.seed.to_string());
    h.text(&format!(
        "{:?} {:?} {:?} {:?}",
        experiment.figures,
        experiment.figures_per_map,
        experiment.paths,
        experiment.sections.as_ref().map(|s| &s.requests)
    ));
    for planner in &experiment.planners {
        h.text(&planner.label);
        h.text(planner.name);
        h.text(&planner.params.to_string());
        h.text(&format!("{:?} {:?}", planner.budget, planner.compare));
    }
    for map in &experiment.maps {
        h.text(&map.name);
        h.text(&format!("{}x{}", map.grid.width(), map.grid.height()));
        h.bytes(
            &map.grid
                .free_cells()
                .iter()
                .map(|&f| u8::from(f))
                .collect::<Vec<u8>>(),
        );
        for p in &map.problems {
            h.text(&format!(
                "{} {} {} {:?} {:?}",
                p.index, p.start, p.goal, p.optimal_length, p.invalid
            ));
        }
    }
    format!("{:016x}", h.0)
}

struct Fnv(u64);

impl Default for Fnv {
    fn default() -> Fnv {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv {
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
        // A separator, so ("ab", "c") and ("a", "bc") differ.
        self.0 ^= 0xff;
        self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
    }

    fn text(&mut self, text: &str) {
        self.bytes(text.as_bytes());
    }
}

/// Appends run `run`'s line, `{"run":INDEX,"record":RECORD}` and a newline, to `out`.
pub fn encode(out: &mut Vec<u8>, run: u64, record: &RunRecord) -> Result<(), RunnerError> {
    out.extend_from_slice(b"{\"run\":");
    out.extend_from_slice(run.to_string().as_bytes());
    out.extend_from_slice(b",\"record\":");
    serde_json::to_writer(&mut *out, record).map_err(RunnerError::Json)?;
    out.extend_from_slice(b"}\n");
    Ok(())
}

#[derive(Deserialize)]
struct Line {
    run: u64,
    record: RunRecord,
}

/// Gives a record read back the standard counter names as static strings (as the
/// planner reported them), not one allocation per name and record: a sweep's records
/// read back are held for its summary, and the names are most of their heap.
fn intern_counter_names(counters: &mut Counters) {
    let standard = |name: &str| {
        Counter::ALL
            .iter()
            .map(|c| c.name())
            .find(|standard| *standard == name)
    };
    if counters.iter().all(|(name, _)| standard(name).is_none()) {
        return;
    }
    let mut interned = Counters::new();
    for (name, value) in counters.iter() {
        match standard(name) {
            Some(name) => interned.push(name, value),
            None => interned.push(name.to_string(), value),
        }
    }
    *counters = interned;
}

/// Reads a stream file: its header, then its runs in order, stopping at a cut last line.
pub struct StreamReader<R> {
    reader: R,
    buffer: Vec<u8>,
    line: u64,
    /// Bytes of complete lines read so far (header included).
    complete_bytes: u64,
    /// Whether the stream ended in a cut line (a process killed mid-write).
    cut: bool,
    what: String,
    /// A framed stream's frames ([`crate::frames`]; `None`: JSON Lines).
    frames: Option<crate::frames::FrameReader>,
}

impl<R: BufRead> StreamReader<R> {
    /// Opens a stream read from `reader` (`what` names it in errors, e.g. the file) and
    /// reads its header.
    pub fn new(reader: R, what: &str) -> Result<(StreamHeader, StreamReader<R>), RunnerError> {
        let mut stream = StreamReader {
            reader,
            buffer: Vec::new(),
            line: 0,
            complete_bytes: 0,
            cut: false,
            what: what.to_string(),
            frames: None,
        };
        let header = match stream.next_line()? {
            Some(line) => serde_json::from_slice::<StreamHeader>(line).map_err(|e| {
                StreamError::new(what, Place::Line(1), StreamProblem::NotAHeader(e))
            })?,
            None => return Err(StreamError::new(what, Place::File, StreamProblem::NoHeader).into()),
        };
        stream.frames = crate::frames::FrameReader::for_format(header.format);
        if stream.frames.is_none() && header.format != STREAM_FORMAT {
            let problem = StreamProblem::Format(header.format);
            return Err(StreamError::new(what, Place::File, problem).into());
        }
        // A shard count no command accepts (a merge would loop over it) is refused here.
        Shard::new(header.shard, header.shards)
            .map_err(|e| StreamError::new(what, Place::Line(1), StreamProblem::Shard(e)))?;
        Ok((header, stream))
    }

    fn next_line(&mut self) -> Result<Option<&[u8]>, RunnerError> {
        self.buffer.clear();
        let n = (&mut self.reader)
            .take(MAX_LINE_BYTES)
            .read_until(b'\n', &mut self.buffer)
            .map_err(|e| StreamError::new(&self.what, Place::File, StreamProblem::Io(e)))?;
        if n == 0 {
            return Ok(None);
        }
        if n as u64 == MAX_LINE_BYTES && self.buffer.last() != Some(&b'\n') {
            let place = Place::Line(self.line + 1);
            return Err(StreamError::new(&self.what, place, StreamProblem::LineTooLong).into());
        }
        if self.buffer.last() != Some(&b'\n') {
            self.cut = true;
            return Ok(None);
        }
        self.line += 1;
        self.complete_bytes += n as u64;
        Ok(Some(&self.buffer))
    }

    /// The next run and its record, or `None` at the end (or at a cut last line).
    pub fn next_run(&mut self) -> Result<Option<(u64, RunRecord)>, RunnerError> {
        if let Some(frames) = &mut self.frames {
            return frames.next_run(&mut self.reader, &self.what);
        }
        if self.next_line()?.is_none() {
            return Ok(None);
        }
        let mut parsed: Line = serde_json::from_slice(&self.buffer).map_err(|e| {
            StreamError::new(&self.what, Place::Line(self.line), StreamProblem::Json(e))
        })?;
        intern_counter_names(&mut parsed.record.counters);
        Ok(Some((parsed.run, parsed.record)))
    }

    /// Bytes of the complete lines (or frames) read so far: where a resumed sweep appends.
    pub fn complete_bytes(&self) -> u64 {
        self.complete_bytes + self.frames.as_ref().map_or(0, |f| f.complete_bytes())
    }

    /// Whether the stream ended in a cut line (or frame).
    pub fn was_cut(&self) -> bool {
        self.cut || self.cut_bytes() > 0
    }

    /// Bytes of the cut last frame of a framed stream that reading stopped at (0: none, or
    /// a JSON Lines stream).
    pub fn cut_bytes(&self) -> u64 {
        self.frames.as_ref().map_or(0, |f| f.cut_bytes())
    }

    /// Whether the stream is framed ([`crate::frames`]).
    pub fn is_framed(&self) -> bool {
        self.frames.is_some()
    }
}

/// Runs the runs `runs` (increasing indices into `experiment`'s [`RunList`]) and calls
/// `sink` with each finished batch of (index, record), in order (the sink owns them, to
/// write or keep; it runs in the sweep's thread pool, so rayon's parallel iterators in it
/// use the sweep's workers), and returns how many
/// ran. The records of one sweep do not depend on the thread count or the batch size.
/// Progress counts runs done in this call. Once [`RunOptions::stop`] is set, no new run
/// starts: the last batch handed to `sink` holds the runs finished before the first one
/// skipped, and the count is short of the runs asked for.
pub fn run_stream(
    experiment: &Experiment,
    runs: impl Iterator<Item = u64>,
    options: &RunOptions<'_>,
    mut sink: impl FnMut(Vec<(u64, RunRecord)>) -> Result<(), RunnerError> + Send,
) -> Result<u64, RunnerError> {
    let list = RunList::new(experiment);
    let threads = match options.threads {
        0 => experiment.threads,
        n => n,
    };
    if threads > crate::config::MAX_THREADS {
        return Err(RunnerError::Threads(threads));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(RunnerError::Pool)?;
    let workers = pool.current_num_threads();
    let workspaces: Vec<Mutex<Workspace>> = (0..workers)
        .map(|_| Mutex::new(Workspace::default()))
        .collect();
    let batch_size = workers * BATCH_PER_WORKER;
    let done = AtomicU64::new(0);
    // The workers log inside the caller's span (as `run_all`'s).
    let span = tracing::Span::current();
    let mut runs = runs.peekable();
    let mut batch: Vec<u64> = Vec::with_capacity(batch_size);
    let mut n_done = 0u64;
    while runs.peek().is_some() {
        batch.clear();
        batch.extend(runs.by_ref().take(batch_size));
        let stopped = || {
            options
                .stop
                .is_some_and(|stop| stop.load(Ordering::Relaxed))
        };
        let records: Vec<Result<Option<(u64, RunRecord)>, RunnerError>> = pool.install(|| {
            batch
                .par_iter()
                .map(|&index| {
                    if stopped() {
                        return Ok(None);
                    }
                    let spec = list.get(index).ok_or(RunnerError::RunIndex(index))?;
                    let worker = rayon::current_thread_index().unwrap_or(0) % workers;
                    let mut workspace = workspaces[worker]
                        .lock()
                        .unwrap_or_else(std::sync::PoisonError::into_inner);
                    let mut record =
                        span.in_scope(|| run_one(experiment, &spec, &mut workspace, options.heap))?;
                    drop(workspace);
                    if !experiment.paths.keeps(spec.repeat) {
                        record.path = None;
                    }
                    if let Some(progress) = options.progress {
                        progress(done.fetch_add(1, Ordering::Relaxed) + 1);
                    }
                    Ok(Some((index, record)))
                })
                .collect()
        });
        // After a stop, the runs finished before the first skipped one: the stream stays
        // an unbroken prefix of the run order.
        let mut finished = Vec::with_capacity(records.len());
        for record in records {
            match record? {
                Some(record) => finished.push(record),
                None => break,
            }
        }
        n_done += finished.len() as u64;
        let cut_short = finished.len() < batch.len();
        // In the pool, so that a sink's parallel work runs on the sweep's workers.
        pool.install(|| sink(finished))?;
        if cut_short || stopped() {
            break;
        }
    }
    Ok(n_done)
}

/// A record read back that is not the run of the config its index names.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RecordMismatch {
    /// The run index is past the end of the sweep.
    #[error("run {run} is past the sweep's {runs} runs")]
    PastEnd {
        /// The record's run index.
        run: u64,
        /// The sweep's runs.
        runs: u64,
    },
    /// One of the record's fields is not its run's.
    #[error(
        "run {run} has {field} {found:?}, but run {run} of the config is {field} {expected:?} \
         (a record of another config)"
    )]
    Field {
        /// The record's run index.
        run: u64,
        /// Which field: `map`, `problem`, `planner label` or `repeat`.
        field: &'static str,
        /// The record's value.
        found: String,
        /// The run's value in the config.
        expected: String,
    },
}

/// Checks that `record`, read back as run `run` of a stream, is that run of `experiment`'s
/// run list `list`: the same map, problem, planner label and repeat. A record of another
/// config at a valid index (a foreign shard or stream) is refused; the error says which
/// field differs, for the caller to prefix with the file and line.
pub fn check_record(
    experiment: &Experiment,
    list: &RunList,
    run: u64,
    record: &RunRecord,
) -> Result<(), RecordMismatch> {
    let spec = list.get(run).ok_or(RecordMismatch::PastEnd {
        run,
        runs: list.len(),
    })?;
    let map = &experiment.maps[spec.map];
    let problem = map.problems[spec.problem].index;
    let label = &experiment.planners[spec.planner].label;
    let fields: [(&str, String, String); 4] = [
        ("map", record.map.clone(), map.name.clone()),
        ("problem", record.problem.to_string(), problem.to_string()),
        ("planner label", record.planner.clone(), label.clone()),
        ("repeat", record.repeat.to_string(), spec.repeat.to_string()),
    ];
    for (field, found, expected) in fields {
        if found != expected {
            return Err(RecordMismatch::Field {
                run,
                field,
                found,
                expected,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn experiment(text: &str) -> Experiment {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../maps/paper/map01.map")
            .display()
            .to_string();
        let text = format!(
            "name = \"t\"\n{text}\n[[maps]]\nfiles = [{map:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n"
        );
        crate::config::parse(std::path::Path::new("t.toml"), &text).unwrap()
    }

    #[test]
    fn streamed_records_equal_collected_ones_and_read_back() {
        let experiment = experiment("repeats = 3\npaths = \"all\"");
        let options = RunOptions {
            threads: 2,
            ..Default::default()
        };
        let collected = crate::run_all(&experiment, &options).unwrap();
        let mut bytes = StreamHeader::new(&experiment, Shard::ALL, 6)
            .to_line()
            .unwrap();
        let n = run_stream(&experiment, 0..6, &options, |batch| {
            for (run, record) in &batch {
                encode(&mut bytes, *run, record)?;
            }
            Ok(())
        })
        .unwrap();
        assert_eq!(n, 6);
        // Cut the last line, as a kill mid-write would.
        bytes.truncate(bytes.len() - 10);
        let (header, mut reader) = StreamReader::new(&bytes[..], "test").unwrap();
        assert_eq!(header.config_hash, config_hash(&experiment));
        let mut read = Vec::new();
        while let Some((run, mut record)) = reader.next_run().unwrap() {
            assert_eq!(run, read.len() as u64);
            record.time_ms = collected[read.len()].time_ms;
            record.setup_ms = collected[read.len()].setup_ms;
            read.push(record);
        }
        assert!(reader.was_cut());
        assert_eq!(read.len(), 5);
        assert_eq!(&read[..], &collected[..5]);
    }

    #[test]
    fn lines_are_bounded_and_special_files_refused() {
        // A header line of MAX_LINE_BYTES without a newline: an error, read in bounded
        // memory, not a cut line.
        let long = std::io::repeat(b'x').take(MAX_LINE_BYTES + 10);
        let error = StreamReader::new(std::io::BufReader::new(long), "long")
            .err()
            .unwrap()
            .to_string();
        assert!(
            error.contains("long line 1: longer than 268435456 bytes"),
            "{error}"
        );
        let error = open_regular(std::path::Path::new("/dev/zero")).unwrap_err();
        assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
        assert!(error.to_string().contains("a character device"), "{error}");
    }

    #[test]
    fn paths_mode_figures_keeps_repeat_zero_only() {
        let experiment = experiment("repeats = 2");
        let mut kept = Vec::new();
        run_stream(&experiment, 0..4, &RunOptions::default(), |batch| {
            kept.extend(batch.iter().map(|(_, r)| (r.repeat, r.path.is_some())));
            Ok(())
        })
        .unwrap();
        assert_eq!(kept, [(0, true), (1, false), (0, true), (1, false)]);
    }

    #[test]
    fn the_hash_sees_parameters_and_repeats_not_threads() {
        let base = config_hash(&experiment("repeats = 2"));
        assert_eq!(base, config_hash(&experiment("repeats = 2\nthreads = 3")));
        assert_ne!(base, config_hash(&experiment("repeats = 3")));
        assert_ne!(base, config_hash(&experiment("repeats = 2\nseed = 1")));
    }

    #[test]
    fn four_billion_repeats_run_lazily() {
        let experiment = experiment("repeats = 4_000_000_000");
        assert_eq!(RunList::new(&experiment).len(), 8_000_000_000);
        let runs = crate::shard::ShardRuns::new(&experiment, Shard::parse("2/3").unwrap());
        assert_eq!(runs.len(), 2_666_666_667);
        let mut n = 0;
        run_stream(
            &experiment,
            runs.iter().take(5),
            &RunOptions::default(),
            |batch| {
                n += batch.len();
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(n, 5);
    }
}
