//! The SVG figures of a sweep, drawn with planner-figures.
//!
//! `figures/<map>-<problem>.svg` puts every planner's path on one map side by side (small
//! maps) or overlaid (large ones), like seed 000's Figs. 7-18 and seed 002's Figs. 12-18;
//! with `figures = "all"`, `figures/<map>-<problem>-<planner>.svg` draws each run alone with
//! step indices and direction arrows. Repeat 0 is drawn.

use planner_figures::{draw_comparison, draw_path, Layer, Style};

use crate::config::{Experiment, FigureMode};
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
        for problem in map.problems.iter().take(limit) {
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
