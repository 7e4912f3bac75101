//! Coverage by spiral and zigzag filling with A* returns: paths by hand, and on thousands
//! of seeded random maps checked against independent methods written here (a BFS for the
//! reachable set, a Dijkstra for return costs, the marking rule replayed from the path).

use std::time::Duration;

use planner_api::{
    Budget, CancelFlag, Cell, Connectivity, CoverageOutcome, CoveragePlanner, CoverageProblem,
    Grid, MoveSet, PathRule, Problem, Status,
};
use planner_astar::{AStar, Heuristic};
use planner_coverage::generate::{random_blocks, random_cells};
use planner_coverage::{Config, Coverage, Heading, Pattern, Rotation, Side};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn spiral(side: Side) -> Config {
    Config {
        pattern: Pattern::Spiral,
        reference_side: Some(side),
        ..Config::default()
    }
}

fn zigzag(rotation: Rotation) -> Config {
    Config {
        pattern: Pattern::Zigzag,
        rotation: Some(rotation),
        ..Config::default()
    }
}

fn cells(list: &[(u32, u32)]) -> Vec<Cell> {
    list.iter().map(|&c| c.into()).collect()
}

/// Covers `map` from `start` with `config` and compares the path with `expect`.
fn check(map: &str, start: (u32, u32), config: Config, expect: &[(u32, u32)]) {
    let grid = Grid::from_ascii(map).unwrap();
    let problem = CoverageProblem::new(&grid, start.into()).unwrap();
    let outcome = Coverage::new(config.clone())
        .unwrap()
        .cover(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found, "{config:?}");
    assert_eq!(outcome.path.cells(), cells(expect), "{config:?}");
    assert!(outcome.metrics.is_complete());
}

#[test]
fn fills_by_hand() {
    let open = "
        ...
        ...
        ...
    ";
    // Section 2.1 from the top-left corner heading right. RLS left: along the top wall,
    // turn right (OLS) at each wall, then inwards: a clockwise spiral.
    check(
        open,
        (0, 0),
        spiral(Side::Left),
        &[
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 1),
            (2, 2),
            (1, 2),
            (0, 2),
            (0, 1),
            (1, 1),
        ],
    );
    // RLS right: heading right would leave the right side open, so the first heading with
    // a wall on the right is down (scanning R, then towards the OLS: U, L, D).
    check(
        open,
        (0, 0),
        spiral(Side::Right),
        &[
            (0, 0),
            (0, 1),
            (0, 2),
            (1, 2),
            (2, 2),
            (2, 1),
            (2, 0),
            (1, 0),
            (1, 1),
        ],
    );
    // Section 2.2: right, up, left, down sweeps rows; clockwise from down sweeps columns.
    check(
        open,
        (0, 0),
        zigzag(Rotation::CounterClockwise),
        &[
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 1),
            (1, 1),
            (0, 1),
            (0, 2),
            (1, 2),
            (2, 2),
        ],
    );
    check(
        open,
        (0, 0),
        zigzag(Rotation::Clockwise),
        &[
            (0, 0),
            (0, 1),
            (0, 2),
            (1, 2),
            (1, 1),
            (1, 0),
            (2, 0),
            (2, 1),
            (2, 2),
        ],
    );
    // Clockwise from right (first = "R") spirals instead: right, down, left, up order.
    check(
        open,
        (0, 0),
        Config {
            first: Some(Heading::Right),
            ..zigzag(Rotation::Clockwise)
        },
        &[
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 1),
            (2, 2),
            (1, 2),
            (0, 2),
            (0, 1),
            (1, 1),
        ],
    );
}

