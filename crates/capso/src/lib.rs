//! CAPSO: a cubic spline through the start, `n` control points and the goal, whose control
//! points a chaotic adaptive particle swarm optimises (seed 002's fourth reference
//! planner, its reference \[44\]).
//!
//! The method is Lian, Yu, Xiao and Liu, "Cubic spline interpolation-based robot path
//! planning using a chaotic adaptive particle swarm optimization algorithm", Mathematical
//! Problems in Engineering 2020, article 1849240
//! (<https://www.hindawi.com/journals/mpe/2020/1849240/>). Its abstract fixes the three
//! ingredients: the particles' position update is modified by the beetle foraging (beetle
//! antennae search) strategy; the inertia weight and acceleration coefficients follow a
//! trigonometric schedule over the iterations (large steps early, fine search late); and a
//! chaotic map replaces PSO's uniform random coefficients. The stored copies of the paper
//! (the publisher's page and a vdocuments.net transcript) hold only its abstract, searched
//! again for issue 34; so the equations below are the published forms those words name,
//! each with its source, and each constant a [`Config`] key. Seed 002 (section 4.2.2)
//! fixes 6 control points, 30 particles and 100 iterations, the defaults.
//!
//! # A particle and its path
//! A particle is the `2 n` coordinates of `n` control points in the grid's box
//! `[0, W - 1] x [0, H - 1]` (cell centres at integers), in path order. It is decoded so:
//! 1. The natural cubic spline through start, the control points in order and goal,
//!    parameterised by chord length ([`spline`]), is sampled `samples_per_segment` times
//!    per knot interval.
//! 2. Each sample is rounded to the nearest cell (clamped into the grid); repeated cells
//!    are dropped.
//! 3. The cell polyline is simplified by Ramer-Douglas-Peucker with tolerance `tolerance`
//!    cells (every dropped cell lies within that distance of the line through its kept
//!    neighbours, Douglas and Peucker's perpendicular distance): rounding
//!    makes a polyline through every sample zigzag by up to half a cell per sample, which
//!    adds to the length of a straight line (2.4 % on seed 002's open map: 114.43 instead
//!    of 111.80 with `tolerance = 0` and 10 samples per interval, tested). The kept cells are the
//!    path's waypoints: an any-angle path ([`PathRule::AnyAngle`](planner_api::PathRule)).
//!    A chord within the tolerance replaces the cells it spans unless it touches a blocked
//!    cell while none of those cells (its ends included) is blocked; then the range is
//!    split at its farthest cell, as one beyond the tolerance is. So a polyline through the
//!    cells whose segments are all free stays free when simplified, and a curve through
//!    blocked cells is simplified as if there were no obstacles (it collides either way).
//!    Until 2026-12-06 every chord within the tolerance was taken: a route that bends less
//!    than the tolerance around an obstacle then simplified into the blocked straight line
//!    (on a 4 x 3 grid with one blocked cell every particle did, and the search ended with
//!    `no_path`; through a wall's gap one row off the straight line the paths were 30.15 to
//!    30.69 long instead of 29.07). The ranges are settled depth first, the left part
//!    first (farthest cell: the first of equals), and each segment is measured as it
//!    settles, a refused chord too.
//!
//! Its fitness is `length + penalty * collision`, where `length` is the polyline's
//! Euclidean length and `collision` is, over its segments, the number of blocked cells
//! touched plus the length inside them, both exact ([`collision`]): the penalty grows with
//! the length in collision, so the swarm is pulled out of obstacles gradually rather than
//! facing a flat wall of infeasible paths. `collision = 0` exactly when every segment
//! passes [`planner_api::segment_is_free`], so a path of fitness below `penalty` is valid.
//! The fitness is that of the returned path itself. The segments are walked on a
//! bit-packed copy of the grid ([`collision::BitGrid`], built once per grid), a segment
//! already measured in the same search is answered by a cache
//! ([`collision::SegmentCache`]), and the decoding reuses its buffers, so an evaluation
//! allocates nothing.
//!
//! # The swarm
//! For iteration `k = 1 ..= T` with `s = sin(pi k / (2 T))`, `c = cos(pi k / (2 T))`:
//! - inertia `w = w_min + (w_max - w_min) c`, cognitive `c1 = c1_max - (c1_max - c1_min) s`,
//!   social `c2 = c2_min + (c2_max - c2_min) s` (the trigonometric schedule of the
//!   abstract: large inertia and self-confidence early, the swarm's pull late; the bounds
//!   0.9 and 0.4 of `w` are Shi and Eberhart's, also the default of the rBAS package's
//!   beetle swarm, <https://jywang2016.github.io/rBAS/reference/BSOoptim.html>; 2.5 and
//!   0.5 for `c1`, `c2` are Ratnaweera et al.'s time-varying coefficients, 2004);
//! - beetle step `delta = beetle_step * beetle_decay^(k - 1)` (beetle antennae search,
//!   Jiang and Li 2017: `delta_{k+1} = eta delta_k`, `eta = 0.95`).
//!
//! Each particle, in order:
//! 1. *Restart.* When its personal best has not improved for `restart_after` iterations,
//!    its position is redrawn uniformly within `jitter` times the grid's extent of the
//!    global best (clamped into the box), its velocity and last move set to 0; its personal
//!    best is kept (issue 34; a choice, not from the paper).
//! 2. *Velocity* (per coordinate): `v = w v + c1 r1 (pbest - x) + c2 r2 (gbest - x)`,
//!    clamped to `max_speed` times the grid's extent on that axis, where `r1` and `r2` are
//!    the next two values of the chaotic sequence ([`chaos`]; the logistic map by
//!    default).
//! 3. *Beetle.* Beetle swarm optimisation (Wang, Yang and Liu, Filomat 34(15) 2020; the
//!    rBAS documentation above) moves the particle by
//!    `x + lambda v + (1 - lambda) xi` with `lambda = 0.4` and
//!    `xi = delta v sign(f(x_r) - f(x_l))` for the antennae `x_r = x + v d / 2` and
//!    `x_l = x - v d / 2`; for minimisation the step goes toward the better antenna,
//!    `xi = -delta v sign(f(x_r) - f(x_l))`. Evaluating two antennae
//!    would triple the work (three fitness evaluations per particle and iteration); here
//!    the antennae are the particle's last two positions, which are already evaluated:
//!    with `u = x_k - x_{k-1}` the last move and `df = f(x_k) - f(x_{k-1})`, the
//!    directional estimate of the slope along `v` has the sign of `df (u . v)`, and
//!    `xi = -delta v sign(df (u . v))` (0 before the first move and after a restart). This
//!    substitution is this crate's choice.
//! 4. The position is clamped into the box (a clamped coordinate's velocity is set to 0)
//!    and evaluated, and the personal best updated. The global best is updated after the
//!    whole swarm has moved.
//!
//! # Initialisation
//! First the [`guide`]: an A* route over blocks of cells (at most 64 per side), shortened
//! by line of sight. Lian et al.'s initialisation is not in the stored abstract; seeding
//! part of the swarm on a route through free blocks (free but for the start's and the
//! goal's own blocks, [`guide`] step 4) is issue 34's answer to random control points missing
//! every free corridor on seed 002's 500 x 500 map. When no route exists even over single
//! cells, the goal is unreachable and the search stops with `no_path` before any
//! evaluation.
//! - Particle 0 has its control points evenly spaced on the straight line start -> goal
//!   (so a free line is found at once, and CAPSO "produces paths identical to PA-star in
//!   obstacle-free environments", seed 002 section 4.3.1).
//! - Particles `1 ..= round(guided_share (P - 1))`: particle 1 has the guide's control
//!   points ([`guide::control_points`]), the others the same plus uniform noise of
//!   `jitter` times the extent per coordinate.
//! - The rest: control points uniform in the box whose nearest cell is free (up to
//!   [`FREE_POINT_ATTEMPTS`] draws each), ordered by their projection on start -> goal so
//!   that they start without loops.
//!
//! Velocities start at 0.
//!
//! Randomness: the initial positions, the chaotic sequence's start value and its reseeds,
//! and the restarts come from ChaCha8 keyed by `seed` ([`chaos::rng_for_seed`]); the guide
//! is deterministic, so the same seed gives the same path and counters bit for bit.
//!
//! # Outcome and counters
//! After the last iteration the global best is decoded: `found` when its collision is 0,
//! else `budget_exhausted` with no path: the swarm's iterations are its budget, and like
//! RRT it cannot prove that no path exists (`no_path` says that, planner-api's
//! `Status`; it is said only when the guide finds no route at all). The best attempt's
//! collision is in the counters. The budget counts fitness evaluations as expansions (`n_expanded`):
//! `30 + 100 * 30 = 3030` with the defaults (one per particle at the start and one per
//! particle and iteration). The guide's block search is not counted (at most the grid's
//! cells per level; `n_guide_expanded`), but it stops at the budget's deadline or cancel
//! flag (`budget_exhausted`, no path). When the budget runs out the outcome is
//! `budget_exhausted`, with the best path so far if that one is collision-free. A memory
//! budget is checked for the bit grid and the guide's finest level (9 bytes a cell).
//!
//! Counters, in this order: `n_iterations`, `n_fitness_evaluations`,
//! `final_collision_cells` and `final_collision_length_milli` (the returned global best's
//! blocked cells touched and its length inside them in thousandths of a cell; 0 for a
//! found path), `n_chaos_reseeds`, `n_restarts`, `n_guide_expanded`, `guide_block` (the
//! guide's block size in cells, 0 when there is no route), `n_segments` and
//! `n_segment_cache_hits` (segments measured over all evaluations, the paths' and the
//! chords the simplification refused, and those the per-search segment cache answered,
//! [`collision::SegmentCache`]), `n_expanded`
//! (= `n_fitness_evaluations`). The outcome's series `best_fitness` (x: `iteration`) is
//! the global best fitness after initialisation (iteration 0) and after each iteration.
//! The tests hold `n_guide_expanded` and `guide_block` to
//! `planner_testkit::reference_capso_guide` (the guide written again from its docs) and
//! the evaluation counts to the formula above, on random grids and on every snapshotted
//! run; xtask's tests (`tests/capso.rs`) write the swarm again from these docs and hold
//! every snapshotted run and 120 small random problems to it: status, path and every
//! counter.
//!
//! # Against seed 002, measured
//! `cargo bench -p planner-capso --bench seed002 -- --repeats=50` (seed 002's settings, seeds
//! 0-49; 2026-12-06 with the simplification that refuses colliding chords, three runs, each
//! planner's repeats in a row as the runner runs them; times are the thread's CPU time,
//! medians, and moved with the machine between the runs; the records of `cargo xtask
//! experiment configs/pastar.toml` give 35.6, 26.6, 1.8, 2.6, 46.4 and 45.8 for the maps
//! with obstacles), beside Theta\*'s length on the same map
//! (`gridplan plan --planner theta_star --start .. --goal .. maps/pastar/MAP`; an any-angle
//! path, so an upper bound on the shortest one):
//!
//! | map (start -> goal) | found | mean length | seed 002's CAPSO | Theta\* | CAPSO / PA-star time |
//! |---|---:|---:|---:|---:|---:|
//! | open 140 x 120 (20,10) -> (70,110) | 50/50 | 111.80 | 111.84 | | 851-924 (PA-star draws a line) |
//! | two obstacles | 50/50 | 112.42 | 112.85 | 112.34 | 26.1-35.9 |
//! | several obstacles | 50/50 | 113.70 | 114.46 | 113.70 | 20.2-26.7 |
//! | 500 x 500 (50,250) -> (400,200) | 50/50 | 455.98 | 382.34 | 452.66 | 1.5-1.7 |
//! | 500 x 500 (50,425) -> (400,225) | 50/50 | 415.94 | 427.30 | 414.93 | 2.0-2.6 |
//! | 200 x 200 map 1 (25,35) -> (140,190) | 50/50 | 203.84 | 210.89 | 203.70 | 43.9-46.4 |
//! | 200 x 200 map 2 | 50/50 | 193.86 | 215.09 | 193.88 | 46.1-47.0 |
//!
//! The mean length is within 1 % of Theta\*'s on every map with obstacles, and within 5 %
//! of the seed's on five of the seven. The maps are reconstructions (planner-pastar's
//! `generate`: the paper's were lost with its figures), and the two that differ differ by
//! their obstacles, as the exact 8-connected optimum (seed 002's RA-star1, Tables 9 and 10;
//! here planner-pastar's docs) shows: 375.11 on the paper's first 500 x 500 scenario against
//! 474.30 on the reconstruction (26 % longer: its obstacles close the route the paper's map
//! left open, and no planner here comes near the seed's 382.34), and 209.07 on the paper's
//! second 200 x 200 map against 202.63 here (the reconstruction is more open; the seed's
//! CAPSO was 6.68 % longer than its PA-star there, this one is at Theta\*'s length). Seed
//! 002's Tables 12-14 give CAPSO 7 to 14 times PA-star's time; here it is 1.5 to 47 times,
//! more than 20 on the 140 x 120 and 200 x 200 maps with obstacles, where PA-star's local
//! searches expand only 289 to 628 cells. Refusing colliding chords (step 3) cost the most
//! there: callgrind (`valgrind --tool=callgrind <the seed002 bench's binary> --repeats=3
//! --only=MAP` in `crates/capso`, this crate against commit 38a9d64's) counts 18 % more
//! instructions on the two-obstacle map (73.4 million against 62.0) and 29 % more on the
//! first 200 x 200 map (119.6 million against 92.7; the segment walk's share grew most: the refused chords and the finer
//! segments of the near-feasible particles), and the CPU ratios rose from 23-27, 10-20 and
//! 27-37 (two obstacles, several, 200 x 200) to the table's; the mean lengths fell by 0.03
//! to 0.3 %. Issue 34's speed-ups of the decoding
//! and the walk took CAPSO's median there from 1.95 to 1.61 ms and from 2.7-2.8 to 2.3-2.4
//! ms, then the spline without a chain of divisions ([`spline`]) and the samples rounded in
//! a loop of their own from 1.62-1.63 to 1.43-1.45 ms and from 2.33-2.45 to 2.12-2.25 ms
//! (three alternating runs of the bench's binaries before and after each change), every
//! path the same. The ratios given with those changes (20.5 and 23.5-24.1, then 18.9-19.1
//! and 20.8-22.6) came from the bench when it alternated the two planners run by run, which
//! left PA-star 25 to 40 % slower than with its repeats in a row (the bench's docs).
//! What the seed's ratio measures: its Tables 12-14 also time TA-star (A* with 8 moves and
//! the Manhattan heuristic, configs/pastar.toml's `TA-star`), at 0.23 s on the 140 x 120
//! maps and 1.55 and 2.03 s on the 500 x 500 scenarios, 7 to 9 times as long. Here TA-star
//! expands 101 to 173 cells on the first and 28,822 and 13,073 on the second (`runs.csv` of
//! `cargo xtask experiment configs/pastar.toml`), and its median times (that run's
//! `summary.md`, Tables 12-14 layout) are 0.019-0.023 ms and 2.33 and 1.62 ms, 71 to 122
//! times as long. So most of the seed's 0.23 s does not grow with the search (a fixed cost of
//! about 0.2 s per call, if its TA-star expands as many cells as this one), and on the small
//! maps its CAPSO / PA-star ratio of 7 to 14 compares CAPSO with that cost; PA-star's own
//! ratio to TA-star is about the seed's there (2.0 to 5.6 in that run against the seed's 2.9
//! to 5.6, the 140 x 120 and 200 x 200 maps with obstacles). Where the searches dominate,
//! on the 500 x 500 maps, the seed's CAPSO took 6.7 and 5.6 times PA-star's time, and this
//! one takes 1.6 and 2.5 times. Issue 34's 20 on the smaller maps would need CAPSO's
//! evaluations 1.3 (several obstacles), 1.7 (two) and 2.3 (200 x 200) times as fast as in
//! the README's table; the profile there is flat (callgrind on the two-obstacle map: no
//! source line above 4 % of the instructions). Tried on 2026-12-06 and not kept: a map of each cell's Chebyshev distance to
//! the nearest blocked cell, so that a segment is free when its two ends' distances sum to
//! at least its longer extent plus 2 (two lookups before the bounding box's four): it proved
//! almost no segment free that the bounding box did not, and callgrind counted 184.2 million
//! instructions against 183.8 (two obstacles, `--repeats=9`) and 310.9 against 303.8
//! (first 200 x 200 map).
//! The control-point study (`cargo xtask experiment
//! configs/capso-control-points.toml`, 50 repeats on the several-obstacle map) gives mean
//! lengths 113.69, 113.68, 113.68 and 113.70 for 3, 4, 5 and 6 control points (every run
//! found a path): flat within 0.02, where seed 002 (section 4.2.2, Fig. 11) finds 6 points
//! best among 3 to 6; fewer points converge faster in the first iterations here (mean best
//! fitness after 10 iterations 114.13, 114.33, 114.38 and 114.70).
//!
//! # On random clutter, measured
//! `cargo run --release -p xtask --example capso_clutter -- CONTROL_POINTS` (300 seeded
//! maps of 20-79 x 15-59 cells, each cell blocked with probability 0.05, 0.15, 0.25 or 0.35,
//! the problems Theta\* solves; the defaults but the control points): CAPSO misses 0, 3,
//! 22 and 35 of 75, 75, 72 and 56 problems with 6 control points, 0, 0, 5 and 26 with 12,
//! 0, 0, 3 and 11 with 20; its paths are 0.99 times Theta\*'s length on average (median
//! 0.995-1.000, worst 1.42-1.52). A route that turns often needs control points to turn
//! at. With the simplification that took every chord within the tolerance (before
//! 2026-12-06; the same example with commit 38a9d64's planner-capso) it missed 0, 20, 51 and 48 with 6 control points and 0, 16, 45 and 47 with
//! 20 (more points did not help), and its paths were 1.08 times Theta\*'s on average
//! (worst 2.46).
//!
//! ```
//! use planner_api::{Budget, Cell, Grid, PathRule, Planner, Problem, Status};
//! use planner_capso::{Capso, Config};
//!
//! let grid = Grid::from_ascii("
//!     ..........
//!     ..........
//!     ....##....
//!     ....##....
//!     ....##....
//!     ..........
//! ").unwrap();
//! let problem = Problem::new(&grid, Cell::new(0, 3), Cell::new(9, 3)).unwrap();
//! let config = Config { control_points: 2, population: 10, iterations: 30, ..Config::default() };
//! let outcome = Capso::new(config).unwrap().plan(&problem, &Budget::unlimited());
//! assert_eq!(outcome.status, Status::Found);
//! let path = outcome.path.unwrap();
//! assert!(path.validate(&grid, PathRule::AnyAngle).is_ok());
//! assert_eq!(outcome.counters.get("final_collision_cells"), Some(0));
//! // 10 + 30 * 10 fitness evaluations; 31 points of the convergence curve.
//! assert_eq!(outcome.counters.get("n_fitness_evaluations"), Some(310));
//! assert_eq!(outcome.series[0].points.len(), 31);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod chaos;
pub mod collision;
pub mod guide;
pub mod spline;

