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
//! chaotic map replaces PSO's uniform random coefficients. Only the abstract could be read
//! in the stored copies of the paper, so its equations and constants below are this
//! crate's transcription of the standard forms those words name, each a [`Config`] key;
//! seed 002 (section 4.2.2) fixes 6 control points, 30 particles and 100 iterations, the
//! defaults.
//!
//! # A particle and its path
//! A particle is the `2 n` coordinates of `n` control points in the grid's box
//! `[0, W - 1] x [0, H - 1]` (cell centres at integers). It is decoded into a path so:
//! 1. The control points are ordered by their projection on the line start -> goal (ties
//!    by index), so that a swarm of unordered points does not draw loops.
//! 2. The natural cubic spline through start, control points and goal, parameterised by
//!    chord length ([`spline`]), is sampled `samples_per_segment` times per knot interval.
//! 3. Each sample is rounded to the nearest cell (clamped into the grid); repeated cells
//!    are dropped.
//! 4. The cell polyline is simplified by Ramer-Douglas-Peucker with tolerance `tolerance`
//!    cells (every dropped cell lies within that distance of the kept segment): rounding
//!    makes a polyline through every sample zigzag by up to half a cell per sample, which
//!    adds to the length of a straight line (2.5 % on seed 002's open map: 114.65 instead
//!    of 111.80 with `tolerance = 0`, tested). The kept cells are the
//!    path's waypoints: an any-angle path ([`PathRule::AnyAngle`](planner_api::PathRule)).
//!
//! Its fitness is `length + penalty * collision`, where `length` is the polyline's
//! Euclidean length and `collision` is, over its segments, the number of blocked cells
//! touched plus the length inside them, both exact ([`collision`]). `collision = 0`
//! exactly when every segment passes [`planner_api::segment_is_free`], so a path of
//! fitness below `penalty` is valid. The fitness is that of the returned path itself.
//!
//! # The swarm
//! For iteration `k = 1 ..= T` with `s = sin(pi k / (2 T))`, `c = cos(pi k / (2 T))`:
//! - inertia `w = w_min + (w_max - w_min) c`, cognitive `c1 = c1_max - (c1_max - c1_min) s`,
//!   social `c2 = c2_min + (c2_max - c2_min) s` (the trigonometric schedule: large
//!   inertia and self-confidence early, the swarm's pull late);
//! - beetle step `delta = beetle_step * beetle_decay^(k - 1)`.
//!
//! Each particle, in order, per coordinate: `v = w v + c1 r1 (pbest - x) + c2 r2 (gbest - x)`,
//! clamped to `max_speed` times the grid's extent on that axis, where `r1` and `r2` are the
//! next two values of the chaotic sequence ([`chaos`]). Then the beetle: its antennae
//! `x_r = x + v delta / 2` and `x_l = x - v delta / 2` are evaluated, and with
//! `xi = -delta v sign(f(x_r) - f(x_l))` (a step toward the better antenna; beetle swarm
//! optimisation's form for minimisation) the position becomes
//! `x + lambda v + (1 - lambda) xi`, clamped into the box (a clamped coordinate's velocity
//! is set to 0). The new position is evaluated and the personal best updated; the global
//! best is updated after the whole swarm has moved. Antenna positions never become
//! personal bests.
//!
//! Initialisation: particle 0 has its control points evenly spaced on the straight line
//! start -> goal (so a free line is found at once, and CAPSO "produces paths identical to
//! PA-star in obstacle-free environments", seed 002 section 4.3.1); the others are uniform
//! in the box. Velocities start at 0.
//!
//! Randomness: the initial positions, the chaotic sequence's start value and its reseeds
//! come from ChaCha8 keyed by `seed` ([`chaos::rng_for_seed`]); nothing else is random, so
//! the same seed gives the same path and counters bit for bit.
//!
//! # Outcome and counters
//! After the last iteration the global best is decoded: `found` when its collision is 0,
//! else `no_path` (the search may have missed a path; the best attempt's collision is in
//! the counters). The budget counts fitness evaluations as expansions (`n_expanded`):
//! `30 + 100 * 30 * 3 = 9030` with the defaults (one per particle at the start, then three
//! per particle and iteration: two antennae and the new position). When it runs out the
//! outcome is `budget_exhausted`, with the best path so far if that one is collision-free.
//!
//! Counters, in this order: `n_iterations`, `n_fitness_evaluations`,
//! `final_collision_cells` and `final_collision_length_milli` (the returned global best's
//! blocked cells touched and its length inside them in thousandths of a cell; 0 for a
//! found path), `n_chaos_reseeds`, `n_expanded` (= `n_fitness_evaluations`). The
//! outcome's series `best_fitness` (x: `iteration`) is the global best fitness after
//! initialisation (iteration 0) and after each iteration.
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
//! // 10 + 30 * 10 * 3 fitness evaluations; 31 points of the convergence curve.
//! assert_eq!(outcome.counters.get("n_fitness_evaluations"), Some(910));
//! assert_eq!(outcome.series[0].points.len(), 31);
//! ```
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod chaos;
pub mod collision;
pub mod spline;

