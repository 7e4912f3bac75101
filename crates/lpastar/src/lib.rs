//! Lifelong Planning A* (LPA*) on 4- and 8-connected grids, with exact costs.
//!
//! Koenig, Likhachev and Furcy, "Lifelong Planning A*", Artificial Intelligence 155
//! (2004) 93-146, <https://doi.org/10.1016/j.artint.2003.12.001>: the pseudocode of its
//! Fig. 3 (CalculateKey, UpdateVertex, ComputeShortestPath) with the start as the root of
//! the search. LPA* keeps its g- and rhs-values between searches: after cells change
//! ([`IncrementalPlanner::apply`]) only the vertices whose distance from the start changed,
//! and those the heuristic cannot rule out, are expanded again. The search is the
//! [`engine`] shared with D* Lite (planner-dstar_lite), whose docs give the rules, the
//! tie-breaking and the counters. A moved start re-roots the search, so LPA* starts over
//! ([`IncrementalPlanner::move_start`]); D* Lite is the variant that keeps its search.
//!
//! Moves follow the Moving AI rule: 4 moves of cost 1, or 8 with diagonals of cost
//! `sqrt 2` ([`Cost::SQRT_2`]) only when both cells beside the diagonal are free (no
//! corner cutting). The heuristic is Manhattan (4 moves) or octile (8), both consistent.
//! Costs are exact [`planner_api::Cost`] integers, so the path cost equals A*'s from
//! scratch bit for bit (tested on random grids and change sequences in planner-replan).
//!
//! On a weighted map ([`planner_api::weights`], a costmap) a move costs its length under the
//! map's rule (the mean of the two cells' weights, or the weight of the cell entered) and
//! the heuristic is multiplied by the map's smallest weight when the search began, so it
//! stays consistent. A change can carry a new weight ([`CellChange::with_weight`]): the
//! edges of that cell change cost and the search is repaired as for a blocked or freed
//! cell. A weight below the one the heuristic was multiplied by would make it overestimate,
//! so that change ends the search and the next replan starts over (its counters say so).
//! planner-replan's `weighted_maps_with_weight_changes_every_replan_exact` checks every
//! replan of 4,000 random weighted grids against A* from scratch.
//!
//! ```
//! use planner_api::{Budget, Cell, CellChange, CostRule, Grid, IncrementalPlanner, Problem};
//! use planner_lpastar::{Config, LpaStar};
//!
//! let grid = Grid::from_ascii("
//!     .....
//!     .....
//! ").unwrap().with_weights(vec![1; 10], CostRule::Mean).unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(4, 0)).unwrap();
//! let mut lpa = LpaStar::new(Config { moves: 4 }).unwrap();
//! lpa.reset(&problem);
//! let first = lpa.replan(&Budget::unlimited());
//! assert_eq!(first.counters.get("path_cost_units"), Some(4 << 32));
//! // The top row's middle cell turns costly: through it, 1 + 5 + 5 + 1 (the mean rule);
//! // around it, six moves of weight 1.
//! lpa.apply(&[CellChange::freed(Cell::new(2, 0)).with_weight(9)]).unwrap();
//! let repaired = lpa.replan(&Budget::unlimited());
//! assert_eq!(repaired.counters.get("path_cost_units"), Some(6 << 32));
//! assert!(!repaired.path.unwrap().cells().contains(&Cell::new(2, 0)));
//! ```
//!
//! ```
//! use planner_api::{Budget, Cell, CellChange, Grid, IncrementalPlanner, Problem, Status};
//! use planner_lpastar::{Config, LpaStar};
//!
//! let grid = Grid::from_ascii("
//!     .....
//!     .....
//!     .....
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(4, 1)).unwrap();
//! let mut lpa = LpaStar::new(Config { moves: 4 }).unwrap();
//! lpa.reset(&problem);
//! let first = lpa.replan(&Budget::unlimited());
//! assert_eq!(first.path.unwrap().len(), 5);
//! // Block the middle of the straight path: the repair finds the 6-step detour.
//! lpa.apply(&[CellChange::blocked(Cell::new(2, 1))]).unwrap();
//! let repaired = lpa.replan(&Budget::unlimited());
//! assert_eq!(repaired.status, Status::Found);
//! assert_eq!(repaired.path.unwrap().len(), 7);
//! // The repair's counters are its own: 6 + 1 axis moves in exact units.
//! assert_eq!(repaired.counters.get("path_cost_units"), Some(6 << 32));
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod engine;

