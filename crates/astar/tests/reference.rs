//! planner-astar against `planner_testkit::reference_astar`, a plain transcription of seed
//! 000's Fig. 4 (std's `BinaryHeap` with lazy deletion and the full key `(f, tie, push
//! sequence)`). The fast OPEN lists (integer slots, f buckets with a front, closed entries
//! dropped early) must give the same path and every counter on every problem, for every
//! tie rule, heuristic, weight and neighbourhood, on grids with and without cell weights.

use planner_api::{Budget, Cell, Connectivity, Grid, MoveSet, NeighborOrder, Problem, Status};
use planner_astar::{AStar, Config, Heuristic, TieBreak};
use planner_testkit::{reference_astar, ReferenceSearch, Tie};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Every tie rule.
const TIES: [TieBreak; 4] = [
    TieBreak::Fifo,
    TieBreak::Lifo,
    TieBreak::LowG,
    TieBreak::HighG,
];

/// The reference search with `config`'s moves, heuristic, weight and tie rule.
fn reference(config: &Config, grid: &Grid, start: Cell, goal: Cell) -> ReferenceSearch {
    let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order).unwrap();
    // On a weighted grid A*'s heuristic is multiplied by the smallest weight.
    let min_weight = grid.weights().map_or(1, |w| u64::from(w.min()));
    let h = |c: Cell| {
        let h = config.heuristic.cost(c.x, c.y, goal.x, goal.y);
        h.times(min_weight).scaled(config.weight)
    };
    let tie = match config.tie_break {
        TieBreak::Fifo => Tie::Fifo,
        TieBreak::Lifo => Tie::Lifo,
        TieBreak::LowG => Tie::LowG,
        TieBreak::HighG => Tie::HighG,
    };
    reference_astar(grid, &moves, h, tie, start, goal)
}

fn check(config: &Config, grid: &Grid, start: Cell, goal: Cell) {
    let problem = Problem::new(grid, start, goal).unwrap();
    let search = AStar::new(config.clone())
        .unwrap()
        .search(&problem, &Budget::unlimited());
    let stats = search.stats;
    let actual: ReferenceSearch = (
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
            for tie_break in TIES {
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

/// Random weighted grids (planner-testkit's: weights 1-255, uniform or in patches, both cost
/// rules), 4- and 8-connected, every tie rule: the weighted search's narrower buckets and
/// weight factors give the reference's path and counters.
#[test]
fn weighted_searches_match_the_reference_on_random_grids() {
    let mut n_expanded = 0;
    for problem in planner_testkit::random_weighted_problems(77, 400) {
        for (moves, heuristic) in [
            (Connectivity::Four, Heuristic::Manhattan),
            (Connectivity::Eight, Heuristic::Octile),
        ] {
            for tie_break in TIES {
                let config = Config {
                    moves,
                    heuristic,
                    tie_break,
                    ..Config::default()
                };
                check(&config, &problem.grid, problem.start, problem.goal);
                let expect = reference(&config, &problem.grid, problem.start, problem.goal);
                n_expanded += expect.2[0];
            }
        }
    }
    // 189,186 expansions (2026-12-06).
    assert!(n_expanded > 150_000, "{n_expanded}");
}
