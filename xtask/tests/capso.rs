//! CAPSO's seeded swarm written again from planner-capso's crate docs, and the planner held
//! to it: every snapshotted CAPSO run and 120 small random problems give the same status,
//! the same path and the same counters, the swarm's own (`n_segments`,
//! `n_segment_cache_hits`, `n_chaos_reseeds`, `n_restarts`) included.
//!
//! The reference rewrites what the swarm decides: the initial positions and the order in
//! which they draw from the generator, the chaotic sequence with its reseeds, the velocity
//! and beetle updates, clamping, restarts, personal and global bests, the decoding's
//! rounding, deduplication and Ramer-Douglas-Peucker simplification with its refusal of
//! colliding chords over free cells, the fitness, the
//! segment cache's hits and the outcome. It takes from planner-capso, unchanged, the
//! pieces that are tested on their own and whose floating-point results the swarm's
//! trajectory depends on to the last bit: the spline ([`planner_capso::spline`]), the
//! guide's control points on its polyline ([`planner_capso::guide::control_points`]; the
//! polyline itself comes from [`planner_testkit::reference_capso_guide`]), the chaotic
//! maps' formulas ([`ChaoticMap::step`]) and the generator ([`chaos::rng_for_seed`],
//! [`chaos::unit`]). A segment's collision is measured on the grid
//! ([`collision::segment_collision`], held to a brute force in planner-capso's tests),
//! not on the planner's packed copy.
//!
//! Seventeen plausible changes to the reference fail both tests: the restart condition
//! (`>` for `>=`), the cache's slot (`>> 51`), ties of the first and of the updated global
//! best (`<=`), the beetle's direction, the final decoding counted, the simplification's
//! comparison (`>=`), its tie among equally far cells (the last, not the first), a chord
//! within the tolerance taken though it collides, every colliding chord refused (blocked
//! cells under it or not), its ends left out of the cells that must be free, the right
//! part settled first, samples
//! rounded down, one axis' speed limit for both, the guided share rounded down, a personal
//! best that does not reset the stagnation count, and free points not redrawn. One change
//! passes: no reseed when a chaotic step returns its own value (the crate's rule); no
//! sequence here met a fixed point.

use planner_api::{Budget, Cell, Grid, Planner, Problem, Status};
use planner_capso::chaos::{self, ChaoticMap, EDGE};
use planner_capso::collision;
use planner_capso::spline::Spline;
use planner_capso::{Capso, Config};
use rand_chacha::ChaCha8Rng;

use crate::common;

/// The reference's outcome: status, path and the planner's counters in its order.
#[derive(Debug, Clone, PartialEq)]
struct SwarmRun {
    status: Status,
    path: Option<Vec<Cell>>,
    counters: Vec<(&'static str, u64)>,
}

/// The counters the reference counts, in planner-capso's order.
#[derive(Debug, Clone, Copy, Default)]
struct Counts {
    iterations: u64,
    evaluations: u64,
    final_cells: u64,
    final_length_milli: u64,
    reseeds: u64,
    restarts: u64,
    guide_expanded: u64,
    guide_block: u64,
    segments: u64,
    cache_hits: u64,
}

impl Counts {
    fn named(&self) -> Vec<(&'static str, u64)> {
        vec![
            ("n_iterations", self.iterations),
            ("n_fitness_evaluations", self.evaluations),
            ("final_collision_cells", self.final_cells),
            ("final_collision_length_milli", self.final_length_milli),
            ("n_chaos_reseeds", self.reseeds),
            ("n_restarts", self.restarts),
            ("n_guide_expanded", self.guide_expanded),
            ("guide_block", self.guide_block),
            ("n_segments", self.segments),
            ("n_segment_cache_hits", self.cache_hits),
            ("n_expanded", self.evaluations),
        ]
    }
}

/// The chaotic sequence (planner-capso's `chaos` docs): starts at a uniform draw inside
/// `[EDGE, 1 - EDGE]` (draws outside are redrawn); each next value is the map's step, or a
/// fresh such draw (a reseed) when the step leaves that interval or stays where it was.
struct Sequence {
    map: ChaoticMap,
    z: f64,
    reseeds: u64,
}

fn inside(rng: &mut ChaCha8Rng) -> f64 {
    loop {
        let u = chaos::unit(rng);
        if (EDGE..=1.0 - EDGE).contains(&u) {
            return u;
        }
    }
}

impl Sequence {
    fn next(&mut self, rng: &mut ChaCha8Rng) -> f64 {
        let z = self.map.step(self.z);
        if !(EDGE..=1.0 - EDGE).contains(&z) || z == self.z {
            self.reseeds += 1;
            self.z = inside(rng);
        } else {
            self.z = z;
        }
        self.z
    }
}

/// Segments measured in one search, as planner-capso's direct-mapped cache of 512 entries
/// holds them: segment `a -> b` lives in slot `(k * 0x9e3779b97f4a7c15) >> 52` (mod 512,
/// wrapping product) of `k = ax << 48 ^ ay << 32 ^ bx << 16 ^ by`, and a lookup is a hit
/// when that slot holds the same segment, measured earlier in the search.
struct Cache {
    slots: Vec<Option<(Cell, Cell)>>,
    lookups: u64,
    hits: u64,
}

impl Cache {
    fn new() -> Cache {
        Cache {
            slots: vec![None; 512],
            lookups: 0,
            hits: 0,
        }
    }

