//! The compared planners by name: `dstar_lite`, `lpastar` (restarted at the agent when it
//! moves), `astar` and `astar_backward` (from scratch at every replan).

use planner_api::IncrementalPlanner;
use planner_dstar_lite::DStarLite;
use planner_lpastar::{Config, LpaStar};
use thiserror::Error;

use crate::restart::Restart;

/// The names [`by_name`] knows, in the order reports list them.
pub const NAMES: [&str; 4] = ["dstar_lite", "lpastar", "astar", "astar_backward"];

/// A planner name [`by_name`] does not know.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown replanning planner `{0}` (known: dstar_lite, lpastar, astar, astar_backward)")]
pub struct UnknownPlanner(pub String);

/// The planner called `name`, with 8 moves without corner cutting (`eight`) or 4.
pub fn by_name(name: &str, eight: bool) -> Result<Box<dyn IncrementalPlanner>, UnknownPlanner> {
    let config = Config {
        moves: if eight { 8 } else { 4 },
    };
    match name {
        "dstar_lite" => Ok(Box::new(valid(DStarLite::new(config)))),
        "lpastar" => Ok(Box::new(valid(LpaStar::new(config)))),
        "astar" => Ok(Box::new(Restart::new(eight, false))),
        "astar_backward" => Ok(Box::new(Restart::new(eight, true))),
        other => Err(UnknownPlanner(other.to_string())),
    }
}

/// A planner built from a configuration valid by construction (4 or 8 moves).
fn valid<T>(built: Result<T, planner_lpastar::ConfigError>) -> T {
    match built {
        Ok(planner) => planner,
        Err(e) => unreachable!("4 and 8 moves are valid: {e}"),
    }
}
