//! The GPPC 2023 dynamic track's scenarios replayed with the oracle, and incremental
//! planners carried across their patches.
//!
//! [`replay`] applies a scenario's commands in order to a map that starts all free.
//! Every query is answered by A* from scratch (planner-astar, 8 moves without corner
//! cutting, exact costs) on the map as patched so far, and its cost must equal the
//! recorded optimum (to 1e-6, the recorded values being decimals with about ten
//! significant digits) or both must say "no path". Then, for the queries selected by
//! `carry_every`, an incremental planner solves the query from scratch on that map, is
//! told the net cell changes of the next batch's patches, repairs, and must match A* from
//! scratch on the next batch's map for the same query: that is the repair measured against
//! restarting ([`CarryRecord`]).

use std::time::{Duration, Instant};

use planner_api::{Budget, CellChange, Grid, GridError, IncrementalPlanner, Problem};
use planner_maps::gppc::{GppcCommand, GppcScenario, PatchSet};

use crate::oracle::{Mismatch, MismatchKind, Oracle};

/// One query's check.
#[derive(Debug, Clone, PartialEq)]
pub struct QueryRecord {
    /// The scenario line.
    pub line: usize,
    /// The batch.
    pub batch: u32,
    /// The recorded optimum (`None`: no path).
    pub recorded: Option<f64>,
    /// A*'s exact cost.
    pub astar: Option<planner_api::Cost>,
    /// A*'s expansions.
    pub astar_expansions: u64,
    /// Whether they agree.
    pub agrees: bool,
}

/// One query carried across the next batch's patches.
#[derive(Debug, Clone, PartialEq)]
pub struct CarryRecord {
    /// The scenario line of the query.
    pub line: usize,
    /// Cells the next batch changed (net).
    pub changed_cells: usize,
    /// The incremental planner's expansions for the query from scratch.
    pub first_expansions: u64,
    /// Its expansions for the repair after the patches.
    pub repair_expansions: u64,
    /// How the repair ended.
    pub status: planner_api::Status,
    /// The planner's counters for the repair alone.
    pub counters: planner_api::Counters,
    /// The exact cost of the repair's path, when it passed its check.
    pub cost: Option<planner_api::Cost>,
    /// The repair's failed check against A* from scratch on the patched map (also in
    /// [`Replay::mismatches`]).
    pub mismatch: Option<Mismatch>,
    /// A*'s expansions from scratch on the patched map.
    pub astar_expansions: u64,
    /// Time of the repair (apply and replan).
    pub repair_time: Duration,
    /// Time of A* from scratch on the patched map (its bit-grid build excluded).
    pub astar_time: Duration,
}

/// A replay's records.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Replay {
    /// Patch commands applied.
    pub patches_applied: u64,
    /// Every query's check.
    pub queries: Vec<QueryRecord>,
    /// The carried queries.
    pub carried: Vec<CarryRecord>,
    /// Every failed check of the incremental planner (by scenario line).
    pub mismatches: Vec<Mismatch>,
    /// Why the replay did not run (its memory need over the experiment's budget): then it
    /// holds no records.
    pub refused: Option<String>,
}

/// The bytes a replay of a `width` x `height` scenario needs for its per-cell state, as
/// the planners' `Budget::check_memory` counts it: the two maps it holds (the map as
/// patched so far and the pending batch's), A*'s search state for the oracle, and as much
/// again for the carried planner. Estimated from A*'s need on a grid of at most 256 x 256
/// cells, scaled to the declared map, so that no grid of the declared size is made first.
pub fn memory_bytes(width: u32, height: u32, eight: bool) -> u64 {
    let cells = u64::from(width) * u64::from(height);
    let Ok(probe) = Grid::new(width.clamp(1, 256), height.clamp(1, 256)) else {
        return u64::MAX;
    };
    let astar = crate::oracle::exact_astar(eight).memory_bytes_for(&probe);
    let per_cell = astar as f64 / probe.len() as f64;
    let maps = 2 * std::mem::size_of::<bool>() as u64;
    (cells as f64 * (maps as f64 + 2.0 * per_cell)).ceil() as u64
}

/// A query as the replay keeps it: line, batch, start, goal, recorded cost.
type Query = (
    usize,
    u32,
    planner_api::Cell,
    planner_api::Cell,
    Option<f64>,
);

/// Whether A*'s exact cost agrees with the recorded optimum.
pub fn agrees(recorded: Option<f64>, exact: Option<planner_api::Cost>) -> bool {
    match (recorded, exact) {
        (None, None) => true,
        (Some(r), Some(c)) => (c.to_f64() - r).abs() <= 1e-6 * r.max(1.0),
        _ => false,
    }
}

/// Replays `scenario` (validated against `patches`) as the [module docs](self) say;
/// `planner` is carried across the patches for every `carry_every`-th query (0: none),
/// and only every `query_every`-th query is checked at all (1: all).
///
/// The commands are replayed in one pass holding two maps at most: a batch's queries are
/// checked once the next batch's first query comes (its map is then complete) or the
/// commands end, so memory does not grow with the number of batches. Errors only when
/// the scenario's map is larger than a grid can be (which
/// [`parse_gppc_scenario`](planner_maps::gppc::parse_gppc_scenario) refuses).
pub fn replay(
    scenario: &GppcScenario,
    patches: &PatchSet,
    planner: &mut dyn IncrementalPlanner,
    query_every: usize,
    carry_every: usize,
) -> Result<Replay, GridError> {
    replay_until(
        scenario,
        patches,
        planner,
        query_every,
        carry_every,
        &|| false,
    )
}

