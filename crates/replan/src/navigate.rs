//! Navigation in unknown terrain, as in the D* Lite paper's experiments.
//!
//! The agent knows the size of the map and nothing else: it assumes every cell free
//! (the free-space assumption). Each step it senses the true state of every cell within
//! `radius` of its cell (a square: `max(|dx|, |dy|) <= radius`, so radius 1 is the eight
//! neighbours), and before its first plan it senses from the start. It plans on what it
//! knows, follows its path one cell per step, and replans when a sensed cell lies on its
//! remaining path or makes one of its diagonal moves cut a corner; it then tells the
//! planner where it stands ([`IncrementalPlanner::move_start`]) and every cell it has
//! seen blocked since the last replan ([`IncrementalPlanner::apply`]).
//!
//! Whatever the radius, the agent also looks at the cells of its next move before making
//! it: the cell it enters and, for a diagonal move, the two cells beside it that the move
//! must not cut. A move into a blocked cell is never made: trying it reveals the cell, and
//! the agent replans where it stands. With a radius of 1 or more these cells were sensed
//! already (they are neighbours of the agent's cell), so this changes nothing; with a
//! radius of 0 it is a robot that learns of an obstacle only by bumping into it. The
//! experiment configs ask for a radius of at least 1 (`configs/replan/README.md`), as the
//! robot of the D* Lite paper's experiments senses its neighbours. A path step that is not
//! a legal move on the agent's map even so (a planner's defect, when no oracle caught it)
//! is a failed check ([`MismatchKind::InvalidPath`]) that ends the run, never a move.
//!
//! Replanning only then is exact: the known map only gains blocked cells, so the rest of
//! a shortest path that is still free keeps its cost and no other path got cheaper.
//!
//! On a weighted map (a costmap) the agent also assumes every cell it has not seen to have
//! weight 1 (the least a weight can be: the free-space assumption for costs) and senses
//! the true weights within the same radius (and those of the cells of its next move); a
//! sensed cell whose weight differs is told to the planner with its weight
//! ([`CellChange::with_weight`]), and a change on a cell of the remaining path is a reason
//! to replan. The rule stays exact: known weights only
//! grow, so a path none of whose cells changed keeps its cost and no other got cheaper.
//! With [`NavConfig::check_every_change`] the oracle checks that claim too, on every step
//! that sensed a change without a replan. The run ends at the goal, when no path is left
//! (the goal is unreachable: a normal outcome), or at [`NavConfig::max_steps`].
//!
//! ```
//! use planner_api::{Budget, Cell, Grid};
//! use planner_replan::{navigate, planners, Oracle};
//!
//! let truth = Grid::from_ascii("
//!     .......
//!     ...#...
//!     ...#...
//!     ...#...
//!     .......
//! ").unwrap();
//! let mut dstar = planners::by_name("dstar_lite", true).unwrap();
//! let config = navigate::NavConfig { radius: 1, ..Default::default() };
//! let run = navigate::run(dstar.as_mut(), Some(&mut Oracle::new(true)), &truth, Cell::new(0, 2), Cell::new(6, 2), &config, &Budget::unlimited()).unwrap();
//! assert!(run.reached && run.mismatches.is_empty());
//! assert_eq!(run.path.first(), Some(&Cell::new(0, 2)));
//! assert_eq!(run.path.last(), Some(&Cell::new(6, 2)));
//! assert!(run.replans.len() >= 2); // the wall is found on the way
//! ```

use std::time::{Duration, Instant};

use planner_api::{
    Budget, Cell, CellChange, Grid, IncrementalPlanner, MoveSet, Problem, ProblemError,
};

use crate::oracle::{Mismatch, MismatchKind, Oracle};
use crate::{Recorder, Records, ReplanRecord};

/// The run's parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct NavConfig {
    /// Sensor radius (a square of half-width `radius` around the agent). At 0 the agent
    /// senses only the cells of each move it tries (see the [module docs](self)).
    pub radius: u32,
    /// Stop after this many steps (`None`: 10 per cell of the map, plus 1,000).
    pub max_steps: Option<u64>,
    /// Also check steps that sensed a change but kept the path (see the module docs).
    pub check_every_change: bool,
}

impl Default for NavConfig {
    fn default() -> NavConfig {
        NavConfig {
            radius: 1,
            max_steps: None,
            check_every_change: false,
        }
    }
}

