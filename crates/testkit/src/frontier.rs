//! [`reference_frontier`]: seed 003's BFS and DFS written again for clarity.

use std::collections::VecDeque;

use planner_api::{Cell, Grid, MoveSet, Status};

/// The counters of [`reference_frontier`], in planner-bfs's and planner-dfs's order.
pub const FRONTIER_COUNTERS: [&str; 6] = [
    "n_expanded",
    "n_neighbor_checks",
    "n_blocked",
    "n_skipped",
    "peak_open",
    "n_open_insertions",
];

/// What [`reference_frontier`] found: status, path, and the counters named in
/// [`FRONTIER_COUNTERS`].
pub type FrontierSearch = (Status, Option<Vec<Cell>>, [u64; 6]);

/// Seed 003's BFS (`lifo` false: a FIFO queue) or DFS (`lifo` true: a LIFO stack), section
/// II.C, as planner-bfs and planner-dfs define it, written for clarity: a `VecDeque`, a
/// visited flag set when a cell enters the frontier, parent links, the goal tested when a
/// cell leaves it, the moves of `moves` checked in their order through
/// [`MoveSet::apply`]. Unlimited budget.
pub fn reference_frontier(
    grid: &Grid,
    moves: &MoveSet,
    start: Cell,
    goal: Cell,
    lifo: bool,
) -> FrontierSearch {
    let n = grid.len();
    let mut visited = vec![false; n];
    let mut parent = vec![usize::MAX; n];
    let mut frontier = VecDeque::new();
    let [mut expanded, mut checks, mut blocked, mut skipped] = [0u64; 4];
    let s = grid.index(start);
    visited[s] = true;
    frontier.push_back(s);
    let (mut peak, mut insertions) = (1u64, 1u64);
    let t = grid.index(goal);
    let found = loop {
        let next = match lifo {
            true => frontier.pop_back(),
            false => frontier.pop_front(),
        };
        let Some(p) = next else {
            break false;
        };
        expanded += 1;
        if p == t {
            break true;
        }
        let cell = grid.cell(p);
        for mv in moves.moves() {
            checks += 1;
            let Some(to) = moves.apply(grid, cell, mv) else {
                blocked += 1;
                continue;
            };
            let q = grid.index(to);
            if visited[q] {
                skipped += 1;
                continue;
            }
            visited[q] = true;
            parent[q] = p;
            frontier.push_back(q);
            insertions += 1;
        }
        peak = peak.max(frontier.len() as u64);
    };
    let counters = [expanded, checks, blocked, skipped, peak, insertions];
    if !found {
        return (Status::NoPath, None, counters);
    }
    let cells = crate::path_from_parents(grid, &parent, start, goal);
    (Status::Found, Some(cells), counters)
}
