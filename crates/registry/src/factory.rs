//! The typed boundary between the runner and the planners.
//!
//! The registry turns a label's parameter table into a [`Factory`] once, when the config
//! is read: the table is deserialized into the planner crate's own `Config` (errors name
//! the key, by [`serde_path_to_error`]), validated by the crate's constructor (errors name
//! the key, by [`ParamKey`]), and the planner built once to read its [`PlannerSpecs`].
//! From then on the runner asks the factory, never the parameter table: whether the
//! planner is seeded, the rule its paths obey, and whether it plans start-goal queries or
//! covers. Planners are then built per worker and reused across runs.

use std::sync::Arc;

use planner_api::{
    CoveragePlanner, IncrementalPlanner, ParamError, ParamKey, Planner, PlannerSpecs, SEED_PARAM,
};
use schemars::JsonSchema;
use serde::de::DeserializeOwned;
use serde::Serialize;

/// What a planner does with a problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Task {
    /// Start-goal path planning ([`Planner`]).
    StartGoal,
    /// Coverage from a start ([`CoveragePlanner`], seed 004); the goal is ignored.
    Coverage,
}

/// A freshly built planner of either task.
pub enum Built {
    /// A start-goal planner.
    Path(Box<dyn Planner>),
    /// A coverage planner.
    Coverage(Box<dyn CoveragePlanner>),
}

/// What a factory needs of a planner crate's `Config`: read from a label's TOML table,
/// written to runs.json as resolved, described by a JSON Schema, and cloned into each
/// planner built (from any worker thread). Every type with those traits has it.
pub trait PlannerConfig:
    DeserializeOwned + Serialize + JsonSchema + Clone + Send + Sync + 'static
{
}

impl<C> PlannerConfig for C where
    C: DeserializeOwned + Serialize + JsonSchema + Clone + Send + Sync + 'static
{
}

type Make = dyn Fn() -> Result<Built, ParamError> + Send + Sync;
type MakeIncremental = dyn Fn() -> Result<Box<dyn IncrementalPlanner>, ParamError> + Send + Sync;

/// A validated planner configuration: builds planners and says what they are.
#[derive(Clone)]
pub struct Factory {
    name: &'static str,
    task: Task,
    specs: PlannerSpecs,
    own_seed: Option<u64>,
    resolved: serde_json::Value,
    parameters: fn() -> schemars::Schema,
    make: Arc<Make>,
    /// Builds the planner behind [`IncrementalPlanner`], for incremental planners.
    make_incremental: Option<Arc<MakeIncremental>>,
}

impl std::fmt::Debug for Factory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factory")
            .field("name", &self.name)
            .field("task", &self.task)
            .field("specs", &self.specs)
            .field("own_seed", &self.own_seed)
            .finish_non_exhaustive()
    }
}

