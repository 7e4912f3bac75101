//! Streamed sweeps: records handed out in run order as the runs finish.
//!
//! [`run_stream`] runs any increasing sequence of run indices (the whole run list, a
//! [`crate::shard::ShardRuns`] slice, or what a resumed sweep has left) on a rayon pool,
//! each worker claiming the next run as it finishes one and reusing its planners, and
//! hands the records to a sink on the calling thread ([`Delivery`]): in run order as soon
//! as the runs before them have finished (a frame's worth, or every tenth of a second at
//! the latest), and the runs that finished while an earlier one still ran, once one of
//! them has waited a tenth of a second for it (or a frame's worth waits), so that a sink
//! can keep every finished run on disk while the order waits for a slow run. Memory is bounded by a window of runs per worker
//! past the first run not yet handed in order, not by the sweep. Paths the config does
//! not keep ([`crate::config::PathsMode`]) are dropped in the worker.
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
//! config is recognised, and the gridplan version that wrote it; since 2026-12-08 also
//! each input's hash ([`input_hashes`]), so that a refused resume can say which input
//! changed ([`changed_inputs`]; streams without them still read). [`check_record`] checks
//! each record read back against the config's run list (map, problem, label, repeat).
//!
//! The runner writes no file: the sink and the reader work on bytes and `std::io` traits.
//! [`open_regular`] opens a stream file for reading, refusing anything but a regular file
//! (a link to `/dev/zero`, a FIFO nobody writes), and [`StreamReader`] refuses a line
//! longer than [`MAX_LINE_BYTES`], so a reader's memory is bounded whatever the file holds.

use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, VecDeque};
use std::io::{BufRead, Read as _};
use std::sync::atomic::Ordering;
use std::sync::{Condvar, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use planner_api::{CancelFlag, CancelPool, Counter, Counters};

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
    /// The hash of each input the config hash covers ([`input_hashes`]: the settings, each
    /// map's grid and problems), so that a refused `--resume` can say which changed
    /// (absent in streams written before 2026-12-08).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inputs: Option<Vec<(String, String)>>,
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
            inputs: Some(input_hashes(experiment)),
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
    hash_settings(&mut h, experiment);
    for map in &experiment.maps {
        h.text(&map.name);
        hash_cells(&mut h, map);
        hash_problems(&mut h, map);
    }
    format!("{:016x}", h.0)
}

/// Hashes an experiment's settings into `h`: name, repeats, seed, figures, paths,
/// sections and the planners (label, registry name, parameters, budget, compare).
fn hash_settings(h: &mut Fnv, experiment: &Experiment) {
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
}

/// Hashes `map`'s size and free cells (its file's content) into `h`.
fn hash_cells(h: &mut Fnv, map: &crate::config::MapEntry) {
    h.text(&format!("{}x{}", map.grid.width(), map.grid.height()));
    h.bytes(
        &map.grid
            .free_cells()
            .iter()
            .map(|&f| u8::from(f))
            .collect::<Vec<u8>>(),
    );
}

/// Hashes `map`'s problems (start, goal, stated optimum, invalidity) into `h`.
fn hash_problems(h: &mut Fnv, map: &crate::config::MapEntry) {
    for p in &map.problems {
        h.text(&format!(
            "{} {} {} {:?} {:?}",
            p.index, p.start, p.goal, p.optimal_length, p.invalid
        ));
    }
}

/// The settings [`hash_settings`] covers, one by one: (key, its text). Keys:
/// `name`, `repeats`, `seed`, `figures`, `paths`, `sections`, `planner LABEL` (its
/// registry name, parameters and `compare`) and `budget LABEL FIELD` (each of its budget's
/// limits), so that a refused resume names the one that changed.
fn setting_texts(experiment: &Experiment) -> Vec<(String, String)> {
    let mut texts = vec![
        ("name".to_string(), experiment.name.clone()),
        ("repeats".to_string(), experiment.repeats.to_string()),
        ("seed".to_string(), experiment.seed.to_string()),
        (
            "figures".to_string(),
            format!("{:?} {:?}", experiment.figures, experiment.figures_per_map),
        ),
        ("paths".to_string(), format!("{:?}", experiment.paths)),
        (
            "sections".to_string(),
            format!("{:?}", experiment.sections.as_ref().map(|s| &s.requests)),
        ),
    ];
    for planner in &experiment.planners {
        let label = &planner.label;
        texts.push((
            format!("planner {label}"),
            format!("{} {} {:?}", planner.name, planner.params, planner.compare),
        ));
        let budget = &planner.budget;
        for (field, value) in [
            ("max_expansions", format!("{:?}", budget.max_expansions)),
            ("max_time_ms", format!("{:?}", budget.max_time)),
            ("max_memory_mb", format!("{:?}", budget.max_memory_mb)),
        ] {
            texts.push((format!("budget {label} {field}"), value));
        }
    }
    texts
}

