//! Streamed, resumable and sharded sweeps on disk, and merging shards.
//!
//! A sweep appends its records to `records.stream` (framed, [`crate::frames`]) in the
//! output's stream area (`.<name>.stream/` beside the output directory, under its own lock:
//! [`outdir::stream_area`]) in run order, as soon as the runs before them have finished
//! (a frame of 1,024 runs, or a tenth of a second's runs at the latest), and the runs that
//! finished while an earlier one still ran to `ahead.stream` beside it, once one of them
//! has waited a tenth of a second (or 1,024 wait), in the order they finished
//! ([`stream::run_stream`]); ahead.stream is cut back to its header whenever
//! records.stream holds all its runs. A killed sweep so loses only the runs in progress
//! and those that finished in the last tenth of a second or so (and a frame cut
//! mid-write).
//! `--resume` reads both files back: if their headers' config hash matches the config's,
//! the runs they hold are kept (a cut last frame is dropped) and the sweep runs the
//! others; a changed config is refused, and so are the finished results of another
//! config or shard in the output (`resume_finished`); a shard's finished results of the
//! same config are left as they are, provenance included (no run runs, nothing is
//! written: a resubmitted Slurm array, whose tasks always resume). A changed config is
//! refused naming what changed, when the stream's header holds its inputs' hashes
//! ([`stream::changed_inputs`]: a map file's content, a map's problems, the maps a glob
//! matches, the settings). A stream that does not read back (a frame failing its checksum
//! with frames after it) is refused with what to do (run without `--resume`, or remove the
//! stream area). Without `--resume` an old stream is discarded, and said
//! ([`Progress::discarding`]: how many runs, of this config or another, where). A symbolic
//! link at a stream file's name is refused, never followed
//! ([`outdir::OutdirError::LinkedStream`]). [`resumed_streams`] lists the files whose headers `--resume`
//! checks (`slurm` checks them before writing its scripts).
//!
//! When the sweep is whole, the final outputs are rendered, in run order, from its records
//! (those of this process, after those a resumed sweep reads back from the stream; the
//! standard counter names of records read back are static strings, not one allocation
//! each) and written atomically by [`outdir::write_results_streamed`]: `runs.json` (a
//! table without paths, [`crate::output::runs_json`]) and `runs.csv` row by row into their
//! files, `summary.md`, figures, and `paths.jsonl` with the paths the config keeps
//! (`paths`). A sweep of more than [`HELD_RUNS`] runs holds none of its records, and one
//! whose records pass [`HELD_BYTES`] lets go of those it held: its
//! outputs are written from its stream on disk (`paths = "figures"`'s paths.jsonl too,
//! [`PATHS_FILE`]), and its report reads them in passes ([`Results::passes`]); `merge` of such a sweep's shards writes the merged records to a
//! framed stream in the output's stream area first, holding one record per shard, and
//! `report` of such a directory reads its `records.stream` in passes. Then the stream
//! area is removed (only while it carries gridplan's marker:
//! [`outdir::StreamArea`]). A shard (`--shard K/N`) instead writes its
//! stream as `shard.stream` (framed; an earlier version's `shard.jsonl` is still read) into its output directory; [`merge`] checks that a set of shard
//! directories is complete and of one config and renders the one sweep's outputs from them.
//!
//! Records read back are checked, not trusted. `--resume` and [`merge`] check every record
//! against the config's run list (its map, problem, planner label and repeat must be those
//! of its run index: [`stream::check_record`]), after the stream header's experiment,
//! config hash and shard, and refuse a mismatch naming the stream or shard file and its
//! line. Versions: a stream header names the gridplan that wrote it; `--resume` refuses a
//! stream of another version (or of none), naming both, so one sweep's records come from
//! one program. `merge` refuses shards whose results markers or stream headers name
//! different gridplan versions, naming both shards and versions, and merges shards all of
//! one other version with a warning naming it and its own.
//!
//! A sweep whose stop flag ([`SweepArgs::stop`], set by the command line on SIGINT or
//! SIGTERM) is raised starts no new run, cancels the runs in progress (through their
//! budget's cancel flag, [`planner_api::Budget::cancel`], within a budget check: a run of
//! hours stops at once) and records none of them (cut short, a run's record would depend
//! on when the stop came, so `--resume` runs them again), appends every finished run, and
//! returns a [`Report`] with [`Report::interrupted`] set: nothing is
//! rendered, the old results stay as they were, and the stream stays for `--resume`.
//! Raised once the runs are done, while the results are rendered and written, it stops
//! that too ([`Results::stop`]: the report checks it between its sections, figures and
//! files, and every pass over the records stops within a record), with the same
//! outcome: nothing written, every run kept in the stream for `--resume`. Raised while the
//! sweep waits for another sweep's lock on the same output, it ends the wait at once
//! ([`outdir::OutdirError::Stopped`]), with nothing created.
//!
//! Failures keep the runs, and say so. Once every run is recorded, any failure to write
//! the results (a full disk, a file of the user's that appeared in the output) is
//! [`RunnerError::NotWritten`]: all N runs are recorded in the stream, and `--resume`
//! writes the results without running any again. A failure to append to the stream (a
//! full disk) is [`RunnerError::StreamNotWritten`], which says how many runs its complete
//! frames keep for `--resume`. A shard given to `merge` whose directory does not exist is
//! [`ResultsError::ShardUnfinished`] when its stream area holds an interrupted run of it
//! (with the command that finishes it), else [`ResultsError::ShardMissing`].

