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
        /// The directory and registry name: 2 to 64 lowercase letters, digits and single
        /// underscores, starting with a letter and not ending with `_`; not a Rust keyword,
        /// a crate of the workspace or a registered planner. Writes crates/<name>/,
        /// configs/<name>.toml, and edits crates/registry and ARCHITECTURE.md.
        name: String,
    },
    /// Write seed 002's generated maps to maps/pastar/ (src/generate.rs documents them).
    GenPastarMaps,
}

fn main() -> ExitCode {
    gridplan::init_logging();
    // The lock files this process takes name it (the runner reads no process state).
    planner_runner::outdir::set_lock_holder(std::process::id());
    match run(Cli::parse().command) {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => gridplan::fail(&error, error.exit_code()),
    }
}

/// Why a task failed.
#[derive(Debug, thiserror::Error)]
enum XtaskError {
    /// A `gridplan` command's error.
    #[error(transparent)]
    Cli(#[from] gridplan::CliError),
    /// `new-planner` refused the name or could not write the crate.
    #[error(transparent)]
    Scaffold(#[from] xtask::scaffold::ScaffoldError),
    /// `gen-pastar-maps` could not write a map.
    #[error(transparent)]
    Maps(#[from] xtask::WriteError),
}

impl XtaskError {
    /// The exit status, as `gridplan`'s: a bad name is a usage error, a failed write 1.
    fn exit_code(&self) -> u8 {
        match self {
            XtaskError::Cli(error) => error.exit_code(),
            XtaskError::Scaffold(xtask::scaffold::ScaffoldError::Io { .. })
            | XtaskError::Maps(_) => gridplan::EXIT_FAILURE,
            XtaskError::Scaffold(_) => gridplan::EXIT_USAGE,
        }
    }
}

fn run(command: Command) -> Result<(), XtaskError> {
    match command {
        Command::User(command) => Ok(gridplan::run(command)?),
        Command::NewPlanner { name } => {
            let root = workspace_root();
            let done = xtask::scaffold::new_planner(&root, &name)?;
            println!("created planner `{name}`:");
            for file in &done.files {
                println!("  {file}");
            }
            if !done.formatted {
                println!("rustfmt did not run: `cargo fmt` formats the new files");
            }
            println!("next: replace the search in crates/{name}/src/lib.rs and its one-line summary in crates/registry/src/lib.rs and ARCHITECTURE.md, then `cargo test -p planner-{name}` and `cargo xtask experiment configs/{name}.toml`");
            Ok(())
        }
        Command::GenPastarMaps => {
            let written = xtask::write_pastar_maps(&workspace_root().join("maps/pastar"))?;
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