    fn note(&mut self, a: Cell, b: Cell) {
        self.lookups += 1;
        let key =
            u64::from(a.x) << 48 ^ u64::from(a.y) << 32 ^ u64::from(b.x) << 16 ^ u64::from(b.y);
        let slot = (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 52) as usize % 512;
        if self.slots[slot] == Some((a, b)) {
            self.hits += 1;
        } else {
            self.slots[slot] = Some((a, b));
        }
    }
}

/// A particle's polyline as it is simplified and measured.
struct Decoding<'a> {
    grid: &'a Grid,
    cells: Vec<Cell>,
    tolerance: f64,
    cache: Option<&'a mut Cache>,
    path: Vec<Cell>,
    length: f64,
    collision: collision::Collision,
}

impl Decoding<'_> {
    /// The segment between cells `a` and `b`: noted by the cache, its length as the square
    /// root of the sum of squares, and its collision measured on the grid.
    fn measure(&mut self, a: usize, b: usize) -> (f64, collision::Collision) {
        let (from, to) = (self.cells[a], self.cells[b]);
        if let Some(cache) = self.cache.as_deref_mut() {
            cache.note(from, to);
        }
        let (dx, dy) = (
            f64::from(from.x.abs_diff(to.x)),
            f64::from(from.y.abs_diff(to.y)),
        );
        let length = (dx * dx + dy * dy).sqrt();
        (length, collision::segment_collision(self.grid, from, to))
    }

    /// Adds the segment to cell `b` to the path.
    fn take(&mut self, b: usize, (length, collision): (f64, collision::Collision)) {
        self.length += length;
        self.collision.add(collision);
        self.path.push(self.cells[b]);
    }

    /// Ramer-Douglas-Peucker between cells `a` and `b` (crate docs, step 3): two
    /// neighbouring cells are a segment; otherwise the farthest cell between them from the
    /// line through them (the first of equals) is found, and when its distance is at most
    /// `tolerance` (the squared distance compared as `cross^2 / |b - a|^2 > tolerance^2` in
    /// `f64`; for `a` and `b` the same cell, the squared distance to it) and the chord
    /// `a -> b` is free or one of the cells `a ..= b` is blocked, the chord is the segment
    /// (a chord from a cell back to itself is no segment: the path stays); else both parts,
    /// the left one first.
    fn settle(&mut self, a: usize, b: usize) {
        if b == a + 1 {
            let measured = self.measure(a, b);
            self.take(b, measured);
            return;
        }
        let cells = &self.cells;
        let (ax, ay) = (i64::from(cells[a].x), i64::from(cells[a].y));
        let (dx, dy) = (i64::from(cells[b].x) - ax, i64::from(cells[b].y) - ay);
        let squared = dx * dx + dy * dy;
        let mut farthest = a + 1;
        let mut largest = -1i64;
        for (k, cell) in cells.iter().enumerate().take(b).skip(a + 1) {
            let (wx, wy) = (i64::from(cell.x) - ax, i64::from(cell.y) - ay);
            let d = match squared {
                0 => wx * wx + wy * wy,
                _ => (wx * dy - wy * dx).abs(),
            };
            if d > largest {
                (farthest, largest) = (k, d);
            }
        }
        let limit = self.tolerance * self.tolerance;
        let beyond = match squared {
            0 => largest as f64 > limit,
            _ => (largest as f64) * (largest as f64) / squared as f64 > limit,
        };
        if !beyond {
            if squared == 0 {
                return;
            }
            let measured = self.measure(a, b);
            let cells_free = self.cells[a..=b].iter().all(|&c| self.grid.is_free(c));
            if measured.1.cells == 0 || !cells_free {
                self.take(b, measured);
                return;
            }
        }
        self.settle(a, farthest);
        self.settle(farthest, b);
    }
}