use planner_api::{Budget, Cell, Counters, Grid, Outcome, Path, Planner, Problem, Series, Status};
use serde::{Deserialize, Serialize};
use thiserror::Error;

pub use chaos::ChaoticMap;
use chaos::{rng_for_seed, unit, Chaos};
use collision::{segment_collision, Collision};
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
    /// Control points `n` between start and goal, `1 ..= 20`. Default 6 (seed 002).
    pub control_points: u32,
    /// Particles, `1 ..= 10_000`. Default 30 (seed 002).
    pub population: u32,
    /// Iterations `T`, `0 ..= 100_000`. Default 100 (seed 002).
    pub iterations: u32,
    /// Inertia weight at the start, `w_max`. Default 0.9.
    pub inertia_max: f64,
    /// Inertia weight at the end, `w_min <= w_max`. Default 0.4.
    pub inertia_min: f64,
    /// Cognitive coefficient at the start, `c1_max`. Default 2.5.
    pub cognitive_max: f64,
    /// Cognitive coefficient at the end, `c1_min <= c1_max`. Default 0.5.
    pub cognitive_min: f64,
    /// Social coefficient at the start, `c2_min`. Default 0.5.
    pub social_min: f64,
    /// Social coefficient at the end, `c2_max >= c2_min`. Default 2.5.
    pub social_max: f64,
    /// `lambda`, the PSO velocity's share of the position update (the beetle step has
    /// `1 - lambda`), in `0 ..= 1`. Default 0.4.
    pub lambda: f64,
    /// The beetle's initial step `delta_0` (relative to the velocity; the antennae are
    /// `delta v / 2` either side), finite and `> 0`. Default 0.9.
    pub beetle_step: f64,
    /// The step's decay per iteration, `eta` in `(0, 1]`. Default 0.95.
    pub beetle_decay: f64,
    /// Speed limit per axis as a fraction of the grid's extent on that axis, `(0, 1]`.
    /// Default 0.1.
    pub max_speed: f64,
    /// The chaotic map for `r1`, `r2`: `"logistic"`, `"tent"`, `"sine"`, `"sinusoidal"`,
    /// `"circle"` or `"gauss"`. Default `"logistic"`.
    pub chaotic_map: ChaoticMap,
    /// Penalty weight per unit of collision (blocked cells touched plus length inside),
    /// finite and `>= 0`. Default 100.
    pub penalty: f64,
    /// Spline samples per knot interval, `1 ..= 1000`. Default 10.
    pub samples_per_segment: u32,
    /// Ramer-Douglas-Peucker tolerance in cells for the sampled polyline, `0 ..= 16`.
    /// Default 1.
    pub tolerance: f64,
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
            samples_per_segment: 10,
            tolerance: 1.0,
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
    knots: Vec<(f64, f64)>,
    samples: Vec<(f64, f64)>,
    cells: Vec<Cell>,
    keep: Vec<bool>,
    stack: Vec<(usize, usize)>,
    order: Vec<usize>,
    path: Vec<Cell>,
}

