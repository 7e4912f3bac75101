//! Experiment configs: parsing with positions, validation, and expansion into runs.
//!
//! `configs/README.md` documents every key. Relative paths in a config are relative to
//! the config file's directory. Every error names the file, line and column, and the key.

use std::ops::Range;
use std::path::{Path, PathBuf};

use indexmap::IndexMap;
use planner_api::{Budget, Cell, Grid, Problem};
use schemars::JsonSchema;
use serde::Deserialize;
use toml::Spanned;

use planner_registry as registry;
use planner_registry::{Factory, Task};

/// Most worker threads a config or command line may ask for.
pub const MAX_THREADS: usize = 256;

/// A config error with its position: `file:line:column: message`, or `file: message` when
/// it has no position (line 0).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}{}: {message}", file.display(), position(*line, *column))]
pub struct ConfigError {
    /// The config file.
    pub file: PathBuf,
    /// 1-based line, 0 when the error has no position.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
    /// What is wrong.
    pub message: String,
}

fn position(line: usize, column: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}:{column}")
    }
}

/// Locates byte offsets of one source text as lines and columns.
struct Source<'a> {
    file: &'a Path,
    text: &'a str,
}

impl Source<'_> {
    fn error(&self, span: Option<Range<usize>>, message: impl Into<String>) -> ConfigError {
        let (line, column) = match span {
            Some(span) => {
                let before = &self.text[..span.start.min(self.text.len())];
                let line = before.matches('\n').count() + 1;
                let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
                (line, column)
            }
            None => (0, 0),
        };
        ConfigError {
            file: self.file.to_path_buf(),
            line,
            column,
            message: message.into(),
        }
    }
}

/// An experiment config as written (configs/README.md). Its `JsonSchema` derive is the
/// experiment schema of `gridplan schema` ([`crate::schema`]), so a key added here is in
/// the schema; the `sections` and `planners` schemas are filled in there (the report's
/// section names, the registry's planners).
#[derive(Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(
    title = "gridplan experiment config",
    description = "An experiment: every map x problem x planner x repeat (configs/README.md)."
)]
pub(crate) struct RawConfig {
    /// The experiment's name; names the output directory.
    #[schemars(with = "String", pattern(r"^[A-Za-z0-9_-]+$"), length(max = MAX_NAME_LEN))]
    name: Spanned<String>,
    /// Free text, copied to the top of summary.md.
    description: Option<String>,
    /// Output directory (default results/<name>).
    #[schemars(with = "Option<String>")]
    output: Option<Spanned<String>>,
    /// Worker threads; 0 = one per core.
    #[serde(default = "zero")]
    #[schemars(with = "usize", range(max = MAX_THREADS))]
    threads: Spanned<usize>,
    /// Runs per (map, problem, planner).
    #[serde(default = "one")]
    #[schemars(with = "u32", range(min = 1))]
    repeats: Spanned<u32>,
    /// Base seed; seeded planners get seed + repeat.
    #[serde(default)]
    seed: u64,
    /// Limits per run, for every planner; a planner table's own `budget` sets some of
    /// them for that planner, key by key (the keys it leaves out keep these values).
    #[serde(default)]
    #[schemars(with = "crate::schema::BudgetKeys")]
    budget: Budget,
    /// Which figures to draw.
    #[serde(default)]
    figures: FigureMode,
    /// At most this many problems per map get figures (default: as many as keep a map's
    /// figures within 2^24 cells of drawn map, at most 256: `Experiment::figure_limit`).
    figures_per_map: Option<usize>,
    /// Which problems of a map get figures.
    #[serde(default)]
    figures_pick: FigurePick,
    /// Also draw each drawn run's expanded cells.
    #[serde(default)]
    figures_expanded: bool,
    /// More line charts of a metric against a parameter.
    #[serde(default)]
    #[schemars(with = "Vec<ChartSpec>")]
    charts: Vec<Spanned<ChartSpec>>,
    /// Write OMPL benchmark logs.
    #[serde(default)]
    ompl: bool,
    /// Which runs' paths to keep in paths.jsonl.
    #[serde(default)]
    paths: PathsMode,
    /// Which result tables to write (default all: csv, json, parquet).
    #[schemars(with = "Option<Vec<crate::output::TableFormat>>", length(min = 1))]
    outputs: Option<Spanned<Vec<crate::output::TableFormat>>>,
    /// A TOML file of published values to compare with.
    #[schemars(with = "Option<String>")]
    published: Option<Spanned<String>>,
    /// Limits of the snapshot test.
    #[serde(default)]
    test: TestLimits,
    /// The summary.md sections to write (configs/README.md).
    #[schemars(with = "Option<Vec<serde_json::Value>>")]
    sections: Option<Spanned<Vec<RawSection>>>,
    /// The map sets.
    #[schemars(with = "Vec<RawMaps>", length(min = 1))]
    maps: Vec<Spanned<RawMaps>>,
    /// Planner labels; each table runs one registered planner.
    #[schemars(with = "serde_json::Map<String, serde_json::Value>", length(min = 1))]
    planners: IndexMap<Spanned<String>, Spanned<RawParams>>,
}

/// One entry of `sections = [...]`: a section name, or a table with its `name` and the
/// section's own options (e.g. `{ name = "seed002", proposed = "pastar" }`).
enum RawSection {
    Name(String),
    Table(toml::Table),
}

/// Read by hand, not `untagged`, so that a wrong entry says what an entry is (serde's
/// untagged enum named the Rust type: "did not match any variant of untagged enum").
impl<'de> Deserialize<'de> for RawSection {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error as _;
        match toml::Value::deserialize(deserializer)? {
            toml::Value::String(name) => Ok(RawSection::Name(name)),
            toml::Value::Table(table) => Ok(RawSection::Table(table)),
            other => Err(D::Error::custom(format!(
                "invalid type: {} {other}, expected a section name (a string) or a table {{ name = \"...\", ... }}",
                other.type_str()
            ))),
        }
    }
}

fn zero() -> Spanned<usize> {
    Spanned::new(0..0, 0)
}

fn one() -> Spanned<u32> {
    Spanned::new(0..0, 1)
}

/// A `[[maps]]` set.
#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a `[[maps]]` table of map files and their problems"
)]
pub(crate) struct RawMaps {
    /// Map files or globs, relative to the config.
    #[schemars(with = "Vec<String>", length(min = 1))]
    files: Spanned<Vec<String>>,
    /// Where the problems come from when no `pairs` or `scen` is given.
    #[schemars(with = "Option<ProblemSource>")]
    problems: Option<Spanned<ProblemSource>>,
    /// The start cell of coverage problems (`problems = "start"`).
    #[schemars(with = "Option<[u32; 2]>")]
    start: Option<Spanned<Pair<u32>>>,
    /// Start-goal pairs.
    #[schemars(with = "Option<Vec<RawPair>>", length(min = 1))]
    pairs: Option<Spanned<Vec<RawPair>>>,
    /// Start-goal pairs as points of a ROS map's map frame, in metres.
    #[schemars(with = "Option<Vec<RawPoints>>", length(min = 1))]
    points: Option<Spanned<Vec<Spanned<RawPoints>>>>,
    /// A Moving AI scenario file, relative to the config.
    #[schemars(with = "Option<String>")]
    scen: Option<Spanned<String>>,
    /// The scenario buckets to keep.
    buckets: Option<Vec<u32>>,
    /// The scenario lines to keep, first and last (1-based).
    #[schemars(with = "Option<[std::num::NonZeroUsize; 2]>")]
    lines: Option<Spanned<Pair<usize>>>,
    /// Keep every n-th scenario.
    #[schemars(with = "Option<usize>", range(min = 1))]
    every: Option<Spanned<usize>>,
    /// At most this many scenarios.
    #[schemars(range(min = 1))]
    limit: Option<usize>,
    /// ROS maps: inflate obstacles by this many cells.
    #[schemars(with = "Option<u32>")]
    inflation: Option<Spanned<u32>>,
    /// ROS maps: inflate unknown cells too.
    #[schemars(with = "Option<bool>")]
    inflate_unknown: Option<Spanned<bool>>,
    /// .csv maps only: the value of a cell that is an obstacle (default 0).
    #[schemars(with = "Option<u8>", extend("enum" = [0, 1]))]
    obstacle: Option<Spanned<i64>>,
    /// Cell costs (weights): graded ROS maps by nav2's cost bands, a weight file, or Moving
    /// AI terrain letters.
    #[schemars(with = "Option<RawCosts>")]
    costs: Option<Spanned<RawCosts>>,
}

/// A map set's `costs = { ... }` (configs/README.md).
#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table of cell-cost options (`rule`, `lethal`, `unknown`, `weights`, `swamp`, `water`)"
)]
pub(crate) struct RawCosts {
    /// How a move's cost combines the weights of the cells it joins.
    #[schemars(with = "Option<crate::schema::CostRuleKeys>")]
    rule: Option<planner_api::CostRule>,
    /// ROS maps: the cost from which a cell is an obstacle.
    #[schemars(with = "Option<u8>", range(min = 1))]
    lethal: Option<Spanned<u8>>,
    /// ROS maps: the cost of an unknown cell.
    #[schemars(with = "Option<u8>", range(max = 254))]
    unknown: Option<Spanned<u8>>,
    /// A .csv file of cell weights, relative to the config.
    #[schemars(with = "Option<String>")]
    weights: Option<Spanned<String>>,
    /// Moving AI maps: the weight of a swamp cell (`S`).
    #[schemars(with = "Option<u16>", range(min = 1))]
    swamp: Option<Spanned<u16>>,
    /// Moving AI maps: the weight of a water cell (`W`).
    #[schemars(with = "Option<u16>", range(min = 1))]
    water: Option<Spanned<u16>>,
}

/// A start-goal pair of a map set.
#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table { start = [x, y], goal = [x, y] }"
)]
pub(crate) struct RawPair {
    /// The start cell.
    #[schemars(with = "[u32; 2]")]
    start: Pair<u32>,
    /// The goal cell.
    #[schemars(with = "[u32; 2]")]
    goal: Pair<u32>,
}

/// An `[x, y]` array of exactly two items. serde's `[T; 2]` reads the first two items
/// of a TOML array and ignores the rest, so a longer array is refused here, with the
/// same words as a shorter one ("invalid length 3, expected an array of length 2").
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Pair<T>(pub(crate) [T; 2]);

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Pair<T> {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for Visitor<T> {
            type Value = Pair<T>;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("an array of length 2")
            }

            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Pair<T>, A::Error> {
                use serde::de::Error as _;
                let x = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(0, &self))?;
                let y = seq
                    .next_element()?
                    .ok_or_else(|| A::Error::invalid_length(1, &self))?;
                let mut n = 2;
                while seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                    n += 1;
                }
                if n > 2 {
                    return Err(A::Error::invalid_length(n, &self));
                }
                Ok(Pair([x, y]))
            }
        }
        deserializer.deserialize_tuple(2, Visitor(std::marker::PhantomData))
    }
}

/// Where the problems of a map set come from when no `pairs` or `scen` is given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ProblemSource {
    /// From the top-left cell (0, 0) to the bottom-right cell (W-1, H-1): seed 000's setup.
    Corners,
    /// The map file's own start-goal pairs (seed 003's `.txt` header).
    File,
    /// One problem from the map set's `start = [x, y]`, with no goal (the goal is set to
    /// the start): for coverage planners (seed 004).
    Start,
}

