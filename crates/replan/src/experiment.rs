//! The `navigate` and `dynamic` experiment kinds: a typed TOML config, its runs (in
//! parallel, deterministic counters) and a results directory.
//!
//! A config is one TOML file (every key in `configs/replan/README.md`):
//!
//! - `kind = "navigate"`: for each map of `[[maps]]` (a Moving AI map and its `.scen`, and
//!   optionally a weight file that makes it a costmap; another map format is an error at
//!   the key `map`, and so is, at its line, a scenario declaring another map size),
//!   `scenarios` scenarios spread evenly over the file, each sensor radius of `radii` and
//!   each planner of `compare`, an agent navigates in unknown terrain ([`navigate`]),
//!   every replan checked by the [`Oracle`].
//! - `kind = "dynamic"`: scripted changes between queries: `[toggles]` (seeded: `k` random
//!   cells toggled near the agent or on its path before each of `events` replans, one run
//!   per scenario, seed and planner, [`toggles`]) on the scenarios of `[[maps]]`, and
//!   `[[gppc]]` (the GPPC 2023 dynamic track's scenario files: every query against its
//!   recorded optimum and A* on the patched map, each planner carried across the next
//!   batch's patches, [`gppc`]).
//!
//! [`run`] writes into the output directory: `runs.csv` (one line per run),
//! `runs.jsonl` (every column of `runs.csv` under its name, with the same value, and the
//! path driven, navigate only, and the messages of the run's first [`MISMATCHES_LISTED`]
//! failed checks, `mismatch_messages`), `replans.jsonl` (one JSON line per replan, with
//! its counters, A*'s expansions from scratch at that replan and, when its check failed,
//! the `mismatch`), `summary.md` (per-run totals and per-replan distributions per map,
//! radius or seed, and planner) and `expansions.svg` (the first incremental planner's
//! expansions per replan against A* from scratch at the same replan; at most
//! [`CHART_POINTS`] points, an even subsample beyond). Times appear only with
//! [`RunOptions::timing`], so that without it every output is a pure function of the config.
//!
//! A scenario whose start or goal is blocked or outside its map is no error: as in the
//! experiment runner, each of its runs is recorded with status `invalid_problem` and an
//! `error` placing the cell in the `.scen` file (file, line and column), and the other
//! runs go on. In `runs.csv` a value that was not measured is an empty field (in
//! `runs.jsonl` `null` or absent), never a 0 that a mean would count: the measurements
//! of such a run, and `reached` of a toggle script, which ends after its events rather
//! than at the goal (its `steps` are the cells the agent drove).
//!
//! A GPPC replay (one `[[gppc]]` scenario file and one planner) is a run; its replans are
//! its carried queries (the planner's repairs after the next batch's patches, each checked
//! against A* from scratch on the patched map), and its checked queries (A* against the
//! recorded optimum) are counted apart: the counts [`run`] returns and `summary.md`'s head
//! are the same, and so are the tables' lines. After the navigations and toggle scripts,
//! each replay has a line in `runs.csv` and `runs.jsonl` (`map` the scenario file's stem,
//! `scenario_line` and `seed` empty, `replans` its carried queries, the expansions their
//! sums as in `gppc.csv`, `mismatches` its failed checks and its queries that disagree
//! with their recorded optimum; `runs.jsonl` adds `"gppc": true`, `queries` and
//! `patches_applied`), and each carried query a line in `replans.jsonl` (`query_line`,
//! the repair's status, expansions, counters and exact cost, A*'s expansions from scratch
//! on the patched map, the planner's `first_expansions` before the patches and the
//! `changed_cells`). The tables are written whatever runs there are: a config of
//! `[[gppc]]` alone has them too. `gppc.csv` has a line per replay with its own columns.
//!
//! The runs go in chunks of [`RUN_CHUNK`], in parallel within a chunk. A run hands its
//! replans to a [`Recorder`] as they happen, which writes their lines to a file of the
//! output's working area (planner-runner's `outdir::stream_area`, `.<output>.stream`
//! beside it) and keeps the run's totals; once the chunk ends, its runs' lines are
//! appended to the three tables there, in the config's order, and what the summary and
//! the chart need is gathered: per map, setting and planner a histogram of expansions per
//! replan (exact percentiles) and one share of A* per run, and the chart's points sampled
//! as they come. So an experiment's memory grows neither with a run's replans nor with
//! its records (`tests/memory.rs` holds both). The tables are copied into the results at
//! the end, and the area removed. [`RunOptions::stop`] (Ctrl-C on the command line) ends
//! a run in progress before its next step or event (a GPPC replay before its next query),
//! or the tables' copy into the results before its next block, and the experiment with
//! [`ExperimentError::Interrupted`], the output as it was and the area removed.
//!
//! The results directory is written as the experiment runner writes its own, by
//! planner-runner's `outdir` (its rules in that module's docs): only into a directory that
//! is absent, empty or gridplan's results ([`MARKER`]) holding nothing its marker does not
//! list (a file of the user's there refuses the run, and stays), under an exclusive lock
//! (a second run on the same output waits for the first, at most two minutes), and whole:
//! the new directory is written beside it and takes its place at once, so no output of an
//! earlier config stays, and a run killed half-way leaves the old results as they were.
//!
//! ```no_run
//! use planner_replan::experiment::{run, RunOptions};
//! let done = run("configs/replan/navigate.toml".as_ref(), "results/navigate".as_ref(), &RunOptions::default())?;
//! assert_eq!(done.mismatches, 0);
//! # Ok::<(), planner_replan::experiment::ExperimentError>(())
//! ```

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use planner_api::{Budget, Endpoint, Grid, IncrementalPlanner, Problem, ProblemError};
use planner_maps::gppc::parse_gppc_scenario;
use planner_maps::{MapError, Scenario, DEFAULT_MAX_FILE_BYTES};
use planner_text::{md_cell, md_prose};
use rayon::prelude::*;
use serde::Deserialize;
use serde_json::json;
use thiserror::Error;
use toml::Spanned;

use crate::navigate::{self, NavConfig, NavEnd};
use crate::report::{quantile, scatter_svg};
use crate::toggles::{self, ToggleConfig};
use crate::{gppc, planners, Mismatch, Oracle, Recorder, ReplanRecord};

/// The most points [`run`] draws in `expansions.svg`.
pub const CHART_POINTS: usize = 20_000;

/// The most `[toggles] events` a config may ask for. Every event is a replan checked by
/// A* from scratch and a line of `replans.jsonl` (about 300 bytes) in every run: a million
/// events already write about 300 MB per scenario, seed and planner, and the 4,294,967,295
/// a `u32` allows would write over a terabyte per run and take days; a longer script is
/// rarely meant, and more seeds measure more.
pub const MAX_EVENTS: u32 = 1_000_000;

/// The most failed checks of a run that `runs.jsonl` lists (`mismatch_messages`), and the most that
/// `summary.md` lists in all; `runs.csv` counts them all, and the `replans.jsonl` line of
/// every failed replan has its `mismatch`. A broken planner may fail every replan: its
/// messages are not kept whole.
pub const MISMATCHES_LISTED: usize = 100;

/// The file every results directory holds, so that [`run`] replaces only gridplan's own
/// outputs (the experiment runner's marker).
pub use planner_runner::outdir::MARKER;

/// The experiment kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Navigation in unknown terrain.
    Navigate,
    /// Scripted changes: seeded toggles and GPPC dynamic scenarios.
    Dynamic,
}

/// A map and its scenarios.
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MapSpec {
    /// The Moving AI map (a `.map` file; any other map format is refused at this key),
    /// relative to the config's directory.
    #[schemars(with = "String")]
    pub map: Spanned<String>,
    /// Its `.scen` file, relative to the config's directory.
    pub scen: String,
    /// Scenarios, spread evenly over the file (at least 1).
    #[serde(default = "default_scenarios")]
    #[schemars(with = "usize", range(min = 1))]
    pub scenarios: Spanned<usize>,
    /// A weight file for the map (a `.csv` of integer weights, one row per map row:
    /// planner-maps' `costs` module), relative to the config's directory: the map becomes
    /// a costmap. A navigating agent assumes weight 1 where it has not looked and senses
    /// the weights ([`navigate`]).
    #[serde(default)]
    pub weights: Option<String>,
    /// The move cost rule of a weighted map: `"mean"` (the default) or `"entered"`. Only
    /// with `weights`.
    #[serde(default)]
    #[schemars(with = "Option<String>", extend("enum" = ["mean", "entered"]))]
    pub cost_rule: Option<Spanned<planner_api::CostRule>>,
}

/// The seeded toggles of a `dynamic` experiment ([`ToggleConfig`], one run per seed).
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ToggleSpec {
    /// Change events after the first plan, at most [`MAX_EVENTS`].
    #[schemars(with = "u32", range(max = MAX_EVENTS))]
    pub events: Spanned<u32>,
    /// Cells toggled per event, at most each map's number of cells.
    #[schemars(with = "u32")]
    pub k: Spanned<u32>,
    /// Half-width of the square around the agent that off-path toggles fall in.
    pub radius: u32,
    /// Cells the agent drives before each event.
    #[serde(default = "default_drive")]
    pub drive: u32,
    /// The seeds (one run per scenario, seed and planner), each at most once.
    #[schemars(with = "Vec<u64>", length(min = 1), extend("uniqueItems" = true))]
    pub seeds: Spanned<Vec<Spanned<u64>>>,
}

/// A GPPC 2023 dynamic-track scenario file (its patch file is named inside it, relative
/// to the scenario's directory).
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GppcSpec {
    /// The `.scen` file, relative to the config's directory.
    pub scen: String,
    /// Check every `query_every`-th query (1: all).
    #[serde(default = "one")]
    #[schemars(with = "usize", range(min = 1))]
    pub query_every: Spanned<usize>,
    /// Carry each planner across the next batch's patches for every `carry_every`-th
    /// checked query (0: none).
    #[serde(default = "default_carry")]
    pub carry_every: usize,
}

/// Smaller settings for tests (`[test]`), used with [`RunOptions::test`].
#[derive(Debug, Clone, Default, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TestLimits {
    /// Scenarios per map.
    pub scenarios: Option<usize>,
    /// Toggle events per run.
    pub events: Option<u32>,
    /// Toggle seeds (the first ones).
    pub seeds: Option<usize>,
    /// GPPC: check every n-th query.
    pub query_every: Option<usize>,
    /// GPPC: carry every n-th checked query.
    pub carry_every: Option<usize>,
}