use planner_api::{Budget, Cell, Counters, Outcome, Path, Planner, Problem, Series, Status};
use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use chaos::ChaoticMap;
use chaos::{rng_for_seed, unit, Chaos};
use collision::{BitGrid, Collision, SegmentCache};
use guide::Guide;
use rand_chacha::ChaCha8Rng;
use spline::Spline;

/// The registry name.
pub const NAME: &str = "capso";

/// The most control points a particle may have.
pub const MAX_CONTROL_POINTS: u32 = 20;

/// CAPSO's parameters; every field has a default (seed 002's settings where it has them).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Seed of the generator (initial positions, the chaotic sequence's start and reseeds).
    /// Default 0; the runner sets it to `seed + repeat`.
    pub seed: u64,
    /// Control points `n` between start and goal, `1 ..= 20`. Default 6 (seed 002). A route
    /// that turns often needs more: on random clutter of density 0.35, 6 points missed 35 of
    /// 56 reachable goals, 20 missed 11 (crate docs, "On random clutter").
    #[schemars(range(min = 1, max = 20))]
    pub control_points: u32,
    /// Particles, `1 ..= 10_000`. Default 30 (seed 002).
    #[schemars(range(min = 1, max = 10_000))]
    pub population: u32,
    /// Iterations `T`, `0 ..= 100_000`. Default 100 (seed 002).
    #[schemars(range(max = 100_000))]
    pub iterations: u32,
    /// Inertia weight at the start, `w_max`. Default 0.9.
    #[schemars(range(min = 0))]
    pub inertia_max: f64,
    /// Inertia weight at the end, `w_min <= w_max`. Default 0.4.
    #[schemars(range(min = 0))]
    pub inertia_min: f64,
    /// Cognitive coefficient at the start, `c1_max`. Default 2.5.
    #[schemars(range(min = 0))]
    pub cognitive_max: f64,
    /// Cognitive coefficient at the end, `c1_min <= c1_max`. Default 0.5.
    #[schemars(range(min = 0))]
    pub cognitive_min: f64,
    /// Social coefficient at the start, `c2_min`. Default 0.5.
    #[schemars(range(min = 0))]
    pub social_min: f64,
    /// Social coefficient at the end, `c2_max >= c2_min`. Default 2.5.
    pub social_max: f64,
    /// `lambda`, the PSO velocity's share of the position update (the beetle step has
    /// `1 - lambda`), in `0 ..= 1`. Default 0.4.
    #[schemars(range(min = 0, max = 1))]
    pub lambda: f64,
    /// The beetle's initial step `delta_0`, relative to the velocity (the beetle term is
    /// `xi = +/- delta v`), finite and `> 0`. Default 0.9 (a choice: the paper's value is
    /// not in its stored abstract).
    #[schemars(extend("exclusiveMinimum" = 0))]
    pub beetle_step: f64,
    /// The step's decay per iteration, `eta` in `(0, 1]`. Default 0.95.
    #[schemars(range(max = 1), extend("exclusiveMinimum" = 0))]
    pub beetle_decay: f64,
    /// Speed limit per axis as a fraction of the grid's extent on that axis, `(0, 1]`.
    /// Default 0.1.
    #[schemars(range(max = 1), extend("exclusiveMinimum" = 0))]
    pub max_speed: f64,
    /// The chaotic map for `r1`, `r2`: `"logistic"`, `"tent"`, `"sine"`, `"sinusoidal"`,
    /// `"circle"` or `"gauss"`. Default `"logistic"`.
    pub chaotic_map: ChaoticMap,
    /// Penalty weight per unit of collision (blocked cells touched plus length inside),
    /// finite and `>= 0`. Default 100.
    #[schemars(range(min = 0))]
    pub penalty: f64,
    /// Spline samples per knot interval, `1 ..= 1000`. Default 2 (issue 34: on seed 002's
    /// maps 2, 3, 4 and 5 gave mean lengths within 0.2 % of each other, 20 repeats
    /// (configs/pastar.toml's seven problems, `repeats = 20`, one `capso` label with
    /// `samples_per_segment = [2, 3, 4, 5]`: 456.09, 455.83, 455.55 and 455.24 on the first
    /// 500 x 500 problem, within 0.09 % on the others),
    /// while the CPU time per evaluation grows with the samples: 5 took 1.24 to 1.32
    /// times as long as 2, `cargo bench -p planner-capso --bench seed002 --
    /// --set=samples_per_segment=5`).
    #[schemars(range(min = 1, max = 1000))]
    pub samples_per_segment: u32,
    /// Ramer-Douglas-Peucker tolerance in cells for the sampled polyline, `0 ..= 16`.
    /// Default 2 (issue 34: on seed 002's maps 1, 1.5 and 2 gave mean lengths within
    /// 0.3 % of each other, 30 repeats, and 2 took 6 % fewer instructions per search than 1
    /// on the 200 x 200 maps, callgrind: fewer waypoints, so fewer segments to measure and
    /// a shorter simplification; every path is checked exactly whatever the tolerance).
    #[schemars(range(min = 0, max = 16))]
    pub tolerance: f64,
    /// Iterations without a better personal best after which a particle restarts near the
    /// global best, `0 ..= 100_000` (0: never). Default 10.
    #[schemars(range(max = 100_000))]
    pub restart_after: u32,
    /// The share of particles 1 .. P - 1 seeded on the guide (one exactly, the others
    /// jittered), in `0 ..= 1`. Default 0.5.
    #[schemars(range(min = 0, max = 1))]
    pub guided_share: f64,
    /// Half-width of the uniform noise of jittered guide particles and restarts, as a
    /// fraction of the grid's extent on each axis, in `0 ..= 1`. Default 0.05.
    #[schemars(range(min = 0, max = 1))]
    pub jitter: f64,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            seed: 0,
            control_points: 6,
            population: 30,
            iterations: 100,
            inertia_max: 0.9,
            inertia_min: 0.4,
            cognitive_max: 2.5,
            cognitive_min: 0.5,
            social_min: 0.5,
            social_max: 2.5,
            lambda: 0.4,
            beetle_step: 0.9,
            beetle_decay: 0.95,
            max_speed: 0.1,
            chaotic_map: ChaoticMap::Logistic,
            penalty: 100.0,
            samples_per_segment: 2,
            tolerance: 2.0,
            restart_after: 10,
            guided_share: 0.5,
            jitter: 0.05,
        }
    }
}

