//! Shared helpers of gridplan's benchmarks (dev-only, not published).
//!
//! - [`load_movingai`]: a Moving AI map and its `.scen` from the repository's
//!   `maps/movingai/`.
//! - [`Peer`]: the `pathfinding` crate's A* (`pathfinding::directed::astar::astar`) on
//!   the same grid, used the way its fastest users use it: integer costs
//!   ([`STRAIGHT`] = 1,000,000 per straight move, [`DIAGONAL`] = 1,414,214 per diagonal,
//!   the octile heuristic on the same scale, no corner cutting; or 4-connected with the
//!   Manhattan heuristic), cell indices as nodes, a padded grid so that no neighbour needs a
//!   bounds check, and a successor iterator that allocates nothing. Its expansions are
//!   counted as the calls of its successor closure (the goal, found when popped, is not
//!   expanded: one fewer than gridplan's `n_expanded` per solved query).
//! - [`WeightedPeer`] and [`seeded_weights`]: the same peer on a weighted grid, with
//!   gridplan's own integer move costs, and the weighted benchmark's seeded weights.
//! - [`Repeats`] and [`best_of_alternating`]: `--repeats=N` from the command line, and
//!   timing that runs two sides' whole workloads `N` times, alternating, keeping each
//!   side's best time (a shared machine's slow spells then hit both sides alike).
//! - [`Line`]: the one-line report `map=... moves=... scenarios=... mismatches=...
//!   expansions=... peer_expansions=... gridplan_ms=... pathfinding_ms=... ratio=...`.
//!
//! ```
//! use planner_api::{Cell, Grid};
//! use planner_bench::{Peer, DIAGONAL, STRAIGHT};
//!
//! let grid = Grid::from_ascii("
//!     ....
//!     .#..
//!     ....
//! ").unwrap();
//! let peer = Peer::new(&grid);
//! // Past the block: no diagonal may cut its corner, so one diagonal and three straight moves.
//! let (cost, n_expanded) = peer.octile(Cell::new(0, 0), Cell::new(3, 2)).unwrap();
//! assert_eq!(cost, 3 * STRAIGHT + DIAGONAL);
//! assert!(n_expanded >= 4);
//! assert_eq!(peer.manhattan(Cell::new(0, 0), Cell::new(3, 2)).unwrap().0, 5 * STRAIGHT);
//! ```
#![deny(missing_docs)]

use std::fmt;
use std::path::PathBuf;
use std::time::{Duration, Instant};

use planner_api::{Cell, Grid};
use planner_maps::Scenario;

/// The peer's cost of a straight move.
pub const STRAIGHT: u64 = 1_000_000;
/// The peer's cost of a diagonal move: `sqrt 2` on the same scale, rounded.
pub const DIAGONAL: u64 = 1_414_214;

/// `maps/movingai/` at the repository root.
pub fn movingai_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai")
}

/// The Moving AI map `maps/movingai/<name>.map` and its scenarios
/// (`<name>.map.scen`), or an error naming the file.
pub fn load_movingai(name: &str) -> Result<(Grid, Vec<Scenario>), String> {
    let dir = movingai_dir();
    let map =
        planner_maps::read_map(&dir.join(format!("{name}.map"))).map_err(|e| e.to_string())?;
    let scenarios = planner_maps::read_scenarios(&dir.join(format!("{name}.map.scen")))
        .map_err(|e| e.to_string())?;
    Ok((map.grid, scenarios))
}

/// The `pathfinding` crate's A* on one grid (see the crate docs for how it is used).
#[derive(Debug, Clone)]
pub struct Peer {
    /// Free cells of the grid with a blocked border one cell wide, row-major.
    free: Vec<bool>,
    /// Row length of `free`: the grid's width plus 2.
    stride: usize,
}

/// The eight moves as (dx, dy); the first four are straight.
const MOVES: [(isize, isize); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (-1, 1),
    (1, -1),
    (-1, -1),
];

impl Peer {
    /// The peer's view of `grid`.
    pub fn new(grid: &Grid) -> Peer {
        let (width, height) = (grid.width() as usize, grid.height() as usize);
        let stride = width + 2;
        let mut free = vec![false; stride * (height + 2)];
        for (y, row) in grid.free_cells().chunks(width).enumerate() {
            free[(y + 1) * stride + 1..][..width].copy_from_slice(row);
        }
        Peer { free, stride }
    }

    fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + 1) * self.stride + cell.x as usize + 1
    }

    /// 8-connected A* without corner cutting, octile heuristic, integer costs: the cost
    /// of a shortest path from `start` to `goal` (in units of `1 / STRAIGHT`) and the
    /// peer's number of expansions, or `None` when there is no path.
    pub fn octile(&self, start: Cell, goal: Cell) -> Option<(u64, u64)> {
        self.search::<true>(start, goal)
    }

    /// 4-connected A* with the Manhattan heuristic, integer costs (`STRAIGHT` per move):
    /// as [`Peer::octile`].
    pub fn manhattan(&self, start: Cell, goal: Cell) -> Option<(u64, u64)> {
        self.search::<false>(start, goal)
    }

    fn search<const DIAGONALS: bool>(&self, start: Cell, goal: Cell) -> Option<(u64, u64)> {
        let free = &self.free[..];
        let stride = self.stride as isize;
        let goal_index = self.index(goal);
        let (goal_x, goal_y) = (goal_index % self.stride, goal_index / self.stride);
        let mut n_expanded = 0u64;
        let successors = |&p: &usize| {
            n_expanded += 1;
            let n_moves = if DIAGONALS { 8 } else { 4 };
            MOVES[..n_moves].iter().filter_map(move |&(dx, dy)| {
                let q = p.wrapping_add_signed(dy * stride + dx);
                // The border keeps every neighbour of a free cell inside `free`.
                let open = free[q]
                    && (dx == 0
                        || dy == 0
                        || (free[p.wrapping_add_signed(dx)]
                            && free[p.wrapping_add_signed(dy * stride)]));
                let cost = if dx == 0 || dy == 0 {
                    STRAIGHT
                } else {
                    DIAGONAL
                };
                open.then_some((q, cost))
            })
        };
        let heuristic = |&p: &usize| {
            let dx = (p % self.stride).abs_diff(goal_x) as u64;
            let dy = (p / self.stride).abs_diff(goal_y) as u64;
            if DIAGONALS {
                let (low, high) = (dx.min(dy), dx.max(dy));
                (high - low) * STRAIGHT + low * DIAGONAL
            } else {
                (dx + dy) * STRAIGHT
            }
        };
        let found =
            pathfinding::directed::astar::astar(&self.index(start), successors, heuristic, |&p| {
                p == goal_index
            });
        found.map(|(_, cost)| (cost, n_expanded))
    }
}

/// The `pathfinding` crate's A* on a weighted grid, used as [`Peer`] is (integer costs,
/// cell indices as nodes, a padded grid, an allocation-free successor iterator), with the
/// same integer move costs as gridplan's (`planner_api::weights`): half the move's
/// [`planner_api::Cost`] units (2^31 straight, 3,037,000,500 diagonal) times
/// `k_from * w(from) + k_to * w(to)`, and the octile heuristic in those units times the
/// grid's smallest weight. Both sides therefore compute the same integers, so their costs
/// must be equal exactly. 8-connected without corner cutting.
#[derive(Debug, Clone)]
pub struct WeightedPeer {
    /// Weights with a border of 0 (blocked) one cell wide, row-major; 0 where blocked.
    weights: Vec<u64>,
    stride: usize,
    min_weight: u64,
    factors: (u64, u64),
}

impl WeightedPeer {
    /// The peer's view of a weighted `grid` (an unweighted grid reads as all weights 1).
    pub fn new(grid: &Grid) -> WeightedPeer {
        let (width, height) = (grid.width() as usize, grid.height() as usize);
        let stride = width + 2;
        let mut weights = vec![0u64; stride * (height + 2)];
        for cell in grid.cells() {
            if grid.is_free(cell) {
                weights[(cell.y as usize + 1) * stride + cell.x as usize + 1] =
                    u64::from(grid.weight(cell));
            }
        }
        let (min_weight, factors) = grid
            .weights()
            .map_or((1, (1, 1)), |w| (u64::from(w.min()), w.rule().factors()));
        WeightedPeer {
            weights,
            stride,
            min_weight,
            factors,
        }
    }