/// Which figures a sweep draws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FigureMode {
    /// One SVG per (map, problem, planner) and one comparison per (map, problem).
    #[default]
    All,
    /// Only the comparison per (map, problem).
    Comparisons,
    /// None.
    None,
}

/// Which problems of a map get figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum FigurePick {
    /// The first `figures_per_map` problems, in order.
    #[default]
    First,
    /// The hardest problems: the largest stated optimum (else the largest straight-line
    /// distance from start to goal) first, up to `figures_per_map`.
    Hardest,
    /// One problem per scenario bucket (the first of each), spread evenly over the
    /// buckets when there are more than `figures_per_map`.
    Buckets,
}

/// A `[[charts]]` entry: one line chart of `y` against `x`, one line per group.
///
/// `x` and `group` name a planner parameter (as resolved, e.g. `beta`, `radius`) or
/// `bucket`; `y` names a record metric (`length`, `steps`, `turns`, `score`, `time_ms`,
/// `optimal_length`) or a counter (`n_expanded`). Values are medians over a label's runs.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a `[[charts]]` table (`x`, `y`, `group`, `title`)"
)]
pub struct ChartSpec {
    /// The horizontal axis: a planner parameter or `bucket`.
    pub x: String,
    /// The vertical axis: a metric or a counter.
    pub y: String,
    /// One line per value of this (a planner parameter, `planner` for the label without
    /// the x parameter, or `map`); default `map`.
    #[serde(default)]
    pub group: Option<String>,
    /// The chart's title; default "`y` against `x`".
    #[serde(default)]
    pub title: Option<String>,
}

/// Which runs' paths a sweep keeps in its results (`paths.jsonl`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PathsMode {
    /// Every run's path.
    All,
    /// The paths the figures draw: repeat 0 of every (map, problem, planner).
    #[default]
    Figures,
    /// None (figures then draw no paths).
    None,
}

impl PathsMode {
    /// Whether the path of a run with repeat `repeat` is kept.
    pub fn keeps(self, repeat: u32) -> bool {
        match self {
            PathsMode::All => true,
            PathsMode::Figures => repeat == 0,
            PathsMode::None => false,
        }
    }
}

/// Limits the snapshot test applies to keep large sweeps fast (ignored by `experiment`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table of test limits (`problems_per_map`, `repeats`)"
)]
pub struct TestLimits {
    /// At most this many problems per map in the test.
    pub problems_per_map: Option<usize>,
    /// At most this many repeats in the test.
    pub repeats: Option<u32>,
}

/// A validated experiment.
#[derive(Debug, Clone)]
pub struct Experiment {
    /// The config file.
    pub source: PathBuf,
    /// Experiment name.
    pub name: String,
    /// Free-text description.
    pub description: Option<String>,
    /// Output directory.
    pub output: PathBuf,
    /// Worker threads; 0 = one per core.
    pub threads: usize,
    /// Repeats per (map, problem, planner).
    pub repeats: u32,
    /// Base seed; stochastic planners get `seed + repeat`.
    pub seed: u64,
    /// Figures to draw.
    pub figures: FigureMode,
    /// Draw figures only for this many problems of each map (`None`: the default of
    /// [`Experiment::figure_limit`]).
    pub figures_per_map: Option<usize>,
    /// Which problems get figures (`figures_pick`).
    pub figures_pick: FigurePick,
    /// Whether figures draw each planner's expanded cells under its path
    /// (`figures_expanded`), from a run with recording on apart from the timed one.
    pub figures_expanded: bool,
    /// The parameter-study charts the config asks for (`[[charts]]`).
    pub charts: Vec<ChartSpec>,
    /// Whether `experiment` writes OMPL benchmark logs (`ompl = true`).
    pub ompl: bool,
    /// Which paths the results keep (`paths = "all" | "figures" | "none"`).
    pub paths: PathsMode,
    /// Which result tables are written (`outputs = ["csv", "json", "parquet"]`).
    pub outputs: crate::output::Outputs,
    /// Published values to compare with, if any.
    pub published: Option<Published>,
    /// Test-only limits.
    pub test: TestLimits,
    /// Maps with their problems, in config order (files sorted within a glob).
    pub maps: Vec<MapEntry>,
    /// Planner configurations, in config order.
    pub planners: Vec<PlannerSpec>,
    /// The summary.md sections the config names (`sections = [...]`); `None` lets each
    /// generic section decide whether it applies. The names are not checked here: the
    /// report knows its sections and checks them ([`Sections::error`]).
    pub sections: Option<Sections>,
}

/// The summary.md sections a config asks for, with the position of the `sections` key.
#[derive(Debug, Clone, PartialEq)]
pub struct Sections {
    /// The sections, in config order.
    pub requests: Vec<SectionRequest>,
    /// The config file.
    pub file: PathBuf,
    /// 1-based line of the `sections` key's value.
    pub line: usize,
    /// 1-based column.
    pub column: usize,
}

impl Sections {
    /// Whether the config asks for section `name`.
    pub fn wants(&self, name: &str) -> bool {
        self.requests.iter().any(|r| r.name == name)
    }

    /// The request for section `name`, if the config makes one.
    pub fn get(&self, name: &str) -> Option<&SectionRequest> {
        self.requests.iter().find(|r| r.name == name)
    }

    /// A config error at the `sections` key, `key `sections`: {message}`.
    pub fn error(&self, message: impl std::fmt::Display) -> ConfigError {
        ConfigError {
            file: self.file.clone(),
            line: self.line,
            column: self.column,
            message: format!("key `sections`: {message}"),
        }
    }
}

/// One section a config asks for: its name and its options (the planners it names, as
/// data: e.g. which label's planner is the proposed method).
#[derive(Debug, Clone, PartialEq)]
pub struct SectionRequest {
    /// The section's name.
    pub name: String,
    /// The section's options (the entry's table without `name`; empty for a bare name).
    pub options: toml::Table,
}

/// One map with its problems.
#[derive(Debug, Clone)]
pub struct MapEntry {
    /// The map's file name, unique within the experiment.
    pub name: String,
    /// Path as resolved.
    pub path: PathBuf,
    /// The grid.
    pub grid: Grid,
    /// The problems, in order.
    pub problems: Vec<ProblemEntry>,
    /// Where the cells lie in the ROS map frame (a `map_server` YAML's resolution and
    /// origin), for `plan --start-world`; `None` for the other formats.
    pub frame: Option<planner_maps::MapFrame>,
    /// The cells a ROS `map_server` map does not know ([`planner_maps::MapFile::unknown`]),
    /// drawn grey in figures; `None` for none.
    pub unknown: Option<Vec<bool>>,
}

/// One start-goal problem of a map.
#[derive(Debug, Clone)]
pub struct ProblemEntry {
    /// 1-based index within the map.
    pub index: usize,
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// The optimal length a scenario file states, if any.
    pub optimal_length: Option<f64>,
    /// The scenario file's bucket, for problems from a `.scen` file.
    pub bucket: Option<u32>,
    /// Why the problem cannot be planned (start or goal blocked or out of bounds), if so.
    pub invalid: Option<String>,
    /// Why its start cannot be covered from (blocked or out of bounds), if so: a coverage
    /// planner ignores the goal, so only this refuses its runs ([`ProblemEntry::invalid_for`]).
    pub invalid_start: Option<String>,
}

/// One labelled planner configuration.
#[derive(Debug, Clone)]
pub struct PlannerSpec {
    /// The label (the key under `[planners]`).
    pub label: String,
    /// Registry name.
    pub name: &'static str,
    /// The validated planner configuration: builds planners, knows their specs.
    pub factory: Factory,
    /// Parameters, as given (without `planner`, `budget` and `compare`).
    pub params: toml::Table,
    /// The budget for this planner: the experiment's, with the keys the planner's own
    /// `budget` table gives replaced, key by key.
    pub budget: Budget,
    /// Which published planner's values to compare with, when not its own.
    pub compare: Option<Compare>,
    /// `costs = "ignore"`: a planner that does not honour cell weights
    /// ([`planner_api::PlannerSpecs::cell_costs`]) runs on weighted maps with their weights
    /// left out, instead of being refused.
    pub ignore_costs: bool,
}

impl PlannerSpec {
    /// The label's parameters as its runs use them, for runs.json, summary.md and the
    /// OMPL logs: [`Factory::resolved`], except that a seeded planner's `seed` is the base
    /// seed of its runs ([`Factory::seed_for`] of repeat 0: its own `seed` if the table
    /// sets one, else the experiment's `base_seed`; repeat `r` runs with that plus `r`).
    /// The planner's `Config` alone says `seed = 0` for a table without one.
    pub fn parameters(&self, base_seed: u64) -> std::borrow::Cow<'_, serde_json::Value> {
        let resolved = self.factory.resolved();
        let seed = self.factory.seed_for(base_seed, 0);
        match (seed, resolved) {
            (Some(seed), serde_json::Value::Object(map))
                if map.contains_key(planner_api::SEED_PARAM) =>
            {
                let mut map = map.clone();
                map.insert(planner_api::SEED_PARAM.into(), seed.into());
                std::borrow::Cow::Owned(serde_json::Value::Object(map))
            }
            _ => std::borrow::Cow::Borrowed(resolved),
        }
    }
}

/// `compare = { with = "backtracking", metrics = ["steps", "turns", "score"] }`: mark these
/// metrics of this planner against another planner's published values (lexastar against
/// Backtracking's best paths). Without it a planner is compared under its registry name.
#[derive(Debug, Clone, PartialEq, Eq, Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table { with = \"<registry name>\", metrics = [...] }"
)]
pub struct Compare {
    /// The published planner key.
    pub with: String,
    /// The metrics to compare; the others are not marked.
    pub metrics: Vec<String>,
}

impl PlannerSpec {
    /// The published key under which `metric` of this planner is compared, if any.
    pub fn published_key(&self, metric: &str) -> Option<&str> {
        match &self.compare {
            Some(c) => c
                .metrics
                .iter()
                .any(|m| m == metric)
                .then_some(c.with.as_str()),
            None => Some(self.name),
        }
    }

    /// Whether it is a coverage planner: it covers from each problem's start and ignores
    /// the goal.
    pub fn is_coverage(&self) -> bool {
        self.factory.task() == Task::Coverage
    }
}

/// Published numbers: `[map_stem.planner_key] metric = value`, or `["map_stem#k".planner_key]`
/// for problem `k` of a map with several problems.
#[derive(Debug, Clone, Default)]
pub struct Published {
    /// The file they came from.
    pub path: PathBuf,
    /// map stem -> planner key -> metric -> value.
    pub values: IndexMap<String, IndexMap<String, IndexMap<String, f64>>>,
}

impl Published {
    /// The published value of `metric` for `planner` on problem `problem` of `map_stem`:
    /// the table `"<stem>#<problem>"` if the file has it, else `<stem>` for problem 1.
    pub fn get_problem(
        &self,
        map_stem: &str,
        problem: usize,
        planner: &str,
        metric: &str,
    ) -> Option<f64> {
        self.get(&format!("{map_stem}#{problem}"), planner, metric)
            .or_else(|| {
                (problem == 1)
                    .then(|| self.get(map_stem, planner, metric))
                    .flatten()
            })
    }

    /// The published value of `metric` for `planner` under the table named `map_stem`.
    pub fn get(&self, map_stem: &str, planner: &str, metric: &str) -> Option<f64> {
        self.values
            .get(map_stem)?
            .get(planner)?
            .get(metric)
            .copied()
    }
}