/// The words for the setting `key` of [`setting_texts`] in a refused resume's message.
fn setting_words(key: &str) -> String {
    if let Some(label) = key.strip_prefix("planner ") {
        return format!("planner {label:?}'s registry name, parameters or `compare`");
    }
    if let Some(rest) = key.strip_prefix("budget ") {
        // The label may hold spaces; the field, the last word, does not.
        let (label, field) = rest.rsplit_once(' ').unwrap_or((rest, ""));
        return format!("budget's `{field}` of planner {label:?} (`[budget]` or its own `budget`)");
    }
    format!("`{key}`")
}

/// What [`config_hash`] covers, hashed input by input (64-bit FNV-1a, hex), in the
/// experiment's order: `settings` (name, repeats, seed, figures, paths, sections and the
/// planners), then per map `map NAME` (its size and free cells: the map file's content)
/// and `problems NAME` (its problems: its scenario file or the config's list); then each
/// setting on its own, `setting KEY` (`setting_texts`), which streams of earlier
/// versions lack.
pub fn input_hashes(experiment: &Experiment) -> Vec<(String, String)> {
    let mut h = Fnv::default();
    hash_settings(&mut h, experiment);
    let mut inputs = vec![("settings".to_string(), format!("{:016x}", h.0))];
    for map in &experiment.maps {
        let mut h = Fnv::default();
        hash_cells(&mut h, map);
        inputs.push((format!("map {}", map.name), format!("{:016x}", h.0)));
        let mut h = Fnv::default();
        hash_problems(&mut h, map);
        inputs.push((format!("problems {}", map.name), format!("{:016x}", h.0)));
    }
    for (key, text) in setting_texts(experiment) {
        let mut h = Fnv::default();
        h.text(&text);
        inputs.push((format!("setting {key}"), format!("{:016x}", h.0)));
    }
    inputs
}

/// The settings that differ between `found` and `now` ([`input_hashes`]), each said;
/// `None` when `found` holds no setting on its own (a stream of an earlier version).
fn changed_settings(found: &[(String, String)], now: &[(String, String)]) -> Option<Vec<String>> {
    let settings = |list: &'_ [(String, String)]| -> Vec<(String, String)> {
        list.iter()
            .filter_map(|(k, hash)| Some((k.strip_prefix("setting ")?.to_string(), hash.clone())))
            .collect()
    };
    let (before, after) = (settings(found), settings(now));
    if before.is_empty() {
        return None;
    }
    let mut changed = Vec::new();
    for (key, hash) in &after {
        match before.iter().find(|(k, _)| k == key) {
            Some((_, old)) if old != hash => {
                changed.push(format!("the config's {} changed", setting_words(key)));
            }
            Some(_) => {}
            None if key.starts_with("planner ") => {
                changed.push(format!("{} was added", setting_words(key)));
            }
            None => {}
        }
    }
    for (key, _) in &before {
        if key.starts_with("planner ") && !after.iter().any(|(k, _)| k == key) {
            changed.push(format!("{} was removed", setting_words(key)));
        }
    }
    let labels = |list: &[(String, String)]| -> Vec<String> {
        list.iter()
            .filter(|(k, _)| k.starts_with("planner "))
            .map(|(k, _)| k.clone())
            .collect()
    };
    if changed.is_empty() && labels(&before) != labels(&after) {
        changed.push("the config's planners are in another order".to_string());
    }
    Some(changed)
}

