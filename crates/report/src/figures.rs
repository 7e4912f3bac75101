//! The SVG figures of a sweep, drawn with planner-figures.
//!
//! `figures/<map>-<problem>.svg` puts every planner's path on one map side by side (small
//! maps) or overlaid (large ones), like seed 000's Figs. 7-18 and seed 002's Figs. 12-18;
//! with `figures = "all"`, `figures/<map>-<problem>-<planner>.svg` draws each run alone with
//! step indices and direction arrows. Repeat 0 is drawn. `figures_pick` chooses the
//! problems: the first `figures_per_map`, the hardest, or one per scenario bucket.
//!
//! With `figures_expanded = true`, the sweep records each drawn run's expanded cells at
//! run time ([`planner_runner::expanded`]; this module runs no planner), and
//! `figures/<map>-<problem>-expanded.svg` draws one panel per planner with its
//! expanded cells in a light fill under its path and their number in its legend (planners
//! that record none say so), and the per-run figures of `figures = "all"` draw them too.
//! The comparison figures stay as they are. [`draw_run`] draws one run's figure, for
//! `plan --svg`.
//!
//! File names: `<map>` is the map's file name without its extension and `<planner>` the
//! label, each through [`crate::file_part`] (kept when made of letters, digits, `-`, `_`
//! and `.`; else those characters with `_` for the rest and a short hash of the original,
//! so `p q.map` and `p_q.map` stay apart), and a name another figure of the sweep took
//! already, letter case aside, gets a hash of its map, problem and label
//! ([`crate::FileNames`]): two figures never share a file, on a case-insensitive file
//! system too.

use std::sync::atomic::AtomicBool;

use planner_api::Cell;
use planner_figures::{draw_comparison, draw_path, Layer, MapView, Style};

use planner_runner::config::{Experiment, FigureMode, MapEntry, ProblemEntry};
use planner_runner::expanded::{pick, ExpandedCells};
use planner_runner::index::ResultsIndex;
use planner_runner::output::OutputFile;
use planner_runner::record::RunRecord;
use planner_runner::sweep::check_stop;
use planner_runner::RunnerError;

use crate::{file_part, FileNames};

/// The style of the figures with expanded cells: up to 1800 pixels a side, so that a
/// panel per planner keeps the cells of a 512 x 512 map visible.
fn expanded_style() -> Style {
    Style {
        max_px: 1800.0,
        ..Style::default()
    }
}

/// `map`'s grid with its unknown cells ([`MapEntry::unknown`]), as figures draw it.
fn view(map: &MapEntry) -> MapView<'_> {
    grid_view(&map.grid, map.unknown.as_deref())
}

/// `grid` with `unknown` (one flag per cell) marking its unknown cells, if given.
fn grid_view<'a>(grid: &'a planner_api::Grid, unknown: Option<&'a [bool]>) -> MapView<'a> {
    match unknown {
        Some(unknown) => MapView::new(grid).with_unknown(unknown),
        None => MapView::new(grid),
    }
}

/// One run's figure as an SVG document: the grid, the run's path with step indices and
/// arrows, its marks, and `expanded` (the cells it expanded, from
/// [`planner_api::Outcome::expanded`]; empty for none) in a light fill under the path
/// with their number in the legend. The title names the planner label, the map and the
/// problem; the legend gives the status and D, T, Score and length.
pub fn draw_run<'a>(map: impl Into<MapView<'a>>, record: &RunRecord, expanded: &[Cell]) -> String {
    let title = format!(
        "{} on {} problem {}: {} -> {}",
        record.planner, record.map, record.problem, record.start, record.goal
    );
    let layer = layer(record).with_expanded(expanded);
    draw_path(
        map,
        record.start,
        record.goal,
        &layer,
        &title,
        &expanded_style(),
    )
}

/// [`draw_run`] of a `plan` run ([`planner_runner::plan::PlanResult`]): its grid, with
/// the map's unknown cells grey, its record and its expanded cells.
pub fn draw_planned(result: &planner_runner::plan::PlanResult) -> String {
    let map = grid_view(&result.grid, result.unknown.as_deref());
    draw_run(map, &result.record, &result.expanded)
}

/// The figure files of `records`; with `figures_expanded`, the expanded cells drawn come
/// from `expanded` (recorded by the sweep; a run without any draws none).
pub fn render(
    experiment: &Experiment,
    records: &[RunRecord],
    expanded: &ExpandedCells,
) -> Vec<OutputFile> {
    // Without a stop flag nothing ends it early.
    render_until(experiment, records, expanded, None).unwrap_or_default()
}