#[test]
fn spiral_backtracks_by_hand() {
    //   .....
    //   .#...
    //   .....
    // From (2,0) heading right with the RLS on the left (outside the grid): right to
    // (4,0), turn to the OLS (down) to (4,2), left to (0,2), up to (0,0), right to (1,0):
    // there the front (2,0) is covered, (1,1) blocked, (0,0) covered: rule 1, the spiral
    // ends. Marked on the way (left with an open 4-neighbour): (2,0) ((2,1) open), (3,0)
    // and (4,1) ((3,1)), (3,2) ((3,1)), (2,2) ((2,1)): five, none dropped yet. The nearest
    // from (1,0) is (2,0) at cost 1 (octile bounds of the others: 2, 1 + sqrt 2, ...).
    // At (2,0) the first heading scanned from right towards the OLS with an open front
    // and a covered RLS is down: (2,1), then rule 2 (RLS = right of the screen) to (3,1),
    // and every neighbourhood is covered.
    let grid = Grid::from_ascii(
        "
        .....
        .#...
        .....
        ",
    )
    .unwrap();
    let problem = CoverageProblem::new(&grid, Cell::new(2, 0)).unwrap();
    let outcome = Coverage::new(spiral(Side::Left))
        .unwrap()
        .cover(&problem, &Budget::unlimited());
    assert_eq!(
        outcome.path.cells(),
        cells(&[
            (2, 0),
            (3, 0),
            (4, 0),
            (4, 1),
            (4, 2),
            (3, 2),
            (2, 2),
            (1, 2),
            (0, 2),
            (0, 1),
            (0, 0),
            (1, 0),
            (2, 0),
            (2, 1),
            (3, 1),
        ])
    );
    assert_eq!(outcome.returns.len(), 1);
    assert_eq!((outcome.returns[0].start, outcome.returns[0].end), (11, 12));
    assert_eq!(outcome.metrics.n_revisits, 1);
    assert_eq!(outcome.counters.get("n_backtracking_points"), Some(1));
    assert_eq!(outcome.counters.get("n_marked_points"), Some(5));
    assert_eq!(outcome.counters.get("n_return_searches"), Some(1));
}

#[test]
fn zigzag_backtracks_by_hand() {
    //   ..#..
    //   .....
    //   ..#..
    // Zigzag (right, up, left, down) from (2,1): right to (4,1), up (4,0), left (3,0):
    // dead end. Marked: (2,1) ((1,1) open), (3,1) ((3,2) open), (4,1) ((4,2) open).
    // Octile bounds from (3,0): (3,1) 1, the others sqrt 2: one A* search, to (3,1). Then
    // down (3,2), right (4,2): dead end; (3,1) and (4,1) are dropped, (2,1) remains: the
    // return (4,2) -> (3,1) diagonally (both (3,2) and (4,1) free) -> (2,1), cost
    // 1 + sqrt 2 ((3,2) -> (2,1) would cut the blocked corner (2,2)). The rest of the
    // left half follows without another return.
    let grid = Grid::from_ascii(
        "
        ..#..
        .....
        ..#..
        ",
    )
    .unwrap();
    let problem = CoverageProblem::new(&grid, Cell::new(2, 1)).unwrap();
    let outcome = Coverage::new(zigzag(Rotation::CounterClockwise))
        .unwrap()
        .cover(&problem, &Budget::unlimited());
    assert!(outcome.metrics.is_complete());
    let legs: Vec<&[Cell]> = outcome
        .returns
        .iter()
        .map(|l| &outcome.path.cells()[l.start..=l.end])
        .collect();
    assert_eq!(
        legs,
        [
            &cells(&[(3, 0), (3, 1)])[..],
            &cells(&[(4, 2), (3, 1), (2, 1)])[..]
        ]
    );

    // A point returned to twice counts twice.
    //   .#.#.
    //   .....
    // From (2,1): right to (4,1), up (4,0): dead end. Only (2,1) is marked ((1,1) and
    // (2,0) open); the return goes around the blocked (3,0): (4,1), (3,1), (2,1). Up to
    // (2,0), dead end, back to (2,1), which still has (1,1) open; left and up to (0,0).
    let grid = Grid::from_ascii(
        "
        .#.#.
        .....
        ",
    )
    .unwrap();
    let problem = CoverageProblem::new(&grid, Cell::new(2, 1)).unwrap();
    let outcome = Coverage::new(zigzag(Rotation::CounterClockwise))
        .unwrap()
        .cover(&problem, &Budget::unlimited());
    assert_eq!(
        outcome.path.cells(),
        cells(&[
            (2, 1),
            (3, 1),
            (4, 1),
            (4, 0),
            (4, 1),
            (3, 1),
            (2, 1),
            (2, 0),
            (2, 1),
            (1, 1),
            (0, 1),
            (0, 0),
        ])
    );
    assert_eq!(outcome.counters.get("n_backtracking_points"), Some(2));
    assert_eq!(outcome.counters.get("n_marked_points"), Some(1));
    assert_eq!(outcome.metrics.n_revisits, 4);
}

