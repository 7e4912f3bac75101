//! The exact oracle: A* from scratch on the planner's current map.
//!
//! planner-astar with the same moves (4, or 8 without corner cutting), the consistent
//! heuristic (Manhattan or octile, times the smallest weight on a weighted map) and exact
//! [`Cost`]s finds an optimal path; its cost, summed exactly over its moves
//! ([`Grid::path_cost`]: their lengths, under the map's weights when it has them), is the
//! truth every replan is held to.

use std::fmt;

use planner_api::{
    Budget, Cell, Connectivity, Cost, Grid, MoveSet, Outcome, PathRule, Planner, Problem, Status,
};
use planner_astar::{AStar, Config, Heuristic};

/// What went wrong in a replan.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MismatchKind {
    /// The path's exact cost differs from A*'s (`None`: no path).
    Cost {
        /// A*'s cost.
        expected: Option<Cost>,
        /// The planner's.
        got: Option<Cost>,
    },
    /// The path is not valid on the current map (a blocked cell, an illegal move, or not
    /// from the start to the goal).
    InvalidPath(String),
    /// The planner ran out of budget, so the replan has no answer to check.
    Unfinished,
    /// The planner refused a change or a move the driver made.
    Rejected(String),
}

/// A failed check, with the step it happened at.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Mismatch {
    /// The step (or event) of the replan.
    pub step: u64,
    /// The start the replan planned from.
    pub start: Cell,
    /// What went wrong.
    pub kind: MismatchKind,
}

impl fmt::Display for Mismatch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            MismatchKind::Cost { expected, got } => write!(
                f,
                "step {} from {}: cost {:?} but A* from scratch finds {:?}",
                self.step,
                self.start,
                got.map(Cost::to_f64),
                expected.map(Cost::to_f64)
            ),
            MismatchKind::InvalidPath(why) => {
                write!(
                    f,
                    "step {} from {}: invalid path: {why}",
                    self.step, self.start
                )
            }
            MismatchKind::Rejected(why) => {
                write!(
                    f,
                    "step {} from {}: change rejected: {why}",
                    self.step, self.start
                )
            }
            MismatchKind::Unfinished => {
                write!(
                    f,
                    "step {} from {}: the replan did not finish",
                    self.step, self.start
                )
            }
        }
    }
}

/// planner-astar with 8 moves without corner cutting (`eight`) or 4, the consistent
/// heuristic of the moves (octile or Manhattan), exact costs and the default ties: the
/// oracle's search and the baseline's ([`crate::restart`]).
pub(crate) fn exact_astar(eight: bool) -> AStar {
    let config = Config {
        moves: if eight {
            Connectivity::Eight
        } else {
            Connectivity::Four
        },
        heuristic: if eight {
            Heuristic::Octile
        } else {
            Heuristic::Manhattan
        },
        ..Config::default()
    };
    // The configuration is valid by construction (4 or 8 moves, weight 1).
    match AStar::new(config) {
        Ok(astar) => astar,
        Err(e) => unreachable!("the exact A* configuration is valid: {e}"),
    }
}

/// The oracle for one move set.
#[derive(Debug, Clone)]
pub struct Oracle {
    astar: AStar,
    moves: MoveSet,
    last_expansions: u64,
}

impl Oracle {
    /// An oracle for 8 moves without corner cutting (`eight`) or 4 moves.
    pub fn new(eight: bool) -> Oracle {
        let astar = exact_astar(eight);
        let moves = astar.move_set().clone();
        Oracle {
            astar,
            moves,
            last_expansions: 0,
        }
    }

    /// The move set paths are checked against.
    pub fn moves(&self) -> &MoveSet {
        &self.moves
    }

    /// The optimal cost from `start` to `goal` on `grid` (`None`: no path, including a
    /// blocked start or goal).
    pub fn optimum(&mut self, grid: &Grid, start: Cell, goal: Cell) -> Option<Cost> {
        self.last_expansions = 0;
        let problem = Problem::new(grid, start, goal).ok()?;
        let outcome = self.astar.plan(&problem, &Budget::unlimited());
        self.last_expansions = outcome.counters.get("n_expanded").unwrap_or(0);
        outcome
            .path
            .as_ref()
            .map(|path| grid.path_cost(path.cells()))
    }

    /// A*'s expansions in the last [`Oracle::optimum`] or [`Oracle::check`]: what A* from
    /// scratch spends on that replan (a check runs A* even when the replan fails it
    /// first, so this is always a measurement; 0 when the start or goal is blocked, which
    /// A* answers without a search).
    pub fn last_expansions(&self) -> u64 {
        self.last_expansions
    }

    /// Builds A*'s per-grid tables for `grid` ahead of a timed [`Oracle::optimum`].
    pub fn prepare(&mut self, grid: &Grid) {
        self.astar.prepare(grid);
    }

    /// Checks a replan's `outcome` from `start` to `goal` on `grid`; returns the exact cost
    /// of its path.
    pub fn check(
        &mut self,
        grid: &Grid,
        start: Cell,
        goal: Cell,
        outcome: &Outcome,
        step: u64,
    ) -> Result<Option<Cost>, Mismatch> {
        // A* runs first, so that the replan's record has A*'s expansions whether or not
        // the replan passes.
        let expected = self.optimum(grid, start, goal);
        let fail = |kind| Mismatch { step, start, kind };
        if outcome.status == Status::BudgetExhausted {
            return Err(fail(MismatchKind::Unfinished));
        }
        let got = match &outcome.path {
            Some(path) => {
                if path.start() != Some(start) || path.goal() != Some(goal) {
                    return Err(fail(MismatchKind::InvalidPath(format!(
                        "runs from {:?} to {:?}",
                        path.start(),
                        path.goal()
                    ))));
                }
                if let Err(e) = path.validate(grid, PathRule::Moves(&self.moves)) {
                    return Err(fail(MismatchKind::InvalidPath(e.to_string())));
                }
                Some(grid.path_cost(path.cells()))
            }
            None => None,
        };
        if got == expected {
            Ok(got)
        } else {
            Err(fail(MismatchKind::Cost { expected, got }))
        }
    }
}
