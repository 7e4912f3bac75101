//! Slurm job arrays for a sweep: `slurm CONFIG --shards N` writes two sbatch scripts, a
//! job array of N tasks (task K runs `experiment CONFIG --shard K/N`) and a merge job.
//! Submitting them (`--submit`: the merge with `--dependency=afterok:<array>` and
//! `--kill-on-invalid-dep=yes`, so a failed task cancels the merge instead of leaving it
//! pending forever) spawns `sbatch`, which the command line does ([`Jobs::array_args`] and
//! [`Jobs::merge_args`] give the arguments); this module writes files only.
//!
//! For an output directory `DIR` (default: the config's; `DIR/`, `DIR/.` and `./DIR` are
//! `DIR`, while the root or a path ending in `..` is refused before anything is written),
//! the scripts, the shards' results (`shard-K`) and the tasks' logs go to `DIR-slurm/`,
//! beside it; the merge writes `DIR`
//! (`merge --shards-in DIR-slurm --shards N`, so its command line has the same length
//! for any N). It merges `shard-1` to `shard-N` only: the `shard-K` directories an
//! earlier `slurm` of the same output with more shards left (K above N) are left out,
//! and left alone (a task of that array may still be writing one; nothing is removed).
//! N is at most the sweep's run count and [`Shard::MAX_COUNT`].
//! The scripts call this very binary and the config by absolute path, so they run from
//! any directory on a cluster whose nodes share the file system.
//!
//! Every task runs `experiment --resume`: a task that Slurm requeues (a node failure, a
//! preemption, `scontrol requeue`) gets SIGTERM, which stops its sweep with the finished
//! runs recorded, and keeps them when it starts again; so does a task of the same command
//! submitted again after a task failed, timed out or was cancelled, and a task whose shard
//! had already finished runs nothing again and leaves its `shard-K` as it is (provenance
//! included). The shard directories and their stream areas in `DIR-slurm/` that a task
//! would refuse to resume (another config's records, another gridplan version's, another
//! shard count's: [`crate::sweep::resumed_streams`]) are refused before anything is
//! written ([`SlurmError::OtherSweep`]), naming the directories to move away to start
//! over; nothing is removed. Both scripts' logs are appended to (`--open-mode=append`), and
//! each start writes a line with the date, `SLURM_JOB_ID`, `SLURM_ARRAY_TASK_ID` and
//! `SLURM_RESTART_COUNT` first, so a log keeps every start of its task.
//!
//! `--submit` records the ids of the jobs it submitted in `DIR-slurm/jobs`
//! ([`record_submitted`]); the command line asks `squeue` about them before it submits
//! again to the same output and refuses while one is still queued or running
//! ([`SlurmError::StillQueued`]), since two arrays would run the same shards at once.
//!
//! Every value that reaches a script is data, never code. One function, [`quote`], quotes
//! it: in single quotes, a `'` written as `'\''`. Bash reads that as the value in the
//! command lines, and sbatch's own parser of `#SBATCH` lines (quotes and backslash escapes,
//! `#` outside quotes starting a comment) reads it as the same value in the directives.
//! Values that no quoting keeps on their `#SBATCH` line, or that the two parsers read
//! differently, are refused with an error naming the key they came from (`--partition`,
//! `--account`, `--qos`, `--time`, `--mem`, `--output` or the config's `output`): a newline, carriage return or NUL
//! anywhere, and a backslash in a directive value (sbatch drops it, bash would not). In
//! the `--output` directives a `%` of the directory is written `%%`, so Slurm's file name
//! patterns (`%j`, `%a`) apply only to the log's own name. Before writing anything,
//! `slurm` checks the results directory under the rules of `experiment`
//! ([`crate::outdir::check`]), so a directory that `merge` would refuse is refused now,
//! and writes into `DIR-slurm/` only when it is new, empty, or carries [`SLURM_MARKER`]
//! (which it writes first): a directory of that name that is not gridplan's is refused
//! ([`OutdirError::ForeignWorkDir`]) and left alone.

