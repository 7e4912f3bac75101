//! `cargo xtask plan`: one run, printed for a person or as one JSON object for scripts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use planner_api::{Budget, Cell, Grid, Outcome, Problem};
use serde::Serialize;

use crate::config;
use crate::registry;

/// What to run.
#[derive(Debug, Clone, Default)]
pub struct PlanArgs {
    /// The map file.
    pub map: PathBuf,
    /// Registry name, or a label of `config`.
    pub planner: String,
    /// An experiment config whose `[planners]` labels `planner` may name.
    pub config: Option<PathBuf>,
    /// 1-based problem of the map's own pairs, or of the `.scen` beside a `.map`.
    pub problem: Option<usize>,
    /// Explicit start.
    pub start: Option<Cell>,
    /// Explicit goal.
    pub goal: Option<Cell>,
    /// `key=value` parameter overrides; values are TOML (`1.5`, `"octile"`) or bare words.
    pub set: Vec<String>,
    /// Expansion budget.
    pub max_expansions: Option<u64>,
}

/// The JSON form of `plan --json`.
#[derive(Debug, Serialize)]
pub struct PlanJson<'a> {
    /// `found`, `no_path` or `budget_exhausted`.
    pub status: &'a str,
    /// The path's cells as `[x, y]` pairs (empty when there is none).
    pub path: Vec<Cell>,
    /// Path metrics (null without a path).
    pub metrics: Option<Metrics>,
    /// The planner's counters.
    pub counters: &'a planner_api::Counters,
}

/// Path metrics in `plan --json`.
#[derive(Debug, Serialize)]
pub struct Metrics {
    /// D.
    pub steps: u64,
    /// T.
    pub turns: u64,
    /// Score.
    pub score: u64,
    /// Euclidean length.
    pub length: f64,
}

/// One finished run.
pub struct PlanResult {
    /// The grid.
    pub grid: Grid,
    /// Start.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
    /// Planner label or name.
    pub planner: String,
    /// The outcome.
    pub outcome: Outcome,
}

/// Runs `args`.
pub fn run(args: &PlanArgs) -> Result<PlanResult, String> {
    let file = planner_maps::read_map(&args.map).map_err(|e| e.to_string())?;
    let grid = file.grid;
    let (start, goal) = match (args.start, args.goal, args.problem) {
        (Some(start), Some(goal), None) => (start, goal),
        (None, None, problem) => pick_problem(&args.map, &grid, &file.problems, problem)?,
        (_, _, Some(_)) => {
            return Err("give either --problem or --start and --goal, not both".into())
        }
        _ => return Err("--start and --goal go together".into()),
    };
    let problem =
        Problem::new(&grid, start, goal).map_err(|e| format!("{}: {e}", args.map.display()))?;

    let coverage_only = |name: &str| {
        registry::find_coverage(name).map(|_| {
            format!("`{name}` is a coverage planner: run it from an experiment config with `problems = \"start\"` (see configs/coverage.toml)")
        })
    };
    if let Some(message) = coverage_only(&args.planner) {
        return Err(message);
    }
    let (name, mut params, mut budget) = match &args.config {
        Some(path) => {
            let experiment = config::load(path).map_err(|e| e.to_string())?;
            let spec = experiment
                .planners
                .iter()
                .find(|p| p.label == args.planner)
                .ok_or_else(|| {
                    let labels: Vec<&str> = experiment
                        .planners
                        .iter()
                        .map(|p| p.label.as_str())
                        .collect();
                    format!(
                        "{}: no planner labelled `{}` (labels: {})",
                        path.display(),
                        args.planner,
                        labels.join(", ")
                    )
                })?;
            (spec.name, spec.params.clone(), spec.budget)
        }
        None => {
            let entry = registry::find(&args.planner).ok_or_else(|| {
                format!(
                    "unknown planner `{}`, expected one of {}",
                    args.planner,
                    registry::names().join(", ")
                )
            })?;
            (entry.name, toml::Table::new(), Budget::unlimited())
        }
    };
    if let Some(message) = coverage_only(name) {
        return Err(message);
    }
    for assignment in &args.set {
        let (key, value) = assignment
            .split_once('=')
            .ok_or_else(|| format!("--set {assignment:?}: expected key=value"))?;
        let key = key.trim();
        let value = value.trim();
        let parsed = toml::from_str::<toml::Table>(&format!("v = {value}"))
            .ok()
            .and_then(|mut t| t.remove("v"))
            .unwrap_or_else(|| toml::Value::String(value.to_string()));
        params.insert(key.to_string(), parsed);
    }
    if let Some(n) = args.max_expansions {
        budget.max_expansions = Some(n);
    }
    let entry = registry::find(name).ok_or_else(|| format!("unknown planner `{name}`"))?;
    let mut planner = (entry.build)(params)
        .map_err(|e| format!("planner `{name}`: {}", e.replace('\n', " ").trim()))?;
    let outcome = planner.plan(&problem, &budget);
    Ok(PlanResult {
        grid,
        start,
        goal,
        planner: args.planner.clone(),
        outcome,
    })
}

