//! gridplan's command line as a library: the `gridplan` binary and `cargo xtask` (which
//! adds the repository's own tasks) parse the same [`Command`]s and run them with [`run`].
//!
//! Everything a command does is the libraries': sweeps and plans are planner-runner's
//! ([`planner_runner::sweep`], [`planner_runner::plan`]), the planner list
//! planner-registry's, and the report files planner-report's with planner-paper's
//! sections ([`planner_paper::renderer`]); this crate wires them and adds the argument
//! parsing, the progress bar and the log output.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use planner_api::Cell;
use planner_runner::plan::PlanArgs;
use planner_runner::{alloc, slurm, sweep};
use planner_runner::{ErrorClass, RunnerError};
use tracing_subscriber::EnvFilter;

/// `gridplan --version`: the package version and the git commit it was built from
/// (`unknown` when built outside a git checkout; build.rs).
pub const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("GRIDPLAN_GIT_COMMIT"),
    ")"
);

/// The `gridplan` command line.
#[derive(Parser)]
#[command(
    name = "gridplan",
    version = VERSION,
    about = "gridplan: sweep experiment configs over maps and planners, run one planner on one map",
    after_help = "Ctrl-C (SIGINT) or SIGTERM stops a command (a sweep cleanly: it cancels the runs in progress and keeps its finished runs for --resume; exit status 130). \
A second signal at least 1 s after the first quits at once. \
A SIGINT inherited ignored (nohup, trap '' INT) stays ignored; SIGTERM still stops. \
Output closed early (a pipe into `head`) ends a command quietly with status 0."
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The user commands (`cargo xtask` has these and the repository's own tasks).
#[derive(Subcommand)]
pub enum Command {
    /// Run an experiment config: every map x problem x planner x repeat, in parallel.
    Experiment {
        /// The TOML config, e.g. configs/paper.toml (keys: configs/README.md).
        config: PathBuf,
        /// Worker threads. Without it (or with 0) the config's `threads` key decides, and
        /// when that is absent or 0, one thread per core. Results do not depend on it.
        #[arg(long, value_name = "N")]
        threads: Option<usize>,
        /// Output directory (default: the config's `output`, else `results/<name>`).
        #[arg(long)]
        output: Option<PathBuf>,
        /// No progress bar (and, when stderr is not a terminal, no progress line every 30 s).
        #[arg(long)]
        quiet: bool,
        /// Keep the runs an interrupted sweep on the same output recorded and run the rest;
        /// after a finished sweep of the same config (or shard), nothing runs again. The
        /// runs or results of another config, version or shard are refused (exit 2) and left
        /// as they are.
        #[arg(long)]
        resume: bool,
        /// Run only shard K of N (1-based), e.g. 2/3; without it, SLURM_ARRAY_TASK_ID with
        /// SLURM_ARRAY_TASK_COUNT, or JOB_COMPLETION_INDEX with GRIDPLAN_SHARD_COUNT, give it.
        #[arg(long)]
        shard: Option<String>,
    },
    /// Combine shard outputs (`experiment --shard`) into the one sweep's results.
    Merge {
        /// The shard directories, every shard once.
        #[arg(required_unless_present = "shards_in")]
        dirs: Vec<PathBuf>,
        /// Also merge every directory `shard-K` (K a number) in DIR, as `slurm` lays them
        /// out; the merge job passes this instead of N paths, so its command line stays short.
        #[arg(long, value_name = "DIR")]
        shards_in: Option<PathBuf>,
        /// With --shards-in: merge exactly `shard-1` to `shard-N` there, and no other
        /// `shard-K` (one left by an earlier `slurm` with more shards); the merge job of
        /// `slurm --shards N` passes it.
        #[arg(long, value_name = "N", requires = "shards_in",
              value_parser = clap::value_parser!(u64).range(1..=planner_runner::shard::Shard::MAX_COUNT))]
        shards: Option<u64>,
        /// Output directory (default: the config's `output`).
        #[arg(long)]
        output: Option<PathBuf>,
        /// The config (default: the one the shards name).
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Re-render a results directory in place from its records (records.stream,
    /// expanded.jsonl, provenance.json): summary.md, figures, charts, report.html, OMPL
    /// logs. No planner runs; the directory is replaced as `experiment` replaces it.
    Report {
        /// The results directory (`experiment`'s or `merge`'s output).
        dir: PathBuf,
        /// The config (default: the one the records name; it must resolve to the config
        /// hash the runs were made with).
        #[arg(long)]
        config: Option<PathBuf>,
    },
    /// Compare two results directories run by run (after a change to a planner): the runs
    /// whose computed fields (status, path, length, cost, counters) differ, listed field by
    /// field, and per label NEW's times over OLD's. Exits 1 when the runs or their computed
    /// fields differ, and 5 (never 1) when OLD or NEW is not a whole sweep's complete results
    /// (not results, a shard's, a cut or damaged records stream).
    Compare {
        /// The results directory before.
        old: PathBuf,
        /// The results directory after.
        new: PathBuf,
        /// How many differing runs to list.
        #[arg(long, default_value_t = 10)]
        examples: usize,
        /// Print one JSON object instead of text (`planner_report::compare::Comparison::json`).
        #[arg(long)]
        json: bool,
    },
    /// Write (and with --submit submit) a Slurm job array of N shards plus a merge job.
    Slurm {
        /// The experiment config.
        config: PathBuf,
        /// Array tasks.
        #[arg(long)]
        shards: u64,
        /// The merged results directory (default: the config's `output`).
        #[arg(long)]
        output: Option<PathBuf>,
        /// sbatch --partition.
        #[arg(long)]
        partition: Option<String>,
        /// sbatch --time.
        #[arg(long)]
        time: Option<String>,
        /// sbatch --account (the allocation charged; many clusters require one).
        #[arg(long)]
        account: Option<String>,
        /// sbatch --qos.
        #[arg(long)]
        qos: Option<String>,
        /// sbatch --mem (memory per node, e.g. 4G).
        #[arg(long)]
        mem: Option<String>,
        /// sbatch --cpus-per-task (also the tasks' worker threads).
        #[arg(long)]
        cpus_per_task: Option<u32>,
        /// Submit both jobs and print their ids.
        #[arg(long)]
        submit: bool,
    },
    /// Run one planner on one problem and print the path, metrics and counters (a coverage
    /// planner covers from --start and takes no --goal).
    Plan {
        /// The map file: Moving AI .map (problems from a .scen beside it, read only without
        /// --start and --goal), seed 003 .txt
        /// (its own start-goal pairs), 0/1 matrix .csv, ROS map_server .yaml (with its
        /// PGM/PNG image), or a .png/.pgm image read with map_server's defaults (dark = occupied).
        map: PathBuf,
        /// Registry name (astar, backtracking, ...), or a label of --config.
        #[arg(long, value_parser = PlannerName, hide_possible_values = true)]
        planner: String,
        /// An experiment config whose planner labels --planner may name.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Problem number (1-based) among the map's own pairs or its .scen file.
        #[arg(long)]
        problem: Option<usize>,
        /// Start cell as x,y.
        #[arg(long, value_name = "X,Y", value_parser = parse_cell, allow_hyphen_values = true)]
        start: Option<Cell>,
        /// Goal cell as x,y (not for coverage planners).
        #[arg(long, value_name = "X,Y", value_parser = parse_cell, allow_hyphen_values = true)]
        goal: Option<Cell>,
        /// Start as a point x,y of a ROS map's map frame, in metres (a map_server .yaml:
        /// its resolution and origin place the cells, as nav2's costmap does): the cell
        /// holding it. The run is then also printed in that frame.
        #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true, conflicts_with = "start")]
        start_world: Option<(f64, f64)>,
        /// Goal as a point x,y of the map frame, in metres (see --start-world).
        #[arg(long, value_name = "X,Y", value_parser = parse_point, allow_hyphen_values = true, conflicts_with = "goal")]
        goal_world: Option<(f64, f64)>,
        /// Planner parameter override, key=value (repeatable; a key twice only with one value), e.g. --set heuristic=octile.
        #[arg(long = "set")]
        set: Vec<String>,
        /// Expansion budget (default: the config label's, else 10,000,000, so every run ends).
        #[arg(long)]
        max_expansions: Option<u64>,
        /// Memory limit of the planner's per-cell state, in MiB (default: the config
        /// label's `budget.max_memory_mb`, else half the machine's memory). A planner whose
        /// arrays would need more does not run, and says how much it needs.
        #[arg(long, value_name = "MIB")]
        max_memory_mb: Option<u64>,
        /// The value of a .csv map's cell that is an obstacle: 0 (the default, seed 000's
        /// convention) or 1 (the common occupancy-grid convention).
        #[arg(long, value_parser = ["0", "1"])]
        obstacle: Option<String>,
        /// Cell weights for the map: a .csv of integers from 1 to 65535, one row per map
        /// row (a map set's `costs.weights`). The path's cost is then printed.
        #[arg(long, value_name = "FILE", help_heading = "Cell costs")]
        weights: Option<PathBuf>,
        /// The move cost rule on a weighted map: mean (length times the mean of the two
        /// cells' weights, the default) or entered (times the entered cell's weight).
        #[arg(long, value_name = "RULE", value_parser = cost_rule_parser(), help_heading = "Cell costs")]
        cost_rule: Option<planner_api::CostRule>,
        /// Read a ROS map's graded values (mode scale or raw) as costs, with nav2's bands.
        #[arg(long, help_heading = "Cell costs")]
        graded: bool,
        /// ROS maps: costs from N up are blocked (default 254, nav2's LETHAL_OBSTACLE; 253 blocks
        /// INSCRIBED too, as nav2's planners do for the robot's centre; implies --graded).
        #[arg(long, value_name = "N", help_heading = "Cell costs")]
        lethal: Option<u8>,
        /// ROS maps: the cost of unknown cells (default: blocked; implies --graded).
        #[arg(long, value_name = "N", help_heading = "Cell costs")]
        unknown: Option<u8>,
        /// Moving AI maps: the weight of swamp `S` (ground is 1).
        #[arg(long, value_name = "N", help_heading = "Cell costs")]
        swamp: Option<u16>,
        /// Moving AI maps: the weight of water `W`, then passable (needs --swamp).
        #[arg(long, value_name = "N", help_heading = "Cell costs")]
        water: Option<u16>,
        /// Plan on a weighted map without its weights with a planner that cannot honour
        /// them (else it is refused).
        #[arg(long, help_heading = "Cell costs")]
        ignore_costs: bool,
        /// Print exactly one JSON object.
        #[arg(long)]
        json: bool,
        /// Also write the run's figure (the SVG a sweep draws for one run) to FILE, with the
        /// cells the search expanded (recorded by a second, untimed run that must repeat the
        /// first: planners that do not record show none).
        #[arg(long, value_name = "FILE")]
        svg: Option<PathBuf>,
        /// Also write the search as a Posthoc search trace (JSON) to FILE: source,
        /// destination, the search's steps, end. A*, bidirectional A*, Theta*, Lazy Theta*, JPS and
        /// weighted JPS record every push into OPEN and every expansion with parent, g and f; the other
        /// planners that list their expanded cells give one `expanding` event per expanded cell
        /// (planner-serve's `trace` module); a planner that lists none gives no steps (said
        /// on stderr).
        #[arg(long, value_name = "FILE")]
        trace: Option<PathBuf>,
        /// Also write an animated GIF of the search (expanded cells in order, then the
        /// path) to FILE, at most 5 MB; a map over 512 cells a side is drawn one pixel per
        /// block of ceil(side / 512) cells, at most 512 pixels a side.
        #[arg(long, value_name = "FILE")]
        gif: Option<PathBuf>,
    },
    /// Serve a local web page on DIR's maps: draw walls, set start and goal, run up to
    /// four planners and play their searches back; open results directories.
    Serve {
        /// The directory whose maps and results directories the page may open (only
        /// files under it are read).
        #[arg(default_value = ".")]
        dir: PathBuf,
        /// The port (0: any free port; the one chosen is printed).
        #[arg(long, default_value_t = 8080)]
        port: u16,
        /// The address to listen on (answered by localhost or IP address, never another host name).
        #[arg(long, default_value = "127.0.0.1")]
        host: std::net::IpAddr,
    },
    /// List the registered planners; with a name, every parameter of that planner (type,
    /// default, allowed values, doc), from its declared parameters.
    Planners {
        /// A registry name, e.g. astar.
        #[arg(value_parser = PlannerName, hide_possible_values = true)]
        name: Option<String>,
    },
    /// Print the JSON Schema of experiment configs (for editors: configs/README.md).
    Schema,
    /// Print a shell completion script, e.g. `gridplan completions bash > ~/.local/share/bash-completion/completions/gridplan`.
    Completions {
        /// The shell.
        shell: clap_complete::Shell,
    },
}

/// A `--start`/`--goal` value that is not a cell.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CellError {
    /// Not two coordinates separated by one comma.
    #[error("{0:?}: expected x,y (two coordinates separated by one comma)")]
    Shape(String),
    /// A coordinate below 0.
    #[error("{text:?}: {axis} coordinate {part} is negative; cells are numbered from 0")]
    Negative {
        /// The whole value.
        text: String,
        /// `x` or `y`.
        axis: char,
        /// The coordinate.
        part: String,
    },
    /// A coordinate over [`u32::MAX`].
    #[error("{text:?}: {axis} coordinate {part} is over the largest cell coordinate, {max}", max = u32::MAX)]
    TooLarge {
        /// The whole value.
        text: String,
        /// `x` or `y`.
        axis: char,
        /// The coordinate.
        part: String,
    },
    /// A coordinate that is not a whole number.
    #[error("{text:?}: {axis} coordinate {part:?} is not a whole number")]
    NotANumber {
        /// The whole value.
        text: String,
        /// `x` or `y`.
        axis: char,
        /// The coordinate.
        part: String,
    },
}