/// A parameter outside its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("parameter `{parameter}` must be {expected}, got {got}")]
pub struct ConfigError {
    /// The config key.
    pub parameter: &'static str,
    /// The allowed range, in words.
    pub expected: &'static str,
    /// The value given.
    pub got: String,
}

impl planner_api::ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        self.parameter
    }
}

impl Config {
    /// Checks every parameter's range; the error names the first bad key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let bad = |parameter, expected, got: String| {
            Err(ConfigError {
                parameter,
                expected,
                got,
            })
        };
        let int = |parameter, value: u32, low: u32, high: u32, expected| {
            if (low..=high).contains(&value) {
                Ok(())
            } else {
                bad(parameter, expected, value.to_string())
            }
        };
        int(
            "control_points",
            self.control_points,
            1,
            MAX_CONTROL_POINTS,
            "in 1..=20",
        )?;
        int("population", self.population, 1, 10_000, "in 1..=10000")?;
        int("iterations", self.iterations, 0, 100_000, "in 0..=100000")?;
        int(
            "restart_after",
            self.restart_after,
            0,
            100_000,
            "in 0..=100000",
        )?;
        int(
            "samples_per_segment",
            self.samples_per_segment,
            1,
            1000,
            "in 1..=1000",
        )?;
        let real = |parameter, value: f64, ok: bool, expected| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                bad(parameter, expected, value.to_string())
            }
        };
        let nonneg = "a finite number >= 0";
        real(
            "inertia_max",
            self.inertia_max,
            self.inertia_max >= 0.0,
            nonneg,
        )?;
        real(
            "inertia_min",
            self.inertia_min,
            (0.0..=self.inertia_max).contains(&self.inertia_min),
            "a finite number in 0..=inertia_max",
        )?;
        real(
            "cognitive_max",
            self.cognitive_max,
            self.cognitive_max >= 0.0,
            nonneg,
        )?;
        real(
            "cognitive_min",
            self.cognitive_min,
            (0.0..=self.cognitive_max).contains(&self.cognitive_min),
            "a finite number in 0..=cognitive_max",
        )?;
        real(
            "social_min",
            self.social_min,
            self.social_min >= 0.0,
            nonneg,
        )?;
        real(
            "social_max",
            self.social_max,
            self.social_max >= self.social_min,
            "a finite number >= social_min",
        )?;
        real(
            "lambda",
            self.lambda,
            (0.0..=1.0).contains(&self.lambda),
            "in 0..=1",
        )?;
        real(
            "beetle_step",
            self.beetle_step,
            self.beetle_step > 0.0,
            "a finite number > 0",
        )?;
        real(
            "beetle_decay",
            self.beetle_decay,
            self.beetle_decay > 0.0 && self.beetle_decay <= 1.0,
            "in (0, 1]",
        )?;
        real(
            "max_speed",
            self.max_speed,
            self.max_speed > 0.0 && self.max_speed <= 1.0,
            "in (0, 1]",
        )?;
        real("penalty", self.penalty, self.penalty >= 0.0, nonneg)?;
        real(
            "guided_share",
            self.guided_share,
            (0.0..=1.0).contains(&self.guided_share),
            "in 0..=1",
        )?;
        real(
            "jitter",
            self.jitter,
            (0.0..=1.0).contains(&self.jitter),
            "in 0..=1",
        )?;
        real(
            "tolerance",
            self.tolerance,
            (0.0..=16.0).contains(&self.tolerance),
            "in 0..=16",
        )?;
        Ok(())
    }
}