use std::collections::BTreeMap;
use std::fs::{self, File};
use std::io::{BufReader, Seek as _, SeekFrom, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::config::ConfigError;
use crate::expanded::{self, ExpandedCells};
use crate::output::{OutputFile, StreamedFile};
use crate::passes::{RecordPasses, StoppablePasses, StreamPasses};
use crate::provenance::{Machine, Provenance};
use crate::readback::{RecordAt, ResultsError, ResumeError, SweepId};
use crate::record::Reproduction;
use crate::run::{HeapMeter, RunList};
use crate::shard::{Shard, ShardRuns};
use crate::stream::{
    self, Delivery, Place, StreamError, StreamHeader, StreamProblem, StreamReader,
};
use crate::{config, outdir, output as results, Experiment, RunOptions, RunRecord, RunnerError};

/// The resume stream of a sweep's stream area: framed binary ([`crate::frames`]), the
/// shard's runs in order from its first.
const RECORDS: &str = "records.stream";

/// The runs of a sweep's stream area that finished while an earlier run had not (it was
/// still running), in the order they finished, framed as [`RECORDS`]: what a kill leaves
/// of them for `--resume`. Cut back to its header once every run in it is in [`RECORDS`].
const AHEAD: &str = "ahead.stream";

/// The JSON Lines resume stream of earlier versions: `--resume` still reads it, carrying
/// its runs over into a framed stream ([`crate::frames::write_framed`]).
const OLD_RECORDS: &str = "records.jsonl";

/// The merged stream of a large merge, in the output's stream area while the outputs are
/// written from it.
const MERGED: &str = "merged.stream";

/// A shard's stream in its results directory: its framed resume stream, copied (about 80
/// bytes a run).
pub const SHARD_FILE: &str = "shard.stream";

/// The JSON Lines shard stream of earlier versions (about 460 bytes a run): `merge` still
/// reads it from a shard directory without [`SHARD_FILE`].
pub const OLD_SHARD_FILE: &str = "shard.jsonl";

/// The most runs whose records a whole sweep holds in memory (for its report's sections and
/// charts that read every record). A larger sweep holds none: its tables are written from
/// its stream on disk, and its report reads the records in passes ([`Results::passes`],
/// [`crate::passes`]), in memory bounded by the report's groups, not by the runs.
pub const HELD_RUNS: u64 = 100_000;

/// The most bytes of records a whole sweep holds in memory ([`record_bytes`]: a record's
/// own size, its strings, counters, path, marks and series): 128 MiB. A sweep whose
/// records pass it, though it has at most [`HELD_RUNS`] runs (a planner that marks every
/// jump point: 34 KB a run), lets go of the records it held and writes its outputs from
/// its stream as a larger sweep does ([`SweepArgs::held_bytes`] lowers it); so does
/// [`report`] of a results directory. (`merge` still holds up to [`HELD_RUNS`] records.)
pub const HELD_BYTES: u64 = 128 << 20;

/// An estimate of the memory `record` takes, its heap included: its own size, its strings,
/// its counters (each name counted as owned), its path, return legs, marks and series,
/// each by its length. What [`HELD_BYTES`] bounds.
pub fn record_bytes(record: &RunRecord) -> u64 {
    use std::mem::size_of;
    let strings = record.map.len()
        + record.planner.len()
        + record.algorithm.len()
        + record.error.as_ref().map_or(0, String::len);
    let counters = record
        .counters
        .iter()
        .map(|(name, _)| size_of::<(std::borrow::Cow<'static, str>, u64)>() + name.len())
        .sum::<usize>();
    let path = record
        .path
        .as_ref()
        .map_or(0, |p| std::mem::size_of_val(p.cells()));
    let returns = record
        .returns
        .as_ref()
        .map_or(0, |r| r.len() * size_of::<planner_api::ReturnLeg>());
    let marks = record
        .marks
        .iter()
        .map(|m| size_of::<planner_api::Mark>() + m.label.len())
        .sum::<usize>();
    let series = record
        .series
        .iter()
        .map(|s| size_of::<planner_api::Series>() + s.name.len() + s.x.len() + s.points.len() * 16)
        .sum::<usize>();
    (size_of::<RunRecord>() + strings + counters + path + returns + marks + series) as u64
}

/// The paths a results directory keeps (`paths`), one JSON line per run.
pub const PATHS_FILE: &str = "paths.jsonl";

/// A whole sweep's results, as the report reads them.
pub struct Results<'a> {
    /// The experiment.
    pub experiment: &'a Experiment,
    /// Its records, in run order (paths as the config keeps them); empty when the sweep
    /// has more than [`HELD_RUNS`] runs or its records take more than [`HELD_BYTES`],
    /// which are then read through `passes` only.
    pub records: &'a [RunRecord],
    /// The same records as passes: `records`, or the sweep's stream on disk.
    pub passes: &'a dyn RecordPasses,
    /// The expanded cells of the drawn runs, recorded at run time (`figures_expanded`).
    pub expanded: &'a ExpandedCells,
    /// Where, when and how the sweep ran.
    pub provenance: &'a Provenance,
    /// The sweep's wall time so far, in seconds (OMPL's experiment time).
    pub seconds: f64,
    /// The sweep's stop flag ([`SweepArgs::stop`]), if it has one: a report checks it
    /// between the files it renders ([`check_stop`]); `passes` already stop with it.
    pub stop: Option<&'a AtomicBool>,
}

/// [`RunnerError::Interrupted`] once `stop` is raised: what a report calls between its
/// steps so that Ctrl-C stops it promptly.
pub fn check_stop(stop: Option<&AtomicBool>) -> Result<(), RunnerError> {
    match stop.is_some_and(|s| s.load(Ordering::Relaxed)) {
        true => Err(RunnerError::Interrupted),
        false => Ok(()),
    }
}

/// The report step of a sweep: the runner hands a whole sweep's [`Results`] to it and
/// writes the files it returns beside runs.json and runs.csv. planner-report implements
/// it; the runner knows no section, figure or chart.
pub trait Render: Sync {
    /// Checks what the config asks of the report (its `sections`), right after the
    /// config is read, so a sweep with a bad request runs nothing.
    fn check(&self, experiment: &Experiment) -> Result<(), ConfigError>;

    /// The report files of `results` and the published numbers they compared.
    fn render(&self, results: &Results<'_>)
        -> Result<(Vec<OutputFile>, Reproduction), RunnerError>;
}

/// What `experiment` did.
#[derive(Debug, Clone)]
pub struct Report {
    /// Runs done.
    pub n_runs: usize,
    /// Output directory written.
    pub output: PathBuf,
    /// Published numbers compared and matched.
    pub reproduction: Reproduction,
    /// Wall time of the sweep and the writing, in seconds.
    pub seconds: f64,
    /// `Some(n)` when the stop flag ended the sweep with `n` of its `n_runs` runs
    /// recorded (in the stream, for `--resume`); no results were written.
    pub interrupted: Option<u64>,
    /// The records written (paths left out, as in runs.json), when [`SweepArgs::keep_records`]
    /// asked for them; else empty.
    pub records: Vec<RunRecord>,
    /// The sentence saying which result tables a large sweep left out
    /// ([`crate::output::Outputs::left_out`], as summary.md says it); `None` when every
    /// table asked for was written.
    pub left_out: Option<String>,
}

/// A sweep's progress display (a command line's progress bar); the sweep calls it from
/// its own thread, in order: [`Progress::start`], [`Progress::set`] any number of times,
/// [`Progress::finish`].
pub trait Progress: Sync {
    /// The sweep has `total` runs, of which `done` were recorded before (a resume).
    fn start(&self, total: u64, done: u64);
    /// `done` of the runs are recorded.
    fn set(&self, done: u64);
    /// The runs are done (the outputs are being written).
    fn finish(&self);
    /// Before [`Progress::start`] of a sweep asked to resume (`--resume`): `done` of its
    /// `total` runs were recorded before in the stream of the results directory `output`
    /// (0: there was nothing to resume, every run runs). By default nothing is shown; the
    /// command line says it on stderr.
    fn resumed(&self, done: u64, total: u64, output: &Path) {
        let _ = (done, total, output);
    }
    /// Before [`Progress::start`] of a sweep not asked to resume: it discards the runs an
    /// interrupted sweep recorded in its output's stream area; `message` says how many, of
    /// which sweep, and where ("discarding N recorded runs of an interrupted sweep of this
    /// config at STREAM (rerun with --resume to keep them)"). By default a warning on the
    /// log; the command line says it on stderr.
    fn discarding(&self, message: &str) {
        tracing::warn!("{message}");
    }
}

/// The machine of a caller that tells none: commit and host unknown.
static UNKNOWN_MACHINE: Machine = Machine {
    commit: None,
    host: None,
};

/// What `experiment` is asked to do.
#[derive(Clone, Copy)]
pub struct SweepArgs<'a> {
    /// The config file.
    pub config: &'a Path,
    /// Worker threads (0: the config's).
    pub threads: usize,
    /// Output directory (default: the config's; for a shard, `<that>-shard-K-of-N`).
    pub output: Option<&'a Path>,
    /// Where progress goes (none: nowhere), and what a resume found.
    pub progress: Option<&'a dyn Progress>,
    /// The commit and host for the provenance, which the caller learns (the runner reads
    /// no environment and starts no process); [`SweepArgs::new`]: unknown.
    pub machine: &'a Machine,
    /// The git commit the calling binary was built from (its build script's, as
    /// `gridplan --version` says it), for the provenance ([`Provenance::build`]);
    /// [`SweepArgs::new`]: `None`, not said.
    pub build: Option<&'a str>,
    /// Peak-heap measurement per run (none: `peak_heap_bytes` is 0); [`crate::alloc::Meter`]
    /// when the binary installs [`crate::alloc::Counting`].
    pub heap: Option<&'a dyn HeapMeter>,
    /// Keep the runs an interrupted sweep recorded (or a finished one: see
    /// `resume_finished`); a stream or finished results of another config, version or
    /// shard are refused ([`crate::readback::ResumeError`]), never replaced.
    pub resume: bool,
    /// Run one shard only.
    pub shard: Option<Shard>,
    /// Once set, the sweep stops (see the module docs).
    pub stop: Option<&'a AtomicBool>,
    /// Return the records in [`Report::records`] (for a library caller; a whole sweep of
    /// at most [`HELD_RUNS`] runs and [`HELD_BYTES`] of records holds them anyway to write
    /// its reports; a larger one returns none).
    pub keep_records: bool,
    /// The report step (summary.md, figures, ...).
    pub render: &'a dyn Render,
    /// The most bytes of records the sweep holds ([`record_bytes`]); [`SweepArgs::new`]:
    /// [`HELD_BYTES`].
    pub held_bytes: u64,
    /// How long to wait for another sweep on the same output to end (the lock its stream
    /// area holds from its start to its end) before failing with
    /// [`crate::outdir::OutdirError::Locked`]; [`SweepArgs::new`]:
    /// [`outdir::DEFAULT_LOCK_WAIT`].
    pub lock_wait: Duration,
}

impl<'a> SweepArgs<'a> {
    /// A plain sweep of `config` reported by `render`: the config's threads and output, no
    /// progress, no heap measurement, commit and host unknown, not resumed, not sharded.
    pub fn new(config: &'a Path, render: &'a dyn Render) -> SweepArgs<'a> {
        SweepArgs {
            config,
            threads: 0,
            output: None,
            progress: None,
            machine: &UNKNOWN_MACHINE,
            build: None,
            heap: None,
            resume: false,
            shard: None,
            keep_records: false,
            stop: None,
            render,
            lock_wait: outdir::DEFAULT_LOCK_WAIT,
            held_bytes: HELD_BYTES,
        }
    }
}

/// Runs (or resumes) a sweep and writes its results directory (or its shard's).
pub fn experiment(args: &SweepArgs) -> Result<Report, RunnerError> {
    let started = Instant::now();
    let experiment = config::load(args.config)?;
    args.render.check(&experiment)?;
    if args.threads > config::MAX_THREADS {
        // Refused before the output's stream area is made, so nothing is written.
        return Err(RunnerError::Threads(args.threads));
    }
    let shard = args.shard.unwrap_or(Shard::ALL);
    let dir = match (args.output, args.shard) {
        (Some(dir), _) => dir.to_path_buf(),
        (None, Some(s)) => {
            let mut name = experiment.output.as_os_str().to_os_string();
            name.push(format!("-shard-{}-of-{}", s.index, s.count));
            PathBuf::from(name)
        }
        (None, None) => experiment.output.clone(),
    };
    outdir::check(&dir)?;
    // Ctrl-C while waiting for another sweep's lock stops at once, leaving nothing behind.
    let area = outdir::stream_area_stoppable(&dir, args.lock_wait, args.stop)?;
    let runs = ShardRuns::new(&experiment, shard);
    let header = StreamHeader::new(&experiment, shard, runs.len());
    let path = area.dir.join(RECORDS);
    let opened = open_stream(args, &area, &header, &experiment, &runs, &dir)?;
    if opened.finished && args.shard.is_some() {
        // A finished shard resumed (a resubmitted or requeued array task): its directory
        // already holds these very records, so it is left as it is, provenance included.
        if let Err(e) = area.remove() {
            tracing::warn!("{} could not be removed: {e}", area.dir.display());
        }
        return Ok(Report {
            n_runs: runs.len() as usize,
            output: dir,
            reproduction: Reproduction::default(),
            seconds: started.elapsed().as_secs_f64(),
            interrupted: None,
            records: Vec::new(),
            left_out: None,
        });
    }
    tracing::info!(experiment = %experiment.name, runs = runs.len(), %shard, "sweep");
    let (records, recorded) = stream_runs(args, &experiment, &runs, opened, &area.dir)?;
    let interrupted = |dir| Report {
        n_runs: runs.len() as usize,
        output: dir,
        reproduction: Reproduction::default(),
        seconds: started.elapsed().as_secs_f64(),
        interrupted: Some(recorded),
        records: Vec::new(),
        left_out: None,
    };
    // Short of the shard's runs: the sweep was stopped.
    if recorded < runs.len() {
        return Ok(interrupted(dir));
    }
    let finished = match args.shard {
        Some(_) => {
            let threads = worker_threads(args.threads, experiment.threads);
            let info = RunInfo {
                provenance: collect_provenance(args, threads),
                seconds: started.elapsed().as_secs_f64(),
            };
            finish_shard(&experiment, &path, &dir, (shard, &info), args.stop)
                .map(|()| (Reproduction::default(), Vec::new()))
        }
        None => finish_sweep(args, &experiment, &header, records, &path, &dir, started),
    };
    // Stopped while rendering or writing (a table's pass fails as a write error): the old
    // results stay, the stream stays for `--resume` (which then runs nothing again and
    // writes the results).
    if finished.is_err() && check_stop(args.stop).is_err() {
        return Ok(interrupted(dir));
    }
    // Any other failure to write them (a full disk, a file of the user's that appeared in
    // the output meanwhile) says that every run is kept for --resume.
    let (reproduction, records) = finished.map_err(|source| RunnerError::NotWritten {
        runs: runs.len(),
        stream: path.clone(),
        source: Box::new(source),
    })?;
    if let Err(e) = area.remove() {
        tracing::warn!(
            "the results are written, but the stream area {} could not be removed: {e}",
            area.dir.display()
        );
    }
    Ok(Report {
        n_runs: runs.len() as usize,
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
        interrupted: None,
        records,
        left_out: match args.shard {
            Some(_) => None,
            None => experiment.outputs.left_out(runs.len()),
        },
    })
}

/// Writes a whole sweep's results directory `dir` from its `records` (when held: at most
/// [`HELD_RUNS`] runs and [`HELD_BYTES`]; else `None`, read back from its stream `path`)
/// through [`finish`];
/// returns the reproduction and, when [`SweepArgs::keep_records`] asks, the records.
fn finish_sweep(
    args: &SweepArgs,
    experiment: &Experiment,
    header: &StreamHeader,
    records: Option<Vec<RunRecord>>,
    path: &Path,
    dir: &Path,
    started: Instant,
) -> Result<(Reproduction, Vec<RunRecord>), RunnerError> {
    if let Some(records) = records.as_ref().filter(|r| r.len() as u64 != header.runs) {
        let problem = StreamProblem::Incomplete {
            recorded: records.len() as u64,
            declared: header.runs,
        };
        let file = path.display().to_string();
        return Err(StreamError::new(&file, Place::File, problem).into());
    }
    let threads = worker_threads(args.threads, experiment.threads);
    let info = RunInfo {
        provenance: collect_provenance(args, threads),
        seconds: started.elapsed().as_secs_f64(),
    };
    let source = match records {
        Some(records) => Source::Held(records),
        None => Source::Stream(StreamPasses::new(path, header.runs)),
    };
    let (reproduction, records) =
        finish(args.render, experiment, source, None, dir, &info, args.stop)?;
    let kept = if args.keep_records {
        records
    } else {
        Vec::new()
    };
    Ok((reproduction, kept))
}

/// A sweep's stream files in its stream area, open for appending, and the runs they hold.
struct Opened {
    /// records.stream, at its end: the first `prefix` runs of the shard, in order.
    records: File,
    /// ahead.stream ([`AHEAD`]), at its end.
    ahead: File,
    /// The bytes of ahead.stream's header line, which a catch-up cuts it back to.
    ahead_header: u64,
    /// Runs records.stream holds.
    prefix: u64,
    /// Runs after those that finished before (ahead.stream's), by index.
    done: BTreeMap<u64, RunRecord>,
    /// Every run of the shard came from the output's finished records
    /// ([`resume_finished`]): nothing is left to run or to write.
    finished: bool,
}

/// The sweep's stream files and the runs they already hold: a resumed sweep's, each cut
/// back to its last complete frame; else new ones with `header`.
fn open_stream(
    args: &SweepArgs,
    area: &outdir::StreamArea,
    header: &StreamHeader,
    experiment: &Experiment,
    runs: &ShardRuns,
    dir: &Path,
) -> Result<Opened, RunnerError> {
    let path = area.dir.join(RECORDS);
    let old = area.dir.join(OLD_RECORDS);
    // A link planted at a stream file's name is neither read nor written through.
    for name in [RECORDS, AHEAD, OLD_RECORDS] {
        area.check_not_link(name)?;
    }
    if !args.resume {
        notice_discarded(args, area, header);
    }
    let mut ahead = None;
    let mut finished = false;
    let damaged = |error| damaged_stream(area, error);
    let done = match args.resume {
        true if fs::symlink_metadata(&path).is_err() && fs::symlink_metadata(&old).is_ok() => {
            match resume_point(&old, header, runs, experiment).map_err(damaged)? {
                Some((_, n)) => Some((carry_over(area, &old, n)?, n)),
                None => None,
            }
        }
        true if fs::symlink_metadata(&path).is_err() => {
            let what = (header, runs, experiment);
            match resume_finished(area, dir, args.shard.is_some(), what) {
                Ok(done) => {
                    finished = done.is_some_and(|(_, n)| n == runs.len());
                    done
                }
                Err(error) => {
                    // Refused: the area, made for this sweep, holds no stream to keep.
                    if let Err(e) = area.remove() {
                        tracing::warn!("{} could not be removed: {e}", area.dir.display());
                    }
                    return Err(error);
                }
            }
        }
        true => {
            let point = resume_point(&path, header, runs, experiment).map_err(damaged)?;
            if let Some((_, prefix)) = point {
                let what = (header, runs, experiment);
                ahead = read_ahead(&area.dir.join(AHEAD), what, prefix).map_err(damaged)?;
            }
            point
        }
        false => None,
    };
    let framed = StreamHeader {
        format: crate::frames::FRAMED_FORMAT,
        ..header.clone()
    };
    let line = framed.to_line()?;
    let (records, prefix) = match done {
        Some((bytes, n)) => (open_at(area, RECORDS, bytes)?, n),
        None => {
            let mut file = area.open_write(RECORDS, true)?;
            file.write_all(&line)
                .map_err(|e| RunnerError::io(&path, e))?;
            (file, 0)
        }
    };
    let (ahead, ahead_header, done) = match ahead {
        Some(read) => (
            open_at(area, AHEAD, read.bytes)?,
            read.header_bytes,
            read.done,
        ),
        None => {
            let mut file = area.open_write(AHEAD, true)?;
            file.write_all(&line)
                .map_err(|e| RunnerError::io(&area.dir.join(AHEAD), e))?;
            (file, line.len() as u64, BTreeMap::new())
        }
    };
    if let (true, Some(progress)) = (args.resume, args.progress) {
        progress.resumed(prefix + done.len() as u64, runs.len(), dir);
    }
    Ok(Opened {
        records,
        ahead,
        ahead_header,
        prefix,
        done,
        finished,
    })
}

/// `error` of reading the stream in `area` back, made [`ResumeError::Damaged`] (which says
/// what to do) when the stream does not read back; other errors as they are.
fn damaged_stream(area: &outdir::StreamArea, error: RunnerError) -> RunnerError {
    match error {
        RunnerError::Stream(_) | RunnerError::Frame { .. } | RunnerError::Io { .. } => {
            ResumeError::Damaged {
                area: area.dir.clone(),
                source: Box::new(error),
            }
            .into()
        }
        other => other,
    }
}

/// Says, as a warning, that a sweep started without `--resume` discards the runs an
/// interrupted sweep recorded in the stream `area` (records.stream and ahead.stream, as far
/// as they read): how many, and whether that sweep was this one (`header`'s config,
/// version and shard: `--resume` would have kept them) or another. Nothing when there are
/// none.
fn notice_discarded(args: &SweepArgs, area: &outdir::StreamArea, header: &StreamHeader) {
    let path = area.dir.join(RECORDS);
    let Some((found, n)) = count_recorded(&path, &area.dir.join(AHEAD)) else {
        return;
    };
    if n == 0 {
        return;
    }
    let runs = match n {
        1 => "1 recorded run".to_string(),
        n => format!("{n} recorded runs"),
    };
    let same = found.config_hash == header.config_hash
        && found.experiment == header.experiment
        && (found.shard, found.shards) == (header.shard, header.shards)
        && found.gridplan == header.gridplan;
    let message = match same {
        true => format!(
            "discarding {runs} of an interrupted sweep of this config at {} (rerun with \
             --resume to keep them)",
            path.display()
        ),
        false => format!(
            "discarding {runs} of an interrupted sweep of another config, version or shard \
             (experiment {:?}, config hash {}, shard {}/{}, gridplan {}) at {}",
            found.experiment,
            found.config_hash,
            found.shard,
            found.shards,
            found.gridplan.as_deref().unwrap_or("of unknown version"),
            path.display()
        ),
    };
    match args.progress {
        Some(progress) => progress.discarding(&message),
        None => tracing::warn!("{message}"),
    }
}

/// The header of the stream `records` and the runs it and `ahead` (the runs finished
/// ahead of it) hold, as far as they read; `None` when `records` is missing or its header
/// does not read.
fn count_recorded(records: &Path, ahead: &Path) -> Option<(StreamHeader, u64)> {
    let open = |path: &Path| {
        let file = stream::open_regular(path).ok()?;
        StreamReader::new(BufReader::new(file), &path.display().to_string()).ok()
    };
    let (header, mut reader) = open(records)?;
    let (mut n, mut last) = (0u64, None);
    while let Ok(Some((run, _))) = reader.next_run() {
        n += 1;
        last = Some(run);
    }
    if let Some((_, mut reader)) = open(ahead) {
        while let Ok(Some((run, _))) = reader.next_run() {
            if last.is_none_or(|last| run > last) {
                n += 1;
            }
        }
    }
    Some((header, n))
}

/// The area's file `name`, open for appending after its first `bytes` (what follows, a
/// frame cut by a kill, is cut off).
fn open_at(area: &outdir::StreamArea, name: &str, bytes: u64) -> Result<File, RunnerError> {
    let mut file = area.open_write(name, false)?;
    file.set_len(bytes)
        .and_then(|()| file.seek(SeekFrom::End(0)).map(drop))
        .map_err(|e| RunnerError::io(&area.dir.join(name), e))?;
    Ok(file)
}

/// A sweep resumed after it finished (a requeued cluster task, a script that always passes
/// `--resume`): no stream is left in the area, and the output `dir`, gridplan's own, holds
/// this very sweep's records (a whole sweep's [`RESULTS_RECORDS`], a shard's
/// [`SHARD_FILE`]: the same config, version and shard). They are copied into the area's
/// stream, so no run runs again; a whole sweep's output is written again from them, and a
/// shard's directory, which already holds them, is left as it is (its provenance too: it
/// says when its runs ran). Finished
/// records of another config, version or shard there (a whole sweep's for a shard, a
/// shard's for a whole sweep) are refused as an interrupted sweep's are
/// ([`ResumeError`]: run without `--resume` to start over), and so are records that do not
/// read back, so that `--resume` never replaces the runs it was asked to keep; an output
/// without records resumes nothing, and every run runs.
fn resume_finished(
    area: &outdir::StreamArea,
    dir: &Path,
    shard: bool,
    (header, runs, experiment): (&StreamHeader, &ShardRuns, &Experiment),
) -> Result<Option<(u64, u64)>, RunnerError> {
    if fs::symlink_metadata(dir.join(outdir::MARKER)).is_err() {
        return Ok(None);
    }
    // The records of this kind of sweep, else the other kind's, whose header then names
    // the shard they hold.
    let names = match shard {
        true => [SHARD_FILE, RESULTS_RECORDS],
        false => [RESULTS_RECORDS, SHARD_FILE],
    };
    let Some(finished) = names
        .iter()
        .map(|name| dir.join(name))
        .find(|path| fs::symlink_metadata(path).is_ok())
    else {
        return Ok(None);
    };
    let Some((bytes, n)) = resume_point(&finished, header, runs, experiment)? else {
        return Ok(None);
    };
    let path = area.dir.join(RECORDS);
    let source = stream::open_regular(&finished).map_err(|e| RunnerError::io(&finished, e))?;
    let mut out = area.open_write(RECORDS, true)?;
    std::io::copy(&mut std::io::Read::take(source, bytes), &mut out)
        .and_then(|_| out.sync_all())
        .map_err(|e| RunnerError::io(&path, e))?;
    Ok(Some((bytes, n)))
}

/// The files whose stream headers a `--resume` into `output` checks against its sweep
/// (config, version, shard), those present of: the stream area's records.stream, its
/// earlier versions' records.jsonl and its ahead.stream, else (no records.stream there)
/// the first of the output's finished records (a shard's [`SHARD_FILE`], a whole sweep's
/// [`RESULTS_RECORDS`]) when the output carries gridplan's marker, as
/// `resume_finished` reads them. Nothing is created or locked.
pub fn resumed_streams(output: &Path) -> Vec<PathBuf> {
    let present = |path: &PathBuf| fs::symlink_metadata(path).is_ok();
    let mut files = Vec::new();
    if let Ok(area) = outdir::stream_area_path(output) {
        files.extend(
            [RECORDS, OLD_RECORDS, AHEAD]
                .iter()
                .map(|name| area.join(name))
                .filter(present),
        );
    }
    if !files.iter().any(|f| f.ends_with(RECORDS))
        && fs::symlink_metadata(output.join(outdir::MARKER)).is_ok()
    {
        files.extend(
            [SHARD_FILE, RESULTS_RECORDS]
                .iter()
                .map(|name| output.join(name))
                .find(present),
        );
    }
    files
}

/// Carries the first `n` runs of the JSON Lines resume stream `old` (an earlier version's)
/// over into the area's framed stream and removes `old`; returns the framed stream's bytes.
fn carry_over(area: &outdir::StreamArea, old: &Path, n: u64) -> Result<u64, RunnerError> {
    let path = area.dir.join(RECORDS);
    let file = stream::open_regular(old).map_err(|e| RunnerError::io(old, e))?;
    let mut out = std::io::BufWriter::new(area.open_write(RECORDS, true)?);
    let what = old.display().to_string();
    let bytes = crate::frames::write_framed(BufReader::new(file), &what, (&mut out, &path), n)?;
    out.flush()
        .and_then(|()| out.get_ref().sync_all())
        .map_err(|e| RunnerError::io(&path, e))?;
    fs::remove_file(old).map_err(|e| RunnerError::io(old, e))?;
    tracing::warn!(
        "--resume: {n} runs carried over from the JSON Lines stream {what} into the framed {RECORDS}"
    );
    Ok(bytes)
}

/// Runs the sweep's runs that its stream files (`opened`, in the stream area `area`) do
/// not hold, appending those [`stream::run_stream`] hands in order to records.stream and
/// those it hands ahead to ahead.stream as they come. Returns the records of a whole
/// sweep (a resumed one's read back first; `None` for a shard, a sweep of more than
/// [`HELD_RUNS`] runs, or one whose records passed [`SweepArgs::held_bytes`]) and how many
/// runs are recorded in the two files.
fn stream_runs(
    args: &SweepArgs,
    experiment: &Experiment,
    runs: &ShardRuns,
    opened: Opened,
    area: &Path,
) -> Result<(Option<Vec<RunRecord>>, u64), RunnerError> {
    let Opened {
        records: mut file,
        mut ahead,
        ahead_header,
        prefix,
        done,
        finished: _,
    } = opened;
    let (path, ahead_path) = (area.join(RECORDS), area.join(AHEAD));
    let n_done = prefix + done.len() as u64;
    if let Some(progress) = args.progress {
        progress.start(runs.len(), n_done);
    }
    let tick = |n: u64| {
        if let Some(progress) = args.progress {
            progress.set(n_done + n);
        }
    };
    let options = RunOptions {
        threads: args.threads,
        progress: Some(&tick),
        heap: args.heap,
        stop: args.stop,
    };
    // A whole sweep of at most HELD_RUNS runs keeps its records for the final outputs (a
    // resumed one reads back those recorded before) while they take at most
    // `held_bytes`; a shard or a larger sweep only streams them, and its outputs read them
    // back from the stream.
    let mut held = Held {
        records: (args.shard.is_none() && runs.len() <= HELD_RUNS).then(Vec::new),
        bytes: 0,
        cap: args.held_bytes,
    };
    if prefix > 0 && held.records.is_some() {
        read_records(&path, &mut held)?;
    }
    let mut frame = Vec::new();
    // A write that fails says how many runs the two files keep for --resume: those of
    // their complete frames, read back as --resume reads them.
    let total = runs.len();
    let kept = |source: RunnerError| RunnerError::StreamNotWritten {
        kept: count_recorded(&path, &ahead_path).map_or(0, |(_, n)| n),
        runs: total,
        area: area.to_path_buf(),
        source: Box::new(source),
    };
    let streamed = stream::run_stream(
        experiment,
        runs.iter().skip(prefix as usize),
        done,
        &options,
        |delivery| match delivery {
            Delivery::InOrder(batch) => {
                append_frames(&mut frame, &batch, (&mut file, &path)).map_err(kept)?;
                held.extend(batch.into_iter().map(|(_, record)| record));
                Ok(())
            }
            Delivery::Ahead(batch) => {
                append_frames(&mut frame, batch, (&mut ahead, &ahead_path)).map_err(kept)
            }
            // Every run of ahead.stream is in records.stream now.
            Delivery::CaughtUp => ahead
                .set_len(ahead_header)
                .and_then(|()| ahead.seek(SeekFrom::End(0)).map(drop))
                .map_err(|e| kept(RunnerError::io(&ahead_path, e))),
        },
    );
    if let Some(progress) = args.progress {
        progress.finish();
    }
    let streamed = streamed?;
    Ok((held.records, prefix + streamed.in_order + streamed.ahead))
}

/// The records a whole sweep holds for its final outputs, while they take at most `cap`
/// bytes ([`record_bytes`]).
struct Held {
    /// The records, in run order; `None` once they passed `cap` (or when none are held).
    records: Option<Vec<RunRecord>>,
    /// Their bytes.
    bytes: u64,
    /// The most bytes held.
    cap: u64,
}

impl Held {
    /// Holds `more` after the records held, or lets go of them all once they pass the cap.
    fn extend(&mut self, more: impl IntoIterator<Item = RunRecord>) {
        let Some(records) = &mut self.records else {
            return;
        };
        for record in more {
            self.bytes += record_bytes(&record);
            if self.bytes > self.cap {
                tracing::info!(
                    "the records take more than {} bytes: they are read from their stream \
                     file in passes",
                    self.cap
                );
                self.records = None;
                return;
            }
            records.push(record);
        }
    }
}

/// Appends `batch` to the stream `file` (at `path`) as frames of at most
/// [`crate::frames::FRAME_RUNS`] runs, encoded in `frame`, in one write.
fn append_frames(
    frame: &mut Vec<u8>,
    batch: &[(u64, RunRecord)],
    (file, path): (&mut File, &Path),
) -> Result<(), RunnerError> {
    frame.clear();
    for chunk in batch.chunks(crate::frames::FRAME_RUNS) {
        crate::frames::encode_batch(frame, chunk)?;
    }
    file.write_all(frame).map_err(|e| RunnerError::io(path, e))
}

/// Writes a whole shard's results directory `dir`: its framed stream `path` copied as the
/// shard.stream that `merge` reads, the expanded cells of the drawn runs it holds, its
/// provenance and wall time (provenance.json, which `merge` carries into the merged
/// results) and (when the config's `outputs` asks) its Parquet part, from the stream one
/// row group at a time. A raised `stop` ends it before `dir` is replaced.
fn finish_shard(
    experiment: &Experiment,
    path: &Path,
    dir: &Path,
    (shard, info): (Shard, &RunInfo),
    stop: Option<&AtomicBool>,
) -> Result<(), RunnerError> {
    let provenance = &info.provenance;
    let copy = StreamedFile {
        path: SHARD_FILE.into(),
        write: Box::new(|out| {
            let mut file = stream::open_regular(path).map_err(|e| RunnerError::io(path, e))?;
            std::io::copy(&mut file, out)
                .map(drop)
                .map_err(|e| RunnerError::io(path, e))
        }),
    };
    let cells = shard_expanded(experiment, path)?;
    check_stop(stop)?;
    let mut files = vec![OutputFile {
        path: PROVENANCE_FILE.into(),
        contents: serde_json::to_vec_pretty(info).map_err(RunnerError::Json)?,
    }];
    if !cells.is_empty() {
        files.push(OutputFile {
            path: EXPANDED_FILE.into(),
            contents: cells.to_jsonl()?,
        });
    }
    // Issue 29: the shard's Parquet part (src/columnar.rs).
    let header = crate::columnar::Header {
        experiment,
        provenance: Some(provenance),
        shard: Some(shard),
    };
    let parquet = crate::columnar::stream_part(header, path);
    let streamed: Vec<StreamedFile> = std::iter::once(copy)
        .chain(experiment.outputs.parquet.then_some(parquet))
        .collect();
    outdir::write_results_streamed(
        dir,
        &experiment.name,
        &files,
        &streamed,
        outdir::DEFAULT_LOCK_WAIT,
    )?;
    Ok(())
}

/// The expanded cells of the drawn runs a shard holds (its stream `path`), when the
/// config asks for them: repeat 0 of the drawn problems, recorded once more.
fn shard_expanded(experiment: &Experiment, path: &Path) -> Result<ExpandedCells, RunnerError> {
    if !experiment.figures_expanded || experiment.figures == config::FigureMode::None {
        return Ok(ExpandedCells::default());
    }
    let file = stream::open_regular(path).map_err(|e| RunnerError::io(path, e))?;
    let what = path.display().to_string();
    let (_, mut reader) = StreamReader::new(BufReader::new(file), &what)?;
    let mut firsts = Vec::new();
    while let Some((_, record)) = reader.next_run()? {
        if record.repeat == 0 {
            firsts.push(record);
        }
    }
    Ok(expanded::record_all(experiment, &firsts)?)
}

/// The provenance of the sweep `args` asks for, run with `threads` workers: its machine's
/// and its build's ([`SweepArgs::build`]).
fn collect_provenance(args: &SweepArgs, threads: usize) -> Provenance {
    Provenance {
        build: args.build.map(str::to_string),
        ..Provenance::collect(args.config, threads, args.machine)
    }
}

/// The worker count a sweep runs with: the argument, else the config's, else one per core.
fn worker_threads(argument: usize, configured: usize) -> usize {
    match (argument, configured) {
        (0, 0) => std::thread::available_parallelism().map_or(1, |n| n.get()),
        (0, c) => c,
        (a, _) => a,
    }
}

/// The stream at `path` opened for a resume, past its header, which must be `header`'s
/// (the same config, version and shard); `None` when there is no such file, or a kill cut
/// its header (nothing was recorded).
fn open_resumed(
    path: &Path,
    header: &StreamHeader,
    experiment: &Experiment,
) -> Result<Option<StreamReader<BufReader<fs::File>>>, RunnerError> {
    let file = match stream::open_regular(path) {
        Ok(file) => file,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(RunnerError::io(path, e)),
    };
    let what = path.display().to_string();
    let (found, reader) = match StreamReader::new(BufReader::new(file), &what) {
        Ok(opened) => opened,
        Err(_) if fs::metadata(path).map(|m| m.len()).unwrap_or(0) < 4096 => return Ok(None),
        Err(e) => return Err(e),
    };
    check_resumed(found, (header, experiment), &what)?;
    Ok(Some(reader))
}

/// Where an interrupted sweep's stream `path` ends: (bytes of complete lines, runs), or
/// `None` if there is no stream. Refuses a stream of another config or shard.
fn resume_point(
    path: &Path,
    header: &StreamHeader,
    runs: &ShardRuns,
    experiment: &Experiment,
) -> Result<Option<(u64, u64)>, RunnerError> {
    let Some(mut reader) = open_resumed(path, header, experiment)? else {
        return Ok(None);
    };
    let what = path.display().to_string();
    let list = RunList::new(experiment);
    let mut expected = runs.iter();
    let mut n = 0u64;
    while let Some((run, record)) = reader.next_run()? {
        if expected.next() != Some(run) {
            return Err(ResumeError::OutOfOrder { file: what, run }.into());
        }
        stream::check_record(experiment, &list, run, &record).map_err(|source| {
            ResumeError::Record {
                file: what.clone(),
                at: RecordAt::after(n, reader.is_framed()),
                source,
            }
        })?;
        n += 1;
    }
    if reader.was_cut() {
        // Said, not silent: the runs of the cut batch run again.
        tracing::warn!(
            "--resume: {what} ends in a batch cut short when the sweep was killed ({}); it is dropped and its runs run again",
            match reader.cut_bytes() {
                0 => "a cut last line".to_string(),
                n => format!("{n} bytes"),
            }
        );
    }
    Ok(Some((reader.complete_bytes(), n)))
}

/// Refuses the header `found` of a stream `what` that a resumed sweep of `experiment`
/// with `header` reads when it is another config's, version's or shard's; another config
/// is said with what changed, when `found` holds its inputs' hashes.
fn check_resumed(
    found: StreamHeader,
    (header, experiment): (&StreamHeader, &Experiment),
    what: &str,
) -> Result<(), RunnerError> {
    let file = what.to_string();
    if found.config_hash != header.config_hash || found.experiment != header.experiment {
        let changed = match &found.inputs {
            Some(inputs) => stream::changed_inputs(inputs, experiment),
            None => Vec::new(),
        };
        return Err(ResumeError::OtherConfig {
            changed,
            file,
            found_experiment: found.experiment,
            found_hash: found.config_hash,
            config: header.config.clone(),
            experiment: header.experiment.clone(),
            hash: header.config_hash.clone(),
        }
        .into());
    }
    if found.gridplan != header.gridplan {
        return Err(ResumeError::OtherVersion {
            file,
            found: found.gridplan,
            this: header.gridplan.clone(),
        }
        .into());
    }
    if (found.shard, found.shards) != (header.shard, header.shards) {
        return Err(ResumeError::OtherShard {
            file,
            found: (found.shard, found.shards),
            wanted: (header.shard, header.shards),
        }
        .into());
    }
    Ok(())
}

/// What an interrupted sweep's ahead.stream holds ([`read_ahead`]).
struct AheadRead {
    /// The bytes of its header line.
    header_bytes: u64,
    /// The bytes of its complete frames (header included).
    bytes: u64,
    /// Its runs past records.stream's, by index.
    done: BTreeMap<u64, RunRecord>,
}

/// The runs that an interrupted sweep's ahead.stream `path` holds past the first `prefix`
/// runs of the shard (those of records.stream; runs of ahead.stream that records.stream
/// holds too are passed over), or `None` when there is no such file (or a kill cut its
/// header). Refuses a stream of another config, version or shard, and a record that is
/// not its run of the shard.
fn read_ahead(
    path: &Path,
    (header, runs, experiment): (&StreamHeader, &ShardRuns, &Experiment),
    prefix: u64,
) -> Result<Option<AheadRead>, RunnerError> {
    let Some(mut reader) = open_resumed(path, header, experiment)? else {
        return Ok(None);
    };
    let what = path.display().to_string();
    let header_bytes = reader.complete_bytes();
    let list = RunList::new(experiment);
    let mut done = BTreeMap::new();
    let mut n = 0u64;
    while let Some((run, record)) = reader.next_run()? {
        let at = RecordAt::after(n, reader.is_framed());
        n += 1;
        stream::check_record(experiment, &list, run, &record).map_err(|source| {
            ResumeError::Record {
                file: what.clone(),
                at,
                source,
            }
        })?;
        match runs.position(run) {
            None => {
                let shard = (header.shard, header.shards);
                return Err(ResumeError::NotInShard {
                    file: what,
                    at,
                    run,
                    shard,
                }
                .into());
            }
            Some(position) if position < prefix => {}
            Some(_) => {
                done.entry(run).or_insert(record);
            }
        }
    }
    if reader.was_cut() {
        tracing::warn!(
            "--resume: {what} ends in a frame cut short when the sweep was killed ({} bytes); it is dropped and its runs run again",
            reader.cut_bytes()
        );
    }
    Ok(Some(AheadRead {
        header_bytes,
        bytes: reader.complete_bytes(),
        done,
    }))
}

/// The records of the stream file `path`, held by `held` (up to its cap).
fn read_records(path: &Path, held: &mut Held) -> Result<(), RunnerError> {
    let file = stream::open_regular(path).map_err(|e| RunnerError::io(path, e))?;
    let what = path.display().to_string();
    let (_, mut reader) = StreamReader::new(BufReader::new(file), &what)?;
    while let Some((_, record)) = reader.next_run()? {
        held.extend([record]);
        if held.records.is_none() {
            break;
        }
    }
    Ok(())
}

/// A results directory's own record of its runs, in run order, with the paths the
/// config keeps: a framed stream file ([`crate::frames`], as the resume stream) that
/// `report` reads back.
pub const RESULTS_RECORDS: &str = "records.stream";

/// The JSON Lines record file of the results directories of earlier versions (about 460
/// bytes a run): `report` still reads it when a directory has no [`RESULTS_RECORDS`].
pub const OLD_RESULTS_RECORDS: &str = "records.jsonl";

/// The expanded cells of the drawn runs, in a results directory or a shard's
/// (`figures_expanded`; [`ExpandedCells::to_jsonl`]).
pub const EXPANDED_FILE: &str = "expanded.jsonl";

/// The sweep's provenance and wall time in a results directory, for `report`.
pub const PROVENANCE_FILE: &str = "provenance.json";

/// `provenance.json`: what a results directory's report shows of where and how long it ran.
#[derive(serde::Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct RunInfo {
    provenance: Provenance,
    seconds: f64,
}