/// The free cells 4-connected to `start`, by a BFS written here.
fn reachable(grid: &Grid, start: Cell) -> Vec<bool> {
    let mut seen = vec![false; grid.len()];
    let mut stack = vec![start];
    seen[grid.index(start)] = true;
    while let Some(c) = stack.pop() {
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(n) = grid.offset(c, dx, dy) {
                if grid.is_free(n) && !seen[grid.index(n)] {
                    seen[grid.index(n)] = true;
                    stack.push(n);
                }
            }
        }
    }
    seen
}

/// 8-connected distances from `from` (no corner cutting; cost 1 and sqrt 2), by an
/// O(n^2) Dijkstra written here.
fn distances(grid: &Grid, from: Cell) -> Vec<f64> {
    let mut dist = vec![f64::INFINITY; grid.len()];
    let mut done = vec![false; grid.len()];
    dist[grid.index(from)] = 0.0;
    loop {
        let next = (0..grid.len())
            .filter(|&i| !done[i] && dist[i].is_finite())
            .min_by(|&a, &b| dist[a].total_cmp(&dist[b]));
        let Some(i) = next else { break };
        done[i] = true;
        let c = grid.cell(i);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if (dx, dy) == (0, 0) {
                    continue;
                }
                let Some(n) = grid.offset(c, dx, dy) else {
                    continue;
                };
                if !grid.is_free(n) {
                    continue;
                }
                let diagonal = dx != 0 && dy != 0;
                if diagonal
                    && !(grid.offset(c, dx, 0).is_some_and(|s| grid.is_free(s))
                        && grid.offset(c, 0, dy).is_some_and(|s| grid.is_free(s)))
                {
                    continue;
                }
                let cost = if diagonal { 2f64.sqrt() } else { 1.0 };
                let j = grid.index(n);
                if dist[i] + cost < dist[j] {
                    dist[j] = dist[i] + cost;
                }
            }
        }
    }
    dist
}

fn open_neighbour(grid: &Grid, covered: &[bool], c: Cell) -> bool {
    [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dx, dy)| {
        grid.offset(c, dx, dy)
            .is_some_and(|n| grid.is_free(n) && !covered[grid.index(n)])
    })
}