/// The fitness of one decoded particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Evaluation {
    /// `length + penalty * collision.cost()`.
    pub fitness: f64,
    /// The polyline's Euclidean length.
    pub length: f64,
    /// What its segments touch of the blocked cells.
    pub collision: Collision,
}

/// The scratch buffers of decoding, reused across evaluations.
#[derive(Debug, Clone, Default)]
struct Decoder {
    spline: Spline,
    /// The spline's samples, rounded into `cells`.
    samples: Vec<(f64, f64)>,
    cells: Vec<Cell>,
    /// The ranges of cells the simplification has yet to settle ([`douglas_peucker`]).
    stack: Vec<(usize, usize)>,
    path: Vec<Cell>,
    /// Collision per segment, cleared per search (the grid may change between them).
    cache: SegmentCache,
}

impl Decoder {
    /// Decodes the control points `position` (`x_0, y_0, x_1, y_1, ...`, in path order)
    /// into the path in `self.path` and evaluates it (crate docs, "A particle and its
    /// path"). Allocates nothing once the buffers have grown to the path's size.
    fn evaluate(
        &mut self,
        grid: &BitGrid,
        start: Cell,
        goal: Cell,
        position: &[f64],
        config: &Config,
    ) -> Evaluation {
        let point = |c: Cell| (f64::from(c.x), f64::from(c.y));
        self.spline.fit_iter(
            std::iter::once(point(start))
                .chain(position.chunks_exact(2).map(|p| (p[0], p[1])))
                .chain(std::iter::once(point(goal))),
        );
        let (max_x, max_y) = (f64::from(grid.width() - 1), f64::from(grid.height() - 1));
        // The samples first, then their cells in a loop of its own (a closure per sample
        // was a call per sample).
        self.samples.clear();
        self.spline
            .sample(config.samples_per_segment as usize, &mut self.samples);
        self.cells.clear();
        for &(x, y) in &self.samples {
            // Clamped into the grid, so the casts are in range. Rounding half up by
            // truncation (the values are >= 0 after the clamp): the same as `round` there,
            // without its library call, but for the one value `0.5 - 2^-54`, whose sum
            // with 0.5 rounds to 1 (a sample that lands there goes to cell 1, not 0).
            let cell = Cell::new(
                (x.clamp(0.0, max_x) + 0.5) as u32,
                (y.clamp(0.0, max_y) + 0.5) as u32,
            );
            if self.cells.last() != Some(&cell) {
                self.cells.push(cell);
            }
        }
        // The spline passes through start and goal exactly. The segments are measured as
        // the simplification settles them, in path order: a chord within the tolerance
        // replaces its cells when it is free or when one of them is blocked.
        let Decoder {
            cells,
            stack,
            path,
            cache,
            ..
        } = self;
        path.clear();
        path.extend(cells.first());
        let mut length = 0.0;
        let mut collision = Collision::default();
        douglas_peucker(cells, config.tolerance, stack, |a, b| {
            let (from, to) = (cells[a], cells[b]);
            if from == to {
                // A range that returns to its first cell: the path stays there.
                return true;
            }
            let (l, c) = cache.segment(grid, from, to);
            // A colliding chord is refused only where the cells it would replace are all
            // free: a curve through blocked cells collides with or without it.
            if b > a + 1
                && !c.is_free()
                && cells[a..=b]
                    .iter()
                    .all(|cell| !grid.is_blocked(cell.x, cell.y))
            {
                return false;
            }
            length += l;
            collision.add(c);
            path.push(to);
            true
        });
        Evaluation {
            fitness: length + config.penalty * collision.cost(),
            length,
            collision,
        }
    }
}