    /// 8-connected weighted A* from `start` to `goal`: the least cost in
    /// [`planner_api::Cost`] units and the peer's expansions (successor calls), or `None`.
    pub fn octile(&self, start: Cell, goal: Cell) -> Option<(u64, u64)> {
        const HALF_STRAIGHT: u64 = planner_api::Cost::ONE.units() / 2;
        const HALF_DIAGONAL: u64 = planner_api::Cost::SQRT_2.units() / 2;
        let weights = &self.weights[..];
        let stride = self.stride as isize;
        let index = |c: Cell| (c.y as usize + 1) * self.stride + c.x as usize + 1;
        let goal_index = index(goal);
        let (goal_x, goal_y) = (goal_index % self.stride, goal_index / self.stride);
        let (k_from, k_to) = self.factors;
        let mut n_expanded = 0u64;
        let successors = |&p: &usize| {
            n_expanded += 1;
            let from = k_from * weights[p];
            MOVES.iter().filter_map(move |&(dx, dy)| {
                let q = p.wrapping_add_signed(dy * stride + dx);
                let w = weights[q];
                let straight = dx == 0 || dy == 0;
                let open = w != 0
                    && (straight
                        || (weights[p.wrapping_add_signed(dx)] != 0
                            && weights[p.wrapping_add_signed(dy * stride)] != 0));
                let half = if straight {
                    HALF_STRAIGHT
                } else {
                    HALF_DIAGONAL
                };
                open.then_some((q, half * (from + k_to * w)))
            })
        };
        let min_weight = self.min_weight;
        let heuristic = |&p: &usize| {
            let dx = (p % self.stride).abs_diff(goal_x) as u64;
            let dy = (p / self.stride).abs_diff(goal_y) as u64;
            let (low, high) = (dx.min(dy), dx.max(dy));
            ((high - low) * 2 * HALF_STRAIGHT + low * 2 * HALF_DIAGONAL) * min_weight
        };
        let found =
            pathfinding::directed::astar::astar(&index(start), successors, heuristic, |&p| {
                p == goal_index
            });
        found.map(|(_, cost)| (cost, n_expanded))
    }
}

/// Seeded random weights for every cell of `grid`, uniform in `1..=max` (xorshift64 from
/// `seed`), with the rule `rule`: the weighted benchmark's maps.
pub fn seeded_weights(grid: &Grid, seed: u64, max: u16, rule: planner_api::CostRule) -> Grid {
    let mut state = seed | 1;
    let weights = (0..grid.len())
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            1 + (state % u64::from(max)) as u16
        })
        .collect();
    grid.clone()
        .with_weights(weights, rule)
        .unwrap_or_else(|e| panic!("weights for a {}x{} grid: {e}", grid.width(), grid.height()))
}

/// How many times each side of a benchmark runs its whole workload, and with which clock.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Repeats(pub u32, pub Clock);

impl Default for Repeats {
    fn default() -> Repeats {
        Repeats(3, Clock::Wall)
    }
}

/// What a pass's time is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Clock {
    /// Elapsed wall time (`std::time::Instant`), the default.
    #[default]
    Wall,
    /// The benchmark thread's time on a CPU (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`,
    /// through the `cpu-time` crate): on a machine shared with other work, time spent
    /// waiting for a core does not count (cache contention still does). Linux's
    /// `/proc/thread-self/schedstat`, read before, is brought up to date only at scheduler
    /// ticks (4 ms here) while the thread computes, too coarse for a 10 ms pass.
    Cpu,
}

impl Clock {
    /// The current reading, or `None` when this clock is unavailable.
    pub fn now(self) -> Option<Duration> {
        match self {
            Clock::Wall => Some(START.with(|start| start.elapsed())),
            Clock::Cpu => cpu_time::ThreadTime::try_now()
                .ok()
                .map(|now| now.as_duration()),
        }
    }
}

thread_local! {
    /// The wall clock's origin.
    static START: Instant = Instant::now();
}

impl Repeats {
    /// `--repeats=N` (N >= 1; default 3) and `--clock=wall|cpu` (default wall) from `args`
    /// (the program name excluded), and the arguments that are not options, in order (a
    /// bench's filters). Other `--` options, such as the `--bench` that `cargo bench`
    /// passes, are ignored.
    pub fn parse(args: impl IntoIterator<Item = String>) -> Result<(Repeats, Vec<String>), String> {
        let mut repeats = Repeats::default();
        let mut rest = Vec::new();
        for arg in args {
            if let Some(value) = arg.strip_prefix("--repeats=") {
                match value.parse::<u32>() {
                    Ok(n) if n >= 1 => repeats.0 = n,
                    _ => {
                        return Err(format!(
                            "--repeats: expected an integer >= 1, got {value:?}"
                        ))
                    }
                }
            } else if let Some(value) = arg.strip_prefix("--clock=") {
                repeats.1 = match value {
                    "wall" => Clock::Wall,
                    "cpu" if Clock::Cpu.now().is_some() => Clock::Cpu,
                    "cpu" => {
                        return Err("--clock=cpu: this thread's CPU clock is unavailable".into())
                    }
                    _ => return Err(format!("--clock: expected wall or cpu, got {value:?}")),
                };
            } else if !arg.starts_with("--") {
                rest.push(arg);
            }
        }
        Ok((repeats, rest))
    }
}

