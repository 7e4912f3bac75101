//! One run of one planner on one problem, printed for a person or as one JSON object for
//! scripts (`plan`). It goes through [`crate::run::run_one`], the function every sweep run
//! goes through, so `plan --config C --planner L --problem k` gives exactly the path,
//! counters and seed of the experiment's record for that problem's repeat 0.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use planner_api::{Budget, Cell, Grid, Problem, ReturnLeg};
use planner_maps::CsvConvention;
use serde::Serialize;

use crate::config::{self, Experiment, MapEntry, PlannerSpec, ProblemEntry};
use crate::record::RunRecord;
use crate::run::{run_one, RunSpec, Workspace};
use crate::usage::UsageError;
use crate::RunnerError;

/// The expansion budget `plan` applies when neither `--max-expansions` nor the config
/// label sets one, so that every `plan` ends (Backtracking on an open 30x30 map would
/// not): ten million expansions, a few seconds for any planner here.
pub const DEFAULT_PLAN_EXPANSIONS: u64 = 10_000_000;

/// The widest map [`PlanResult::to_text`] draws, in cells (one column each).
pub const TEXT_COLUMNS: usize = 200;

/// What to run.
#[derive(Debug, Clone, Default)]
pub struct PlanArgs {
    /// The map file.
    pub map: PathBuf,
    /// Registry name, or a label of `config`.
    pub planner: String,
    /// An experiment config whose `[planners]` labels `planner` may name.
    pub config: Option<PathBuf>,
    /// 1-based problem of the map's own pairs, or of the `.scen` beside a `.map` (which is
    /// read only when no start or goal is given); with a config listing this map, the
    /// problem of the config's map set.
    pub problem: Option<usize>,
    /// Explicit start.
    pub start: Option<Cell>,
    /// Explicit goal.
    pub goal: Option<Cell>,
    /// Explicit start as a point `(x, y)` of the ROS map frame, in metres (`--start-world`):
    /// the cell holding it ([`planner_maps::MapFrame::cell_at`]). For maps with a frame
    /// only (a `map_server` YAML), instead of `start`.
    pub start_world: Option<(f64, f64)>,
    /// Explicit goal in the map frame (`--goal-world`), instead of `goal`.
    pub goal_world: Option<(f64, f64)>,
    /// `key=value` parameter overrides; values are TOML (`1.5`, `"octile"`) or bare words.
    pub set: Vec<String>,
    /// Expansion budget.
    pub max_expansions: Option<u64>,
    /// Which value of a `.csv` matrix is an obstacle (`--obstacle 0|1`; default `0`, as a
    /// config's `obstacle` key); refused for other maps and for a map the config lists.
    pub obstacle: Option<planner_maps::CsvConvention>,
}

/// What `plan` does besides [`PlanArgs`]: options of the planning run itself, kept apart
/// so that adding one does not change how `PlanArgs` is built.
#[derive(Debug, Clone, Default)]
pub struct PlanOptions {
    /// Cell costs for a map read from its file (not one a config lists, whose map set's
    /// `costs` table decides).
    pub costs: PlanCosts,
    /// The memory limit of the planner's per-cell state, in MiB (`--max-memory-mb`);
    /// `None`: the label's `budget.max_memory_mb`, else the runner's default
    /// ([`crate::run::default_max_memory_mb`], half the machine's memory).
    pub max_memory_mb: Option<u64>,
    /// Run once more, after the timed run, with the expanded cells recorded
    /// ([`PlanResult::expanded`], drawn by planner-report's `figures::draw_run`); the second run must
    /// give the same counters, status and path (else an error).
    pub record_expanded: bool,
    /// With `record_expanded`, also record the search step by step
    /// ([`PlanResult::events`], for `plan --trace`).
    pub record_events: bool,
}