/// What differs between the inputs a stream was recorded with (`found`, its header's
/// [`StreamHeader::inputs`]) and `experiment`'s now, said for a person: the settings,
/// a map file's content, a map's problems, maps added or gone (a glob matching other
/// files), their order. Empty when nothing is told apart.
pub fn changed_inputs(found: &[(String, String)], experiment: &Experiment) -> Vec<String> {
    let now = input_hashes(experiment);
    let find = |list: &[(String, String)], key: &str| {
        list.iter()
            .find(|(k, _)| k == key)
            .map(|(_, hash)| hash.clone())
    };
    let mut changed = Vec::new();
    if find(found, "settings") != find(&now, "settings") {
        match changed_settings(found, &now) {
            Some(settings) if !settings.is_empty() => changed.extend(settings),
            _ => changed.push(
                "the config's settings (name, repeats, seed, figures, paths, sections, \
                 planners or budgets) changed"
                    .to_string(),
            ),
        }
    }
    let names = |list: &[(String, String)]| -> Vec<String> {
        list.iter()
            .filter_map(|(k, _)| k.strip_prefix("map ").map(str::to_string))
            .collect()
    };
    let (before, after) = (names(found), names(&now));
    for map in &experiment.maps {
        if !before.contains(&map.name) {
            continue;
        }
        let key = format!("map {}", map.name);
        if find(found, &key) != find(&now, &key) {
            changed.push(format!(
                "map file {}'s content changed since the recorded runs",
                map.path.display()
            ));
        }
        let key = format!("problems {}", map.name);
        if find(found, &key) != find(&now, &key) {
            changed.push(format!(
                "the problems of map {} (its scenario file or the config's list) changed since \
                 the interrupted sweep",
                map.name
            ));
        }
    }
    let added: Vec<&str> = after
        .iter()
        .filter(|n| !before.contains(n))
        .map(String::as_str)
        .collect();
    let gone: Vec<&str> = before
        .iter()
        .filter(|n| !after.contains(n))
        .map(String::as_str)
        .collect();
    if !added.is_empty() || !gone.is_empty() {
        let mut said = String::from(
            "the config's maps (a glob of its map sets matches other files, or a map set changed):",
        );
        if !added.is_empty() {
            said.push_str(&format!(" now also {}", added.join(", ")));
        }
        if !gone.is_empty() {
            if !added.is_empty() {
                said.push(';');
            }
            said.push_str(&format!(" no longer {}", gone.join(", ")));
        }
        changed.push(said);
    } else if changed.is_empty() && before != after {
        changed.push("the config's maps are in another order".to_string());
    }
    changed
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

/// What [`run_stream`] hands its sink.
#[derive(Debug)]
pub enum Delivery<'a> {
    /// The next runs of the sequence in order, (index, record), each run once.
    InOrder(Vec<(u64, RunRecord)>),
    /// Runs that finished while an earlier run of the sequence had not (it was still
    /// running, or it failed), in the order they finished, each run once. They are handed
    /// again in [`Delivery::InOrder`] at their turn; a sink that must not lose a finished
    /// run to a kill writes them aside meanwhile (the sweep's `ahead.stream`,
    /// [`crate::sweep`]).
    Ahead(&'a [(u64, RunRecord)]),
    /// Every run handed in [`Delivery::Ahead`] so far, and every run given as done, has
    /// since been handed in order: what was written aside may go.
    CaughtUp,
}

/// What [`run_stream`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Streamed {
    /// Runs handed in order ([`Delivery::InOrder`]), the done ones given included.
    pub in_order: u64,
    /// Runs this call ran.
    pub ran: u64,
    /// Finished runs not handed in order (an earlier run failed, or did not run before a
    /// stop): each was handed in [`Delivery::Ahead`] or given as done.
    pub ahead: u64,
}

/// Positions of the run sequence a worker may run ahead of the first run not yet handed
/// in order, per worker: what bounds the records held.
const WINDOW_PER_WORKER: u64 = 512;

/// How long the coordinating thread sleeps when no run finishes.
const TICK: Duration = Duration::from_millis(10);

/// The longest a finished run waits before the sink is handed it (in order, or ahead).
const FLUSH_INTERVAL: Duration = Duration::from_millis(100);

