//! Why records read back do not make the sweep a command expects: `--resume`'s stream of
//! another config, version or shard ([`ResumeError`]), and a results directory or shards
//! that `report` or `merge` cannot use ([`ResultsError`]). Typed, so that a caller can tell
//! the cases apart; each message says what to do.

use std::path::PathBuf;

use crate::stream::RecordMismatch;

/// Where a record sits in its file: a JSON Lines stream's line (the header is line 1) or a
/// framed stream's record (from 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RecordAt {
    /// A 1-based line.
    Line(u64),
    /// A 1-based record.
    Record(u64),
}

impl RecordAt {
    /// The place of the record after `n` earlier ones: `framed` streams count records,
    /// JSON Lines streams lines (after the header line).
    pub fn after(n: u64, framed: bool) -> RecordAt {
        match framed {
            true => RecordAt::Record(n + 1),
            false => RecordAt::Line(n + 2),
        }
    }
}

impl std::fmt::Display for RecordAt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            RecordAt::Line(n) => write!(f, "line {n}"),
            RecordAt::Record(n) => write!(f, "record {n}"),
        }
    }
}

/// The identity of a sweep as a stream header states it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SweepId {
    /// The experiment's name.
    pub experiment: String,
    /// The config's hash.
    pub config_hash: String,
    /// Its shard count.
    pub shards: u64,
}

impl std::fmt::Display for SweepId {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "experiment {:?}, config hash {}, {} shards",
            self.experiment, self.config_hash, self.shards
        )
    }
}

/// `--resume` refused the stream it found.
#[derive(Debug, thiserror::Error)]
pub enum ResumeError {
    /// The stream was recorded by another config.
    #[error(
        "--resume: {file} was recorded by a different config (experiment {found_experiment:?}, config hash {found_hash}); \
         {config} resolves to experiment {experiment:?}, hash {hash}{}. Run without --resume to start over.",
        match .changed.is_empty() {
            true => String::new(),
            false => format!(": {}", .changed.join("; ")),
        }
    )]
    OtherConfig {
        /// The stream.
        file: String,
        /// The experiment its header names.
        found_experiment: String,
        /// The config hash its header names.
        found_hash: String,
        /// The config file given.
        config: String,
        /// The experiment the config names.
        experiment: String,
        /// The config's hash.
        hash: String,
        /// What changed, when the stream's header tells ([`crate::stream::changed_inputs`]):
        /// "map file maps/a.map's content changed since the interrupted sweep".
        changed: Vec<String>,
    },
    /// The stream was written by another gridplan version.
    #[error(
        "--resume: {file} was written by gridplan {}, this is gridplan {}; records of two \
         versions are not mixed in one sweep. Run without --resume to start over.",
        .found.as_deref().unwrap_or("of unknown version (its header names none)"),
        .this.as_deref().unwrap_or("?")
    )]
    OtherVersion {
        /// The stream.
        file: String,
        /// The version its header names.
        found: Option<String>,
        /// This gridplan's version.
        this: Option<String>,
    },
    /// The stream holds another shard.
    #[error("--resume: {file} holds shard {}/{}, not {}/{}. Run without --resume to start over.", .found.0, .found.1, .wanted.0, .wanted.1)]
    OtherShard {
        /// The stream.
        file: String,
        /// The shard and count it holds.
        found: (u64, u64),
        /// The shard and count asked for.
        wanted: (u64, u64),
    },
    /// A run out of the run list's order.
    #[error("--resume: {file}: run {run} is out of order; run without --resume")]
    OutOfOrder {
        /// The stream.
        file: String,
        /// The run index read.
        run: u64,
    },
    /// A run that the shard resumed does not hold.
    #[error("--resume: {file} {at}: run {run} is not a run of shard {}/{}; run without --resume", .shard.0, .shard.1)]
    NotInShard {
        /// The stream.
        file: String,
        /// Where the record is.
        at: RecordAt,
        /// The run index read.
        run: u64,
        /// The shard and count resumed.
        shard: (u64, u64),
    },
    /// A stream that cannot be read back (a frame failing its checksum with frames after
    /// it, a header that is not one): its runs cannot be kept.
    #[error(
        "--resume: {source}; its recorded runs cannot be kept: run without --resume to start \
         over (they are discarded and run again), or remove `{}` yourself",
        .area.display()
    )]
    Damaged {
        /// The sweep's stream area.
        area: PathBuf,
        /// What could not be read.
        source: Box<crate::RunnerError>,
    },
    /// A record that is not its run of the config.
    #[error("--resume: {file} {at}: {source}; run without --resume")]
    Record {
        /// The stream.
        file: String,
        /// Where the record is.
        at: RecordAt,
        /// What differs.
        source: RecordMismatch,
    },
}