/// `plan`'s cell cost options, the flags of a map set's `costs` table (configs/README.md):
/// all off by default, so a map reads unweighted as before.
#[derive(Debug, Clone, Default)]
pub struct PlanCosts {
    /// `--weights FILE`: a `.csv` of cell weights for the map (planner-maps' weight files).
    pub weights: Option<PathBuf>,
    /// `--cost-rule mean|entered`: the move cost rule (default mean).
    pub rule: Option<planner_api::CostRule>,
    /// `--graded`: read a ROS map's graded values as costs with nav2's bands (implied by
    /// `lethal` and `unknown`).
    pub graded: bool,
    /// `--lethal N`: ROS costs from N up are blocked (default 254).
    pub lethal: Option<u8>,
    /// `--unknown N`: the cost of a ROS map's unknown cells (default: blocked).
    pub unknown: Option<u8>,
    /// `--swamp N`: the weight of Moving AI swamp `S` (terrain weights).
    pub swamp: Option<u16>,
    /// `--water N`: the weight of Moving AI water `W`, passable at it (terrain weights).
    pub water: Option<u16>,
    /// `--ignore-costs`: a planner that does not honour cell costs plans on a weighted map
    /// without them (a config's `costs = "ignore"`), instead of being refused.
    pub ignore: bool,
}

impl PlanCosts {
    /// Whether any option reads costs (all but `ignore`).
    fn any(&self) -> bool {
        self.weights.is_some()
            || self.rule.is_some()
            || self.graded
            || self.lethal.is_some()
            || self.unknown.is_some()
            || self.swamp.is_some()
            || self.water.is_some()
    }

    /// The reading options for `map`, checked as a map set's `costs` table is: ROS bands
    /// for ROS maps, terrain for Moving AI `.map`s, a weight file for any map but not with
    /// either.
    fn read_options(&self, map: &Path) -> Result<planner_maps::CostOptions, RunnerError> {
        let extension = map
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .unwrap_or_default();
        let ros = matches!(extension.as_str(), "yaml" | "yml" | "pgm" | "png");
        let graded = self.graded || self.lethal.is_some() || self.unknown.is_some();
        let terrain = self.swamp.is_some() || self.water.is_some();
        let mut options = planner_maps::CostOptions {
            rule: self.rule.unwrap_or_default(),
            ..planner_maps::CostOptions::default()
        };
        if self.weights.is_some() && (graded || terrain) {
            return Err(UsageError::WeightsAndBands.into());
        }
        if graded {
            if !ros {
                return Err(UsageError::BandsNotRos(map.to_path_buf()).into());
            }
            options.graded = true;
            if let Some(lethal) = self.lethal {
                if lethal == 0 {
                    return Err(UsageError::LethalZero.into());
                }
                options.bands.lethal = lethal;
            }
            if let Some(unknown) = self.unknown {
                if unknown == 255 {
                    return Err(UsageError::UnknownTooHigh.into());
                }
                options.bands.unknown = Some(unknown);
            }
        }
        if terrain {
            if extension != "map" {
                return Err(UsageError::TerrainNotMovingAi(map.to_path_buf()).into());
            }
            let Some(swamp) = self.swamp else {
                return Err(UsageError::WaterWithoutSwamp.into());
            };
            if swamp == 0 || self.water == Some(0) {
                return Err(UsageError::TerrainWeightZero.into());
            }
            options.terrain = Some(planner_maps::TerrainWeights {
                swamp,
                water: self.water,
            });
        }
        if self.rule.is_some() && !graded && !terrain && self.weights.is_none() {
            return Err(UsageError::RuleWithoutCosts.into());
        }
        Ok(options)
    }
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
    /// The planner's counters, in its order.
    pub counters: &'a planner_api::Counters,
    /// The seed a seeded planner ran with.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub seed: Option<u64>,
    /// Coverage planners only: coverage metrics and returns.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coverage: Option<CoverageJson<'a>>,
    /// The cells the planner marked (PA-star's handover points), if any.
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub marks: &'a [planner_api::Mark],
    /// On a weighted map, the path's cost under the map's cost rule (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cost: Option<f64>,
    /// Why the planner did not run, when it did not: its per-cell state is over the
    /// memory limit (`needs 114 MB for a 3000 x 3000 grid, over the max_memory_mb = 1
    /// budget`), with status `budget_exhausted`. Absent when it ran, so that a script tells
    /// a refused run from a spent budget.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_run: Option<&'a str>,
    /// What a run that ran says of its result, when it says something: its costs
    /// saturated (`its costs reached 4.294967e9, where gridplan's costs saturate, before
    /// it traced a path`). Absent otherwise (and for a run that did not run: `not_run`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<&'a str>,
    /// On a map with a ROS map frame (a `map_server` YAML), the run in that frame, in
    /// metres (absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub map_frame: Option<FrameJson>,
}

