//! gridplan's command line as a library: the `gridplan` binary and `cargo xtask` (which
//! adds the repository's own tasks) parse the same [`Command`]s and run them with [`run`].
//!
//! Everything a command does is planner-runner's ([`planner_runner::sweep`],
//! [`planner_runner::plan`], [`planner_runner::registry`]); this crate adds the argument
//! parsing, the progress bar and the log output.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use planner_api::Cell;
use planner_runner::plan::PlanArgs;
use planner_runner::{alloc, slurm, sweep};
use tracing_subscriber::EnvFilter;

/// The `gridplan` command line.
#[derive(Parser)]
#[command(
    name = "gridplan",
    version,
    about = "gridplan: sweep experiment configs over maps and planners, run one planner on one map"
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
        /// Worker threads (default: the config's `threads`, 0 = one per core).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Output directory (default: the config's `output`, else `results/<name>`).
        #[arg(long)]
        output: Option<PathBuf>,
        /// No progress bar.
        #[arg(long)]
        quiet: bool,
        /// Keep the runs an interrupted sweep on the same output recorded and run the rest
        /// (a changed config is refused).
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
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (default: the config's `output`).
        #[arg(long)]
        output: Option<PathBuf>,
        /// The config (default: the one the shards name).
        #[arg(long)]
        config: Option<PathBuf>,
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
        /// The map file (.map, .txt, .csv, or a ROS map_server .yaml).
        map: PathBuf,
        /// Registry name (astar, backtracking, ...), or a label of --config.
        #[arg(long)]
        planner: String,
        /// An experiment config whose planner labels --planner may name.
        #[arg(long)]
        config: Option<PathBuf>,
        /// Problem number (1-based) among the map's own pairs or its .scen file.
        #[arg(long)]
        problem: Option<usize>,
        /// Start cell as x,y.
        #[arg(long, value_parser = parse_cell)]
        start: Option<Cell>,
        /// Goal cell as x,y (not for coverage planners).
        #[arg(long, value_parser = parse_cell)]
        goal: Option<Cell>,
        /// Planner parameter override, key=value (repeatable), e.g. --set heuristic=octile.
        #[arg(long = "set")]
        set: Vec<String>,
        /// Expansion budget (default: the config label's, else 10,000,000, so every run ends).
        #[arg(long)]
        max_expansions: Option<u64>,
        /// The value of a .csv map's cell that is an obstacle: 0 (the default, seed 000's
        /// convention) or 1 (the common occupancy-grid convention).
        #[arg(long, value_parser = clap::value_parser!(u8).range(0..=1))]
        obstacle: Option<u8>,
        /// Print exactly one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// List the registered planners.
    Planners,
}

/// Parses `x,y` into a cell.
pub fn parse_cell(text: &str) -> Result<Cell, String> {
    let (x, y) = text
        .split_once(',')
        .ok_or_else(|| format!("{text:?}: expected x,y"))?;
    let number = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|e| format!("{text:?}: {s:?} is not a cell coordinate: {e}"))
    };
    Ok(Cell::new(number(x)?, number(y)?))
}

/// Sends `tracing` output to stderr, filtered by `RUST_LOG` (default: warnings), plain
/// text unless stderr is a terminal.
pub fn init_logging() {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_target(false)
        .without_time()
        .init();
}