/// A replanning experiment config (see the [module docs](self)).
#[derive(Debug, Clone, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ExperimentConfig {
    /// `navigate` or `dynamic`.
    pub kind: Kind,
    /// Letters, digits, `-` and `_`.
    #[schemars(with = "String", pattern(r"^[A-Za-z0-9_-]+$"))]
    pub name: Spanned<String>,
    /// Free text, copied to the top of `summary.md`.
    #[serde(default)]
    pub description: String,
    /// The compared planners by [`planners::by_name`] name (key `compare`; not `planners`,
    /// which the runner's configs use for a table); default all four.
    #[serde(default = "default_planners", rename = "compare")]
    #[schemars(
        with = "Vec<String>",
        length(min = 1),
        extend("uniqueItems" = true, "items" = { "enum": planners::names() })
    )]
    pub planners: Vec<Spanned<String>>,
    /// 4, or 8 without corner cutting (default).
    #[schemars(with = "Option<u32>", extend("enum" = [4, 8]))]
    pub moves: Option<Spanned<u32>>,
    /// Maps and scenarios (navigate; dynamic with `[toggles]`).
    #[serde(default)]
    pub maps: Vec<MapSpec>,
    /// Sensor radii (navigate), each at least 1.
    #[serde(default)]
    #[schemars(
        with = "Vec<std::num::NonZeroU32>",
        length(min = 1),
        extend("uniqueItems" = true)
    )]
    pub radii: Vec<Spanned<u32>>,
    /// Steps before a navigation stops (default: 10 per cell plus 1,000).
    pub max_steps: Option<u64>,
    /// Seeded toggles (dynamic).
    #[schemars(with = "Option<ToggleSpec>")]
    pub toggles: Option<Spanned<ToggleSpec>>,
    /// GPPC dynamic scenarios (dynamic).
    #[serde(default)]
    pub gppc: Vec<GppcSpec>,
    /// The memory a GPPC replay may take for its per-cell state, in MiB (at least 1): a
    /// replay whose scenario declares a map needing more ([`gppc::memory_bytes`]) is
    /// recorded with status `over_memory` and the shortfall instead of run. None: half the
    /// machine's memory, the runner's default ([`planner_runner::run::default_max_memory_mb`];
    /// no limit where it cannot be read).
    #[schemars(with = "Option<std::num::NonZeroU64>")]
    pub max_memory_mb: Option<Spanned<u64>>,
    /// Settings for tests.
    #[serde(default)]
    pub test: TestLimits,
    /// The config's text, for the line and column of a value refused once the maps are
    /// read (`[toggles] k`).
    #[serde(skip)]
    #[schemars(skip)]
    source: String,
}

fn default_scenarios() -> Spanned<usize> {
    Spanned::new(0..0, 10)
}

fn default_drive() -> u32 {
    1
}

fn one() -> Spanned<usize> {
    Spanned::new(0..0, 1)
}

fn default_carry() -> usize {
    10
}

fn default_planners() -> Vec<Spanned<String>> {
    planners::names()
        .iter()
        .map(|n| Spanned::new(0..0, n.to_string()))
        .collect()
}