/// Everything the crate docs promise about one run, checked independently.
/// Returns the number of returns and of returns with a tie at the least cost.
fn check_run(grid: &Grid, start: Cell, config: &Config, astar: &mut AStar) -> (u64, u64) {
    let problem = CoverageProblem::new(grid, start).unwrap();
    let outcome = Coverage::new(config.clone())
        .unwrap()
        .cover(&problem, &Budget::unlimited());
    let what = format!("{config:?} from {start} on\n{}", grid.to_ascii());
    assert_eq!(outcome.status, Status::Found, "{what}");
    let path = outcome.path.cells();
    assert_eq!(path[0], start, "{what}");

    // Every step is a valid 8-connected move; every filling step a 4-connected move into
    // an uncovered cell.
    let eight = MoveSet::standard(Connectivity::Eight);
    assert_eq!(
        outcome.path.validate(grid, PathRule::Moves(&eight)),
        Ok(()),
        "{what}"
    );
    let in_return = |i: usize| outcome.returns.iter().any(|l| l.start < i && i <= l.end);
    let mut covered = vec![false; grid.len()];
    covered[grid.index(start)] = true;
    // When each cell was first left with an open neighbour (the marking rule, replayed).
    let mut marked_at: Vec<Option<usize>> = vec![None; grid.len()];
    let mut leg = 0;
    let mut n_ties = 0;
    for i in 1..path.len() {
        if !in_return(i) {
            assert_eq!(path[i - 1].manhattan(path[i]), 1, "{what} step {i}");
            assert!(!covered[grid.index(path[i])], "{what} step {i} refills");
        }
        covered[grid.index(path[i])] = true;
        let left = grid.index(path[i - 1]);
        if marked_at[left].is_none() && open_neighbour(grid, &covered, path[i - 1]) {
            marked_at[left] = Some(i);
        }
        // At the start of a return: the candidates are the covered cells with an open
        // neighbour (the invariant of the crate docs), all marked; the target is one of
        // them at the least 8-connected cost, the one marked last among equal costs, and
        // the leg costs exactly that, as planner-astar run directly finds.
        if let Some(l) = outcome.returns.get(leg) {
            if l.start == i {
                let from = path[i];
                let dist = distances(grid, from);
                let candidates: Vec<usize> = (0..grid.len())
                    .filter(|&c| covered[c] && open_neighbour(grid, &covered, grid.cell(c)))
                    .collect();
                assert!(!candidates.is_empty(), "{what}");
                assert!(candidates.iter().all(|&c| marked_at[c].is_some()), "{what}");
                let best = candidates
                    .iter()
                    .map(|&c| dist[c])
                    .fold(f64::INFINITY, f64::min);
                let tied: Vec<usize> = candidates
                    .iter()
                    .copied()
                    .filter(|&c| (dist[c] - best).abs() < 1e-9)
                    .collect();
                if tied.len() > 1 {
                    n_ties += 1;
                }
                let expected = tied.iter().copied().max_by_key(|&c| marked_at[c]).unwrap();
                let target = path[l.end];
                assert_eq!(target, grid.cell(expected), "{what} return {leg}");
                let leg_cells = &path[l.start..=l.end];
                let leg_cost: f64 = leg_cells.windows(2).map(|w| w[0].euclidean(w[1])).sum();
                assert!((leg_cost - best).abs() < 1e-9, "{what} return {leg}");
                let direct = astar
                    .search(
                        &Problem::new(grid, from, target).unwrap(),
                        &Budget::unlimited(),
                    )
                    .cost
                    .unwrap();
                assert!((leg_cost - direct).abs() < 1e-9, "{what} return {leg}");
                leg += 1;
            }
        }
    }
    assert_eq!(leg, outcome.returns.len(), "{what}");

    // 100 % of the reachable set (BFS here) is covered; the metrics agree.
    let reach = reachable(grid, start);
    let n_reachable = reach.iter().filter(|&&r| r).count() as u64;
    assert!(reach.iter().zip(&covered).all(|(&r, &c)| r == c), "{what}");
    let m = outcome.metrics;
    assert_eq!(
        (m.n_reachable, m.n_covered),
        (n_reachable, n_reachable),
        "{what}"
    );
    assert_eq!(m.percent, 100.0);
    assert_eq!(m.n_revisits, path.len() as u64 - n_reachable);
    let c = &outcome.counters;
    assert_eq!(c.get("n_covered"), Some(n_reachable));
    assert_eq!(c.get("n_moves"), Some(path.len() as u64 - 1));
    assert_eq!(
        c.get("n_fill_moves").unwrap() + c.get("n_return_moves").unwrap(),
        path.len() as u64 - 1
    );
    // Fill moves enter new cells: all but the start's one cover a new cell each.
    assert!(c.get("n_fill_moves").unwrap() < n_reachable);
    assert_eq!(
        c.get("n_backtracking_points"),
        Some(outcome.returns.len() as u64)
    );
    assert_eq!(
        c.get("n_marked_points"),
        Some(marked_at.iter().filter(|m| m.is_some()).count() as u64)
    );
    (outcome.returns.len() as u64, n_ties)
}

#[test]
fn random_maps_are_covered() {
    let configs = [
        spiral(Side::Left),
        spiral(Side::Right),
        zigzag(Rotation::CounterClockwise),
        zigzag(Rotation::Clockwise),
    ];
    let mut astar = AStar::new(planner_astar::Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        ..planner_astar::Config::default()
    })
    .unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(2004);
    let mut n_maps = 0;
    let mut n_returns = 0;
    let mut n_ties = 0;
    while n_maps < 2000 {
        let width = rng.gen_range(1..=11);
        let height = rng.gen_range(1..=11);
        let seed = rng.gen();
        let keep = Cell::new(rng.gen_range(0..width), rng.gen_range(0..height));
        let grid = if rng.gen_bool(0.5) {
            random_cells(width, height, rng.gen_range(0.0..0.45), keep, seed).unwrap()
        } else {
            let n_blocks = rng.gen_range(0..8);
            random_blocks(width, height, n_blocks, 4, keep, seed).unwrap()
        };
        // Pockets the start cannot reach stay free: coverage is measured against the
        // reachable set.
        for config in &configs {
            let (returns, ties) = check_run(&grid, keep, config, &mut astar);
            n_returns += returns;
            n_ties += ties;
        }
        n_maps += 1;
    }
    // The maps are varied enough to need many returns, some with tied nearest points
    // (15031 returns, 1196 with ties when written).
    println!("{n_returns} returns, {n_ties} with ties");
    assert!(n_returns > 10_000 && n_ties > 500, "{n_returns} {n_ties}");
}

