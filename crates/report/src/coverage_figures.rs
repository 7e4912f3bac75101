//! Coverage runs' figures (seed 004).
//!
//! A coverage run covers from the problem's start and ignores its goal (a
//! `problems = "start"` map set sets the goal to the start). Its record holds the coverage
//! path, the path metrics, the planner's counters (coverage, revisits, backtracking
//! points, turns, return expansions...) and the return legs; this module draws them.

use std::path::PathBuf;

use planner_api::Path;
use planner_figures::{draw_comparison, draw_timeline, Layer, Layout, MapView, Marker, Style};

use planner_runner::output::OutputFile;
use planner_runner::record::RunRecord;

/// The figures of one coverage run, `<base>.svg` and `<base>-returns.svg`: the path
/// coloured by time with the backtracking points returned to marked `B1`, `B2`, ... in
/// order (like seed 004's Figs. 7-8), and the path with each A* return drawn over it.
pub fn figures(grid: MapView<'_>, run: &RunRecord, base: &str, style: &Style) -> Vec<OutputFile> {
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