impl Factory {
    /// The registry name.
    pub fn name(&self) -> &'static str {
        self.name
    }

    /// Start-goal or coverage.
    pub fn task(&self) -> Task {
        self.task
    }

    /// What the planner declares about itself.
    pub fn specs(&self) -> &PlannerSpecs {
        &self.specs
    }

    /// The seed of run `repeat` for a seeded planner: the label's own `seed` parameter if
    /// it sets one, else the experiment's `base`, plus `repeat` (wrapping at `u64::MAX`,
    /// documented in configs/README.md). `None` for unseeded planners.
    pub fn seed_for(&self, base: u64, repeat: u32) -> Option<u64> {
        self.specs.seeded.then(|| {
            self.own_seed
                .unwrap_or(base)
                .wrapping_add(u64::from(repeat))
        })
    }

    /// The planner's configuration as resolved: every parameter, the defaults included,
    /// as the planner crate's `Config` serializes it (for summary.md and runs.json).
    pub fn resolved(&self) -> &serde_json::Value {
        &self.resolved
    }

    /// The JSON Schema of the planner crate's `Config`: its declared parameters, with their
    /// types, defaults, allowed values and doc comments ([`crate::schema`] reads it).
    pub fn parameters(&self) -> schemars::Schema {
        (self.parameters)()
    }

    /// A new planner.
    pub fn build(&self) -> Result<Built, ParamError> {
        (self.make)()
    }

    /// Whether the planner is incremental: registered with [`Factory::incremental`], so
    /// [`Factory::build_incremental`] builds it behind [`IncrementalPlanner`].
    pub fn is_incremental(&self) -> bool {
        self.make_incremental.is_some()
    }

    /// A new planner behind the [`IncrementalPlanner`] interface (`None`: the planner is
    /// not incremental).
    pub fn build_incremental(&self) -> Option<Result<Box<dyn IncrementalPlanner>, ParamError>> {
        self.make_incremental.as_ref().map(|make| make())
    }

    /// A start-goal factory for the planner crate whose config is `C` and constructor `new`.
    pub fn path<C, P, E>(
        name: &'static str,
        params: &toml::Table,
        new: fn(C) -> Result<P, E>,
    ) -> Result<Factory, ParamError>
    where
        C: PlannerConfig,
        P: Planner + 'static,
        E: ParamKey + 'static,
    {
        Factory::typed(name, Task::StartGoal, params, new, P::specs, |p| {
            Built::Path(Box::new(p))
        })
    }

    /// A start-goal factory for an incremental planner crate (one that implements both
    /// [`Planner`] and [`IncrementalPlanner`]): [`Factory::build`] builds it as a
    /// one-shot planner, [`Factory::build_incremental`] as an incremental one. A crate
    /// registered this way is one of the planners the replanning experiments
    /// (planner-replan) can compare.
    pub fn incremental<C, P, E>(
        name: &'static str,
        params: &toml::Table,
        new: fn(C) -> Result<P, E>,
    ) -> Result<Factory, ParamError>
    where
        C: PlannerConfig,
        P: Planner + IncrementalPlanner + 'static,
        E: ParamKey + 'static,
    {
        let mut factory = Factory::path(name, params, new)?;
        let config: C = deserialize(params)?;
        factory.make_incremental = Some(Arc::new(
            move || -> Result<Box<dyn IncrementalPlanner>, ParamError> {
                new(config.clone())
                    .map(|p| Box::new(p) as Box<dyn IncrementalPlanner>)
                    .map_err(|e| e.to_param_error())
            },
        ));
        Ok(factory)
    }

    /// A coverage factory for the planner crate whose config is `C` and constructor `new`.
    pub fn coverage<C, P, E>(
        name: &'static str,
        params: &toml::Table,
        new: fn(C) -> Result<P, E>,
    ) -> Result<Factory, ParamError>
    where
        C: PlannerConfig,
        P: CoveragePlanner + 'static,
        E: ParamKey + 'static,
    {
        Factory::typed(name, Task::Coverage, params, new, P::specs, |p| {
            Built::Coverage(Box::new(p))
        })
    }

    /// The factory of either task: deserializes and validates `params` into `C` once,
    /// reads the planner's specs, and builds planners with `new`, wrapped by `wrap`.
    fn typed<C, P, E>(
        name: &'static str,
        task: Task,
        params: &toml::Table,
        new: fn(C) -> Result<P, E>,
        specs_of: fn(&P) -> PlannerSpecs,
        wrap: fn(P) -> Built,
    ) -> Result<Factory, ParamError>
    where
        C: PlannerConfig,
        P: 'static,
        E: ParamKey + 'static,
    {
        let config: C = deserialize(params)?;
        let resolved = serde_json::to_value(&config).unwrap_or(serde_json::Value::Null);
        let planner = new(config.clone()).map_err(|e| e.to_param_error())?;
        let specs = specs_of(&planner);
        let make = move || -> Result<Built, ParamError> {
            new(config.clone())
                .map(wrap)
                .map_err(|e| e.to_param_error())
        };
        Ok(Factory {
            name,
            task,
            own_seed: own_seed(&specs, params)?,
            resolved,
            parameters: crate::schema::parameters_of::<C>,
            specs,
            make: Arc::new(make),
            make_incremental: None,
        })
    }
}

/// The label's own seed, for seeded planners: the `seed` parameter ([`SEED_PARAM`]),
/// which every seeded planner's config takes as a `u64`.
fn own_seed(specs: &PlannerSpecs, params: &toml::Table) -> Result<Option<u64>, ParamError> {
    if !specs.seeded {
        return Ok(None);
    }
    match params.get(SEED_PARAM) {
        None => Ok(None),
        Some(value) => value
            .as_integer()
            .and_then(|s| u64::try_from(s).ok())
            .map(Some)
            .ok_or_else(|| {
                ParamError::new(
                    SEED_PARAM,
                    format!(
                        "parameter `{SEED_PARAM}` must be an integer from 0 to 2^63-1, got {value}"
                    ),
                )
            }),
    }
}

/// Deserializes a parameter table into a planner's config; errors name the key.
fn deserialize<C: DeserializeOwned>(params: &toml::Table) -> Result<C, ParamError> {
    serde_path_to_error::deserialize(toml::Value::Table(params.clone())).map_err(|e| {
        let key = e.path().to_string();
        let key = if key == "." { String::new() } else { key };
        // toml appends "in `key`" on a second line; the key is reported apart.
        let message = e.inner().to_string();
        let message = message
            .lines()
            .next()
            .unwrap_or_default()
            .trim()
            .to_string();
        ParamError::new(key, message)
    })
}
