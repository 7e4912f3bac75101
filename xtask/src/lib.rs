//! `cargo xtask`: the command-line front of planner-runner, and the repository's tasks.
//!
//! The runner (configs, registry, sweeps, reports) is the `planner-runner` library; this
//! crate adds what a binary owns: the counting allocator behind the runner's peak-heap
//! hook ([`alloc`]), the progress bar, writing the results directory safely ([`outdir`]:
//! its marker, its lock and the atomic swap), streamed, resumable and sharded sweeps and
//! their merge ([`sweep`]), Slurm job-array scripts ([`slurm`]), and the
//! repository's own tasks: `new-planner` ([`scaffold`]) and `gen-pastar-maps`
//! ([`write_pastar_maps`]).
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod alloc;
pub mod outdir;
pub mod scaffold;
pub mod slurm;
pub mod sweep;

use std::path::{Path, PathBuf};

use planner_runner::report::Reproduction;

#[global_allocator]
static ALLOCATOR: alloc::Counting = alloc::Counting;

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
}

/// Runs the experiment in `config` and writes its results directory (a streamed sweep,
/// not resumed, not sharded: [`sweep::experiment`] does the rest).
///
/// `threads = 0` takes the config's setting; `output` overrides the config's directory.
pub fn experiment(
    config: &Path,
    threads: usize,
    output: Option<&Path>,
    progress: bool,
) -> Result<Report, String> {
    sweep::experiment(&sweep::SweepArgs {
        config: config.to_path_buf(),
        threads,
        output: output.map(Path::to_path_buf),
        progress,
        ..Default::default()
    })
}

/// The worker count a sweep ran with: the argument, else the config's, else one per core.
pub(crate) fn rayon_threads(argument: usize, configured: usize) -> usize {
    match (argument, configured) {
        (0, 0) => std::thread::available_parallelism().map_or(1, |n| n.get()),
        (0, c) => c,
        (a, _) => a,
    }
}

/// Writes seed 002's generated maps ([`planner_pastar::generate::specs`]) to `dir` as
/// Moving AI `.map` files; returns the paths.
pub fn write_pastar_maps(dir: &Path) -> Result<Vec<String>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut written = Vec::new();
    for map in planner_pastar::generate::specs() {
        let path = dir.join(map.name);
        std::fs::write(&path, planner_maps::to_movingai(&map.grid))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path.display().to_string());
    }
    Ok(written)
}
