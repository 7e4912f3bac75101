//! The compared planners by name: the registry's incremental planners (planner-registry's
//! entries built with `Factory::incremental`: `lpastar`, restarted at the agent when it
//! moves, and `dstar_lite`), and this crate's baselines `astar` and `astar_backward` (A*
//! from scratch at every replan, [`Restart`]).
//!
//! The registry is the one list of planners: a new incremental planner joins the
//! experiments by its registry entry alone.
//!
//! ```
//! use planner_replan::planners;
//! let names = planners::names();
//! assert!(names.contains(&"dstar_lite") && names.contains(&"lpastar"));
//! assert_eq!(&names[names.len() - 2..], ["astar", "astar_backward"]);
//! assert!(planners::by_name("bfs", true).is_err()); // registered, but not incremental
//! ```

use std::sync::OnceLock;

use planner_api::IncrementalPlanner;
use thiserror::Error;

use crate::restart::Restart;

/// The baselines this crate adds to the registry's incremental planners.
const BASELINES: [&str; 2] = ["astar", "astar_backward"];

/// The names [`by_name`] knows, in the order reports list them: the registry's
/// incremental planners in registry order, then the baselines.
pub fn names() -> Vec<&'static str> {
    static NAMES: OnceLock<Vec<&'static str>> = OnceLock::new();
    NAMES
        .get_or_init(|| {
            let mut names = planner_registry::incremental_names();
            names.extend(BASELINES);
            names
        })
        .clone()
}

/// A planner name [`by_name`] does not know.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("unknown replanning planner `{name}` (known: {known})")]
pub struct UnknownPlanner {
    /// The name asked for.
    pub name: String,
    /// The known names, comma-separated.
    pub known: String,
}

/// The planner called `name`, with 8 moves without corner cutting (`eight`) or 4.
pub fn by_name(name: &str, eight: bool) -> Result<Box<dyn IncrementalPlanner>, UnknownPlanner> {
    let unknown = || UnknownPlanner {
        name: name.to_string(),
        known: names().join(", "),
    };
    match name {
        "astar" => return Ok(Box::new(Restart::new(eight, false))),
        "astar_backward" => return Ok(Box::new(Restart::new(eight, true))),
        _ => {}
    }
    let mut params = toml::Table::new();
    params.insert(
        "moves".into(),
        toml::Value::Integer(if eight { 8 } else { 4 }),
    );
    match planner_registry::build_incremental(name, &params) {
        Some(Ok(planner)) => Ok(planner),
        // Every incremental planner takes `moves = 4 or 8`: an error here is a planner
        // that does not, which the experiments cannot compare.
        Some(Err(_)) | None => Err(unknown()),
    }
}