/// A side's result (of its last pass) and its best time over the passes.
#[derive(Debug, Clone, PartialEq)]
pub struct Timed<T> {
    /// What the side returned.
    pub result: T,
    /// Its least time over all passes.
    pub best: Duration,
}

/// Runs `ours` and then `peer`, `repeats` times in turn, and returns each side's result and
/// best time. Both sides must be deterministic: a pass whose result differs from the
/// first pass's is an error.
pub fn best_of_alternating<A: PartialEq, B: PartialEq>(
    repeats: Repeats,
    mut ours: impl FnMut() -> A,
    mut peer: impl FnMut() -> B,
) -> Result<(Timed<A>, Timed<B>), String> {
    /// Runs one pass; `Ok(false)` when its result differs from the first pass's.
    fn pass<T: PartialEq>(
        clock: Clock,
        run: &mut impl FnMut() -> T,
        side: &mut Option<Timed<T>>,
    ) -> Result<bool, String> {
        let unavailable = || "the clock became unavailable".to_string();
        let start = clock.now().ok_or_else(unavailable)?;
        let result = run();
        let elapsed = clock.now().ok_or_else(unavailable)?.saturating_sub(start);
        Ok(match side {
            None => {
                *side = Some(Timed {
                    result,
                    best: elapsed,
                });
                true
            }
            Some(timed) => {
                timed.best = timed.best.min(elapsed);
                timed.result == result
            }
        })
    }
    let clock = repeats.1;
    let (mut a, mut b) = (None, None);
    for round in 0..repeats.0.max(1) {
        if !pass(clock, &mut ours, &mut a)? || !pass(clock, &mut peer, &mut b)? {
            return Err(format!(
                "pass {} gave a different result than pass 1",
                round + 1
            ));
        }
    }
    match (a, b) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err("no pass ran".to_string()),
    }
}

/// One benchmark line (issue 14's format), printed by its `Display`.
#[derive(Debug, Clone, PartialEq)]
pub struct Line {
    /// Map name, e.g. `den520d`.
    pub map: String,
    /// Number of directions, 8 or 4.
    pub moves: u32,
    /// Scenarios run.
    pub scenarios: usize,
    /// Scenarios whose length is off the reference.
    pub mismatches: usize,
    /// gridplan's total `n_expanded`.
    pub expansions: u64,
    /// The peer's total expansions.
    pub peer_expansions: u64,
    /// gridplan's best time.
    pub gridplan: Duration,
    /// The peer's best time.
    pub pathfinding: Duration,
}

impl fmt::Display for Line {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        write!(
            f,
            "map={} moves={} scenarios={} mismatches={} expansions={} peer_expansions={} \
             gridplan_ms={:.1} pathfinding_ms={:.1} ratio={:.2}",
            self.map,
            self.moves,
            self.scenarios,
            self.mismatches,
            self.expansions,
            self.peer_expansions,
            ms(self.gridplan),
            ms(self.pathfinding),
            self.pathfinding.as_secs_f64() / self.gridplan.as_secs_f64().max(1e-12),
        )
    }
}