/// A particle's path and fitness (crate docs, "A particle and its path").
fn decode(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    position: &[f64],
    config: &Config,
    cache: Option<&mut Cache>,
) -> (f64, Vec<Cell>, collision::Collision) {
    let mut knots = vec![(f64::from(start.x), f64::from(start.y))];
    knots.extend(position.chunks_exact(2).map(|p| (p[0], p[1])));
    knots.push((f64::from(goal.x), f64::from(goal.y)));
    let mut spline = Spline::new();
    spline.fit(&knots);
    let mut samples = Vec::new();
    spline.sample(config.samples_per_segment as usize, &mut samples);
    let (max_x, max_y) = (f64::from(grid.width() - 1), f64::from(grid.height() - 1));
    let mut cells: Vec<Cell> = Vec::new();
    for (x, y) in samples {
        let cell = Cell::new(
            x.clamp(0.0, max_x).round() as u32,
            y.clamp(0.0, max_y).round() as u32,
        );
        if cells.last() != Some(&cell) {
            cells.push(cell);
        }
    }
    let last = cells.len() - 1;
    let mut decoding = Decoding {
        grid,
        path: vec![cells[0]],
        cells,
        tolerance: config.tolerance,
        cache,
        length: 0.0,
        collision: collision::Collision::default(),
    };
    decoding.settle(0, last);
    let total = decoding.collision;
    let fitness = decoding.length + config.penalty * (total.cells as f64 + total.length);
    (fitness, decoding.path, total)
}