fn pick_problem(
    map: &Path,
    grid: &Grid,
    own: &[planner_maps::ProblemSpec],
    problem: Option<usize>,
) -> Result<(Cell, Cell), String> {
    let mut pairs: Vec<(Cell, Cell)> = own.iter().map(|p| (p.start, p.goal)).collect();
    let scen = PathBuf::from(format!("{}.scen", map.display()));
    if pairs.is_empty() && scen.exists() {
        pairs = planner_maps::read_scenarios(&scen)
            .map_err(|e| e.to_string())?
            .iter()
            .map(|s| (s.start, s.goal))
            .collect();
    }
    match problem {
        Some(k) => pairs.get(k.wrapping_sub(1)).copied().ok_or_else(|| {
            format!(
                "--problem {k}: {} has {} problem(s), numbered from 1",
                map.display(),
                pairs.len()
            )
        }),
        None => Ok(pairs.first().copied().unwrap_or((
            Cell::new(0, 0),
            Cell::new(grid.width() - 1, grid.height() - 1),
        ))),
    }
}

impl PlanResult {
    /// The one JSON object of `--json`.
    pub fn to_json(&self) -> Result<String, String> {
        let path = self.outcome.path.as_ref();
        let json = PlanJson {
            status: self.outcome.status.as_str(),
            path: path.map(|p| p.cells().to_vec()).unwrap_or_default(),
            metrics: path.map(|p| {
                let m = p.metrics();
                Metrics {
                    steps: m.steps,
                    turns: m.turns,
                    score: m.score,
                    length: m.length,
                }
            }),
            counters: &self.outcome.counters,
        };
        serde_json::to_string(&json).map_err(|e| e.to_string())
    }

    /// The run for a person: header, the map with the path drawn, metrics, counters.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{} on a {}x{} grid, {} -> {}: {}",
            self.planner,
            self.grid.width(),
            self.grid.height(),
            self.start,
            self.goal,
            self.outcome.status.as_str()
        );
        if let Some(path) = &self.outcome.path {
            let m = path.metrics();
            let _ = writeln!(
                out,
                "steps (D) {}, turns (T) {}, score {}, length {:.4}",
                m.steps, m.turns, m.score, m.length
            );
        }
        if self.grid.width() <= 120 && self.grid.height() <= 120 {
            out.push_str(&draw_text(
                &self.grid,
                self.start,
                self.goal,
                self.outcome.path.as_ref(),
            ));
        } else {
            out.push_str("(map wider or taller than 120 cells: not drawn)\n");
        }
        let _ = writeln!(out, "{}", self.outcome.counters);
        out
    }
}

/// The grid as text: `#` blocked, `.` free, `S` start, `G` goal, and the path: an arrow
/// (`>` `<` `v` `^`, diagonals `\` `/`) on each cell for the move leaving it, `*` on the
/// cells where a longer move starts.
pub fn draw_text(grid: &Grid, start: Cell, goal: Cell, path: Option<&planner_api::Path>) -> String {
    let mut canvas: Vec<Vec<char>> = (0..grid.height())
        .map(|y| {
            (0..grid.width())
                .map(|x| {
                    if grid.is_free(Cell::new(x, y)) {
                        '.'
                    } else {
                        '#'
                    }
                })
                .collect()
        })
        .collect();
    if let Some(path) = path {
        for pair in path.cells().windows(2) {
            let dx = i64::from(pair[1].x) - i64::from(pair[0].x);
            let dy = i64::from(pair[1].y) - i64::from(pair[0].y);
            let mark = match (dx, dy) {
                (1, 0) => '>',
                (-1, 0) => '<',
                (0, 1) => 'v',
                (0, -1) => '^',
                (1, 1) | (-1, -1) => '\\',
                (1, -1) | (-1, 1) => '/',
                _ => '*',
            };
            canvas[pair[0].y as usize][pair[0].x as usize] = mark;
        }
    }
    canvas[start.y as usize][start.x as usize] = 'S';
    canvas[goal.y as usize][goal.x as usize] = 'G';
    let mut out = String::new();
    for row in canvas {
        out.extend(row);
        out.push('\n');
    }
    out
}