/// Finished runs that wake the coordinating thread before its tick.
const WAKE_AT: usize = 256;

/// A run a worker finished (or a done run it passed), for the coordinating thread.
struct Finished {
    /// Its position in the run sequence.
    position: u64,
    /// Its run index.
    index: u64,
    /// Its record.
    outcome: Result<RunRecord, RunnerError>,
    /// Whether the sink has it already (a done run given to [`run_stream`]).
    written: bool,
}

/// What the workers and the coordinating thread share, under one lock.
struct State<I> {
    /// The run sequence left to claim.
    runs: I,
    /// The position of the next run to claim.
    next: u64,
    /// Whether `runs` has ended.
    exhausted: bool,
    /// Finished runs given to [`run_stream`], not yet passed by the claims.
    done: BTreeMap<u64, RunRecord>,
    /// The position of the first run not yet handed in order.
    frontier: u64,
    /// Runs finished and not yet taken by the coordinating thread.
    inbox: Vec<Finished>,
    /// Workers still claiming.
    active: usize,
    /// Workers waiting for the window to move.
    waiting: usize,
    /// Whether the coordinating thread waits for finished runs (and no worker has woken
    /// it since): workers wake it only then, once.
    sleeping: bool,
    /// No run starts any more (an error, a sink that failed, a worker that panicked).
    abort: bool,
}

struct Shared<I> {
    state: Mutex<State<I>>,
    /// Workers wait here for room in the window.
    room: Condvar,
    /// The coordinating thread waits here for finished runs.
    arrived: Condvar,
    /// Positions a worker may claim beyond the frontier.
    window: u64,
}

impl<I> Shared<I> {
    fn lock(&self) -> MutexGuard<'_, State<I>> {
        self.state
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// Leaves the workers' count when a worker ends, also by a panic (which stops the other
/// workers, so that the sweep ends and rayon hands the panic on).
struct Leaving<'a, I>(&'a Shared<I>);

impl<I> Drop for Leaving<'_, I> {
    fn drop(&mut self) {
        let mut state = self.0.lock();
        state.active -= 1;
        state.abort |= std::thread::panicking();
        drop(state);
        self.0.arrived.notify_one();
        self.0.room.notify_all();
    }
}