/// The provenance.json of the results directory `dir`.
fn read_run_info(dir: &Path) -> Result<RunInfo, RunnerError> {
    let info_path = dir.join(PROVENANCE_FILE);
    let bytes = read_regular(&info_path)?;
    Ok(
        serde_json::from_slice(&bytes).map_err(|source| ResultsError::Provenance {
            path: info_path.clone(),
            source,
        })?,
    )
}

/// Where and how the sweep of the results directory `dir` ran (its provenance.json).
pub fn read_provenance(dir: &Path) -> Result<Provenance, RunnerError> {
    Ok(read_run_info(dir)?.provenance)
}

/// A whole sweep's records for its final outputs: held in memory (at most [`HELD_RUNS`]),
/// or in a stream file on disk, read in passes.
enum Source {
    /// The records, in run order.
    Held(Vec<RunRecord>),
    /// A complete stream file of the records, in run order.
    Stream(StreamPasses),
}

/// Renders the outputs of a whole sweep's records (`source`, in run order): records the
/// expanded cells its figures draw (when the config asks and `expanded` is `None`: the
/// sweep's own step, the one that runs planners again), hands the results to `render`
/// for the report files, and writes those, runs.json, runs.csv, runs.parquet,
/// records.stream, expanded.jsonl and provenance.json to `dir`. `info` holds the
/// provenance and the sweep's wall time so far (OMPL's experiment time). A raised `stop`
/// ends it with [`RunnerError::Interrupted`] before `dir` is replaced. Returns the held
/// records (paths left out; none for a stream).
fn finish(
    render: &dyn Render,
    experiment: &Experiment,
    source: Source,
    expanded: Option<ExpandedCells>,
    dir: &Path,
    info: &RunInfo,
    stop: Option<&AtomicBool>,
) -> Result<(Reproduction, Vec<RunRecord>), RunnerError> {
    let provenance = &info.provenance;
    let (mut records, stream) = match source {
        Source::Held(records) => (records, None),
        Source::Stream(passes) => (Vec::new(), Some(passes)),
    };
    let held: &[RunRecord] = &records;
    let plain: &dyn RecordPasses = match &stream {
        Some(stream) => stream,
        None => &held,
    };
    // Every pass of the report and of the tables ends early once `stop` is raised.
    let stoppable = stop.map(|stop| StoppablePasses::new(plain, stop));
    let passes: &dyn RecordPasses = match &stoppable {
        Some(stoppable) => stoppable,
        None => plain,
    };
    let expanded = match expanded {
        Some(cells) => cells,
        None => record_expanded(experiment, &records, stream.is_some(), passes)?,
    };
    check_stop(stop)?;
    let results = Results {
        experiment,
        records: &records,
        passes,
        expanded: &expanded,
        provenance,
        seconds: info.seconds,
        stop,
    };
    let (mut all, reproduction) = render.render(&results)?;
    check_stop(stop)?;
    if !expanded.is_empty() {
        all.push(OutputFile {
            path: EXPANDED_FILE.into(),
            contents: expanded.to_jsonl()?,
        });
    }
    all.push(OutputFile {
        path: PROVENANCE_FILE.into(),
        contents: serde_json::to_vec_pretty(info).map_err(RunnerError::Json)?,
    });
    let header = StreamHeader::new(experiment, Shard::ALL, passes.len());
    let outputs = experiment.outputs.for_runs(passes.len());
    let parquet = match &stream {
        None => crate::columnar::records_part(experiment, provenance, &records),
        Some(stream) => crate::columnar::stream_part(
            crate::columnar::Header {
                experiment,
                provenance: Some(provenance),
                shard: None,
            },
            stream.path(),
        ),
    };
    let tables: Vec<StreamedFile> = [
        paths_from_passes(experiment, stream.is_some(), passes)?,
        (outputs.json).then(|| StreamedFile {
            path: "runs.json".into(),
            write: Box::new(move |out| {
                results::write_runs_json_passes(out, experiment, passes, Some(provenance))
            }),
        }),
        (outputs.csv).then(|| StreamedFile {
            path: "runs.csv".into(),
            write: Box::new(move |out| results::write_runs_csv_passes(out, passes)),
        }),
        // Issue 29: the Parquet dataset's one part (src/columnar.rs).
        (outputs.parquet).then_some(parquet),
        Some(StreamedFile {
            path: RESULTS_RECORDS.into(),
            write: Box::new(move |out| write_stream(out, &header, passes)),
        }),
    ]
    .into_iter()
    .flatten()
    .collect();
    outdir::write_results_streamed(
        dir,
        &experiment.name,
        &all,
        &tables,
        outdir::DEFAULT_LOCK_WAIT,
    )?;
    drop(tables);
    for record in &mut records {
        record.path = None;
    }
    Ok((reproduction, records))
}