/// Reads and validates the experiment config at `path`.
pub fn load(path: &Path) -> Result<Experiment, ConfigError> {
    let text = planner_maps::read_text_file(path, MAX_TEXT_BYTES).map_err(|e| ConfigError {
        file: path.to_path_buf(),
        line: e.line,
        column: e.column,
        message: format!("cannot read the config: {}", read_failure(&e)),
    })?;
    parse(path, &text)
}

/// Why [`planner_maps::read_text_file`] failed, without its "cannot read the file" for
/// an operating-system error (the callers say what they could not read).
fn read_failure(error: &planner_maps::MapError) -> String {
    match &error.kind {
        planner_maps::MapErrorKind::Io { message } => message.clone(),
        other => other.to_string(),
    }
}

/// The longest experiment `name`: it names the output directory and its lock and stream
/// files, which must fit a file name (255 bytes on common file systems).
pub const MAX_NAME_LEN: usize = 100;

/// The cells of drawn map the figures of one map may take when the config does not say
/// how many problems to draw (`figures_per_map`): 2^24, about 60 MB of SVG (a 512 x 512
/// figure is about 1 MB). See [`Experiment::figure_limit`].
pub const DEFAULT_FIGURE_CELLS: u64 = 1 << 24;

/// The most problems of a map that get figures when the config does not say how many
/// (`figures_per_map`). See [`Experiment::figure_limit`].
pub const DEFAULT_FIGURE_PROBLEMS: usize = 256;

/// The largest config or published-values file read: 16 MiB. Like the map readers, only
/// regular files are read, so `/dev/zero` or a FIFO is an error, not a hang.
pub const MAX_TEXT_BYTES: u64 = 16 << 20;

/// The most planner labels [`parse`] warns about one by one when their specs declare them
/// not admissible (`moves = 16` with the Manhattan heuristic, a weight above 1).
const MAX_ADMISSIBILITY_WARNINGS: usize = 10;

/// The key that the deserializer's `path` names for its error `message` (`seed`,
/// `planners.a.moves`, `maps[0].files`), without serde_spanned's inner segments; for an
/// unknown field, the table holding it (its message names the field). `None` at the top.
fn path_key(path: &serde_path_to_error::Path, message: &str) -> Option<String> {
    let mut segments = key_segments(path);
    if message.starts_with("unknown field") {
        segments.pop();
    }
    join_key(segments)
}

/// The key a deserializer's `path` names (`radii[0]`, `maps[0].scenarios`), without the
/// TOML and serde_spanned deserializers' private segments; `None` at the top. The
/// replanning configs' errors name their keys with it too.
pub fn serde_path_key(path: &serde_path_to_error::Path) -> Option<String> {
    join_key(key_segments(path))
}

/// The segments of `path` a user wrote (the deserializers' private `$__...` ones left out).
fn key_segments(path: &serde_path_to_error::Path) -> Vec<String> {
    path.iter()
        .map(ToString::to_string)
        .filter(|s| !s.starts_with("$__"))
        .collect()
}

/// `segments` as one key: names joined by `.`, indices (`[0]`) appended.
fn join_key(segments: Vec<String>) -> Option<String> {
    let mut key = String::new();
    for segment in segments {
        if !key.is_empty() && !segment.starts_with('[') {
            key.push('.');
        }
        key.push_str(&segment);
    }
    (!key.is_empty()).then_some(key)
}

/// The span of top-level key `key` as written in `text` (a `[key]` header, `key = ...`,
/// the first `[[key]]`), for an error about the key's whole value; the start of the file
/// (1:1, as a missing key's error) when it is not written.
fn top_key_span(text: &str, key: &str) -> Range<usize> {
    toml_edit::ImDocument::parse(text)
        .ok()
        .and_then(|doc| {
            doc.as_table()
                .get_key_value(key)
                .and_then(|(k, _)| k.span())
        })
        .unwrap_or(0..0)
}

/// The top-level `kind` of a config, read alone (any other key ignored).
#[derive(Deserialize)]
struct KindOnly {
    kind: Option<Spanned<toml::Value>>,
}

/// The key whose value is at byte `at` of the config `text`, as written: the key before
/// the `=` of that line, within the last table header above it (`planners.a.moves`,
/// `maps.files`). For errors of the TOML parser itself (a number too large for any
/// integer), which come with a position and no key. `None` when the line has no `key =`
/// before `at`.
fn key_at(text: &str, at: usize) -> Option<String> {
    let before = text.get(..at)?;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let (key, _) = before[line_start..].split_once('=')?;
    let key = key.trim();
    if key.is_empty() || key.starts_with(['[', '#']) {
        return None;
    }
    let above = &before[..line_start];
    let header = above
        .lines()
        .rev()
        .map(str::trim_start)
        .find(|l| l.starts_with('['));
    let Some(header) = header else {
        return Some(key.to_string());
    };
    let table = header
        .trim_start_matches('[')
        .split(']')
        .next()
        .map_or("", str::trim);
    if table.is_empty() {
        return Some(key.to_string());
    }
    // An array of tables (`[[maps]]`): its element, counted as the deserializer does.
    fn name_of(l: &str) -> Option<&str> {
        l.strip_prefix("[[")
            .and_then(|l| l.split(']').next())
            .map(str::trim)
    }
    Some(match name_of(header) {
        Some(_) => {
            let n = above
                .lines()
                .map(str::trim_start)
                .filter(|l| name_of(l) == Some(table))
                .count();
            format!("{table}[{}].{key}", n.saturating_sub(1))
        }
        None => format!("{table}.{key}"),
    })
}

/// The error of a config that does not deserialize: toml's, at its span, after the key
/// whose value it is (`key` from the deserializer's path, else the key written at the
/// span), except that a config with a top-level `kind` is named as the replanning
/// experiment's config it is (planner-replan's, `kind = "navigate"` or `"dynamic"`), or as
/// an unknown kind, not as an unknown key.
fn syntax_error(src: &Source<'_>, e: &toml::de::Error, key: Option<String>) -> ConfigError {
    let kind = toml::from_str::<KindOnly>(src.text)
        .ok()
        .and_then(|t| t.kind);
    // The two tables whose shape is easy to get wrong: when the error is the wrong shape
    // at one of them (its span starts on the line of the key or its header), say which
    // shape it takes.
    let line = e.span().and_then(|at| {
        let from = src.text.get(..at.start)?.rfind('\n').map_or(0, |i| i + 1);
        Some(src.text[from..].trim_start())
    });
    let names = |key: &str| {
        line.is_some_and(|l| {
            let l = l.trim_start_matches('[').trim_start();
            l.strip_prefix(key)
                .is_some_and(|rest| rest.starts_with([' ', '\t', '=', ']']))
        })
    };
    if e.message()
        .contains("invalid type: sequence, expected a map")
        && names("planners")
    {
        return src.error(
            e.span(),
            "key `planners`: a table of labelled planners, one `[planners.LABEL]` each with \
             `planner = \"NAME\"` and its parameters (the label names its runs), not an \
             array (`[[planners]]`)",
        );
    }
    if e.message()
        .contains("invalid type: map, expected a sequence")
        && names("maps")
    {
        return src.error(
            e.span(),
            "key `maps`: an array of tables, one `[[maps]]` per group of maps, not a table \
             (`[maps]`)",
        );
    }
    match kind.as_ref().map(|k| (k.span(), k.get_ref())) {
        Some((_, toml::Value::String(kind))) if kind == "navigate" || kind == "dynamic" => src
            .error(
                e.span(),
                format!(
                    "key `kind`: a replanning experiment (kind = \"{kind}\", \
                     configs/replan/README.md) runs with `gridplan experiment` (or `cargo \
                     xtask experiment`) alone; `plan`, `report` and `merge` with `--config`, \
                     `slurm` and Python's run_experiment read the experiment runner's \
                     configs, which have no `kind`"
                ),
            ),
        Some((span, kind)) => src.error(
            Some(span),
            format!(
                "key `kind`: unknown kind {kind}: a replanning experiment has kind = \
                 \"navigate\" or \"dynamic\" (configs/replan/README.md); an experiment runner \
                 config has no kind"
            ),
        ),
        None => {
            // serde's words (`expected u8`) in the config's ("an integer from 0 to 255").
            let message = &crate::usage::plain_words(e.message(), &[]);
            let key = key.or_else(|| e.span().and_then(|at| key_at(src.text, at.start)));
            match key {
                Some(key) if !message.starts_with("key `") => {
                    src.error(e.span(), format!("key `{key}`: {message}"))
                }
                _ => src.error(e.span(), message),
            }
        }
    }
}