/// Parses `x,y` (two whole numbers from 0 to [`u32::MAX`]) into a cell.
pub fn parse_cell(text: &str) -> Result<Cell, CellError> {
    let parts: Vec<&str> = text.split(',').collect();
    let [x, y] = parts[..] else {
        return Err(CellError::Shape(text.to_string()));
    };
    let number = |axis: char, part: &str| {
        let part = part.trim();
        let fail = |kind: fn(String, char, String) -> CellError| {
            Err(kind(text.to_string(), axis, part.to_string()))
        };
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        match part.parse::<u32>() {
            Ok(n) => Ok(n),
            Err(_) if part.strip_prefix('-').is_some_and(digits) => {
                fail(|text, axis, part| CellError::Negative { text, axis, part })
            }
            Err(_) if digits(part.strip_prefix('+').unwrap_or(part)) => {
                fail(|text, axis, part| CellError::TooLarge { text, axis, part })
            }
            Err(_) => fail(|text, axis, part| CellError::NotANumber { text, axis, part }),
        }
    };
    Ok(Cell::new(number('x', x)?, number('y', y)?))
}

/// A `--start-world`/`--goal-world` value that is not a point.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum PointError {
    /// No comma.
    #[error("{0:?}: expected x,y (metres)")]
    Shape(String),
    /// A coordinate that is not a finite number.
    #[error("{text:?}: {part:?} is not a finite number of metres")]
    Coordinate {
        /// The whole value.
        text: String,
        /// The coordinate.
        part: String,
    },
}

/// Parses `x,y` into a point of the map frame (finite numbers, such as `-9.5,3.25`).
pub fn parse_point(text: &str) -> Result<(f64, f64), PointError> {
    let (x, y) = text
        .split_once(',')
        .ok_or_else(|| PointError::Shape(text.to_string()))?;
    let number = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| PointError::Coordinate {
                text: text.to_string(),
                part: s.to_string(),
            })
    };
    Ok((number(x)?, number(y)?))
}

/// Parses `--cost-rule`: `mean` or `entered` (possible values, so clap's error lists them
/// and the shell completions offer them).
fn cost_rule_parser() -> impl clap::builder::TypedValueParser<Value = planner_api::CostRule> {
    use clap::builder::TypedValueParser as _;
    clap::builder::PossibleValuesParser::new(["mean", "entered"]).map(|rule| match &*rule {
        "entered" => planner_api::CostRule::Entered,
        _ => planner_api::CostRule::Mean,
    })
}

/// The value parser of a planner name (`plan --planner`, `planners NAME`): any text (a
/// config's label as well as a registry name; an unknown one is the runner's error, which
/// lists the names), with the registry's names as possible values for the shell
/// completions (`gridplan completions`).
#[derive(Clone)]
struct PlannerName;

impl clap::builder::TypedValueParser for PlannerName {
    type Value = String;