impl Decoder {
    /// Decodes the control points `position` (`x_0, y_0, x_1, y_1, ...`) into the path in
    /// `self.path` and evaluates it (crate docs, "A particle and its path").
    fn evaluate(
        &mut self,
        grid: &Grid,
        start: Cell,
        goal: Cell,
        position: &[f64],
        config: &Config,
    ) -> Evaluation {
        let (sx, sy) = (f64::from(start.x), f64::from(start.y));
        let (gx, gy) = (f64::from(goal.x), f64::from(goal.y));
        let (ux, uy) = (gx - sx, gy - sy);
        let n = position.len() / 2;
        self.order.clear();
        self.order.extend(0..n);
        let projection = |k: usize| (position[2 * k] - sx) * ux + (position[2 * k + 1] - sy) * uy;
        self.order
            .sort_unstable_by(|&a, &b| projection(a).total_cmp(&projection(b)).then(a.cmp(&b)));
        self.knots.clear();
        self.knots.push((sx, sy));
        for &k in &self.order {
            self.knots.push((position[2 * k], position[2 * k + 1]));
        }
        self.knots.push((gx, gy));
        self.spline.fit(&self.knots);
        self.samples.clear();
        self.spline
            .sample(config.samples_per_segment as usize, &mut self.samples);

        let (max_x, max_y) = (f64::from(grid.width() - 1), f64::from(grid.height() - 1));
        self.cells.clear();
        for &(x, y) in &self.samples {
            // Clamped into the grid, so the casts are exact and in range.
            let cell = Cell::new(
                x.round().clamp(0.0, max_x) as u32,
                y.round().clamp(0.0, max_y) as u32,
            );
            if self.cells.last() != Some(&cell) {
                self.cells.push(cell);
            }
        }
        // The spline passes through start and goal exactly.
        simplify(
            &self.cells,
            config.tolerance,
            &mut self.keep,
            &mut self.stack,
        );
        self.path.clear();
        for (&cell, &keep) in self.cells.iter().zip(&self.keep) {
            if keep && self.path.last() != Some(&cell) {
                self.path.push(cell);
            }
        }
        let mut length = 0.0;
        let mut collision = Collision::default();
        for pair in self.path.windows(2) {
            length += pair[0].euclidean(pair[1]);
            collision.add(segment_collision(grid, pair[0], pair[1]));
        }
        Evaluation {
            fitness: length + config.penalty * collision.cost(),
            length,
            collision,
        }
    }
}

/// Ramer-Douglas-Peucker on `cells`: keeps the first and last cell and every cell farther
/// than `tolerance` from the segment between its kept neighbours (the farthest first,
/// recursively), as a particle's sampled cells are simplified.
pub fn simplify_cells(cells: &[Cell], tolerance: f64) -> Vec<Cell> {
    let (mut keep, mut stack) = (Vec::new(), Vec::new());
    simplify(cells, tolerance, &mut keep, &mut stack);
    cells
        .iter()
        .zip(&keep)
        .filter_map(|(&c, &k)| k.then_some(c))
        .collect()
}

/// [`simplify_cells`] into the flags `keep` (one per cell); `keep` and `stack` are scratch,
/// resized here.
fn simplify(cells: &[Cell], tolerance: f64, keep: &mut Vec<bool>, stack: &mut Vec<(usize, usize)>) {
    keep.clear();
    keep.resize(cells.len(), false);
    let Some(last) = cells.len().checked_sub(1) else {
        return;
    };
    keep[0] = true;
    keep[last] = true;
    stack.clear();
    stack.push((0, last));
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        // Squared distances: the same order as distances, without a square root.
        let (mut farthest, mut distance) = (a, -1.0);
        for (k, &cell) in cells.iter().enumerate().take(b).skip(a + 1) {
            let d = squared_point_segment_distance(cell, cells[a], cells[b]);
            if d > distance {
                (farthest, distance) = (k, d);
            }
        }
        if distance > tolerance * tolerance {
            keep[farthest] = true;
            stack.push((farthest, b));
            stack.push((a, farthest));
        }
    }
}

/// The squared Euclidean distance from the centre of `p` to the segment between the
/// centres of `a` and `b`.
fn squared_point_segment_distance(p: Cell, a: Cell, b: Cell) -> f64 {
    let (px, py) = (f64::from(p.x), f64::from(p.y));
    let (ax, ay) = (f64::from(a.x), f64::from(a.y));
    let (dx, dy) = (f64::from(b.x) - ax, f64::from(b.y) - ay);
    let squared = dx * dx + dy * dy;
    let t = if squared == 0.0 {
        0.0
    } else {
        (((px - ax) * dx + (py - ay) * dy) / squared).clamp(0.0, 1.0)
    };
    let (ex, ey) = (px - ax - t * dx, py - ay - t * dy);
    ex * ex + ey * ey
}