/// What went wrong in [`load`] or [`run`].
#[derive(Debug, Error)]
pub enum ExperimentError {
    /// A file could not be read or written.
    #[error("{path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// The config is not valid TOML or has a key or value of the wrong type.
    #[error("{}: {message}", place(path, *line, *column))]
    Parse {
        /// The config file.
        path: String,
        /// 1-based line (0: the whole file).
        line: usize,
        /// 1-based column in characters (0: the whole line).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A value the experiment cannot run with.
    #[error("{}: `{key}`: {message}", place(path, *line, *column))]
    Invalid {
        /// The config file.
        path: String,
        /// 1-based line of the value (0: not known).
        line: usize,
        /// 1-based column of the value (0: not known).
        column: usize,
        /// The key.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// More toggles per event than a map has cells: a change list that long would take
    /// the memory before the first replan.
    #[error("{}: `[toggles] k`: {k} toggles per event is more than the {cells} cells of {map}; use at most that", place(path, *line, *column))]
    TooManyToggles {
        /// The config file.
        path: String,
        /// 1-based line of the value of `k`.
        line: usize,
        /// 1-based column of the value of `k`.
        column: usize,
        /// The config's `k`.
        k: u32,
        /// The map's name.
        map: String,
        /// Its cells.
        cells: usize,
    },
    /// A map, scenario or patch file is malformed (with its file, line and column).
    #[error(transparent)]
    Map(#[from] MapError),
    /// A GPPC scenario's map that no grid can hold (the scenario reader refuses it first).
    #[error("{path}: {source}")]
    GppcGrid {
        /// The scenario.
        path: String,
        /// What the grid refused.
        source: planner_api::GridError,
    },
    /// A scenario's start or goal is not a free cell of its map. [`run`] does not return
    /// it: such a scenario is a run with status `invalid_problem` in the outputs, as in
    /// the experiment runner's, and the other runs go on. Kept for callers that match on
    /// it.
    #[error("{path} line {line}: {message}")]
    Problem {
        /// The scenario file.
        path: String,
        /// Its line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A table could not be written to its file in the output's working area.
    #[error("{path}: {source}")]
    Table {
        /// The file.
        path: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// [`RunOptions::stop`] was raised: nothing was written.
    #[error("interrupted: no results were written, the output is as it was")]
    Interrupted,
    /// The output directory may not be written: the experiment runner's rules
    /// (planner-runner's `outdir`), its message naming the path and what to do.
    #[error(transparent)]
    Output(#[from] planner_runner::outdir::OutdirError),
}

/// `path:line:column`, less what is not known (0: an error toml gives without a
/// position).
fn place(path: &str, line: usize, column: usize) -> String {
    match (line, column) {
        (0, _) => path.to_owned(),
        (_, 0) => format!("{path}:{line}"),
        _ => format!("{path}:{line}:{column}"),
    }
}

/// How [`run`] runs.
#[derive(Debug, Clone, Copy, Default)]
pub struct RunOptions {
    /// Use the config's `[test]` limits.
    pub test: bool,
    /// Record wall-clock times in the outputs (otherwise they are left out, and every
    /// output is a pure function of the config).
    pub timing: bool,
    /// Worker threads (0: rayon's default, one per core). Results do not depend on it.
    pub threads: usize,
    /// A flag that stops the experiment when raised (a command line's Ctrl-C): no run
    /// starts after it, a run in progress ends before its next step or event (a GPPC
    /// replay before its next query), the results being written are discarded, the
    /// working files go, the output is left as it was, and [`run`] returns
    /// [`ExperimentError::Interrupted`].
    pub stop: Option<&'static std::sync::atomic::AtomicBool>,
}

impl RunOptions {
    fn stopped(&self) -> bool {
        self.stop
            .is_some_and(|flag| flag.load(std::sync::atomic::Ordering::Relaxed))
    }
}

/// What [`run`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ExperimentSummary {
    /// The experiment's name.
    pub name: String,
    /// Runs (navigations, toggle scripts, GPPC replays).
    pub runs: usize,
    /// Replans checked by the oracle (GPPC: carried repairs).
    pub replans: u64,
    /// GPPC queries checked against their recorded optimum (0 without `[[gppc]]`).
    pub queries: u64,
    /// Failed checks (GPPC: also queries that disagree with the recorded optimum).
    pub mismatches: u64,
    /// The files written.
    pub files: Vec<PathBuf>,
}

/// The 1-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, column)
}

/// The experiment kind a config's `text` declares (`kind = "navigate"` or `"dynamic"`),
/// without validating the rest: `None` for any other config (such as the runner's, which
/// have no `kind`) or text that is not TOML. A command that runs both kinds of config
/// dispatches on it.
///
/// ```
/// use planner_replan::experiment::{kind_of, Kind};
/// assert_eq!(kind_of("kind = \"navigate\"\nname = \"x\""), Some(Kind::Navigate));
/// assert_eq!(kind_of("name = \"paper\""), None);
/// ```
pub fn kind_of(text: &str) -> Option<Kind> {
    let table: toml::Table = toml::from_str(text).ok()?;
    match table.get("kind")?.as_str()? {
        "navigate" => Some(Kind::Navigate),
        "dynamic" => Some(Kind::Dynamic),
        _ => None,
    }
}

/// Reads and validates the config at `path`.
pub fn load(path: &Path) -> Result<ExperimentConfig, ExperimentError> {
    // A regular file only (never a FIFO or a device), as the runner reads its configs.
    let text = planner_maps::read_text_file(path, planner_runner::config::MAX_TEXT_BYTES)?;
    parse(path, &text)
}

/// Parses and validates a config's `text` (`path` names it in errors).
pub fn parse(path: &Path, text: &str) -> Result<ExperimentConfig, ExperimentError> {
    let name = path.display().to_string();
    // Through serde_path_to_error, as the runner's configs are read, so that a value of
    // the wrong type names its key (`radii = [-1]` said "invalid value: integer `-1`,
    // expected u32" alone).
    let mut config: ExperimentConfig =
        serde_path_to_error::deserialize(toml::Deserializer::new(text)).map_err(|e| {
            let (line, column) = e
                .inner()
                .span()
                .map_or((0, 0), |s| line_column(text, s.start));
            let message = e.inner().message().trim();
            let message = match planner_runner::config::serde_path_key(e.path()) {
                Some(key) if !message.starts_with("unknown field") => {
                    format!("key `{key}`: {message}")
                }
                _ => message.to_string(),
            };
            ExperimentError::Parse {
                path: name.clone(),
                line,
                column,
                message,
            }
        })?;
    // An empty list or an array of tables holds no span of its own: the key's value has.
    let value_span = |key: &str| -> std::ops::Range<usize> {
        toml::from_str::<std::collections::BTreeMap<String, Spanned<toml::Value>>>(text)
            .ok()
            .and_then(|values| values.get(key).map(Spanned::span))
            .unwrap_or(0..0)
    };
    // A key that is missing (span 0..0) is said at 1:1, as toml says a missing `name`.
    let invalid = |span: std::ops::Range<usize>, key: &str, message: String| {
        let (line, column) = line_column(text, span.start);
        ExperimentError::Invalid {
            path: name.clone(),
            line,
            column,
            key: key.to_string(),
            message,
        }
    };
    let n = config.name.get_ref();
    if n.is_empty()
        || !n
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
    {
        return Err(invalid(
            config.name.span(),
            "name",
            format!("{n:?}: letters, digits, '-' and '_' only"),
        ));
    }
    if config.planners.is_empty() {
        return Err(invalid(
            value_span("compare"),
            "compare",
            "name at least one planner".into(),
        ));
    }
    for (i, p) in config.planners.iter().enumerate() {
        if let Err(e) = planners::by_name(p.get_ref(), true) {
            return Err(invalid(p.span(), "compare", e.to_string()));
        }
        if config.planners[..i]
            .iter()
            .any(|q| q.get_ref() == p.get_ref())
        {
            return Err(invalid(
                p.span(),
                "compare",
                format!("`{}` is listed twice", p.get_ref()),
            ));
        }
    }
    if let Some(moves) = &config.moves {
        if !matches!(moves.get_ref(), 4 | 8) {
            return Err(invalid(
                moves.span(),
                "moves",
                format!("must be 4 or 8, got {}", moves.get_ref()),
            ));
        }
    }
    for map in &config.maps {
        // The experiments read a Moving AI map with its `.scen` file; another format's
        // own costs (a ROS map's graded values) would be dropped without a word.
        let format = planner_maps::MapFormat::from_path(Path::new(map.map.get_ref()));
        if !matches!(format, Ok(planner_maps::MapFormat::MovingAi)) {
            return Err(invalid(
                map.map.span(),
                "map",
                format!(
                    "{:?} is not a Moving AI map (.map): a replanning experiment reads a Moving AI map and its .scen file (cell costs: a weights = \".csv\" file)",
                    map.map.get_ref()
                ),
            ));
        }
        if *map.scenarios.get_ref() == 0 {
            return Err(invalid(
                map.scenarios.span(),
                "scenarios",
                "must be at least 1".into(),
            ));
        }
        if let (Some(rule), None) = (&map.cost_rule, &map.weights) {
            return Err(invalid(
                rule.span(),
                "cost_rule",
                "only for a weighted map: name its weight file (weights = ...)".into(),
            ));
        }
    }
    if let (Some(moves), Some(_)) = (&config.moves, config.gppc.first()) {
        if *moves.get_ref() != 8 {
            return Err(invalid(
                moves.span(),
                "moves",
                "GPPC scenarios are 8-connected: [[gppc]] needs moves = 8".into(),
            ));
        }
    }
    if let Some(mb) = config
        .max_memory_mb
        .as_ref()
        .filter(|mb| *mb.get_ref() == 0)
    {
        return Err(invalid(
            mb.span(),
            "max_memory_mb",
            "must be at least 1".into(),
        ));
    }
    for g in &config.gppc {
        if *g.query_every.get_ref() == 0 {
            return Err(invalid(
                g.query_every.span(),
                "query_every",
                "must be at least 1".into(),
            ));
        }
    }
    match config.kind {
        Kind::Navigate => {
            if config.maps.is_empty() {
                return Err(invalid(
                    0..0,
                    "maps",
                    "a navigate experiment needs [[maps]]".into(),
                ));
            }
            if config.radii.is_empty() {
                return Err(invalid(
                    value_span("radii"),
                    "radii",
                    "a navigate experiment needs radii".into(),
                ));
            }
            // The D* Lite paper's robot senses its neighbours: radius 1 at least.
            if let Some(r) = config.radii.iter().find(|r| *r.get_ref() == 0) {
                return Err(invalid(
                    r.span(),
                    "radii",
                    "a sensor radius must be at least 1: the robot senses its neighbours (radius 1) or more, as in the D* Lite paper's navigation experiments".into(),
                ));
            }
            if let Some(twice) = repeated(&config.radii) {
                return Err(invalid(
                    twice.span(),
                    "radii",
                    format!(
                        "radius {} is listed twice: its runs would have the same identity",
                        twice.get_ref()
                    ),
                ));
            }
            if let Some(t) = &config.toggles {
                return Err(invalid(
                    t.span(),
                    "toggles",
                    "only for kind = \"dynamic\"".into(),
                ));
            }
            if !config.gppc.is_empty() {
                return Err(invalid(
                    value_span("gppc"),
                    "gppc",
                    "only for kind = \"dynamic\"".into(),
                ));
            }
        }
        Kind::Dynamic => {
            if let Some(r) = config.radii.first() {
                return Err(invalid(
                    r.span(),
                    "radii",
                    "only for kind = \"navigate\"".into(),
                ));
            }
            if config.toggles.is_none() && config.gppc.is_empty() {
                return Err(invalid(
                    0..0,
                    "toggles",
                    "a dynamic experiment needs [toggles] (with [[maps]]) or [[gppc]]".into(),
                ));
            }
            if let Some(t) = &config.toggles {
                if config.maps.is_empty() {
                    return Err(invalid(
                        t.span(),
                        "maps",
                        "[toggles] runs on the scenarios of [[maps]]".into(),
                    ));
                }
                let seeds = &t.get_ref().seeds;
                if seeds.get_ref().is_empty() {
                    return Err(invalid(
                        seeds.span(),
                        "seeds",
                        "name at least one seed".into(),
                    ));
                }
                if let Some(twice) = repeated(seeds.get_ref()) {
                    return Err(invalid(
                        twice.span(),
                        "seeds",
                        format!(
                            "seed {} is listed twice: its runs would have the same identity",
                            twice.get_ref()
                        ),
                    ));
                }
                let events = &t.get_ref().events;
                if *events.get_ref() > MAX_EVENTS {
                    return Err(invalid(
                        events.span(),
                        "events",
                        format!(
                            "{} events per run is more than the limit of {MAX_EVENTS}: each is a replan checked by A* from scratch and a line of replans.jsonl; use more seeds or scenarios instead",
                            events.get_ref()
                        ),
                    ));
                }
            }
            if config.toggles.is_none() && !config.maps.is_empty() {
                return Err(invalid(
                    value_span("maps"),
                    "maps",
                    "[[maps]] of a dynamic experiment need [toggles]".into(),
                ));
            }
        }
    }
    config.source = text.to_owned();
    Ok(config)
}

/// The first value of `values` that an earlier one equals (the second of the pair, so
/// that an error points at the repeat).
fn repeated<T: PartialEq>(values: &[Spanned<T>]) -> Option<&Spanned<T>> {
    values.iter().enumerate().find_map(|(i, v)| {
        values[..i]
            .iter()
            .any(|w| w.get_ref() == v.get_ref())
            .then_some(v)
    })
}

/// A map read with its picked scenarios.
struct LoadedMap {
    /// The map's file stem (its name in the outputs).
    name: String,
    grid: Grid,
    scenarios: Vec<Scenario>,
    /// Per scenario, why it cannot run when its start or goal is not a free cell of the
    /// map: the `.scen` file, line and column of the cell, and the problem.
    invalid: Vec<Option<String>>,
}

fn load_maps(
    config: &ExperimentConfig,
    dir: &Path,
    options: &RunOptions,
) -> Result<Vec<LoadedMap>, ExperimentError> {
    let mut out = Vec::new();
    for spec in &config.maps {
        let map_path = dir.join(spec.map.get_ref());
        let scen_path = dir.join(&spec.scen);
        let mut grid = planner_maps::read_map(&map_path)?.grid;
        if let Some(weights) = &spec.weights {
            let rule = spec
                .cost_rule
                .as_ref()
                .map_or_else(Default::default, |r| *r.get_ref());
            let options = planner_maps::ReadOptions::default();
            grid = planner_maps::read_weights(&dir.join(weights), grid, rule, &options)?;
        }
        let all = planner_maps::read_scenarios(&scen_path)?;
        let mut n = *spec.scenarios.get_ref();
        if options.test {
            n = n.min(config.test.scenarios.unwrap_or(n));
        }
        let n = n.min(all.len());
        let scenarios: Vec<Scenario> = (0..n).map(|i| all[i * all.len() / n].clone()).collect();
        // A scenario made for a map of another size is an error at its line and column
        // (the `.scen` file is another map's), not a run.
        let origin = scen_path.display().to_string();
        for s in &scenarios {
            s.check_size(&grid, &origin)?;
        }
        // A scenario whose start or goal is blocked or outside the map is recorded as a run
        // with status `invalid_problem`, as the experiment runner records it, and the other
        // runs go on; the message places the cell in the `.scen` file.
        let mut scen_text = None;
        let mut invalid = Vec::with_capacity(scenarios.len());
        for s in &scenarios {
            let why = match Problem::new(&grid, s.start, s.goal) {
                Ok(_) => None,
                Err(e) => {
                    if scen_text.is_none() {
                        scen_text = Some(planner_maps::read_text_file(
                            &scen_path,
                            DEFAULT_MAX_FILE_BYTES,
                        )?);
                    }
                    let text = scen_text.as_deref().unwrap_or_default();
                    let column = scenario_column(text, s.line, &e);
                    let place = place(&scen_path.display().to_string(), s.line, column);
                    Some(format!("{place}: {e}"))
                }
            };
            invalid.push(why);
        }
        let mut name = map_path.file_stem().map_or_else(
            || spec.map.get_ref().clone(),
            |s| s.to_string_lossy().into_owned(),
        );
        if let Some(weights) = &spec.weights {
            // A weighted map is named by both files, apart from the map without weights.
            let stem = Path::new(weights).file_stem().map(|s| s.to_string_lossy());
            name = format!("{name}+{}", stem.unwrap_or_default());
        }
        out.push(LoadedMap {
            name,
            grid,
            scenarios,
            invalid,
        });
    }
    Ok(out)
}

/// The 1-based column, on `line` of a Moving AI `.scen` file's `text`, of the coordinate
/// that makes its problem `error`: the x of the start or goal (its y when only the y is
/// outside the map); 0 when the line is not found. Lines and columns are counted as
/// planner-maps counts them: after a byte-order mark, without a CRLF's `\r`, fields split
/// at tabs, a field's leading spaces skipped, in characters.
fn scenario_column(text: &str, line: usize, error: &ProblemError) -> usize {
    let (endpoint, y_only) = match error {
        ProblemError::Blocked { endpoint, .. } => (endpoint, false),
        ProblemError::OutOfBounds {
            endpoint,
            cell,
            width,
            ..
        } => (endpoint, cell.x < *width),
    };
    // The fields are: bucket, map, width, height, start x, start y, goal x, goal y, length.
    let field = match endpoint {
        Endpoint::Start => 4,
        Endpoint::Goal => 6,
    } + usize::from(y_only);
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Some(row) = text.split('\n').nth(line.wrapping_sub(1)) else {
        return 0;
    };
    let row = row.strip_suffix('\r').unwrap_or(row);
    let mut column = 1;
    for (index, value) in row.split('\t').enumerate() {
        if index == field {
            return column + value.chars().take_while(|c| c.is_whitespace()).count();
        }
        column += value.chars().count() + 1;
    }
    0
}

/// Which run: map, scenario line, setting and planner.
#[derive(Clone)]
struct RunId {
    map: String,
    line: usize,
    /// Radius (navigate) or seed (toggles).
    setting: u64,
    planner: String,
}

impl RunId {
    /// `(map, scenario line, setting, planner)`, the names escaped for the output (`csv`
    /// or `md`): one rule for every text output that names a run.
    fn identity(&self, escape: fn(&str) -> String) -> (String, usize, u64, String) {
        (
            escape(&self.map),
            self.line,
            self.setting,
            escape(&self.planner),
        )
    }
}

/// A finished run: what `runs.csv`, `runs.jsonl` and the summary need of it. Its replans
/// are in files of the working area ([`RunFiles`]), not here.
struct RunDone {
    id: RunId,
    /// How the run ended: the navigation or the toggle script, or why it did not run.
    end: RunEnd,
    totals: RunTotals,
    files: RunFiles,
}

/// How a run ended.
enum RunEnd {
    /// A navigation (navigate): reached, steps, the path driven.
    Navigated(NavEnd),
    /// A toggle script (dynamic): cells toggled and cells driven in all.
    Toggled {
        /// Cells toggled.
        toggled: u64,
        /// Cells the agent drove.
        steps: u64,
    },
    /// The scenario's start or goal is not a free cell of its map: nothing ran. The
    /// message places the cell in the `.scen` file.
    InvalidProblem(String),
}

impl RunDone {
    /// The navigation's end, for a navigate run that ran.
    fn nav(&self) -> Option<&NavEnd> {
        match &self.end {
            RunEnd::Navigated(nav) => Some(nav),
            _ => None,
        }
    }

    /// Why the run did not run, when its problem is invalid.
    fn invalid(&self) -> Option<&str> {
        match &self.end {
            RunEnd::InvalidProblem(why) => Some(why),
            _ => None,
        }
    }

    /// The run's status in the tables: `invalid_problem` when nothing ran, else `ran`.
    fn status(&self) -> &'static str {
        match self.end {
            RunEnd::InvalidProblem(_) => "invalid_problem",
            _ => "ran",
        }
    }
}

/// What a run counted over its replans, kept while it runs ([`RunRecorder`]) and handed
/// to the tables and the summary when it ends ([`RunDone`]).
#[derive(Default)]
struct RunTotals {
    replans: u64,
    expansions: u64,
    /// A*'s expansions over the replans the oracle checked (`None`: none was).
    oracle_expansions: Option<u64>,
    /// Failed checks, all counted.
    mismatches: u64,
    /// The first [`MISMATCHES_LISTED`] of them.
    listed: Vec<String>,
    /// The first replan's planning time (the time to the first move).
    first_planning: Duration,
    planning_time: Duration,
}

/// The files of one run in progress in the working area, named by its place in its chunk
/// (each chunk's runs reuse them): its `replans.jsonl` lines, and for every replan after
/// the first its expansions and A*'s ([`LATER_BYTES`] bytes, read back for the summary and
/// the chart). They are appended to the tables in task order once the chunk ends, and
/// removed.
struct RunFiles {
    lines: PathBuf,
    later: PathBuf,
}

/// Bytes per replan in a run's [`RunFiles::later`] file: its expansions, then A*'s
/// (`u64::MAX` when not checked), little-endian.
const LATER_BYTES: usize = 16;

impl RunFiles {
    fn of(area: &planner_runner::outdir::StreamArea, slot: usize) -> RunFiles {
        RunFiles {
            lines: area.dir.join(format!("run-{slot}.replans.jsonl")),
            later: area.dir.join(format!("run-{slot}.later")),
        }
    }

    /// Removes both files once appended (a failed experiment's go with the working area).
    fn remove(&self) {
        let _ = std::fs::remove_file(&self.lines);
        let _ = std::fs::remove_file(&self.later);
    }
}

/// The [`Recorder`] of a run in an experiment: writes each replan's line to the run's
/// file as it comes and keeps the run's totals, so that a run's memory does not grow with
/// its replans. It stops the run when the experiment's stop flag is raised or a file
/// cannot be written.
struct RunRecorder<'a> {
    id: &'a RunId,
    setting_key: &'static str,
    options: &'a RunOptions,
    lines: std::io::BufWriter<std::fs::File>,
    later: std::io::BufWriter<std::fs::File>,
    files: RunFiles,
    /// The first write that failed.
    failed: Option<ExperimentError>,
    totals: RunTotals,
}

impl<'a> RunRecorder<'a> {
    fn create(
        area: &planner_runner::outdir::StreamArea,
        slot: usize,
        id: &'a RunId,
        kind: Kind,
        options: &'a RunOptions,
    ) -> Result<RunRecorder<'a>, ExperimentError> {
        let files = RunFiles::of(area, slot);
        let open = |path: &Path| -> Result<_, ExperimentError> {
            let name = path.file_name().map(|n| n.to_string_lossy().into_owned());
            Ok(std::io::BufWriter::new(
                area.open_write(&name.unwrap_or_default(), true)?,
            ))
        };
        Ok(RunRecorder {
            id,
            setting_key: setting_key(kind),
            options,
            lines: open(&files.lines)?,
            later: open(&files.later)?,
            files,
            failed: None,
            totals: RunTotals::default(),
        })
    }

    /// Writes `bytes` to one of the run's files, keeping the first failure.
    fn put(&mut self, later: bool, bytes: &[u8]) {
        use std::io::Write as _;
        if self.failed.is_some() {
            return;
        }
        let (writer, path) = match later {
            false => (&mut self.lines, &self.files.lines),
            true => (&mut self.later, &self.files.later),
        };
        if let Err(e) = writer.write_all(bytes) {
            self.failed = Some(io_failure(path, e));
        }
    }

    /// Counts a failed check, keeps its message among the first listed, and returns it.
    fn note(&mut self, mismatch: &Mismatch) -> String {
        let text = mismatch.to_string();
        self.totals.mismatches += 1;
        if self.totals.listed.len() < MISMATCHES_LISTED {
            self.totals.listed.push(text.clone());
        }
        text
    }

    /// Flushes the run's files and returns what the tables and the summary need of it.
    fn finish(mut self, end: RunEnd) -> Result<RunDone, ExperimentError> {
        for (writer, path) in [
            (&mut self.lines, &self.files.lines),
            (&mut self.later, &self.files.later),
        ] {
            if let Err(e) = std::io::Write::flush(writer) {
                self.failed.get_or_insert_with(|| io_failure(path, e));
            }
        }
        if let Some(failed) = self.failed {
            return Err(failed);
        }
        Ok(RunDone {
            id: self.id.clone(),
            end,
            totals: self.totals,
            files: self.files,
        })
    }
}

impl Recorder for RunRecorder<'_> {
    fn replan(&mut self, record: ReplanRecord, mismatch: Option<Mismatch>) {
        let index = self.totals.replans;
        self.totals.replans += 1;
        self.totals.expansions += record.expansions;
        if let Some(astar) = record.oracle_expansions {
            *self.totals.oracle_expansions.get_or_insert(0) += astar;
        }
        self.totals.planning_time += record.planning_time();
        if index == 0 {
            self.totals.first_planning = record.planning_time();
        } else {
            let mut later = [0u8; LATER_BYTES];
            later[..8].copy_from_slice(&record.expansions.to_le_bytes());
            later[8..].copy_from_slice(&record.oracle_expansions.unwrap_or(u64::MAX).to_le_bytes());
            self.put(true, &later);
        }
        let counters: serde_json::Map<String, serde_json::Value> = record
            .counters
            .iter()
            .map(|(k, v)| (k.to_string(), v.into()))
            .collect();
        let mut line = json!({
            "map": self.id.map,
            "scenario_line": self.id.line,
            self.setting_key: self.id.setting,
            "planner": self.id.planner,
            "replan": index,
            "step": record.step,
            "status": record.status.as_str(),
            "expansions": record.expansions,
            "astar_expansions": record.oracle_expansions,
            "cost_units": record.cost.map(|c| c.units()),
            "counters": counters,
        });
        if let Some(mismatch) = &mismatch {
            line["mismatch"] = self.note(mismatch).into();
        }
        if self.options.timing {
            line["update_us"] = (micros(record.update_time) as u64).into();
            line["replan_us"] = (micros(record.replan_time) as u64).into();
        }
        self.put(false, format!("{line}\n").as_bytes());
    }