use std::path::{Component, Path, PathBuf};

use crate::config::{self, ConfigError};
use crate::outdir::OutdirError;
use crate::run::RunList;
use crate::shard::Shard;
use crate::stream::{StreamHeader, StreamReader};

/// What `slurm` is asked to do.
#[derive(Debug, Clone, Default)]
pub struct SlurmArgs {
    /// The experiment config.
    pub config: PathBuf,
    /// Array tasks (shards).
    pub shards: u64,
    /// The merged results directory (default: the config's `output`).
    pub output: Option<PathBuf>,
    /// `--partition`.
    pub partition: Option<String>,
    /// `--time`.
    pub time: Option<String>,
    /// `--account` (the allocation charged; many clusters require one).
    pub account: Option<String>,
    /// `--qos` (quality of service).
    pub qos: Option<String>,
    /// `--mem` (memory per node, e.g. `4G`).
    pub mem: Option<String>,
    /// `--cpus-per-task` (and the tasks' worker threads).
    pub cpus_per_task: Option<u32>,
    /// The binary the scripts run (`gridplan`): the caller's own executable (the command
    /// line passes `std::env::current_exe`; the runner reads no process state). A relative
    /// path is taken from [`SlurmArgs::current_dir`].
    pub binary: PathBuf,
    /// The directory a relative `config`, `output` or `binary` is taken from: the
    /// caller's current directory (the scripts name every path absolutely).
    pub current_dir: PathBuf,
}

/// What `slurm` wrote.
#[derive(Debug, Clone)]
pub struct Jobs {
    /// `DIR-slurm/`, where the scripts, shards, logs and [`JOBS_FILE`] are.
    pub work: PathBuf,
    /// The array job's script.
    pub array_script: PathBuf,
    /// The merge job's script.
    pub merge_script: PathBuf,
}

impl Jobs {
    /// The arguments of `sbatch --parsable` that submit the array job.
    pub fn array_args(&self) -> Vec<String> {
        vec![self.array_script.display().to_string()]
    }

    /// The arguments of `sbatch --parsable` that submit the merge job after the array job
    /// `array_id` (cancelled if a task fails).
    pub fn merge_args(&self, array_id: &str) -> Vec<String> {
        vec![
            format!("--dependency=afterok:{array_id}"),
            "--kill-on-invalid-dep=yes".to_string(),
            self.merge_script.display().to_string(),
        ]
    }
}