/// One navigation run's records.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NavRun {
    /// Whether the agent reached the goal.
    pub reached: bool,
    /// Whether the run stopped at [`NavConfig::max_steps`].
    pub hit_step_limit: bool,
    /// Steps driven.
    pub steps: u64,
    /// The first plan and every replan.
    pub replans: Vec<ReplanRecord>,
    /// The cells driven through, the start first.
    pub path: Vec<Cell>,
    /// Every failed check (empty without an oracle).
    pub mismatches: Vec<Mismatch>,
    /// Checks of steps without a replan ([`NavConfig::check_every_change`]).
    pub extra_checks: u64,
}

impl NavRun {
    /// Vertex expansions over all replans.
    pub fn total_expansions(&self) -> u64 {
        self.replans.iter().map(|r| r.expansions).sum()
    }

    /// Planning time (updates and replans) over all replans.
    pub fn planning_time(&self) -> Duration {
        self.replans.iter().map(ReplanRecord::planning_time).sum()
    }

    /// Time before the first move: setting up the planner and its first plan.
    pub fn time_to_first_move(&self) -> Duration {
        self.replans
            .first()
            .map_or(Duration::ZERO, ReplanRecord::planning_time)
    }
}

/// Senses around `at`: marks in `known` every cell within `radius` that is blocked in
/// `truth` but free in `known`, or (on a weighted map) whose weight differs, and lists it.
fn sense(
    truth: &Grid,
    known: &mut Grid,
    at: Cell,
    radius: u32,
    seen: &mut Vec<CellChange>,
) -> bool {
    // The square of cells within `radius`, clipped to the grid first: a radius larger
    // than the map costs the map's cells, not the square's.
    let r = i64::from(radius);
    let (ax, ay) = (i64::from(at.x), i64::from(at.y));
    let (max_x, max_y) = (i64::from(truth.width()) - 1, i64::from(truth.height()) - 1);
    let before = seen.len();
    for y in (ay - r).max(0)..=(ay + r).min(max_y) {
        for x in (ax - r).max(0)..=(ax + r).min(max_x) {
            sense_cell(truth, known, Cell::new(x as u32, y as u32), seen);
        }
    }
    seen.len() > before
}

/// Senses the cells of the move from `from` to `to` that `moves` has (the cell entered
/// and the cells the move must not cut) as [`sense`] senses a cell; nothing for a step
/// that is no move of the set.
fn sense_move(
    truth: &Grid,
    known: &mut Grid,
    moves: &MoveSet,
    from: Cell,
    to: Cell,
    seen: &mut Vec<CellChange>,
) -> bool {
    let Some(mv) = moves.find(from, to) else {
        return false;
    };
    let before = seen.len();
    for &(dx, dy) in std::iter::once(&(mv.dx, mv.dy)).chain(&mv.via) {
        if let Some(cell) = truth.offset(from, dx, dy) {
            sense_cell(truth, known, cell, seen);
        }
    }
    seen.len() > before
}

/// Marks `cell` in `known` as it is in `truth` when it is blocked there but free in
/// `known`, or (on a weighted map) its weight differs, and lists the change in `seen`.
fn sense_cell(truth: &Grid, known: &mut Grid, cell: Cell, seen: &mut Vec<CellChange>) {
    let mut change = None;
    if !truth.is_free(cell) && known.is_free(cell) {
        known.set_free(cell, false);
        change = Some(CellChange::blocked(cell));
    }
    if truth.is_weighted() && truth.weight(cell) != known.weight(cell) {
        let weight = truth.weight(cell);
        known.set_weight(cell, weight);
        let free = known.is_free(cell);
        change = Some(CellChange {
            cell,
            free,
            weight: Some(weight),
        });
    }
    seen.extend(change);
}

/// The agent's map before it looks: `truth`'s size, every cell free, and on a weighted
/// map every weight 1 under `truth`'s rule.
fn assumed(truth: &Grid) -> Grid {
    let free = Grid::from_free_cells(truth.width(), truth.height(), vec![true; truth.len()])
        .unwrap_or_else(|_| unreachable!("a copy of a valid grid's size is valid"));
    match truth.weights() {
        Some(weights) => free
            .with_weights(vec![1; truth.len()], weights.rule())
            .unwrap_or_else(|_| unreachable!("one weight of 1 per cell is valid")),
        None => free,
    }
}