/// Whether lengths `a` and `b` agree within a relative `1e-4` (the scenario files give
/// optima to 8 decimals; the peer's diagonal is `sqrt 2` rounded to 7).
pub fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-4 * b.abs().max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn the_cpu_clock_ticks_finer_than_a_millisecond() {
        // A scheduler-tick clock (schedstat's, 4 ms here) would step by whole ticks while
        // this thread computes: over 20 ms of reads it takes at most a handful of distinct
        // values. The thread CPU clock steps by the reads' own cost, so it takes thousands;
        // one long step (a virtual machine's stolen time is counted as the thread's) must
        // not fail the test, so it counts steps rather than bounding the largest.
        let Some(first) = Clock::Cpu.now() else {
            return;
        };
        let (mut steps, mut last) = (0u32, first);
        while last - first < Duration::from_millis(20) {
            let now = Clock::Cpu.now().unwrap();
            steps += u32::from(now != last);
            last = now;
        }
        assert!(steps >= 100, "{steps} steps in 20 ms");
    }

    #[test]
    fn repeats_are_parsed_and_checked() {
        let check = |input: &[&str], expect: Result<(Repeats, Vec<String>), String>| {
            assert_eq!(Repeats::parse(args(input)), expect, "{input:?}");
        };
        check(&["--bench"], Ok((Repeats(3, Clock::Wall), vec![])));
        check(
            &["--clock=wall", "--repeats=2"],
            Ok((Repeats(2, Clock::Wall), vec![])),
        );
        check(
            &["--clock=x"],
            Err("--clock: expected wall or cpu, got \"x\"".into()),
        );
        check(
            &["--repeats=1", "den520d"],
            Ok((Repeats(1, Clock::Wall), args(&["den520d"]))),
        );
        check(
            &["--repeats=0"],
            Err("--repeats: expected an integer >= 1, got \"0\"".into()),
        );
        check(
            &["--repeats=x"],
            Err("--repeats: expected an integer >= 1, got \"x\"".into()),
        );
    }

    #[test]
    fn each_side_runs_once_per_repeat_and_must_agree() {
        let (mut n_ours, mut n_peer) = (0, 0);
        let timed = best_of_alternating(
            Repeats(4, Clock::Wall),
            || {
                n_ours += 1;
                7
            },
            || {
                n_peer += 1;
                "x"
            },
        )
        .unwrap();
        assert_eq!((n_ours, n_peer), (4, 4));
        assert_eq!((timed.0.result, timed.1.result), (7, "x"));
        let mut n = 0;
        let drifting = best_of_alternating(
            Repeats(2, Clock::Wall),
            || 1,
            || {
                n += 1;
                n
            },
        );
        assert_eq!(
            drifting,
            Err("pass 2 gave a different result than pass 1".into())
        );
    }

    #[test]
    fn the_peer_finds_the_scenario_optima() {
        // The first scenarios of arena (a small map) against the file's optimal lengths.
        let (grid, scenarios) = load_movingai("arena").unwrap();
        let peer = Peer::new(&grid);
        for s in scenarios.iter().take(50) {
            let (cost, n_expanded) = peer.octile(s.start, s.goal).unwrap();
            assert!(
                close(cost as f64 / STRAIGHT as f64, s.optimal_length),
                "line {}",
                s.line
            );
            // Every cell of the path but the goal is expanded, at least one per move.
            let n_moves = s
                .start
                .x
                .abs_diff(s.goal.x)
                .max(s.start.y.abs_diff(s.goal.y));
            assert!(n_expanded >= u64::from(n_moves), "line {}", s.line);
        }
    }

    #[test]
    fn the_weighted_peer_agrees_with_the_oracle() {
        let (grid, scenarios) = load_movingai("arena").unwrap();
        for rule in [planner_api::CostRule::Mean, planner_api::CostRule::Entered] {
            let weighted = seeded_weights(&grid, 7, 255, rule);
            let peer = WeightedPeer::new(&weighted);
            let moves = planner_api::MoveSet::new(
                planner_api::Connectivity::Eight,
                false,
                &planner_api::NeighborOrder::default(),
            )
            .unwrap();
            for s in scenarios.iter().step_by(7).take(20) {
                let best = planner_testkit::weighted_dijkstra(&weighted, &moves, s.start, s.goal);
                let found = peer.octile(s.start, s.goal).map(|(cost, _)| cost);
                assert_eq!(found, best.map(planner_api::Cost::units), "line {}", s.line);
            }
        }
    }

    #[test]
    fn the_peer_reports_no_path() {
        let grid = Grid::from_ascii(".#.").unwrap();
        let peer = Peer::new(&grid);
        assert_eq!(peer.manhattan(Cell::new(0, 0), Cell::new(2, 0)), None);
        assert_eq!(peer.octile(Cell::new(0, 0), Cell::new(2, 0)), None);
    }

    #[test]
    fn lines_have_the_issue_format() {
        let line = Line {
            map: "den520d".into(),
            moves: 8,
            scenarios: 2,
            mismatches: 0,
            expansions: 10,
            peer_expansions: 8,
            gridplan: Duration::from_millis(2),
            pathfinding: Duration::from_millis(9),
        };
        assert_eq!(
            line.to_string(),
            "map=den520d moves=8 scenarios=2 mismatches=0 expansions=10 peer_expansions=8 \
             gridplan_ms=2.0 pathfinding_ms=9.0 ratio=4.50"
        );
    }
}