/// Why the scripts could not be written.
#[derive(Debug, thiserror::Error)]
pub enum SlurmError {
    /// A shard count out of range (`--shards`).
    #[error("--shards {shards}: {reason}")]
    Shards {
        /// The count asked for.
        shards: u64,
        /// Why it cannot be.
        reason: String,
    },
    /// A value that cannot be written safely into a script.
    #[error(
        "{key}: {value:?} holds {what}, which cannot be written safely into a Slurm script; \
         choose a value without it"
    )]
    Unsafe {
        /// The option or key it came from.
        key: String,
        /// The value.
        value: String,
        /// The character refused, in words.
        what: &'static str,
    },
    /// An option's value that sbatch would refuse (an empty value, a time or memory size
    /// not in Slurm's forms, no CPUs), caught before the scripts are written.
    #[error("{key} {value:?}: {expected}")]
    Value {
        /// The option.
        key: &'static str,
        /// The value.
        value: String,
        /// What the option takes.
        expected: String,
    },
    /// Records in `DIR-slurm/` that the array task of their shard, which always resumes,
    /// would refuse: another config's, another gridplan version's, or another shard
    /// count's (an earlier `slurm` of this output). Refused before the scripts are written;
    /// nothing is removed.
    #[error(
        "{}: {found}. Task {shard} of the array resumes the runs recorded for its shard \
         there (a resubmitted array continues where it stopped), so it would refuse them: \
         give another --output, or, once no task of an earlier array runs, move {} {}away \
         to start shard {shard} over",
        file.display(),
        dir.display(),
        area.as_ref().map_or(String::new(), |a| format!("and {} ", a.display()))
    )]
    OtherSweep {
        /// The shard (its task).
        shard: u64,
        /// The stream file read.
        file: PathBuf,
        /// The shard's directory, `DIR-slurm/shard-K`.
        dir: PathBuf,
        /// Its stream area, if there is one.
        area: Option<PathBuf>,
        /// What it holds, in words.
        found: String,
    },
    /// Jobs that an earlier `--submit` of the same output recorded ([`JOBS_FILE`]) are
    /// still queued or running: a second array would run the same shards at once.
    #[error(
        "jobs {} of an earlier submission of this output (listed in {}) are still queued or \
         running; scancel them or wait until they end, then submit again",
        jobs.join(", "),
        work.join(JOBS_FILE).display()
    )]
    StillQueued {
        /// `DIR-slurm/`.
        work: PathBuf,
        /// The jobs still queued or running.
        jobs: Vec<String>,
    },
    /// A results directory that names no directory of its own: the root, or a path
    /// ending in `..` (whose `DIR-slurm` would not be beside it).
    #[error("{key}: {} does not name a results directory by its own name (it is the root or ends in `..`); give the directory itself, e.g. `results/name`", path.display())]
    OutputName {
        /// The option or key it came from.
        key: String,
        /// The path given.
        path: PathBuf,
    },
    /// A path that is not UTF-8 (a script is text).
    #[error("{key}: {} is not valid UTF-8", path.display())]
    NotUtf8 {
        /// The option or key it came from.
        key: String,
        /// The path.
        path: PathBuf,
    },
    /// The config cannot be read or is invalid.
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// The results directory may not be written.
    #[error(transparent)]
    Output(#[from] OutdirError),
    /// A file or directory could not be read or written.
    #[error("{what}: {source}")]
    Io {
        /// The file, or what the caller looked up (the current directory, its binary's
        /// path).
        what: String,
        /// What went wrong.
        source: std::io::Error,
    },
}

/// An I/O error about `what`.
fn io(what: impl std::fmt::Display) -> impl FnOnce(std::io::Error) -> SlurmError {
    let what = what.to_string();
    move |source| SlurmError::Io { what, source }
}

/// `path`, taken from `current_dir` when relative.
fn absolute(current_dir: &Path, path: &Path) -> PathBuf {
    if path.is_absolute() {
        path.to_path_buf()
    } else {
        current_dir.join(path)
    }
}

/// The results directory `output` (from the option or key `key`) as an absolute path
/// without `.` components or trailing separators, so that `DIR-slurm` is its sibling:
/// `o2/`, `o2/.` and `./o2` are `o2`, and `.` the current directory. A path that ends in
/// `..`, or the root, is refused ([`SlurmError::OutputName`]): its last name is not the
/// directory's (`..` is not resolved by hand, as a link would resolve it otherwise).
fn results_dir(current_dir: &Path, output: &Path, key: &str) -> Result<PathBuf, SlurmError> {
    let path: PathBuf = absolute(current_dir, output)
        .components()
        .filter(|c| !matches!(c, Component::CurDir))
        .collect();
    match path.components().next_back() {
        Some(Component::Normal(_)) => Ok(path),
        _ => Err(SlurmError::OutputName {
            key: key.to_string(),
            path: output.to_path_buf(),
        }),
    }
}

/// Single-quotes `text` for bash and for sbatch's `#SBATCH` parser: `'...'` with each `'`
/// written `'\''`. Check a value with [`script_value`] first.
///
/// ```
/// assert_eq!(planner_runner::slurm::quote("it's"), "'it'\\''s'");
/// ```
pub fn quote(text: &str) -> String {
    format!("'{}'", text.replace('\'', "'\\''"))
}

