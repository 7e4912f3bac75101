//! [`reference_rrt`]: seed 003's RRT written again for clarity.

use planner_api::{for_each_segment_cell, segment_is_free, Cell, Grid, Status};
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
    let mut rng = generator(seed);
    let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
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
        let near = nearest(&nodes, target);
        let from = nodes[near].0;
        let new = steer(from, target, eight, step);
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
    match found {
        true => (
            Status::Found,
            Some(path_to(&nodes, nodes.len() - 1)),
            counters,
        ),
        false => (Status::BudgetExhausted, None, counters),
    }
}

/// The counters of [`reference_rrt_connect`], in planner-rrt_connect's order.
pub const RRT_CONNECT_COUNTERS: [&str; 10] = [
    "n_iterations",
    "n_extensions",
    "n_collisions",
    "n_duplicates",
    "start_tree_size",
    "goal_tree_size",
    "n_connect_steps",
    "n_segment_checks",
    "n_segment_cells",
    "n_expanded",
];

/// How one extension of [`reference_rrt_connect`] ended.
enum Extension {
    Trapped,
    /// Reached the target (a node already, or added), or advanced toward it: the node.
    Reached(usize),
    Advanced(usize),
    /// The new cell is node `to` of the other tree, reached from node `from`.
    Met {
        from: usize,
        to: usize,
    },
}

/// planner-rrt_connect's run as its crate docs define it (Kuffner and LaValle 2000 on grid
/// cells), written for clarity: the same documented draws as [`reference_rrt`] (a free
/// cell per iteration, no goal bias), two trees as flat lists with a cell's tree in a flat
/// array, nearest nodes by a linear scan, `EXTEND` (trapped when planner-api's
/// [`for_each_segment_cell`] meets a blocked cell, a duplicate when the target is a node
/// already, meeting when the new cell is a node of the other tree) and `CONNECT` (extend
/// the other tree toward the reached node while it advances), the trees swapping roles each
/// iteration. `goal_bias` is ignored. Counts as the crate docs say, segment cells being the
/// cells the traversal visits up to the first blocked one. Unlimited budget.
pub fn reference_rrt_connect(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    settings: RrtSettings,
) -> (Status, Option<Vec<Cell>>, [u64; 10]) {
    // n_iterations, n_extensions, n_collisions, n_duplicates, n_connect_steps, segment
    // checks, segment cells.
    let mut tally = [0u64; 7];
    let mut trees: [Vec<(Cell, usize)>; 2] = [vec![(start, 0)], vec![(goal, 0)]];
    // Per cell: the tree holding it (0 or 1) and its node there.
    let mut owner: Vec<Option<(usize, usize)>> = vec![None; grid.len()];
    owner[grid.index(start)] = Some((0, 0));
    let finish = |trees: &[Vec<(Cell, usize)>; 2], tally: &[u64; 7]| {
        [
            tally[0],
            tally[1],
            tally[2],
            tally[3],
            trees[0].len() as u64,
            trees[1].len() as u64,
            tally[4],
            tally[5],
            tally[6],
            tally[1],
        ]
    };
    if start == goal {
        return (Status::Found, Some(vec![start]), finish(&trees, &tally));
    }
    owner[grid.index(goal)] = Some((1, 0));
    let extend = |trees: &mut [Vec<(Cell, usize)>; 2],
                  owner: &mut Vec<Option<(usize, usize)>>,
                  tally: &mut [u64; 7],
                  active: usize,
                  target: Cell| {
        tally[1] += 1;
        let near = nearest(&trees[active], target);
        let from = trees[active][near].0;
        let new = steer(from, target, settings.eight, settings.step);
        if new == from {
            tally[3] += 1;
            return Extension::Reached(near);
        }
        tally[5] += 1;
        let mut cells = 0;
        let free = for_each_segment_cell(from, new, |c| {
            cells += 1;
            grid.is_free(c)
        });
        tally[6] += cells;
        if !free {
            tally[2] += 1;
            return Extension::Trapped;
        }
        match owner[grid.index(new)] {
            Some((tree, to)) if tree != active => return Extension::Met { from: near, to },
            _ => {}
        }
        trees[active].push((new, near));
        let node = trees[active].len() - 1;
        owner[grid.index(new)] = Some((active, node));
        match new == target {
            true => Extension::Reached(node),
            false => Extension::Advanced(node),
        }
    };
    let joined = |trees: &[Vec<(Cell, usize)>; 2], active: usize, from: usize, to: usize| {
        let mut cells = path_to(&trees[active], from);
        let mut rest = path_to(&trees[1 - active], to);
        rest.reverse();
        cells.extend(rest);
        if active == 1 {
            cells.reverse();
        }
        cells
    };
    let mut rng = generator(settings.seed);
    let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
    let mut active = 0;
    while tally[0] < settings.max_iterations {
        tally[0] += 1;
        let sample = free[below(&mut rng, free.len() as u64) as usize];
        let reached = match extend(&mut trees, &mut owner, &mut tally, active, sample) {
            Extension::Trapped => None,
            Extension::Advanced(node) | Extension::Reached(node) => Some(node),
            Extension::Met { from, to } => {
                let path = joined(&trees, active, from, to);
                return (Status::Found, Some(path), finish(&trees, &tally));
            }
        };
        if let Some(node) = reached {
            let target = trees[active][node].0;
            let other = 1 - active;
            loop {
                match extend(&mut trees, &mut owner, &mut tally, other, target) {
                    Extension::Advanced(_) => tally[4] += 1,
                    Extension::Met { from, to } => {
                        tally[4] += 1;
                        let path = joined(&trees, other, from, to);
                        return (Status::Found, Some(path), finish(&trees, &tally));
                    }
                    Extension::Reached(_) | Extension::Trapped => break,
                }
            }
        }
        active = 1 - active;
    }
    (Status::BudgetExhausted, None, finish(&trees, &tally))
}

