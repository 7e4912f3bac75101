//! `cargo xtask plan`: one run, printed for a person or as one JSON object for scripts.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use planner_api::{
    Budget, Cell, CoverageMetrics, CoverageProblem, Grid, Outcome, Problem, ReturnLeg,
};
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
    /// Coverage planners only: coverage metrics and returns.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coverage: Option<CoverageJson<'a>>,
    /// The cells the planner marked (PA-star's handover points), if any.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub marks: &'a [planner_api::Mark],
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

/// Coverage in `plan --json`, for coverage planners.
#[derive(Debug, Serialize)]
pub struct CoverageJson<'a> {
    /// Free cells 4-connected to the start.
    pub n_reachable: u64,
    /// Distinct reachable cells on the path.
    pub n_covered: u64,
    /// `100 * n_covered / n_reachable`.
    pub percent: f64,
    /// Path cells entered when already covered.
    pub n_revisits: u64,
    /// The stretches of the path that return to a backtracking point.
    pub returns: &'a [ReturnLeg],
}

/// What a coverage planner reports beyond a path planner's outcome.
pub struct CoverageReport {
    /// Coverage, revisits and path metrics.
    pub metrics: CoverageMetrics,
    /// The path's returns to backtracking points.
    pub returns: Vec<ReturnLeg>,
}

/// One finished run.
pub struct PlanResult {
    /// The grid.
    pub grid: Grid,
    /// Start.
    pub start: Cell,
    /// Goal (a coverage planner has none: `None`).
    pub goal: Option<Cell>,
    /// Planner label or name.
    pub planner: String,
    /// The outcome: for a coverage planner its status, path and counters.
    pub outcome: Outcome,
    /// For a coverage planner, its coverage metrics and returns.
    pub coverage: Option<CoverageReport>,
}

/// Runs `args`. A coverage planner covers from the start (`--start`, or the problem's)
/// and takes no `--goal`.
pub fn run(args: &PlanArgs) -> Result<PlanResult, String> {
    let file = planner_maps::read_map(&args.map).map_err(|e| e.to_string())?;
    let grid = file.grid;
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
            let name = registry::find(&args.planner)
                .map(|e| e.name)
                .or_else(|| registry::find_coverage(&args.planner).map(|e| e.name))
                .ok_or_else(|| {
                    format!(
                        "unknown planner `{}`, expected one of {}",
                        args.planner,
                        registry::names().join(", ")
                    )
                })?;
            (name, toml::Table::new(), Budget::unlimited())
        }
    };
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
    let planner_error = |e: String| format!("planner `{name}`: {}", e.replace('\n', " ").trim());

    if let Some(entry) = registry::find_coverage(name) {
        let start = match (args.start, args.goal, args.problem) {
            (_, Some(_), _) => {
                return Err(format!(
                    "`{name}` is a coverage planner: it covers from --start and takes no --goal"
                ))
            }
            (Some(start), None, None) => start,
            (None, None, problem) => pick_problem(&args.map, &grid, &file.problems, problem)?.0,
            (Some(_), None, Some(_)) => {
                return Err("give either --problem or --start, not both".into())
            }
        };
        let problem = CoverageProblem::new(&grid, start)
            .map_err(|e| format!("{}: {e}", args.map.display()))?;
        let mut planner = (entry.build)(params).map_err(planner_error)?;
        let covered = planner.cover(&problem, &budget);
        return Ok(PlanResult {
            start,
            goal: None,
            planner: args.planner.clone(),
            outcome: Outcome::new(covered.status, Some(covered.path), covered.counters),
            coverage: Some(CoverageReport {
                metrics: covered.metrics,
                returns: covered.returns,
            }),
            grid,
        });
    }

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
    let entry = registry::find(name).ok_or_else(|| format!("unknown planner `{name}`"))?;
    let mut planner = (entry.build)(params).map_err(planner_error)?;
    let outcome = planner.plan(&problem, &budget);
    Ok(PlanResult {
        grid,
        start,
        goal: Some(goal),
        planner: args.planner.clone(),
        outcome,
        coverage: None,
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
            coverage: self.coverage.as_ref().map(|c| CoverageJson {
                n_reachable: c.metrics.n_reachable,
                n_covered: c.metrics.n_covered,
                percent: c.metrics.percent,
                n_revisits: c.metrics.n_revisits,
                returns: &c.returns,
            }),
            marks: &self.outcome.marks,
        };
        serde_json::to_string(&json).map_err(|e| e.to_string())
    }

    /// The run for a person: header, the map with the path drawn, metrics, counters.
    pub fn to_text(&self) -> String {
        let mut out = String::new();
        let route = match self.goal {
            Some(goal) => format!("{} -> {goal}", self.start),
            None => format!("covering from {}", self.start),
        };
        let _ = writeln!(
            out,
            "{} on a {}x{} grid, {route}: {}",
            self.planner,
            self.grid.width(),
            self.grid.height(),
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
        if let Some(c) = &self.coverage {
            let _ = writeln!(
                out,
                "covered {} of {} reachable cells ({:.2}%), {} revisits, {} returns",
                c.metrics.n_covered,
                c.metrics.n_reachable,
                c.metrics.percent,
                c.metrics.n_revisits,
                c.returns.len()
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
        if !self.outcome.marks.is_empty() {
            let marks: Vec<String> = self
                .outcome
                .marks
                .iter()
                .map(|m| format!("{} {}", m.label, m.cell))
                .collect();
            let _ = writeln!(out, "marks: {}", marks.join(", "));
        }
        let _ = writeln!(out, "{}", self.outcome.counters);
        out
    }
}

/// The grid as text: `#` blocked, `.` free, `S` start, `G` goal (if any), and the path: an
/// arrow (`>` `<` `v` `^`, diagonals `\` `/`) on each cell for the move leaving it (the last
/// one when a coverage path leaves a cell several times), `*` on the cells where a longer
/// move starts.
pub fn draw_text(
    grid: &Grid,
    start: Cell,
    goal: Option<Cell>,
    path: Option<&planner_api::Path>,
) -> String {
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
    if let Some(goal) = goal {
        canvas[goal.y as usize][goal.x as usize] = 'G';
    }
    let mut out = String::new();
    for row in canvas {
        out.extend(row);
        out.push('\n');
    }
    out
}
