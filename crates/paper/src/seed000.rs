//! Seed 000's Tables 3-8: one table per planner and map size, metric rows (Steps, Turns,
//! Score, then every counter in the planner's order), one column per map and problem.
//! Each cell is the run's repeat 0 (the heading's note says so when the config runs more
//! repeats; the `repeats` section has the others).
//!
//! With `published` set, each cell shows the measured value and a mark: `✓` when it
//! equals the published one, `✗ (published P)` when not, and a published metric the
//! planner does not report gets a row of its own, `- ✗ (published P; not measured)`.
//! Every published number of the config's maps and planners is compared and counted,
//! also where a table has more than [`MAX_COLUMNS`] columns and is not drawn: a note
//! then gives its count and lists its ✗ numbers.

use std::fmt::Write as _;

use planner_report::{md_cell, md_code};
use planner_report::{Context, Reproduction, Section, MAX_COLUMNS};
use planner_runner::config::{map_stem, PlannerSpec};
use planner_runner::record::RunRecord;

/// Seed 000's quality and search-effort tables (section name `seed000`).
pub struct Seed000;

impl Section for Seed000 {
    fn name(&self) -> &'static str {
        "seed000"
    }

    /// When the config gives `published` values (which only this section compares; a
    /// config whose `sections` leave it out while giving `published` is refused), else
    /// only when a config names it.
    fn applies(&self, context: &Context<'_>) -> bool {
        context.experiment.published.is_some()
    }

    fn render(&self, context: &Context<'_>, out: &mut String, reproduction: &mut Reproduction) {
        let quality = quality_tables(context, reproduction);
        if let Some(published) = &context.experiment.published {
            let _ = writeln!(
                out,
                "**Published numbers reproduced: {} of {}** (from {}; ✓ equal, ✗ different).\n",
                reproduction.matched,
                reproduction.compared,
                md_code(&published.path.display().to_string())
            );
        }
        out.push_str(&quality);
    }
}

fn quality_tables(context: &Context<'_>, reproduction: &mut Reproduction) -> String {
    let experiment = context.experiment;
    let mut out =
        String::from("## Path quality and search effort (seed 000, Tables 3-8 layout)\n\n");
    if experiment.repeats > 1 {
        let _ = writeln!(
            out,
            "Each cell is repeat 0 of its run (the config runs {} repeats; the `repeats` section and runs.csv have them all).\n",
            experiment.repeats
        );
    }
    let mut sizes: Vec<(u32, u32)> = Vec::new();
    for map in &experiment.maps {
        let size = (map.grid.width(), map.grid.height());
        if !sizes.contains(&size) {
            sizes.push(size);
        }
    }
    let mut too_wide: Vec<String> = Vec::new();
    for planner in &experiment.planners {
        for &(w, h) in &sizes {
            let columns: Vec<(&str, usize)> = experiment
                .maps
                .iter()
                .filter(|m| (m.grid.width(), m.grid.height()) == (w, h))
                .flat_map(|m| m.problems.iter().map(move |p| (m.name.as_str(), p.index)))
                .collect();
            if columns.is_empty() {
                continue;
            }
            let table = Table::new(context, planner, &columns);
            let heading = format!(
                "### {} ({}) on {w}x{h} maps\n\n",
                md_cell(&planner.label),
                planner.name
            );
            let mut marks = Reproduction::default();
            let cells: Vec<Vec<String>> = table
                .metrics
                .iter()
                .map(|metric| {
                    columns
                        .iter()
                        .map(|&(map, problem)| table.cell(map, problem, metric, &mut marks))
                        .collect()
                })
                .collect();
            reproduction.compared += marks.compared;
            reproduction.matched += marks.matched;
            if columns.len() > MAX_COLUMNS {
                if marks.compared == 0 {
                    too_wide.push(format!("{} on {w}x{h}", md_cell(&planner.label)));
                    continue;
                }
                // Not drawn, but its published numbers count: say how many and which
                // differ.
                out.push_str(&heading);
                write_wide_note(&mut out, &columns, &table.metrics, &cells, marks);
                continue;
            }
            out.push_str(&heading);
            let single = experiment
                .maps
                .iter()
                .filter(|m| (m.grid.width(), m.grid.height()) == (w, h))
                .all(|m| m.problems.len() == 1);
            write_table(&mut out, &columns, single, &table.metrics, &cells);
        }
    }
    if !too_wide.is_empty() {
        let _ = writeln!(
            out,
            "(Too many problems per map size for this layout: {}; see runs.csv.)\n",
            too_wide.join(", ")
        );
    }
    out
}

