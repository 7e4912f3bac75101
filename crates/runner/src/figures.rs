//! The SVG figures of a sweep, drawn with planner-figures.
//!
//! `figures/<map>-<problem>.svg` puts every planner's path on one map side by side (small
//! maps) or overlaid (large ones), like seed 000's Figs. 7-18 and seed 002's Figs. 12-18;
//! with `figures = "all"`, `figures/<map>-<problem>-<planner>.svg` draws each run alone with
//! step indices and direction arrows. Repeat 0 is drawn. `figures_pick` chooses the
//! problems: the first `figures_per_map`, the hardest, or one per scenario bucket.

use planner_figures::{draw_comparison, draw_path, Layer, Style};

use crate::config::{Experiment, FigureMode, FigurePick, ProblemEntry};
use crate::index::ResultsIndex;
use crate::output::OutputFile;
use crate::record::RunRecord;

/// The figure files of `records`.
pub fn render(experiment: &Experiment, records: &[RunRecord]) -> Vec<OutputFile> {
    let mut files = Vec::new();
    if experiment.figures == FigureMode::None {
        return files;
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
            let runs: Vec<&RunRecord> = experiment
                .planners
                .iter()
                .filter_map(|p| index.first(&map.name, problem.index, &p.label))
                .collect();
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
    files
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