    fn mismatch(&mut self, mismatch: Mismatch) {
        self.note(&mismatch);
    }

    fn stopped(&self) -> bool {
        self.failed.is_some() || self.options.stopped()
    }
}

/// A CSV field (planner-text's rule, the runner's too).
fn csv(field: &str) -> String {
    planner_text::csv_field(field).into_owned()
}

fn micros(d: Duration) -> u128 {
    d.as_micros()
}

/// Runs the experiment at `path` and writes its results into `output` (see the
/// [module docs](self)). A mismatch is recorded, counted and reported, not an error.
pub fn run(
    path: &Path,
    output: &Path,
    options: &RunOptions,
) -> Result<ExperimentSummary, ExperimentError> {
    run_config(&load(path)?, path, output, options)
}

/// [`run`] of a config already read from `path` (by [`load`] or [`parse`]), so a caller
/// that read it to choose the output does not read it again.
pub fn run_config(
    config: &ExperimentConfig,
    path: &Path,
    output: &Path,
    options: &RunOptions,
) -> Result<ExperimentSummary, ExperimentError> {
    let by_name = |name: &str, eight: bool| match planners::by_name(name, eight) {
        Ok(planner) => planner,
        Err(e) => unreachable!("planner names are validated by parse: {e}"),
    };
    run_config_with(config, path, output, options, &by_name)
}

/// Builds the planner a config names, with 8 moves (`true`) or 4. The names are the
/// config's, which [`parse`] checked against [`planners::names`].
pub type PlannerFactory = dyn Fn(&str, bool) -> Box<dyn IncrementalPlanner> + Sync;