/// For a sweep whose records are not held (`streamed`), `paths = "figures"`'s paths.jsonl
/// (repeat 0 of every run that found a path) written from a pass, so its paths are never
/// held either; the report writes it from held records otherwise. A first pass says
/// whether there is any such path: without one there is no file, as from held records.
fn paths_from_passes<'a>(
    experiment: &Experiment,
    streamed: bool,
    passes: &'a dyn RecordPasses,
) -> Result<Option<StreamedFile<'a>>, RunnerError> {
    let mut any_path = false;
    if streamed && experiment.paths == config::PathsMode::Figures {
        passes.pass(&mut |r| any_path |= r.repeat == 0 && r.path.is_some())?;
    }
    Ok(any_path.then(|| StreamedFile {
        path: PATHS_FILE.into(),
        write: Box::new(move |out| {
            let mut failed = None;
            passes.pass(&mut |r| {
                if failed.is_none() && r.repeat == 0 {
                    failed = results::write_path_line(out, r).err();
                }
            })?;
            failed.map_or(Ok(()), Err)
        }),
    }))
}

/// The expanded cells of the runs the figures draw, recorded again ([`expanded::record_all`]):
/// from the held `records`, or (`streamed`) from repeat 0 of every run, read in one pass.
fn record_expanded(
    experiment: &Experiment,
    records: &[RunRecord],
    streamed: bool,
    passes: &dyn RecordPasses,
) -> Result<ExpandedCells, RunnerError> {
    if !streamed {
        return Ok(expanded::record_all(experiment, records)?);
    }
    let mut firsts = Vec::new();
    if experiment.figures_expanded && experiment.figures != config::FigureMode::None {
        passes.pass(&mut |r| {
            if r.repeat == 0 {
                let mut r = r.clone();
                r.path = None;
                firsts.push(r);
            }
        })?;
    }
    Ok(expanded::record_all(experiment, &firsts)?)
}

