//! gridplan's task runner as a library: the `cargo xtask` binary and the snapshot tests
//! share it.
//!
//! - [`config`]: experiment configs (TOML) with positioned errors.
//! - [`registry`]: the one list of planners.
//! - [`run`]: expansion into runs and the parallel sweep.
//! - [`output`]: runs.csv and runs.json.
//! - [`outdir`]: the results directory: its marker, its lock and the atomic swap.
//! - [`summary`]: summary.md in the seeds' table layouts.
//! - [`figures`]: the SVG figures of a sweep.
//! - [`coverage`]: coverage planners' runs, figures and summary table (seed 004).
//! - [`generate`]: `cargo xtask gen-pastar-maps`, seed 002's maps.
//! - [`pastar_summary`]: seed 002's tables in summary.md (R_length, R_time, timing tests).
//! - [`plan`]: `cargo xtask plan`, one run printed.
//! - [`scaffold`]: `cargo xtask new-planner`.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod alloc;
pub mod config;
pub mod coverage;
pub mod figures;
pub mod generate;
pub mod outdir;
pub mod output;
pub mod pastar_summary;
pub mod plan;
pub mod registry;
pub mod run;
pub mod scaffold;
pub mod summary;

use std::path::Path;
use std::time::Instant;

use output::OutputFile;

#[global_allocator]
static ALLOCATOR: alloc::Counting = alloc::Counting;

/// What `experiment` did.
#[derive(Debug, Clone)]
pub struct Report {
    /// Runs done.
    pub n_runs: usize,
    /// Output directory written.
    pub output: std::path::PathBuf,
    /// Published numbers compared and matched.
    pub reproduction: summary::Reproduction,
    /// Wall time of the sweep and the writing, in seconds.
    pub seconds: f64,
}

/// Runs the experiment in `config` and writes its results directory.
///
/// `threads = 0` takes the config's setting; `output` overrides the config's directory.
pub fn experiment(
    config: &Path,
    threads: usize,
    output: Option<&Path>,
    progress: bool,
) -> Result<Report, String> {
    let started = Instant::now();
    let experiment = config::load(config).map_err(|e| e.to_string())?;
    let dir = output.map_or_else(|| experiment.output.clone(), Path::to_path_buf);
    outdir::check(&dir).map_err(|e| e.to_string())?;
    tracing::info!(experiment = %experiment.name, runs = experiment.n_runs(), "sweep");
    let records = run::run_all(&experiment, threads, progress)?;
    let (summary, reproduction) = summary::render(&experiment, &records);
    let files = vec![
        OutputFile {
            path: "runs.json".into(),
            contents: output::runs_json(&experiment, &records)?,
        },
        OutputFile {
            path: "runs.csv".into(),
            contents: output::runs_csv(&records),
        },
        OutputFile {
            path: "summary.md".into(),
            contents: summary.into_bytes(),
        },
    ];
    let mut files = files;
    files.extend(figures::render(&experiment, &records));
    outdir::write_results(&dir, &experiment.name, &files, outdir::DEFAULT_LOCK_WAIT)
        .map_err(|e| e.to_string())?;
    Ok(Report {
        n_runs: records.len(),
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
    })
}