/// [`run_config`] with the planners built by `make` instead of [`planners::by_name`]: the
/// records keep the config's names. For a test that runs a config's experiment with
/// another implementation of a planner in its place (planner-replan's tests hold every
/// planner's records to a reference search this way).
pub fn run_config_with(
    config: &ExperimentConfig,
    path: &Path,
    output: &Path,
    options: &RunOptions,
    make: &PlannerFactory,
) -> Result<ExperimentSummary, ExperimentError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(options.threads)
        .build()
        .map_err(|e| ExperimentError::Io {
            path: "thread pool".into(),
            message: e.to_string(),
        })?;
    let maps = load_maps(config, dir, options)?;
    if let Some(toggles) = &config.toggles {
        let k = &toggles.get_ref().k;
        if let Some(map) = maps.iter().find(|m| *k.get_ref() as usize > m.grid.len()) {
            // A config that `parse` did not read has no text to place the value in.
            let (line, column) = match config.source.is_empty() {
                true => (0, 0),
                false => line_column(&config.source, k.span().start),
            };
            return Err(ExperimentError::TooManyToggles {
                path: path.display().to_string(),
                line,
                column,
                k: *k.get_ref(),
                map: map.name.clone(),
                cells: map.grid.len(),
            });
        }
    }
    let eight = config.moves.as_ref().is_none_or(|m| *m.get_ref() == 8);
    let names: Vec<String> = config
        .planners
        .iter()
        .map(|p| p.get_ref().clone())
        .collect();
    // GPPC inputs are read (and checked) before anything runs or is written.
    let mut gppc_inputs = Vec::new();
    for spec in &config.gppc {
        let scen_path = dir.join(&spec.scen);
        let scen_name = scen_path.display().to_string();
        // Regular files only, at most the map readers' limit: a FIFO or `/dev/zero` named
        // by the config or by the scenario would never end.
        let scen_text = planner_maps::read_text_file(&scen_path, DEFAULT_MAX_FILE_BYTES)?;
        let scenario = parse_gppc_scenario(&scen_text, &scen_name)?;
        // A patch file that cannot be read is an error where the scenario names it.
        let patches = scenario.read_patches(&scen_path, DEFAULT_MAX_FILE_BYTES)?;
        scenario
            .validate(&patches, &scen_name)
            .map_err(|e| gppc_column(e, &scen_text))?;
        let stem = scen_path
            .file_stem()
            .map_or_else(|| spec.scen.clone(), |s| s.to_string_lossy().into_owned());
        gppc_inputs.push((stem, spec.clone(), scenario, patches));
    }
    // Refused before anything runs, as the experiment runner refuses an output.
    planner_runner::outdir::check(output)?;

    // The runs, in a fixed order; rayon keeps it in the collected results.
    let mut tasks: Vec<(usize, usize, u64, usize)> = Vec::new();
    let settings: Vec<u64> = match config.kind {
        Kind::Navigate => config
            .radii
            .iter()
            .map(|r| u64::from(*r.get_ref()))
            .collect(),
        Kind::Dynamic => match &config.toggles {
            Some(t) => {
                let seeds = t.get_ref().seeds.get_ref();
                let n = if options.test {
                    config.test.seeds.unwrap_or(seeds.len()).min(seeds.len())
                } else {
                    seeds.len()
                };
                seeds[..n].iter().map(|s| *s.get_ref()).collect()
            }
            None => Vec::new(),
        },
    };
    for (m, map) in maps.iter().enumerate() {
        for s in 0..map.scenarios.len() {
            for &setting in &settings {
                for p in 0..names.len() {
                    tasks.push((m, s, setting, p));
                }
            }
        }
    }
    let toggle_config = config.toggles.as_ref().map(|t| {
        let t = t.get_ref();
        ToggleConfig {
            events: if options.test {
                let events = *t.events.get_ref();
                config.test.events.unwrap_or(events).min(events)
            } else {
                *t.events.get_ref()
            },
            k: *t.k.get_ref(),
            radius: t.radius,
            drive: t.drive,
            seed: 0,
        }
    });
    // Each run writes its replans into files of the output's working area as they come;
    // once a chunk of runs ends, their lines are appended to the tables in task order and
    // what the summary and the chart need is gathered, so memory does not grow with the
    // records.
    let run_one = |area: &planner_runner::outdir::StreamArea,
                   slot: usize,
                   &(m, s, setting, p): &(usize, usize, u64, usize)|
     -> Result<RunDone, ExperimentError> {
        let map = &maps[m];
        let scenario = &map.scenarios[s];
        let name = &names[p];
        let id = RunId {
            map: map.name.clone(),
            line: scenario.line,
            setting,
            planner: name.clone(),
        };
        let mut recorder = RunRecorder::create(area, slot, &id, config.kind, options)?;
        if let Some(why) = &map.invalid[s] {
            return recorder.finish(RunEnd::InvalidProblem(why.clone()));
        }
        let mut planner = make(name, eight);
        let mut oracle = Oracle::new(eight);
        match config.kind {
            Kind::Navigate => {
                let nav = NavConfig {
                    radius: setting as u32,
                    max_steps: config.max_steps,
                    check_every_change: false,
                };
                match navigate::run_recorded(
                    planner.as_mut(),
                    Some(&mut oracle),
                    &map.grid,
                    scenario.start,
                    scenario.goal,
                    &nav,
                    &Budget::unlimited(),
                    &mut recorder,
                ) {
                    Ok(end) => recorder.finish(RunEnd::Navigated(end)),
                    Err(e) => unreachable!("a scenario load_maps found invalid does not run: {e}"),
                }
            }
            Kind::Dynamic => {
                let problem = match Problem::new(&map.grid, scenario.start, scenario.goal) {
                    Ok(problem) => problem,
                    Err(e) => unreachable!("a scenario load_maps found invalid does not run: {e}"),
                };
                let toggle = ToggleConfig {
                    seed: setting,
                    ..toggle_config.unwrap_or(ToggleConfig {
                        events: 0,
                        k: 0,
                        radius: 0,
                        drive: 0,
                        seed: 0,
                    })
                };
                let end = toggles::run_recorded(
                    planner.as_mut(),
                    &mut oracle,
                    &problem,
                    &toggle,
                    &Budget::unlimited(),
                    &mut recorder,
                );
                recorder.finish(RunEnd::Toggled {
                    toggled: end.toggled,
                    steps: end.steps,
                })
            }
        }
    };
    let mut summary = RunSummary::new(charted_planner(config));
    // Taken even when no table is written, so that what a killed run left there goes.
    let area = WorkingArea(planner_runner::outdir::stream_area(
        output,
        planner_runner::outdir::DEFAULT_LOCK_WAIT,
    )?);
    // The tables are written whatever runs there are: a GPPC replay is a run too.
    let mut tables = Tables::create(&area.0, config.kind, options)?;
    {
        let area = &area.0;
        {
            for chunk in tasks.chunks(RUN_CHUNK) {
                // Once stopped, the chunk's remaining runs do not start, and a run in
                // progress ends before its next step or event.
                let runs: Vec<Option<Result<RunDone, ExperimentError>>> = pool.install(|| {
                    chunk
                        .par_iter()
                        .enumerate()
                        .map(|(slot, task)| (!options.stopped()).then(|| run_one(area, slot, task)))
                        .collect()
                });
                if options.stopped() {
                    return Err(ExperimentError::Interrupted);
                }
                for run in runs.into_iter().flatten() {
                    let run = run?;
                    tables.write(&run, config.kind, options)?;
                    summary.add(&run)?;
                    run.files.remove();
                }
            }
        }
    }
    let gppc_runs: Result<Vec<(String, String, gppc::Replay)>, ExperimentError> =
        pool.install(|| {
            let jobs: Vec<(usize, usize)> = (0..gppc_inputs.len())
                .flat_map(|g| (0..names.len()).map(move |p| (g, p)))
                .collect();
            jobs.par_iter()
                .map(|&(g, p)| {
                    let (stem, spec, scenario, patches) = &gppc_inputs[g];
                    let mut planner = make(&names[p], true);
                    let (mut query_every, mut carry_every) =
                        (*spec.query_every.get_ref(), spec.carry_every);
                    if options.test {
                        query_every = query_every.max(config.test.query_every.unwrap_or(1));
                        carry_every = carry_every.max(config.test.carry_every.unwrap_or(0));
                    }
                    let stop = || options.stopped();
                    // A map too large for the budget is refused before any of it is made;
                    // without `max_memory_mb`, the runner's default (half the machine's
                    // memory) is the budget, as a sweep's.
                    let budget = Budget {
                        max_memory_mb: config
                            .max_memory_mb
                            .as_ref()
                            .map(|mb| *mb.get_ref())
                            .or_else(planner_runner::run::default_max_memory_mb),
                        ..Budget::unlimited()
                    };
                    if let Some(mb) = budget.max_memory_mb {
                        let needed = gppc::memory_bytes(scenario.width, scenario.height, true);
                        if needed > mb.saturating_mul(1 << 20) {
                            let shortfall = planner_api::MemoryShortfall {
                                needed_bytes: needed,
                                max_memory_mb: mb,
                                width: scenario.width,
                                height: scenario.height,
                            };
                            let replay = gppc::Replay {
                                refused: Some(format!("{stem}: {shortfall}")),
                                ..gppc::Replay::default()
                            };
                            return Ok((stem.clone(), names[p].clone(), replay));
                        }
                    }
                    let replay = gppc::replay_until(
                        scenario,
                        patches,
                        planner.as_mut(),
                        query_every,
                        carry_every,
                        &stop,
                    )
                    .map_err(|source| ExperimentError::GppcGrid {
                        path: stem.clone(),
                        source,
                    })?;
                    Ok((stem.clone(), names[p].clone(), replay))
                })
                .collect::<Result<_, ExperimentError>>()
        });
    if options.stopped() {
        return Err(ExperimentError::Interrupted);
    }
    let gppc_runs = gppc_runs?;
    for (stem, planner, replay) in &gppc_runs {
        tables.write_replay(stem, planner, replay, options)?;
    }
    let tables = Some(tables.finish()?);
    write_results(
        config,
        output,
        options,
        &summary,
        tables.as_ref(),
        &gppc_runs,
    )
    // The area goes here, its tables copied into the results, or the run failed.
}