/// Writes `records` (a whole sweep's, in run order) as a framed stream file with
/// `header` (its format set to framed), a frame of [`crate::frames::FRAME_RUNS`] runs at
/// a time.
fn write_stream(
    out: &mut dyn std::io::Write,
    header: &StreamHeader,
    records: &dyn RecordPasses,
) -> Result<(), RunnerError> {
    let io = |e: std::io::Error| RunnerError::io(Path::new(RESULTS_RECORDS), e);
    let header = StreamHeader {
        format: crate::frames::FRAMED_FORMAT,
        ..header.clone()
    };
    out.write_all(&header.to_line()?).map_err(io)?;
    let mut batch: Vec<(u64, RunRecord)> = Vec::with_capacity(crate::frames::FRAME_RUNS);
    let mut frame = Vec::new();
    let mut run = 0u64;
    let mut failed = None;
    let mut flush = |batch: &mut Vec<(u64, RunRecord)>, out: &mut dyn std::io::Write| {
        frame.clear();
        let written = crate::frames::encode_batch(&mut frame, batch)
            .and_then(|()| out.write_all(&frame).map_err(io));
        batch.clear();
        written
    };
    records.pass(&mut |record| {
        if failed.is_some() {
            return;
        }
        batch.push((run, record.clone()));
        run += 1;
        if batch.len() == crate::frames::FRAME_RUNS {
            failed = flush(&mut batch, out).err();
        }
    })?;
    if let Some(e) = failed {
        return Err(e);
    }
    if !batch.is_empty() {
        flush(&mut batch, out)?;
    }
    Ok(())
}