/// `plan --json`'s `map_frame`: the map's frame and the run's cells as map-frame points
/// (cell centres, [`planner_maps::MapFrame::world`]).
#[derive(Debug, Serialize)]
pub struct FrameJson {
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the bottom-left cell's lower-left corner, as the YAML gives it.
    pub origin: [f64; 3],
    /// The start cell's centre.
    pub start: (f64, f64),
    /// The goal cell's centre (absent for a coverage planner).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub goal: Option<(f64, f64)>,
    /// The path's cells' centres, as `path` lists the cells.
    pub path: Vec<(f64, f64)>,
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

/// One finished run.
pub struct PlanResult {
    /// The grid.
    pub grid: Grid,
    /// The map's ROS map frame, when it has one ([`MapEntry::frame`]).
    pub frame: Option<planner_maps::MapFrame>,
    /// The map's unknown cells, when it has some ([`MapEntry::unknown`]).
    pub unknown: Option<Vec<bool>>,
    /// Planner label or name.
    pub planner: String,
    /// Whether the planner covers (no goal).
    pub coverage: bool,
    /// The budget the run had.
    pub budget: Budget,
    /// The run's record, as a sweep records it.
    pub record: RunRecord,
    /// The cells the planner expanded, in order, when [`PlanOptions::record_expanded`]
    /// asked for them and the planner records them; else empty.
    pub expanded: Vec<Cell>,
    /// The search step by step, when [`PlanOptions::record_events`] asked for it and the
    /// planner records it; else empty.
    pub events: Vec<planner_api::SearchEvent>,
}

/// The files a plan of `args` with `options` may read: the map, a ROS map's image (when its
/// YAML can be read now), the `.scen` beside the map, the config and the weight file. A
/// picture written for the run must not replace one of them (`gridplan plan --svg`,
/// `--trace`, `--gif`).
pub fn input_files(args: &PlanArgs, options: &PlanOptions) -> Vec<PathBuf> {
    let mut files = vec![args.map.clone(), scen_beside(&args.map)];
    if planner_maps::MapFormat::from_path(&args.map)
        .is_ok_and(|f| f == planner_maps::MapFormat::Ros)
    {
        let origin = args.map.display().to_string();
        let image = planner_maps::read_text_file(&args.map, planner_maps::DEFAULT_MAX_FILE_BYTES)
            .and_then(|text| planner_maps::parse_ros_yaml(&text, &origin));
        if let Ok(yaml) = image {
            let dir = args.map.parent().unwrap_or(Path::new(""));
            files.push(dir.join(yaml.image));
        }
    }
    files.extend(args.config.iter().cloned());
    files.extend(options.costs.weights.iter().cloned());
    files
}

/// The `.scen` file beside map `map` whose problems `plan` takes when the map has none of
/// its own (`map.map.scen` for `map.map`).
fn scen_beside(map: &Path) -> PathBuf {
    PathBuf::from(format!("{}.scen", map.display()))
}

/// Runs `args`. A coverage planner covers from the start (`--start`, or the problem's)
/// and takes no `--goal`.
pub fn run(args: &PlanArgs) -> Result<PlanResult, RunnerError> {
    run_with(args, &PlanOptions::default())
}

/// Runs `args` with `options` (see [`run`]).
pub fn run_with(args: &PlanArgs, options: &PlanOptions) -> Result<PlanResult, RunnerError> {
    let experiment = match &args.config {
        Some(path) => Some(config::load(path)?),
        None => None,
    };
    let mut spec = resolve_spec(args, options, experiment.as_ref())?;
    let coverage = spec.is_coverage();
    let (map, problems, convention) =
        resolve_map(args, &spec, &options.costs, experiment.as_ref())?;
    // As a config's check: a planner that cannot honour cell costs is refused a weighted
    // map, unless told to ignore them.
    spec.ignore_costs |= options.costs.ignore;
    if refuses_costs(&spec, &map.grid) {
        return Err(UsageError::RefusesCosts {
            label: spec.label.clone(),
            planner: spec.name.to_string(),
            why: spec.factory.specs().cell_costs_refusal(),
            map: map.name.clone(),
        }
        .into());
    }
    let entry = pick_problem(args, &spec, &map, &problems)?;
    let check_goal = if coverage { entry.start } else { entry.goal };
    if let Err(error) = Problem::new(&map.grid, entry.start, check_goal) {
        let hint = convention.and_then(|convention| {
            planner_maps::csv_inversion_hint(&map.grid, convention, entry.start, check_goal)
        });
        return Err(match hint {
            Some(hint) => RunnerError::InvertedProblem {
                map: args.map.clone(),
                error,
                hint,
            },
            None => RunnerError::Problem {
                map: args.map.clone(),
                error,
            },
        });
    }
    let seed = experiment.as_ref().map_or(0, |e| e.seed);
    run_single(
        map,
        entry,
        spec,
        seed,
        &args.planner,
        options.record_expanded,
        options.record_expanded && options.record_events,
    )
}

/// Whether `spec` is refused `grid`: the grid has cell costs, the planner cannot honour
/// them ([`planner_api::PlannerSpecs::cell_costs`]), and its label does not say
/// `costs = "ignore"` ([`PlannerSpec::ignore_costs`]). A config makes this check for its
/// map sets; `plan`, the server and the Python package make it for one run.
pub fn refuses_costs(spec: &PlannerSpec, grid: &Grid) -> bool {
    grid.is_weighted() && !spec.ignore_costs && !spec.factory.specs().cell_costs
}

/// One run of `spec` on `entry` of `map` with `seed`, through [`run_one`] as a sweep's
/// repeat 0 runs it (`planner` names it in the result); with `record_expanded`, once more
/// with the expanded cells recorded ([`crate::expanded::record_expanded`], which checks
/// that the second run repeats the first), unless the first was cancelled
/// ([`Budget::cancel`]); with `record_events` too, that run also records the search step by
/// step ([`PlanResult::events`]). The start and goal are checked by the caller.
pub fn run_single(
    map: MapEntry,
    entry: ProblemEntry,
    spec: PlannerSpec,
    seed: u64,
    planner: &str,
    record_expanded: bool,
    record_events: bool,
) -> Result<PlanResult, RunnerError> {
    let coverage = spec.is_coverage();
    let mut single = Experiment::single(map, entry, spec, seed);
    let record = run_one(
        &single,
        &RunSpec {
            map: 0,
            problem: 0,
            planner: 0,
            repeat: 0,
        },
        &mut Workspace::default(),
        None,
    )?;
    let (map, spec) = (&single.maps[0], &single.planners[0]);
    let (expanded, events) = if record_expanded && !spec.budget.is_cancelled() {
        let problem = &map.problems[0];
        crate::expanded::record_search(&single, map, problem, spec, &record, record_events)?
    } else {
        (Vec::new(), Vec::new())
    };
    let budget = spec.budget;
    let map = single.maps.swap_remove(0);
    Ok(PlanResult {
        grid: map.grid,
        frame: map.frame,
        unknown: map.unknown,
        planner: planner.to_string(),
        coverage,
        budget,
        record,
        expanded,
        events,
    })
}

/// A planner parameter's value as `plan --set key=value` (and `gridplan serve`'s settings)
/// give it: TOML (`1.5`, `true`, `"octile"`), or else a bare word (`octile`). A value that
/// starts as a number does (a digit, a sign or a point) must be one: `None` for `1e400`
/// (beyond 64 bits), `1_000_` or `1.5x`, which are not taken for words.
///
/// ```
/// use planner_runner::plan::setting_value;
/// assert_eq!(setting_value("2.5"), Some(toml::Value::Float(2.5)));
/// assert_eq!(setting_value("octile"), Some(toml::Value::String("octile".into())));
/// assert_eq!(setting_value("1e400"), None);
/// ```
pub fn setting_value(value: &str) -> Option<toml::Value> {
    match toml::from_str::<toml::Table>(&format!("v = {value}")) {
        Ok(mut table) => table.remove("v"),
        Err(_) if value.starts_with(|c: char| c.is_ascii_digit() || "+-.".contains(c)) => None,
        Err(_) => Some(toml::Value::String(value.to_string())),
    }
}

/// The planner `args` name (a registry name, or a label of `experiment`), with the
/// `--set` overrides and the budget `plan` applies.
fn resolve_spec(
    args: &PlanArgs,
    options: &PlanOptions,
    experiment: Option<&Experiment>,
) -> Result<PlannerSpec, RunnerError> {
    let mut spec = match experiment {
        Some(experiment) => experiment
            .planners
            .iter()
            .find(|p| p.label == args.planner)
            .cloned()
            .ok_or_else(|| RunnerError::UnknownLabel {
                config: experiment.source.clone(),
                label: args.planner.clone(),
                labels: experiment
                    .planners
                    .iter()
                    .map(|p| p.label.clone())
                    .collect(),
            })?,
        None => config::planner_from_table(
            &args.planner,
            &args.planner,
            toml::Table::new(),
            Budget::unlimited(),
        )?,
    };
    if !args.set.is_empty() {
        let mut params = spec.params.clone();
        let mut given: Vec<(&str, &str)> = Vec::new();
        for assignment in &args.set {
            let (key, value) = assignment
                .split_once('=')
                .filter(|(key, _)| !key.trim().is_empty())
                .ok_or_else(|| UsageError::Assignment(assignment.clone()))?;
            let (key, value) = (key.trim(), value.trim());
            // The same value twice is one setting; two values leave which wins unsaid.
            if let Some(&(_, first)) = given.iter().find(|(k, _)| *k == key) {
                if first != value {
                    return Err(UsageError::SetTwice {
                        key: key.to_string(),
                        first: first.to_string(),
                        second: value.to_string(),
                    }
                    .into());
                }
            }
            given.push((key, value));
            let parsed = setting_value(value).ok_or_else(|| UsageError::SetNumber {
                key: key.to_string(),
                value: value.to_string(),
            })?;
            params.insert(key.trim().to_string(), parsed);
        }
        spec = config::planner_from_table(&spec.label, spec.name, params, spec.budget)?;
    }
    if let Some(n) = args.max_expansions {
        spec.budget.max_expansions = Some(n);
    }
    if spec.budget.max_expansions.is_none() {
        spec.budget.max_expansions = Some(DEFAULT_PLAN_EXPANSIONS);
    }
    if let Some(mb) = options.max_memory_mb {
        spec.budget.max_memory_mb = Some(mb);
    }
    Ok(spec)
}

/// The map `args` names with its own problems (the config's entry when `experiment` lists
/// it, else the file read), and the `.csv` convention it was read with, if any.
fn resolve_map(
    args: &PlanArgs,
    spec: &PlannerSpec,
    costs: &PlanCosts,
    experiment: Option<&Experiment>,
) -> Result<(MapEntry, Vec<ProblemEntry>, Option<CsvConvention>), RunnerError> {
    let listed = experiment.and_then(|e| e.find_map(&args.map)).cloned();
    let config = || experiment.map(|e| e.source.clone()).unwrap_or_default();
    if listed.is_some() && costs.any() {
        return Err(UsageError::CostsOfListedMap {
            config: config(),
            map: args.map.clone(),
        }
        .into());
    }
    if let Some(convention) = args.obstacle {
        let value = convention.obstacle_value();
        if !config::is_csv(&args.map) {
            return Err(UsageError::ObstacleNotCsv {
                value,
                map: args.map.clone(),
            }
            .into());
        }
        if listed.is_some() {
            return Err(UsageError::ObstacleOfListedMap {
                value,
                config: config(),
                map: args.map.clone(),
            }
            .into());
        }
    }
    let convention =
        (listed.is_none() && config::is_csv(&args.map)).then(|| args.obstacle.unwrap_or_default());
    if let Some(map) = listed {
        let problems = map.problems.clone();
        return Ok((map, problems, convention));
    }
    // The map is read within the run's memory budget (--max-memory-mb, the label's, else
    // half the machine's memory), not a fixed size.
    let max_cells = crate::run::effective_budget(spec).max_memory_mb.map_or(
        planner_maps::DEFAULT_MAX_CELLS,
        planner_maps::max_cells_for_memory_mb,
    );
    let options = planner_maps::ReadOptions {
        csv: args.obstacle.unwrap_or_default(),
        max_cells,
        costs: costs.read_options(&args.map)?,
        ..planner_maps::ReadOptions::default()
    };
    let file = config::read_map_file(&args.map, &options)?;
    let grid = match &costs.weights {
        Some(weights) => {
            planner_maps::read_weights(weights, file.grid, options.costs.rule, &options)?
        }
        None => file.grid,
    };
    // Points in metres on a YAML whose frame places no cell: say why it has none.
    let world = [("start", args.start_world), ("goal", args.goal_world)];
    if let (Some(why), Some((which, _))) = (
        file.frame_error,
        world.iter().find(|(_, point)| point.is_some()),
    ) {
        return Err(UsageError::UnusableMapFrame {
            which,
            map: args.map.clone(),
            why,
        }
        .into());
    }
    let map = MapEntry {
        name: file_name(&args.map),
        path: args.map.clone(),
        grid,
        problems: Vec::new(),
        frame: file.frame,
        unknown: file.unknown,
    };
    // Cells given on the command line need no scenario: a `.scen` beside the map is read
    // only for `--problem K` or when no start or goal is given.
    let cells_given = args.start.is_some()
        || args.goal.is_some()
        || args.start_world.is_some()
        || args.goal_world.is_some();
    let pairs = own_pairs(&args.map, &map.grid, &file.problems, !cells_given)?;
    let problems = pairs
        .into_iter()
        .enumerate()
        .map(|(i, (start, goal, optimal_length))| {
            ProblemEntry::new(&map.grid, i + 1, start, goal, optimal_length)
        })
        .collect();
    Ok((map, problems, convention))
}

/// The problem `args` asks for: `--problem K` of the map's own, `--start` (and `--goal`),
/// else the map's first problem, else corner to corner.
fn pick_problem(
    args: &PlanArgs,
    spec: &PlannerSpec,
    map: &MapEntry,
    problems: &[ProblemEntry],
) -> Result<ProblemEntry, RunnerError> {
    let coverage = spec.is_coverage();
    let start = in_frame(args, map, "start", args.start, args.start_world)?;
    let goal = in_frame(args, map, "goal", args.goal, args.goal_world)?;
    Ok(match (start, goal, args.problem) {
        (Some(_), Some(_), Some(_)) | (Some(_), None, Some(_)) | (None, Some(_), Some(_)) => {
            return Err(UsageError::ProblemAndCells.into())
        }
        (_, Some(_), None) if coverage => {
            return Err(UsageError::CoverageGoal(spec.name.to_string()).into())
        }
        (Some(start), None, None) if coverage => {
            ProblemEntry::new(&map.grid, 1, start, start, None)
        }
        (Some(start), Some(goal), None) => ProblemEntry::new(&map.grid, 1, start, goal, None),
        (Some(_), None, None) | (None, Some(_), None) => {
            return Err(UsageError::StartWithoutGoal.into())
        }
        (None, None, Some(k)) => {
            problems
                .get(k.wrapping_sub(1))
                .cloned()
                .ok_or_else(|| UsageError::NoSuchProblem {
                    number: k,
                    map: args.map.clone(),
                    count: problems.len(),
                })?
        }
        (None, None, None) => problems.first().cloned().unwrap_or_else(|| {
            let corner = Cell::new(map.grid.width() - 1, map.grid.height() - 1);
            ProblemEntry::new(&map.grid, 1, Cell::new(0, 0), corner, None)
        }),
    })
}

/// The cell `cell` names, or the cell of the map that holds map-frame point `world`.
fn in_frame(
    args: &PlanArgs,
    map: &MapEntry,
    which: &'static str,
    cell: Option<Cell>,
    world: Option<(f64, f64)>,
) -> Result<Option<Cell>, RunnerError> {
    let Some((x, y)) = world else {
        return Ok(cell);
    };
    if cell.is_some() {
        return Err(UsageError::CellAndWorld(which).into());
    }
    let Some(frame) = map.frame else {
        return Err(UsageError::NoMapFrame {
            which,
            map: args.map.clone(),
        }
        .into());
    };
    frame
        .cell_at(x, y)
        .map(Some)
        .ok_or_else(|| RunnerError::OutsideMap {
            map: args.map.clone(),
            which,
            point: (x, y),
            frame,
        })
}

fn file_name(path: &Path) -> String {
    path.file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| path.display().to_string())
}