    fn parse_ref(
        &self,
        command: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<String, clap::Error> {
        clap::builder::StringValueParser::new().parse_ref(command, arg, value)
    }

    fn possible_values(
        &self,
    ) -> Option<Box<dyn Iterator<Item = clap::builder::PossibleValue> + '_>> {
        Some(Box::new(planner_registry::PLANNERS.iter().map(|entry| {
            clap::builder::PossibleValue::new(entry.name).help(entry.summary)
        })))
    }
}

/// Writes one line (`format!` arguments) to stderr, as `eprintln!` does, except that a
/// stderr that cannot be written (closed early: `2>&1 | head -1`) loses the line instead of
/// panicking: a warning or a note is never worth a sweep's results, and an error's exit
/// status still says what happened. Every line gridplan writes to stderr goes through it
/// (`eprintln!` is refused in this crate by xtask's tidy test).
macro_rules! to_stderr {
    ($($arg:tt)*) => {
        $crate::stderr_line(format_args!($($arg)*))
    };
}

/// [`to_stderr!`]'s write: one line, its error ignored.
fn stderr_line(line: std::fmt::Arguments<'_>) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr().lock(), "{line}");
}

/// Stderr for `tracing`'s events, whose write errors are dropped: tracing-subscriber reports
/// a failed write with `eprintln!`, which panics when stderr is a closed pipe (a warning
/// then ended the command with status 101 before a sweep wrote anything).
struct QuietStderr;

impl std::io::Write for QuietStderr {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let _ = std::io::stderr().lock().write_all(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let _ = std::io::stderr().lock().flush();
        Ok(())
    }
}

/// Sends `tracing` output to stderr, filtered by `RUST_LOG` (default: warnings), plain
/// text unless stderr is a terminal. A closed stderr loses the events, nothing else.
pub fn init_logging() {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("warn")),
        )
        .with_writer(|| QuietStderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_target(false)
        .without_time()
        .init();
}

/// Why a command failed. [`CliError::exit_code`] is the exit status the command ends with
/// (the `EXIT_*` constants; README.md lists them).
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// The runner's error, typed (its class decides the exit status).
    #[error(transparent)]
    Runner(#[from] RunnerError),
    /// Command-line arguments that do not fit (beside those clap refuses, also exit 2).
    #[error("{0}")]
    Usage(String),
    /// `slurm` could not write its scripts.
    #[error(transparent)]
    Slurm(#[from] slurm::SlurmError),
    /// A replanning experiment's error (`kind = "navigate"` or `"dynamic"` configs).
    #[error(transparent)]
    Replan(#[from] planner_replan::experiment::ExperimentError),
    /// `serve` could not start.
    #[error(transparent)]
    Serve(#[from] planner_serve::ServeError),
    /// `plan --svg/--trace/--gif` wrote no picture.
    #[error(transparent)]
    Pictures(#[from] planner_serve::PictureError),
    /// The Ctrl-C handler could not be installed.
    #[error("cannot handle Ctrl-C: {0}")]
    Signals(#[from] ctrlc::Error),
    /// Standard output could not be written (not a closed pipe: a full disk).
    #[error("cannot write to stdout: {0}")]
    Stdout(std::io::Error),
    /// A replanning experiment ran, and some of its checks failed: replans that disagree
    /// with A* from scratch, or GPPC queries that disagree with their recorded optimum.
    #[error(
        "{mismatches} checks failed: replans that disagree with A* from scratch, or GPPC \
         queries that disagree with their recorded optimum (see {})",
        output.display()
    )]
    ReplanMismatches {
        /// The replans that disagree.
        mismatches: u64,
        /// The results directory that lists them.
        output: PathBuf,
    },
    /// `slurm --submit` could not submit a job.
    #[error(transparent)]
    Submit(#[from] SubmitError),
    /// The directory of `merge --shards-in` could not be listed.
    #[error("--shards-in {}: {source}", dir.display())]
    ShardsIn {
        /// The directory.
        dir: PathBuf,
        /// Why it could not be listed.
        source: std::io::Error,
    },
    /// A registered planner's schema or defaults could not be built (a registry defect).
    #[error(transparent)]
    Registry(#[from] planner_registry::schema::RegistryError),
    /// A registered planner refused its own defaults (a registry defect).
    #[error("its defaults: {0}")]
    Defaults(#[from] planner_api::ParamError),
    /// `compare` found runs that differ (its text says which).
    #[error(
        "{runs} runs differ in their computed fields, {unmatched} runs are in one directory only"
    )]
    Differ {
        /// Runs in both whose computed fields differ.
        runs: u64,
        /// Runs in one directory only.
        unmatched: u64,
    },
    /// The config schema could not be written as JSON.
    #[error("the config schema: {0}")]
    Json(#[from] serde_json::Error),
}

/// Why `slurm --submit` submitted less than both jobs.
#[derive(Debug, thiserror::Error)]
pub enum SubmitError {
    /// sbatch could not be started.
    #[error("cannot run sbatch (is Slurm installed?): {0}")]
    Spawn(std::io::Error),
    /// sbatch refused the job.
    #[error("sbatch {args} failed: {stderr}{}", .max_array.map_or(String::new(), |limit| format!(
        "\nthis cluster's MaxArraySize is {limit}, so an array has at most {} tasks: write the scripts again with fewer --shards",
        limit.saturating_sub(1)
    )))]
    Refused {
        /// sbatch's arguments.
        args: String,
        /// What sbatch printed.
        stderr: String,
        /// For an array sbatch found invalid: the cluster's `MaxArraySize`, if known (the
        /// likely cause).
        max_array: Option<u64>,
    },
    /// sbatch succeeded but printed no job id.
    #[error("sbatch {args} printed no job id")]
    NoJobId {
        /// sbatch's arguments.
        args: String,
    },
    /// The array job was submitted and its merge job was not.
    #[error("{source}\nthe array job {array} was submitted and its merge job was not: submit it with `sbatch {merge_args}`, or cancel the array with `scancel {array}`")]
    MergeNotSubmitted {
        /// Why the merge job was not submitted.
        source: Box<SubmitError>,
        /// The array job's id.
        array: String,
        /// The merge job's sbatch arguments, as a shell reads them.
        merge_args: String,
    },
}

/// Refuses (exit 2, before the run) an output file of `plan` (`--svg`, `--trace`,
/// `--gif`) that is a link leading to one of the run's `inputs`: the file it resolves to
/// (links followed) is an input's. planner-serve's check compares the picture's directory
/// entry, which a picture would replace (the link, not the map), so `--svg fig.svg` with
/// `fig.svg -> m.map` passed it and the run replaced the link; the map is named by it all
/// the same, and the README promises such a picture is refused. A file that does not
/// exist yet (or a dangling link) names no input.
fn refuse_links_to_inputs(files: &[&std::path::Path], inputs: &[PathBuf]) -> Result<(), CliError> {
    let inputs: Vec<(&PathBuf, PathBuf)> = inputs
        .iter()
        .filter_map(|input| input.canonicalize().ok().map(|resolved| (input, resolved)))
        .collect();
    for file in files {
        let Ok(resolved) = file.canonicalize() else {
            continue;
        };
        if let Some((input, _)) = inputs.iter().find(|(_, r)| *r == resolved) {
            return Err(CliError::Pictures(planner_serve::PictureError::Input {
                path: file.to_path_buf(),
                input: (*input).clone(),
            }));
        }
    }
    Ok(())
}

/// Any other failure (an I/O error, a full disk in the output or the resume stream, a
/// stream or shard set that cannot be read, a determinism bug found while drawing
/// expanded cells).
pub const EXIT_FAILURE: u8 = 1;
/// Command-line arguments that do not fit (clap's own usage errors exit 2 too), and values
/// that `slurm` cannot write safely into a script, one file named by two of `plan`'s
/// `--svg`, `--trace` and `--gif`, and such a file that is one of the run's inputs.
pub const EXIT_USAGE: u8 = 2;
/// An experiment config that cannot be read or is invalid.
pub const EXIT_CONFIG: u8 = 3;
/// A map or scenario file that cannot be read, or a start or goal that cannot be planned.
pub const EXIT_INPUT: u8 = 4;
/// An output directory gridplan may not write: not its own results, a mount point, or held
/// by another sweep's lock; a directory given to `report` or `compare` that does not hold a whole
/// sweep's complete results (not results, a shard's, a cut or damaged records stream).
pub const EXIT_OUTPUT: u8 = 5;
/// The exit code of a command stopped by Ctrl-C (SIGINT) or SIGTERM (a sweep also while it
/// waits for another sweep's lock): 128 + 2, as shells report Ctrl-C.
pub const EXIT_INTERRUPTED: u8 = 130;

impl CliError {
    /// The exit status of this failure.
    pub fn exit_code(&self) -> u8 {
        let runner = match self {
            CliError::Usage(_) => return EXIT_USAGE,
            CliError::Slurm(error) => {
                return match error {
                    slurm::SlurmError::Config(_) => EXIT_CONFIG,
                    slurm::SlurmError::Output(_) | slurm::SlurmError::StillQueued { .. } => {
                        EXIT_OUTPUT
                    }
                    slurm::SlurmError::Io { .. } => EXIT_FAILURE,
                    _ => EXIT_USAGE,
                }
            }
            CliError::Signals(_)
            | CliError::Stdout(_)
            | CliError::ReplanMismatches { .. }
            | CliError::Submit(_)
            | CliError::ShardsIn { .. }
            | CliError::Registry(_)
            | CliError::Defaults(_)
            | CliError::Json(_)
            | CliError::Differ { .. }
            | CliError::Serve(_) => return EXIT_FAILURE,
            CliError::Pictures(error) => {
                return match error {
                    planner_serve::PictureError::SameFile { .. }
                    | planner_serve::PictureError::Input { .. }
                    | planner_serve::PictureError::NotAFile { .. } => EXIT_USAGE,
                    _ => EXIT_FAILURE,
                }
            }
            CliError::Replan(error) => {
                use planner_replan::experiment::ExperimentError as E;
                return match error {
                    E::Parse { .. } | E::Invalid { .. } | E::TooManyToggles { .. } => EXIT_CONFIG,
                    E::Map(_) | E::Problem { .. } | E::GppcGrid { .. } => EXIT_INPUT,
                    E::Output(_) | E::Table { .. } => EXIT_OUTPUT,
                    _ => EXIT_FAILURE,
                };
            }
            // Stopped (Ctrl-C, SIGTERM) while waiting for another sweep's lock: nothing ran.
            CliError::Runner(error)
                if matches!(
                    error.innermost(),
                    RunnerError::Output(planner_runner::outdir::OutdirError::Stopped { .. })
                ) =>
            {
                return EXIT_INTERRUPTED
            }
            CliError::Runner(error) => error.class(),
        };
        // The Python package raises its exception class from the same class.
        match runner {
            ErrorClass::Config => EXIT_CONFIG,
            ErrorClass::Map | ErrorClass::Problem => EXIT_INPUT,
            ErrorClass::Output => EXIT_OUTPUT,
            ErrorClass::Usage | ErrorClass::Parameter => EXIT_USAGE,
            ErrorClass::Determinism | ErrorClass::Other => EXIT_FAILURE,
        }
    }
}

/// The command of the command line (`std::env::args`), or, when clap answered instead,
/// the exit status after its answer was printed: `--help` and `--version` go to stdout as
/// every command's output does (a closed pipe ends quietly with status 0, any other write
/// error, such as a full disk, is an error, status 1), a usage error to stderr with
/// status 2.
pub fn parse() -> Result<Command, ExitCode> {
    let error = match Cli::try_parse() {
        Ok(cli) => return Ok(cli.command),
        Err(error) => error,
    };
    let colour =
        |terminal: bool| terminal && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty());
    let rendered = error.render();
    if error.use_stderr() {
        // clap quotes the values the user gave as they are: a line break in one is
        // escaped, so that it cannot end the error's line.
        let arguments = || std::env::args_os().skip(1);
        let text = match colour(std::io::IsTerminal::is_terminal(&std::io::stderr())) {
            true => arguments_on_one_line(&rendered.ansi().to_string(), arguments()),
            false => {
                planner_text::terminal(&arguments_on_one_line(&rendered.to_string(), arguments()))
                    .into_owned()
            }
        };
        // A stderr that cannot be written loses the message; the status still says it.
        let _ = std::io::Write::write_all(&mut std::io::stderr().lock(), text.as_bytes());
        return Err(ExitCode::from(
            u8::try_from(error.exit_code()).unwrap_or(EXIT_USAGE),
        ));
    }
    let text = match colour(std::io::IsTerminal::is_terminal(&std::io::stdout())) {
        true => rendered.ansi().to_string(),
        false => rendered.to_string(),
    };
    match write_stdout(text.as_bytes()) {
        Ok(()) => Err(ExitCode::SUCCESS),
        Err(error) => Err(exit(Err(error))),
    }
}