/// A results directory that `report` cannot read back, or shard outputs that `merge`
/// cannot combine into one sweep.
#[derive(Debug, thiserror::Error)]
pub enum ResultsError {
    /// A results directory without its records.
    #[error("report: {} has no {file} ({source}); rerun the experiment with this version to re-render it", .dir.display())]
    NoRecords {
        /// The directory.
        dir: PathBuf,
        /// The records file's name.
        file: &'static str,
        /// Why it could not be opened.
        source: std::io::Error,
    },
    /// A path given to `command` (`report`, `compare`) that is not a results directory:
    /// missing, not a directory, or a directory without gridplan's marker.
    #[error("{command}: `{}` {what}; {command} reads a results directory that `gridplan experiment` wrote (it holds `{marker}`)", .dir.display(), marker = crate::outdir::MARKER)]
    NotResults {
        /// The command that read it.
        command: &'static str,
        /// The path given.
        dir: PathBuf,
        /// What it is, e.g. "does not exist".
        what: &'static str,
    },
    /// A replanning experiment's results given to `command`, which reads the runner's.
    #[error("{command}: {} holds a replanning experiment's results ({file}), which {command} does not read; run its config again with `gridplan experiment`", .dir.display())]
    ReplanResults {
        /// The command that read it.
        command: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The replanning experiment's file found there.
        file: &'static str,
    },
    /// A shard's output given to `command`, which reads a whole sweep's results.
    #[error("{command}: {} holds one shard of a sweep ({file}), not its results; merge the shards (`gridplan merge`) and give {command} the merged directory", .dir.display())]
    ShardNotResults {
        /// The command that read it.
        command: &'static str,
        /// The directory.
        dir: PathBuf,
        /// The shard's records file's name.
        file: &'static str,
    },
    /// A provenance file that does not read.
    #[error("report: {}: {source}", .path.display())]
    Provenance {
        /// The file.
        path: PathBuf,
        /// Why.
        source: serde_json::Error,
    },
    /// A record that is not its run of the config (`command`: `report` or `merge`).
    #[error("{command}: {file} {at}: {source}")]
    Record {
        /// The command.
        command: &'static str,
        /// The records file.
        file: String,
        /// Where the record is.
        at: RecordAt,
        /// What differs.
        source: RecordMismatch,
    },
    /// A results directory's records that end before the sweep does (fewer runs than its
    /// header's count, or a cut last record), found by `command` (`report`, `compare`).
    #[error("{command}: {file} holds {held} of {runs} runs")]
    Short {
        /// The command that read it.
        command: &'static str,
        /// The records file.
        file: String,
        /// Runs read.
        held: u64,
        /// Runs of the sweep.
        runs: u64,
    },
    /// Results that `command` (`report`, `compare`) cannot read whole: a records stream or
    /// a provenance.json that is damaged, or a file of them that cannot be read.
    #[error("{command}: {} does not hold complete results: {source}", .dir.display())]
    Damaged {
        /// The command that read it.
        command: &'static str,
        /// The results directory.
        dir: PathBuf,
        /// What was wrong.
        source: Box<crate::RunnerError>,
    },
    /// The config now hashes otherwise than when the records were made.
    #[error(
        "{command}: {} now resolves to config hash {hash}, but the {runs} were run with {ran}; \
         rerun the {runs} or pass the config they ran with (--config)",
        .config.display(),
        runs = if *.command == "merge" { "shards" } else { "runs" }
    )]
    ConfigChanged {
        /// The command (`report` or `merge`).
        command: &'static str,
        /// The config file.
        config: PathBuf,
        /// Its hash now.
        hash: String,
        /// The hash the records were made with.
        ran: String,
    },
    /// An `expanded.jsonl` that is not UTF-8.
    #[error("{}: {source}", .path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::string::FromUtf8Error,
    },
    /// A directory without a shard's stream.
    #[error("merge: {} is not a shard's output ({file}: {source})", .dir.display())]
    NotAShard {
        /// The directory.
        dir: PathBuf,
        /// The stream file's name.
        file: String,
        /// Why it could not be opened.
        source: std::io::Error,
    },
    /// A shard directory given to merge that does not exist, while the shard's stream area
    /// beside it holds an interrupted run of it.
    #[error(
        "merge: shard {shard} ({}) is not finished: an interrupted run of it is recorded in \
         {}; finish it with `gridplan experiment {config} --shard {shard}/{shards} --output {} \
         --resume`",
        .dir.display(), .stream.display(), .dir.display()
    )]
    ShardUnfinished {
        /// The shard's directory.
        dir: PathBuf,
        /// The interrupted run's stream.
        stream: PathBuf,
        /// The shard, from the stream's header.
        shard: u64,
        /// The shard count.
        shards: u64,
        /// The config file the stream's header names.
        config: String,
    },
    /// A shard directory given to merge that does not exist (and no run of it is recorded
    /// beside it).
    #[error(
        "merge: shard directory {} does not exist and no run of it is recorded beside it: run \
         that shard first (`gridplan experiment CONFIG --shard K/N --output {}`), or give the \
         directory it was written to",
        .dir.display(), .dir.display()
    )]
    ShardMissing {
        /// The directory given.
        dir: PathBuf,
    },
    /// Shards of two sweeps.
    #[error("merge: {} ({first_sweep}) and {} ({other_sweep}) are shards of different sweeps", .first.display(), .other.display())]
    DifferentSweeps {
        /// The first shard's directory.
        first: PathBuf,
        /// Its sweep.
        first_sweep: SweepId,
        /// The other shard's directory.
        other: PathBuf,
        /// Its sweep.
        other_sweep: SweepId,
    },
    /// One shard given in two directories.
    #[error("merge: shard {shard}/{shards} given twice: {}", paths(.dirs))]
    ShardTwice {
        /// The shard.
        shard: u64,
        /// The shard count.
        shards: u64,
        /// The directories holding it.
        dirs: Vec<PathBuf>,
    },
    /// Shards not given.
    #[error(
        "merge: shards {} of experiment {experiment:?} are missing (given: {})",
        .missing.iter().map(|k| format!("{k}/{shards}")).collect::<Vec<_>>().join(", "),
        paths(.given)
    )]
    ShardsMissing {
        /// The shards missing.
        missing: Vec<u64>,
        /// The shard count.
        shards: u64,
        /// The experiment.
        experiment: String,
        /// The directories given.
        given: Vec<PathBuf>,
    },
    /// A run that no shard holds.
    #[error(
        "merge: run {run} of {runs} is in no shard (a shard is incomplete: {})",
        .held.iter().map(|(d, k, n)| format!("{} holds shard {k}/{n}", d.display())).collect::<Vec<_>>().join(", ")
    )]
    RunMissing {
        /// The run.
        run: u64,
        /// Runs of the sweep.
        runs: u64,
        /// Each directory with its shard and count.
        held: Vec<(PathBuf, u64, u64)>,
    },
    /// A shard with runs after the sweep's last.
    #[error("merge: {} holds runs past the sweep's end", .dir.display())]
    PastEnd {
        /// The shard's directory.
        dir: PathBuf,
    },
    /// Shards of two gridplan versions.
    #[error(
        "merge: {first_dir} was written by gridplan {first} and {} by gridplan {version}; \
         rerun the shards with one gridplan version",
        .dir.display()
    )]
    Versions {
        /// The directory seen first.
        first_dir: String,
        /// Its version.
        first: String,
        /// The other directory.
        dir: PathBuf,
        /// Its version.
        version: String,
    },
    /// A report's passes over the records gave one quantile set other values.
    #[error("exact quantiles: set {set} held other values in another pass (the records changed while the report read them)")]
    QuantilesChanged {
        /// The set.
        set: usize,
    },
}