/// The records file of the results directory `dir` (records.stream, or an earlier
/// version's records.jsonl) and its path, opened; an error that says what `dir` is
/// instead when it is not a gridplan results directory (none, a file, no marker, a shard, a
/// replanning experiment's results). Reads only: whether `dir` may be replaced is the
/// caller's question ([`outdir::check`]). `command` (`report`, `compare`) names the reader in
/// the errors.
pub fn open_results(dir: &Path, command: &'static str) -> Result<(PathBuf, File), RunnerError> {
    // Only gridplan's own results directory: its marker, as `experiment` requires. What
    // else the path is gets its own message here, not an `experiment` output's advice.
    let not_results = |what| ResultsError::NotResults {
        command,
        dir: dir.to_path_buf(),
        what,
    };
    match fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return Err(not_results("does not exist").into())
        }
        Ok(meta) if !meta.is_dir() => return Err(not_results("is not a directory").into()),
        _ => {}
    }
    if fs::symlink_metadata(dir.join(outdir::MARKER)).is_err() {
        return Err(not_results("has no results marker").into());
    }
    let mut path = dir.join(RESULTS_RECORDS);
    if fs::symlink_metadata(&path).is_err()
        && fs::symlink_metadata(dir.join(OLD_RESULTS_RECORDS)).is_ok()
    {
        // An earlier version's results directory.
        path = dir.join(OLD_RESULTS_RECORDS);
    }
    let file = stream::open_regular(&path).map_err(|source| {
        // planner-replan's per-replan records: its results share the runner's marker.
        const REPLANS_FILE: &str = "replans.jsonl";
        if fs::symlink_metadata(dir.join(SHARD_FILE)).is_ok_and(|m| m.is_file()) {
            ResultsError::ShardNotResults {
                command,
                dir: dir.to_path_buf(),
                file: SHARD_FILE,
            }
        } else if fs::symlink_metadata(dir.join(REPLANS_FILE)).is_ok_and(|m| m.is_file()) {
            ResultsError::ReplanResults {
                command,
                dir: dir.to_path_buf(),
                file: REPLANS_FILE,
            }
        } else {
            ResultsError::NoRecords {
                dir: dir.to_path_buf(),
                file: RESULTS_RECORDS,
                source,
            }
        }
    })?;
    Ok((path, file))
}