/// The exit code of a command's result; prints the error.
pub fn exit(result: Result<(), CliError>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => fail(&error, error.exit_code()),
    }
}

/// Prints `error` as `error: ...` on stderr, escaped for the terminal (messages carry
/// config text: labels, paths; no control sequence reaches the terminal), and returns the
/// exit status `code`.
pub fn fail(error: &dyn std::fmt::Display, code: u8) -> ExitCode {
    let message = arguments_on_one_line(&error.to_string(), std::env::args_os().skip(1));
    to_stderr!("error: {}", planner_text::terminal(&message));
    ExitCode::from(code)
}

/// `message` with every piece of the command-line `arguments` that holds a control
/// character (a path's component, an option's `=` value) written on one line
/// ([`planner_text::one_line`]) wherever it appears, so that a path the user gave
/// (`plan $'new\nline.map'`), which the libraries' errors name as it is, cannot end the
/// line of the error; the line breaks of messages that span lines on purpose are kept.
fn arguments_on_one_line(
    message: &str,
    arguments: impl Iterator<Item = std::ffi::OsString>,
) -> String {
    let mut message = message.to_string();
    for argument in arguments {
        let argument = argument.to_string_lossy().into_owned();
        let mut pieces: Vec<&str> = argument
            .split(['/', '='])
            .filter(|piece| piece.contains(char::is_control))
            .collect();
        // The longest first, so that a piece holding another is replaced whole.
        pieces.sort_by_key(|piece| std::cmp::Reverse(piece.len()));
        for piece in pieces {
            message = message.replace(piece, &planner_text::one_line(piece));
        }
    }
    message
}

/// Raised by the first SIGINT or SIGTERM while a sweep watches it.
static STOP: AtomicBool = AtomicBool::new(false);

/// Whether a sweep watches [`STOP`] (else a signal ends the process at once).
static GRACEFUL: AtomicBool = AtomicBool::new(false);

/// When the first signal raised [`STOP`].
static FIRST_STOP: std::sync::OnceLock<std::time::Instant> = std::sync::OnceLock::new();

/// How long after the first SIGINT or SIGTERM of a sweep another one is taken as the same
/// signal delivered again, not as "interrupt again": GNU `timeout` sends its signal to
/// the child and then to the child's process group, which may arrive as two (README).
pub const REPEATED_SIGNAL: std::time::Duration = std::time::Duration::from_secs(1);

/// Installs the one handler of SIGINT and SIGTERM (Ctrl-C; Slurm's `scancel`). While a
/// sweep watches [`STOP`], the first signal raises it, so the sweep starts no new run,
/// cancels the runs in progress and keeps the finished ones; a signal within
/// [`REPEATED_SIGNAL`] of the first is taken as the same one. Otherwise (`plan`, which
/// writes nothing, or a second signal later) it prints "interrupted" and exits at once with [`EXIT_INTERRUPTED`] (a sweep's
/// stream may then end in a cut line, which `--resume` drops). A handler installed first
/// is kept.
///
/// A SIGINT or SIGHUP that the process inherited ignored (started by `nohup`, in the
/// background of a non-interactive shell, under `trap '' INT`) stays ignored, the POSIX
/// convention for programs that catch them: whoever started gridplan that way asked for
/// Ctrl-C (or the terminal's hangup) not to reach it. SIGTERM is handled either way.
fn install_handler() -> Result<(), ctrlc::Error> {
    let ignored = signals::inherited_ignored();
    let handler = || {
        if GRACEFUL.load(Ordering::SeqCst) {
            if !STOP.swap(true, Ordering::SeqCst) {
                let _ = FIRST_STOP.set(std::time::Instant::now());
                to_stderr!(
                    "stopping: cancelling the runs in progress; finished runs are kept \
                     (interrupt again to quit at once)"
                );
                return;
            }
            // The first signal delivered twice (GNU `timeout` signals the child and then
            // its process group): not yet a second interrupt.
            if FIRST_STOP
                .get()
                .is_some_and(|first| first.elapsed() < REPEATED_SIGNAL)
            {
                return;
            }
        }
        to_stderr!("interrupted");
        std::process::exit(i32::from(EXIT_INTERRUPTED));
    };
    // `try_set_handler` refuses when a signal's disposition is not the default, which an
    // ignored one is not: then the handler is set over the ignored dispositions, and
    // those are ignored again at once.
    let installed = if ignored.is_empty() {
        ctrlc::try_set_handler(handler)
    } else {
        ctrlc::set_handler(handler)
    };
    match installed {
        Ok(()) => {
            signals::ignore(&ignored);
            Ok(())
        }
        Err(ctrlc::Error::MultipleHandlers) => Ok(()),
        Err(error) => Err(error),
    }
}