/// Parses and validates config `text`, read from `path` (relative paths resolve against
/// its directory). A planner whose specs declare it not admissible
/// ([`planner_api::PlannerSpecs::admissible`]) is accepted with a `tracing` warning naming
/// its label's line and column.
pub fn parse(path: &Path, text: &str) -> Result<Experiment, ConfigError> {
    let src = Source { file: path, text };
    let raw: RawConfig = serde_path_to_error::deserialize(toml::Deserializer::new(text))
        .map_err(|e| syntax_error(&src, e.inner(), path_key(e.path(), e.inner().message())))?;
    let base = path.parent().unwrap_or(Path::new("")).to_path_buf();

    let name = check_top_level(&src, &raw)?;

    let planners = collect_planners(&src, &raw)?;
    let maps = collect_maps(&src, &base, &raw.maps, map_cell_limit(&planners))?;
    if maps.is_empty() {
        return Err(src.error(
            Some(top_key_span(src.text, "maps")),
            "key `maps`: at least one map is needed",
        ));
    }
    // The one place where planners that cannot honour cell costs meet weighted maps.
    for map in maps.iter().filter(|m| m.grid.is_weighted()) {
        if let Some(p) = planners
            .iter()
            .find(|p| !p.ignore_costs && !p.factory.specs().cell_costs)
        {
            let label = raw.planners.keys().find(|l| l.get_ref() == &p.label);
            return Err(src.error(
                label.map(Spanned::span),
                format!(
                    "planner `{}` ({}) {}, and map `{}` has them; add `costs = \"ignore\"` to its table to plan without them",
                    p.label,
                    p.name,
                    p.factory.specs().cell_costs_refusal(),
                    map.name
                ),
            ));
        }
    }
    if let Some(goalless) = raw.maps.iter().find_map(|m| {
        m.get_ref()
            .problems
            .as_ref()
            .filter(|p| *p.get_ref() == ProblemSource::Start)
    }) {
        if let Some(p) = planners.iter().find(|p| !p.is_coverage()) {
            return Err(src.error(
                Some(goalless.span()),
                format!(
                    "`problems = \"start\"` has no goal, but planner `{}` ({}) is not a coverage planner (coverage planners: {})",
                    p.label,
                    p.name,
                    registry::PLANNERS
                        .iter()
                        .filter(|e| e.task == Task::Coverage)
                        .map(|e| e.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    }

    let sections = match raw.sections {
        Some(sections) => Some(read_sections(&src, sections)?),
        None => None,
    };
    let published = match &raw.published {
        Some(p) => Some(read_published(&src, p, &base, sections.as_ref(), &maps)?),
        None => None,
    };

    Ok(Experiment {
        source: path.to_path_buf(),
        output: read_output(&src, raw.output)?.unwrap_or_else(|| Path::new("results").join(&name)),
        name,
        description: raw.description,
        threads: *raw.threads.get_ref(),
        repeats: *raw.repeats.get_ref(),
        seed: raw.seed,
        figures: raw.figures,
        figures_per_map: raw.figures_per_map,
        figures_pick: raw.figures_pick,
        figures_expanded: raw.figures_expanded,
        charts: check_charts(&src, raw.charts, &planners)?,
        ompl: raw.ompl,
        paths: raw.paths,
        outputs: read_outputs(&src, raw.outputs)?,
        published,
        test: raw.test,
        maps,
        planners,
        sections,
    })
}

/// The `[[charts]]` entries, each `x` and `group` checked against what the runs have: a
/// planner parameter that some label resolves, `bucket`, and for `group` also `map` and
/// `planner` (a misspelt key had drawn an empty chart). `y` can name any counter, which
/// the planners report only as they run, so the report says when no run has it.
fn check_charts(
    src: &Source<'_>,
    charts: Vec<Spanned<ChartSpec>>,
    planners: &[PlannerSpec],
) -> Result<Vec<ChartSpec>, ConfigError> {
    let mut parameters: Vec<&str> = planners
        .iter()
        .filter_map(|p| p.factory.resolved().as_object())
        .flat_map(|params| params.keys().map(String::as_str))
        .collect();
    parameters.sort_unstable();
    parameters.dedup();
    let mut out = Vec::with_capacity(charts.len());
    for (i, chart) in charts.into_iter().enumerate() {
        let span = chart.span();
        let spec = chart.into_inner();
        let keys = [("x", Some(&spec.x)), ("group", spec.group.as_ref())];
        for (key, value) in keys {
            let Some(value) = value else { continue };
            let known = value == "bucket"
                || (key == "group" && matches!(value.as_str(), "map" | "planner"))
                || parameters.contains(&value.as_str());
            if !known {
                let others = if key == "group" {
                    "`bucket`, `map` or `planner`"
                } else {
                    "`bucket`"
                };
                return Err(src.error(
                    Some(span),
                    format!(
                        "charts[{i}]: key `{key}`: {value:?} is no planner parameter of this \
                         config's labels ({}) nor {others}",
                        parameters.join(", ")
                    ),
                ));
            }
        }
        out.push(spec);
    }
    Ok(out)
}

/// The `output` directory a config names, if any; one that names no directory (empty, or
/// a root alone) is refused at the key, as the sweep would refuse it later without a
/// position ([`crate::outdir::OutdirError::NoName`]).
fn read_output(
    src: &Source<'_>,
    output: Option<Spanned<String>>,
) -> Result<Option<PathBuf>, ConfigError> {
    let Some(output) = output else {
        return Ok(None);
    };
    let span = output.span();
    let path = PathBuf::from(output.into_inner());
    let root_alone = path.has_root() && path.parent().is_none();
    if path.as_os_str().is_empty() || root_alone {
        let error = crate::outdir::OutdirError::NoName { path };
        return Err(src.error(Some(span), format!("key `output`: {error}")));
    }
    Ok(Some(path))
}

/// The tables `outputs = [...]` asks for (default: all); an empty list is refused at the key.
fn read_outputs(
    src: &Source<'_>,
    outputs: Option<Spanned<Vec<crate::output::TableFormat>>>,
) -> Result<crate::output::Outputs, ConfigError> {
    let Some(outputs) = outputs else {
        return Ok(crate::output::Outputs::default());
    };
    crate::output::Outputs::of(outputs.get_ref()).ok_or_else(|| {
        src.error(
            Some(outputs.span()),
            "key `outputs`: names no table; give at least one of \"csv\", \"json\", \"parquet\"",
        )
    })
}

/// Checks the top-level keys `name`, `repeats` and `threads`; returns the name.
fn check_top_level(src: &Source<'_>, raw: &RawConfig) -> Result<String, ConfigError> {
    let name = raw.name.get_ref().clone();
    if name.len() > MAX_NAME_LEN {
        return Err(src.error(
            Some(raw.name.span()),
            format!(
                "key `name`: {} characters, more than {MAX_NAME_LEN} (it names the output directory)",
                name.len()
            ),
        ));
    }
    let name_ok = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !name_ok {
        return Err(src.error(
            Some(raw.name.span()),
            format!("key `name`: {name:?} must be non-empty letters, digits, '-' or '_' (it names the output directory)"),
        ));
    }
    if *raw.repeats.get_ref() == 0 {
        return Err(src.error(Some(raw.repeats.span()), "key `repeats` must be at least 1"));
    }
    if *raw.threads.get_ref() > MAX_THREADS {
        return Err(src.error(
            Some(raw.threads.span()),
            format!(
                "key `threads`: {} is more than {MAX_THREADS}; use 0 for one per core",
                raw.threads.get_ref()
            ),
        ));
    }
    Ok(name)
}

/// The planner labels of `raw`, sweeps expanded. A label whose specs declare it not
/// admissible is accepted with a `tracing` warning (the first
/// [`MAX_ADMISSIBILITY_WARNINGS`] one by one, then their count), said at config time,
/// before anything runs.
fn collect_planners(src: &Source<'_>, raw: &RawConfig) -> Result<Vec<PlannerSpec>, ConfigError> {
    // An empty label wrote an empty planner cell in runs.csv and a figure named `-<hash>`.
    if let Some(label) = raw.planners.keys().find(|l| l.get_ref().trim().is_empty()) {
        return Err(src.error(
            Some(label.span()),
            format!(
                "key `planners`: label {:?} is empty; a label names its planner's runs, figures and files (`[planners.LABEL]`)",
                label.get_ref()
            ),
        ));
    }
    let mut planners = Vec::new();
    let mut inadmissible = Vec::new();
    for (label, table) in &expand_sweeps(src, &raw.planners)? {
        let planner = planner_spec(src, label, table, raw.budget)?;
        if planner.factory.specs().admissible == Some(false) {
            inadmissible.push(src.error(Some(label.span()), format!(
                "planner `{}` ({}): its specs declare that its paths need not be least-cost (for A*: its heuristic can overestimate under its moves, or its weight is above 1); its runs are recorded `admissible = false` and summary.md says so",
                planner.label, planner.name
            )));
        }
        planners.push(planner);
    }
    for warning in inadmissible.iter().take(MAX_ADMISSIBILITY_WARNINGS) {
        tracing::warn!("{warning}");
    }
    if inadmissible.len() > MAX_ADMISSIBILITY_WARNINGS {
        tracing::warn!(
            "{}: {} more planner labels are not admissible",
            src.file.display(),
            inadmissible.len() - MAX_ADMISSIBILITY_WARNINGS
        );
    }
    if planners.is_empty() {
        return Err(src.error(
            Some(top_key_span(src.text, "planners")),
            "key `planners`: at least one planner is needed",
        ));
    }
    Ok(planners)
}

/// The most cells a map of the config may have: maps are read within the largest memory
/// budget of the planners that run on them (each planner's `max_memory_mb`, else half the
/// machine's memory), not a fixed size.
fn map_cell_limit(planners: &[PlannerSpec]) -> u64 {
    planners
        .iter()
        .map(|p| crate::run::effective_budget(p).max_memory_mb)
        .try_fold(0, |most: u64, mb| mb.map(|mb| most.max(mb)))
        .map_or(
            planner_maps::DEFAULT_MAX_CELLS,
            planner_maps::max_cells_for_memory_mb,
        )
}

/// The maps of every `[[maps]]` set, in config order, their names and stems unique.
fn collect_maps(
    src: &Source<'_>,
    base: &Path,
    sets: &[Spanned<RawMaps>],
    max_cells: u64,
) -> Result<Vec<MapEntry>, ConfigError> {
    let mut maps: Vec<MapEntry> = Vec::new();
    for (i, spanned) in sets.iter().enumerate() {
        for entry in map_entries(src, base, i, spanned, max_cells)? {
            let stem = map_stem(&entry.name);
            if let Some(other) = maps
                .iter()
                .find(|m| m.name != entry.name && map_stem(&m.name) == stem)
            {
                return Err(src.error(
                    Some(spanned.span()),
                    format!(
                        "maps[{i}]: `{}` and `{}` have the same stem `{stem}`, which names their figures and published tables; rename one",
                        other.name, entry.name
                    ),
                ));
            }
            if maps.iter().any(|m| m.name == entry.name) {
                return Err(src.error(
                    Some(spanned.span()),
                    format!(
                        "maps[{i}]: map name `{}` appears twice; map file names must be unique",
                        entry.name
                    ),
                ));
            }
            maps.push(entry);
        }
    }
    Ok(maps)
}

/// The `sections` entries as requests, with the key's position for later errors.
fn read_sections(
    src: &Source<'_>,
    sections: Spanned<Vec<RawSection>>,
) -> Result<Sections, ConfigError> {
    let at = src.error(Some(sections.span()), "");
    let mut requests = Vec::new();
    for entry in sections.into_inner() {
        requests.push(match entry {
            RawSection::Name(name) => SectionRequest {
                name,
                options: toml::Table::new(),
            },
            RawSection::Table(mut options) => match options.remove("name") {
                Some(toml::Value::String(name)) => SectionRequest { name, options },
                _ => {
                    return Err(ConfigError {
                        message: "key `sections`: a section table needs a string `name`".into(),
                        ..at
                    })
                }
            },
        });
    }
    Ok(Sections {
        requests,
        file: at.file,
        line: at.line,
        column: at.column,
    })
}

/// A map's file name without its extension (the table name of published values, and
/// of its figures and logs).
pub fn map_stem(name: &str) -> &str {
    name.rsplit_once('.').map_or(name, |(stem, _)| stem)
}

type RawParams = IndexMap<Spanned<String>, Spanned<toml::Value>>;

/// A planner table with its label, as the config spells them (spans kept).
type LabelledTable = (Spanned<String>, Spanned<RawParams>);

/// Most labels one planner table may sweep into.
pub const MAX_SWEEP_LABELS: usize = 100_000;

/// Parameter sweeps: a list value in a planner table, for a parameter whose declared type
/// is not itself a list ([`crate::schema::declared`]), expands the table into one label per
/// combination of the listed values, named `<label>[key=value,...]` with the swept keys in
/// table order (strings unquoted). Combinations run in table order with the last swept
/// key varying fastest, like nested loops written in that order. Tables without lists,
/// and tables whose planner is missing or unknown (reported by [`planner_spec`]), pass
/// unchanged.
fn expand_sweeps(
    src: &Source<'_>,
    planners: &IndexMap<Spanned<String>, Spanned<RawParams>>,
) -> Result<Vec<LabelledTable>, ConfigError> {
    let mut expanded: Vec<LabelledTable> = Vec::new();
    for (label, table) in planners {
        let declared = table
            .get_ref()
            .get("planner")
            .and_then(|name| name.get_ref().as_str())
            .and_then(|name| planner_registry::schema::declared(name).ok())
            .unwrap_or_default();
        let swept: Vec<(&Spanned<String>, &Spanned<toml::Value>, &Vec<toml::Value>)> = table
            .get_ref()
            .iter()
            .filter(|(key, _)| {
                declared
                    .iter()
                    .any(|p| p.key == *key.get_ref() && !p.is_list)
            })
            .filter_map(|(key, value)| value.get_ref().as_array().map(|list| (key, value, list)))
            .collect();
        if swept.is_empty() {
            expanded.push((label.clone(), table.clone()));
            continue;
        }
        let mut n_labels: usize = 1;
        for (key, value, list) in &swept {
            if list.is_empty() {
                return Err(src.error(
                    Some(value.span()),
                    format!(
                        "planner `{}`, key `{}`: an empty list sweeps nothing; give at least one value",
                        label.get_ref(),
                        key.get_ref()
                    ),
                ));
            }
            n_labels = n_labels.saturating_mul(list.len());
        }
        if n_labels > MAX_SWEEP_LABELS {
            return Err(src.error(
                Some(label.span()),
                format!(
                    "planner `{}`: the sweep has {n_labels} combinations, more than {MAX_SWEEP_LABELS}",
                    label.get_ref()
                ),
            ));
        }
        // One index per swept key, counted like an odometer (last key fastest).
        let mut digits = vec![0_usize; swept.len()];
        for _ in 0..n_labels {
            let mut params = table.get_ref().clone();
            let mut names = Vec::new();
            for ((key, value, list), &digit) in swept.iter().zip(&digits) {
                let chosen = list[digit].clone();
                let shown = match &chosen {
                    toml::Value::String(text) => text.clone(),
                    other => other.to_string(),
                };
                names.push(format!("{}={shown}", key.get_ref()));
                params.insert((*key).clone(), Spanned::new(value.span(), chosen));
            }
            let name = format!("{}[{}]", label.get_ref(), names.join(","));
            expanded.push((
                Spanned::new(label.span(), name),
                Spanned::new(table.span(), params),
            ));
            for (digit, (_, _, list)) in digits.iter_mut().zip(&swept).rev() {
                *digit += 1;
                if *digit < list.len() {
                    break;
                }
                *digit = 0;
            }
        }
    }
    let mut seen = std::collections::HashSet::new();
    for (label, _) in &expanded {
        if !seen.insert(label.get_ref().as_str()) {
            return Err(src.error(
                Some(label.span()),
                format!(
                    "planner label `{}` appears twice (a sweep's labels are `<label>[key=value,...]`)",
                    label.get_ref()
                ),
            ));
        }
    }
    Ok(expanded)
}

fn planner_spec(
    src: &Source<'_>,
    label: &Spanned<String>,
    table: &Spanned<RawParams>,
    default_budget: Budget,
) -> Result<PlannerSpec, ConfigError> {
    let label_text = label.get_ref();
    let key_span = |key: &str| {
        table
            .get_ref()
            .keys()
            .find(|k| k.get_ref() == key)
            .map(Spanned::span)
    };
    let Some(name_value) = table.get_ref().get("planner") else {
        return Err(src.error(
            Some(label.span()),
            format!(
                "planner `{label_text}`: key `planner` is missing (one of {})",
                registry::names().join(", ")
            ),
        ));
    };
    let Some(name) = name_value.get_ref().as_str() else {
        return Err(src.error(
            Some(name_value.span()),
            format!(
                "planner `{label_text}`, key `planner`: expected a registry name (a string: one of {}), found {} {}",
                registry::names().join(", "),
                name_value.get_ref().type_str(),
                name_value.get_ref()
            ),
        ));
    };
    let Some(entry) = registry::find(name) else {
        return Err(src.error(
            Some(name_value.span()),
            format!(
                "planner `{label_text}`: unknown planner {:?} in key `planner`, expected one of {}",
                name_value.get_ref().to_string().trim_matches('"'),
                registry::names().join(", ")
            ),
        ));
    };
    let mut params = toml::Table::new();
    let mut budget = default_budget;
    let mut compare = None;
    let mut ignore_costs = false;
    for (key, value) in table.get_ref() {
        match key.get_ref().as_str() {
            "planner" => {}
            "costs" => {
                if value.get_ref().as_str() != Some("ignore") {
                    return Err(src.error(
                        Some(value.span()),
                        format!(
                            "planner `{label_text}`, key `costs`: expected \"ignore\" (plan on weighted maps without their weights), found {}",
                            value.get_ref()
                        ),
                    ));
                }
                ignore_costs = true;
            }
            "compare" => compare = Some(read_compare(src, label_text, value)?),
            "budget" => budget = planner_budget(src, label_text, value, default_budget)?,
            other => {
                params.insert(other.to_string(), value.get_ref().clone());
            }
        }
    }
    let factory = (entry.factory)(&params).map_err(|e| {
        // The error names its key; point there, else at the label.
        let span = key_span(&e.key).unwrap_or_else(|| label.span());
        param_error(src, span, label_text, entry.name, &e)
    })?;
    Ok(PlannerSpec {
        label: label_text.clone(),
        name: entry.name,
        factory,
        params,
        budget,
        compare,
        ignore_costs,
    })
}

/// The budget of label `label` whose table's `budget` is `value`: key by key, what the
/// table sets replaces the experiment's `[budget]` (`default`) value of that key; the
/// other keys keep the experiment's.
fn planner_budget(
    src: &Source<'_>,
    label: &str,
    value: &Spanned<toml::Value>,
    default: Budget,
) -> Result<Budget, ConfigError> {
    let own = Budget::deserialize(value.get_ref().clone()).map_err(|e| {
        src.error(
            Some(value.span()),
            format!(
                "planner `{label}`, key `budget`: {}",
                crate::usage::plain_words(first_line(&e.to_string()), &[])
            ),
        )
    })?;
    Ok(Budget {
        max_expansions: own.max_expansions.or(default.max_expansions),
        max_time: own.max_time.or(default.max_time),
        max_memory_mb: own.max_memory_mb.or(default.max_memory_mb),
        ..default
    })
}

/// The `compare` key of label `label` (`value`), its metrics checked.
fn read_compare(
    src: &Source<'_>,
    label: &str,
    value: &Spanned<toml::Value>,
) -> Result<Compare, ConfigError> {
    let parsed = Compare::deserialize(value.get_ref().clone()).map_err(|e| {
        src.error(
            Some(value.span()),
            format!(
                "planner `{label}`, key `compare`: {}",
                first_line(&e.to_string())
            ),
        )
    })?;
    if registry::find(&parsed.with).is_none() {
        return Err(src.error(
            Some(value.span()),
            format!(
                "planner `{label}`, key `compare`: `with = {:?}` is no planner; expected a registry name ({}), the key of its published values",
                parsed.with,
                registry::names().join(", ")
            ),
        ));
    }
    let known = published_metrics();
    if let Some(bad) = parsed.metrics.iter().find(|m| !known.contains(&m.as_str())) {
        return Err(src.error(
            Some(value.span()),
            format!(
                "planner `{label}`, key `compare`: unknown metric `{bad}`, expected some of {}",
                known.join(", ")
            ),
        ));
    }
    Ok(parsed)
}

/// A planner factory's parameter error `e` for label `label` (planner `name`) at `span`;
/// the message names the parameter unless it does already.
fn param_error(
    src: &Source<'_>,
    span: Range<usize>,
    label: &str,
    name: &str,
    e: &planner_api::ParamError,
) -> ConfigError {
    let message = param_message(name, e);
    src.error(
        Some(span),
        format!(
            "planner `{label}` ({name}): {}",
            message.replace('\n', " ").trim()
        ),
    )
}

/// The message of planner `name`'s parameter error `e`: serde's words in the config's
/// ([`crate::usage::plain_words`], a choice's declared values listed), after the key
/// unless it names it already.
fn param_message(name: &str, e: &planner_api::ParamError) -> String {
    let choices: Vec<String> = registry::schema::declared(name)
        .ok()
        .and_then(|params| params.into_iter().find(|p| p.key == e.key))
        .map(|param| {
            param
                .allowed
                .iter()
                .map(|v| match v {
                    serde_json::Value::String(s) => s.clone(),
                    other => other.to_string(),
                })
                .collect()
        })
        .unwrap_or_default();
    let words = crate::usage::plain_words(&e.message, &choices);
    if e.key.is_empty() || words.contains(&format!("`{}`", e.key)) {
        words
    } else {
        format!("parameter `{}`: {words}", e.key)
    }
}

/// The planner spec of `label` running registry planner `name` with `params`: the path
/// `plan` takes for registry names and `--set` overrides.
pub fn planner_from_table(
    label: &str,
    name: &str,
    params: toml::Table,
    budget: Budget,
) -> Result<PlannerSpec, crate::RunnerError> {
    let entry = registry::find(name).ok_or_else(|| crate::RunnerError::UnknownPlanner {
        name: name.to_string(),
    })?;
    let factory = (entry.factory)(&params).map_err(|e| {
        // Name the key, as config errors do (`--set moves=7`: "parameter `moves`: ...").
        let message = param_message(name, &e);
        crate::RunnerError::Param(
            label.to_string(),
            planner_api::ParamError::new(e.key, message),
        )
    })?;
    Ok(PlannerSpec {
        label: label.to_string(),
        name: entry.name,
        factory,
        params,
        budget,
        compare: None,
        ignore_costs: false,
    })
}

/// Reads a map file of any format planner-maps knows with `options` (ROS inflation, the
/// `.csv` convention), and prints its warnings (ROS YAML keys `map_server` ignores, each
/// naming file, line and column) as `tracing` warnings.
pub fn read_map_file(
    path: &Path,
    options: &planner_maps::ReadOptions,
) -> Result<planner_maps::MapFile, planner_maps::MapError> {
    let read = planner_maps::read_map_with(path, options)?;
    for warning in &read.warnings {
        tracing::warn!("{warning}");
    }
    Ok(read.file)
}

/// Whether `path` is a `.csv` matrix (the maps the `obstacle` key and `plan --obstacle`
/// apply to).
pub fn is_csv(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// `entry` with, when it is invalid on a `.csv` map read with `convention` and its start
/// and goal would both be free in the other convention, that hint appended to `invalid`
/// (and to `invalid_start`, when the start is what is blocked).
pub fn with_inversion_hint(
    mut entry: ProblemEntry,
    grid: &Grid,
    convention: Option<planner_maps::CsvConvention>,
) -> ProblemEntry {
    if let (Some(why), Some(convention)) = (&entry.invalid, convention) {
        if let Some(hint) =
            planner_maps::csv_inversion_hint(grid, convention, entry.start, entry.goal)
        {
            entry.invalid = Some(format!("{why}; {hint}"));
            if let Some(start) = &entry.invalid_start {
                entry.invalid_start = Some(format!("{start}; {hint}"));
            }
        }
    }
    entry
}

fn is_ros(path: &Path) -> bool {
    matches!(
        path.extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase)
            .as_deref(),
        Some("yaml" | "yml")
    )
}

fn first_line(text: &str) -> &str {
    text.lines().next().unwrap_or_default()
}

/// One `[[maps]]` set being read (the `index`-th), for errors that point into it.
struct MapSet<'a> {
    src: &'a Source<'a>,
    index: usize,
    spanned: &'a Spanned<RawMaps>,
}

impl MapSet<'_> {
    /// An error at `span`, prefixed with the set's `maps[index]`.
    fn at(&self, span: Range<usize>, message: String) -> ConfigError {
        self.src
            .error(Some(span), format!("maps[{}]: {message}", self.index))
    }

    /// The whole set's span.
    fn span(&self) -> Range<usize> {
        self.spanned.span()
    }
}

/// The reading options of a map set's `costs` table, checked against its files: `lethal`
/// and `unknown` for ROS maps (which they make graded), `swamp` and `water` for Moving AI
/// maps, `weights` for a set of one file.
fn cost_options(
    costs: &Spanned<RawCosts>,
    files: &[PathBuf],
    at: &dyn Fn(Range<usize>, String) -> ConfigError,
) -> Result<planner_maps::CostOptions, ConfigError> {
    let raw = costs.get_ref();
    let all_ros = files.iter().all(|p| is_ros(p));
    let all_movingai = files
        .iter()
        .all(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("map")));
    let mut options = planner_maps::CostOptions {
        rule: raw.rule.unwrap_or_default(),
        ..planner_maps::CostOptions::default()
    };
    if let Some(weights) = &raw.weights {
        if files.len() != 1 {
            return Err(at(
                weights.span(),
                format!(
                    "key `costs.weights`: a weight file belongs to one map, but `files` gives {}",
                    files.len()
                ),
            ));
        }
        if let Some(bad) = raw.lethal.as_ref().or(raw.unknown.as_ref()) {
            return Err(at(
                bad.span(),
                "key `costs`: `lethal` and `unknown` grade ROS maps and do not go with `weights`"
                    .into(),
            ));
        }
        if let Some(bad) = raw.swamp.as_ref().or(raw.water.as_ref()) {
            return Err(at(
                bad.span(),
                "key `costs`: `swamp` and `water` weigh Moving AI terrain and do not go with `weights`"
                    .into(),
            ));
        }
        return Ok(options);
    }
    if all_ros {
        if let Some(bad) = raw.swamp.as_ref().or(raw.water.as_ref()) {
            return Err(at(
                bad.span(),
                "key `costs`: `swamp` and `water` apply to Moving AI `.map` files, not ROS maps"
                    .into(),
            ));
        }
        options.graded = true;
        if let Some(lethal) = &raw.lethal {
            if *lethal.get_ref() == 0 {
                return Err(at(
                    lethal.span(),
                    "key `costs.lethal`: 0 would block every cell; costs from `lethal` up are blocked (254 is nav2's LETHAL_OBSTACLE; its planners block from 253, INSCRIBED, for the robot's centre)".into(),
                ));
            }
            options.bands.lethal = *lethal.get_ref();
        }
        if let Some(unknown) = &raw.unknown {
            if *unknown.get_ref() == 255 {
                return Err(at(
                    unknown.span(),
                    "key `costs.unknown`: the cost of an unknown cell must be below 255 (leave the key out to block unknown cells)".into(),
                ));
            }
            options.bands.unknown = Some(*unknown.get_ref());
        }
        return Ok(options);
    }
    if all_movingai {
        options.terrain = Some(terrain_weights(costs, at)?);
        return Ok(options);
    }
    Err(at(
        costs.span(),
        "key `costs`: graded costs apply to sets of ROS maps (`lethal`, `unknown`) or of Moving AI maps (`swamp`, `water`); other formats take a `weights` file".into(),
    ))
}

/// The Moving AI terrain weights of a `costs` table (`swamp` for `S`, `water` for `W`).
fn terrain_weights(
    costs: &Spanned<RawCosts>,
    at: &dyn Fn(Range<usize>, String) -> ConfigError,
) -> Result<planner_maps::TerrainWeights, ConfigError> {
    let raw = costs.get_ref();
    if let Some(bad) = raw.lethal.as_ref().or(raw.unknown.as_ref()) {
        return Err(at(
            bad.span(),
            "key `costs`: `lethal` and `unknown` apply to ROS maps, not Moving AI `.map` files"
                .into(),
        ));
    }
    let Some(swamp) = &raw.swamp else {
        return Err(at(
            costs.span(),
            "key `costs`: a Moving AI map set needs `swamp` (the weight of `S`; `water` is optional) or `weights`".into(),
        ));
    };
    let positive = |w: &Spanned<u16>, key: &str| {
        if *w.get_ref() == 0 {
            Err(at(
                w.span(),
                format!("key `costs.{key}`: weights are integers from 1 to 65535, found 0"),
            ))
        } else {
            Ok(*w.get_ref())
        }
    };
    Ok(planner_maps::TerrainWeights {
        swamp: positive(swamp, "swamp")?,
        water: raw
            .water
            .as_ref()
            .map(|w| positive(w, "water"))
            .transpose()?,
    })
}

fn map_entries(
    src: &Source<'_>,
    base: &Path,
    index: usize,
    spanned: &Spanned<RawMaps>,
    max_cells: u64,
) -> Result<Vec<MapEntry>, ConfigError> {
    let set = MapSet {
        src,
        index,
        spanned,
    };
    let raw = spanned.get_ref();
    check_map_keys(&set)?;
    let files = map_files(&set, base)?;
    let scenarios = match &raw.scen {
        Some(scen) => {
            let all = planner_maps::read_scenarios(&base.join(scen.get_ref()))
                .map_err(|e| set.at(scen.span(), format!("key `scen`: {e}")))?;
            Some(
                select_scenarios(all, raw)
                    .map_err(|(span, m)| set.at(span.unwrap_or_else(|| set.span()), m))?,
            )
        }
        None => None,
    };
    let read_options = map_read_options(&set, &files, max_cells)?;
    let mut entries = Vec::new();
    for path in files {
        check_file_options(&set, &path)?;
        let file = read_map_file(&path, &read_options)
            .map_err(|e| set.at(raw.files.span(), e.to_string()))?;
        let mut grid = file.grid;
        if let Some(weights) = raw
            .costs
            .as_ref()
            .and_then(|c| c.get_ref().weights.as_ref())
        {
            grid = planner_maps::read_weights(
                &base.join(weights.get_ref()),
                grid,
                read_options.costs.rule,
                &read_options,
            )
            .map_err(|e| set.at(weights.span(), format!("key `costs.weights`: {e}")))?;
        }
        let (mut pairs, buckets) =
            file_pairs(&set, &path, &grid, &file.problems, scenarios.as_deref())?;
        pairs.extend(frame_pairs(&set, &path, file.frame)?);
        let convention = is_csv(&path).then_some(read_options.csv);
        let problems = pairs
            .into_iter()
            .enumerate()
            .map(|(i, (start, goal, optimal_length))| {
                let entry = ProblemEntry {
                    bucket: buckets.get(i).copied().flatten(),
                    ..ProblemEntry::new(&grid, i + 1, start, goal, optimal_length)
                };
                with_inversion_hint(entry, &grid, convention)
            })
            .collect();
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_else(|| path.display().to_string());
        entries.push(MapEntry {
            name,
            path,
            grid,
            problems,
            frame: file.frame,
            unknown: file.unknown,
        });
    }
    Ok(entries)
}

/// A start-goal pair of a map set as points of the map frame (metres).
#[derive(Deserialize, JsonSchema)]
#[serde(
    deny_unknown_fields,
    expecting = "a table { start = [x, y], goal = [x, y] } of metres"
)]
pub(crate) struct RawPoints {
    /// The start, `[x, y]` in metres.
    #[schemars(with = "[f64; 2]")]
    start: Pair<f64>,
    /// The goal, `[x, y]` in metres.
    #[schemars(with = "[f64; 2]")]
    goal: Pair<f64>,
}