/// Whether a change of `seen` falls on a cell of `path` (a weight change there alters the
/// path's cost; blocked cells are [`still_free`]'s test).
fn reweighted_on(seen: &[CellChange], path: &[Cell]) -> bool {
    seen.iter()
        .any(|c| c.weight.is_some() && path.contains(&c.cell))
}

/// Whether every step of `path` is still a legal move on `known`.
fn still_free(known: &Grid, moves: &MoveSet, path: &[Cell]) -> bool {
    path.windows(2).all(|w| {
        moves
            .find(w[0], w[1])
            .and_then(|mv| moves.apply(known, w[0], mv))
            == Some(w[1])
    })
}

/// Whether the changes just sensed (`sensed`, the agent standing at `rest[0]`) are a
/// reason to replan: a step of the remaining path `rest` is no longer a legal move on
/// `known`, or a cell of it changed its weight. When they are not, and the config asks
/// ([`NavConfig::check_every_change`]), the oracle checks that the rest of the path is
/// still a shortest one.
#[allow(clippy::too_many_arguments)]
fn sensed_a_reason(
    known: &Grid,
    moves: &MoveSet,
    sensed: &[CellChange],
    rest: &[Cell],
    config: &NavConfig,
    oracle: Option<&mut Oracle>,
    goal: Cell,
    out: &mut NavEnd,
    recorder: &mut dyn Recorder,
) -> bool {
    if !still_free(known, moves, rest) || reweighted_on(sensed, rest) {
        return true;
    }
    if let (true, Some(oracle)) = (config.check_every_change, oracle) {
        out.extra_checks += 1;
        let kept = planner_api::Path::new(rest.to_vec());
        let outcome = planner_api::Outcome::found(kept, planner_api::Counters::new());
        if let Err(m) = oracle.check(known, rest[0], goal, &outcome, out.steps) {
            recorder.mismatch(m);
        }
    }
    false
}

/// How a recorded navigation ended ([`run_recorded`]): a [`NavRun`] without the records
/// its recorder took.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct NavEnd {
    /// Whether the agent reached the goal.
    pub reached: bool,
    /// Whether the run stopped at [`NavConfig::max_steps`].
    pub hit_step_limit: bool,
    /// Whether the recorder ended the run early ([`Recorder::stopped`]).
    pub stopped: bool,
    /// Steps driven.
    pub steps: u64,
    /// The cells driven through, the start first.
    pub path: Vec<Cell>,
    /// Checks of steps without a replan ([`NavConfig::check_every_change`]).
    pub extra_checks: u64,
}

/// Runs `planner` from `start` to `goal` on the unknown map `truth` (see the
/// [module docs](self)); the oracle, when given, checks every replan. Errors only when
/// `start` or `goal` is outside `truth` or blocked in it.
pub fn run(
    planner: &mut dyn IncrementalPlanner,
    oracle: Option<&mut Oracle>,
    truth: &Grid,
    start: Cell,
    goal: Cell,
    config: &NavConfig,
    budget: &Budget,
) -> Result<NavRun, ProblemError> {
    let mut records = Records::default();
    let end = run_recorded(
        planner,
        oracle,
        truth,
        start,
        goal,
        config,
        budget,
        &mut records,
    )?;
    Ok(NavRun {
        reached: end.reached,
        hit_step_limit: end.hit_step_limit,
        steps: end.steps,
        replans: records.replans,
        path: end.path,
        mismatches: records.mismatches,
        extra_checks: end.extra_checks,
    })
}