/// Signal dispositions, read and set with the C library (the one place gridplan calls it
/// directly; `ctrlc` installs the handler itself).
#[cfg(unix)]
#[allow(unsafe_code)]
mod signals {
    /// The signals among SIGINT and SIGHUP that are ignored (`SIG_IGN`) now, if every
    /// signal ctrlc handles (those two and SIGTERM) is either ignored or at its default;
    /// empty otherwise (another handler is installed: it is kept).
    pub(super) fn inherited_ignored() -> Vec<libc::c_int> {
        let mut ignored = Vec::new();
        for signal in [libc::SIGINT, libc::SIGHUP, libc::SIGTERM] {
            // SAFETY: sigaction with a null new action only reads the current one into
            // `current`, a zeroed `struct sigaction` owned by this frame.
            let handler = unsafe {
                let mut current: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(signal, std::ptr::null(), &mut current) != 0 {
                    return Vec::new();
                }
                current.sa_sigaction
            };
            match handler {
                libc::SIG_DFL => {}
                libc::SIG_IGN if signal != libc::SIGTERM => ignored.push(signal),
                _ => return Vec::new(),
            }
        }
        ignored
    }

    /// Sets `signals` back to ignored (after `ctrlc` installed its handler for them).
    pub(super) fn ignore(signals: &[libc::c_int]) {
        for &signal in signals {
            // SAFETY: SIG_IGN installs no code as a handler; signal(2) only changes the
            // disposition.
            unsafe {
                libc::signal(signal, libc::SIG_IGN);
            }
        }
    }
}

/// Elsewhere no signal is taken as inherited ignored.
#[cfg(not(unix))]
mod signals {
    pub(super) fn inherited_ignored() -> Vec<i32> {
        Vec::new()
    }

    pub(super) fn ignore(_: &[i32]) {}
}

/// Makes Ctrl-C end the process at once with "interrupted" and [`EXIT_INTERRUPTED`]: for
/// `plan` and `serve`, which write nothing, so stopping anywhere is clean.
fn stop_on_interrupt() -> Result<(), CliError> {
    Ok(install_handler()?)
}

/// Makes SIGINT and SIGTERM stop a sweep cleanly: the flag it watches, or `None` (with a
/// warning) if no handler can be installed.
fn stop_on_signals() -> Option<&'static AtomicBool> {
    GRACEFUL.store(true, Ordering::SeqCst);
    match install_handler() {
        Ok(()) => Some(&STOP),
        Err(error) => {
            GRACEFUL.store(false, Ordering::SeqCst);
            tracing::warn!("no SIGINT/SIGTERM handler, a signal will kill the sweep: {error}");
            None
        }
    }
}

/// How often a sweep whose stderr is not a terminal (a Slurm log, `nohup`, `2> file`)
/// prints a progress line instead of the bar.
pub const PROGRESS_LINE_EVERY: std::time::Duration = std::time::Duration::from_secs(30);

/// A sweep's progress on stderr, and what a resumed sweep found: a progress bar on a
/// terminal, else a plain line (`progress: N of M runs (P %), S s`) every
/// [`PROGRESS_LINE_EVERY`], with no carriage return or escape code.
struct Bar {
    bar: std::sync::OnceLock<ProgressBar>,
    /// `--quiet`: no bar and no lines (what a resume found is still said).
    quiet: bool,
    /// Without a terminal: the sweep's start, its run count and the last line's time.
    lines: std::sync::Mutex<Option<Lines>>,
}

/// The progress lines of [`Bar`] without a terminal.
struct Lines {
    /// The sweep's runs.
    total: u64,
    /// When the sweep started.
    started: std::time::Instant,
    /// When the last line was printed (or the sweep started).
    last: std::time::Instant,
    /// The time between two lines.
    every: std::time::Duration,
}

impl Bar {
    /// The bar of a sweep (`quiet`: none).
    fn new(quiet: bool) -> Bar {
        Bar {
            bar: std::sync::OnceLock::new(),
            quiet,
            lines: std::sync::Mutex::new(None),
        }
    }
}

/// The time between two progress lines: [`PROGRESS_LINE_EVERY`], or for the tests the
/// milliseconds `GRIDPLAN_PROGRESS_LINE_MS` gives (not promised to users).
fn progress_line_every() -> std::time::Duration {
    std::env::var("GRIDPLAN_PROGRESS_LINE_MS")
        .ok()
        .and_then(|ms| ms.parse().ok())
        .map_or(PROGRESS_LINE_EVERY, std::time::Duration::from_millis)
}

