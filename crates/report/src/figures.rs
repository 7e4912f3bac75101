//! The SVG figures of a sweep, drawn with planner-figures.
//!
//! `figures/<map>-<problem>.svg` puts every planner's path on one map side by side (small
//! maps) or overlaid (large ones), like seed 000's Figs. 7-18 and seed 002's Figs. 12-18;
//! with `figures = "all"`, `figures/<map>-<problem>-<planner>.svg` draws each run alone with
//! step indices and direction arrows. Repeat 0 is drawn. `figures_pick` chooses the
//! problems: the first `figures_per_map`, the hardest, or one per scenario bucket.
//!
//! With `figures_expanded = true`, each drawn (map, problem, label) is run once more with
//! [`planner_api::Budget::record_expanded`] on, apart from the timed runs (whose records
//! stay as they were), and its counters, status and path must equal the timed repeat 0's:
//! a difference is a determinism bug and an error ([`FigureError::Mismatch`]; not
//! checked for budgets with a wall-clock limit, whose counters depend on the machine).
//! `figures/<map>-<problem>-expanded.svg` then draws one panel per planner with its
//! expanded cells in a light fill under its path and their number in its legend (planners
//! that record none say so), and the per-run figures of `figures = "all"` draw them too.
//! The comparison figures stay as they are. [`draw_run`] draws one run's figure, for
//! `plan --svg`.

use planner_api::{Cell, Grid, Problem};
use planner_figures::{draw_comparison, draw_path, Layer, Style};

use crate::config::{Experiment, FigureMode, FigurePick, MapEntry, PlannerSpec, ProblemEntry};
use crate::factory::Built;
use crate::index::ResultsIndex;
use crate::output::OutputFile;
use crate::record::{RunRecord, RunStatus};

/// Why the figures with expanded cells could not be drawn.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    /// The run with recording on did not repeat the timed run.
    #[error(
        "{label} on {map} problem {problem}: the run recording expanded cells gave \
         {recorded}, the timed run {timed}; runs must be deterministic (a bug)"
    )]
    Mismatch {
        /// The planner label.
        label: String,
        /// The map file name.
        map: String,
        /// The 1-based problem.
        problem: usize,
        /// The timed run's status and counters.
        timed: String,
        /// The recording run's status and counters.
        recorded: String,
    },
    /// The planner could not be built again (its config built for the timed run).
    #[error("planner `{0}`: {1}")]
    Build(String, planner_api::ParamError),
}

/// The style of the figures with expanded cells: up to 1800 pixels a side, so that a
/// panel per planner keeps the cells of a 512 x 512 map visible.
fn expanded_style() -> Style {
    Style {
        max_px: 1800.0,
        ..Style::default()
    }
}

/// Runs `planner` on `problem` of `map` again with [`planner_api::Budget::record_expanded`]
/// on (with the seed and budget of `timed`'s run) and returns the expanded cells, after
/// checking that status, counters and path equal `timed`'s. Coverage planners and
/// invalid problems give none.
pub fn record_expanded(
    experiment: &Experiment,
    map: &MapEntry,
    problem: &ProblemEntry,
    planner: &PlannerSpec,
    timed: &RunRecord,
) -> Result<Vec<Cell>, FigureError> {
    let Ok(query) = Problem::new(&map.grid, problem.start, problem.goal) else {
        return Ok(Vec::new());
    };
    let built = planner
        .factory
        .build()
        .map_err(|e| FigureError::Build(planner.label.clone(), e))?;
    let Built::Path(mut p) = built else {
        return Ok(Vec::new());
    };
    p.prepare(&map.grid);
    if let Some(seed) = planner.factory.seed_for(experiment.seed, timed.repeat) {
        p.reseed(seed);
    }
    let budget = crate::run::effective_budget(planner).recording_expanded(true);
    let outcome = p.plan(&query, &budget);
    let same = RunStatus::from(outcome.status) == timed.status
        && outcome.counters == timed.counters
        // Records keep paths only as `paths` says: compare a kept one.
        && (timed.path.is_none() || outcome.path == timed.path);
    if !same && budget.max_time.is_none() {
        return Err(FigureError::Mismatch {
            label: planner.label.clone(),
            map: map.name.clone(),
            problem: problem.index,
            timed: format!("{} {}", timed.status, timed.counters),
            recorded: format!("{} {}", outcome.status.as_str(), outcome.counters),
        });
    }
    Ok(outcome.expanded)
}