/// Re-renders the results directory `dir` in place from what it holds (records.stream,
/// expanded.jsonl, provenance.json) and its config (`config`, default the one its records
/// name; it must resolve to the config hash they were run with): summary.md, figures,
/// charts, report.html, OMPL logs, and the tables again. No planner runs. The directory is
/// replaced under the same rules as `experiment` writes it ([`outdir`]: only a gridplan
/// results directory, under its lock, atomically).
pub fn report(
    dir: &Path,
    config: Option<&Path>,
    render: &dyn Render,
) -> Result<Report, RunnerError> {
    let started = Instant::now();
    let (path, file) = open_results(dir, "report")?;
    // Replaced as `experiment` replaces an output.
    outdir::check(dir)?;
    outdir::Marker::read(dir).map_err(|e| RunnerError::during("report", e.into()))?;
    let what = path.display().to_string();
    let damaged = |e| crate::readback::damaged("report", dir, e);
    let (header, reader) = StreamReader::new(BufReader::new(file), &what).map_err(damaged)?;
    let experiment = load_checked(&header, config, render, "report")?;
    let source = read_results_records(&experiment, &header, reader, &path)?;
    let info = read_run_info(dir).map_err(damaged)?;
    let expanded = read_expanded(dir, &experiment).map_err(damaged)?;
    let n_runs = header.total_runs as usize;
    let (reproduction, _) = finish(
        render,
        &experiment,
        source,
        Some(expanded),
        dir,
        &info,
        None,
    )?;
    Ok(Report {
        n_runs,
        output: dir.to_path_buf(),
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
        interrupted: None,
        records: Vec::new(),
        left_out: None,
    })
}

/// The records of a results directory's records.stream (or an earlier version's records.jsonl: `path`; its `header` read, the rest
/// in `reader`), every one checked against `experiment`'s run list
/// ([`stream::check_record`]) and all of the sweep's runs there: held when there are at
/// most [`HELD_RUNS`] taking at most [`HELD_BYTES`], else the file itself, read in passes. Records of another gridplan
/// version are kept as that version computed them, with a warning naming both.
fn read_results_records(
    experiment: &Experiment,
    header: &StreamHeader,
    mut reader: StreamReader<BufReader<File>>,
    path: &Path,
) -> Result<Source, RunnerError> {
    let what = path.display().to_string();
    let hold = header.total_runs <= HELD_RUNS;
    let this = env!("CARGO_PKG_VERSION");
    if header.gridplan.as_deref() != Some(this) {
        tracing::warn!(
            "{what} was written by gridplan {}, this is gridplan {this}: the records are kept \
             as that version computed them",
            header.gridplan.as_deref().unwrap_or("of unknown version")
        );
    }
    let list = RunList::new(experiment);
    let mut held = Held {
        records: hold.then(Vec::new),
        bytes: 0,
        cap: HELD_BYTES,
    };
    let mut n = 0u64;
    let dir = path.parent().unwrap_or(Path::new("."));
    while let Some((run, record)) = reader
        .next_run()
        .map_err(|e| crate::readback::damaged("report", dir, e))?
    {
        stream::check_record(experiment, &list, run, &record).map_err(|source| {
            ResultsError::Record {
                command: "report",
                file: what.clone(),
                at: RecordAt::after(n, reader.is_framed()),
                source,
            }
        })?;
        n += 1;
        if n <= header.total_runs {
            held.extend([record]);
        }
    }
    if n != header.total_runs || reader.was_cut() {
        return Err(ResultsError::Short {
            command: "report",
            file: what,
            held: n,
            runs: header.total_runs,
        }
        .into());
    }
    Ok(match held.records {
        Some(records) => Source::Held(records),
        None => Source::Stream(StreamPasses::new(path, n)),
    })
}

/// The whole of the regular file `path` (never a FIFO or a device: [`stream::open_regular`]).
fn read_regular(path: &Path) -> Result<Vec<u8>, RunnerError> {
    let mut bytes = Vec::new();
    stream::open_regular(path)
        .and_then(|mut file| std::io::Read::read_to_end(&mut file, &mut bytes))
        .map_err(|e| RunnerError::io(path, e))?;
    Ok(bytes)
}

/// The config `header`'s records were run with (`config` overrides its path), checked by
/// `render` and against the records' config hash; `what` prefixes errors.
fn load_checked(
    header: &StreamHeader,
    config: Option<&Path>,
    render: &dyn Render,
    what: &'static str,
) -> Result<Experiment, RunnerError> {
    let config_path = config.map_or_else(|| PathBuf::from(&header.config), Path::to_path_buf);
    let experiment = config::load(&config_path).map_err(|e| RunnerError::during(what, e.into()))?;
    render
        .check(&experiment)
        .map_err(|e| RunnerError::during(what, e.into()))?;
    let hash = stream::config_hash(&experiment);
    if hash != header.config_hash {
        return Err(ResultsError::ConfigChanged {
            command: what,
            config: config_path,
            hash,
            ran: header.config_hash.clone(),
        }
        .into());
    }
    Ok(experiment)
}

/// The expanded cells recorded in `dir` (none when the file is absent and the config
/// asks for none).
fn read_expanded(dir: &Path, experiment: &Experiment) -> Result<ExpandedCells, RunnerError> {
    let path = dir.join(EXPANDED_FILE);
    let mut bytes = Vec::new();
    match stream::open_regular(&path) {
        Ok(mut file) => std::io::Read::read_to_end(&mut file, &mut bytes)
            .map_err(|e| RunnerError::io(&path, e))?,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            let drawn = experiment.figures_expanded
                && experiment.figures != config::FigureMode::None
                && !experiment.planners.is_empty();
            if drawn && experiment.maps.iter().any(|m| !m.problems.is_empty()) {
                // The sweep writes the file whenever it recorded a cell; a config that
                // asks for them and draws some runs without any file is not this sweep's.
                tracing::warn!(
                    "{}: no {EXPANDED_FILE}; figures are drawn without expanded cells",
                    dir.display()
                );
            }
            return Ok(ExpandedCells::default());
        }
        Err(e) => return Err(RunnerError::io(&path, e)),
    };
    let text = String::from_utf8(bytes).map_err(|source| ResultsError::NotText {
        path: path.clone(),
        source,
    })?;
    ExpandedCells::from_jsonl(&text, &path.display().to_string())
}

/// Merges the shard directories `dirs` into the one sweep's results in `output` (default:
/// the config's). `config` overrides the config file the shards name; `machine` gives the
/// commit and host of the provenance for the config file merged (the caller learns them:
/// [`SweepArgs::machine`]).
pub fn merge(
    dirs: &[PathBuf],
    output: Option<&Path>,
    config: Option<&Path>,
    render: &dyn Render,
    machine: &dyn Fn(&Path) -> Machine,
) -> Result<Report, RunnerError> {
    let started = Instant::now();
    let mut shards = open_shards(dirs)?;
    let first = shards[0].1.clone();
    check_shard_set(&shards, &first, dirs)?;
    check_versions(&shards)?;
    let experiment = load_checked(&first, config, render, "merge")?;
    let config_path = config.map_or_else(|| PathBuf::from(&first.config), Path::to_path_buf);
    let mut expanded = ExpandedCells::default();
    for (dir, _, _) in &shards {
        expanded.extend(read_expanded(dir, &experiment)?);
    }
    let dir = output.map_or_else(|| experiment.output.clone(), Path::to_path_buf);
    outdir::check_not_input(&dir, dirs)?;
    outdir::check(&dir)?;
    let n_runs = first.total_runs as usize;
    // At most HELD_RUNS runs are merged into memory; more into a framed stream in the
    // output's stream area, which the outputs then read in passes. Either way the merge
    // holds one record per shard (and a frame of the merged stream).
    let mut area = None;
    let source = if first.total_runs <= HELD_RUNS {
        let mut records = Vec::with_capacity(n_runs);
        merge_records(&mut shards, &first, &experiment, &mut |_, record| {
            records.push(record);
            Ok(())
        })?;
        Source::Held(records)
    } else {
        let stream_area = outdir::stream_area(&dir, outdir::DEFAULT_LOCK_WAIT)?;
        let path = stream_area.dir.join(MERGED);
        let had_stream = fs::symlink_metadata(stream_area.dir.join(RECORDS)).is_ok();
        let file = stream_area.open_write(MERGED, true)?;
        area = Some((stream_area, had_stream));
        let io = |e: std::io::Error| RunnerError::io(&path, e);
        let mut out = std::io::BufWriter::with_capacity(1 << 20, file);
        let header = StreamHeader {
            format: crate::frames::FRAMED_FORMAT,
            ..StreamHeader::new(&experiment, Shard::ALL, first.total_runs)
        };
        out.write_all(&header.to_line()?).map_err(io)?;
        let mut batch = Vec::with_capacity(crate::frames::FRAME_RUNS);
        merge_records(&mut shards, &first, &experiment, &mut |run, record| {
            batch.push((run, record));
            if batch.len() == crate::frames::FRAME_RUNS {
                out.write_all(&crate::frames::encode_frames(&batch)?)
                    .map_err(io)?;
                batch.clear();
            }
            Ok(())
        })?;
        out.write_all(&crate::frames::encode_frames(&batch)?)
            .and_then(|()| out.flush())
            .map_err(io)?;
        Source::Stream(StreamPasses::new(&path, first.total_runs))
    };
    let info = merged_run_info(&shards).unwrap_or_else(|| RunInfo {
        provenance: Provenance::collect(
            &config_path,
            worker_threads(0, experiment.threads),
            &machine(&config_path),
        ),
        seconds: started.elapsed().as_secs_f64(),
    });
    let finished = finish(
        render,
        &experiment,
        source,
        Some(expanded),
        &dir,
        &info,
        None,
    );
    if let Some((area, had_stream)) = area {
        // The merged stream goes; so does the area, unless it also holds an interrupted
        // sweep's stream (kept for its --resume).
        let removed = match had_stream {
            true => fs::remove_file(area.dir.join(MERGED)),
            false => area.remove(),
        };
        if let Err(e) = removed {
            tracing::warn!("merge: {} could not be removed: {e}", area.dir.display());
        }
    }
    let (reproduction, _) = finished?;
    Ok(Report {
        n_runs,
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
        interrupted: None,
        records: Vec::new(),
        left_out: None,
    })
}