impl sweep::Progress for Bar {
    fn start(&self, total: u64, done: u64) {
        if self.quiet {
            return;
        }
        if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            let now = std::time::Instant::now();
            if let Ok(mut lines) = self.lines.lock() {
                *lines = Some(Lines {
                    total,
                    started: now,
                    last: now,
                    every: progress_line_every(),
                });
            }
            return;
        }
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs ({eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_position(done);
        let _ = self.bar.set(bar);
    }

    fn set(&self, done: u64) {
        if let Some(bar) = self.bar.get() {
            bar.set_position(done);
        }
        let Ok(mut lines) = self.lines.lock() else {
            return;
        };
        if let Some(lines) = lines.as_mut() {
            let now = std::time::Instant::now();
            if now.duration_since(lines.last) >= lines.every && done < lines.total {
                lines.last = now;
                to_stderr!(
                    "progress: {done} of {} runs ({} %), {} s",
                    lines.total,
                    u128::from(done) * 100 / u128::from(lines.total.max(1)),
                    now.duration_since(lines.started).as_secs()
                );
            }
        }
    }

    fn finish(&self) {
        if let Some(bar) = self.bar.get() {
            bar.finish_and_clear();
        }
    }

    fn resumed(&self, done: u64, total: u64, output: &Path) {
        if done == 0 {
            to_stderr!(
                "nothing to resume for {}: running every run",
                planner_text::one_line(&output.display().to_string())
            );
        } else {
            to_stderr!("resuming: {done} of {total} runs already recorded");
        }
    }

    fn discarding(&self, message: &str) {
        let message = arguments_on_one_line(message, std::env::args_os().skip(1));
        to_stderr!("{}", planner_text::terminal(&message));
    }
}

/// What the provenance of a sweep of `config` needs from the environment and from git
/// (the runner reads neither): the host name (`/proc/sys/kernel/hostname`, else
/// `$HOSTNAME`) and the commit of the config's working tree, `-dirty` with changes. The
/// front ends' one gathering of them: the command line, xtask and the Python package
/// call it.
pub fn machine(config: &Path) -> planner_runner::provenance::Machine {
    let dir = config
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let git = |args: &[&str]| {
        std::process::Command::new("git")
            .arg("-C")
            .arg(dir)
            .args(args)
            .stdin(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|o| String::from_utf8_lossy(&o.stdout).into_owned())
    };
    planner_runner::provenance::Machine::from_facts(planner_runner::provenance::Facts {
        hostname_file: std::fs::read_to_string("/proc/sys/kernel/hostname").ok(),
        hostname_env: std::env::var("HOSTNAME").ok(),
        git_head: git(&["rev-parse", "HEAD"]),
        git_status: git(&["status", "--porcelain", "--untracked-files=no"]),
    })
}

/// The text of the config at `path` if it is a replanning experiment (`kind = "navigate"`
/// or `"dynamic"`, run by planner-replan), or `None` for the runner's configs and for a file
/// that cannot be read (the runner then reports that, typed). The text is what
/// [`replan_experiment`] parses, so the file is read once.
/// Only a regular file is read, and at most [`REPLAN_SNIFF_BYTES`] of it: a FIFO, a device or
/// a huge file is left to the runner's reader, which refuses it with its own error.
fn replan_text(path: &Path) -> Option<String> {
    use std::io::Read;
    // Opened without blocking on a FIFO, and refused unless a regular file.
    let file = planner_runner::stream::open_regular(path).ok()?;
    let mut text = String::new();
    file.take(REPLAN_SNIFF_BYTES)
        .read_to_string(&mut text)
        .ok()?;
    planner_replan::experiment::kind_of(&text).map(|_| text)
}

/// The most of a config [`replan_text`] reads (configs are a few kilobytes).
const REPLAN_SNIFF_BYTES: u64 = 1 << 20;

/// Runs the `navigate` or `dynamic` config (issue 31) at `config`, whose `text`
/// [`replan_text`] read, into `output` (default `results/<name>`); fails when the oracle
/// found a mismatch.
fn replan_experiment(
    config: &Path,
    text: &str,
    output: Option<PathBuf>,
    threads: Option<usize>,
) -> Result<(), CliError> {
    use planner_replan::experiment;
    let parsed = experiment::parse(config, text)?;
    let output = output.unwrap_or_else(|| PathBuf::from("results").join(parsed.name.get_ref()));
    let options = experiment::RunOptions {
        test: false,
        timing: true,
        threads: threads.unwrap_or(0),
        // Ctrl-C stops the runs and leaves the output as it was.
        stop: stop_on_signals(),
    };
    let done = match experiment::run_config(&parsed, config, &output, &options) {
        Err(experiment::ExperimentError::Interrupted) => {
            to_stderr!(
                "interrupted: no results were written, {} is as it was",
                planner_text::one_line(&output.display().to_string())
            );
            std::process::exit(i32::from(EXIT_INTERRUPTED));
        }
        done => done?,
    };
    let queries = match done.queries {
        0 => String::new(),
        n => format!(", {n} GPPC queries checked against their recorded optimum"),
    };
    write_text(&format!(
        "{}: {} runs, {} replans checked against A* from scratch{queries}, {} mismatches -> {}\n",
        done.name,
        done.runs,
        done.replans,
        done.mismatches,
        output.display()
    ))?;
    if done.mismatches > 0 {
        return Err(CliError::ReplanMismatches {
            mismatches: done.mismatches,
            output: output.to_path_buf(),
        });
    }
    Ok(())
}

/// Runs one user command.
pub fn run(command: Command) -> Result<(), CliError> {
    match command {
        Command::Experiment {
            config,
            threads,
            output,
            quiet,
            resume,
            shard,
        } => {
            if let Some(text) = replan_text(&config) {
                if resume || shard.is_some() {
                    return Err(CliError::Usage(format!(
                        "{}: --resume and --shard do not apply to navigate or dynamic configs",
                        config.display()
                    )));
                }
                // A shard the environment gives (a Slurm array task) would have each task
                // run the whole experiment into the same output.
                let from_env = planner_runner::shard::Shard::from_env(|k| std::env::var(k).ok())
                    .map_err(|e| CliError::Usage(e.to_string()))?;
                if let Some(shard) = from_env {
                    return Err(CliError::Usage(format!(
                        "{}: the environment gives shard {shard} (SLURM_ARRAY_TASK_ID or \
                         JOB_COMPLETION_INDEX), but navigate and dynamic configs run whole: \
                         run them outside a job array",
                        config.display()
                    )));
                }
                return replan_experiment(&config, &text, output, threads);
            }
            let shard = match shard {
                Some(text) => Some(
                    planner_runner::shard::Shard::parse(&text)
                        .map_err(|e| CliError::Usage(format!("--shard: {e}")))?,
                ),
                None => planner_runner::shard::Shard::from_env(|k| std::env::var(k).ok())
                    .map_err(|e| CliError::Usage(e.to_string()))?,
            };
            let bar = Bar::new(quiet);
            let stop = stop_on_signals();
            let renderer = planner_paper::renderer();
            let machine = machine(&config);
            let report = sweep::experiment(&sweep::SweepArgs {
                threads: threads.unwrap_or(0),
                output: output.as_deref(),
                progress: Some(&bar as &dyn sweep::Progress),
                machine: &machine,
                heap: Some(&alloc::Meter),
                resume,
                shard,
                stop,
                build: Some(env!("GRIDPLAN_GIT_COMMIT")).filter(|commit| *commit != "unknown"),
                ..sweep::SweepArgs::new(&config, &renderer)
            })?;
            if let Some(n_recorded) = report.interrupted {
                match n_recorded as usize == report.n_runs {
                    // Stopped while the results were written: every run is in the stream.
                    true => to_stderr!(
                        "interrupted while writing the results of all {} runs, which are kept; \
                         rerun with --resume to write them without running any again",
                        report.n_runs
                    ),
                    false => to_stderr!(
                        "interrupted after {n_recorded} of {} runs; rerun with --resume to continue",
                        report.n_runs
                    ),
                }
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
            let mut out = format!(
                "{} runs in {:.2} s -> {}\n",
                report.n_runs,
                report.seconds,
                report.output.display()
            );
            if report.reproduction.compared > 0 {
                out.push_str(&format!(
                    "published numbers reproduced: {} of {}\n",
                    report.reproduction.matched, report.reproduction.compared
                ));
            }
            if let Some(left_out) = &report.left_out {
                to_stderr!("note: {left_out}");
            }
            write_text(&out)
        }
        Command::Merge {
            mut dirs,
            shards_in,
            shards,
            output,
            config,
        } => {
            if let Some(parent) = &shards_in {
                match shards {
                    // Named, not listed: merge reports a missing one.
                    Some(n) => dirs.extend((1..=n).map(|k| parent.join(format!("shard-{k}")))),
                    None => dirs.extend(shard_dirs_in(parent)?),
                }
            }
            let report = sweep::merge(
                &dirs,
                output.as_deref(),
                config.as_deref(),
                &planner_paper::renderer(),
                &machine,
            )?;
            write_text(&format!(
                "{} runs merged from {} shards -> {}\n",
                report.n_runs,
                dirs.len(),
                report.output.display()
            ))
        }
        Command::Report { dir, config } => {
            let report = sweep::report(&dir, config.as_deref(), &planner_paper::renderer())?;
            write_text(&format!(
                "{} runs reported -> {}\n",
                report.n_runs,
                report.output.display()
            ))
        }
        Command::Compare {
            old,
            new,
            examples,
            json,
        } => {
            let comparison = planner_report::compare::compare(&old, &new, examples)?;
            match json {
                true => write_stdout(format!("{}\n", comparison.json()).as_bytes())?,
                false => write_text(&comparison.text())?,
            }
            match comparison.same() {
                true => Ok(()),
                false => Err(CliError::Differ {
                    runs: comparison.differing,
                    unmatched: comparison.runs[0] + comparison.runs[1] - 2 * comparison.both,
                }),
            }
        }
        Command::Slurm {
            config,
            shards,
            output,
            partition,
            time,
            account,
            qos,
            mem,
            cpus_per_task,
            submit,
        } => {
            // The scripts run this very binary, with paths made absolute from here.
            let looked_up = |what: &str| {
                let what = what.to_string();
                move |source| slurm::SlurmError::Io { what, source }
            };
            let args = slurm::SlurmArgs {
                config,
                shards,
                output,
                partition,
                time,
                account,
                qos,
                mem,
                cpus_per_task,
                binary: std::env::current_exe().map_err(looked_up("this binary's path"))?,
                current_dir: std::env::current_dir().map_err(looked_up("current directory"))?,
            };
            // The jobs of an earlier submission of this output that may still run: a
            // second array would run the same shards at once, so it waits for them.
            let mut earlier = Vec::new();
            if submit {
                let work = slurm::work_dir(&args)?;
                earlier = slurm::submitted(&work)?;
                if !earlier.is_empty() {
                    match squeue(&earlier) {
                        Ok(queued) if !queued.is_empty() => {
                            let jobs = queued;
                            return Err(slurm::SlurmError::StillQueued { work, jobs }.into());
                        }
                        Ok(_) => earlier.clear(),
                        Err(why) => to_stderr!(
                            "warning: {}, so whether jobs {} of an earlier submission of \
                             this output still run is unknown; submitting anyway (if they do, \
                             two arrays run the same shards)",
                            planner_text::terminal(&why),
                            earlier.join(", ")
                        ),
                    }
                }
            }
            let jobs = slurm::slurm(&args)?;
            // What the next submission asks squeue about (a warning if it cannot be kept).
            let record = |ids: &[String]| {
                if let Err(e) = slurm::record_submitted(&jobs.work, ids) {
                    to_stderr!(
                        "warning: the submitted job ids could not be recorded: {}",
                        planner_text::terminal(&e.to_string())
                    );
                }
            };
            let mut out = format!(
                "array script: {}\nmerge script: {}\n",
                jobs.array_script.display(),
                jobs.merge_script.display()
            );
            if submit {
                let array = sbatch(&jobs.array_args()).map_err(array_hint)?;
                earlier.push(array.clone());
                record(&earlier);
                let merge = sbatch(&jobs.merge_args(&array)).map_err(|e| {
                    // The array runs without its merge: say what is left to do.
                    let args: Vec<String> = jobs
                        .merge_args(&array)
                        .iter()
                        .map(|a| shell_word(a))
                        .collect();
                    SubmitError::MergeNotSubmitted {
                        source: Box::new(e),
                        array: array.clone(),
                        merge_args: args.join(" "),
                    }
                })?;
                earlier.push(merge.clone());
                record(&earlier);
                out.push_str(&format!("array job {array}\nmerge job {merge}\n"));
            }
            write_text(&out)
        }
        Command::Plan {
            map,
            planner,
            config,
            problem,
            start,
            goal,
            start_world,
            goal_world,
            set,
            max_expansions,
            max_memory_mb,
            obstacle,
            weights,
            cost_rule,
            graded,
            lethal,
            unknown,
            swamp,
            water,
            ignore_costs,
            json,
            svg,
            trace,
            gif,
        } => {
            stop_on_interrupt()?;
            let args = PlanArgs {
                map,
                planner,
                config,
                problem,
                start,
                goal,
                start_world,
                goal_world,
                set,
                max_expansions,
                obstacle: obstacle
                    .and_then(|value| value.parse().ok())
                    .and_then(planner_maps::CsvConvention::from_obstacle_value),
            };
            let options = planner_runner::plan::PlanOptions {
                max_memory_mb,
                record_expanded: svg.is_some() || trace.is_some() || gif.is_some(),
                record_events: trace.is_some(),
                costs: planner_runner::plan::PlanCosts {
                    weights,
                    rule: cost_rule,
                    graded,
                    lethal,
                    unknown,
                    swamp,
                    water,
                    ignore: ignore_costs,
                },
            };
            // A picture may not replace an input: refused before the run.
            let inputs = planner_runner::plan::input_files(&args, &options);
            let files: Vec<&std::path::Path> = [&svg, &trace, &gif]
                .into_iter()
                .filter_map(|file| file.as_deref())
                .collect();
            planner_serve::check_picture_files(&files, &inputs)?;
            refuse_links_to_inputs(&files, &inputs)?;
            let result = planner_runner::plan::run_with(&args, &options)?;
            let figure = svg
                .as_ref()
                .map(|_| planner_report::figures::draw_planned(&result));
            let pictures = planner_serve::Pictures {
                svg: svg.as_deref().zip(figure.as_deref()),
                trace: trace.as_deref(),
                gif: gif.as_deref(),
            };
            planner_serve::write_pictures(&result, &pictures, &inputs)?;
            // JSON is written as serde_json escapes it (a C1 control such as U+0085 stays a
            // character there); the text for a person has its control characters escaped.
            if json {
                write_stdout(format!("{}\n", result.to_json()?).as_bytes())?;
            } else {
                write_text(&result.to_text_within(text_columns()))?;
            }
            // No steps from a run that searched: one that expanded cells, or a planner
            // that counts no `n_expanded` at all (coverage, whose return searches'
            // expansions are `n_return_expansions`; the RRT family, which samples). A
            // planner that lists its cells and expanded none (start = goal) says nothing.
            let searched = result
                .record
                .counters
                .get("n_expanded")
                .is_none_or(|n| n > 0);
            if trace.is_some() && result.events.is_empty() && result.expanded.is_empty() && searched
            {
                to_stderr!(
                    "note: {} records no search steps (it lists no expanded cells), so the trace holds only its start, goal and end",
                    planner_text::one_line(&result.record.planner)
                );
            }
            if trace.is_some() && result.events.len() >= planner_api::MAX_SEARCH_EVENTS {
                to_stderr!(
                    "note: the trace holds the search's first {} steps (planner_api::MAX_SEARCH_EVENTS); the search went on",
                    planner_api::MAX_SEARCH_EVENTS
                );
            }
            if result.hit_default_budget() {
                to_stderr!(
                    "note: stopped at plan's default budget of {} expansions; raise it with --max-expansions",
                    planner_runner::plan::DEFAULT_PLAN_EXPANSIONS
                );
            }
            Ok(())
        }
        Command::Serve { dir, port, host } => {
            // Serving writes nothing: a signal ends it at once, with status 130 (it was
            // killed by SIGTERM, status 143).
            stop_on_interrupt()?;
            let options = planner_serve::ServeOptions {
                host,
                ..planner_serve::ServeOptions::new(&dir, port)
            };
            planner_serve::serve(&options, |addr| {
                // Printed as soon as the port is bound, so a script can wait for the line.
                let line = format!("serving {} at http://{addr}/\n", dir.display());
                let _ = write_text(&line);
                if !addr.ip().is_loopback() {
                    to_stderr!(
                        "note: listening on {}, not only this machine: whoever reaches it can \
                         read the maps and results under {} and run planners here",
                        addr.ip(),
                        planner_text::one_line(&dir.display().to_string())
                    );
                }
            })?;
            Ok(())
        }
        Command::Planners { name: None } => {
            let mut out = String::new();
            for entry in planner_registry::PLANNERS {
                out.push_str(&format!("{:<20} {}\n", entry.name, entry.summary));
            }
            out.push_str("\n`gridplan planners <name>` lists a planner's parameters.\n");
            write_stdout(out.as_bytes())
        }
        Command::Planners { name: Some(name) } => write_stdout(describe_planner(&name)?.as_bytes()),
        Command::Schema => {
            let text = serde_json::to_string_pretty(&schema()?)?;
            write_stdout(format!("{text}\n").as_bytes())
        }
        Command::Completions { shell } => {
            let mut command = <Cli as clap::CommandFactory>::command();
            let mut script = Vec::new();
            clap_complete::generate(shell, &mut command, "gridplan", &mut script);
            if shell == clap_complete::Shell::Fish {
                script.extend(fish_positionals(&command).into_bytes());
            }
            write_stdout(&script)
        }
    }
}

/// The fish completions of the subcommands' positional arguments with possible values
/// (`planners NAME`, `completions SHELL`), which clap_complete's fish script leaves out
/// (it completes options only, and files for the rest).
fn fish_positionals(command: &clap::Command) -> String {
    let mut lines = String::new();
    for subcommand in command.get_subcommands() {
        for positional in subcommand.get_positionals() {
            let values: Vec<String> = positional
                .get_possible_values()
                .iter()
                .filter(|value| !value.is_hide_set())
                .map(|value| value.get_name().to_string())
                .collect();
            // Names of letters, digits, `_` and `-` only: nothing fish would expand.
            let plain = |name: &String| {
                name.bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b'_' || b == b'-')
            };
            if values.is_empty() || !values.iter().all(plain) {
                continue;
            }
            lines.push_str(&format!(
                "complete -c gridplan -n \"__fish_gridplan_using_subcommand {}\" -f -a \"{}\"\n",
                subcommand.get_name(),
                values.join(" ")
            ));
        }
    }
    lines
}

/// `gridplan schema`: the JSON Schema (draft 2020-12) of every config `experiment` runs,
/// one of the runner's experiment configs ([`planner_runner::schema::experiment_schema`],
/// with the report's sections and their options) and the replanning experiments' (`kind = "navigate"`
/// or `"dynamic"`, derived from planner-replan's config type). Each refuses the other's
/// keys (the runner's knows no `kind`, which the replanning one requires), so a config is
/// exactly one of them.
pub fn schema() -> Result<serde_json::Value, CliError> {
    let mut runner =
        planner_runner::schema::experiment_schema(&planner_paper::renderer().section_schemas())?;
    let mut replan =
        planner_registry::schema::parameters_of::<planner_replan::experiment::ExperimentConfig>()
            .to_value();
    planner_runner::schema::bound_unsigned(&mut replan);
    let mut draft = serde_json::Value::Null;
    for part in [&mut runner, &mut replan] {
        if let Some(object) = part.as_object_mut() {
            if let Some(url) = object.remove("$schema") {
                draft = url;
            }
        }
    }
    if let Some(object) = replan.as_object_mut() {
        object.insert(
            "title".into(),
            "gridplan replanning experiment config".into(),
        );
        object.insert(
            "description".into(),
            "A navigate or dynamic experiment of the incremental planners (configs/replan/README.md)."
                .into(),
        );
    }
    Ok(serde_json::json!({
        "$schema": draft,
        "title": "gridplan config",
        "description": "An experiment config: the runner's (configs/README.md) or a replanning experiment's (kind = \"navigate\" or \"dynamic\").",
        "oneOf": [runner, replan],
    }))
}

/// The widest map `plan` draws as text: the terminal's width when stdout is a terminal,
/// else [`planner_runner::plan::TEXT_COLUMNS`] (200).
fn text_columns() -> usize {
    let stdout = std::io::stdout();
    if std::io::IsTerminal::is_terminal(&stdout) {
        if let Some((terminal_size::Width(width), _)) = terminal_size::terminal_size_of(&stdout) {
            return usize::from(width);
        }
    }
    planner_runner::plan::TEXT_COLUMNS
}

/// Writes `bytes` (a command's whole output, written once at its end) to stdout. A closed
/// pipe (`gridplan planners | head -1`) is not an error: the reader has what it wanted, so
/// the command ends quietly with status 0, as `head`-style pipelines expect (a sweep's
/// results are on disk by then). Any other write error (a full disk, `>/dev/full`) is an
/// error, status 1.
fn write_stdout(bytes: &[u8]) -> Result<(), CliError> {
    use std::io::Write as _;
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(bytes).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(CliError::Stdout(e)),
        _ => Ok(()),
    }
}