use engine::{Computed, Engine};
use planner_api::{
    Budget, Cell, CellChange, ChangeError, Connectivity, Cost, Grid, IncrementalPlanner, MoveSet,
    Outcome, PathSpec, Planner, PlannerSpecs, Problem,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name of this planner.
pub const NAME: &str = "lpastar";

/// LPA*'s parameters (shared by D* Lite).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4, or 8 without corner cutting (the Moving AI rule). Default 8.
    #[schemars(extend("enum" = [4, 8]))]
    pub moves: u32,
}

impl Default for Config {
    fn default() -> Config {
        Config { moves: 8 }
    }
}

/// A parameter the incremental planners cannot run with.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConfigError {
    /// `moves` is not 4 or 8.
    #[error("parameter `moves` must be 4 or 8, got {0}")]
    Moves(u32),
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        "moves"
    }
}

impl Config {
    /// Whether the configuration is 8-connected, after validating it.
    pub fn eight(&self) -> Result<bool, ConfigError> {
        match self.moves {
            4 => Ok(false),
            8 => Ok(true),
            other => Err(ConfigError::Moves(other)),
        }
    }

    /// The move set paths obey: 4, or 8 without corner cutting.
    pub fn move_set(&self) -> MoveSet {
        MoveSet::standard(if self.moves == 8 {
            Connectivity::Eight
        } else {
            Connectivity::Four
        })
    }
}

/// Checks `changes` against `grid`: every cell in the map, and a new weight only on a
/// weighted map and never 0. Nothing is applied when one fails.
pub fn checked_changes<'c>(
    grid: Option<&Grid>,
    changes: &'c [CellChange],
) -> Result<&'c [CellChange], ChangeError> {
    let grid = grid.ok_or(ChangeError::NotStarted)?;
    for c in changes {
        if !grid.contains(c.cell) {
            return Err(ChangeError::OutOfBounds {
                cell: c.cell,
                width: grid.width(),
                height: grid.height(),
            });
        }
        match c.weight {
            Some(0) => return Err(ChangeError::ZeroWeight { cell: c.cell }),
            Some(_) if !grid.is_weighted() => return Err(ChangeError::Unweighted { cell: c.cell }),
            _ => {}
        }
    }
    Ok(changes)
}

/// Checks that `cell` can be the agent's new cell on `grid`.
pub fn checked_start(grid: Option<&Grid>, cell: Cell) -> Result<(), ChangeError> {
    let grid = grid.ok_or(ChangeError::NotStarted)?;
    if grid.contains(cell) && grid.is_free(cell) {
        Ok(())
    } else {
        Err(ChangeError::BadStart { cell })
    }
}

/// The outcome of a finished [`Engine::compute`]: the traced path (`root_first` when the
/// root is the start) checked against `g(target)`, with the repair's counters.
pub fn outcome(engine: &mut Engine, computed: Computed, root_first: bool) -> Outcome {
    let stats = engine.take_stats();
    let mut counters = stats.report();
    match computed {
        Computed::OverMemory(shortfall) => Outcome::over_memory(shortfall, counters),
        Computed::Exhausted => Outcome::budget_exhausted(None, counters),
        Computed::Done if engine.target_distance() == Some(Cost::from_units(engine::SATURATED)) => {
            Outcome::over_cost_range(counters)
        }
        Computed::Done => match (engine.target_distance(), engine.path(root_first)) {
            (Some(distance), Some(path)) => {
                counters.push("path_cost_units", distance.units());
                Outcome::found(path, counters)
            }
            _ => Outcome::no_path(counters),
        },
    }
}