/// ChaCha8 keyed by `seed`'s 8 little-endian bytes, then zeros (planner-rrt's generator).
fn generator(seed: u64) -> ChaCha8Rng {
    let mut key = [0u8; 32];
    key[..8].copy_from_slice(&seed.to_le_bytes());
    ChaCha8Rng::from_seed(key)
}

/// Lemire's multiply-shift with rejection: exactly uniform in `0..n` (`n >= 1`).
fn below(rng: &mut ChaCha8Rng, n: u64) -> u64 {
    let threshold = n.wrapping_neg() % n;
    loop {
        let m = u128::from(rng.next_u64()) * u128::from(n);
        if m as u64 >= threshold {
            return (m >> 64) as u64;
        }
    }
}

/// The node of `nodes` (cell, parent) nearest `target` by exact squared distance, the
/// first added among equals. Precondition: `nodes` is not empty.
fn nearest(nodes: &[(Cell, usize)], target: Cell) -> usize {
    let squared = |c: Cell| {
        let (dx, dy) = (
            u64::from(c.x.abs_diff(target.x)),
            u64::from(c.y.abs_diff(target.y)),
        );
        dx * dx + dy * dy
    };
    // `min_by_key` keeps the first of equal keys.
    (0..nodes.len())
        .min_by_key(|&k| squared(nodes[k].0))
        .unwrap_or(0)
}

/// `step` unit moves from `from` toward `target`, stopping there: diagonal when both
/// offsets are non-zero (`eight`), else along the larger offset, ties along x.
fn steer(from: Cell, target: Cell, eight: bool, step: u32) -> Cell {
    let (mut x, mut y) = (i64::from(from.x), i64::from(from.y));
    let (tx, ty) = (i64::from(target.x), i64::from(target.y));
    for _ in 0..step {
        if (x, y) == (tx, ty) {
            break;
        }
        if eight {
            x += (tx - x).signum();
            y += (ty - y).signum();
        } else if (tx - x).abs() >= (ty - y).abs() {
            x += (tx - x).signum();
        } else {
            y += (ty - y).signum();
        }
    }
    Cell::new(x as u32, y as u32)
}

/// The cells from `nodes`' root (node 0) to node `k`.
fn path_to(nodes: &[(Cell, usize)], mut k: usize) -> Vec<Cell> {
    let mut cells = vec![nodes[k].0];
    while k != 0 {
        k = nodes[k].1;
        cells.push(nodes[k].0);
    }
    cells.reverse();
    cells
}