/// The cells of the set's `points` on map file `path`, whose map frame is `frame`: each
/// point's cell ([`planner_maps::MapFrame::cell_at`]). A map without a frame, and a point
/// off the map, are errors at the key or the pair.
fn frame_pairs(
    set: &MapSet<'_>,
    path: &Path,
    frame: Option<planner_maps::MapFrame>,
) -> Result<Vec<(Cell, Cell, Option<f64>)>, ConfigError> {
    let Some(points) = &set.spanned.get_ref().points else {
        return Ok(Vec::new());
    };
    let Some(frame) = frame else {
        return Err(set.at(
            points.span(),
            format!(
                "key `points`: points are metres of a ROS map's map frame, and {} has none (a map_server .yaml has one); give `pairs` of cells instead",
                path.display()
            ),
        ));
    };
    let mut pairs = Vec::with_capacity(points.get_ref().len());
    for pair in points.get_ref() {
        let cell = |[x, y]: [f64; 2], which: &str| {
            if !(x.is_finite() && y.is_finite()) {
                return Err(set.at(
                    pair.span(),
                    format!("key `points`: the {which} [{x}, {y}] is not a point: its coordinates must be finite numbers of metres"),
                ));
            }
            frame.cell_at(x, y).ok_or_else(|| {
                set.at(
                    pair.span(),
                    format!(
                        "key `points`: the {which} [{}, {}] lies outside {}, which spans {}",
                        planner_maps::metres(x),
                        planner_maps::metres(y),
                        path.display(),
                        frame.extent()
                    ),
                )
            })
        };
        let RawPoints { start, goal } = *pair.get_ref();
        pairs.push((cell(start.0, "start")?, cell(goal.0, "goal")?, None));
    }
    Ok(pairs)
}