/// Ramer-Douglas-Peucker on `cells`: keeps the first and last cell and every cell farther
/// than `tolerance` from the line through its kept neighbours (the farthest first,
/// recursively), without regard to obstacles (a particle's cells are simplified so, except
/// that a colliding chord over free cells is refused: the crate docs' step 3).
pub fn simplify_cells(cells: &[Cell], tolerance: f64) -> Vec<Cell> {
    let mut kept: Vec<Cell> = cells.first().into_iter().copied().collect();
    douglas_peucker(cells, tolerance, &mut Vec::new(), |_, b| {
        kept.push(cells[b]);
        true
    });
    kept
}

/// Relative margins around `tolerance^2 |b - a|^2` outside which [`douglas_peucker`]
/// decides without dividing (far wider than the few roundings they cover).
const ABOVE: f64 = 1.0 + 1e-9;
const BELOW: f64 = 1.0 - 1e-9;

/// Ramer-Douglas-Peucker on `cells` (crate docs, step 3), depth first and the left part
/// first, with a say for the caller: a range `a..=b` with cells between whose farthest cell
/// lies within `tolerance` of the chord `a -> b` becomes that chord when `chord(a, b)` returns
/// true, and is split at its farthest cell otherwise, as a range beyond the tolerance is.
/// `chord` is called for every range that becomes a segment of the result, in path order
/// (for a range of two neighbouring cells too, whose answer is ignored), and for every
/// chord it refused, when that range is examined; `stack` is scratch.
#[inline(always)]
fn douglas_peucker(
    cells: &[Cell],
    tolerance: f64,
    stack: &mut Vec<(usize, usize)>,
    mut chord: impl FnMut(usize, usize) -> bool,
) {
    stack.clear();
    let Some(last) = cells.len().checked_sub(1) else {
        return;
    };
    let limit = tolerance * tolerance;
    if last > 0 {
        stack.push((0, last));
    }
    while let Some((a, b)) = stack.pop() {
        if b == a + 1 {
            chord(a, b);
            continue;
        }
        // The perpendicular distance to the line through cells a and b (Douglas and
        // Peucker 1973) is |cross| / |b - a|, so the farthest cell has the largest |cross|
        // (exact integers, the first of equals); only the winner is compared with the
        // tolerance. When a and b are the same cell (a path that returns to a cell), the
        // distance to it.
        let (ax, ay) = (i64::from(cells[a].x), i64::from(cells[a].y));
        let (bx, by) = (i64::from(cells[b].x), i64::from(cells[b].y));
        let (dx, dy) = (bx - ax, by - ay);
        let squared = dx * dx + dy * dy;
        let (mut farthest, mut largest) = (a, -1i64);
        for (k, &cell) in (a + 1..).zip(&cells[a + 1..b]) {
            let (wx, wy) = (i64::from(cell.x) - ax, i64::from(cell.y) - ay);
            let d = if squared == 0 {
                wx * wx + wy * wy
            } else {
                (wx * dy - wy * dx).abs()
            };
            if d > largest {
                (farthest, largest) = (k, d);
            }
        }
        // The squared distance of the farthest cell, largest^2 / squared, is compared
        // with the tolerance's square as its f64 quotient; when the product of the
        // divisor and the square is clearly above or below the dividend, the quotient is
        // too, and the division (long, on the path to an unpredictable branch) is left
        // out: the same decisions.
        let split = if squared == 0 {
            largest as f64 > limit
        } else {
            let (q, s) = ((largest as f64) * (largest as f64), squared as f64);
            let bound = limit * s;
            let (above, below) = (q > bound * ABOVE, q < bound * BELOW);
            if above | below {
                above
            } else {
                q / s > limit
            }
        };
        if split || !chord(a, b) {
            // The left part is taken first.
            stack.push((farthest, b));
            stack.push((a, farthest));
        }
    }
}