/// One run's figure as an SVG document: the grid, the run's path with step indices and
/// arrows, its marks, and `expanded` (the cells it expanded, from
/// [`planner_api::Outcome::expanded`]; empty for none) in a light fill under the path
/// with their number in the legend. The title names the planner label, the map and the
/// problem; the legend gives the status and D, T, Score and length.
pub fn draw_run(grid: &Grid, record: &RunRecord, expanded: &[Cell]) -> String {
    let title = format!(
        "{} on {} problem {}: {} -> {}",
        record.planner, record.map, record.problem, record.start, record.goal
    );
    let layer = layer(record).with_expanded(expanded);
    draw_path(
        grid,
        record.start,
        record.goal,
        &layer,
        &title,
        &expanded_style(),
    )
}

/// The figure files of `records`. With `figures_expanded`, a recording run that does not
/// repeat its timed run is logged as an error and the figures are drawn without expanded
/// cells; [`render_checked`] returns the error instead.
pub fn render(experiment: &Experiment, records: &[RunRecord]) -> Vec<OutputFile> {
    match render_checked(experiment, records) {
        Ok(files) => files,
        Err(e) => {
            tracing::error!("{e}; figures drawn without expanded cells");
            render_with(experiment, records, false).unwrap_or_default()
        }
    }
}

/// The figure files of `records`, or the error of a recording run (`figures_expanded`)
/// that did not repeat its timed run.
pub fn render_checked(
    experiment: &Experiment,
    records: &[RunRecord],
) -> Result<Vec<OutputFile>, FigureError> {
    render_with(experiment, records, experiment.figures_expanded)
}

fn render_with(
    experiment: &Experiment,
    records: &[RunRecord],
    with_expanded: bool,
) -> Result<Vec<OutputFile>, FigureError> {
    let mut files = Vec::new();
    if experiment.figures == FigureMode::None {
        return Ok(files);
    }
    let style = Style::default();
    let index = ResultsIndex::new(records);
    for map in &experiment.maps {
        let stem = map
            .name
            .rsplit_once('.')
            .map_or(map.name.as_str(), |(s, _)| s);
        let limit = experiment.figures_per_map.unwrap_or(usize::MAX);
        for problem in pick(&map.problems, experiment.figures_pick, limit) {
            if problem.invalid.is_some() {
                continue;
            }
            let (specs, runs): (Vec<&PlannerSpec>, Vec<&RunRecord>) = experiment
                .planners
                .iter()
                .filter_map(|p| Some((p, index.first(&map.name, problem.index, &p.label)?)))
                .unzip();
            let expanded: Vec<Vec<Cell>> = if with_expanded {
                specs
                    .iter()
                    .zip(&runs)
                    .map(|(spec, run)| record_expanded(experiment, map, problem, spec, run))
                    .collect::<Result<_, _>>()?
            } else {
                Vec::new()
            };
            let layers: Vec<Layer<'_>> = runs.iter().map(|r| layer(r)).collect();
            let title = format!(
                "{} problem {}: {} -> {}",
                map.name, problem.index, problem.start, problem.goal
            );
            let svg = draw_comparison(
                &map.grid,
                problem.start,
                problem.goal,
                &layers,
                &title,
                &style,
            );
            files.push(OutputFile {
                path: format!("figures/{stem}-{}.svg", problem.index).into(),
                contents: svg.into_bytes(),
            });
            let layers: Vec<Layer<'_>> = if with_expanded {
                let effort: Vec<Layer<'_>> = layers
                    .into_iter()
                    .zip(&expanded)
                    .map(|(layer, cells)| layer.with_expanded(cells))
                    .collect();
                let title = format!(
                    "Expanded cells, {} problem {}: {} -> {}",
                    map.name, problem.index, problem.start, problem.goal
                );
                let svg = draw_comparison(
                    &map.grid,
                    problem.start,
                    problem.goal,
                    &effort,
                    &title,
                    &Style {
                        layout: planner_figures::Layout::Panels,
                        ..expanded_style()
                    },
                );
                files.push(OutputFile {
                    path: format!("figures/{stem}-{}-expanded.svg", problem.index).into(),
                    contents: svg.into_bytes(),
                });
                effort
            } else {
                layers
            };
            if experiment.figures == FigureMode::All {
                for (run, layer) in runs.iter().zip(&layers) {
                    if run.returns.is_some() {
                        let base = format!(
                            "figures/{stem}-{}-{}",
                            problem.index,
                            file_safe(&run.planner)
                        );
                        files.extend(crate::coverage::figures(&map.grid, run, &base, &style));
                        continue;
                    }
                    let title =
                        format!("{} on {} problem {}", run.planner, map.name, problem.index);
                    let svg = draw_path(
                        &map.grid,
                        problem.start,
                        problem.goal,
                        layer,
                        &title,
                        &style,
                    );
                    files.push(OutputFile {
                        path: format!(
                            "figures/{stem}-{}-{}.svg",
                            problem.index,
                            file_safe(&run.planner)
                        )
                        .into(),
                        contents: svg.into_bytes(),
                    });
                }
            }
        }
    }
    Ok(files)
}