/// Checks that the set names its problems exactly one way (`problems`, `pairs`, `scen`),
/// `pairs` and `points` not empty, `start` exactly with `problems = "start"`, and
/// scenario selections only with `scen`.
fn check_map_keys(set: &MapSet<'_>) -> Result<(), ConfigError> {
    let raw = set.spanned.get_ref();
    let sources = [
        raw.problems.is_some(),
        raw.pairs.is_some(),
        raw.points.is_some(),
        raw.scen.is_some(),
    ];
    match sources.iter().filter(|&&s| s).count() {
        1 => {}
        0 => return Err(set.at(
            set.span(),
            "give exactly one of `problems` (\"corners\", \"file\" or \"start\"), `pairs`, `points` or `scen`"
                .into(),
        )),
        _ => {
            return Err(set.at(
                set.span(),
                "`problems`, `pairs`, `points` and `scen` exclude each other".into(),
            ))
        }
    }
    // An empty list would run nothing without a word, as an empty `files` would.
    if let Some(pairs) = raw.pairs.as_ref().filter(|p| p.get_ref().is_empty()) {
        return Err(set.at(
            pairs.span(),
            "key `pairs`: at least one start-goal pair is needed".into(),
        ));
    }
    if let Some(points) = raw.points.as_ref().filter(|p| p.get_ref().is_empty()) {
        return Err(set.at(
            points.span(),
            "key `points`: at least one start-goal pair is needed".into(),
        ));
    }
    let start_source = raw
        .problems
        .as_ref()
        .is_some_and(|p| *p.get_ref() == ProblemSource::Start);
    match (&raw.start, start_source) {
        (None, true) => {
            return Err(set.at(
                set.span(),
                "`problems = \"start\"` needs `start = [x, y]`".into(),
            ))
        }
        (Some(start), false) => {
            return Err(set.at(
                start.span(),
                "key `start` goes with `problems = \"start\"`".into(),
            ))
        }
        _ => {}
    }
    if raw.scen.is_none()
        && (raw.buckets.is_some()
            || raw.lines.is_some()
            || raw.every.is_some()
            || raw.limit.is_some())
    {
        return Err(set.at(
            set.span(),
            "`buckets`, `lines`, `every` and `limit` select scenarios and need `scen`".into(),
        ));
    }
    Ok(())
}