/// [`write_stdout`] of text for a person, its control characters (but line breaks and tabs)
/// escaped ([`planner_text::terminal`]): labels, paths and map names come from configs.
fn write_text(text: &str) -> Result<(), CliError> {
    write_stdout(planner_text::terminal(text).as_bytes())
}

/// The jobs of `ids` that `squeue` still lists (pending, running, completing, ...), asked
/// one id at a time (squeue fails on a single id it no longer knows, which has left the
/// queue); `Err` says why squeue could not answer.
fn squeue(ids: &[String]) -> Result<Vec<String>, String> {
    let mut queued = Vec::new();
    for id in ids {
        let out = std::process::Command::new("squeue")
            .args(["--noheader", "--format=%i", "--jobs", id])
            .output()
            .map_err(|e| format!("cannot run squeue: {e}"))?;
        let stderr = String::from_utf8_lossy(&out.stderr);
        if !out.status.success() {
            if stderr.contains("Invalid job id") {
                continue;
            }
            return Err(format!("squeue --jobs {id} failed: {}", stderr.trim()));
        }
        // An array's tasks are listed as `55_1` or `55_[2-3]`.
        let listed = String::from_utf8_lossy(&out.stdout)
            .lines()
            .any(|line| line.trim().split('_').next() == Some(id.as_str()));
        if listed {
            queued.push(id.clone());
        }
    }
    Ok(queued)
}