/// CAPSO's counters as plain integers (crate docs, "Outcome and counters").
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct CapsoStats {
    /// Iterations completed.
    pub n_iterations: u64,
    /// Fitness evaluations (initial particles, antennae, moved particles).
    pub n_fitness_evaluations: u64,
    /// Blocked cells the returned global best touches (0 for a found path).
    pub final_collision_cells: u64,
    /// The returned global best's length inside blocked cells, in thousandths of a cell.
    pub final_collision_length_milli: u64,
    /// Chaotic values replaced by a fresh draw (see [`chaos`]).
    pub n_chaos_reseeds: u64,
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
            .with("n_expanded", self.n_fitness_evaluations)
    }
}

/// The CAPSO planner. Keeps its swarm and decoding buffers between calls.
#[derive(Debug, Clone)]
pub struct Capso {
    config: Config,
    decoder: Decoder,
    positions: Vec<f64>,
    velocities: Vec<f64>,
    best_positions: Vec<f64>,
    best_fitness: Vec<f64>,
    global: Vec<f64>,
    antenna: Vec<f64>,
    stats: CapsoStats,
}

impl Capso {
    /// A planner with `config`, validated ([`Config::validate`]).
    pub fn new(config: Config) -> Result<Capso, ConfigError> {
        config.validate()?;
        Ok(Capso {
            config,
            decoder: Decoder::default(),
            positions: Vec::new(),
            velocities: Vec::new(),
            best_positions: Vec::new(),
            best_fitness: Vec::new(),
            global: Vec::new(),
            antenna: Vec::new(),
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

    /// Decodes and evaluates control points `position` (`x_0, y_0, x_1, y_1, ...`) for
    /// `problem` as a particle is (crate docs), returning the evaluation and the path.
    pub fn evaluate(&mut self, problem: &Problem<'_>, position: &[f64]) -> (Evaluation, Path) {
        let e = self.decoder.evaluate(
            problem.grid(),
            problem.start(),
            problem.goal(),
            position,
            &self.config,
        );
        (e, Path::new(self.decoder.path.clone()))
    }
}

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
        let config = self.config.clone();
        let mut stats = CapsoStats::default();
        let mut series = Series::new("best_fitness", "iteration");
        if start == goal {
            self.stats = stats;
            return Outcome::found(Path::new(vec![start]), stats.counters());
        }
        let n = config.control_points as usize;
        let dims = 2 * n;
        let particles = config.population as usize;
        let extent = [f64::from(grid.width() - 1), f64::from(grid.height() - 1)];
        let speed = [config.max_speed * extent[0], config.max_speed * extent[1]];
        let mut rng = rng_for_seed(config.seed);
        let mut clock = budget.start();

        self.positions.clear();
        for p in 0..particles {
            for k in 0..n {
                let (x, y) = if p == 0 {
                    let f = (k + 1) as f64 / (n + 1) as f64;
                    (
                        f64::from(start.x) + f * (f64::from(goal.x) - f64::from(start.x)),
                        f64::from(start.y) + f * (f64::from(goal.y) - f64::from(start.y)),
                    )
                } else {
                    (unit(&mut rng) * extent[0], unit(&mut rng) * extent[1])
                };
                self.positions.push(x);
                self.positions.push(y);
            }
        }
        let mut chaos = Chaos::new(config.chaotic_map, &mut rng);
        self.velocities.clear();
        self.velocities.resize(particles * dims, 0.0);
        self.best_positions.clone_from(&self.positions);
        self.best_fitness.clear();
        self.global.clear();
        let mut global_fitness = f64::INFINITY;
        let mut exhausted = false;

        for p in 0..particles {
            if !clock.allows(stats.n_fitness_evaluations) {
                exhausted = true;
                break;
            }
            stats.n_fitness_evaluations += 1;
            let x = &self.positions[p * dims..(p + 1) * dims];
            let f = self.decoder.evaluate(grid, start, goal, x, &config).fitness;
            self.best_fitness.push(f);
            if f < global_fitness {
                global_fitness = f;
                self.global.clear();
                self.global.extend_from_slice(x);
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
            let (s, c) = phase.sin_cos();
            let w = config.inertia_min + (config.inertia_max - config.inertia_min) * c;
            let c1 = config.cognitive_max - (config.cognitive_max - config.cognitive_min) * s;
            let c2 = config.social_min + (config.social_max - config.social_min) * s;
            let delta = config.beetle_step * config.beetle_decay.powi(k as i32 - 1);
            for p in 0..particles {
                let range = p * dims..(p + 1) * dims;
                for d in 0..dims {
                    let i = range.start + d;
                    let (r1, r2) = (chaos.next(&mut rng), chaos.next(&mut rng));
                    let x = self.positions[i];
                    let v = w * self.velocities[i]
                        + c1 * r1 * (self.best_positions[i] - x)
                        + c2 * r2 * (self.global[d] - x);
                    self.velocities[i] = v.clamp(-speed[d % 2], speed[d % 2]);
                }
                // The antennae, each side of x along v.
                let mut antenna_fitness = [0.0; 2];
                for (side, sign) in [(0, 1.0), (1, -1.0)] {
                    if !clock.allows(stats.n_fitness_evaluations) {
                        exhausted = true;
                        break 'iterations;
                    }
                    stats.n_fitness_evaluations += 1;
                    self.antenna.clear();
                    for d in 0..dims {
                        let i = range.start + d;
                        let a = self.positions[i] + sign * self.velocities[i] * delta / 2.0;
                        self.antenna.push(a.clamp(0.0, extent[d % 2]));
                    }
                    antenna_fitness[side] = self
                        .decoder
                        .evaluate(grid, start, goal, &self.antenna, &config)
                        .fitness;
                }
                let toward = match antenna_fitness[0].total_cmp(&antenna_fitness[1]) {
                    std::cmp::Ordering::Less => 1.0,
                    std::cmp::Ordering::Greater => -1.0,
                    std::cmp::Ordering::Equal => 0.0,
                };
                for d in 0..dims {
                    let i = range.start + d;
                    let v = self.velocities[i];
                    let xi = toward * delta * v;
                    let x = self.positions[i] + config.lambda * v + (1.0 - config.lambda) * xi;
                    let clamped = x.clamp(0.0, extent[d % 2]);
                    if clamped != x {
                        self.velocities[i] = 0.0;
                    }
                    self.positions[i] = clamped;
                }
                if !clock.allows(stats.n_fitness_evaluations) {
                    exhausted = true;
                    break 'iterations;
                }
                stats.n_fitness_evaluations += 1;
                let f = self
                    .decoder
                    .evaluate(grid, start, goal, &self.positions[range.clone()], &config)
                    .fitness;
                if f < self.best_fitness[p] {
                    self.best_fitness[p] = f;
                    self.best_positions[range.clone()].copy_from_slice(&self.positions[range]);
                }
            }
            for p in 0..particles {
                if self.best_fitness[p] < global_fitness {
                    global_fitness = self.best_fitness[p];
                    self.global.clear();
                    self.global
                        .extend_from_slice(&self.best_positions[p * dims..(p + 1) * dims]);
                }
            }
            stats.n_iterations += 1;
            series.points.push([f64::from(k), global_fitness]);
        }
        stats.n_chaos_reseeds = chaos.n_reseeds;

        let best = (!self.global.is_empty()).then(|| {
            let e = self
                .decoder
                .evaluate(grid, start, goal, &self.global, &config);
            (e, Path::new(self.decoder.path.clone()))
        });
        let (status, path) = match best {
            Some((e, path)) => {
                stats.final_collision_cells = e.collision.cells;
                // Non-negative and finite: the cast rounds to the nearest thousandth.
                stats.final_collision_length_milli = (e.collision.length * 1000.0).round() as u64;
                let free = e.collision.is_free();
                match (exhausted, free) {
                    (false, true) => (Status::Found, Some(path)),
                    (false, false) => (Status::NoPath, None),
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