/// The map files the set's `files` patterns match (relative to `base`), each pattern's
/// matches sorted ([`crate::pattern`]); no pattern, or one that matches nothing, is an
/// error.
fn map_files(set: &MapSet<'_>, base: &Path) -> Result<Vec<PathBuf>, ConfigError> {
    use crate::pattern::PatternError;
    let raw = set.spanned.get_ref();
    if raw.files.get_ref().is_empty() {
        return Err(set.at(
            raw.files.span(),
            "key `files`: at least one map is needed".into(),
        ));
    }
    let mut files = Vec::new();
    for pattern in raw.files.get_ref() {
        let full = base.join(pattern);
        let matches = crate::pattern::expand(&full).map_err(|e| {
            let message = match e {
                PatternError::Pattern(e) => format!("key `files`: bad pattern {pattern:?}: {e}"),
                PatternError::Directory { .. } | PatternError::NotUnicode { .. } => {
                    format!("key `files`: {pattern:?}: {e}")
                }
            };
            set.at(raw.files.span(), message)
        })?;
        if matches.is_empty() {
            return Err(set.at(
                raw.files.span(),
                format!(
                    "key `files`: nothing matches {pattern:?} (looked for {})",
                    full.display()
                ),
            ));
        }
        files.extend(matches);
    }
    Ok(files)
}

/// How the set's maps are read: its `.csv` convention (`obstacle`), ROS options
/// (`inflation`, `inflate_unknown`) and at most `max_cells` cells.
fn map_read_options(
    set: &MapSet<'_>,
    files: &[PathBuf],
    max_cells: u64,
) -> Result<planner_maps::ReadOptions, ConfigError> {
    let raw = set.spanned.get_ref();
    let ros_options = planner_maps::RosOptions {
        inflation_radius: raw.inflation.as_ref().map_or(0, |r| *r.get_ref()),
        inflate_unknown: raw.inflate_unknown.as_ref().is_some_and(|u| *u.get_ref()),
    };
    let csv = match &raw.obstacle {
        Some(value) => Some(
            u8::try_from(*value.get_ref())
                .ok()
                .and_then(planner_maps::CsvConvention::from_obstacle_value)
                .ok_or_else(|| {
                    set.at(
                        value.span(),
                        format!(
                            "key `obstacle`: {} is neither 0 nor 1 (the value of a `.csv` cell that is an obstacle)",
                            value.get_ref()
                        ),
                    )
                })?,
        ),
        None => None,
    };
    let costs = match &raw.costs {
        None => planner_maps::CostOptions::default(),
        Some(costs) => cost_options(costs, files, &|span, message| set.at(span, message))?,
    };
    Ok(planner_maps::ReadOptions {
        csv: csv.unwrap_or_default(),
        ros: ros_options,
        max_cells,
        costs,
        ..planner_maps::ReadOptions::default()
    })
}

/// Checks that the set's format options fit map file `path`: `obstacle` only for `.csv`,
/// `inflation` and `inflate_unknown` only for ROS `.yaml`.
fn check_file_options(set: &MapSet<'_>, path: &Path) -> Result<(), ConfigError> {
    let raw = set.spanned.get_ref();
    if let (Some(value), false) = (&raw.obstacle, is_csv(path)) {
        return Err(set.at(
            value.span(),
            format!(
                "key `obstacle` applies to `.csv` maps, not {}",
                path.display()
            ),
        ));
    }
    if !is_ros(path) && (raw.inflation.is_some() || raw.inflate_unknown.is_some()) {
        let span = match (&raw.inflation, &raw.inflate_unknown) {
            (Some(inflation), _) => inflation.span(),
            (None, Some(unknown)) => unknown.span(),
            (None, None) => set.span(),
        };
        return Err(set.at(
            span,
            format!(
                "`inflation` and `inflate_unknown` apply to ROS `.yaml` maps, not {}",
                path.display()
            ),
        ));
    }
    Ok(())
}

/// The start-goal pairs (with any stated optimal length) of map file `path` (its `grid`
/// and the problems the file lists), from the set's `problems`, `pairs` and the selected
/// `scenarios`, and each pair's scenario bucket.
#[allow(clippy::type_complexity)]
fn file_pairs(
    set: &MapSet<'_>,
    path: &Path,
    grid: &Grid,
    listed: &[planner_maps::ProblemSpec],
    scenarios: Option<&[planner_maps::Scenario]>,
) -> Result<(Vec<(Cell, Cell, Option<f64>)>, Vec<Option<u32>>), ConfigError> {
    let raw = set.spanned.get_ref();
    let mut pairs: Vec<(Cell, Cell, Option<f64>)> = Vec::new();
    let mut buckets: Vec<Option<u32>> = Vec::new();
    if let Some(source) = &raw.problems {
        match source.get_ref() {
            ProblemSource::Corners => pairs.push((
                Cell::new(0, 0),
                Cell::new(grid.width() - 1, grid.height() - 1),
                None,
            )),
            ProblemSource::File => {
                if listed.is_empty() {
                    return Err(set.at(
                        source.span(),
                        format!(
                            "`problems = \"file\"`, but {} lists no start-goal pairs",
                            path.display()
                        ),
                    ));
                }
                pairs.extend(listed.iter().map(|p| (p.start, p.goal, None)));
            }
            ProblemSource::Start => {
                if let Some(start) = &raw.start {
                    let Pair([x, y]) = *start.get_ref();
                    pairs.push((Cell::new(x, y), Cell::new(x, y), None));
                }
            }
        }
    }
    if let Some(list) = &raw.pairs {
        pairs.extend(list.get_ref().iter().map(|p| {
            let (Pair([sx, sy]), Pair([gx, gy])) = (p.start, p.goal);
            (Cell::new(sx, sy), Cell::new(gx, gy), None)
        }));
    }
    if let Some(scenarios) = scenarios {
        for s in scenarios {
            if (s.width, s.height) != (grid.width(), grid.height()) {
                // Scenarios come from the `scen` key, whose span and file the error names.
                let (span, scen_path) = match &raw.scen {
                    Some(scen) => (scen.span(), scen.get_ref().as_str()),
                    None => (set.span(), "the scenario file"),
                };
                return Err(set.at(
                    span,
                    format!(
                        "key `scen`: {}:{}:{}: the scenario is for a {}x{} map, but {} is {}x{}",
                        scen_path,
                        s.line,
                        s.size_column,
                        s.width,
                        s.height,
                        path.display(),
                        grid.width(),
                        grid.height()
                    ),
                ));
            }
            buckets.resize(pairs.len(), None);
            pairs.push((s.start, s.goal, Some(s.optimal_length)));
            buckets.push(Some(s.bucket));
        }
        let name = path.file_name().map(|n| n.to_string_lossy().to_string());
        if let (Some(first), Some(name)) = (scenarios.first(), name) {
            let scen_map = first.map.rsplit(['/', '\\']).next().unwrap_or(&first.map);
            if scen_map != name {
                tracing::warn!(
                    "{}: maps[{}]: the scenarios name map {}, not {name} (same size, so used)",
                    set.src.file.display(),
                    set.index,
                    first.map
                );
            }
        }
    }
    Ok((pairs, buckets))
}

/// The scenarios of `all` that the set's `buckets`, `lines`, `every` and `limit` select;
/// an error at the key that is wrong (`None`: the set's, for an empty selection).
fn select_scenarios(
    all: Vec<planner_maps::Scenario>,
    raw: &RawMaps,
) -> Result<Vec<planner_maps::Scenario>, (Option<Range<usize>>, String)> {
    let lines = raw.lines.as_ref().map(|l| (l.span(), *l.get_ref()));
    if let Some((span, Pair([from, to]))) = &lines {
        if *from == 0 {
            return Err((
                Some(span.clone()),
                format!("key `lines`: [{from}, {to}]: lines are 1-based (the file's first line is line 1)"),
            ));
        }
        if from > to {
            return Err((
                Some(span.clone()),
                format!(
                    "key `lines`: [{from}, {to}] starts after it ends (the first line, then the last)"
                ),
            ));
        }
    }
    let mut selected: Vec<planner_maps::Scenario> = all
        .into_iter()
        .filter(|s| raw.buckets.as_ref().is_none_or(|b| b.contains(&s.bucket)))
        .filter(|s| {
            lines
                .as_ref()
                .is_none_or(|(_, Pair([from, to]))| (*from..=*to).contains(&s.line))
        })
        .collect();
    if let Some(every) = &raw.every {
        if *every.get_ref() == 0 {
            return Err((Some(every.span()), "key `every` must be at least 1".into()));
        }
        selected = selected.into_iter().step_by(*every.get_ref()).collect();
    }
    if let Some(limit) = raw.limit {
        selected.truncate(limit);
    }
    if selected.is_empty() {
        return Err((
            None,
            "the scenario selection (`buckets`, `lines`, `every`, `limit`) is empty".into(),
        ));
    }
    Ok(selected)
}

/// The metrics a published-values file may give: the path metrics and the standard
/// counters ([`planner_api::Counter`]).
pub fn published_metrics() -> Vec<&'static str> {
    let mut names = vec!["steps", "turns", "score", "length"];
    names.extend(planner_api::Counter::ALL.iter().map(|c| c.name()));
    names
}

/// The `published` key `key` (a path relative to `base`): refused when `sections` leave
/// out `seed000`, the only section that compares the values (the config would check
/// nothing and say nothing), else the file read by [`load_published`].
fn read_published(
    src: &Source<'_>,
    key: &Spanned<String>,
    base: &Path,
    sections: Option<&Sections>,
    maps: &[MapEntry],
) -> Result<Published, ConfigError> {
    if sections.is_some_and(|s| !s.wants("seed000")) {
        return Err(src.error(
            Some(key.span()),
            "key `published`: the published values are compared by the `seed000` section, which `sections` leaves out; add \"seed000\" to `sections` (or leave `sections` out: `published` then shows it)",
        ));
    }
    load_published(src, &base.join(key.get_ref()), key.span(), maps)
}

/// Reads a published-values file strictly: `[<map>] file = "..."` (optional) and
/// `[<map>.<planner>] <metric> = <number>`; an unknown metric, a value that is not a number
/// or any other shape is an error naming the file, line and column, and so is a table
/// that names nothing (a planner key that is no registry name, a map stem that is
/// neither one of the config's `maps` nor a file beside the published file, a `file` that
/// does not exist or has another stem), so a typo can never switch the reproduction check
/// off.
fn load_published(
    src: &Source<'_>,
    path: &Path,
    span: Range<usize>,
    maps: &[MapEntry],
) -> Result<Published, ConfigError> {
    let text = planner_maps::read_text_file(path, MAX_TEXT_BYTES).map_err(|e| {
        src.error(
            Some(span.clone()),
            match e.line {
                0 => format!(
                    "key `published`: cannot read {}: {}",
                    path.display(),
                    read_failure(&e)
                ),
                line => format!(
                    "key `published`: cannot read {}:{line}:{}: {}",
                    path.display(),
                    e.column,
                    read_failure(&e)
                ),
            },
        )
    })?;
    parse_published_for(path, &text, maps)
}

/// Parses published-values `text`, read from `path` (see the `published` key in
/// configs/README.md); errors as in [`parse`], positioned in `path`. Its map stems,
/// planner keys and `file`s are checked only as a config's are: the planner keys against
/// the registry, the map stems and `file`s against the files beside `path`.
pub fn parse_published(path: &Path, text: &str) -> Result<Published, ConfigError> {
    parse_published_for(path, text, &[])
}

/// The stems of the files in `dir` (the maps a published-values file may give values
/// for besides the config's own).
fn stems_in(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
        .filter_map(|e| e.file_name().to_str().map(|n| map_stem(n).to_string()))
        .collect()
}

