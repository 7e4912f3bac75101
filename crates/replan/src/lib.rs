//! Replanning experiments: incremental planners driven through map changes, every replan
//! checked exactly against A* from scratch.
//!
//! - [`oracle`]: after every replan, the planner's path must be valid on the planner's
//!   current map, join the current start to the goal, and cost exactly (integer
//!   [`planner_api::Cost`] equality) what planner-astar finds from scratch on that map; or
//!   both must find no path. A disagreement is a [`Mismatch`] recorded with its step,
//!   never a silent number.
//! - [`restart`]: A* from scratch (forward or backward) behind the
//!   [`IncrementalPlanner`](planner_api::IncrementalPlanner) interface, the baseline.
//! - [`navigate`]: an agent that knows nothing at the start (the free-space assumption of
//!   the D* Lite paper), senses the cells within a radius each step, replans when it sees
//!   its path blocked, and moves one cell.
//! - [`toggles`]: seeded scripted changes: k random cells toggled near the agent or on its
//!   current path between replans.
//! - [`gppc`]: the GPPC 2023 dynamic track's scenarios replayed query by query, and
//!   incremental planners carried across their patches.
//! - [`experiment`]: the `navigate` and `dynamic` experiment kinds: a TOML config, its
//!   runs in parallel and a results directory (CSV, JSON Lines, summary, chart).
//! - [`planners`]: the compared planners by name.
//! - [`args`]: the command-line options of the examples and the bench.
//! - [`report`]: medians, percentiles and the SVG chart of expansions per replan against
//!   A* from scratch.
//!
//! Every run returns plain records (per run and per replan: expansions, counters, times),
//! so a test, an example or a runner can sum them or draw their distribution. A driver's
//! `run_recorded` hands them to a [`Recorder`] as they happen instead, so that a long run
//! need not hold them, and ends early when the recorder says so.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod args;
pub mod experiment;
pub mod gppc;
pub mod navigate;
pub mod oracle;
pub mod planners;
pub mod report;
pub mod restart;
pub mod toggles;

pub use oracle::{Mismatch, MismatchKind, Oracle};

use std::time::Duration;

use planner_api::{Cost, Counters, Status};

/// What one replan did.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplanRecord {
    /// The agent's step count (or the event number) at which the replan ran.
    pub step: u64,
    /// How the replan ended.
    pub status: Status,
    /// The planner's counters for this replan alone.
    pub counters: Counters,
    /// Its vertex expansions (`n_expanded`).
    pub expansions: u64,
    /// The exact cost of the path it returned.
    pub cost: Option<Cost>,
    /// A*'s expansions from scratch on the same map and start (the oracle's search), when
    /// an oracle checked the replan.
    pub oracle_expansions: Option<u64>,
    /// Wall-clock time of telling the planner the changes and the move (apply, move_start).
    pub update_time: Duration,
    /// Wall-clock time of the replan itself.
    pub replan_time: Duration,
}

impl ReplanRecord {
    /// Update and replan time together: the planning time of this replan.
    pub fn planning_time(&self) -> Duration {
        self.update_time + self.replan_time
    }
}

/// Takes a run's records as a driver makes them ([`navigate::run_recorded`],
/// [`toggles::run_recorded`]), and may end the run early.
pub trait Recorder {
    /// One replan's record, and its failed check when it failed one.
    fn replan(&mut self, record: ReplanRecord, mismatch: Option<Mismatch>);

    /// A failed check that belongs to no replan: a change or move the planner refused, or
    /// a navigation step checked without a replan.
    fn mismatch(&mut self, mismatch: Mismatch);

    /// Whether the run should end now (a raised stop flag, or records that could not be
    /// written): the driver asks before every step or event. Never, by default.
    fn stopped(&self) -> bool {
        false
    }
}

/// A [`Recorder`] that keeps every record, in order: what the drivers' `run` returns.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Records {
    /// The replans.
    pub replans: Vec<ReplanRecord>,
    /// Every failed check, of a replan or not.
    pub mismatches: Vec<Mismatch>,
}

impl Recorder for Records {
    fn replan(&mut self, record: ReplanRecord, mismatch: Option<Mismatch>) {
        self.replans.push(record);
        self.mismatches.extend(mismatch);
    }

    fn mismatch(&mut self, mismatch: Mismatch) {
        self.mismatches.push(mismatch);
    }
}
