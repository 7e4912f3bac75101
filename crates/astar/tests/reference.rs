//! planner-astar against a plain transcription of seed 000's Fig. 4: std's `BinaryHeap`
//! with lazy deletion and the full key `(f, tie, push sequence)`, `HashMap`-free but
//! otherwise written for clarity, not speed. The fast OPEN lists (integer slots, f buckets
//! with a front, closed entries dropped early) must give the same path and every counter
//! on every problem, for every tie rule, heuristic, weight and neighbourhood.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Problem, Status};
use planner_astar::{AStar, Config, Heuristic, TieBreak};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// What the reference search produced: status, path cells, and the counters in the order
/// expanded, neighbour checks, blocked, skipped, insertions, relaxations, peak OPEN.
type Result = (Status, Option<Vec<Cell>>, [u64; 7]);

/// A* as Fig. 4 reads, with `config`'s moves, heuristic, weight and tie rule.
fn reference(config: &Config, grid: &Grid, start: Cell, goal: Cell) -> Result {
    let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order).unwrap();
    let h = |c: Cell| config.weight * config.heuristic.estimate(c.x, c.y, goal.x, goal.y);
    // Floats >= 0 order like their bits; the tie value is g's bits (low g first) or their
    // complement (high g first); LIFO complements the sequence.
    let key = |f: f64, g: f64, seq: u64| {
        let g_bits = (g + 0.0).to_bits();
        let (tie, seq) = match config.tie_break {
            TieBreak::Fifo => (0, seq),
            TieBreak::Lifo => (0, u64::MAX - seq),
            TieBreak::LowG => (g_bits, seq),
            TieBreak::HighG => (!g_bits, seq),
        };
        ((f + 0.0).to_bits(), tie, seq)
    };
    let n = grid.len();
    let mut g = vec![f64::INFINITY; n];
    let mut parent = vec![usize::MAX; n];
    let mut in_open = vec![false; n];
    let mut closed = vec![false; n];
    let mut heap = BinaryHeap::new();
    let mut seq = 0u64;
    let [mut exp, mut checks, mut blocked, mut skipped, mut ins, mut rel, mut peak] = [0u64; 7];
    let (s, t) = (grid.index(start), grid.index(goal));
    g[s] = 0.0;
    in_open[s] = true;
    heap.push(Reverse((key(h(start), 0.0, seq), s)));
    seq += 1;
    ins += 1;
    peak = peak.max(1);
    let mut n_open = 1u64;
    while let Some(Reverse((_, p))) = heap.pop() {
        if closed[p] {
            continue;
        }
        closed[p] = true;
        in_open[p] = false;
        n_open -= 1;
        exp += 1;
        if p == t {
            let mut cells = vec![grid.cell(t)];
            let mut node = t;
            while node != s {
                node = parent[node];
                cells.push(grid.cell(node));
            }
            cells.reverse();
            let counters = [exp, checks, blocked, skipped, ins, rel, peak];
            return (Status::Found, Some(cells), counters);
        }
        let from = grid.cell(p);
        for mv in moves.moves() {
            checks += 1;
            let Some(to) = moves.apply(grid, from, mv) else {
                blocked += 1;
                continue;
            };
            let q = grid.index(to);
            if closed[q] {
                skipped += 1;
                continue;
            }
            let g_new = g[p] + mv.cost;
            if !in_open[q] || g_new < g[q] {
                rel += 1;
                if !in_open[q] {
                    ins += 1;
                    n_open += 1;
                    peak = peak.max(n_open);
                }
                in_open[q] = true;
                g[q] = g_new;
                parent[q] = p;
                heap.push(Reverse((key(g_new + h(to), g_new, seq), q)));
                seq += 1;
            }
        }
    }
    let counters = [exp, checks, blocked, skipped, ins, rel, peak];
    (Status::NoPath, None, counters)
}

fn check(config: &Config, grid: &Grid, start: Cell, goal: Cell) {
    let problem = Problem::new(grid, start, goal).unwrap();
    let search = AStar::new(config.clone())
        .unwrap()
        .search(&problem, &Budget::unlimited());
    let stats = search.stats;
    let actual: Result = (
        search.status,
        search.path.map(|path| path.cells().to_vec()),
        [
            stats.n_expanded,
            stats.n_neighbor_checks,
            stats.n_blocked,
            stats.n_skipped,
            stats.n_open_insertions,
            stats.n_relaxations,
            stats.peak_open,
        ],
    );
    let expect = reference(config, grid, start, goal);
    assert_eq!(
        actual,
        expect,
        "{config:?} {start} -> {goal}\n{}",
        grid.to_ascii()
    );
}

/// Every tie rule with 4-connected integer costs (the integer OPEN) and the weights and
/// heuristics that leave it (the general one), and 8 to 32 directions, on open and
/// cluttered random grids, including a weight that makes OPEN's `f` go down.
#[test]
fn fast_open_lists_match_the_reference_on_random_grids() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let setups = [
        (Connectivity::Four, Heuristic::Manhattan, 1.0),
        (Connectivity::Four, Heuristic::Chebyshev, 1.0),
        (Connectivity::Four, Heuristic::Zero, 1.0),
        (Connectivity::Four, Heuristic::Manhattan, 0.0),
        (Connectivity::Four, Heuristic::Manhattan, 2.0),
        (Connectivity::Four, Heuristic::Euclidean, 1.0),
        (Connectivity::Eight, Heuristic::Octile, 1.0),
        (Connectivity::Eight, Heuristic::Manhattan, 1.0),
        (Connectivity::Eight, Heuristic::Octile, 3.5),
        (Connectivity::Sixteen, Heuristic::Euclidean, 1.0),
        (Connectivity::ThirtyTwo, Heuristic::Euclidean, 1.5),
    ];
    let mut n_found = 0;
    for round in 0..60 {
        let (width, height) = (rng.gen_range(5..40), rng.gen_range(5..40));
        let density = [0.0, 0.1, 0.25, 0.4][round % 4];
        let free: Vec<bool> = (0..width * height)
            .map(|_| !rng.gen_bool(density))
            .collect();
        let grid = Grid::from_free_cells(width, height, free).unwrap();
        let cells: Vec<Cell> = grid.cells().filter(|&c| grid.is_free(c)).collect();
        if cells.len() < 2 {
            continue;
        }
        let start = cells[rng.gen_range(0..cells.len())];
        let goal = cells[rng.gen_range(0..cells.len())];
        for &(moves, heuristic, weight) in &setups {
            for tie_break in [
                TieBreak::Fifo,
                TieBreak::Lifo,
                TieBreak::LowG,
                TieBreak::HighG,
            ] {
                let config = Config {
                    moves,
                    heuristic,
                    weight,
                    tie_break,
                    corner_cutting: round % 3 == 0 && moves == Connectivity::Eight,
                    order: if round % 2 == 1 && moves == Connectivity::Four {
                        "U D L R".parse().unwrap()
                    } else {
                        NeighborOrder::default()
                    },
                };
                check(&config, &grid, start, goal);
            }
        }
        n_found += usize::from(
            AStar::new(Config::default())
                .unwrap()
                .search(
                    &Problem::new(&grid, start, goal).unwrap(),
                    &Budget::unlimited(),
                )
                .status
                == Status::Found,
        );
    }
    // Most problems have a path, so paths and the goal test are compared too.
    assert!(n_found >= 30, "{n_found}");
}
