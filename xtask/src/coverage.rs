//! Coverage planners in the runner (seed 004): one run, its figures, the summary table.
//!
//! A coverage run covers from the problem's start and ignores its goal (a
//! `problems = "start"` map set sets the goal to the start). Its record holds the coverage
//! path (fill moves are 4-connected, A* returns 8-connected; `valid` checks every step
//! against the 8-connected move set without corner cutting), the path metrics, the
//! planner's counters (coverage, revisits, backtracking points, turns, return
//! expansions...) and the return legs.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use planner_api::{Cell, Connectivity, CoverageProblem, Grid, MoveSet, Path, PathRule};
use planner_figures::{draw_comparison, draw_timeline, Layer, Layout, Marker, Style};

use crate::alloc;
use crate::config::{Experiment, PlannerSpec};
use crate::output::OutputFile;
use crate::run::RunRecord;

/// Runs the coverage planner `spec` from `start` on `grid` and fills `record` (status,
/// path metrics, validity, counters, path, returns, time and peak heap). A start that is
/// blocked or outside the grid leaves the record as the caller made it.
pub fn run(
    grid: &Grid,
    start: Cell,
    spec: &PlannerSpec,
    record: &mut RunRecord,
) -> Result<(), String> {
    let Ok(problem) = CoverageProblem::new(grid, start) else {
        return Ok(());
    };
    let baseline = alloc::start();
    let mut planner = spec
        .build_coverage()
        .map_err(|e| format!("planner `{}`: {e}", spec.label))?;
    let started = Instant::now();
    let outcome = planner.cover(&problem, &spec.budget);
    record.time_ms = started.elapsed().as_secs_f64() * 1e3;
    drop(planner);
    record.peak_heap_bytes = alloc::peak_since_start(baseline);
    record.status = outcome.status.as_str().into();
    let m = outcome.metrics.path;
    record.steps = Some(m.steps);
    record.turns = Some(m.turns);
    record.score = Some(m.score);
    record.length = Some(m.length);
    let eight = MoveSet::standard(Connectivity::Eight);
    let valid = outcome.path.start() == Some(start)
        && outcome.path.validate(grid, PathRule::Moves(&eight)).is_ok();
    if !valid {
        tracing::warn!("the coverage planner returned an invalid path");
    }
    record.valid = Some(valid);
    record.counters = outcome.counters;
    record.path = Some(outcome.path);
    record.returns = Some(outcome.returns);
    Ok(())
}

/// The figures of one coverage run, `<base>.svg` and `<base>-returns.svg`: the path
/// coloured by time with the backtracking points returned to marked `B1`, `B2`, ... in
/// order (like seed 004's Figs. 7-8), and the path with each A* return drawn over it.
pub fn figures(grid: &Grid, run: &RunRecord, base: &str, style: &Style) -> Vec<OutputFile> {
    let Some(path) = &run.path else {
        return Vec::new();
    };
    let legs = run.returns.as_deref().unwrap_or_default();
    let cells = path.cells();
    let markers: Vec<Marker> = legs
        .iter()
        .enumerate()
        .filter_map(|(i, leg)| {
            cells.get(leg.end).map(|&cell| Marker {
                cell,
                label: format!("B{}", i + 1),
            })
        })
        .collect();
    let covered = match (
        run.counters.get("n_covered"),
        run.counters.get("n_reachable"),
    ) {
        (Some(c), Some(r)) if r > 0 => format!("{:.1} %", 100.0 * c as f64 / r as f64),
        _ => "-".into(),
    };
    let title = format!(
        "{} on {}: {} covered, {} backtracking points, {} moves",
        run.planner,
        run.map,
        covered,
        legs.len(),
        run.steps.unwrap_or(0)
    );
    let mut files = vec![OutputFile {
        path: PathBuf::from(format!("{base}.svg")),
        contents: draw_timeline(grid, path, &markers, &title, style).into_bytes(),
    }];

    let segments: Vec<(String, Path, String)> = legs
        .iter()
        .enumerate()
        .filter_map(|(i, leg)| {
            let part = cells.get(leg.start..=leg.end)?;
            let segment = Path::new(part.to_vec());
            let note = format!(
                "A* {} -> {}, length {:.2}",
                part[0],
                part[part.len() - 1],
                segment.metrics().length
            );
            Some((format!("return {}", i + 1), segment, note))
        })
        .collect();
    let mut layers = vec![Layer::new(&run.planner, Some(path), "coverage path")];
    layers.extend(
        segments
            .iter()
            .map(|(label, segment, note)| Layer::new(label, Some(segment), note.clone())),
    );
    let overlay = Style {
        layout: Layout::Overlay,
        ..style.clone()
    };
    let start = path.start().unwrap_or_default();
    let title = format!("{} on {}: A* returns", run.planner, run.map);
    files.push(OutputFile {
        path: PathBuf::from(format!("{base}-returns.svg")),
        contents: draw_comparison(grid, start, start, &layers, &title, &overlay).into_bytes(),
    });
    files
}

/// The coverage table of `summary.md`: one row per map, problem and coverage planner;
/// empty when the experiment has no coverage planner.
pub fn summary(experiment: &Experiment, records: &[RunRecord]) -> String {
    let planners: Vec<&PlannerSpec> = experiment.planners.iter().filter(|p| p.coverage).collect();
    if planners.is_empty() {
        return String::new();
    }
    let mut out = String::from("## Coverage (seed 004)\n\n");
    out.push_str("Coverage is covered / reachable free cells (4-connected to the start); backtracking points are the returns to one (seed 004 Fig. 8 counts three for spiral and two for zigzag on its map); marked are all points ever marked; length is the Euclidean length of the whole path; A* expansions are those of the returns.\n\n");
    out.push_str("| Map | Start | Planner | Status | Coverage | Reachable | Backtracking points | Marked | Moves | Length | Turns | Revisits | Return moves | A* expansions |\n|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
    for map in &experiment.maps {
        for problem in &map.problems {
            for planner in &planners {
                let Some(r) = records.iter().find(|r| {
                    r.map == map.name
                        && r.problem == problem.index
                        && r.planner == planner.label
                        && r.repeat == 0
                }) else {
                    continue;
                };
                let c = |name: &str| {
                    r.counters
                        .get(name)
                        .map_or_else(|| "-".to_string(), |v| v.to_string())
                };
                let coverage = match (r.counters.get("n_covered"), r.counters.get("n_reachable")) {
                    (Some(covered), Some(reachable)) if reachable > 0 => {
                        format!("{:.1} %", 100.0 * covered as f64 / reachable as f64)
                    }
                    _ => "-".into(),
                };
                let _ = writeln!(
                    out,
                    "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                    map.name,
                    problem.start,
                    planner.label,
                    r.status,
                    coverage,
                    c("n_reachable"),
                    c("n_backtracking_points"),
                    c("n_marked_points"),
                    r.steps.map_or("-".into(), |v| v.to_string()),
                    r.length.map_or("-".into(), |v| format!("{v:.2}")),
                    c("n_turns"),
                    c("n_revisits"),
                    c("n_return_moves"),
                    c("n_return_expansions"),
                );
            }
        }
    }
    out.push('\n');
    out
}