#[test]
fn budget_stops_with_the_path_so_far() {
    let grid = random_blocks(12, 12, 6, 4, Cell::new(0, 0), 7).unwrap();
    let problem = CoverageProblem::new(&grid, Cell::new(0, 0)).unwrap();
    let mut planner = Coverage::new(spiral(Side::Left)).unwrap();
    let full = planner.cover(&problem, &Budget::unlimited());
    for n in [0, 1, 5, 40, 100] {
        let cut = planner.cover(&problem, &Budget::expansions(n));
        assert_eq!(cut.status, Status::BudgetExhausted, "{n}");
        assert!(full.path.cells().starts_with(cut.path.cells()), "{n}");
        assert!(!cut.metrics.is_complete());
    }
    // n = 0: no move at all; the path is the start.
    assert_eq!(
        planner.cover(&problem, &Budget::expansions(0)).path.len(),
        1
    );
}

/// `h * 1_000_003 + (a << 32 | b)` over the pairs, wrapping: a fingerprint of a path or
/// of return legs.
fn fingerprint(pairs: impl IntoIterator<Item = (u64, u64)>) -> u64 {
    pairs.into_iter().fold(0u64, |h, (a, b)| {
        h.wrapping_mul(1_000_003).wrapping_add(a << 32 | b)
    })
}

fn path_fingerprint(outcome: &CoverageOutcome) -> u64 {
    fingerprint(
        outcome
            .path
            .cells()
            .iter()
            .map(|c| (u64::from(c.x), u64::from(c.y))),
    )
}

fn counter(outcome: &CoverageOutcome, name: &str) -> u64 {
    outcome.counters.get(name).unwrap()
}

/// The counters of a run, in reporting order.
fn all_counters(outcome: &CoverageOutcome) -> [u64; 11] {
    planner_testkit::COVERAGE_COUNTERS.map(|name| counter(outcome, name))
}

/// A run's counters and the fingerprints of its path and return legs.
type Pinned = ([u64; 11], u64, u64);

/// Random maps of 250 x 250 and 1000 x 1000 cells, a fifth of them blocked: the maps on
/// which sorting every point at every return made the run quadratic (crate docs, "Run
/// time": 222 s on such a million-cell map, under 1 s with the points' index). Counters
/// and fingerprints are those of that code, the seed's procedure as written (2026-12-07):
/// the index changes nothing. Expansion budgets then cut each run to a prefix of its path,
/// within the work they allow. Debug builds (70 s for the million cells) take the small
/// map only unless `GRIDPLAN_ALL_SCENARIOS` is set.
#[test]
fn large_random_maps_keep_their_paths_and_counters() {
    let maps: [(u32, [Pinned; 2]); 2] = [
        (
            250,
            [
                (
                    [
                        49_822, 49_822, 13_912, 63_733, 37_841, 5_675, 27_670, 49_821, 13_912,
                        9_602, 247_612,
                    ],
                    0x26ea_5654_4d9b_3ed9,
                    0xaaab_9ffa_af2d_f753,
                ),
                (
                    [
                        49_822, 49_822, 15_245, 65_066, 36_207, 5_949, 27_439, 49_821, 15_245,
                        10_094, 176_653,
                    ],
                    0x35a5_5835_977d_8560,
                    0x39b8_8096_56c8_60ba,
                ),
            ],
        ),
        (
            1000,
            [
                (
                    [
                        797_745, 797_745, 211_469, 1_009_213, 598_514, 89_743, 446_784, 797_744,
                        211_469, 151_057, 6_007_075,
                    ],
                    0x6e75_d207_f526_a7c0,
                    0x2f91_7a9b_4c47_9b9f,
                ),
                (
                    [
                        797_745, 797_745, 239_214, 1_036_958, 574_823, 93_345, 444_203, 797_744,
                        239_214, 161_720, 4_105_633,
                    ],
                    0x05b6_b34a_0424_6a65,
                    0x9a0b_a1eb_9282_ae00,
                ),
            ],
        ),
    ];
    let all = !cfg!(debug_assertions) || std::env::var_os("GRIDPLAN_ALL_SCENARIOS").is_some();
    for (side, pinned) in maps {
        if side > 250 && !all {
            continue;
        }
        let grid = random_cells(side, side, 0.2, Cell::new(0, 0), 2).unwrap();
        let problem = CoverageProblem::new(&grid, Cell::new(0, 0)).unwrap();
        let configs = [spiral(Side::Left), zigzag(Rotation::CounterClockwise)];
        for (config, (counters, path, returns)) in configs.into_iter().zip(pinned) {
            let what = format!("{side} x {side}, {config:?}");
            let mut planner = Coverage::new(config).unwrap();
            let full = planner.cover(&problem, &Budget::unlimited());
            assert_eq!(full.status, Status::Found, "{what}");
            assert!(full.metrics.is_complete(), "{what}");
            assert_eq!(all_counters(&full), counters, "{what}");
            assert_eq!(path_fingerprint(&full), path, "{what}");
            let legs = full
                .returns
                .iter()
                .map(|leg| (leg.start as u64, leg.end as u64));
            assert_eq!(fingerprint(legs), returns, "{what}");
            let work = counters[7] + counters[10];
            for n in [work / 20, work / 2] {
                let cut = planner.cover(&problem, &Budget::expansions(n));
                assert_eq!(cut.status, Status::BudgetExhausted, "{what} {n}");
                let done = counter(&cut, "n_fill_moves") + counter(&cut, "n_return_expansions");
                assert!(done <= n, "{what} {n}: {done}");
                assert!(
                    full.path.cells().starts_with(cut.path.cells()),
                    "{what} {n}"
                );
            }
        }
    }
}