/// CAPSO's counters as plain integers (crate docs, "Outcome and counters").
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct CapsoStats {
    /// Iterations completed.
    pub n_iterations: u64,
    /// Fitness evaluations (one per particle at the start and per particle and iteration).
    pub n_fitness_evaluations: u64,
    /// Blocked cells the returned global best touches (0 for a found path).
    pub final_collision_cells: u64,
    /// The returned global best's length inside blocked cells, in thousandths of a cell.
    pub final_collision_length_milli: u64,
    /// Chaotic values replaced by a fresh draw (see [`chaos`]).
    pub n_chaos_reseeds: u64,
    /// Stagnating particles restarted.
    pub n_restarts: u64,
    /// Blocks expanded by the guide's searches ([`guide`]).
    pub n_guide_expanded: u64,
    /// The guide's block size in cells (0 when the guide found no route).
    pub guide_block: u64,
    /// Path segments measured for collision over all evaluations.
    pub n_segments: u64,
    /// Those answered by the segment cache ([`collision::SegmentCache`]).
    pub n_segment_cache_hits: u64,
}

impl CapsoStats {
    /// The counters in reporting order.
    pub fn counters(&self) -> Counters {
        Counters::new()
            .with("n_iterations", self.n_iterations)
            .with("n_fitness_evaluations", self.n_fitness_evaluations)
            .with("final_collision_cells", self.final_collision_cells)
            .with(
                "final_collision_length_milli",
                self.final_collision_length_milli,
            )
            .with("n_chaos_reseeds", self.n_chaos_reseeds)
            .with("n_restarts", self.n_restarts)
            .with("n_guide_expanded", self.n_guide_expanded)
            .with("guide_block", self.guide_block)
            .with("n_segments", self.n_segments)
            .with("n_segment_cache_hits", self.n_segment_cache_hits)
            .with("n_expanded", self.n_fitness_evaluations)
    }
}

/// The swarm's state, flat per particle and coordinate (`particle * dims + d`), kept
/// between searches so that a search allocates only when it needs more room.
#[derive(Debug, Clone, Default)]
struct Swarm {
    positions: Vec<f64>,
    velocities: Vec<f64>,
    /// The last move of each particle, `x_k - x_{k-1}` (0 before the first move and after a
    /// restart).
    moved: Vec<f64>,
    best_positions: Vec<f64>,
    best_fitness: Vec<f64>,
    /// The fitness at the current and at the previous position.
    fitness: Vec<f64>,
    previous_fitness: Vec<f64>,
    /// Iterations since the personal best last improved.
    stagnation: Vec<u32>,
    global: Vec<f64>,
}

/// The CAPSO planner. Keeps its grid copy, swarm and decoding buffers between calls.
#[derive(Debug, Clone)]
pub struct Capso {
    config: Config,
    bits: BitGrid,
    guide: Guide,
    decoder: Decoder,
    swarm: Swarm,
    stats: CapsoStats,
}

impl Capso {
    /// A planner with `config`, validated ([`Config::validate`]).
    pub fn new(config: Config) -> Result<Capso, ConfigError> {
        config.validate()?;
        Ok(Capso {
            config,
            bits: BitGrid::new(),
            guide: Guide::default(),
            decoder: Decoder::default(),
            swarm: Swarm::default(),
            stats: CapsoStats::default(),
        })
    }

    /// The validated config.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The counters of the last search.
    pub fn stats(&self) -> CapsoStats {
        self.stats
    }

    /// Decodes and evaluates control points `position` (`x_0, y_0, x_1, y_1, ...`, in path
    /// order) for `problem` as a particle is (crate docs), returning the evaluation and the
    /// path.
    pub fn evaluate(&mut self, problem: &Problem<'_>, position: &[f64]) -> (Evaluation, Path) {
        self.bits.load(problem.grid());
        self.decoder.cache.clear();
        let e = self.decoder.evaluate(
            &self.bits,
            problem.start(),
            problem.goal(),
            position,
            &self.config,
        );
        (e, Path::new(self.decoder.path.clone()))
    }

    /// The initial positions (crate docs, "Initialisation") into `self.swarm.positions`.
    fn initialise(&mut self, start: Cell, goal: Cell, rng: &mut ChaCha8Rng) {
        let config = &self.config;
        let n = config.control_points as usize;
        let particles = config.population as usize;
        let extent = [
            f64::from(self.bits.width() - 1),
            f64::from(self.bits.height() - 1),
        ];
        let jitter = [config.jitter * extent[0], config.jitter * extent[1]];
        let guided = (config.guided_share * (particles - 1) as f64).round() as usize;
        let positions = &mut self.swarm.positions;
        positions.clear();
        // Particle 0: the straight line.
        let (sx, sy) = (f64::from(start.x), f64::from(start.y));
        let (gx, gy) = (f64::from(goal.x), f64::from(goal.y));
        for k in 0..n {
            let f = (k + 1) as f64 / (n + 1) as f64;
            positions.push(sx + f * (gx - sx));
            positions.push(sy + f * (gy - sy));
        }
        // Particles 1 ..= guided: the guide's control points, then jittered copies.
        let mut guide_points = Vec::with_capacity(2 * n);
        guide::control_points(&self.guide.polyline, n, &mut guide_points);
        for p in 1..particles.min(guided + 1) {
            for (d, &v) in guide_points.iter().enumerate() {
                let noise = if p == 1 {
                    0.0
                } else {
                    (2.0 * unit(rng) - 1.0) * jitter[d % 2]
                };
                positions.push((v + noise).clamp(0.0, extent[d % 2]));
            }
        }
        // The rest: control points uniform in free space, in order along start -> goal.
        let mut points: Vec<(f64, f64)> = Vec::with_capacity(n);
        for _ in (guided + 1).max(1)..particles {
            points.clear();
            for _ in 0..n {
                points.push(free_point(&self.bits, rng, extent));
            }
            let projection = |p: &(f64, f64)| (p.0 - sx) * (gx - sx) + (p.1 - sy) * (gy - sy);
            points.sort_by(|a, b| projection(a).total_cmp(&projection(b)));
            for &(x, y) in &points {
                positions.push(x);
                positions.push(y);
            }
        }
    }
}

/// A point uniform in the box `[0, extent[0]] x [0, extent[1]]` whose nearest cell is
/// free: up to [`FREE_POINT_ATTEMPTS`] draws, else the last draw.
fn free_point(bits: &BitGrid, rng: &mut ChaCha8Rng, extent: [f64; 2]) -> (f64, f64) {
    let mut point = (0.0, 0.0);
    for _ in 0..FREE_POINT_ATTEMPTS {
        point = (unit(rng) * extent[0], unit(rng) * extent[1]);
        // In the box, so the rounded casts are in range.
        if !bits.is_blocked(point.0.round() as u32, point.1.round() as u32) {
            break;
        }
    }
    point
}

/// Draws per uniform free-space control point before the last draw is kept.
pub const FREE_POINT_ATTEMPTS: u32 = 64;

impl Planner for Capso {
    fn name(&self) -> &str {
        NAME
    }

    /// Seeded; paths are waypoints joined by segments checked by exact traversal, so they
    /// obey the any-angle rule.
    fn specs(&self) -> planner_api::PlannerSpecs {
        planner_api::PlannerSpecs::seeded(planner_api::PathSpec::AnyAngle)
    }