/// The map's own start-goal pairs, else, with `with_scen`, those of the `.scen` file
/// beside it (checked against the map's size; a scenario naming another map file is
/// warned about). None when there is no `.scen` there; anything else at its path that is
/// not a scenario file (not a regular file, a link loop) is an error naming it.
fn own_pairs(
    map: &Path,
    grid: &Grid,
    own: &[planner_maps::ProblemSpec],
    with_scen: bool,
) -> Result<Vec<(Cell, Cell, Option<f64>)>, RunnerError> {
    if !own.is_empty() {
        return Ok(own.iter().map(|p| (p.start, p.goal, None)).collect());
    }
    let scen = scen_beside(map);
    // Only a missing `.scen` falls back to the corners: anything else there (a FIFO, a
    // directory, a dangling link or a link loop) is read, and refused naming it, as an
    // experiment refuses it.
    let missing =
        std::fs::symlink_metadata(&scen).is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound);
    if !with_scen || missing {
        return Ok(Vec::new());
    }
    let scenarios = planner_maps::read_scenarios(&scen)?;
    let name = file_name(map);
    let mut warned = false;
    let mut pairs = Vec::with_capacity(scenarios.len());
    for s in &scenarios {
        if (s.width, s.height) != (grid.width(), grid.height()) {
            return Err(UsageError::ScenarioSize {
                scen,
                line: s.line,
                column: s.size_column,
                scenario: (s.width, s.height),
                map: map.to_path_buf(),
                grid: (grid.width(), grid.height()),
            }
            .into());
        }
        if !warned && !s.names_map(&name) {
            tracing::warn!(
                "{}:{}: the scenario names map {}, not {}",
                scen.display(),
                s.line,
                s.map,
                name
            );
            warned = true;
        }
        pairs.push((s.start, s.goal, Some(s.optimal_length)));
    }
    Ok(pairs)
}

