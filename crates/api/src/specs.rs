//! What a planner declares about itself, and typed parameter errors.
//!
//! In the spirit of OMPL's `PlannerSpecs`: the runner never guesses what a planner is from
//! its parameter names. A planner says whether it is seeded and which rule its paths obey
//! ([`PlannerSpecs`]); a planner's constructor reports a bad parameter as a
//! [`ParamError`] that names the key, so a config reader can point at it without reading
//! the message.

use thiserror::Error;

use crate::moves::MoveSet;
use crate::path::PathRule;

/// The parameter name under which every seeded planner takes its seed (a `u64`).
pub const SEED_PARAM: &str = "seed";

/// What a planner declares about itself.
#[derive(Debug, Clone)]
pub struct PlannerSpecs {
    /// Whether results depend on a seed ([`crate::Planner::reseed`] sets it per run);
    /// otherwise counters are a pure function of (grid, problem, config).
    pub seeded: bool,
    /// The rule every path the planner returns obeys, checked by the runner.
    pub path_rule: PathSpec,
    /// For heuristic searches: whether the heuristic, times its weight, never overestimates
    /// the remaining cost under the planner's moves, so that found paths are optimal by
    /// design. `Some(false)` marks configurations that trade optimality on purpose (seed
    /// 002's TA-star: Manhattan with 8 moves; weighted A*). `None`: no such claim.
    pub admissible: Option<bool>,
    /// Whether the planner also implements
    /// [`IncrementalPlanner`](crate::incremental::IncrementalPlanner): it can be fed map
    /// changes and repairs its search instead of restarting.
    pub incremental: bool,
    /// Whether the planner honours cell weights ([`crate::weights`]): on a weighted grid
    /// its paths are least-cost under the grid's move cost rule (or as good as its
    /// admissibility says). A planner that does not is refused a weighted grid by the
    /// runner, with an error naming the planner and the map, unless the config says
    /// `costs = "ignore"`. The conformance tests hold a planner that declares both this
    /// and `admissible: Some(true)` to the weighted oracle's costs; without an
    /// admissibility claim they check only that its paths on weighted grids keep its rule,
    /// so the declaration is the planner's word (its crate's docs say how it weighs costs).
    pub cell_costs: bool,
    /// Set when the planner honours cell weights only in other configurations (so
    /// [`PlannerSpecs::cell_costs`] is false in this one): the parameter that decides it,
    /// the values with which it does, and why not otherwise. A refusal of a weighted map
    /// names them, so a user knows which setting to change.
    pub cell_costs_only_with: Option<CostsCondition>,
}

/// The parameter setting with which a planner honours cell weights
/// ([`PlannerSpecs::cell_costs_only_with`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CostsCondition {
    /// The parameter's key, e.g. `moves`.
    pub param: &'static str,
    /// The values with which the planner honours cell weights, in words, e.g. `4 or 8`.
    pub values: &'static str,
    /// Why other values do not, one clause, e.g. "a longer move is charged only for its
    /// two end cells".
    pub reason: &'static str,
}

impl PlannerSpecs {
    /// Why a planner with these specs is refused a weighted grid, as the clause after its
    /// name: "does not honour cell costs", or, with [`PlannerSpecs::cell_costs_only_with`],
    /// the setting with which it would.
    ///
    /// ```
    /// # use planner_api::{PathSpec, PlannerSpecs, Connectivity, MoveSet, NeighborOrder};
    /// let moves = MoveSet::new(Connectivity::Four, false, &NeighborOrder::default()).unwrap();
    /// let specs = PlannerSpecs::deterministic(PathSpec::Moves(moves));
    /// assert_eq!(specs.cell_costs_refusal(), "does not honour cell costs");
    /// let specs = specs.with_cell_costs_only_with("moves", "4 or 8", "a long move skips cells");
    /// assert_eq!(
    ///     specs.cell_costs_refusal(),
    ///     "honours cell costs only with `moves` = 4 or 8 (a long move skips cells)"
    /// );
    /// ```
    pub fn cell_costs_refusal(&self) -> String {
        match &self.cell_costs_only_with {
            Some(c) => format!(
                "honours cell costs only with `{}` = {} ({})",
                c.param, c.values, c.reason
            ),
            None => "does not honour cell costs".to_string(),
        }
    }

    /// An unseeded planner whose paths obey `path_rule`.
    pub fn deterministic(path_rule: PathSpec) -> PlannerSpecs {
        PlannerSpecs {
            seeded: false,
            path_rule,
            admissible: None,
            incremental: false,
            cell_costs: false,
            cell_costs_only_with: None,
        }
    }