fn layer(run: &RunRecord) -> Layer<'_> {
    let note = match (run.steps, run.turns, run.score) {
        (Some(d), Some(t), Some(s)) => format!(
            "{}: D={d} T={t} Score={s} length={:.2}",
            run.status,
            run.length.unwrap_or(0.0)
        ),
        _ => run.status.as_str().replace('_', " "),
    };
    Layer::new(&run.planner, run.path.as_ref(), note).with_markers(&run.marks)
}

/// Labels come from user configs; keep file names to letters, digits, '-' and '_'.
fn file_safe(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// The problems of a map to draw, at most `limit`, in map order.
fn pick(problems: &[ProblemEntry], how: FigurePick, limit: usize) -> Vec<&ProblemEntry> {
    let valid = problems.iter().filter(|p| p.invalid.is_none());
    let mut chosen: Vec<&ProblemEntry> = match how {
        FigurePick::First => return problems.iter().take(limit).collect(),
        FigurePick::Hardest => {
            let hardness = |p: &ProblemEntry| {
                p.optimal_length.unwrap_or_else(|| {
                    let dx = f64::from(p.start.x) - f64::from(p.goal.x);
                    let dy = f64::from(p.start.y) - f64::from(p.goal.y);
                    dx.hypot(dy)
                })
            };
            let mut all: Vec<&ProblemEntry> = valid.collect();
            // Hardest first; ties keep map order (the sort is stable).
            all.sort_by(|a, b| hardness(b).total_cmp(&hardness(a)));
            all.truncate(limit);
            all
        }
        FigurePick::Buckets => {
            let mut firsts: Vec<&ProblemEntry> = Vec::new();
            for p in valid {
                if !firsts.iter().any(|f| f.bucket == p.bucket) {
                    firsts.push(p);
                }
            }
            firsts.sort_by_key(|p| p.bucket);
            if firsts.len() > limit && limit > 0 {
                let n = firsts.len();
                let step = (n - 1) as f64 / (limit.max(2) - 1) as f64;
                let mut spread: Vec<&ProblemEntry> = (0..limit)
                    .map(|i| firsts[((i as f64 * step).round() as usize).min(n - 1)])
                    .collect();
                spread.dedup_by_key(|p| p.index);
                spread
            } else {
                firsts.truncate(limit);
                firsts
            }
        }
    };
    chosen.sort_by_key(|p| p.index);
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Cell, Grid};

    fn problems() -> Vec<ProblemEntry> {
        let grid = Grid::new(10, 1).unwrap();
        (0..6)
            .map(|i| ProblemEntry {
                bucket: Some(i / 2),
                ..ProblemEntry::new(
                    &grid,
                    i as usize + 1,
                    Cell::new(0, 0),
                    Cell::new(i, 0),
                    Some(f64::from(i)),
                )
            })
            .collect()
    }

    fn check(how: FigurePick, limit: usize, expect: &[usize]) {
        let all = problems();
        let got: Vec<usize> = pick(&all, how, limit).iter().map(|p| p.index).collect();
        assert_eq!(got, expect, "{how:?} {limit}");
    }

    #[test]
    fn figures_pick_first_hardest_and_one_per_bucket() {
        check(FigurePick::First, 2, &[1, 2]);
        // Optima 0..5: the two largest are problems 6 and 5.
        check(FigurePick::Hardest, 2, &[5, 6]);
        // Buckets 0, 1, 2 begin at problems 1, 3, 5.
        check(FigurePick::Buckets, 3, &[1, 3, 5]);
        // Two of three buckets: the first and the last.
        check(FigurePick::Buckets, 2, &[1, 5]);
    }
}
