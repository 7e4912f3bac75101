//! [`reference_rrt`]: seed 003's RRT written again for clarity.

use planner_api::{segment_is_free, Cell, Grid, Status};
use rand_chacha::rand_core::{RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The counters of [`reference_rrt`], in planner-rrt's order.
pub const RRT_COUNTERS: [&str; 7] = [
    "n_iterations",
    "n_samples",
    "n_goal_samples",
    "n_collisions",
    "tree_size",
    "n_duplicates",
    "n_expanded",
];

/// What [`reference_rrt`] found: status, path, and the counters named in [`RRT_COUNTERS`].
pub type RrtSearch = (Status, Option<Vec<Cell>>, [u64; 7]);

/// RRT's parameters as planner-rrt's `Config` names them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RrtSettings {
    /// The generator's seed.
    pub seed: u64,
    /// The probability of sampling the goal.
    pub goal_bias: f64,
    /// The iterations before the run gives up.
    pub max_iterations: u64,
    /// Eight unit moves (else four) in steering.
    pub eight: bool,
    /// Unit moves per extension.
    pub step: u32,
}

/// planner-rrt's run as its crate docs define it (seed 003, section II.D), written for
/// clarity and not speed: ChaCha8 keyed by `seed`'s 8 little-endian bytes then zeros, its
/// raw 64-bit words reduced as documented (the goal coin on the top 53 bits; a free cell,
/// in flat-index order, by Lemire's multiply-shift with rejection), the nearest tree node
/// by a linear scan of exact squared distances (ties to the node added first; the planner
/// files nodes in a bucket grid), steering by `step` unit moves (`eight`: diagonal when
/// both offsets are non-zero, else along the larger offset, ties along x), and a step kept
/// when its cell is new and planner-api's [`segment_is_free`] holds. Unlimited budget:
/// the run ends at the goal or after `max_iterations` iterations.
pub fn reference_rrt(grid: &Grid, start: Cell, goal: Cell, settings: RrtSettings) -> RrtSearch {
    let RrtSettings {
        seed,
        goal_bias,
        max_iterations,
        eight,
        step,
    } = settings;
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    let mut rng = ChaCha8Rng::from_seed(key);
    let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
    // Lemire's multiply-shift with rejection: exactly uniform in 0..n.
    let below = |rng: &mut ChaCha8Rng, n: u64| {
        let threshold = n.wrapping_neg() % n;
        loop {
            let m = u128::from(rng.next_u64()) * u128::from(n);
            if m as u64 >= threshold {
                return (m >> 64) as u64;
            }
        }
    };
    let mut nodes: Vec<(Cell, usize)> = vec![(start, 0)];
    let mut in_tree = vec![false; grid.len()];
    in_tree[grid.index(start)] = true;
    let [mut iterations, mut goal_samples, mut collisions, mut duplicates] = [0u64; 4];
    let mut found = start == goal;
    while !found && iterations < max_iterations {
        iterations += 1;
        let coin = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let target = if coin < goal_bias {
            goal_samples += 1;
            goal
        } else {
            free[below(&mut rng, free.len() as u64) as usize]
        };
        let squared = |c: Cell| {
            let (dx, dy) = (
                u64::from(c.x.abs_diff(target.x)),
                u64::from(c.y.abs_diff(target.y)),
            );
            dx * dx + dy * dy
        };
        // The first of the nearest (min_by_key keeps the first of equal keys).
        let near = (0..nodes.len())
            .min_by_key(|&k| squared(nodes[k].0))
            .unwrap_or(0);
        let from = nodes[near].0;
        let (mut x, mut y) = (i64::from(from.x), i64::from(from.y));
        let (tx, ty) = (i64::from(target.x), i64::from(target.y));
        for _ in 0..step {
            if (x, y) == (tx, ty) {
                break;
            }
            let (ax, ay) = ((tx - x).abs(), (ty - y).abs());
            if eight {
                x += (tx - x).signum();
                y += (ty - y).signum();
            } else if ax >= ay {
                x += (tx - x).signum();
            } else {
                y += (ty - y).signum();
            }
        }
        let new = Cell::new(x as u32, y as u32);
        if in_tree[grid.index(new)] {
            duplicates += 1;
        } else if !segment_is_free(grid, from, new) {
            collisions += 1;
        } else {
            in_tree[grid.index(new)] = true;
            nodes.push((new, near));
            found = new == goal;
        }
    }
    let counters = [
        iterations,
        iterations,
        goal_samples,
        collisions,
        nodes.len() as u64,
        duplicates,
        iterations,
    ];
    if !found {
        return (Status::BudgetExhausted, None, counters);
    }
    let mut cells = vec![nodes[nodes.len() - 1].0];
    let mut k = nodes.len() - 1;
    while k != 0 {
        k = nodes[k].1;
        cells.push(nodes[k].0);
    }
    cells.reverse();
    (Status::Found, Some(cells), counters)
}