/// CAPSO on `grid` from `start` to `goal` with `config` and an unlimited budget, written
/// from planner-capso's crate docs ("The swarm", "Initialisation", "Outcome and counters").
fn reference_capso(grid: &Grid, start: Cell, goal: Cell, config: &Config) -> SwarmRun {
    let mut counts = Counts::default();
    if start == goal {
        return SwarmRun {
            status: Status::Found,
            path: Some(vec![start]),
            counters: counts.named(),
        };
    }
    let guide = planner_testkit::reference_capso_guide(grid, start, goal);
    counts.guide_expanded = guide.n_expanded;
    counts.guide_block = u64::from(guide.block);
    if guide.block == 0 {
        return SwarmRun {
            status: Status::NoPath,
            path: None,
            counters: counts.named(),
        };
    }
    let n = config.control_points as usize;
    let dims = 2 * n;
    let count = config.population as usize;
    let extent = [f64::from(grid.width() - 1), f64::from(grid.height() - 1)];
    let jitter = [config.jitter * extent[0], config.jitter * extent[1]];
    let speed = [config.max_speed * extent[0], config.max_speed * extent[1]];
    let mut rng = chaos::rng_for_seed(config.seed);

    // Initial positions, particle by particle.
    let mut x: Vec<Vec<f64>> = Vec::new();
    let (sx, sy) = (f64::from(start.x), f64::from(start.y));
    let (gx, gy) = (f64::from(goal.x), f64::from(goal.y));
    x.push(
        (1..=n)
            .flat_map(|k| {
                let f = k as f64 / (n + 1) as f64;
                [sx + f * (gx - sx), sy + f * (gy - sy)]
            })
            .collect(),
    );
    let guided = (config.guided_share * (count - 1) as f64).round() as usize;
    let mut on_guide = Vec::new();
    planner_capso::guide::control_points(&guide.polyline, n, &mut on_guide);
    for p in 1..=guided.min(count - 1) {
        let mut position = Vec::new();
        for (d, &v) in on_guide.iter().enumerate() {
            let noise = match p {
                1 => 0.0,
                _ => (2.0 * chaos::unit(&mut rng) - 1.0) * jitter[d % 2],
            };
            position.push((v + noise).clamp(0.0, extent[d % 2]));
        }
        x.push(position);
    }
    while x.len() < count {
        let mut points = Vec::new();
        for _ in 0..n {
            let mut point = (0.0, 0.0);
            for _ in 0..planner_capso::FREE_POINT_ATTEMPTS {
                point = (
                    chaos::unit(&mut rng) * extent[0],
                    chaos::unit(&mut rng) * extent[1],
                );
                let cell = Cell::new(point.0.round() as u32, point.1.round() as u32);
                if grid.is_free(cell) {
                    break;
                }
            }
            points.push(point);
        }
        let along = |p: &(f64, f64)| (p.0 - sx) * (gx - sx) + (p.1 - sy) * (gy - sy);
        points.sort_by(|a, b| along(a).total_cmp(&along(b)));
        x.push(points.iter().flat_map(|&(a, b)| [a, b]).collect());
    }
    let mut sequence = Sequence {
        map: config.chaotic_map,
        z: inside(&mut rng),
        reseeds: 0,
    };
    let mut cache = Cache::new();
    let mut fitness_of = |position: &[f64], counts: &mut Counts| {
        counts.evaluations += 1;
        decode(grid, start, goal, position, config, Some(&mut cache)).0
    };

    let mut v = vec![vec![0.0; dims]; count];
    let mut moved = vec![vec![0.0; dims]; count];
    let mut best = x.clone();
    let mut f = Vec::new();
    for position in &x {
        f.push(fitness_of(position, &mut counts));
    }
    let mut f_best = f.clone();
    let mut f_before = f.clone();
    let mut stagnant = vec![0u32; count];
    // The first particle unless a later one is strictly better.
    let mut global = 0;
    for p in 1..count {
        if f[p] < f[global] {
            global = p;
        }
    }
    let mut g = x[global].clone();
    let mut g_fitness = f[global];

    for k in 1..=config.iterations {
        let phase = std::f64::consts::FRAC_PI_2 * f64::from(k) / f64::from(config.iterations);
        let (s, c) = phase.sin_cos();
        let w = config.inertia_min + (config.inertia_max - config.inertia_min) * c;
        let c1 = config.cognitive_max - (config.cognitive_max - config.cognitive_min) * s;
        let c2 = config.social_min + (config.social_max - config.social_min) * s;
        let delta = config.beetle_step * config.beetle_decay.powi(k as i32 - 1);
        for p in 0..count {
            if config.restart_after > 0 && stagnant[p] >= config.restart_after {
                counts.restarts += 1;
                stagnant[p] = 0;
                for d in 0..dims {
                    let noise = (2.0 * chaos::unit(&mut rng) - 1.0) * jitter[d % 2];
                    x[p][d] = (g[d] + noise).clamp(0.0, extent[d % 2]);
                    v[p][d] = 0.0;
                    moved[p][d] = 0.0;
                }
            }
            // Velocity, and the last move's projection on it.
            let mut projection = 0.0;
            for d in 0..dims {
                let r1 = sequence.next(&mut rng);
                let r2 = sequence.next(&mut rng);
                let new =
                    w * v[p][d] + c1 * r1 * (best[p][d] - x[p][d]) + c2 * r2 * (g[d] - x[p][d]);
                v[p][d] = new.clamp(-speed[d % 2], speed[d % 2]);
                projection += moved[p][d] * v[p][d];
            }
            // The beetle steps against the sign of df (u . v).
            let slope = (f[p] - f_before[p]) * projection;
            let toward = match slope {
                s if s > 0.0 => -1.0,
                s if s < 0.0 => 1.0,
                _ => 0.0,
            };
            for d in 0..dims {
                let xi = toward * delta * v[p][d];
                let old = x[p][d];
                let new = old + config.lambda * v[p][d] + (1.0 - config.lambda) * xi;
                let inside_box = new.clamp(0.0, extent[d % 2]);
                if inside_box != new {
                    v[p][d] = 0.0;
                }
                x[p][d] = inside_box;
                moved[p][d] = inside_box - old;
            }
            let fitness = fitness_of(&x[p], &mut counts);
            f_before[p] = f[p];
            f[p] = fitness;
            if fitness < f_best[p] {
                f_best[p] = fitness;
                best[p] = x[p].clone();
                stagnant[p] = 0;
            } else {
                stagnant[p] += 1;
            }
        }
        for p in 0..count {
            if f_best[p] < g_fitness {
                g_fitness = f_best[p];
                g = best[p].clone();
            }
        }
        counts.iterations += 1;
    }
    counts.reseeds = sequence.reseeds;
    counts.segments = cache.lookups;
    counts.cache_hits = cache.hits;
    // The global best decoded once more, outside the counts.
    let (_, path, hit) = decode(grid, start, goal, &g, config, None);
    counts.final_cells = hit.cells;
    counts.final_length_milli = (hit.length * 1000.0).round() as u64;
    let found = hit.cells == 0;
    SwarmRun {
        // A swarm that missed every path proved nothing: its iterations ran out.
        status: if found {
            Status::Found
        } else {
            Status::BudgetExhausted
        },
        path: found.then_some(path),
        counters: counts.named(),
    }
}

