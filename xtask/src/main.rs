//! `cargo xtask`: gridplan's command line.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use planner_api::Cell;
use planner_runner::plan::PlanArgs;
use tracing_subscriber::EnvFilter;

#[derive(Parser)]
#[command(
    name = "cargo xtask",
    about = "gridplan: sweep experiments, run one planner, add a planner"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run an experiment config: every map x problem x planner x repeat, in parallel.
    Experiment {
        /// The TOML config, e.g. configs/paper.toml (keys: configs/README.md).
        config: PathBuf,
        /// Worker threads (default: the config's `threads`, 0 = one per core).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Output directory (default: the config's `output`, else results/<name>).
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
        /// Print exactly one JSON object.
        #[arg(long)]
        json: bool,
    },
    /// Scaffold crates/<name> and register it, ready to run.
    NewPlanner {
        /// Lowercase letters and digits: the directory and registry name.
        name: String,
    },
    /// List the registered planners.
    Planners,
    /// Write seed 002's generated maps to maps/pastar/ (src/generate.rs documents them).
    GenPastarMaps,
}

fn parse_cell(text: &str) -> Result<Cell, String> {
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

fn main() -> ExitCode {
    tracing_subscriber::fmt()
        .with_env_filter(
            EnvFilter::try_from_default_env().unwrap_or_else(|_| EnvFilter::new("warn")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_target(false)
        .without_time()
        .init();
    match run(Cli::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.command {
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
            let report = xtask::sweep::experiment(&xtask::sweep::SweepArgs {
                config,
                threads,
                output,
                progress: !quiet,
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
            let report = xtask::sweep::merge(&dirs, output.as_deref(), config.as_deref())?;
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
            let jobs = xtask::slurm::slurm(&xtask::slurm::SlurmArgs {
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
            json,
        } => {
            let args = PlanArgs {
                map,
                planner,
                config,
                problem,
                start,
                goal,
                set,
                max_expansions,
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
        Command::NewPlanner { name } => {
            let root = workspace_root();
            let done = xtask::scaffold::new_planner(&root, &name)?;
            println!("created planner `{name}`:");
            for file in &done.files {
                println!("  {file}");
            }
            println!("next: edit crates/{name}/src/lib.rs, then `cargo test -p planner-{name}` and add it to a config under [planners]");
            Ok(())
        }
        Command::GenPastarMaps => {
            for path in xtask::write_pastar_maps(&workspace_root().join("maps/pastar"))? {
                println!("{path}");
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

/// The workspace root: the parent of this crate's directory.
fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."))
}