/// The note of a table too wide to draw: its problems, its published numbers reproduced
/// (`marks`) and each ✗ of its `cells` (rows `metrics`, columns `columns`).
fn write_wide_note(
    out: &mut String,
    columns: &[(&str, usize)],
    metrics: &[String],
    cells: &[Vec<String>],
    marks: Reproduction,
) {
    let _ = writeln!(
        out,
        "{} problems, more than the {MAX_COLUMNS} columns of this layout (see runs.csv); published numbers reproduced here: {} of {}.\n",
        columns.len(),
        marks.matched,
        marks.compared
    );
    let mut listed = false;
    for (metric, row) in metrics.iter().zip(cells) {
        for (&(map, problem), cell) in columns.iter().zip(row) {
            if cell.contains('✗') {
                listed = true;
                let stem = md_cell(map_stem(map));
                let _ = writeln!(out, "- {stem} #{problem} {metric}: {cell}");
            }
        }
    }
    if listed {
        out.push('\n');
    }
}

/// A drawn table: a column per (map, problem) of `columns` (headed by the map alone when
/// each map has one problem: `single`), a row per metric of `metrics`, `cells` as marked.
fn write_table(
    out: &mut String,
    columns: &[(&str, usize)],
    single: bool,
    metrics: &[String],
    cells: &[Vec<String>],
) {
    out.push_str("| Metric |");
    for (map, problem) in columns {
        if single {
            let _ = write!(out, " {} |", md_cell(map_stem(map)));
        } else {
            let _ = write!(out, " {} #{problem} |", md_cell(map_stem(map)));
        }
    }
    out.push_str("\n|---|");
    out.push_str(&"---:|".repeat(columns.len()));
    out.push('\n');
    for (metric, row) in metrics.iter().zip(cells) {
        let _ = write!(out, "| {metric} |");
        for cell in row {
            let _ = write!(out, " {cell} |");
        }
        out.push('\n');
    }
    out.push('\n');
}

/// One planner's table on one map size: its metric rows and where its values come from.
struct Table<'a> {
    context: &'a Context<'a>,
    planner: &'a PlannerSpec,
    /// `status`, the path metrics, the counters its runs report, then the published
    /// metrics of its columns that no run reports (marked not measured).
    metrics: Vec<String>,
}

impl<'a> Table<'a> {
    fn new(context: &'a Context<'a>, planner: &'a PlannerSpec, columns: &[(&str, usize)]) -> Self {
        let mut metrics: Vec<String> = ["status", "steps", "turns", "score", "length"]
            .map(String::from)
            .to_vec();
        for (map, problem) in columns {
            if let Some(r) = context.index.first(map, *problem, &planner.label) {
                for (name, _) in r.counters.iter() {
                    if !metrics.iter().any(|m| m == name) {
                        metrics.push(name.to_string());
                    }
                }
            }
        }
        if let Some(published) = &context.experiment.published {
            for metric in planner_runner::config::published_metrics() {
                if metrics.iter().any(|m| m == metric) {
                    continue;
                }
                let given = columns.iter().any(|(map, problem)| {
                    planner.published_key(metric).is_some_and(|key| {
                        published
                            .get_problem(map_stem(map), *problem, key, metric)
                            .is_some()
                    })
                });
                if given {
                    metrics.push(metric.to_string());
                }
            }
        }
        Table {
            context,
            planner,
            metrics,
        }
    }

    /// The cell of `metric` on problem `problem` of `map`, marked (and counted in `marks`)
    /// when a published value is given for it.
    fn cell(&self, map: &str, problem: usize, metric: &str, marks: &mut Reproduction) -> String {
        let published = self
            .context
            .experiment
            .published
            .as_ref()
            .zip(self.planner.published_key(metric))
            .and_then(|(p, key)| p.get_problem(map_stem(map), problem, key, metric));
        match self.context.index.first(map, problem, &self.planner.label) {
            Some(r) => mark(metric_value(r, metric), published, metric, marks),
            None => mark(None, published, metric, marks),
        }
    }
}

/// The value of `metric` in `record` as text: `status`, a path metric or a counter.
fn metric_value(record: &RunRecord, metric: &str) -> Option<String> {
    match metric {
        "status" => Some(record.status.to_string()),
        "steps" => record.steps.map(|v| v.to_string()),
        "turns" => record.turns.map(|v| v.to_string()),
        "score" => record.score.map(|v| v.to_string()),
        "length" => record.length.map(|v| format!("{v:.2}")),
        counter => record.counters.get(counter).map(|v| v.to_string()),
    }
}

fn mark(
    value: Option<String>,
    published: Option<f64>,
    metric: &str,
    reproduction: &mut Reproduction,
) -> String {
    let Some(published) = published else {
        return value.unwrap_or_else(|| "-".into());
    };
    reproduction.compared += 1;
    let equal = value
        .as_deref()
        .and_then(|v| v.parse::<f64>().ok())
        .is_some_and(|v| {
            (v - published).abs() < 1e-9 || (metric == "length" && (v - published).abs() < 5e-3)
        });
    match value {
        Some(text) if equal => {
            reproduction.matched += 1;
            format!("{text} ✓")
        }
        Some(text) => format!("{text} ✗ (published {published})"),
        None => format!("- ✗ (published {published}; not measured)"),
    }
}