/// `value` (from the option or key `key`) checked for a script and quoted by [`quote`]:
/// refused if it holds a newline, carriage return or NUL (which end a line whatever the
/// quoting), or, in an `#SBATCH` directive (`directive`), a backslash (which sbatch's
/// parser drops and bash keeps).
pub fn script_value(key: &str, value: &str, directive: bool) -> Result<String, SlurmError> {
    let bad = value
        .chars()
        .find(|&c| matches!(c, '\n' | '\r' | '\0') || (directive && c == '\\'));
    match bad {
        None => Ok(quote(value)),
        Some(c) => Err(SlurmError::Unsafe {
            key: key.to_string(),
            value: value.to_string(),
            what: match c {
                '\n' => "a newline",
                '\r' => "a carriage return",
                '\0' => "a NUL character",
                _ => "a backslash (sbatch reads it differently from bash)",
            },
        }),
    }
}

/// A path as text for a script, checked by [`script_value`].
fn path_value(key: &str, path: &Path, directive: bool) -> Result<String, SlurmError> {
    let text = path.to_str().ok_or_else(|| SlurmError::NotUtf8 {
        key: key.to_string(),
        path: path.to_path_buf(),
    })?;
    script_value(key, text, directive)
}

/// The `#SBATCH` option lines (`--partition`, `--account`, `--qos`, `--time`, `--mem`,
/// `--cpus-per-task`) of both scripts.
fn options(args: &SlurmArgs) -> Result<String, SlurmError> {
    let mut options = String::new();
    let given = [
        ("--partition", &args.partition),
        ("--account", &args.account),
        ("--qos", &args.qos),
        ("--time", &args.time),
        ("--mem", &args.mem),
    ];
    for (option, value) in given {
        if let Some(value) = value {
            check_option(option, value)?;
            let value = script_value(option, value, true)?;
            options.push_str(&format!("#SBATCH {option}={value}\n"));
        }
    }
    if let Some(c) = args.cpus_per_task {
        let expected = if c == 0 {
            Some("at least 1 (sbatch refuses 0)".to_string())
        } else if usize::try_from(c).map_or(true, |c| c > config::MAX_THREADS) {
            // The tasks run `--threads C`, which the sweep refuses above its limit.
            Some(format!(
                "at most {} (it is also the tasks' worker threads, at most {} in a sweep)",
                config::MAX_THREADS,
                config::MAX_THREADS
            ))
        } else {
            None
        };
        if let Some(expected) = expected {
            return Err(SlurmError::Value {
                key: "--cpus-per-task",
                value: c.to_string(),
                expected,
            });
        }
        options.push_str(&format!("#SBATCH --cpus-per-task={c}\n"));
    }
    Ok(options)
}

/// Refuses what sbatch would refuse at submission: an empty value, a `--time` not in one
/// of sbatch's forms (`minutes`, `minutes:seconds`, `hours:minutes:seconds`, `days-hours`,
/// `days-hours:minutes`, `days-hours:minutes:seconds`, or `UNLIMITED` / `INFINITE`), a
/// `--mem` that is not a whole number with an optional unit `K`, `M`, `G` or `T` (sbatch(1))
/// or is more than Slurm's count of megabytes holds ([`mem_megabytes`]).
fn check_option(option: &'static str, value: &str) -> Result<(), SlurmError> {
    let refuse = |expected: &str| {
        Err(SlurmError::Value {
            key: option,
            value: value.to_string(),
            expected: expected.to_string(),
        })
    };
    let digits = |part: &str| !part.is_empty() && part.bytes().all(|b| b.is_ascii_digit());
    if value.trim().is_empty() {
        return refuse("a value (it is empty)");
    }
    match option {
        "--time" => {
            let unlimited = ["unlimited", "infinite"]
                .iter()
                .any(|word| value.eq_ignore_ascii_case(word));
            let (days, clock) = match value.split_once('-') {
                Some((days, clock)) => (Some(days), clock),
                None => (None, value),
            };
            let parts: Vec<&str> = clock.split(':').collect();
            let clock_ok = parts.iter().all(|p| digits(p))
                && match days {
                    Some(days) => digits(days) && parts.len() <= 3,
                    None => parts.len() <= 3,
                };
            if !unlimited && !clock_ok {
                return refuse(
                    "a time as sbatch takes it: minutes, minutes:seconds, hours:minutes:seconds, \
                     days-hours, days-hours:minutes, days-hours:minutes:seconds, or UNLIMITED",
                );
            }
        }
        "--mem" if mem_megabytes(value).is_none() => {
            return refuse(
                "a whole number of megabytes, or with a unit K, M, G or T (4G), of at most \
                 8 EiB (9223372036854775807M), which sbatch reads",
            );
        }
        _ => {}
    }
    Ok(())
}

