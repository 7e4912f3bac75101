//! gridplan's experiment runner as a library: the `cargo xtask` and `gridplan` command
//! lines and the Python package all call it.
//!
//! # Design
//! The boundary between the runner and the planners is typed. When a config is read,
//! planner-registry turns each label's parameter table into a [`Factory`], once: the
//! table is deserialized into the planner crate's own config and validated there, errors
//! name the parameter's key, and the planner declares what it is
//! ([`planner_api::PlannerSpecs`]: seeded or not, the rule its paths obey) and whether it
//! plans start-goal queries or covers ([`Task`]). After that the runner never reads a
//! planner's parameters and names no planner; the registry is the one crate that does.
//! The runner draws nothing either: a sweep hands its results to a report step
//! ([`sweep::Render`], planner-report's) and writes the files it returns.
//!
//! - [`config`]: experiment configs (TOML) with positioned errors; map sets.
//! - [`schema`]: the JSON Schema of experiment configs.
//! - [`run`]: the lazy run list and the parallel sweep; planners built once per worker
//!   and label, reused across runs; [`run::run_one`], the one function that runs a run.
//! - [`expanded`]: the expanded cells of the runs the figures draw, recorded at run time.
//! - [`record`] and [`index`]: the results model and lookups into it; [`passes`]: passes
//!   over a whole sweep's records, in memory or read back from disk.
//! - [`output`]: runs.csv, runs.json and paths.jsonl as bytes; [`columnar`]: the same
//!   table as Apache Parquet (`runs.parquet/`).
//! - [`plan`]: one run of one planner, for `plan`.
//! - [`provenance`]: version, commit, date, host, CPU and config hash of a sweep.
//! - [`stream`] and [`shard`]: streamed sweeps (records in run order as the runs finish,
//!   and those finished ahead of a slow run aside, in streams that survive a kill),
//!   resumable and merged; deterministic cost-balanced shards of a run list for job arrays.
//! - [`sweep`]: an experiment on disk: the streamed, resumable, sharded sweep, the merge
//!   of shards, and the final outputs; [`outdir`] writes a results directory safely (its
//!   marker, lock and atomic swap); [`slurm`] writes job arrays (the command line submits
//!   them).
//! - [`alloc`]: a counting global allocator and its peak-heap hook, for binaries.
//!
//! The library installs no global allocator and draws no progress bar: progress is a
//! callback ([`sweep::Progress`], [`run::RunOptions`]) and peak-heap measurement a hook
//! ([`run::HeapMeter`]; [`alloc::Counting`] for a binary to install). Files are written
//! only by [`sweep`] (through [`outdir`]) and [`slurm`].
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod alloc;
pub mod columnar;
pub mod config;
pub mod expanded;
pub mod frames;
pub mod index;
pub mod outdir;
pub mod output;
pub mod passes;
pub mod pattern;
pub mod plan;
pub mod provenance;
pub mod readback;
pub mod record;
pub mod run;
pub mod schema;
pub mod shard;
pub mod slurm;
pub mod stream;
pub mod sweep;
pub mod usage;

use std::path::PathBuf;

pub use config::{ConfigError, Experiment};
use planner_registry as registry;
pub use planner_registry::{Built, Factory, Task};
pub use record::{RunRecord, RunStatus};
pub use run::{run_all, RunOptions};