/// The `file` of published table `map` (map stem `stem`), at `at`: `named`, resolved
/// beside the published file, must be a file with that stem.
fn check_published_file(
    inner: &Source<'_>,
    at: Option<Range<usize>>,
    named: PathBuf,
    (map, stem): (&str, &str),
) -> Result<(), ConfigError> {
    if !named.is_file() {
        return Err(inner.error(
            at,
            format!(
                "`{map}.file`: {} is not a file (`file` is the map the values are for, beside the published file)",
                named.display()
            ),
        ));
    }
    let name = named
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default();
    if map_stem(name) != stem {
        return Err(inner.error(
            at,
            format!(
                "`{map}.file`: `{name}` is map `{}`, not `{stem}`",
                map_stem(name)
            ),
        ));
    }
    Ok(())
}

/// Published table `map` (`"<stem>#<k>"`) must name problem `k` of `entry`, the config's
/// map of that stem, as the report looks it up (`#1` to `#n`, no leading zeros): another
/// would be dropped without a word.
fn check_published_problem(
    inner: &Source<'_>,
    at: Option<Range<usize>>,
    map: &str,
    k: usize,
    entry: &MapEntry,
) -> Result<(), ConfigError> {
    let n = entry.problems.len();
    if k == 0 || k > n || map != format!("{}#{k}", map_stem(&entry.name)) {
        return Err(inner.error(
            at,
            format!(
                "`[{map}]`: map `{}` has {n} problem{} (`#1` to `#{n}`); the table names no problem of it",
                entry.name,
                if n == 1 { "" } else { "s" }
            ),
        ));
    }
    Ok(())
}

/// The published value `value` of `key` (`map.planner.metric`): an integer or a finite
/// float (`nan` and `inf` are no published number).
fn published_number(
    inner: &Source<'_>,
    value: &toml_edit::Item,
    key: &str,
) -> Result<f64, ConfigError> {
    let number = value
        .as_float()
        .or_else(|| value.as_integer().map(|i| i as f64))
        .ok_or_else(|| {
            inner.error(
                value.span(),
                format!("`{key}` must be a number, not {}", value.type_name()),
            )
        })?;
    if !number.is_finite() {
        return Err(inner.error(
            value.span(),
            format!("`{key}` must be a number, not {number}"),
        ));
    }
    Ok(number)
}

/// [`parse_published`], with the map stems also allowed to be those of `maps`
/// (a published file beside none of them, as a test's, may give values for them).
fn parse_published_for(
    path: &Path,
    text: &str,
    maps: &[MapEntry],
) -> Result<Published, ConfigError> {
    let inner = Source { file: path, text };
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    let beside = stems_in(dir);
    let config_stems: Vec<&str> = maps.iter().map(|m| map_stem(&m.name)).collect();

    let doc = toml_edit::ImDocument::parse(text)
        .map_err(|e| inner.error(e.span(), e.message().trim()))?;
    let known = published_metrics();
    let mut values = IndexMap::new();
    for (map, entry) in doc.as_table().iter() {
        let Some(entry) = entry.as_table_like() else {
            return Err(inner.error(
                doc.as_table()
                    .get_key_value(map)
                    .and_then(|(k, _)| k.span()),
                format!("`{map}` must be a table of planners, `[{map}.<planner>]`"),
            ));
        };
        // `"<stem>#<k>"` is problem k of map `<stem>`.
        let (stem, problem) = match map.rsplit_once('#') {
            Some((stem, k)) if k.parse::<usize>().is_ok() => (stem, k.parse::<usize>().ok()),
            _ => (map, None),
        };
        if let (Some(k), Some(entry)) = (problem, maps.iter().find(|m| map_stem(&m.name) == stem)) {
            let at = doc
                .as_table()
                .get_key_value(map)
                .and_then(|(k, _)| k.span());
            check_published_problem(&inner, at, map, k, entry)?;
        }
        if !config_stems.contains(&stem) && !beside.iter().any(|b| b == stem) {
            let at = doc
                .as_table()
                .get_key_value(map)
                .and_then(|(k, _)| k.span());
            let dir = dir.display();
            let message = format!(
                "`[{map}]`: no map of the config and no file in {dir} has the stem `{stem}`"
            );
            return Err(inner.error(at, message));
        }
        let mut planners = IndexMap::new();
        for (planner, metrics) in entry.iter() {
            if planner == "file" {
                if let Some(file) = metrics.as_str() {
                    let at = entry.get_key_value(planner).and_then(|(_, v)| v.span());
                    check_published_file(&inner, at, dir.join(file), (map, stem))?;
                    continue;
                }
            }
            if registry::find(planner).is_none() {
                let at = entry.get_key_value(planner).and_then(|(k, _)| k.span());
                let names = registry::names().join(", ");
                let message = format!("`[{map}.{planner}]`: unknown planner `{planner}`, expected a registry name ({names})");
                return Err(inner.error(at, message));
            }
            let Some(metrics) = metrics.as_table_like() else {
                return Err(inner.error(
                    entry.get_key_value(planner).and_then(|(k, _)| k.span()),
                    format!("`{map}.{planner}` must be a table of metrics (or `file = \"...\"`)"),
                ));
            };
            let mut numbers = IndexMap::new();
            for (metric, value) in metrics.iter() {
                if !known.contains(&metric) {
                    let at = metrics.get_key_value(metric).and_then(|(k, _)| k.span());
                    return Err(inner.error(
                        at.or_else(|| value.span()),
                        format!(
                            "`{map}.{planner}`: unknown metric `{metric}`, expected one of {}",
                            known.join(", ")
                        ),
                    ));
                }
                let key = format!("{map}.{planner}.{metric}");
                let number = published_number(&inner, value, &key)?;
                numbers.insert(metric.to_string(), number);
            }
            planners.insert(planner.to_string(), numbers);
        }
        values.insert(map.to_string(), planners);
    }
    Ok(Published {
        path: path.to_path_buf(),
        values,
    })
}

impl ProblemEntry {
    /// Problem `index` (1-based) from `start` to `goal` on `grid`, checked: `invalid` says
    /// why it cannot be planned, if so.
    pub fn new(
        grid: &Grid,
        index: usize,
        start: Cell,
        goal: Cell,
        optimal_length: Option<f64>,
    ) -> ProblemEntry {
        ProblemEntry {
            index,
            start,
            goal,
            optimal_length,
            bucket: None,
            invalid: Problem::new(grid, start, goal).err().map(|e| e.to_string()),
            invalid_start: planner_api::CoverageProblem::new(grid, start)
                .err()
                .map(|e| e.to_string()),
        }
    }

    /// Why a planner of `task` cannot run this problem, if so: [`ProblemEntry::invalid`] for
    /// a start-goal planner, [`ProblemEntry::invalid_start`] for a coverage planner, which
    /// ignores the goal (configs/README.md: a coverage planner runs on any problem).
    pub fn invalid_for(&self, task: Task) -> Option<&str> {
        match task {
            Task::StartGoal => self.invalid.as_deref(),
            Task::Coverage => self.invalid_start.as_deref(),
        }
    }
}

impl Experiment {
    /// An experiment of one run: `planner` on problem `problem` of `map`, with base seed
    /// `seed` (what `plan` runs).
    pub fn single(
        mut map: MapEntry,
        problem: ProblemEntry,
        planner: PlannerSpec,
        seed: u64,
    ) -> Experiment {
        map.problems = vec![problem];
        Experiment {
            source: PathBuf::new(),
            name: "plan".into(),
            description: None,
            output: PathBuf::new(),
            threads: 1,
            repeats: 1,
            seed,
            figures: FigureMode::None,
            figures_per_map: None,
            figures_pick: FigurePick::First,
            figures_expanded: false,
            charts: Vec::new(),
            ompl: false,
            paths: PathsMode::All,
            outputs: crate::output::Outputs::default(),
            published: None,
            test: TestLimits::default(),
            maps: vec![map],
            planners: vec![planner],
            sections: None,
        }
    }

    /// How many problems of `map` get figures: `figures_per_map` when the config gives
    /// it, else as many as keep the figures of one map within [`DEFAULT_FIGURE_CELLS`]
    /// cells of drawn map (every figure draws the whole map: one per problem with
    /// `figures = "comparisons"`, one more per planner with `"all"`, one more with
    /// `figures_expanded`), at least one and at most [`DEFAULT_FIGURE_PROBLEMS`] (a figure
    /// of a tiny map still takes a few kilobytes). So a sweep over every scenario of a
    /// map draws a sample, not thousands of figures held in memory until they are written.
    ///
    /// ```
    /// use planner_runner::config::{parse, DEFAULT_FIGURE_CELLS, DEFAULT_FIGURE_PROBLEMS};
    ///
    /// let text = "name = \"f\"\n[[maps]]\nfiles = [\"../maps/movingai/arena.map\"]\n\
    ///             problems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n";
    /// let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../configs/f.toml");
    /// let experiment = parse(&dir, text).unwrap();
    /// // arena is 49 x 49 = 2,401 cells, drawn twice per problem (comparison and the run):
    /// // 2^24 / 4,802 = 3,493 problems would fit, more than the count's limit.
    /// assert_eq!(DEFAULT_FIGURE_CELLS / 4802, 3493);
    /// assert_eq!(experiment.figure_limit(&experiment.maps[0]), DEFAULT_FIGURE_PROBLEMS);
    /// ```
    pub fn figure_limit(&self, map: &MapEntry) -> usize {
        if let Some(limit) = self.figures_per_map {
            return limit;
        }
        let per_problem = match self.figures {
            FigureMode::None => return 0,
            FigureMode::Comparisons => 1,
            FigureMode::All => 1 + self.planners.len() as u64,
        } + u64::from(self.figures_expanded);
        let drawn = (map.grid.len() as u64).saturating_mul(per_problem).max(1);
        let fit = (DEFAULT_FIGURE_CELLS / drawn).clamp(1, DEFAULT_FIGURE_PROBLEMS as u64);
        usize::try_from(fit).unwrap_or(DEFAULT_FIGURE_PROBLEMS)
    }

    /// The map whose file is `path` (compared after resolving both), if the experiment has it.
    pub fn find_map(&self, path: &Path) -> Option<&MapEntry> {
        let wanted = path.canonicalize().ok()?;
        self.maps
            .iter()
            .find(|m| m.path.canonicalize().ok().as_ref() == Some(&wanted))
    }

    /// Applies the `[test]` limits (for the snapshot test).
    pub fn trimmed_for_test(mut self) -> Experiment {
        if let Some(n) = self.test.problems_per_map {
            for map in &mut self.maps {
                map.problems.truncate(n);
            }
        }
        if let Some(r) = self.test.repeats {
            self.repeats = self.repeats.min(r);
        }
        self
    }

    /// Number of runs: maps x problems x planners x repeats (a problem that no label can run
    /// counts once per planner, unrepeated: [`Experiment::repeats_of`]).
    pub fn n_runs(&self) -> u64 {
        self.maps
            .iter()
            .flat_map(|m| &m.problems)
            .map(|p| self.repeats_of(p))
            .sum::<u64>()
            * self.planners.len() as u64
    }

    /// The runs of each label on `problem`: the experiment's repeats when some label can run
    /// it ([`ProblemEntry::invalid_for`] its task: a coverage label runs a problem whose goal
    /// alone is blocked), else one (it is recorded as invalid, not planned).
    pub fn repeats_of(&self, problem: &ProblemEntry) -> u64 {
        let runs = self
            .planners
            .iter()
            .any(|p| problem.invalid_for(p.factory.task()).is_none());
        match runs {
            true => u64::from(self.repeats),
            false => 1,
        }
    }
}