/// A `--mem` value in megabytes as sbatch reads it (Slurm's `str_to_mbytes`): a whole
/// number with an optional unit `K` (rounded up), `M`, `G` or `T` (either case), which must
/// fit Slurm's signed 64-bit count of megabytes; `None` for anything else.
fn mem_megabytes(value: &str) -> Option<u64> {
    let number = value.trim_end_matches(|c: char| "KMGTkmgt".contains(c));
    let unit = &value[number.len()..];
    if number.is_empty() || !number.bytes().all(|b| b.is_ascii_digit()) || unit.len() > 1 {
        return None;
    }
    let n: u64 = number.parse().ok()?;
    let megabytes = match unit {
        "" | "M" | "m" => Some(n),
        "K" | "k" => Some(n.div_ceil(1024)),
        "G" | "g" => n.checked_mul(1024),
        _ => n.checked_mul(1024 * 1024),
    }?;
    // sbatch parses the number as a signed 64-bit integer (strtoll), before the unit too.
    let limit = i64::MAX as u64;
    (n <= limit && megabytes <= limit).then_some(megabytes)
}

/// Checks the shard count against the sweep's `n_runs` and [`Shard::MAX_COUNT`].
fn check_shards(shards: u64, n_runs: u64) -> Result<(), SlurmError> {
    let reason = if shards == 0 {
        "at least 1".to_string()
    } else if shards > Shard::MAX_COUNT {
        format!("at most {} shards", Shard::MAX_COUNT)
    } else if shards > n_runs {
        // A shard with no run would be an array task that does nothing; more shards than
        // runs is refused rather than capped, so the array has the size the user asked for.
        format!("the sweep has {n_runs} run(s), so at most {n_runs} shard(s)")
    } else {
        return Ok(());
    };
    Err(SlurmError::Shards { shards, reason })
}

/// The marker file `slurm` writes into its `DIR-slurm/` working directory; an existing
/// `DIR-slurm/` is written into only if it carries it or is empty.
pub const SLURM_MARKER: &str = ".gridplan-slurm";

/// Creates `work` (and its missing parents) as `slurm`'s working directory for `output`,
/// or checks that an existing one is gridplan's (the outdir rules:
/// [`crate::outdir::claim_dir`]).
fn claim_work_dir(work: &Path, output: &Path) -> Result<(), SlurmError> {
    if let Some(parent) = work.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(io(parent.display()))?;
    }
    crate::outdir::claim_dir(
        work,
        SLURM_MARKER,
        "# Written by gridplan slurm: job scripts, shard results and logs of one sweep;\n\
         # gridplan writes here again only while this file is in it.\n",
        || OutdirError::ForeignWorkDir {
            path: work.to_path_buf(),
            output: output.to_path_buf(),
            marker: SLURM_MARKER,
        },
    )?;
    Ok(())
}

/// Where `slurm` writes for `args`: the config, its absolute path, the key a bad output
/// value is reported under, the results directory and `DIR-slurm/`.
struct Places {
    experiment: crate::Experiment,
    config_path: PathBuf,
    output_key: String,
    output: PathBuf,
    work: PathBuf,
}