/// Everything the runner can fail with.
#[derive(Debug, thiserror::Error)]
pub enum RunnerError {
    /// A config file is malformed or invalid (with its position).
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A map or scenario file could not be read (with its position).
    #[error(transparent)]
    Map(#[from] planner_maps::MapError),
    /// A planner's parameters are invalid.
    #[error("planner `{0}`: {1}")]
    Param(String, planner_api::ParamError),
    /// A planner could not be built for a run.
    #[error("planner `{0}`: {1}")]
    Build(String, planner_api::ParamError),
    /// An unknown registry name.
    #[error("unknown planner `{name}`, expected one of {}", registry::names().join(", "))]
    UnknownPlanner {
        /// The name given.
        name: String,
    },
    /// A label that the config does not define.
    #[error("{}: no planner labelled `{label}` (labels: {})", config.display(), labels.join(", "))]
    UnknownLabel {
        /// The config file.
        config: PathBuf,
        /// The label given.
        label: String,
        /// The labels it defines.
        labels: Vec<String>,
    },
    /// A start or goal that cannot be planned.
    #[error("{}: {error}", map.display())]
    Problem {
        /// The map file.
        map: PathBuf,
        /// What is wrong with the start or goal.
        error: planner_api::ProblemError,
    },
    /// A start or goal given in the map frame (`plan --start-world`) outside the map.
    #[error("{}: --{which}-world {},{} lies outside the map, which spans {}", map.display(), planner_maps::metres(point.0), planner_maps::metres(point.1), frame.extent())]
    OutsideMap {
        /// The map file.
        map: PathBuf,
        /// `start` or `goal`.
        which: &'static str,
        /// The point given.
        point: (f64, f64),
        /// The map's frame.
        frame: planner_maps::MapFrame,
    },
    /// A start or goal that cannot be planned on a `.csv` map that looks written in the
    /// other convention: the hint says so, and how to read it the other way.
    #[error("{}: {error}; {hint} (--obstacle {})", map.display(), hint.convention.other().obstacle_value())]
    InvertedProblem {
        /// The map file.
        map: PathBuf,
        /// What is wrong with the start or goal.
        error: planner_api::ProblemError,
        /// Why the map looks inverted.
        hint: planner_maps::InversionHint,
    },
    /// Command-line arguments that do not fit together.
    #[error(transparent)]
    Usage(#[from] usage::UsageError),
    /// Too many worker threads asked for.
    #[error("{0} worker threads asked for; at most {max} (0 = one per core)", max = config::MAX_THREADS)]
    Threads(usize),
    /// The thread pool could not start.
    #[error("cannot start the worker threads: {0}")]
    Pool(rayon::ThreadPoolBuildError),
    /// A run index past the end of the run list (a bug).
    #[error("run index {0} is past the end of the run list")]
    RunIndex(u64),
    /// A record stream (a resumed sweep's, a shard's) is unreadable or does not fit.
    #[error(transparent)]
    Stream(#[from] stream::StreamError),
    /// A frame of a stream could not be written.
    #[error("a batch of {runs} runs: {source}")]
    Frame {
        /// Runs in the batch.
        runs: usize,
        /// Why.
        source: frames::FrameError,
    },
    /// The runs do not fit the Parquet dataset's columns (a bug).
    #[error(transparent)]
    Columns(#[from] columnar::ColumnsError),
    /// Serializing results failed.
    #[error("cannot serialize the results: {0}")]
    Json(serde_json::Error),
    /// Writing or reading the Parquet dataset runs.parquet/ failed (issue 29).
    #[error("runs.parquet: {0}")]
    Parquet(#[from] ::parquet::errors::ParquetError),
    /// A results directory that may not be written (not gridplan's own, held by another
    /// sweep's lock, ...).
    #[error(transparent)]
    Output(#[from] outdir::OutdirError),
    /// A run recording expanded cells did not repeat its timed run (a determinism bug).
    #[error(transparent)]
    Expanded(#[from] expanded::ExpandedError),
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// `--resume` refused the stream it found (another config or shard, runs out of order).
    #[error(transparent)]
    Resume(Box<readback::ResumeError>),
    /// Shards that do not make one sweep (`merge`), or a results directory that `report`
    /// cannot read back.
    #[error(transparent)]
    Results(Box<readback::ResultsError>),
    /// The sweep's stop flag was raised (Ctrl-C, SIGTERM) while its results were being
    /// rendered or written ([`sweep::check_stop`]): nothing was written, and
    /// [`sweep::experiment`] reports the sweep as interrupted.
    #[error("interrupted while writing the results; nothing was written")]
    Interrupted,
    /// The results of a sweep (or shard) whose runs are all recorded could not be
    /// written: the runs stay in its resume stream, and `--resume` writes the results
    /// without running any again. Classed as `source`.
    #[error(
        "{source}; all {runs} runs are recorded in {}: free space or fix the cause, then rerun \
         with --resume to write the results without running any again",
        stream.display()
    )]
    NotWritten {
        /// The runs of the sweep or shard.
        runs: u64,
        /// Its resume stream.
        stream: PathBuf,
        /// Why the results were not written.
        source: Box<RunnerError>,
    },
    /// A sweep's resume stream could not be appended to (a full disk): the sweep stops,
    /// and the runs recorded before stay for `--resume`.
    #[error(
        "{source}; {kept} of {runs} runs are recorded in {} and kept: free space or fix the \
         cause, then rerun with --resume to continue",
        area.display()
    )]
    StreamNotWritten {
        /// Runs recorded (complete frames in the stream files).
        kept: u64,
        /// The runs of the sweep or shard.
        runs: u64,
        /// The stream area.
        area: PathBuf,
        /// Why the stream could not be written.
        source: Box<RunnerError>,
    },
    /// An error met while doing `context` (`merge`, `report`), said with that prefix.
    #[error("{context}: {source}")]
    During {
        /// What was being done.
        context: &'static str,
        /// The error.
        source: Box<RunnerError>,
    },
}

impl From<readback::ResumeError> for RunnerError {
    fn from(error: readback::ResumeError) -> RunnerError {
        RunnerError::Resume(Box::new(error))
    }
}

impl From<readback::ResultsError> for RunnerError {
    fn from(error: readback::ResultsError) -> RunnerError {
        RunnerError::Results(Box::new(error))
    }
}

impl RunnerError {
    /// A file error at `path`.
    pub fn io(path: &std::path::Path, source: std::io::Error) -> RunnerError {
        RunnerError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    /// `error`, met while doing `context`.
    pub fn during(context: &'static str, error: RunnerError) -> RunnerError {
        RunnerError::During {
            context,
            source: Box::new(error),
        }
    }

    /// The error itself, without the [`RunnerError::During`] contexts around it.
    pub fn innermost(&self) -> &RunnerError {
        match self {
            RunnerError::During { source, .. } | RunnerError::NotWritten { source, .. } => {
                source.innermost()
            }
            other => other,
        }
    }

    /// What kind of failure this is, for the front ends: the command line's exit status
    /// and the Python package's exception class both follow it, so they cannot disagree.
    /// The match names every variant, so a new one must be classed.
    ///
    /// ```
    /// use planner_runner::{ErrorClass, RunnerError};
    /// let error = RunnerError::during("merge", RunnerError::Threads(9999));
    /// assert_eq!(error.class(), ErrorClass::Usage);
    /// ```
    pub fn class(&self) -> ErrorClass {
        match self {
            RunnerError::Config(_) => ErrorClass::Config,
            RunnerError::Map(_) => ErrorClass::Map,
            RunnerError::Problem { .. }
            | RunnerError::InvertedProblem { .. }
            | RunnerError::OutsideMap { .. } => ErrorClass::Problem,
            RunnerError::Param(..)
            | RunnerError::Build(..)
            | RunnerError::UnknownPlanner { .. }
            | RunnerError::UnknownLabel { .. } => ErrorClass::Parameter,
            // A damaged stream is one that cannot be read, not a resume asked amiss.
            RunnerError::Resume(error)
                if matches!(**error, readback::ResumeError::Damaged { .. }) =>
            {
                ErrorClass::Other
            }
            RunnerError::Usage(_) | RunnerError::Threads(_) | RunnerError::Resume(_) => {
                ErrorClass::Usage
            }
            // A path that does not hold a whole sweep's results (not results, a shard's,
            // damaged) is refused as `experiment` refuses an output that is not its own.
            // A full disk is a failure to write, not an output gridplan may not write.
            RunnerError::Output(outdir::OutdirError::Io { source, .. }) if full_disk(source) => {
                ErrorClass::Other
            }
            RunnerError::Output(_) => ErrorClass::Output,
            RunnerError::Results(error) if error.not_complete_results() => ErrorClass::Output,
            RunnerError::Expanded(_) => ErrorClass::Determinism,
            RunnerError::Pool(_)
            | RunnerError::RunIndex(_)
            | RunnerError::Stream(_)
            | RunnerError::Frame { .. }
            | RunnerError::Columns(_)
            | RunnerError::Json(_)
            | RunnerError::Io { .. }
            | RunnerError::Parquet(_)
            | RunnerError::Interrupted
            | RunnerError::Results(_) => ErrorClass::Other,
            RunnerError::During { source, .. } | RunnerError::NotWritten { source, .. } => {
                source.class()
            }
            RunnerError::StreamNotWritten { .. } => ErrorClass::Other,
        }
    }
}

/// Whether `error` says the disk is full (no space left, or the quota reached).
fn full_disk(error: &std::io::Error) -> bool {
    matches!(
        error.kind(),
        std::io::ErrorKind::StorageFull | std::io::ErrorKind::QuotaExceeded
    )
}

/// The kinds of [`RunnerError`] ([`RunnerError::class`]): the command line's exit status
/// (README.md) and the Python package's exception class of each.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorClass {
    /// A config that cannot be read or is invalid (exit 3, `ConfigError`).
    Config,
    /// A map or scenario file that cannot be read (exit 4, `MapError`).
    Map,
    /// A start or goal that cannot be planned (exit 4, `ProblemError`).
    Problem,
    /// An unknown planner or label, or a parameter it refuses (exit 2, `ParameterError`).
    Parameter,
    /// Arguments that do not fit: threads, a resume of another config (exit 2,
    /// `ValueError`).
    Usage,
    /// An output directory gridplan may not write, or one another run holds; a directory
    /// given to `report` or `compare` that does not hold a whole sweep's complete results
    /// (exit 5, `OutputError`). A full disk is not this but [`ErrorClass::Other`].
    Output,
    /// A run that did not repeat itself when recorded again (exit 1, `DeterminismError`).
    Determinism,
    /// Anything else: a file that cannot be read or written (a full disk included, in the
    /// output directory or the resume stream), a stream or shard set that cannot be read
    /// (exit 1, `GridplanError`).
    Other,
}