/// The planner's run in the reference's terms.
fn planner_run(grid: &Grid, start: Cell, goal: Cell, config: &Config) -> SwarmRun {
    let problem = Problem::new(grid, start, goal).unwrap();
    let outcome = Capso::new(config.clone())
        .unwrap()
        .plan(&problem, &Budget::unlimited());
    let reference = Counts::default().named();
    let counters = reference
        .iter()
        .map(|&(name, _)| (name, outcome.counters.get(name).unwrap()))
        .collect();
    let names: Vec<&str> = outcome.counters.iter().map(|(name, _)| name).collect();
    let expected: Vec<&str> = reference.iter().map(|&(name, _)| name).collect();
    assert_eq!(names, expected, "the planner's counters and their order");
    SwarmRun {
        status: outcome.status,
        path: outcome.path.map(|p| p.cells().to_vec()),
        counters,
    }
}

/// Every CAPSO run of the snapshotted configs (configs/pastar.toml's seven problems and
/// configs/capso-control-points.toml's four control-point counts, two repeats each, seed
/// `seed + repeat`) is the reference swarm's: status, path length and every counter.
#[test]
fn every_capso_run_is_the_reference_swarm() {
    let entry = planner_registry::find("capso").unwrap();
    let n_checked = common::for_each_snapshotted_run(entry.name, |path, map, params, r| {
        let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
        let resolved = (entry.factory)(params).unwrap().resolved().clone();
        let mut config: Config = serde_json::from_value(resolved).unwrap();
        config.seed = r.seed.unwrap();
        let reference = reference_capso(&map.grid, r.start, r.goal, &config);
        assert_eq!(r.status.as_str(), reference.status.as_str(), "{what}");
        for &(name, value) in &reference.counters {
            assert_eq!(r.counters.get(name), Some(value), "{what}: {name}");
        }
        let length = reference
            .path
            .map(|cells| planner_api::Path::new(cells).metrics().length);
        assert_eq!(r.length, length, "{what}");
    });
    assert_eq!(n_checked, 14 + 8);
}

/// Small random problems (open and cluttered grids, reachable and not) under configs that
/// vary every parameter the swarm reads: the planner's outcome is the reference's.
#[test]
fn capso_is_the_reference_swarm_on_random_problems() {
    let maps = ChaoticMap::ALL;
    let mut next = planner_testkit::xorshift(34);
    let mut n_found = 0;
    let mut n_restarted = 0;
    let mut n_reseeded = 0;
    let problems = planner_testkit::small_random_problems(34, 120);
    for (i, (grid, start, goal)) in problems.iter().enumerate() {
        let config = Config {
            seed: next() % 1000,
            control_points: 1 + (next() % 5) as u32,
            population: 2 + (next() % 8) as u32,
            iterations: (next() % 25) as u32,
            chaotic_map: maps[i % maps.len()],
            samples_per_segment: 1 + (next() % 4) as u32,
            tolerance: [0.0, 0.5, 1.0, 2.0, 3.5][i % 5],
            restart_after: [0, 1, 3, 10][i % 4],
            guided_share: [0.0, 0.5, 1.0][i % 3],
            penalty: [0.0, 1.0, 100.0][(i / 3) % 3],
            ..Config::default()
        };
        let planner = planner_run(grid, *start, *goal, &config);
        let reference = reference_capso(grid, *start, *goal, &config);
        assert_eq!(
            planner,
            reference,
            "problem {i}: {start} -> {goal}, {config:?}\n{}",
            grid.to_ascii()
        );
        let get = |name: &str| reference.counters.iter().find(|c| c.0 == name).unwrap().1;
        n_found += usize::from(reference.status == Status::Found);
        n_restarted += usize::from(get("n_restarts") > 0);
        n_reseeded += usize::from(get("n_chaos_reseeds") > 0);
    }
    // The problems exercise what they are meant to.
    assert!(n_found > 30 && n_found < problems.len(), "{n_found} found");
    assert!(n_restarted > 20, "{n_restarted} with restarts");
    assert!(n_reseeded > 5, "{n_reseeded} with reseeds");
}