/// [`replay`] that checks no further query once `stop` says so (a command line's Ctrl-C):
/// the replay then ends early, with the records of the queries checked so far.
pub fn replay_until(
    scenario: &GppcScenario,
    patches: &PatchSet,
    planner: &mut dyn IncrementalPlanner,
    query_every: usize,
    carry_every: usize,
    stop: &dyn Fn() -> bool,
) -> Result<Replay, GridError> {
    let mut replayer = Replayer {
        out: Replay::default(),
        oracle: Oracle::new(true),
        planner,
        index: 0,
        query_every,
        carry_every,
        stop,
    };
    // The map as patched so far.
    let mut map = Grid::new(scenario.width, scenario.height)?;
    // The batch whose queries wait for the next batch's map: its map and queries.
    let mut pending: Option<(Grid, Vec<Query>)> = None;
    let mut querying = false;
    for command in &scenario.commands {
        match *command {
            GppcCommand::Patch { patch, x, y, .. } => {
                patches.apply(&mut map, patch, x, y);
                replayer.out.patches_applied += 1;
                querying = false;
            }
            GppcCommand::Query {
                batch,
                start,
                goal,
                cost,
                line,
            } => {
                if !querying {
                    if stop() {
                        return Ok(replayer.out);
                    }
                    // A new batch: `map` is its map, the one the pending batch's queries
                    // are carried to.
                    if let Some((grid, queries)) = pending.take() {
                        replayer.batch(&grid, &queries, Some(&map));
                    }
                    pending = Some((map.clone(), Vec::new()));
                    querying = true;
                }
                if let Some((_, queries)) = pending.as_mut() {
                    queries.push((line, batch, start, goal, cost));
                }
            }
        }
    }
    if let Some((grid, queries)) = pending {
        replayer.batch(&grid, &queries, None);
    }
    Ok(replayer.out)
}

/// A replay's state between batches.
struct Replayer<'p> {
    out: Replay,
    oracle: Oracle,
    planner: &'p mut dyn IncrementalPlanner,
    /// Queries seen so far, over all batches.
    index: usize,
    query_every: usize,
    carry_every: usize,
    /// Ends the replay before the next query when it says so.
    stop: &'p dyn Fn() -> bool,
}

impl Replayer<'_> {
    /// Checks the `queries` of one batch, asked on `grid`; those selected for carrying are
    /// carried to `next`, the next batch's map (none for the last batch).
    fn batch(&mut self, grid: &Grid, queries: &[Query], next: Option<&Grid>) {
        let (query_every, carry_every) = (self.query_every, self.carry_every);
        let next = next.map(|next| {
            let changes: Vec<CellChange> = grid
                .free_cells()
                .iter()
                .zip(next.free_cells())
                .enumerate()
                .filter(|(_, (a, b))| a != b)
                .map(|(i, (_, &free))| CellChange {
                    cell: grid.cell(i),
                    free,
                    weight: None,
                })
                .collect();
            (next, changes)
        });
        let Replayer {
            out,
            oracle,
            planner,
            index,
            stop,
            ..
        } = self;
        for &(line, batch, start, goal, recorded) in queries {
            if stop() {
                return;
            }
            *index += 1;
            if query_every > 1 && *index % query_every != 0 {
                continue;
            }
            let astar = oracle.optimum(grid, start, goal);
            out.queries.push(QueryRecord {
                line,
                batch,
                recorded,
                astar,
                astar_expansions: oracle.last_expansions(),
                agrees: agrees(recorded, astar),
            });
            let Some((next, changes)) = &next else {
                continue;
            };
            if carry_every == 0 || *index % carry_every != 0 {
                continue;
            }
            let Ok(problem) = Problem::new(grid, start, goal) else {
                continue;
            };
            let fail = |kind| Mismatch {
                step: line as u64,
                start,
                kind,
            };
            planner.reset(&problem);
            let first = planner.replan(&Budget::unlimited());
            if let Err(mut m) = oracle.check(grid, start, goal, &first, line as u64) {
                m.step = line as u64;
                out.mismatches.push(m);
                continue;
            }
            let started = Instant::now();
            if let Err(e) = planner.apply(changes) {
                out.mismatches
                    .push(fail(MismatchKind::Rejected(e.to_string())));
                continue;
            }
            let repair = planner.replan(&Budget::unlimited());
            let repair_time = started.elapsed();
            // A* from scratch on the patched map, timed without its bit-grid build.
            oracle.prepare(next);
            let astar_started = Instant::now();
            let _ = oracle.optimum(next, start, goal);
            let astar_time = astar_started.elapsed();
            let astar_expansions = oracle.last_expansions();
            let (cost, mismatch) = match oracle.check(next, start, goal, &repair, line as u64) {
                Ok(cost) => (cost, None),
                Err(m) => {
                    out.mismatches.push(m.clone());
                    (None, Some(m))
                }
            };
            out.carried.push(CarryRecord {
                line,
                changed_cells: changes.len(),
                first_expansions: first.counters.get("n_expanded").unwrap_or(0),
                repair_expansions: repair.counters.get("n_expanded").unwrap_or(0),
                status: repair.status,
                counters: repair.counters.clone(),
                cost,
                mismatch,
                astar_expansions,
                repair_time,
                astar_time,
            });
        }
    }
}
