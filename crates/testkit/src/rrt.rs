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
        let (free, cells) = walk_counted(grid, from, new);
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

/// What [`reference_rrt_star`] found: status, path, the counters by name in
/// planner-rrt_star's order (`first_solution_iteration` only when the goal joined the
/// tree), and the `best_cost` series as `[iteration, cost]` points.
pub type RrtStarSearch = (
    Status,
    Option<Vec<Cell>>,
    Vec<(&'static str, u64)>,
    Vec<[f64; 2]>,
);

/// planner-rrt_star's run as its crate docs define it (Karaman and Frazzoli 2011,
/// Algorithm 6, on grid cells), written for clarity: the draws, nearest node and steering
/// of [`reference_rrt`]; the near set by a scan of every node with
/// `|x - new|^2 <= floor(min(gamma^2 ln n / n, eta^2))` (`n` the nodes before the new one,
/// `eta^2` the steering's longest reach squared, `gamma` the given one or 1.1 times
/// `sqrt(3 n_free / pi)`); choose-parent over the nearest then the near nodes by increasing
/// id, keeping the earlier on equal cost, a segment checked only for a candidate that would
/// improve; rewiring by increasing id with the subtree's costs recomputed (each counted);
/// costs `f64` sums of [`Cell::euclidean`]; the goal's cost decreases recorded; the run
/// ending `iterations_after_solution` iterations after the goal joined, or after
/// `max_iterations`. Segment checks and cells are counted by planner-api's traversal, a
/// segment checked in choose-parent not again when rewiring. Unlimited budget.
pub fn reference_rrt_star(
    grid: &Grid,
    start: Cell,
    goal: Cell,
    settings: RrtSettings,
    iterations_after_solution: u64,
    gamma: Option<f64>,
) -> RrtStarSearch {
    let gamma = gamma.unwrap_or_else(|| {
        let n_free = grid.cells().filter(|&c| grid.is_free(c)).count();
        1.1 * (3.0 * n_free as f64 / std::f64::consts::PI).sqrt()
    });
    let step = u64::from(settings.step);
    let reach_squared = match settings.eight {
        true => 2 * step * step,
        false => step * step,
    };
    // Per node: cell, parent, cost, edge to the parent; children per node.
    let mut nodes: Vec<(Cell, usize)> = vec![(start, 0)];
    let mut cost = vec![0.0f64];
    let mut edge = vec![0.0f64];
    let mut children: Vec<Vec<usize>> = vec![Vec::new()];
    let mut in_tree = vec![false; grid.len()];
    in_tree[grid.index(start)] = true;
    // Iterations, goal samples, collisions, duplicates, near, parent changes, rewires, cost
    // updates, segment checks, segment cells, improvements.
    let mut t = [0u64; 11];
    let segment = |t: &mut [u64; 11], a: Cell, b: Cell| {
        t[8] += 1;
        let (free, cells) = walk_counted(grid, a, b);
        t[9] += cells;
        free
    };
    let mut series = Vec::new();
    let mut goal_node = (start == goal).then_some(0usize);
    let mut first_solution = None;
    let mut best = f64::INFINITY;
    if goal_node.is_some() {
        best = 0.0;
        first_solution = Some(0);
        t[10] = 1;
        series.push([0.0, 0.0]);
    }
    let mut rng = generator(settings.seed);
    let free: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
    loop {
        if let Some(found_at) = first_solution {
            if start == goal || t[0] - found_at >= iterations_after_solution {
                break;
            }
        }
        if t[0] >= settings.max_iterations {
            break;
        }
        t[0] += 1;
        let coin = (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let target = if coin < settings.goal_bias {
            t[1] += 1;
            goal
        } else {
            free[below(&mut rng, free.len() as u64) as usize]
        };
        let near_node = nearest(&nodes, target);
        let from = nodes[near_node].0;
        let new_cell = steer(from, target, settings.eight, settings.step);
        if in_tree[grid.index(new_cell)] {
            t[3] += 1;
            continue;
        }
        if !segment(&mut t, from, new_cell) {
            t[2] += 1;
            continue;
        }
        let n = nodes.len().max(1) as f64;
        let radius_squared = (gamma * gamma * n.ln() / n)
            .min(reach_squared as f64)
            .floor() as u64;
        let squared = |a: Cell, b: Cell| {
            let (dx, dy) = (u64::from(a.x.abs_diff(b.x)), u64::from(a.y.abs_diff(b.y)));
            dx * dx + dy * dy
        };
        let near: Vec<usize> = (0..nodes.len())
            .filter(|&k| squared(nodes[k].0, new_cell) <= radius_squared)
            .collect();
        t[4] += near.len() as u64;
        // Choose parent; `checked[k]`: the segment from near[k] was checked, and its answer.
        let mut checked: Vec<Option<bool>> = vec![None; near.len()];
        let mut parent = near_node;
        let mut parent_edge = from.euclidean(new_cell);
        let mut parent_cost = cost[near_node] + parent_edge;
        for (k, &x) in near.iter().enumerate() {
            if x == near_node {
                checked[k] = Some(true);
                continue;
            }
            let x_edge = nodes[x].0.euclidean(new_cell);
            let x_cost = cost[x] + x_edge;
            if x_cost < parent_cost {
                let free = segment(&mut t, nodes[x].0, new_cell);
                checked[k] = Some(free);
                if free {
                    (parent, parent_edge, parent_cost) = (x, x_edge, x_cost);
                }
            }
        }
        if parent != near_node {
            t[5] += 1;
        }
        nodes.push((new_cell, parent));
        cost.push(cost[parent] + parent_edge);
        edge.push(parent_edge);
        children.push(Vec::new());
        children[parent].push(nodes.len() - 1);
        in_tree[grid.index(new_cell)] = true;
        let new = nodes.len() - 1;
        // Rewire.
        for (k, &x) in near.iter().enumerate() {
            if x == parent {
                continue;
            }
            let x_edge = new_cell.euclidean(nodes[x].0);
            if cost[new] + x_edge >= cost[x] {
                continue;
            }
            let free = match checked[k] {
                Some(free) => free,
                None => segment(&mut t, new_cell, nodes[x].0),
            };
            if !free {
                continue;
            }
            let old = nodes[x].1;
            children[old].retain(|&c| c != x);
            nodes[x].1 = new;
            children[new].push(x);
            edge[x] = x_edge;
            cost[x] = cost[new] + x_edge;
            t[6] += 1;
            let mut stack = vec![x];
            while let Some(p) = stack.pop() {
                for &c in &children[p] {
                    cost[c] = cost[p] + edge[c];
                    t[7] += 1;
                    stack.push(c);
                }
            }
        }
        if new_cell == goal {
            goal_node = Some(new);
            first_solution = Some(t[0]);
        }
        if let Some(g) = goal_node {
            if cost[g] < best {
                best = cost[g];
                t[10] += 1;
                series.push([t[0] as f64, cost[g]]);
            }
        }
    }
    let mut counters = vec![
        ("n_iterations", t[0]),
        ("n_samples", t[0]),
        ("n_goal_samples", t[1]),
        ("n_collisions", t[2]),
        ("tree_size", nodes.len() as u64),
        ("n_duplicates", t[3]),
        ("n_near", t[4]),
        ("n_parent_changes", t[5]),
        ("n_rewires", t[6]),
        ("n_cost_updates", t[7]),
        ("n_segment_checks", t[8]),
        ("n_segment_cells", t[9]),
        ("n_improvements", t[10]),
    ];
    if let Some(iteration) = first_solution {
        counters.push(("first_solution_iteration", iteration));
    }
    counters.push(("n_expanded", t[0]));
    match goal_node {
        Some(g) => (Status::Found, Some(path_to(&nodes, g)), counters, series),
        None => (Status::BudgetExhausted, None, counters, series),
    }
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

/// Whether the segment between the centres of `a` and `b` is free, by planner-api's exact
/// traversal ([`for_each_segment_cell`]), and the cells it visited: up to and including
/// the first blocked one.
fn walk_counted(grid: &Grid, a: Cell, b: Cell) -> (bool, u64) {
    let mut cells = 0;
    let free = for_each_segment_cell(a, b, |c| {
        cells += 1;
        grid.is_free(c)
    });
    (free, cells)
}
