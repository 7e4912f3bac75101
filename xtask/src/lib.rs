//! `cargo xtask`: the command-line front of planner-runner, and the repository's tasks.
//!
//! The runner (configs, registry, sweeps, reports) is the `planner-runner` library; this
//! crate adds what a binary owns: the counting allocator behind the runner's peak-heap
//! hook ([`alloc`]), the progress bar, writing the results directory safely ([`outdir`]:
//! its marker, its lock and the atomic swap), and the
//! repository's own tasks: `new-planner` ([`scaffold`]) and `gen-pastar-maps`
//! ([`write_pastar_maps`]).
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod alloc;
pub mod outdir;
pub mod scaffold;

use std::path::{Path, PathBuf};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use planner_runner::output::OutputFile;
use planner_runner::provenance::Provenance;
use planner_runner::report::Reproduction;
use planner_runner::{
    charts, config, figures, html, ompl, output as results, report, run_all, RunOptions,
};

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
    let bar = if progress {
        let bar =
            ProgressBar::with_draw_target(Some(experiment.n_runs()), ProgressDrawTarget::stderr());
        if let Ok(style) = ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs ({eta})",
        ) {
            bar.set_style(style);
        }
        bar
    } else {
        ProgressBar::hidden()
    };
    let tick = |done: u64| bar.set_position(done);
    let options = RunOptions {
        threads,
        progress: Some(&tick),
        heap: Some(&alloc::Meter),
    };
    let records = run_all(&experiment, &options).map_err(|e| e.to_string())?;
    bar.finish_and_clear();
    let provenance = Provenance::collect(config, rayon_threads(threads, experiment.threads));
    let (summary, reproduction) = report::render_with(&experiment, &records, Some(&provenance));
    let mut files = vec![
        OutputFile {
            path: "runs.json".into(),
            contents: results::runs_json_with(&experiment, &records, Some(&provenance))
                .map_err(|e| e.to_string())?,
        },
        OutputFile {
            path: "runs.csv".into(),
            contents: results::runs_csv(&records),
        },
        OutputFile {
            path: "summary.md".into(),
            contents: summary.clone().into_bytes(),
        },
    ];
    files.extend(figures::render(&experiment, &records));
    files.extend(charts::render(&experiment, &records));
    let page = html::report_html(&experiment.name, &summary, &files);
    files.push(OutputFile {
        path: "report.html".into(),
        contents: page.into_bytes(),
    });
    if experiment.ompl {
        let seconds = started.elapsed().as_secs_f64();
        files.extend(ompl::logs(&experiment, &records, &provenance, seconds));
    }
    outdir::write_results(&dir, &experiment.name, &files, outdir::DEFAULT_LOCK_WAIT)
        .map_err(|e| e.to_string())?;
    Ok(Report {
        n_runs: records.len(),
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The worker count a sweep ran with: the argument, else the config's, else one per core.
fn rayon_threads(argument: usize, configured: usize) -> usize {
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
