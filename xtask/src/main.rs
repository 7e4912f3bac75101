//! `cargo xtask`: gridplan's command line (the `gridplan` commands) and the repository's
//! own tasks (`new-planner`, `gen-pastar-maps`).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

#[global_allocator]
static ALLOCATOR: planner_runner::alloc::Counting = planner_runner::alloc::Counting;

#[derive(Parser)]
#[command(
    name = "cargo xtask",
    version,
    about = "gridplan: sweep experiments, run one planner, add a planner"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

// The command line is parsed once per process: the user commands' size costs nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Subcommand)]
enum Command {
    #[command(flatten)]
    User(gridplan::Command),
    /// Scaffold crates/<name> and register it, ready to run.
    NewPlanner {
        /// Lowercase letters, digits and underscores: the directory and registry name.
        name: String,
    },
    /// Write seed 002's generated maps to maps/pastar/ (src/generate.rs documents them).
    GenPastarMaps,
}

fn main() -> ExitCode {
    gridplan::init_logging();
    // The lock files this process takes name it (the runner reads no process state).
    planner_runner::outdir::set_lock_holder(std::process::id());
    gridplan::exit(run(Cli::parse().command))
}

fn run(command: Command) -> Result<(), gridplan::CliError> {
    match command {
        Command::User(command) => gridplan::run(command),
        Command::NewPlanner { name } => {
            let root = workspace_root();
            let done = xtask::scaffold::new_planner(&root, &name).map_err(|e| match e {
                xtask::scaffold::ScaffoldError::Io { .. } => {
                    gridplan::CliError::Failed(e.to_string())
                }
                _ => gridplan::CliError::Usage(e.to_string()),
            })?;
            println!("created planner `{name}`:");
            for file in &done.files {
                println!("  {file}");
            }
            println!("next: edit crates/{name}/src/lib.rs, then `cargo test -p planner-{name}` and `cargo xtask experiment configs/{name}.toml`");
            Ok(())
        }
        Command::GenPastarMaps => {
            let written = xtask::write_pastar_maps(&workspace_root().join("maps/pastar"))
                .map_err(|e| gridplan::CliError::Failed(e.to_string()))?;
            for path in written {
                println!("{path}");
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