/// Runs the runs `runs` (increasing indices into `experiment`'s [`RunList`]) on the
/// pool's workers and hands `sink` their records ([`Delivery`]): in run order, a frame's
/// worth or every tenth of a second at the latest, and the runs that finished ahead of an
/// earlier one once one of them has waited a tenth of a second for it (or a frame's worth
/// waits), each once. The runs of `done` (finished before, which `sink` has had as
/// [`Delivery::Ahead`]) are not run: they are handed in order at their turn. A worker
/// claims the next run when it finishes one, never more than 512 runs per worker past the
/// first run not yet handed in order, so
/// the records held are bounded whatever the runs' times; the records do not depend on
/// the thread count. `sink` runs on the calling thread; progress counts the runs this
/// call ran, also from the calling thread. Once [`RunOptions::stop`] is set, no new run
/// starts and the runs in progress are cancelled (their budgets carry a
/// [`planner_api::CancelFlag`] that the calling thread raises within a tick of the stop):
/// a run that ends while the flag is raised is dropped, not handed (cut short, its
/// record would depend on when the stop came), so `--resume` runs it again. Every
/// finished run is handed to `sink` before this returns (in order up to the first run
/// that did not finish, the rest ahead).
/// A run's error stops the sweep the same way and is returned (the one earliest in the
/// run order); the sink's error is returned at once.
pub fn run_stream(
    experiment: &Experiment,
    runs: impl Iterator<Item = u64> + Send,
    done: BTreeMap<u64, RunRecord>,
    options: &RunOptions<'_>,
    mut sink: impl FnMut(Delivery<'_>) -> Result<(), RunnerError>,
) -> Result<Streamed, RunnerError> {
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
    let outstanding = done.len() as u64;
    let shared = Shared {
        state: Mutex::new(State {
            runs,
            next: 0,
            exhausted: false,
            done,
            frontier: 0,
            inbox: Vec::new(),
            active: workers,
            waiting: 0,
            sleeping: false,
            abort: false,
        }),
        room: Condvar::new(),
        arrived: Condvar::new(),
        window: workers as u64 * WINDOW_PER_WORKER,
    };
    let list = RunList::new(experiment);
    // The workers log inside the caller's span (as `run_all`'s).
    let span = tracing::Span::current();
    // Raised by the coordinating thread once the stop flag is: it cancels the runs in
    // progress. Lent from a pool, since a flag's byte is never freed.
    let lent = CANCEL.lend();
    let cancel = lent.flag();
    pool.in_place_scope(|scope| {
        for _ in 0..workers {
            let (shared, list, span) = (&shared, &list, &span);
            scope.spawn(move |_| work(shared, experiment, list, (options, cancel), span));
        }
        let mut coordinator = Coordinator::new(outstanding, cancel);
        let result = coordinator.coordinate(&shared, options, &mut sink);
        if result.is_err() {
            // The workers finish the runs they hold and start none.
            shared.lock().abort = true;
            shared.room.notify_all();
        }
        result
    })
}

/// Whether the sweep's stop flag is raised.
fn stopped(options: &RunOptions<'_>) -> bool {
    options
        .stop
        .is_some_and(|stop| stop.load(Ordering::Relaxed))
}

/// The cancel flags of [`run_stream`]'s calls, one lent to each call.
static CANCEL: CancelPool = CancelPool::new();

/// A worker: claims the next run of the sequence, runs it, hands it in, until the runs,
/// a stop or an abort end it; keeps one planner per label across its runs, whose budgets
/// carry `cancel`. A run that ends with `cancel` raised is dropped (it may have been cut
/// short).
fn work<I: Iterator<Item = u64>>(
    shared: &Shared<I>,
    experiment: &Experiment,
    list: &RunList,
    (options, cancel): (&RunOptions<'_>, CancelFlag),
    span: &tracing::Span,
) {
    let _leaving = Leaving(shared);
    let mut workspace = Workspace::cancelled_by(cancel);
    let mut finished: Option<Finished> = None;
    loop {
        let (position, index) = {
            let mut state = shared.lock();
            if let Some(finished) = finished.take() {
                state.inbox.push(finished);
                if state.sleeping && (state.inbox.len() >= WAKE_AT || state.waiting > 0) {
                    state.sleeping = false;
                    shared.arrived.notify_one();
                }
            }
            match claim(shared, state, options) {
                Some(claimed) => claimed,
                None => return,
            }
        };
        let outcome = list
            .get(index)
            .ok_or(RunnerError::RunIndex(index))
            .and_then(|spec| {
                let mut record =
                    span.in_scope(|| run_one(experiment, &spec, &mut workspace, options.heap))?;
                if !experiment.paths.keeps(spec.repeat) {
                    record.path = None;
                }
                Ok(record)
            });
        if cancel.is_cancelled() {
            // Stopped: no run starts any more, and this one may have been cut short.
            return;
        }
        finished = Some(Finished {
            position,
            index,
            outcome,
            written: false,
        });
    }
}

/// The next run to run (position, index), waiting while it lies beyond the window; done
/// runs passed on the way go to the inbox as they are. `None` once the runs end, the
/// stop flag is raised or the sweep aborts.
fn claim<I: Iterator<Item = u64>>(
    shared: &Shared<I>,
    mut state: MutexGuard<'_, State<I>>,
    options: &RunOptions<'_>,
) -> Option<(u64, u64)> {
    loop {
        if state.abort || state.exhausted || stopped(options) {
            return None;
        }
        if state.next >= state.frontier + shared.window {
            state.waiting += 1;
            // The coordinating thread moves the window as runs are handed in order.
            if std::mem::take(&mut state.sleeping) {
                shared.arrived.notify_one();
            }
            state = shared
                .room
                .wait_timeout(state, TICK)
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .0;
            state.waiting -= 1;
            continue;
        }
        let Some(index) = state.runs.next() else {
            state.exhausted = true;
            return None;
        };
        let position = state.next;
        state.next += 1;
        match state.done.remove(&index) {
            Some(record) => state.inbox.push(Finished {
                position,
                index,
                outcome: Ok(record),
                written: true,
            }),
            None => return Some((position, index)),
        }
    }
}

/// The coordinating thread's side of [`run_stream`]: finished runs put back in order and
/// handed to the sink.
struct Coordinator {
    /// Finished runs not yet handed in order, by position from the frontier's: (index,
    /// record, when it came if the sink has not had it ahead); at most the window's
    /// positions.
    buffer: VecDeque<Option<(u64, RunRecord, Option<Instant>)>>,
    /// Runs in order, not yet handed.
    ready: Vec<(u64, RunRecord)>,
    /// The position of the next run to hand in order.
    frontier: u64,
    /// Runs the sink has had ahead (or was given as done) and not yet in order.
    outstanding: u64,
    /// Runs in `buffer` the sink has not had.
    unwritten: usize,
    /// When the longest waiting of them came, or earlier (`None`: none waits).
    oldest: Option<Instant>,
    /// Whether runs were handed ahead (or given as done) since the last catch-up.
    behind: bool,
    /// The earliest error of a run, by position.
    error: Option<(u64, RunnerError)>,
    streamed: Streamed,
    last_flush: Instant,
    /// The flag the workers' runs carry, raised once the stop flag is.
    cancel: CancelFlag,
}

impl Coordinator {
    fn new(outstanding: u64, cancel: CancelFlag) -> Coordinator {
        Coordinator {
            buffer: VecDeque::new(),
            ready: Vec::new(),
            frontier: 0,
            outstanding,
            unwritten: 0,
            oldest: None,
            behind: outstanding > 0,
            error: None,
            streamed: Streamed::default(),
            last_flush: Instant::now(),
            cancel,
        }
    }

    /// Takes the workers' finished runs until every worker has ended, handing them to
    /// `sink` as they come into order (and ahead when they wait too long); returns what
    /// was handed, or the first error of a run (by position) or of the sink.
    fn coordinate<I>(
        &mut self,
        shared: &Shared<I>,
        options: &RunOptions<'_>,
        sink: &mut dyn FnMut(Delivery<'_>) -> Result<(), RunnerError>,
    ) -> Result<Streamed, RunnerError> {
        loop {
            let (inbox, ended) = {
                let mut state = shared.lock();
                if state.frontier != self.frontier {
                    state.frontier = self.frontier;
                    if state.waiting > 0 {
                        shared.room.notify_all();
                    }
                }
                if self.error.is_some() && !state.abort {
                    state.abort = true;
                    shared.room.notify_all();
                }
                if stopped(options) {
                    // The runs in progress end at their next budget check.
                    self.cancel.cancel();
                    if state.waiting > 0 {
                        shared.room.notify_all();
                    }
                }
                if state.inbox.is_empty() && state.active > 0 {
                    state.sleeping = true;
                    state = shared
                        .arrived
                        .wait_timeout(state, TICK)
                        .unwrap_or_else(std::sync::PoisonError::into_inner)
                        .0;
                    state.sleeping = false;
                }
                // A worker hands in its last run before it leaves: with none left, the
                // inbox holds every run still to take.
                (std::mem::take(&mut state.inbox), state.active == 0)
            };
            self.take(inbox, options);
            self.hand(sink, ended)?;
            if ended {
                // The last hand wrote every run left ahead; `outstanding` also counts the
                // done runs never reached.
                self.streamed.ahead = self.outstanding;
                return match self.error.take() {
                    Some((_, error)) => Err(error),
                    None => Ok(self.streamed),
                };
            }
        }
    }

    /// Puts `inbox`'s runs into the buffer and the runs now in order into `ready`.
    fn take(&mut self, inbox: Vec<Finished>, options: &RunOptions<'_>) {
        let ran = self.streamed.ran;
        let now = Instant::now();
        for finished in inbox {
            let record = match finished.outcome {
                Ok(record) => record,
                Err(error) => {
                    if self
                        .error
                        .as_ref()
                        .is_none_or(|(p, _)| finished.position < *p)
                    {
                        self.error = Some((finished.position, error));
                    }
                    continue;
                }
            };
            // A done run: the sink had it, and `outstanding` counts it already.
            let came = (!finished.written).then_some(now);
            if came.is_some() {
                self.streamed.ran += 1;
                self.unwritten += 1;
                self.oldest = self.oldest.or(came);
            }
            // Positions below the frontier are handed already; a worker claims none
            // beyond the window.
            let slot = (finished.position - self.frontier) as usize;
            if self.buffer.len() <= slot {
                self.buffer.resize_with(slot + 1, || None);
            }
            self.buffer[slot] = Some((finished.index, record, came));
        }
        if let (Some(progress), true) = (options.progress, self.streamed.ran > ran) {
            progress(self.streamed.ran);
        }
        while let Some(Some(_)) = self.buffer.front() {
            let Some(Some((index, record, came))) = self.buffer.pop_front() else {
                break;
            };
            match came {
                None => self.outstanding -= 1,
                Some(_) => self.unwritten -= 1,
            }
            self.ready.push((index, record));
            self.frontier += 1;
        }
    }

    /// Hands `sink` the runs in order, when a frame's worth waits, [`FLUSH_INTERVAL`] has
    /// passed since the last hand, or (`last`) the workers have ended; the catch-up; and
    /// the runs that wait for an earlier run, when a frame's worth waits, one has waited
    /// [`FLUSH_INTERVAL`], or at the `last`.
    fn hand(
        &mut self,
        sink: &mut dyn FnMut(Delivery<'_>) -> Result<(), RunnerError>,
        last: bool,
    ) -> Result<(), RunnerError> {
        let due = last || self.last_flush.elapsed() >= FLUSH_INTERVAL;
        let caught_up = self.behind && self.outstanding == 0;
        if self.ready.len() >= crate::frames::FRAME_RUNS
            || (!self.ready.is_empty() && (due || caught_up))
        {
            let ready = std::mem::take(&mut self.ready);
            self.streamed.in_order += ready.len() as u64;
            sink(Delivery::InOrder(ready))?;
            self.last_flush = Instant::now();
        }
        if caught_up {
            sink(Delivery::CaughtUp)?;
            self.behind = false;
        }
        if self.unwritten == 0 {
            self.oldest = None;
        } else if last || self.unwritten >= crate::frames::FRAME_RUNS || self.waited_long() {
            let ahead: Vec<(u64, RunRecord)> = self
                .buffer
                .iter_mut()
                .flatten()
                .filter(|(_, _, came)| came.is_some())
                .map(|(index, record, came)| {
                    *came = None;
                    (*index, record.clone())
                })
                .collect();
            self.outstanding += ahead.len() as u64;
            self.unwritten = 0;
            self.oldest = None;
            self.behind = true;
            sink(Delivery::Ahead(&ahead))?;
        }
        Ok(())
    }

    /// Whether a run the sink has not had has waited [`FLUSH_INTERVAL`] for an earlier
    /// run (`oldest` brought up to date when it looks so).
    fn waited_long(&mut self) -> bool {
        if self.oldest.is_none_or(|t| t.elapsed() < FLUSH_INTERVAL) {
            return false;
        }
        // `oldest` may be a run handed in order since: the oldest of those still waiting.
        self.oldest = self
            .buffer
            .iter()
            .flatten()
            .filter_map(|(_, _, came)| *came)
            .min();
        self.oldest.is_some_and(|t| t.elapsed() >= FLUSH_INTERVAL)
    }
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
        let n = run_stream(&experiment, 0..6, BTreeMap::new(), &options, |delivery| {
            if let Delivery::InOrder(batch) = delivery {
                for (run, record) in &batch {
                    encode(&mut bytes, *run, record)?;
                }
            }
            Ok(())
        })
        .unwrap();
        assert_eq!(n.in_order, 6);
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
        let options = RunOptions::default();
        run_stream(&experiment, 0..4, BTreeMap::new(), &options, |delivery| {
            if let Delivery::InOrder(batch) = delivery {
                kept.extend(batch.iter().map(|(_, r)| (r.repeat, r.path.is_some())));
            }
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
            BTreeMap::new(),
            &RunOptions::default(),
            |delivery| {
                if let Delivery::InOrder(batch) = delivery {
                    n += batch.len();
                }
                Ok(())
            },
        )
        .unwrap();
        assert_eq!(n, 5);
    }
}