/// Reads the config and works out [`Places`], writing nothing.
fn places(args: &SlurmArgs) -> Result<Places, SlurmError> {
    if args.shards == 0 || args.shards > Shard::MAX_COUNT {
        // Refused before the config is read.
        check_shards(args.shards, u64::MAX)?;
    }
    let experiment = config::load(&args.config)?;
    check_shards(args.shards, RunList::new(&experiment).len())?;
    let config_path = absolute(&args.current_dir, &args.config)
        .canonicalize()
        .map_err(io(args.config.display()))?;
    // The key a bad output value is reported under.
    let output_key = if args.output.is_some() {
        "--output".to_string()
    } else {
        format!("{}: key `output`", args.config.display())
    };
    let output = results_dir(
        &args.current_dir,
        args.output.as_deref().unwrap_or(&experiment.output),
        &output_key,
    )?;
    let mut work = output.as_os_str().to_os_string();
    work.push("-slurm");
    Ok(Places {
        experiment,
        config_path,
        output_key,
        output,
        work: PathBuf::from(work),
    })
}

/// `DIR-slurm/`, where [`slurm`] writes for `args` (the config is read; nothing is
/// written): what the caller reads [`submitted`] from before it submits again.
pub fn work_dir(args: &SlurmArgs) -> Result<PathBuf, SlurmError> {
    Ok(places(args)?.work)
}

/// What the records of `found` hold, in words, when a resume of `wanted` refuses them
/// (the runner's rule: another config, gridplan version or shard); `None` if it keeps them.
fn other_sweep(found: &StreamHeader, wanted: &StreamHeader) -> Option<String> {
    if found.config_hash != wanted.config_hash || found.experiment != wanted.experiment {
        Some(format!(
            "it holds records of another config (experiment {:?}, config hash {}), not of \
             {} (experiment {:?}, config hash {})",
            found.experiment,
            found.config_hash,
            wanted.config,
            wanted.experiment,
            wanted.config_hash
        ))
    } else if found.gridplan != wanted.gridplan {
        Some(format!(
            "it holds records written by gridplan {}, and this is gridplan {}; one sweep's \
             records come from one version",
            found.gridplan.as_deref().unwrap_or("of unknown version"),
            wanted.gridplan.as_deref().unwrap_or("?")
        ))
    } else if (found.shard, found.shards) != (wanted.shard, wanted.shards) {
        Some(format!(
            "it holds the records of shard {} of {} (an earlier `slurm` of this output with \
             --shards {}), not of shard {} of {}",
            found.shard, found.shards, found.shards, wanted.shard, wanted.shards
        ))
    } else {
        None
    }
}

/// Refuses the shards in `work` (`shard-K` and its stream area, K from 1 to `n`) whose
/// recorded runs task K, which always resumes, would refuse ([`SlurmError::OtherSweep`]).
/// A stream whose header cannot be read is left to the task to report.
fn check_resumable(experiment: &crate::Experiment, work: &Path, n: u64) -> Result<(), SlurmError> {
    let Ok(entries) = std::fs::read_dir(work) else {
        return Ok(());
    };
    // The shards with a directory or a stream area here (a listing, not N lookups).
    let mut shards = std::collections::BTreeSet::new();
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let k = name
            .strip_prefix(".shard-")
            .and_then(|rest| rest.strip_suffix(".stream"))
            .or_else(|| name.strip_prefix("shard-"));
        if let Some(k) = k.and_then(|k| k.parse::<u64>().ok()) {
            if (1..=n).contains(&k) {
                shards.insert(k);
            }
        }
    }
    for k in shards {
        let shard = Shard { index: k, count: n };
        let wanted = StreamHeader::new(experiment, shard, 0);
        let dir = work.join(format!("shard-{k}"));
        for file in crate::sweep::resumed_streams(&dir) {
            let Ok(opened) = crate::stream::open_regular(&file) else {
                continue;
            };
            let what = file.display().to_string();
            let Ok((found, _)) = StreamReader::new(std::io::BufReader::new(opened), &what) else {
                continue;
            };
            if let Some(found) = other_sweep(&found, &wanted) {
                let area = crate::outdir::stream_area_path(&dir)
                    .ok()
                    .filter(|a| std::fs::symlink_metadata(a).is_ok());
                return Err(SlurmError::OtherSweep {
                    shard: k,
                    file,
                    dir,
                    area,
                    found,
                });
            }
        }
    }
    Ok(())
}