    fn reseed(&mut self, seed: u64) {
        self.config.seed = seed;
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let (start, goal) = (problem.start(), problem.goal());
        let mut stats = CapsoStats::default();
        let mut series = Series::new("best_fitness", "iteration");
        if start == goal {
            self.stats = stats;
            return Outcome::found(Path::new(vec![start]), stats.counters());
        }
        let cells = u64::from(grid.width()) * u64::from(grid.height());
        let bytes = BitGrid::bytes_for(grid) + cells * guide::BYTES_PER_BLOCK;
        if let Err(shortfall) = budget.check_memory(bytes, grid) {
            self.stats = stats;
            return Outcome::over_memory(shortfall, stats.counters());
        }
        self.bits.load(grid);
        self.decoder.cache.clear();
        // One clock for the whole plan: the guide's search honours its deadline and cancel
        // flag, the swarm all of it.
        let mut clock = budget.start();
        let route = self.guide.find(&self.bits, start, goal, &mut clock);
        stats.n_guide_expanded = self.guide.n_expanded;
        stats.guide_block = u64::from(self.guide.block);
        let status = match route {
            guide::Route::Found => None,
            guide::Route::Unreachable => Some(Status::NoPath),
            guide::Route::Stopped => Some(Status::BudgetExhausted),
        };
        if let Some(status) = status {
            self.stats = stats;
            return Outcome::new(status, None, stats.counters());
        }

        let config = self.config.clone();
        let n = config.control_points as usize;
        let dims = 2 * n;
        let particles = config.population as usize;
        let extent = [f64::from(grid.width() - 1), f64::from(grid.height() - 1)];
        let speed = [config.max_speed * extent[0], config.max_speed * extent[1]];
        let jitter = [config.jitter * extent[0], config.jitter * extent[1]];
        let mut rng = rng_for_seed(config.seed);

        self.initialise(start, goal, &mut rng);
        let mut chaos = Chaos::new(config.chaotic_map, &mut rng);
        let bits = &self.bits;
        let decoder = &mut self.decoder;
        let s = &mut self.swarm;
        let zeros = |v: &mut Vec<f64>| {
            v.clear();
            v.resize(particles * dims, 0.0);
        };
        zeros(&mut s.velocities);
        zeros(&mut s.moved);
        s.best_positions.clone_from(&s.positions);
        s.best_fitness.clear();
        s.fitness.clear();
        s.previous_fitness.clear();
        s.stagnation.clear();
        s.stagnation.resize(particles, 0);
        s.global.clear();
        let mut global_fitness = f64::INFINITY;
        let mut exhausted = false;

        for p in 0..particles {
            if !clock.allows(stats.n_fitness_evaluations) {
                exhausted = true;
                break;
            }
            stats.n_fitness_evaluations += 1;
            let x = &s.positions[p * dims..(p + 1) * dims];
            let f = decoder.evaluate(bits, start, goal, x, &config).fitness;
            s.best_fitness.push(f);
            s.fitness.push(f);
            s.previous_fitness.push(f);
            // The first particle is the global best until a better one comes: a fitness
            // may be infinite (a huge penalty times a collision), and the swarm still
            // needs a global best to pull towards and to restart around.
            if f < global_fitness || s.global.is_empty() {
                global_fitness = f;
                s.global.clear();
                s.global.extend_from_slice(x);
            }
        }
        if !exhausted {
            series.points.push([0.0, global_fitness]);
        }

        let total = f64::from(config.iterations.max(1));
        'iterations: for k in 1..=config.iterations {
            if exhausted {
                break;
            }
            let phase = std::f64::consts::FRAC_PI_2 * f64::from(k) / total;
            let (sin, cos) = phase.sin_cos();
            let w = config.inertia_min + (config.inertia_max - config.inertia_min) * cos;
            let c1 = config.cognitive_max - (config.cognitive_max - config.cognitive_min) * sin;
            let c2 = config.social_min + (config.social_max - config.social_min) * sin;
            let delta = config.beetle_step * config.beetle_decay.powi(k as i32 - 1);
            for p in 0..particles {
                let range = p * dims..(p + 1) * dims;
                if config.restart_after > 0 && s.stagnation[p] >= config.restart_after {
                    // Restart around the global best; the personal best is kept.
                    stats.n_restarts += 1;
                    s.stagnation[p] = 0;
                    for d in 0..dims {
                        let i = range.start + d;
                        let noise = (2.0 * unit(&mut rng) - 1.0) * jitter[d % 2];
                        s.positions[i] = (s.global[d] + noise).clamp(0.0, extent[d % 2]);
                        s.velocities[i] = 0.0;
                        s.moved[i] = 0.0;
                    }
                }
                // The coordinates in (x, y) pairs, so that each axis' limits are fixed and
                // the slices' bounds are checked once.
                let mut along = 0.0;
                let velocities = s.velocities[range.clone()].chunks_exact_mut(2);
                let positions = s.positions[range.clone()].chunks_exact(2);
                let bests = s.best_positions[range.clone()].chunks_exact(2);
                let moves = s.moved[range.clone()].chunks_exact(2);
                for (((v, x), b), (g, m)) in velocities
                    .zip(positions)
                    .zip(bests)
                    .zip(s.global.chunks_exact(2).zip(moves))
                {
                    for axis in 0..2 {
                        let (r1, r2) = (chaos.next(&mut rng), chaos.next(&mut rng));
                        let new = w * v[axis]
                            + c1 * r1 * (b[axis] - x[axis])
                            + c2 * r2 * (g[axis] - x[axis]);
                        let new = new.clamp(-speed[axis], speed[axis]);
                        v[axis] = new;
                        along += m[axis] * new;
                    }
                }
                // The antennae are the last two positions: the fitness change along the
                // last move, projected on v, says which side of x along v is downhill.
                let signal = (s.fitness[p] - s.previous_fitness[p]) * along;
                let toward = if signal > 0.0 {
                    -1.0
                } else if signal < 0.0 {
                    1.0
                } else {
                    0.0
                };
                let velocities = s.velocities[range.clone()].chunks_exact_mut(2);
                let positions = s.positions[range.clone()].chunks_exact_mut(2);
                let moves = s.moved[range.clone()].chunks_exact_mut(2);
                for ((v, x), m) in velocities.zip(positions).zip(moves) {
                    for axis in 0..2 {
                        let xi = toward * delta * v[axis];
                        let old = x[axis];
                        let new = old + config.lambda * v[axis] + (1.0 - config.lambda) * xi;
                        let clamped = new.clamp(0.0, extent[axis]);
                        if clamped != new {
                            v[axis] = 0.0;
                        }
                        x[axis] = clamped;
                        m[axis] = clamped - old;
                    }
                }
                if !clock.allows(stats.n_fitness_evaluations) {
                    exhausted = true;
                    break 'iterations;
                }
                stats.n_fitness_evaluations += 1;
                let f = decoder
                    .evaluate(bits, start, goal, &s.positions[range.clone()], &config)
                    .fitness;
                s.previous_fitness[p] = s.fitness[p];
                s.fitness[p] = f;
                if f < s.best_fitness[p] {
                    s.best_fitness[p] = f;
                    s.stagnation[p] = 0;
                    s.best_positions[range.clone()].copy_from_slice(&s.positions[range]);
                } else {
                    s.stagnation[p] += 1;
                }
            }
            for p in 0..particles {
                if s.best_fitness[p] < global_fitness {
                    global_fitness = s.best_fitness[p];
                    s.global.clear();
                    s.global
                        .extend_from_slice(&s.best_positions[p * dims..(p + 1) * dims]);
                }
            }
            stats.n_iterations += 1;
            series.points.push([f64::from(k), global_fitness]);
        }
        stats.n_chaos_reseeds = chaos.n_reseeds;
        stats.n_segments = decoder.cache.lookups;
        stats.n_segment_cache_hits = decoder.cache.hits;