/// Runs `sbatch --parsable ARGS` and returns the job id.
fn sbatch(args: &[String]) -> Result<String, SubmitError> {
    let out = std::process::Command::new("sbatch")
        .arg("--parsable")
        .args(args)
        .output()
        .map_err(SubmitError::Spawn)?;
    if !out.status.success() {
        return Err(SubmitError::Refused {
            args: args.join(" "),
            stderr: String::from_utf8_lossy(&out.stderr).trim().to_string(),
            max_array: None,
        });
    }
    let text = String::from_utf8_lossy(&out.stdout);
    // `--parsable` prints `id` or `id;cluster`.
    let id = text.trim().split(';').next().unwrap_or("").to_string();
    if id.is_empty() {
        return Err(SubmitError::NoJobId {
            args: args.join(" "),
        });
    }
    Ok(id)
}

/// `word` as a shell reads it back: bare when it holds only characters no shell treats
/// specially, else single-quoted ([`slurm::quote`]).
fn shell_word(word: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_./:=,+-@%".contains(c);
    if !word.is_empty() && word.chars().all(plain) {
        word.to_string()
    } else {
        slurm::quote(word)
    }
}

/// An array job that sbatch refused as an invalid array: more tasks than the cluster's
/// `MaxArraySize` allows (1001 by default: task ids 0 to 1000) is the likely cause, so
/// the error gives that limit, asked of `scontrol show config`, when it is known.
fn array_hint(mut error: SubmitError) -> SubmitError {
    let SubmitError::Refused {
        stderr, max_array, ..
    } = &mut error
    else {
        return error;
    };
    if stderr.contains("Invalid job array specification") {
        *max_array = std::process::Command::new("scontrol")
            .args(["show", "config"])
            .output()
            .ok()
            .and_then(|out| {
                String::from_utf8_lossy(&out.stdout)
                    .lines()
                    .find_map(|line| {
                        let (key, value) = line.split_once('=')?;
                        (key.trim() == "MaxArraySize").then(|| value.trim().parse::<u64>().ok())?
                    })
            });
    }
    error
}

/// The directories `shard-K` (K a decimal number) in `parent`, by K.
fn shard_dirs_in(parent: &std::path::Path) -> Result<Vec<PathBuf>, CliError> {
    let failed = |source: std::io::Error| CliError::ShardsIn {
        dir: parent.to_path_buf(),
        source,
    };
    let entries = std::fs::read_dir(parent).map_err(failed)?;
    let mut found = Vec::new();
    for entry in entries {
        let entry = entry.map_err(failed)?;
        let name = entry.file_name();
        let number = name
            .to_str()
            .and_then(|n| n.strip_prefix("shard-"))
            .filter(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
            .and_then(|k| k.parse::<u64>().ok());
        if let Some(k) = number {
            if entry.path().is_dir() {
                found.push((k, entry.path()));
            }
        }
    }
    if found.is_empty() {
        return Err(CliError::Usage(format!(
            "--shards-in {}: no shard-K directories in it",
            parent.display()
        )));
    }
    found.sort();
    Ok(found.into_iter().map(|(_, path)| path).collect())
}

/// `gridplan planners <name>`: the planner's summary, then each declared parameter as
/// `key: type = default`, its allowed values and its doc line.
pub fn describe_planner(name: &str) -> Result<String, CliError> {
    use std::fmt::Write as _;
    let entry = planner_registry::find(name).ok_or_else(|| RunnerError::UnknownPlanner {
        name: name.to_string(),
    })?;
    let task = match entry.task {
        planner_registry::Task::StartGoal => "start-goal",
        planner_registry::Task::Coverage => "coverage",
    };
    let mut out = format!("{} ({task}): {}\n", entry.name, entry.summary);
    let factory = (entry.factory)(&Default::default())?;
    let _ = writeln!(
        out,
        "with its defaults: {}",
        describe_specs(factory.specs())
    );
    let params = planner_registry::schema::declared(name)?;
    if params.is_empty() {
        out.push_str("no parameters\n");
    } else {
        let _ = writeln!(
            out,
            "parameters (a list of values in a config's planner table sweeps them):"
        );
    }
    for param in params {
        let default = param
            .default
            .as_ref()
            .map_or_else(|| "unset".to_string(), show_value);
        let _ = writeln!(out, "  {}: {} = {default}", param.key, param.kind);
        if !param.allowed.is_empty() {
            let allowed: Vec<String> = param.allowed.iter().map(show_value).collect();
            let _ = writeln!(out, "      one of: {}", allowed.join(", "));
        }
        if !param.doc.is_empty() {
            let _ = writeln!(out, "      {}", param.doc);
        }
    }
    Ok(out)
}

/// What a planner declares it is ([`planner_api::PlannerSpecs`]), in words: its paths'
/// rule, whether they are least-cost by design, seeded or not, cell costs, incremental.
fn describe_specs(specs: &planner_api::PlannerSpecs) -> String {
    let paths = format!("paths: {}", specs.path_rule);
    let optimal = match specs.admissible {
        Some(true) => "least-cost by design",
        Some(false) => "not least-cost (inadmissible on purpose)",
        None => "no optimality claim",
    };
    let seeded = match specs.seeded {
        true => "seeded",
        false => "deterministic",
    };
    let costs = match specs.cell_costs {
        true => "honours cell weights",
        false => "refuses weighted maps unless costs = \"ignore\"",
    };
    let mut words = vec![paths, optimal.into(), seeded.into(), costs.into()];
    if specs.incremental {
        words.push("incremental (repairs after map changes)".into());
    }
    words.join("; ")
}

/// A parameter value as a config writes it (TOML): strings quoted, numbers as they are.
fn show_value(value: &serde_json::Value) -> String {
    match value {
        serde_json::Value::Null => "unset".to_string(),
        other => other.to_string(),
    }
}