/// The file in `DIR-slurm/` that lists the jobs `--submit` submitted there, one id a line
/// after `#` comment lines ([`record_submitted`], [`submitted`]).
pub const JOBS_FILE: &str = "jobs";

/// The most of [`JOBS_FILE`] read: ids of a few submissions, never a file's worth.
const MAX_JOBS_BYTES: u64 = 1 << 20;

/// The job ids listed in `work`'s [`JOBS_FILE`] (none when there is no such file). Only a
/// regular file is read, and at most 1 MiB of it: a link or a device planted
/// at its name is an error, not followed (a link to `/dev/zero` would never end).
pub fn submitted(work: &Path) -> Result<Vec<String>, SlurmError> {
    use std::io::Read as _;
    let path = work.join(JOBS_FILE);
    let metadata = match std::fs::symlink_metadata(&path) {
        Ok(metadata) => metadata,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io(path.display())(e)),
    };
    if !metadata.is_file() {
        let kind = match metadata.file_type().is_symlink() {
            true => "a symbolic link",
            false => planner_maps::file_kind(&metadata.file_type()),
        };
        let e = std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("not a regular file ({kind}): gridplan wrote a file there; remove it"),
        );
        return Err(io(path.display())(e));
    }
    // Opened without following a link put there since the look above.
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    crate::outdir::no_follow(&mut options);
    let mut bytes = Vec::new();
    options
        .open(&path)
        .and_then(|file| file.take(MAX_JOBS_BYTES).read_to_end(&mut bytes))
        .map_err(io(path.display()))?;
    let text = String::from_utf8_lossy(&bytes);
    Ok(text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .map(str::to_string)
        .collect())
}

/// Writes `ids` as `work`'s [`JOBS_FILE`] (replacing it; a link planted at its name is
/// replaced, not written through): the jobs not known to have left the queue, which the
/// next `--submit` to the same output asks `squeue` about.
pub fn record_submitted(work: &Path, ids: &[String]) -> Result<(), SlurmError> {
    let path = work.join(JOBS_FILE);
    let mut text = String::from(
        "# Written by gridplan slurm --submit: the jobs it submitted for this output;\n\
         # it submits again only when squeue lists none of them.\n",
    );
    for id in ids {
        text.push_str(id);
        text.push('\n');
    }
    replace_file(&path, &text)
}

/// Writes `text` as `path`, replacing a link planted at its name instead of writing
/// through it.
fn replace_file(path: &Path, text: &str) -> Result<(), SlurmError> {
    if std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) {
        std::fs::remove_file(path).map_err(io(path.display()))?;
    }
    std::fs::write(path, text).map_err(io(path.display()))
}