/// The exit code of a command's result; prints the error.
pub fn exit(result: Result<(), String>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

/// The exit code of a command stopped by Ctrl-C (SIGINT): 128 + 2, as shells report it.
pub const EXIT_INTERRUPTED: u8 = 130;

/// Makes Ctrl-C (SIGINT) end the process at once with "interrupted" on stderr and exit
/// code [`EXIT_INTERRUPTED`]: for `plan`, which writes nothing, so stopping anywhere is
/// clean. A handler another command installed first is kept.
fn stop_on_interrupt() -> Result<(), String> {
    match ctrlc::set_handler(|| {
        eprintln!("interrupted");
        std::process::exit(i32::from(EXIT_INTERRUPTED));
    }) {
        Ok(()) | Err(ctrlc::Error::MultipleHandlers) => Ok(()),
        Err(error) => Err(format!("cannot handle Ctrl-C: {error}")),
    }
}

/// A sweep's progress bar on stderr (hidden when stderr is not a terminal).
#[derive(Default)]
struct Bar(std::sync::OnceLock<ProgressBar>);

impl sweep::Progress for Bar {
    fn start(&self, total: u64, done: u64) {
        let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs ({eta})",
        ) {
            bar.set_style(style);
        }
        bar.set_position(done);
        let _ = self.0.set(bar);
    }

    fn set(&self, done: u64) {
        if let Some(bar) = self.0.get() {
            bar.set_position(done);
        }
    }

    fn finish(&self) {
        if let Some(bar) = self.0.get() {
            bar.finish_and_clear();
        }
    }
}

/// Runs one user command.
pub fn run(command: Command) -> Result<(), String> {
    match command {
        Command::Experiment {
            config,
            threads,
            output,
            quiet,
            resume,
            shard,
        } => {
            let shard = match shard {
                Some(text) => Some(planner_runner::shard::Shard::parse(&text)?),
                None => planner_runner::shard::Shard::from_env(|k| std::env::var(k).ok())?,
            };
            let bar = Bar::default();
            let report = sweep::experiment(&sweep::SweepArgs {
                config: &config,
                threads,
                output: output.as_deref(),
                progress: (!quiet).then_some(&bar as &dyn sweep::Progress),
                heap: Some(&alloc::Meter),
                resume,
                shard,
            })?;
            println!(
                "{} runs in {:.2} s -> {}",
                report.n_runs,
                report.seconds,
                report.output.display()
            );
            if report.reproduction.compared > 0 {
                println!(
                    "published numbers reproduced: {} of {}",
                    report.reproduction.matched, report.reproduction.compared
                );
            }
            Ok(())
        }
        Command::Merge {
            dirs,
            output,
            config,
        } => {
            let report = sweep::merge(&dirs, output.as_deref(), config.as_deref())?;
            println!(
                "{} runs merged from {} shards -> {}",
                report.n_runs,
                dirs.len(),
                report.output.display()
            );
            Ok(())
        }
        Command::Slurm {
            config,
            shards,
            output,
            partition,
            time,
            cpus_per_task,
            submit,
        } => {
            let jobs = slurm::slurm(&slurm::SlurmArgs {
                config,
                shards,
                output,
                partition,
                time,
                cpus_per_task,
                submit,
            })?;
            println!("array script: {}", jobs.array_script.display());
            println!("merge script: {}", jobs.merge_script.display());
            if let Some((array, merge)) = jobs.ids {
                println!("array job {array}");
                println!("merge job {merge}");
            }
            Ok(())
        }
        Command::Plan {
            map,
            planner,
            config,
            problem,
            start,
            goal,
            set,
            max_expansions,
            obstacle,
            json,
        } => {
            stop_on_interrupt()?;
            let args = PlanArgs {
                map,
                planner,
                config,
                problem,
                start,
                goal,
                set,
                max_expansions,
                obstacle: obstacle.and_then(planner_maps::CsvConvention::from_obstacle_value),
            };
            let result = planner_runner::plan::run(&args).map_err(|e| e.to_string())?;
            if json {
                println!("{}", result.to_json().map_err(|e| e.to_string())?);
            } else {
                print!("{}", result.to_text());
            }
            if result.hit_default_budget() {
                eprintln!(
                    "note: stopped at plan's default budget of {} expansions; raise it with --max-expansions",
                    planner_runner::plan::DEFAULT_PLAN_EXPANSIONS
                );
            }
            Ok(())
        }
        Command::Planners => {
            for entry in planner_runner::registry::PLANNERS {
                println!("{:<20} {}", entry.name, entry.summary);
            }
            Ok(())
        }
    }
}