/// A raised cancel flag or a past deadline ends a run at its first return, before any A*
/// search: the run's clock reads them every `TIME_CHECK_INTERVAL` (1024) fill moves and
/// A* every 1024 expansions, which neither the first filling (8 moves here) nor a short
/// search reaches, so the returns read them before each search (crate docs, "Run time").
#[test]
fn a_cancel_or_a_deadline_stops_the_returns() {
    let grid = random_cells(200, 200, 0.2, Cell::new(0, 0), 2).unwrap();
    let problem = CoverageProblem::new(&grid, Cell::new(0, 0)).unwrap();
    let mut planner = Coverage::new(spiral(Side::Left)).unwrap();
    let full = planner.cover(&problem, &Budget::unlimited());
    let first = full.returns[0].start;
    assert_eq!(first, 8);
    let flag = CancelFlag::new();
    flag.cancel();
    for budget in [
        Budget::unlimited().with_cancel(flag),
        Budget::expansions(u64::MAX).with_time(Duration::ZERO),
    ] {
        let cut = planner.cover(&problem, &budget);
        assert_eq!(cut.status, Status::BudgetExhausted, "{budget:?}");
        assert_eq!(cut.path.cells(), &full.path.cells()[..=first], "{budget:?}");
        assert_eq!(counter(&cut, "n_return_searches"), 0, "{budget:?}");
        assert_eq!(counter(&cut, "n_fill_moves"), first as u64, "{budget:?}");
    }
}

#[test]
fn planner_is_reusable_across_grids() {
    let a = random_cells(9, 7, 0.25, Cell::new(0, 0), 1).unwrap();
    let b = random_cells(5, 11, 0.25, Cell::new(4, 10), 2).unwrap();
    let mut reused = Coverage::new(zigzag(Rotation::CounterClockwise)).unwrap();
    for (grid, start) in [
        (&a, Cell::new(0, 0)),
        (&b, Cell::new(4, 10)),
        (&a, Cell::new(0, 0)),
    ] {
        let problem = CoverageProblem::new(grid, start).unwrap();
        let fresh = Coverage::new(zigzag(Rotation::CounterClockwise))
            .unwrap()
            .cover(&problem, &Budget::unlimited());
        assert_eq!(reused.cover(&problem, &Budget::unlimited()), fresh);
    }
}

#[test]
fn config_from_toml() {
    let config: Config =
        toml::from_str("pattern = \"zigzag\"\nrotation = \"cw\"\nfirst = \"R\"").unwrap();
    assert_eq!(config.rotation, Some(Rotation::Clockwise));
    assert_eq!(config.first, Some(Heading::Right));
    let err = toml::from_str::<Config>("pattern = \"zigzag\"\nside = \"left\"").unwrap_err();
    assert!(err.to_string().contains("unknown field `side`"), "{err}");
    let config: Config = toml::from_str("reference_side = \"right\"\nheading = \"up\"").unwrap();
    assert_eq!(
        (config.reference_side, config.heading),
        (Some(Side::Right), Some(Heading::Up))
    );
}