impl ResultsError {
    /// Whether this says that a path given to `report` or `compare` does not hold a whole
    /// sweep's results (not results at all, a shard's, a replanning experiment's, without
    /// records, or damaged: cut, unreadable, or a record that is not its run): such results are refused as `experiment` refuses an output
    /// that is not its own ([`crate::ErrorClass::Output`]).
    pub fn not_complete_results(&self) -> bool {
        matches!(
            self,
            ResultsError::NotResults { .. }
                | ResultsError::ShardNotResults { .. }
                | ResultsError::ReplanResults { .. }
                | ResultsError::NoRecords { .. }
                | ResultsError::Short { .. }
                | ResultsError::Provenance { .. }
                | ResultsError::NotText { .. }
                | ResultsError::Damaged { .. }
                | ResultsError::Record {
                    command: "report",
                    ..
                }
        )
    }
}

/// `error`, met by `command` (`report`, `compare`) while reading the results directory
/// `dir`: an error that is not already of a class of its own (a damaged or unreadable
/// stream, an unreadable file) becomes [`ResultsError::Damaged`], so that every reading
/// error of results is classed as results that are not complete.
pub fn damaged(
    command: &'static str,
    dir: &std::path::Path,
    error: crate::RunnerError,
) -> crate::RunnerError {
    match error.class() {
        crate::ErrorClass::Other => ResultsError::Damaged {
            command,
            dir: dir.to_path_buf(),
            source: Box::new(error),
        }
        .into(),
        _ => error,
    }
}

/// The paths, comma-separated.
fn paths(dirs: &[PathBuf]) -> String {
    dirs.iter()
        .map(|d| d.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