    /// A seeded planner whose paths obey `path_rule`.
    pub fn seeded(path_rule: PathSpec) -> PlannerSpecs {
        PlannerSpecs {
            seeded: true,
            path_rule,
            admissible: None,
            incremental: false,
            cell_costs: false,
            cell_costs_only_with: None,
        }
    }

    /// These specs, declaring whether the heuristic is admissible (see
    /// [`PlannerSpecs::admissible`]).
    pub fn with_admissible(self, admissible: bool) -> PlannerSpecs {
        PlannerSpecs {
            admissible: Some(admissible),
            ..self
        }
    }

    /// These specs, declaring that the planner honours cell weights (see
    /// [`PlannerSpecs::cell_costs`]).
    pub fn with_cell_costs(self) -> PlannerSpecs {
        PlannerSpecs {
            cell_costs: true,
            ..self
        }
    }

    /// These specs, declaring that the planner honours cell weights only with `param` set
    /// to `values` ([`PlannerSpecs::cell_costs_only_with`]), not in this configuration.
    pub fn with_cell_costs_only_with(
        self,
        param: &'static str,
        values: &'static str,
        reason: &'static str,
    ) -> PlannerSpecs {
        PlannerSpecs {
            cell_costs: false,
            cell_costs_only_with: Some(CostsCondition {
                param,
                values,
                reason,
            }),
            ..self
        }
    }

    /// These specs, declaring the planner incremental (see [`PlannerSpecs::incremental`]).
    pub fn with_incremental(self) -> PlannerSpecs {
        PlannerSpecs {
            incremental: true,
            ..self
        }
    }
}

/// The owned form of a [`PathRule`]: which consecutive cells a planner's paths may join.
#[derive(Debug, Clone, PartialEq)]
pub enum PathSpec {
    /// Every step is one move of this set (4-connected, 8-connected with or without corner
    /// cutting, or the 16, 32, 48 directions), valid on the grid.
    Moves(MoveSet),
    /// Any-angle: waypoints joined by segments that cross no blocked cell.
    AnyAngle,
}

/// `any-angle`, or the moves: `8-connected`, with `, corners cut` when diagonals may pass
/// a blocked corner (what `gridplan planners NAME` and the Python package's `PlannerInfo`
/// say).
///
/// ```
/// use planner_api::{Connectivity, MoveSet, NeighborOrder, PathSpec};
///
/// let eight = MoveSet::new(Connectivity::Eight, false, &NeighborOrder::default()).unwrap();
/// assert_eq!(PathSpec::Moves(eight).to_string(), "8-connected");
/// assert_eq!(PathSpec::AnyAngle.to_string(), "any-angle");
/// ```
impl std::fmt::Display for PathSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PathSpec::AnyAngle => f.write_str("any-angle"),
            PathSpec::Moves(moves) if moves.corner_cutting() => {
                write!(f, "{}, corners cut", moves.connectivity())
            }
            PathSpec::Moves(moves) => write!(f, "{}", moves.connectivity()),
        }
    }
}

impl PathSpec {
    /// The rule as [`crate::Path::validate`] takes it.
    pub fn rule(&self) -> PathRule<'_> {
        match self {
            PathSpec::Moves(moves) => PathRule::Moves(moves),
            PathSpec::AnyAngle => PathRule::AnyAngle,
        }
    }
}

/// A parameter a planner cannot run with, and the key it belongs to.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{message}")]
pub struct ParamError {
    /// The parameter's key in the planner's table, e.g. `weight`; empty when the error
    /// concerns the table as a whole.
    pub key: String,
    /// What is wrong, e.g. "parameter `weight` must be a finite number >= 0, got -2".
    pub message: String,
}

impl ParamError {
    /// An error about parameter `key`.
    pub fn new(key: impl Into<String>, message: impl Into<String>) -> ParamError {
        ParamError {
            key: key.into(),
            message: message.into(),
        }
    }
}

/// A planner's configuration error that knows which parameter it is about.
///
/// Each planner crate implements it for its `ConfigError`, so the registry turns any
/// constructor error into a [`ParamError`] with the right key.
pub trait ParamKey: std::fmt::Display {
    /// The parameter the error is about.
    fn param_key(&self) -> &str;

    /// The error as a [`ParamError`].
    fn to_param_error(&self) -> ParamError {
        ParamError::new(self.param_key(), self.to_string())
    }
}

impl ParamKey for crate::error::MoveOrderError {
    fn param_key(&self) -> &str {
        use crate::error::MoveOrderError;
        match self {
            MoveOrderError::CornerCutting(_) => "corner_cutting",
            _ => "order",
        }
    }
}