/// The words of `row` (split at whitespace) with their 1-based columns in characters.
fn word_columns(row: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut column = 0;
    let mut start = None;
    let mut words = Vec::new();
    for (byte, ch) in row.char_indices() {
        column += 1;
        match (ch.is_whitespace(), start) {
            (false, None) => start = Some((byte, column)),
            (true, Some((from, at))) => {
                words.push((at, &row[from..byte]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some((from, at)) = start {
        words.push((at, &row[from..]));
    }
    words.into_iter()
}

/// `error` of a GPPC scenario's command, with the column of the field it is about: the
/// patch number of a patch that does not exist, the `x` or `y` that puts a patch outside
/// the map, the coordinate of a query's start or goal outside it. planner-maps' check
/// ([`GppcScenario::validate`](planner_maps::gppc::GppcScenario::validate)) names the
/// command's line alone; the column is found in that line of the scenario's `text`. Any
/// other error, or one with a column, is returned as it is.
fn gppc_column(mut error: MapError, text: &str) -> MapError {
    use planner_maps::MapErrorKind as K;
    if error.column != 0 || error.line == 0 {
        return error;
    }
    // The field's place on the line: `P batch patch x y`, `Q batch sx sy gx gy cost`.
    let field = match &error.kind {
        K::UnknownPatch { .. } => 2,
        K::PatchOutside {
            patch_width,
            x,
            y,
            width,
            height,
            ..
        } => {
            let right = u64::from(*x) + u64::from(*patch_width);
            if *x >= *width || (*y < *height && right > u64::from(*width)) {
                3
            } else {
                4
            }
        }
        K::QueryOutside {
            endpoint,
            cell,
            width,
            ..
        } => {
            let x = if *endpoint == "start" { 2 } else { 4 };
            if cell.x >= *width {
                x
            } else {
                x + 1
            }
        }
        _ => return error,
    };
    // Lines and columns as planner-maps counts them: after a byte-order mark, without the
    // `\r` of a CRLF line end, in characters.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let Some(line) = text.split('\n').nth(error.line - 1) else {
        return error;
    };
    if let Some((column, _)) = word_columns(line).nth(field) {
        error.column = column;
    }
    error
}

/// The output's working area while the tables are written there: removed when the
/// experiment ends, however it ends. A process killed at once (SIGKILL, or the command
/// line's second Ctrl-C) leaves it and its lock, which hold nothing to resume: the next run
/// on the same output takes them over and removes them.
struct WorkingArea(planner_runner::outdir::StreamArea);

impl Drop for WorkingArea {
    fn drop(&mut self) {
        let _ = self.0.remove();
    }
}

/// Tasks run between two writes of the tables: each chunk's records are appended in task
/// order as soon as it finishes (from its runs' files in the working area), so memory holds
/// one chunk's run totals at most.
pub const RUN_CHUNK: usize = 256;

/// The planner whose replans `expansions.svg` draws: the first incremental one compared.
fn charted_planner(config: &ExperimentConfig) -> Option<&'static str> {
    ["dstar_lite", "lpastar"]
        .into_iter()
        .find(|n| config.planners.iter().any(|p| p.get_ref() == n))
}

/// What `summary.md` and `expansions.svg` need of the runs, gathered in task order as the
/// runs finish: per group of runs (map, setting, planner) its totals, one share of A* (and
/// one planning time) per run and the histogram of expansions per replan after the
/// first; the first [`MISMATCHES_LISTED`] failed checks; the chart's sampled points. Its
/// memory grows with the runs and the distinct expansion counts, not with the replans.
struct RunSummary {
    groups: Vec<Group>,
    /// Each group's index in `groups`, by its key.
    index: std::collections::HashMap<(String, u64, String), usize>,
    runs: usize,
    replans: u64,
    mismatches: u64,
    /// The first failed checks, each with its run: (run, message).
    listed: Vec<(RunId, String)>,
    /// Runs whose problem is invalid (they ran nothing and are in no group).
    invalid_runs: usize,
    /// The first [`MISMATCHES_LISTED`] invalid problems, each once (a problem is a run per
    /// setting and planner): its map and message; how many there are; the last one's map
    /// and scenario line.
    invalid_listed: Vec<(String, String)>,
    invalid_problems: usize,
    last_invalid: Option<(String, usize)>,
    charted: Option<&'static str>,
    chart: ChartSample,
}

/// One group's part of a [`RunSummary`].
struct Group {
    id: RunId,
    runs: usize,
    reached: usize,
    replans: u64,
    mismatches: u64,
    expansions: u64,
    /// Per run with A* expansions: the planner's expansions as a share of A*'s.
    shares: Vec<f64>,
    /// Per run: its planning time in milliseconds.
    planning_ms: Vec<f64>,
    /// The expansions of every replan after the first.
    later: Histogram,
}

impl RunSummary {
    fn new(charted: Option<&'static str>) -> RunSummary {
        RunSummary {
            groups: Vec::new(),
            index: std::collections::HashMap::new(),
            runs: 0,
            replans: 0,
            mismatches: 0,
            listed: Vec::new(),
            invalid_runs: 0,
            invalid_listed: Vec::new(),
            invalid_problems: 0,
            last_invalid: None,
            charted,
            chart: ChartSample::default(),
        }
    }

    /// Adds a finished run, reading its replans after the first from its file.
    fn add(&mut self, run: &RunDone) -> Result<(), ExperimentError> {
        use std::io::Read as _;
        self.runs += 1;
        if let Some(why) = run.invalid() {
            // Runs come in task order: a problem's runs (one per setting and planner)
            // follow each other.
            self.invalid_runs += 1;
            let problem = (run.id.map.clone(), run.id.line);
            if self.last_invalid.as_ref() != Some(&problem) {
                self.invalid_problems += 1;
                if self.invalid_listed.len() < MISMATCHES_LISTED {
                    self.invalid_listed
                        .push((run.id.map.clone(), why.to_owned()));
                }
                self.last_invalid = Some(problem);
            }
            return Ok(());
        }
        let key = (run.id.map.clone(), run.id.setting, run.id.planner.clone());
        let at = *self.index.entry(key).or_insert_with(|| {
            self.groups.push(Group {
                id: run.id.clone(),
                runs: 0,
                reached: 0,
                replans: 0,
                mismatches: 0,
                expansions: 0,
                shares: Vec::new(),
                planning_ms: Vec::new(),
                later: Histogram::default(),
            });
            self.groups.len() - 1
        });
        let group = &mut self.groups[at];
        group.runs += 1;
        group.reached += usize::from(run.nav().is_some_and(|n| n.reached));
        group.replans += run.totals.replans;
        group.mismatches += run.totals.mismatches;
        group.expansions += run.totals.expansions;
        if let Some(astar) = run.totals.oracle_expansions.filter(|&a| a > 0) {
            group
                .shares
                .push(run.totals.expansions as f64 / astar as f64);
        }
        group
            .planning_ms
            .push(run.totals.planning_time.as_secs_f64() * 1e3);
        self.replans += run.totals.replans;
        self.mismatches += run.totals.mismatches;
        for m in &run.totals.listed {
            if self.listed.len() < MISMATCHES_LISTED {
                self.listed.push((run.id.clone(), m.clone()));
            }
        }
        let charted = self.charted == Some(run.id.planner.as_str());
        let path = &run.files.later;
        let file = planner_runner::stream::open_regular(path).map_err(|e| io_failure(path, e))?;
        let mut file = std::io::BufReader::new(file);
        let mut record = [0u8; LATER_BYTES];
        loop {
            match file.read_exact(&mut record) {
                Ok(()) => {}
                Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
                Err(e) => return Err(io_failure(path, e)),
            }
            let (mine, astar) = record.split_at(8);
            let expansions = u64::from_le_bytes(mine.try_into().unwrap_or_default());
            let astar = u64::from_le_bytes(astar.try_into().unwrap_or_default());
            group.later.add(expansions);
            if charted && astar != u64::MAX {
                self.chart.add((astar, expansions));
            }
        }
        Ok(())
    }
}

/// Counts of values, for exact quantiles without keeping every value: its memory grows
/// with the distinct values (expansions per replan, at most a few per cell of a map).
#[derive(Default)]
struct Histogram {
    counts: std::collections::BTreeMap<u64, u64>,
    total: u64,
}

impl Histogram {
    fn add(&mut self, value: u64) {
        *self.counts.entry(value).or_insert(0) += 1;
        self.total += 1;
    }

    /// The `q`-quantile by the nearest-rank method, as [`quantile`] finds it among the
    /// values themselves (`None` when empty).
    fn quantile(&self, q: f64) -> Option<f64> {
        if self.total == 0 {
            return None;
        }
        let rank = ((q.clamp(0.0, 1.0) * self.total as f64).ceil() as u64).clamp(1, self.total);
        let mut seen = 0;
        for (&value, &count) in &self.counts {
            seen += count;
            if seen >= rank {
                return Some(value as f64);
            }
        }
        None
    }
}

/// An even subsample of the chart's points as they come, at most [`CHART_POINTS`] of
/// them: every `stride`-th point, the stride doubling (and every other point kept
/// dropped) whenever they would be more.
struct ChartSample {
    points: Vec<(u64, u64)>,
    stride: u64,
    seen: u64,
}

impl Default for ChartSample {
    fn default() -> ChartSample {
        ChartSample {
            points: Vec::new(),
            stride: 1,
            seen: 0,
        }
    }
}

impl ChartSample {
    fn add(&mut self, point: (u64, u64)) {
        if self.seen % self.stride == 0 {
            self.points.push(point);
            if self.points.len() > CHART_POINTS {
                self.stride *= 2;
                let mut i = 0;
                self.points.retain(|_| {
                    i += 1;
                    i % 2 == 1
                });
            }
        }
        self.seen += 1;
    }
}

/// `n` as an English ordinal: 1st, 2nd, 3rd, 4th, 11th, 22nd.
fn ordinal(n: u64) -> String {
    let suffix = match (n % 10, n % 100) {
        (_, 11..=13) => "th",
        (1, _) => "st",
        (2, _) => "nd",
        (3, _) => "rd",
        _ => "th",
    };
    format!("{n}{suffix}")
}

/// The three tables with a line per run or replan (`runs.csv`, `runs.jsonl`,
/// `replans.jsonl`), written as the runs finish into files of the output's working area
/// (planner-runner's `outdir::stream_area`), and copied into the results at the end.
struct Tables {
    files: TableFiles,
    runs_csv: std::io::BufWriter<std::fs::File>,
    runs_jsonl: std::io::BufWriter<std::fs::File>,
    replans_jsonl: std::io::BufWriter<std::fs::File>,
}

/// Where [`Tables`] wrote: each table's name in the results and its file in the area.
struct TableFiles([(&'static str, PathBuf); 3]);

impl Tables {
    fn create(
        area: &planner_runner::outdir::StreamArea,
        kind: Kind,
        options: &RunOptions,
    ) -> Result<Tables, ExperimentError> {
        let names = ["runs.csv", "runs.jsonl", "replans.jsonl"];
        let open = |name: &str| -> Result<_, ExperimentError> {
            Ok(std::io::BufWriter::new(area.open_write(name, true)?))
        };
        let mut tables = Tables {
            files: TableFiles(names.map(|n| (n, area.dir.join(n)))),
            runs_csv: open(names[0])?,
            runs_jsonl: open(names[1])?,
            replans_jsonl: open(names[2])?,
        };
        let header = format!(
            "map,scenario_line,{},planner,reached,steps,replans,total_expansions,astar_expansions,mismatches,status,error{}\n",
            setting_key(kind),
            if options.timing {
                ",time_to_first_move_us,planning_time_us"
            } else {
                ""
            }
        );
        tables.put(0, &header)?;
        Ok(tables)
    }

    /// Appends `text` to table `which` (0: runs.csv, 1: runs.jsonl, 2: replans.jsonl).
    fn put(&mut self, which: usize, text: &str) -> Result<(), ExperimentError> {
        use std::io::Write as _;
        let writer = match which {
            0 => &mut self.runs_csv,
            1 => &mut self.runs_jsonl,
            _ => &mut self.replans_jsonl,
        };
        writer
            .write_all(text.as_bytes())
            .map_err(|e| io_failure(&self.files.0[which].1, e))
    }

    /// Appends `run`'s lines: its line in runs.csv and runs.jsonl, and its replans' lines
    /// from its file.
    fn write(
        &mut self,
        run: &RunDone,
        kind: Kind,
        options: &RunOptions,
    ) -> Result<(), ExperimentError> {
        let setting_key = setting_key(kind);
        // A value that was not measured is an empty field (JSON: absent or null), never a
        // 0 that a mean would count: `reached` of a toggle script (it ends after its
        // events, not at the goal), and every measurement of a run that did not run.
        let ran = run.invalid().is_none();
        let (reached, steps) = match &run.end {
            RunEnd::Navigated(nav) => (Some(nav.reached), Some(nav.steps)),
            RunEnd::Toggled { steps, .. } => (None, Some(*steps)),
            RunEnd::InvalidProblem(_) => (None, None),
        };
        let field = |value: Option<String>| value.unwrap_or_default();
        let measured = |value: u64| field(ran.then(|| value.to_string()));
        let (map, line, setting, planner) = run.id.identity(csv);
        let mut csv_line = format!(
            "{map},{line},{setting},{planner},{},{},{},{},{},{},{},{}",
            field(reached.map(|r| r.to_string())),
            field(steps.map(|s| s.to_string())),
            measured(run.totals.replans),
            measured(run.totals.expansions),
            field(run.totals.oracle_expansions.map(|a| a.to_string())),
            measured(run.totals.mismatches),
            run.status(),
            csv(run.invalid().unwrap_or_default()),
        );
        if options.timing {
            let _ = write!(
                csv_line,
                ",{},{}",
                field(ran.then(|| micros(run.totals.first_planning).to_string())),
                field(ran.then(|| micros(run.totals.planning_time).to_string())),
            );
        }
        csv_line.push('\n');
        self.put(0, &csv_line)?;
        let mut line = json!({
            "map": run.id.map,
            "scenario_line": run.id.line,
            setting_key: run.id.setting,
            "planner": run.id.planner,
            "status": run.status(),
            "replans": ran.then_some(run.totals.replans),
            "total_expansions": ran.then_some(run.totals.expansions),
            "astar_expansions": run.totals.oracle_expansions,
            "mismatches": ran.then_some(run.totals.mismatches),
            "mismatch_messages": run.totals.listed,
        });
        if let Some(why) = run.invalid() {
            line["error"] = why.into();
        }
        if let Some(reached) = reached {
            line["reached"] = reached.into();
        }
        if let Some(steps) = steps {
            line["steps"] = steps.into();
        }
        match &run.end {
            RunEnd::Navigated(nav) => {
                line["path"] = nav.path.iter().map(|c| json!([c.x, c.y])).collect();
            }
            RunEnd::Toggled { toggled, .. } => line["toggled"] = (*toggled).into(),
            RunEnd::InvalidProblem(_) => {}
        }
        if options.timing && ran {
            line["time_to_first_move_us"] = (micros(run.totals.first_planning) as u64).into();
            line["planning_time_us"] = (micros(run.totals.planning_time) as u64).into();
        }
        self.put(1, &format!("{line}\n"))?;
        let path = &run.files.lines;
        let mut from =
            planner_runner::stream::open_regular(path).map_err(|e| io_failure(path, e))?;
        std::io::copy(&mut from, &mut self.replans_jsonl)
            .map_err(|e| io_failure(&self.files.0[2].1, e))?;
        Ok(())
    }

    /// Appends a GPPC replay's lines (after every navigation and toggle script): its line
    /// in runs.csv and runs.jsonl (the scenario file's stem as `map`, no scenario line or
    /// setting: the replay is of a whole file; `replans` its carried queries, the
    /// expansions their sums, `mismatches` its failed checks and the queries that disagree
    /// with their recorded optimum), and a line per carried query in replans.jsonl.
    fn write_replay(
        &mut self,
        stem: &str,
        planner: &str,
        replay: &gppc::Replay,
        options: &RunOptions,
    ) -> Result<(), ExperimentError> {
        if let Some(why) = &replay.refused {
            let mut csv_line = format!(
                "{},,,{},,,,,,,over_memory,{}",
                csv(stem),
                csv(planner),
                csv(why)
            );
            if options.timing {
                csv_line.push_str(",,");
            }
            csv_line.push('\n');
            self.put(0, &csv_line)?;
            let line = json!({
                "map": stem,
                "scenario_line": null,
                "seed": null,
                "planner": planner,
                "status": "over_memory",
                "error": why,
                "gppc": true,
            });
            return self.put(1, &format!("{line}\n"));
        }
        let carried = &replay.carried;
        // Measured on carried queries only: none carried, none measured.
        let sum = |f: fn(&gppc::CarryRecord) -> u64| {
            (!carried.is_empty()).then(|| carried.iter().map(f).sum::<u64>())
        };
        let (expansions, astar) = (sum(|c| c.repair_expansions), sum(|c| c.astar_expansions));
        let repair_time: Duration = carried.iter().map(|c| c.repair_time).sum();
        let mut listed: Vec<String> = replay.mismatches.iter().map(|m| m.to_string()).collect();
        listed.extend(replay.queries.iter().filter(|q| !q.agrees).map(|q| {
            format!(
                "query at line {}: recorded {}, A* {}",
                q.line,
                q.recorded.map_or("no path".into(), |r| r.to_string()),
                q.astar.map_or("no path".into(), |c| c.to_f64().to_string()),
            )
        }));
        let mismatches = listed.len();
        listed.truncate(MISMATCHES_LISTED);
        let field = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
        let mut csv_line = format!(
            "{},,,{},,,{},{},{},{mismatches},ran,",
            csv(stem),
            csv(planner),
            carried.len(),
            field(expansions),
            field(astar),
        );
        if options.timing {
            let _ = write!(
                csv_line,
                ",,{}",
                field((!carried.is_empty()).then(|| micros(repair_time) as u64))
            );
        }
        csv_line.push('\n');
        self.put(0, &csv_line)?;
        let mut line = json!({
            "map": stem,
            "scenario_line": null,
            "seed": null,
            "planner": planner,
            "status": "ran",
            "replans": carried.len(),
            "total_expansions": expansions,
            "astar_expansions": astar,
            "mismatches": mismatches,
            "mismatch_messages": listed,
            "gppc": true,
            "queries": replay.queries.len(),
            "patches_applied": replay.patches_applied,
        });
        if options.timing && !carried.is_empty() {
            line["planning_time_us"] = (micros(repair_time) as u64).into();
        }
        self.put(1, &format!("{line}\n"))?;
        for (index, c) in carried.iter().enumerate() {
            let counters: serde_json::Map<String, serde_json::Value> = c
                .counters
                .iter()
                .map(|(k, v)| (k.to_string(), v.into()))
                .collect();
            let mut line = json!({
                "map": stem,
                "scenario_line": null,
                "seed": null,
                "planner": planner,
                "replan": index,
                "step": c.line,
                "query_line": c.line,
                "status": c.status.as_str(),
                "expansions": c.repair_expansions,
                "astar_expansions": c.astar_expansions,
                "first_expansions": c.first_expansions,
                "changed_cells": c.changed_cells,
                "cost_units": c.cost.map(|c| c.units()),
                "counters": counters,
            });
            if let Some(mismatch) = &c.mismatch {
                line["mismatch"] = mismatch.to_string().into();
            }
            if options.timing {
                line["replan_us"] = (micros(c.repair_time) as u64).into();
            }
            self.put(2, &format!("{line}\n"))?;
        }
        Ok(())
    }

    /// Flushes the tables and closes them.
    fn finish(self) -> Result<TableFiles, ExperimentError> {
        let Tables {
            files,
            runs_csv,
            runs_jsonl,
            replans_jsonl,
        } = self;
        for (writer, (_, path)) in [runs_csv, runs_jsonl, replans_jsonl]
            .into_iter()
            .zip(&files.0)
        {
            writer
                .into_inner()
                .map_err(|e| io_failure(path, e.into_error()))?;
        }
        Ok(files)
    }
}

/// The key of a run's setting in the tables: the sensor radius or the toggles' seed.
fn setting_key(kind: Kind) -> &'static str {
    match kind {
        Kind::Navigate => "radius",
        Kind::Dynamic => "seed",
    }
}

fn io_failure(path: &Path, source: std::io::Error) -> ExperimentError {
    ExperimentError::Table {
        path: path.display().to_string(),
        source,
    }
}

/// Writes every output file as the results directory `output` (see the
/// [module docs](self)): the tables from `tables`' files, the rest from `stats` and
/// `gppc_runs`.
fn write_results(
    config: &ExperimentConfig,
    output: &Path,
    options: &RunOptions,
    runs: &RunSummary,
    tables: Option<&TableFiles>,
    gppc_runs: &[(String, String, gppc::Replay)],
) -> Result<ExperimentSummary, ExperimentError> {
    let mut gppc_csv = String::from(
        "scenario,planner,patches_applied,queries,agree,carried,repair_expansions,astar_expansions,first_expansions,mismatches\n",
    );
    for (stem, planner, replay) in gppc_runs {
        // A refused replay measured nothing: empty fields, not zeros.
        if replay.refused.is_some() {
            let _ = writeln!(gppc_csv, "{},{},,,,,,,,", csv(stem), csv(planner));
            continue;
        }
        let agree = replay.queries.iter().filter(|q| q.agrees).count();
        // The expansions are measured on carried queries only: none carried, none
        // measured (an empty field, not a 0).
        let sum = |f: fn(&gppc::CarryRecord) -> u64| match replay.carried.is_empty() {
            true => String::new(),
            false => replay.carried.iter().map(f).sum::<u64>().to_string(),
        };
        let _ = writeln!(
            gppc_csv,
            "{},{},{},{},{agree},{},{},{},{},{}",
            csv(stem),
            csv(planner),
            replay.patches_applied,
            replay.queries.len(),
            replay.carried.len(),
            sum(|c| c.repair_expansions),
            sum(|c| c.astar_expansions),
            sum(|c| c.first_expansions),
            replay.mismatches.len()
        );
    }
    let totals = Totals::of(runs, gppc_runs);
    let summary = summary_md(config, options, runs, &totals, gppc_runs);
    let mut outputs = Vec::new();
    let mut write = |name: &str, text: &str| {
        outputs.push(planner_runner::outdir::OutputFile {
            path: PathBuf::from(name),
            contents: text.as_bytes().to_vec(),
        });
    };
    write("summary.md", &summary);
    if !gppc_runs.is_empty() {
        write("gppc.csv", &gppc_csv);
    }
    if let Some(charted) = runs.charted.filter(|_| runs.runs > 0) {
        let chart = &runs.chart;
        let title = if chart.stride > 1 {
            format!(
                "{}: expansions per replan after the first (every {} of {})",
                config.name.get_ref(),
                ordinal(chart.stride),
                chart.seen
            )
        } else {
            format!(
                "{}: expansions per replan after the first ({} replans)",
                config.name.get_ref(),
                chart.seen
            )
        };
        write(
            "expansions.svg",
            &scatter_svg(
                &chart.points,
                "A* from scratch at the replan",
                &format!("{charted} at the replan"),
                &title,
            ),
        );
    }
    // The tables are copied from the working area straight into the new directory, a
    // block at a time: a stop between blocks fails the write, which discards the new
    // directory and leaves the output as it was.
    let streamed: Vec<planner_runner::output::StreamedFile<'_>> = tables
        .map(|t| &t.0[..])
        .unwrap_or_default()
        .iter()
        .map(|(name, path)| planner_runner::output::StreamedFile {
            path: PathBuf::from(name),
            write: Box::new(move |out| {
                copy_unless_stopped(path, out, options)
                    .map_err(|e| planner_runner::RunnerError::io(path, e))
            }),
        })
        .collect();
    let written = planner_runner::outdir::write_results_streamed(
        output,
        config.name.get_ref(),
        &outputs,
        &streamed,
        planner_runner::outdir::DEFAULT_LOCK_WAIT,
    )
    .map_err(|e| match options.stopped() {
        true => ExperimentError::Interrupted,
        false => e.into(),
    })?;
    let mut files: Vec<PathBuf> = outputs.iter().map(|f| written.join(&f.path)).collect();
    files.extend(streamed.iter().map(|f| written.join(&f.path)));
    Ok(ExperimentSummary {
        name: config.name.get_ref().clone(),
        runs: totals.runs,
        replans: totals.replans,
        queries: totals.queries,
        mismatches: totals.mismatches,
        files,
    })
}

/// The counts that the command line's report (through [`ExperimentSummary`]) and
/// `summary.md`'s head both give, from one place. A GPPC replay (one scenario file and one
/// planner) is a run; its replans are its carried queries (the planner's repairs after the
/// next batch's patches, each checked against A* from scratch on the patched map); its
/// checked queries (A* against the recorded optimum) are counted apart.
struct Totals {
    /// Navigations and toggle scripts, and GPPC replays.
    runs: usize,
    /// Of `runs`, the GPPC replays.
    replays: usize,
    /// Replans checked against A* from scratch, GPPC's carried queries included.
    replans: u64,
    /// Of `replans`, GPPC's carried queries.
    carried: u64,
    /// GPPC queries checked against their recorded optimum.
    queries: u64,
    /// Failed checks: replans, and GPPC queries that disagree with their recorded optimum.
    mismatches: u64,
}

impl Totals {
    fn of(runs: &RunSummary, gppc_runs: &[(String, String, gppc::Replay)]) -> Totals {
        let sum = |f: fn(&gppc::Replay) -> u64| gppc_runs.iter().map(|(_, _, g)| f(g)).sum::<u64>();
        let carried = sum(|g| g.carried.len() as u64);
        Totals {
            runs: runs.runs + gppc_runs.len(),
            replays: gppc_runs.len(),
            replans: runs.replans + carried,
            carried,
            queries: sum(|g| g.queries.len() as u64),
            mismatches: runs.mismatches
                + sum(|g| {
                    g.mismatches.len() as u64
                        + g.queries.iter().filter(|q| !q.agrees).count() as u64
                }),
        }
    }
}

/// Copies the file at `path` to `out` a block at a time, and fails with
/// [`std::io::ErrorKind::Interrupted`] once `options`' stop flag is raised.
fn copy_unless_stopped(
    path: &Path,
    out: &mut dyn std::io::Write,
    options: &RunOptions,
) -> std::io::Result<()> {
    use std::io::Read as _;
    let mut from = planner_runner::stream::open_regular(path)?;
    let mut block = vec![0u8; 1 << 20];
    loop {
        if options.stopped() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::Interrupted,
                "stopped while the results were written",
            ));
        }
        match from.read(&mut block) {
            Ok(0) => return Ok(()),
            Ok(n) => out.write_all(&block[..n])?,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
}

fn pct(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{:.1} %", 100.0 * x))
}

fn whole(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{x:.0}"))
}

/// `summary.md`: the `totals`; per map, setting and planner, the runs' totals and the
/// per-replan distribution; GPPC replays per scenario and planner.
fn summary_md(
    config: &ExperimentConfig,
    options: &RunOptions,
    runs: &RunSummary,
    totals: &Totals,
    gppc_runs: &[(String, String, gppc::Replay)],
) -> String {
    let mut out = format!("# {}\n\n", md_cell(config.name.get_ref()));
    if !config.description.trim().is_empty() {
        // Markdown kept, raw HTML and unsafe links shown as text, as in the runner's reports.
        let prose = md_prose(config.description.trim());
        let _ = writeln!(out, "{prose}\n");
    }
    let (kind, setting) = match config.kind {
        Kind::Navigate => ("navigate", "radius"),
        Kind::Dynamic => ("dynamic", "seed"),
    };
    let test = if options.test { " (test limits)" } else { "" };
    let Totals {
        runs: total_runs,
        replays,
        replans,
        carried,
        queries,
        mismatches,
    } = totals;
    // Runs whose problem is invalid are counted and listed, in no group.
    let invalid = match runs.invalid_runs {
        0 => String::new(),
        n => format!(
            " ({n} of them on {} invalid problem{}, which did not run: listed below, in no table row)",
            runs.invalid_problems,
            if runs.invalid_problems == 1 { "" } else { "s" }
        ),
    };
    if gppc_runs.is_empty() {
        let _ = writeln!(
            out,
            "Kind `{kind}`{test}: {total_runs} runs{invalid}, {replans} replans, each checked against A* from scratch on the same map: **{mismatches} mismatches**.\n",
        );
    } else {
        let _ = writeln!(
            out,
            "Kind `{kind}`{test}: {total_runs} runs{invalid} ({replays} of them GPPC replays), {replans} replans ({carried} of them GPPC queries carried across the next batch's patches), each checked against A* from scratch on the same map, and {queries} GPPC queries checked against their recorded optimum: **{mismatches} mismatches**.\n",
        );
    }
    if !runs.groups.is_empty() {
        let _ = writeln!(
            out,
            "Per map, {setting} and planner: runs; runs that reached the goal (navigate); replans; mismatches; total expansions over the runs; the median over runs of the planner's total expansions as a share of A* from scratch at the same replans (the oracle's searches); expansions per replan after the first (p50, p90, p99, max){}.\n",
            if options.timing {
                "; median planning time per run (ms)"
            } else {
                ""
            }
        );
        let _ = writeln!(
            out,
            "| map | {setting} | planner | runs | reached | replans | mismatches | expansions | median share of A* | p50 | p90 | p99 | max |{}",
            if options.timing { " planning ms |" } else { "" }
        );
        let _ = writeln!(
            out,
            "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|{}",
            if options.timing { "---:|" } else { "" }
        );
        for group in &runs.groups {
            let (map, s, planner) = (&group.id.map, group.id.setting, &group.id.planner);
            let reached = match config.kind {
                Kind::Navigate => group.reached.to_string(),
                Kind::Dynamic => "-".into(),
            };
            let later = &group.later;
            let _ = write!(
                out,
                "| {} | {s} | {} | {} | {reached} | {} | {} | {} | {} | {} | {} | {} | {} |",
                md_cell(map),
                md_cell(planner),
                group.runs,
                group.replans,
                group.mismatches,
                group.expansions,
                pct(quantile(&group.shares, 0.5)),
                whole(later.quantile(0.5)),
                whole(later.quantile(0.9)),
                whole(later.quantile(0.99)),
                whole(later.quantile(1.0)),
            );
            if options.timing {
                let _ = write!(
                    out,
                    " {} |",
                    quantile(&group.planning_ms, 0.5).map_or("-".into(), |t| format!("{t:.2}"))
                );
            }
            out.push('\n');
        }
        out.push('\n');
        for (id, m) in &runs.listed {
            let (map, line, value, planner) = id.identity(md_cell);
            let _ = writeln!(
                out,
                "- MISMATCH {map} line {line} {setting} {value} {planner}: {}",
                md_cell(m)
            );
        }
        let unlisted = runs.mismatches - runs.listed.len() as u64;
        if unlisted > 0 {
            let _ = writeln!(
                out,
                "- and {unlisted} more mismatches: runs.csv counts each run's, runs.jsonl lists each run's first {MISMATCHES_LISTED} (`mismatch_messages`), and the replans.jsonl line of every failed replan has its `mismatch`."
            );
        }
    }
    if runs.invalid_runs > 0 {
        for (map, why) in &runs.invalid_listed {
            let _ = writeln!(out, "- INVALID PROBLEM {}: {}", md_cell(map), md_cell(why));
        }
        let unlisted = runs.invalid_problems - runs.invalid_listed.len();
        if unlisted > 0 {
            let _ = writeln!(
                out,
                "- and {unlisted} more invalid problems: runs.csv and runs.jsonl have each run's `error`."
            );
        }
        out.push('\n');
    }
    for why in gppc_runs.iter().filter_map(|(_, _, g)| g.refused.as_ref()) {
        let _ = writeln!(out, "- OVER MEMORY {}\n", md_cell(why));
    }
    if !gppc_runs.is_empty() {
        let _ = writeln!(
            out,
            "GPPC dynamic scenarios: per scenario and planner (one replay, a run), patch commands applied, queries checked (each against its recorded optimum and A* on the patched map), those that agree, queries carried across the next batch's patches (the replay's replans), the planner's mismatches there, and its repair expansions against A*'s from scratch on the patched map. The mismatches above count these and the queries that do not agree.\n"
        );
        let _ = writeln!(
            out,
            "| scenario | planner | patches | queries | agree | carried | mismatches | repair expansions | A* expansions | share |"
        );
        let _ = writeln!(out, "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|");
        for (stem, planner, replay) in gppc_runs {
            // A refused replay measured nothing (it is listed above as over memory).
            if replay.refused.is_some() {
                let _ = writeln!(
                    out,
                    "| {} | {} | - | - | - | - | - | - | - | - |",
                    md_cell(stem),
                    md_cell(planner)
                );
                continue;
            }
            let agree = replay.queries.iter().filter(|q| q.agrees).count();
            let repair: u64 = replay.carried.iter().map(|c| c.repair_expansions).sum();
            let astar: u64 = replay.carried.iter().map(|c| c.astar_expansions).sum();
            // None carried, none measured.
            let (repair_cell, astar_cell) = match replay.carried.is_empty() {
                true => ("-".to_owned(), "-".to_owned()),
                false => (repair.to_string(), astar.to_string()),
            };
            let _ = writeln!(
                out,
                "| {} | {} | {} | {} | {agree} | {} | {} | {repair_cell} | {astar_cell} | {} |",
                md_cell(stem),
                md_cell(planner),
                replay.patches_applied,
                replay.queries.len(),
                replay.carried.len(),
                replay.mismatches.len(),
                pct((astar > 0).then(|| repair as f64 / astar as f64)),
            );
        }
        out.push('\n');
        for (stem, planner, replay) in gppc_runs {
            for m in &replay.mismatches {
                let _ = writeln!(
                    out,
                    "- MISMATCH {} {}: {}",
                    md_cell(stem),
                    md_cell(planner),
                    md_cell(&m.to_string())
                );
            }
        }
    }
    out
}