impl PlanResult {
    /// The one JSON object of `--json`.
    pub fn to_json(&self) -> Result<String, RunnerError> {
        let r = &self.record;
        let path = r.path.as_ref();
        let json = PlanJson {
            status: r.status.as_str(),
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
            counters: &r.counters,
            seed: r.seed,
            coverage: self.coverage_json(),
            marks: &r.marks,
            cost: r.cost,
            not_run: crate::run::not_run_reason(r),
            error: r
                .error
                .as_deref()
                .filter(|_| crate::run::not_run_reason(r).is_none()),
            map_frame: self.frame.map(|frame| FrameJson {
                resolution: frame.resolution,
                origin: frame.origin,
                start: frame.world(r.start),
                goal: (!self.coverage).then(|| frame.world(r.goal)),
                path: path.map_or_else(Vec::new, |p| {
                    p.cells().iter().map(|&c| frame.world(c)).collect()
                }),
            }),
        };
        serde_json::to_string(&json).map_err(RunnerError::Json)
    }

    fn coverage_json(&self) -> Option<CoverageJson<'_>> {
        let returns = self.record.returns.as_deref()?;
        let counter = |name: &str| self.record.counters.get(name).unwrap_or(0);
        let (covered, reachable) = (counter("n_covered"), counter("n_reachable"));
        Some(CoverageJson {
            n_reachable: reachable,
            n_covered: covered,
            percent: if reachable == 0 {
                0.0
            } else {
                100.0 * covered as f64 / reachable as f64
            },
            n_revisits: counter("n_revisits"),
            returns,
        })
    }

    /// Whether the run stopped at the budget `plan` applies by default.
    pub fn hit_default_budget(&self) -> bool {
        self.record.status == crate::record::RunStatus::BudgetExhausted
            && self.record.error.is_none()
            && self.budget.max_expansions == Some(DEFAULT_PLAN_EXPANSIONS)
    }

    /// The run for a person ([`PlanResult::to_text_within`] at [`TEXT_COLUMNS`] columns).
    pub fn to_text(&self) -> String {
        self.to_text_within(TEXT_COLUMNS)
    }

    /// The run for a person: header, metrics, the map with the path drawn ([`draw_text`]) if
    /// it is at most `columns` cells wide (else a line saying so, with a hint to `--svg`),
    /// marks, counters.
    pub fn to_text_within(&self, columns: usize) -> String {
        let r = &self.record;
        let mut out = String::new();
        let route = if self.coverage {
            format!("covering from {}", r.start)
        } else {
            format!("{} -> {}", r.start, r.goal)
        };
        let _ = writeln!(
            out,
            "{} on a {}x{} grid, {route}: {}",
            self.planner,
            self.grid.width(),
            self.grid.height(),
            r.status
        );
        if let Some(frame) = self.frame {
            let point = |c: Cell| {
                let (x, y) = frame.world(c);
                format!("({}, {})", planner_maps::metres(x), planner_maps::metres(y))
            };
            let route = match self.coverage {
                true => format!("start {}", point(r.start)),
                false => format!("start {} -> goal {}", point(r.start), point(r.goal)),
            };
            let length = r.path.as_ref().map_or(String::new(), |p| {
                format!(
                    ", path {} m",
                    planner_maps::metres(p.metrics().length * frame.resolution)
                )
            });
            let _ = writeln!(
                out,
                "map frame (metres, cell centres): {route}{length}; {} m per cell; every point: --json's map_frame",
                planner_maps::metres(frame.resolution)
            );
        }
        if self.hit_default_budget() {
            let _ = writeln!(
                out,
                "(stopped at plan's default budget of {DEFAULT_PLAN_EXPANSIONS} expansions; raise it with --max-expansions)"
            );
        }
        match (crate::run::not_run_reason(r), &r.error) {
            (Some(error), _) => {
                let _ = writeln!(out, "(not run: {error}; raise it with --max-memory-mb)");
            }
            (None, Some(error)) => {
                let _ = writeln!(out, "({error})");
            }
            (None, None) => {}
        }
        if let Some(path) = &r.path {
            let m = path.metrics();
            let _ = writeln!(
                out,
                "steps (D) {}, turns (T) {}, score {}, length {:.4}",
                m.steps, m.turns, m.score, m.length
            );
            if let Some(cost) = r.cost {
                let _ = writeln!(
                    out,
                    "cost {cost:.4} (cell weights, {} rule)",
                    self.grid.weights().map_or("mean", |w| w.rule().name())
                );
            }
        }
        if let Some(c) = self.coverage_json() {
            let _ = writeln!(
                out,
                "covered {} of {} reachable cells ({:.2}%), {} revisits, {} returns",
                c.n_covered,
                c.n_reachable,
                c.percent,
                c.n_revisits,
                c.returns.len()
            );
        }
        if self.grid.width() as usize <= columns {
            let goal = (!self.coverage).then_some(r.goal);
            out.push_str(&draw_text(&self.grid, r.start, goal, r.path.as_ref()));
        } else {
            let _ = writeln!(
                out,
                "(the map is {} cells wide, more than the {columns} columns here: not drawn; --svg FILE draws it)",
                self.grid.width()
            );
        }
        if !r.marks.is_empty() {
            let marks: Vec<String> = r
                .marks
                .iter()
                .map(|m| format!("{} {}", m.label, m.cell))
                .collect();
            let _ = writeln!(out, "marks: {}", marks.join(", "));
        }
        let _ = writeln!(out, "{}", r.counters);
        out
    }
}

/// The grid as text: `#` blocked, `.` free, `S` start, `G` goal (if any), and the path: an
/// arrow (`>` `<` `v` `^`, diagonals `\` `/`) on each cell for the move leaving it (the last
/// one when a coverage path leaves a cell several times), `*` on the cells where a longer
/// move starts. Without a goal (coverage) the path's last cell is `E`, its end.
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
    if goal.is_none() {
        if let Some(end) = path.and_then(|p| p.cells().last()) {
            canvas[end.y as usize][end.x as usize] = 'E';
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