/// Which end of the problem the [`engine`]'s search is rooted at: the one difference
/// between LPA* ([`AtStart`]) and D* Lite (planner-dstar_lite's `AtGoal`).
pub trait Rooting: Clone + std::fmt::Debug + Send + Sync + 'static {
    /// The planner's registry name.
    const NAME: &'static str;
    /// Whether the search is rooted at the goal, towards the agent (D* Lite: a moved
    /// agent keeps the search, `km` grows), rather than at the start (LPA*: a moved start
    /// re-roots the search, which starts over).
    const AT_GOAL: bool;
}

/// LPA*'s rooting: the search grows from the start to the goal.
#[derive(Debug, Clone, Copy, Default)]
pub struct AtStart;

impl Rooting for AtStart {
    const NAME: &'static str = NAME;
    const AT_GOAL: bool = false;
}

/// An incremental planner over the [`engine`], LPA* or D* Lite by its [`Rooting`]. Build
/// with [`Incremental::new`].
#[derive(Debug, Clone)]
pub struct Incremental<R: Rooting> {
    config: Config,
    engine: Engine,
    rooting: std::marker::PhantomData<R>,
}

/// The LPA* planner. Build with [`LpaStar::new`].
pub type LpaStar = Incremental<AtStart>;

impl<R: Rooting> Incremental<R> {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<Incremental<R>, ConfigError> {
        let eight = config.eight()?;
        Ok(Incremental {
            config,
            engine: Engine::new(eight).with_paths_to_root(R::AT_GOAL),
            rooting: std::marker::PhantomData,
        })
    }

    /// The engine, for inspection (g-values, km).
    pub fn engine(&self) -> &Engine {
        &self.engine
    }
}

/// The exact cost of a found outcome's path, from its `path_cost_units` counter.
pub fn outcome_cost(outcome: &Outcome) -> Option<Cost> {
    outcome
        .counters
        .get("path_cost_units")
        .map(Cost::from_units)
}

impl<R: Rooting> IncrementalPlanner for Incremental<R> {
    fn name(&self) -> &str {
        R::NAME
    }

    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.config.move_set()))
            .with_admissible(true)
            .with_incremental()
            .with_cell_costs()
    }

    /// Roots the search at the start (LPA*) or the goal (D* Lite).
    fn reset(&mut self, problem: &Problem<'_>) {
        let (root, target) = if R::AT_GOAL {
            (problem.goal(), problem.start())
        } else {
            (problem.start(), problem.goal())
        };
        self.engine.reset(problem.grid(), root, target);
    }

    fn grid(&self) -> Option<&Grid> {
        self.engine.grid()
    }

    fn start(&self) -> Option<Cell> {
        if R::AT_GOAL {
            self.engine.target()
        } else {
            self.engine.root()
        }
    }

    /// LPA* re-roots the search at `cell`, so the next replan starts over; D* Lite keeps
    /// its search and `km` grows by the heuristic between the old and new start.
    fn move_start(&mut self, cell: Cell) -> Result<(), ChangeError> {
        checked_start(self.engine.grid(), cell)?;
        if R::AT_GOAL {
            self.engine.move_target(cell);
        } else {
            self.engine.move_root(cell);
        }
        Ok(())
    }

    fn apply(&mut self, changes: &[CellChange]) -> Result<(), ChangeError> {
        let changes = checked_changes(self.engine.grid(), changes)?;
        self.engine.apply(changes);
        Ok(())
    }

    fn replan(&mut self, budget: &Budget) -> Outcome {
        let computed = self.engine.compute(budget);
        outcome(&mut self.engine, computed, !R::AT_GOAL)
    }
}

impl<R: Rooting> Planner for Incremental<R> {
    fn name(&self) -> &str {
        R::NAME
    }

    /// Unseeded and admissible; paths are moves of the configured set; incremental.
    fn specs(&self) -> PlannerSpecs {
        IncrementalPlanner::specs(self)
    }

    /// A first search from scratch: A* (LPA*, forward; D* Lite, backward) with the
    /// incremental planner's counters.
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        IncrementalPlanner::reset(self, problem);
        IncrementalPlanner::replan(self, budget)
    }
}
