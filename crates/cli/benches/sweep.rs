//! The runner's overhead on many short queries: `configs/bench/arena-repeats.toml` (arena's
//! 160 scenarios x 100 repeats of 8-connected A*) swept by `run_all`, against the same
//! queries planned in a plain loop with one reused planner, in the same process.
//!
//! `cargo bench -p gridplan --bench sweep` prints, per phase, the wall time, and the
//! sum of the records' `time_ms` (the search alone) beside the plain loop's time.

use std::path::Path;
use std::time::Instant;

use planner_api::{Budget, Planner, Problem};
use planner_report::figures;
use planner_runner::expanded::ExpandedCells;
use planner_runner::{config, output, run_all, RunOptions};

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let path = root.join("configs/bench/arena-repeats.toml");
    let threads: usize = std::env::args()
        .find_map(|a| a.strip_prefix("--threads=").and_then(|n| n.parse().ok()))
        .unwrap_or(2);

    let t = Instant::now();
    let experiment = config::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let load = t.elapsed();

    let t = Instant::now();
    let options = RunOptions {
        threads,
        ..Default::default()
    };
    let records = run_all(&experiment, &options).unwrap_or_else(|e| panic!("{e}"));
    let sweep = t.elapsed();

    let t = Instant::now();
    let (summary, _) = planner_paper::renderer()
        .summary(&experiment, &records)
        .unwrap_or_else(|e| panic!("{e}"));
    let summary_time = t.elapsed();
    let t = Instant::now();
    let json = output::runs_json(&experiment, &records).unwrap_or_else(|e| panic!("{e}"));
    let json_time = t.elapsed();
    let t = Instant::now();
    let csv = output::runs_csv(&records);
    let csv_time = t.elapsed();
    let t = Instant::now();
    let n_figures = figures::render(&experiment, &records, &ExpandedCells::default()).len();
    let figures_time = t.elapsed();

    let time_ms: f64 = records.iter().map(|r| r.time_ms).sum();
    let setup_ms: f64 = records.iter().map(|r| r.setup_ms).sum();
    let expansions: u64 = records
        .iter()
        .filter_map(|r| r.counters.get("n_expanded"))
        .sum();

    // The same queries, one reused planner, one thread, timed as a whole.
    let map = &experiment.maps[0];
    let params = experiment.planners[0].params.clone();
    let config: planner_astar::Config = params.try_into().unwrap_or_else(|e| panic!("{e}"));
    let mut astar = planner_astar::AStar::new(config).unwrap_or_else(|e| panic!("{e}"));
    astar.prepare(&map.grid);
    let mut loop_expansions = 0u64;
    let t = Instant::now();
    for _ in 0..experiment.repeats {
        for p in &map.problems {
            let problem =
                Problem::new(&map.grid, p.start, p.goal).unwrap_or_else(|e| panic!("{e}"));
            let outcome = astar.plan(&problem, &Budget::unlimited());
            loop_expansions += outcome.counters.get("n_expanded").unwrap_or(0);
        }
    }
    let plain = t.elapsed();

    println!(
        "runs={} threads={threads} expansions={expansions} loop_expansions={loop_expansions}",
        records.len()
    );
    println!(
        "load_ms={:.1} sweep_ms={:.1} summary_ms={:.1} json_ms={:.1} ({} bytes) csv_ms={:.1} ({} bytes) figures_ms={:.1} ({n_figures} files, summary {} bytes)",
        load.as_secs_f64() * 1e3,
        sweep.as_secs_f64() * 1e3,
        summary_time.as_secs_f64() * 1e3,
        json_time.as_secs_f64() * 1e3,
        json.len(),
        csv_time.as_secs_f64() * 1e3,
        csv.len(),
        figures_time.as_secs_f64() * 1e3,
        summary.len(),
    );
    println!(
        "sum_time_ms={time_ms:.1} sum_setup_ms={setup_ms:.1} plain_loop_ms={:.1} ratio={:.2}",
        plain.as_secs_f64() * 1e3,
        time_ms / (plain.as_secs_f64() * 1e3)
    );
}