/// The provenance of a sweep merged from `shards`, from what each shard recorded (its
/// provenance.json): the first shard's, with the most threads any shard ran with (and
/// each shard's count when they differ), and as seconds the sum of the shards' wall
/// times. `None` when a shard has none (an earlier version's): the merge then records
/// its own, as before, and says so.
fn merged_run_info(shards: &[OpenShard]) -> Option<RunInfo> {
    let mut infos = Vec::with_capacity(shards.len());
    for (dir, _, _) in shards {
        match read_run_info(dir) {
            Ok(info) => infos.push(info),
            Err(e) => {
                tracing::warn!(
                    "merge: {} has no readable provenance ({e}); the merged provenance is the merge's own",
                    dir.display()
                );
                return None;
            }
        }
    }
    let mut infos = infos.into_iter();
    let first = infos.next()?;
    let mut threads = vec![first.provenance.threads];
    let mut seconds = first.seconds;
    for info in infos {
        threads.push(info.provenance.threads);
        seconds += info.seconds;
    }
    let mut provenance = first.provenance;
    provenance.threads = threads.iter().copied().max().unwrap_or(provenance.threads);
    provenance.shard_threads = threads.iter().any(|&t| t != threads[0]).then_some(threads);
    Some(RunInfo {
        provenance,
        seconds,
    })
}

/// A shard directory with its stream's header and a reader after it.
type OpenShard = (PathBuf, StreamHeader, StreamReader<BufReader<File>>);

/// The streams of the shard directories `dirs` (at least one), opened.
fn open_shards(dirs: &[PathBuf]) -> Result<Vec<OpenShard>, RunnerError> {
    if dirs.is_empty() {
        return Err(crate::usage::UsageError::NoShards.into());
    }
    let mut shards = Vec::new();
    for dir in dirs {
        let mut path = dir.join(SHARD_FILE);
        if fs::symlink_metadata(&path).is_err()
            && fs::symlink_metadata(dir.join(OLD_SHARD_FILE)).is_ok()
        {
            // An earlier version's shard.
            path = dir.join(OLD_SHARD_FILE);
        }
        let file = stream::open_regular(&path).map_err(|source| {
            if source.kind() == std::io::ErrorKind::NotFound {
                if let Some(unfinished) = unfinished_shard(dir) {
                    return unfinished;
                }
            }
            ResultsError::NotAShard {
                dir: dir.clone(),
                file: path
                    .file_name()
                    .map_or(SHARD_FILE.into(), |n| n.to_string_lossy().into_owned()),
                source,
            }
        })?;
        let (header, reader) =
            StreamReader::new(BufReader::new(file), &path.display().to_string())?;
        shards.push((dir.clone(), header, reader));
    }
    Ok(shards)
}

/// Why the shard directory `dir` given to merge holds no shard stream, when it is not
/// there at all: an interrupted run of a shard recorded in its stream area beside it
/// ([`ResultsError::ShardUnfinished`], with the command that finishes it), or none
/// ([`ResultsError::ShardMissing`]). `None` when `dir` exists.
fn unfinished_shard(dir: &Path) -> Option<ResultsError> {
    if fs::symlink_metadata(dir).is_ok() {
        return None;
    }
    let recorded = outdir::stream_area_path(dir).ok().and_then(|area| {
        let stream = area.join(RECORDS);
        // Read only when it is a file of its own: a link there is not followed.
        if !fs::symlink_metadata(&stream).is_ok_and(|m| m.is_file()) {
            return None;
        }
        let file = stream::open_regular(&stream).ok()?;
        let (header, _) =
            StreamReader::new(BufReader::new(file), &stream.display().to_string()).ok()?;
        Some((stream, header))
    });
    Some(match recorded {
        Some((stream, header)) => ResultsError::ShardUnfinished {
            dir: dir.to_path_buf(),
            stream,
            shard: header.shard,
            shards: header.shards,
            config: header.config,
        },
        None => ResultsError::ShardMissing {
            dir: dir.to_path_buf(),
        },
    })
}

/// Checks that `shards` are of one sweep (`first`'s) and hold each of its shards once.
fn check_shard_set(
    shards: &[OpenShard],
    first: &StreamHeader,
    dirs: &[PathBuf],
) -> Result<(), RunnerError> {
    for (dir, header, _) in &shards[1..] {
        if header.config_hash != first.config_hash
            || header.shards != first.shards
            || header.experiment != first.experiment
        {
            let id = |h: &StreamHeader| SweepId {
                experiment: h.experiment.clone(),
                config_hash: h.config_hash.clone(),
                shards: h.shards,
            };
            return Err(ResultsError::DifferentSweeps {
                first: shards[0].0.clone(),
                first_sweep: id(first),
                other: dir.clone(),
                other_sweep: id(header),
            }
            .into());
        }
    }
    let mut missing = Vec::new();
    for k in 1..=first.shards {
        let holders: Vec<&PathBuf> = shards
            .iter()
            .filter(|(_, h, _)| h.shard == k)
            .map(|(d, _, _)| d)
            .collect();
        match holders.len() {
            0 => missing.push(k),
            1 => {}
            _ => {
                return Err(ResultsError::ShardTwice {
                    shard: k,
                    shards: first.shards,
                    dirs: holders.into_iter().cloned().collect(),
                }
                .into())
            }
        }
    }
    if !missing.is_empty() {
        return Err(ResultsError::ShardsMissing {
            missing,
            shards: first.shards,
            experiment: first.experiment.clone(),
            given: dirs.to_vec(),
        }
        .into());
    }
    Ok(())
}

/// The shards' records in run order, each handed to `sink` with its run index: a k-way
/// merge by run index that holds one record per shard, every index of the sweep
/// (`first.total_runs`) exactly once, each record checked against `experiment`'s run list
/// ([`stream::check_record`]).
fn merge_records(
    shards: &mut [OpenShard],
    first: &StreamHeader,
    experiment: &Experiment,
    sink: &mut dyn FnMut(u64, RunRecord) -> Result<(), RunnerError>,
) -> Result<(), RunnerError> {
    // Each record is checked against the config's run list.
    let list = RunList::new(experiment);
    // Per shard: the records read before its head record.
    let mut read: Vec<u64> = vec![0; shards.len()];
    let mut heads: Vec<Option<(u64, RunRecord)>> = Vec::with_capacity(shards.len());
    for (_, _, reader) in shards.iter_mut() {
        heads.push(reader.next_run()?);
    }
    for expected in 0..first.total_runs {
        let Some(i) = heads
            .iter()
            .position(|h| h.as_ref().is_some_and(|(run, _)| *run == expected))
        else {
            return Err(ResultsError::RunMissing {
                run: expected,
                runs: first.total_runs,
                held: shards
                    .iter()
                    .map(|(d, h, _)| (d.clone(), h.shard, h.shards))
                    .collect(),
            }
            .into());
        };
        let next = shards[i].2.next_run()?;
        if let Some((run, record)) = std::mem::replace(&mut heads[i], next) {
            stream::check_record(experiment, &list, run, &record).map_err(|source| {
                let framed = shards[i].2.is_framed();
                let file = if framed { SHARD_FILE } else { OLD_SHARD_FILE };
                ResultsError::Record {
                    command: "merge",
                    file: shards[i].0.join(file).display().to_string(),
                    at: RecordAt::after(read[i], framed),
                    source,
                }
            })?;
            read[i] += 1;
            sink(run, record)?;
        }
    }
    if let Some(i) = heads.iter().position(Option::is_some) {
        return Err(ResultsError::PastEnd {
            dir: shards[i].0.clone(),
        }
        .into());
    }
    Ok(())
}

/// The gridplan version of each shard: its results marker's (`.gridplan-results`) and its
/// stream header's. Shards written by different versions are refused, naming both (their
/// planners may count differently, so the merged tables would mix two programs); shards
/// of one version other than this gridplan's are merged with a warning naming both.
fn check_versions(shards: &[OpenShard]) -> Result<(), RunnerError> {
    let mut seen: Vec<(String, String)> = Vec::new();
    for (dir, header, _) in shards {
        let marker = outdir::Marker::read(dir).ok().map(|m| m.gridplan);
        for version in [marker, header.gridplan.clone()].into_iter().flatten() {
            match seen.iter().find(|(v, _)| *v != version) {
                Some((other, other_dir)) => {
                    return Err(ResultsError::Versions {
                        first_dir: other_dir.clone(),
                        first: other.clone(),
                        dir: dir.clone(),
                        version,
                    }
                    .into())
                }
                None => seen.push((version, dir.display().to_string())),
            }
        }
    }
    let this = env!("CARGO_PKG_VERSION");
    if let Some((version, dir)) = seen.iter().find(|(v, _)| v != this) {
        tracing::warn!(
            "merging shards written by gridplan {version} ({dir}) with gridplan {this}: the \
             records are kept as that version computed them"
        );
    }
    Ok(())
}