/// [`render`], ended before the next drawn problem with [`RunnerError::Interrupted`] once
/// `stop` is raised (a sweep's Ctrl-C).
pub fn render_until(
    experiment: &Experiment,
    records: &[RunRecord],
    expanded: &ExpandedCells,
    stop: Option<&AtomicBool>,
) -> Result<Vec<OutputFile>, RunnerError> {
    let mut files = Vec::new();
    if experiment.figures == FigureMode::None {
        return Ok(files);
    }
    let index = ResultsIndex::new(records);
    let mut names = FileNames::default();
    for map in &experiment.maps {
        let limit = experiment.figure_limit(map);
        for problem in pick(&map.problems, experiment.figures_pick, limit) {
            if problem.invalid.is_some() {
                continue;
            }
            check_stop(stop)?;
            files.extend(problem_figures(
                experiment, &index, expanded, map, problem, &mut names,
            ));
        }
    }
    Ok(files)
}

/// The figures of one drawn problem: the comparison, the expanded cells' panels (with
/// `figures_expanded`) and, with `figures = "all"`, one per run.
fn problem_figures(
    experiment: &Experiment,
    index: &ResultsIndex<'_>,
    expanded: &ExpandedCells,
    map: &MapEntry,
    problem: &ProblemEntry,
    names: &mut FileNames,
) -> Vec<OutputFile> {
    let with_expanded = experiment.figures_expanded;
    let style = Style::default();
    let stem = file_part(planner_runner::config::map_stem(&map.name));
    let mut files = Vec::new();
    let runs: Vec<&RunRecord> = experiment
        .planners
        .iter()
        .filter_map(|p| index.first(&map.name, problem.index, &p.label))
        .collect();
    let cells: Vec<&[Cell]> = runs
        .iter()
        .map(|r| {
            expanded
                .get(&map.name, problem.index, &r.planner)
                .unwrap_or_default()
        })
        .collect();
    let layers: Vec<Layer<'_>> = runs.iter().map(|r| layer(r)).collect();
    let title = format!(
        "{} problem {}: {} -> {}",
        map.name, problem.index, problem.start, problem.goal
    );
    let svg = draw_comparison(
        view(map),
        problem.start,
        problem.goal,
        &layers,
        &title,
        &style,
    );
    let key = format!("{}\n{}", map.name, problem.index);
    files.push(OutputFile {
        path: names
            .claim(format!("figures/{stem}-{}.svg", problem.index), &key)
            .into(),
        contents: svg.into_bytes(),
    });
    let layers: Vec<Layer<'_>> = if with_expanded {
        let effort: Vec<Layer<'_>> = layers
            .into_iter()
            .zip(&cells)
            .map(|(layer, cells)| layer.with_expanded(cells))
            .collect();
        let title = format!(
            "Expanded cells, {} problem {}: {} -> {}",
            map.name, problem.index, problem.start, problem.goal
        );
        let svg = draw_comparison(
            view(map),
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
            path: names
                .claim(
                    format!("figures/{stem}-{}-expanded.svg", problem.index),
                    &format!("{key}\nexpanded"),
                )
                .into(),
            contents: svg.into_bytes(),
        });
        effort
    } else {
        layers
    };
    if experiment.figures == FigureMode::All {
        let drawn = Drawn {
            map,
            problem,
            stem: &stem,
            key: &key,
            style: &style,
        };
        files.extend(run_figures(&drawn, &runs, &layers, names));
    }
    files
}

/// One drawn problem: its map and problem, the map's file-name part, the key of its
/// figures (map name and problem) and the style.
struct Drawn<'a> {
    map: &'a MapEntry,
    problem: &'a ProblemEntry,
    stem: &'a str,
    key: &'a str,
    style: &'a Style,
}

/// The per-run figures of `figures = "all"`: each run of `runs` alone (a coverage run's
/// own figures), drawn with its layer.
fn run_figures(
    drawn: &Drawn<'_>,
    runs: &[&RunRecord],
    layers: &[Layer<'_>],
    names: &mut FileNames,
) -> Vec<OutputFile> {
    let Drawn {
        map,
        problem,
        stem,
        style,
        ..
    } = *drawn;
    let mut files = Vec::new();
    for (run, layer) in runs.iter().zip(layers) {
        let key = format!("{}\n{}", drawn.key, run.planner);
        if run.returns.is_some() {
            let base = format!(
                "figures/{stem}-{}-{}",
                problem.index,
                file_part(&run.planner)
            );
            for mut file in crate::coverage_figures::figures(view(map), run, &base, style) {
                let wanted = file.path.to_string_lossy().into_owned();
                let suffix = wanted.strip_prefix(&base).unwrap_or_default();
                file.path = names
                    .claim(wanted.clone(), &format!("{key}{suffix}"))
                    .into();
                files.push(file);
            }
            continue;
        }
        let title = format!("{} on {} problem {}", run.planner, map.name, problem.index);
        let svg = draw_path(view(map), problem.start, problem.goal, layer, &title, style);
        files.push(OutputFile {
            path: names
                .claim(
                    format!(
                        "figures/{stem}-{}-{}.svg",
                        problem.index,
                        file_part(&run.planner)
                    ),
                    &key,
                )
                .into(),
            contents: svg.into_bytes(),
        });
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