        let best = (!s.global.is_empty()).then(|| {
            let e = decoder.evaluate(bits, start, goal, &s.global, &config);
            (e, Path::new(decoder.path.clone()))
        });
        let (status, path) = match best {
            Some((e, path)) => {
                stats.final_collision_cells = e.collision.cells;
                // Non-negative and finite: the cast rounds to the nearest thousandth.
                stats.final_collision_length_milli = (e.collision.length * 1000.0).round() as u64;
                let free = e.collision.is_free();
                match (exhausted, free) {
                    (false, true) => (Status::Found, Some(path)),
                    // A swarm that missed every path proved nothing.
                    (false, false) => (Status::BudgetExhausted, None),
                    (true, free) => (Status::BudgetExhausted, free.then_some(path)),
                }
            }
            None => (Status::BudgetExhausted, None),
        };
        self.stats = stats;
        let mut outcome = Outcome::new(status, path, stats.counters());
        outcome.series.push(series);
        outcome
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn config_validation_names_the_parameter() {
        let bad = |config: Config| {
            let err = Capso::new(config).unwrap_err();
            assert!(err.to_string().contains(&format!("`{}`", err.parameter)));
            err.to_string()
        };
        let with = |f: fn(&mut Config)| {
            let mut c = Config::default();
            f(&mut c);
            c
        };
        assert_eq!(
            bad(with(|c| c.control_points = 0)),
            "parameter `control_points` must be in 1..=20, got 0"
        );
        assert_eq!(
            bad(with(|c| c.control_points = 21)),
            "parameter `control_points` must be in 1..=20, got 21"
        );
        assert_eq!(
            bad(with(|c| c.population = 0)),
            "parameter `population` must be in 1..=10000, got 0"
        );
        assert_eq!(
            bad(with(|c| c.lambda = 1.5)),
            "parameter `lambda` must be in 0..=1, got 1.5"
        );
        assert_eq!(
            bad(with(|c| c.inertia_min = 1.0)).split(' ').nth(1),
            Some("`inertia_min`")
        );
        assert!(bad(with(|c| c.penalty = f64::NAN)).contains("`penalty`"));
        assert!(bad(with(|c| c.beetle_decay = 0.0)).contains("`beetle_decay`"));
        assert!(bad(with(|c| c.beetle_step = 0.0)).contains("`beetle_step`"));
        assert!(bad(with(|c| c.max_speed = 2.0)).contains("`max_speed`"));
        assert!(bad(with(|c| c.samples_per_segment = 0)).contains("`samples_per_segment`"));
        assert!(bad(with(|c| c.tolerance = -1.0)).contains("`tolerance`"));
        assert!(bad(with(|c| c.social_max = 0.1)).contains("`social_max`"));
        assert!(bad(with(|c| c.cognitive_min = 3.0)).contains("`cognitive_min`"));
        assert!(Capso::new(with(|c| c.control_points = 20)).is_ok());
    }

    #[test]
    fn config_from_toml() {
        let config: Config =
            toml::from_str("seed = 3\ncontrol_points = 4\nchaotic_map = \"tent\"").unwrap();
        assert_eq!(
            config,
            Config {
                seed: 3,
                control_points: 4,
                chaotic_map: ChaoticMap::Tent,
                ..Config::default()
            }
        );
        assert!(toml::from_str::<Config>("chaotic_map = \"henon\"").is_err());
        assert!(toml::from_str::<Config>("control_point = 4").is_err());
    }

    /// Douglas-Peucker as first written here: recursive, the squared distance divided out.
    fn reference_simplify(cells: &[Cell], tolerance: f64, a: usize, b: usize, keep: &mut [bool]) {
        if b <= a + 1 {
            return;
        }
        let (ax, ay) = (i64::from(cells[a].x), i64::from(cells[a].y));
        let (dx, dy) = (i64::from(cells[b].x) - ax, i64::from(cells[b].y) - ay);
        let squared = dx * dx + dy * dy;
        let (mut farthest, mut largest) = (a, -1i64);
        for (k, cell) in cells.iter().enumerate().take(b).skip(a + 1) {
            let (wx, wy) = (i64::from(cell.x) - ax, i64::from(cell.y) - ay);
            let d = if squared == 0 {
                wx * wx + wy * wy
            } else {
                (wx * dy - wy * dx).abs()
            };
            if d > largest {
                (farthest, largest) = (k, d);
            }
        }
        let distance = if squared == 0 {
            largest as f64
        } else {
            (largest as f64) * (largest as f64) / squared as f64
        };
        if distance > tolerance * tolerance {
            keep[farthest] = true;
            reference_simplify(cells, tolerance, a, farthest, keep);
            reference_simplify(cells, tolerance, farthest, b, keep);
        }
    }

    #[test]
    fn simplification_equals_the_dividing_reference() {
        // Random walks of up to 100 cells (more than one word of flags), with tolerances
        // that make distances equal to the tolerance common (squares of small integers
        // and of halves).
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        for round in 0..3000 {
            let n = 1 + next(100) as usize;
            let mut cells = vec![Cell::new(50, 50)];
            while cells.len() < n {
                let c = cells[cells.len() - 1];
                let step = |v: u32, d: u64| (v + d as u32).saturating_sub(2).min(99);
                cells.push(Cell::new(step(c.x, next(5)), step(c.y, next(5))));
            }
            let tolerance = [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 5.0_f64.sqrt()][round % 8];
            let mut keep = vec![false; n];
            keep[0] = true;
            keep[n - 1] = true;
            reference_simplify(&cells, tolerance, 0, n - 1, &mut keep);
            let expect: Vec<Cell> = cells
                .iter()
                .zip(&keep)
                .filter_map(|(&c, &k)| k.then_some(c))
                .collect();
            assert_eq!(
                simplify_cells(&cells, tolerance),
                expect,
                "{cells:?} {tolerance}"
            );
        }
    }

    #[test]
    fn simplification_by_hand() {
        let cells = |v: &[(u32, u32)]| v.iter().map(|&c| c.into()).collect::<Vec<Cell>>();
        // A staircase within 1 of its chord collapses to the chord.
        let stairs = cells(&[(0, 0), (1, 0), (1, 1), (2, 1), (2, 2), (3, 2), (3, 3)]);
        assert_eq!(simplify_cells(&stairs, 1.0), cells(&[(0, 0), (3, 3)]));
        // A corner 4 away from the chord (0,0)-(8,0)... (4, 4) is kept.
        let corner = cells(&[(0, 0), (2, 2), (4, 4), (6, 2), (8, 0)]);
        assert_eq!(
            simplify_cells(&corner, 1.0),
            cells(&[(0, 0), (4, 4), (8, 0)])
        );
        // Tolerance 0 keeps every cell off the chord.
        assert_eq!(simplify_cells(&stairs, 0.0).len(), 7);
    }
}