/// Writes the scripts (the caller submits them if asked: [`Jobs::array_args`]).
pub fn slurm(args: &SlurmArgs) -> Result<Jobs, SlurmError> {
    let Places {
        experiment,
        config_path,
        output_key,
        output,
        work,
    } = places(args)?;
    let binary = absolute(&args.current_dir, &args.binary);
    let n = args.shards;
    let options = options(args)?;
    let threads = args
        .cpus_per_task
        .map_or(String::new(), |c| format!(" --threads {c}"));
    let bin = path_value("this binary's path", &binary, false)?;
    let cfg = path_value("the config's path", &config_path, false)?;
    let dir = path_value(&output_key, &work, false)?;
    let out = path_value(&output_key, &output, false)?;
    // Slurm's file name patterns apply to the log name only: `%` of the directory is `%%`.
    let log = |file: &str| -> Result<String, SlurmError> {
        let text = work.to_str().ok_or_else(|| SlurmError::NotUtf8 {
            key: output_key.clone(),
            path: work.clone(),
        })?;
        script_value(
            &output_key,
            &format!("{}/{file}", text.replace('%', "%%")),
            true,
        )
    };
    let task_log = log("task-%a.log")?;
    let merge_log = log("merge.log")?;
    // The results directory must be one `merge` may write, before anything is written.
    crate::outdir::check(&output)?;
    // So must every shard's recorded runs be ones its task resumes.
    check_resumable(&experiment, &work, n)?;
    claim_work_dir(&work, &output)?;
    let name = &experiment.name;
    // Each start says when and which job it is, in the log it appends to.
    let started = "echo \"== $(date '+%Y-%m-%d %H:%M:%S %z') start: job ${SLURM_JOB_ID:-?}, \
                   array task ${SLURM_ARRAY_TASK_ID:--}, restart ${SLURM_RESTART_COUNT:-0}\"";
    let array = format!(
        "#!/bin/bash\n\
         # Written by `gridplan slurm`: shard K of {n} of experiment {name}.\n\
         #SBATCH --job-name=gridplan-{name}\n\
         #SBATCH --array=1-{n}\n\
         #SBATCH --output={task_log}\n\
         #SBATCH --open-mode=append\n\
         {options}\
         set -euo pipefail\n\
         {started}\n\
         # Always --resume: a task requeued, or submitted again after it failed, timed out or\n\
         # was cancelled, keeps the runs it recorded; a finished shard runs nothing again.\n\
         exec {bin} experiment {cfg} --shard \"$SLURM_ARRAY_TASK_ID/{n}\" --output {dir}/shard-\"$SLURM_ARRAY_TASK_ID\" --quiet{threads} --resume\n",
    );
    let merge = format!(
        "#!/bin/bash\n\
         # Written by `gridplan slurm`: merges the {n} shards of experiment {name}.\n\
         #SBATCH --job-name=gridplan-{name}-merge\n\
         #SBATCH --output={merge_log}\n\
         #SBATCH --open-mode=append\n\
         {options}\
         set -euo pipefail\n\
         {started}\n\
         exec {bin} merge --shards-in {dir} --shards {n} --config {cfg} --output {out}\n",
    );
    let array_script = work.join("array.sbatch");
    let merge_script = work.join("merge.sbatch");
    for (path, text) in [(&array_script, &array), (&merge_script, &merge)] {
        // A script is replaced, never written through a link planted at its name.
        replace_file(path, text)?;
    }
    Ok(Jobs {
        work,
        array_script,
        merge_script,
    })
}

#[cfg(test)]
mod tests {
    use super::check_option;

    #[test]
    fn options_in_sbatch_forms_pass_and_others_are_refused() {
        for time in [
            "30",
            "30:00",
            "1:30:00",
            "2-0",
            "2-12",
            "2-12:30",
            "2-12:30:00",
            "0",
            "UNLIMITED",
            "infinite",
        ] {
            assert!(check_option("--time", time).is_ok(), "{time}");
        }
        for time in [
            "",
            " ",
            "abc",
            "1:2:3:4",
            "1h",
            "-5",
            "2-",
            "2-1:2:3:4",
            "1::2",
            "1.5",
        ] {
            let error = check_option("--time", time).unwrap_err().to_string();
            assert!(error.starts_with(&format!("--time {time:?}: ")), "{error}");
        }
        for mem in ["4096", "4G", "4g", "512M", "1T", "0", "64K"] {
            assert!(check_option("--mem", mem).is_ok(), "{mem}");
        }
        for mem in ["", "G", "4GG", "four", "4.5G", "-1", "4 G"] {
            assert!(check_option("--mem", mem).is_err(), "{mem}");
        }
        assert!(check_option("--partition", "gpu").is_ok());
        assert!(check_option("--partition", "").is_err());
        assert!(check_option("--account", "  ").is_err());
    }
}
