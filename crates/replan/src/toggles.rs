//! Seeded scripted changes: between replans the agent drives a few cells along its path,
//! then `k` random cells are toggled (blocked <-> free), each on the agent's remaining
//! path or within a square of the given radius around it, with equal chance.
//!
//! The agent's own cell is never toggled; the goal may be, so "no path" is a normal
//! outcome that later toggles can undo. Every replan is checked by the [`Oracle`] on the
//! driver's own copy of the map, and the agent drives only a path that passed: after a
//! failed check it stays where it is until a later replan passes.
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, Problem};
//! use planner_replan::{planners, toggles, Oracle};
//!
//! let grid = Grid::from_ascii("
//!     ......
//!     .##...
//!     ......
//!     ...#..
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(5, 3)).unwrap();
//! let mut dstar = planners::by_name("dstar_lite", true).unwrap();
//! let config = toggles::ToggleConfig { events: 20, k: 3, radius: 2, drive: 1, seed: 1 };
//! let run = toggles::run(dstar.as_mut(), &mut Oracle::new(true), &problem, &config, &Budget::unlimited());
//! assert_eq!(run.replans.len(), 21);
//! assert!(run.mismatches.is_empty());
//! ```

use std::time::Instant;

use planner_api::{Budget, Cell, CellChange, IncrementalPlanner, Problem};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use crate::oracle::{Mismatch, MismatchKind, Oracle};
use crate::{Recorder, Records, ReplanRecord};

/// The script's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ToggleConfig {
    /// Change events after the first plan (one replan each).
    pub events: u32,
    /// Cells toggled per event.
    pub k: u32,
    /// Half-width of the square around the agent that off-path toggles fall in.
    pub radius: u32,
    /// Cells the agent drives along its path before each event.
    pub drive: u32,
    /// The seed of the script (ChaCha8).
    pub seed: u64,
}

/// A scripted run's records.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ToggleRun {
    /// The first plan and one replan per event.
    pub replans: Vec<ReplanRecord>,
    /// Every failed check.
    pub mismatches: Vec<Mismatch>,
    /// Cells toggled in all.
    pub toggled: u64,
    /// Cells the agent drove in all (a move is one cell).
    pub steps: u64,
}

/// How a recorded run ended ([`run_recorded`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ToggleEnd {
    /// Cells toggled in all.
    pub toggled: u64,
    /// Cells the agent drove in all: `drive` before each event, fewer where its path
    /// ended sooner, none while it had no path.
    pub steps: u64,
    /// Whether the recorder ended the run before its last event.
    pub stopped: bool,
}

/// Runs the script on `planner` (see the [module docs](self)).
pub fn run(
    planner: &mut dyn IncrementalPlanner,
    oracle: &mut Oracle,
    problem: &Problem<'_>,
    config: &ToggleConfig,
    budget: &Budget,
) -> ToggleRun {
    let mut records = Records::default();
    let end = run_recorded(planner, oracle, problem, config, budget, &mut records);
    ToggleRun {
        replans: records.replans,
        mismatches: records.mismatches,
        toggled: end.toggled,
        steps: end.steps,
    }
}

/// [`run`] that hands each replan's record and each failed check to `recorder` as they
/// happen, holding none of them, and ends before the next event once
/// [`Recorder::stopped`] says so.
pub fn run_recorded(
    planner: &mut dyn IncrementalPlanner,
    oracle: &mut Oracle,
    problem: &Problem<'_>,
    config: &ToggleConfig,
    budget: &Budget,
    recorder: &mut dyn Recorder,
) -> ToggleEnd {
    let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
    let mut map = problem.grid().clone();
    let goal = problem.goal();
    let mut agent = problem.start();
    let mut end = ToggleEnd::default();
    let started = Instant::now();
    planner.reset_within(problem, budget);
    let update_time = started.elapsed();
    let mut path = replan_checked(
        planner,
        oracle,
        &map,
        agent,
        goal,
        0,
        update_time,
        budget,
        recorder,
    );
    for event in 1..=u64::from(config.events) {
        if recorder.stopped() {
            end.stopped = true;
            break;
        }
        let remaining: &[Cell] = match &path {
            Some(cells) => {
                let at = (config.drive as usize).min(cells.len() - 1);
                agent = cells[at];
                end.steps += at as u64;
                &cells[at..]
            }
            None => &[],
        };
        // Reserved for at most the map's cells: `k` is the config's word, the memory the
        // work's (a change is pushed per draw).
        let mut changes = Vec::with_capacity((config.k as usize).min(map.len()));
        for _ in 0..config.k {
            let cell = if remaining.len() > 1 && rng.gen_bool(0.5) {
                remaining[rng.gen_range(1..remaining.len())]
            } else {
                let r = i64::from(config.radius);
                let x = (i64::from(agent.x) + rng.gen_range(-r..=r))
                    .clamp(0, i64::from(map.width()) - 1);
                let y = (i64::from(agent.y) + rng.gen_range(-r..=r))
                    .clamp(0, i64::from(map.height()) - 1);
                Cell::new(x as u32, y as u32)
            };
            if cell == agent {
                continue;
            }
            let free = !map.is_free(cell);
            map.set_free(cell, free);
            changes.push(CellChange {
                cell,
                free,
                weight: None,
            });
        }
        end.toggled += changes.len() as u64;
        let started = Instant::now();
        let told = planner
            .move_start(agent)
            .and_then(|()| planner.apply(&changes));
        let update_time = started.elapsed();
        if let Err(e) = told {
            recorder.mismatch(Mismatch {
                step: event,
                start: agent,
                kind: MismatchKind::Rejected(e.to_string()),
            });
            break;
        }
        path = replan_checked(
            planner,
            oracle,
            &map,
            agent,
            goal,
            event,
            update_time,
            budget,
            recorder,
        );
    }
    end
}

/// One replan, timed and checked; its path's cells when found.
#[allow(clippy::too_many_arguments)]
fn replan_checked(
    planner: &mut dyn IncrementalPlanner,
    oracle: &mut Oracle,
    map: &planner_api::Grid,
    agent: Cell,
    goal: Cell,
    step: u64,
    update_time: std::time::Duration,
    budget: &Budget,
    recorder: &mut dyn Recorder,
) -> Option<Vec<Cell>> {
    let started = Instant::now();
    let outcome = planner.replan(budget);
    let replan_time = started.elapsed();
    let checked = oracle.check(map, agent, goal, &outcome, step);
    let oracle_expansions = Some(oracle.last_expansions());
    let (cost, mismatch) = match checked {
        Ok(cost) => (cost, None),
        Err(mismatch) => (None, Some(mismatch)),
    };
    let record = ReplanRecord {
        step,
        status: outcome.status,
        expansions: outcome.counters.get("n_expanded").unwrap_or(0),
        counters: outcome.counters.clone(),
        cost,
        oracle_expansions,
        update_time,
        replan_time,
    };
    let failed = mismatch.is_some();
    recorder.replan(record, mismatch);
    // The agent drives only a path that passed its check: one through a blocked cell, or
    // from elsewhere, is recorded as the failed check and not driven.
    outcome
        .path
        .filter(|_| !failed)
        .map(|p| p.into_cells())
        .filter(|cells| cells.first() == Some(&agent))
}