/// [`run`] that hands each replan's record and each failed check to `recorder` as they
/// happen, holding none of them, and ends before the next step once
/// [`Recorder::stopped`] says so.
#[allow(clippy::too_many_arguments)]
pub fn run_recorded(
    planner: &mut dyn IncrementalPlanner,
    mut oracle: Option<&mut Oracle>,
    truth: &Grid,
    start: Cell,
    goal: Cell,
    config: &NavConfig,
    budget: &Budget,
    recorder: &mut dyn Recorder,
) -> Result<NavEnd, ProblemError> {
    Problem::new(truth, start, goal)?;
    let mut known = assumed(truth);
    let mut pending = Vec::new();
    sense(truth, &mut known, start, config.radius, &mut pending);
    pending.clear();
    let problem = Problem::new(&known, start, goal)?;
    // The first plan's update time is the planner's reset (the driver's own setup, the
    // agent's map and first sensing, is not planning).
    let started = Instant::now();
    planner.reset_within(&problem, budget);
    let reset_time = started.elapsed();
    let moves = match planner.specs().path_rule {
        planner_api::PathSpec::Moves(moves) => moves,
        planner_api::PathSpec::AnyAngle => MoveSet::standard(planner_api::Connectivity::Eight),
    };
    let max_steps = config.max_steps.unwrap_or(10 * truth.len() as u64 + 1000);
    let mut out = NavEnd {
        path: vec![start],
        ..NavEnd::default()
    };
    let mut agent = start;
    let mut path = replan(
        planner,
        oracle.as_deref_mut(),
        &known,
        agent,
        goal,
        0,
        reset_time,
        budget,
        recorder,
    );
    let mut at = 0usize;
    while agent != goal {
        let Some(cells) = &path else {
            break;
        };
        // A path that ends short of the goal leaves nowhere to go (only a planner's
        // defect, when no oracle checked it).
        let Some(&next) = cells.get(at + 1) else {
            break;
        };
        if out.steps >= max_steps {
            out.hit_step_limit = true;
            break;
        }
        if recorder.stopped() {
            out.stopped = true;
            break;
        }
        // The agent looks at the cells of its next move before making it, whatever its
        // radius: a move into a blocked cell reveals that cell instead of being made.
        let before = pending.len();
        let looked = sense_move(truth, &mut known, &moves, agent, next, &mut pending);
        // Whether the cells sensed since `$before` give a reason to replan (one call for
        // both the look before a move and the sensing after it).
        macro_rules! sensed_since {
            ($before:expr) => {
                sensed_a_reason(
                    &known,
                    &moves,
                    &pending[$before..],
                    &cells[at..],
                    config,
                    oracle.as_deref_mut(),
                    goal,
                    &mut out,
                    recorder,
                )
            };
        }
        let replan_now = looked && sensed_since!(before);
        if !replan_now {
            if !still_free(&known, &moves, &cells[at..at + 2]) {
                // Not a legal move on what the agent knows, and nothing new explains it:
                // the planner's path is wrong, and the agent does not drive it.
                recorder.mismatch(Mismatch {
                    step: out.steps,
                    start: agent,
                    kind: MismatchKind::InvalidPath(format!(
                        "its step from {agent} to {next} is not a legal move on the agent's map"
                    )),
                });
                break;
            }
            at += 1;
            agent = next;
            out.steps += 1;
            out.path.push(agent);
            let before = pending.len();
            if !sense(truth, &mut known, agent, config.radius, &mut pending)
                || !sensed_since!(before)
            {
                continue;
            }
        }
        let told = Instant::now();
        let result = planner
            .move_start(agent)
            .and_then(|()| planner.apply(&pending));
        pending.clear();
        let update_time = told.elapsed();
        if let Err(e) = result {
            recorder.mismatch(Mismatch {
                step: out.steps,
                start: agent,
                kind: MismatchKind::Rejected(e.to_string()),
            });
            break;
        }
        path = replan(
            planner,
            oracle.as_deref_mut(),
            &known,
            agent,
            goal,
            out.steps,
            update_time,
            budget,
            recorder,
        );
        at = 0;
    }
    out.reached = agent == goal;
    Ok(out)
}

/// One replan, timed and (with an oracle) checked; its path's cells when found.
#[allow(clippy::too_many_arguments)]
fn replan(
    planner: &mut dyn IncrementalPlanner,
    oracle: Option<&mut Oracle>,
    known: &Grid,
    agent: Cell,
    goal: Cell,
    step: u64,
    update_time: Duration,
    budget: &Budget,
    recorder: &mut dyn Recorder,
) -> Option<Vec<Cell>> {
    let started = Instant::now();
    let outcome = planner.replan(budget);
    let replan_time = started.elapsed();
    let mut cost = outcome
        .path
        .as_ref()
        .map(|path| known.path_cost(path.cells()));
    let mut mismatch = None;
    let mut oracle_expansions = None;
    if let Some(oracle) = oracle {
        let checked = oracle.check(known, agent, goal, &outcome, step);
        oracle_expansions = Some(oracle.last_expansions());
        match checked {
            Ok(checked) => cost = checked,
            Err(m) => mismatch = Some(m),
        }
    }
    let failed = mismatch.is_some();
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
    recorder.replan(record, mismatch);
    // A failed check ends the run (the mismatch is recorded with its step).
    outcome
        .path
        .filter(|_| !failed)
        .map(|p| p.into_cells())
        .filter(|cells| cells.first() == Some(&agent))
}
