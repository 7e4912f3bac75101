//! Backtracking against hand counts, against a literal transcription of seed 000's Fig. 5
//! written here (counters, budgets, best path), against BFS, and under budgets.

use crate::common;

use std::time::Duration;

use planner_api::{
    Budget, Cell, Connectivity, Counters, Grid, MoveSet, NeighborOrder, Outcome, Path, PathRank,
    PathRule, Planner, Problem, Status,
};
use planner_backtracking::{Backtracking, Config, ConfigError, Prune};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const NAMES: [&str; 8] = [
    "n_expanded",
    "n_neighbor_checks",
    "n_blocked",
    "n_skipped",
    "n_solutions",
    "n_dead_ends",
    "n_backtracks",
    "max_depth",
];

fn values(counters: &Counters) -> [u64; 8] {
    NAMES.map(|n| counters.get(n).unwrap())
}

fn plan(grid: &Grid, start: Cell, goal: Cell, config: Config, budget: Budget) -> Outcome {
    let problem = Problem::new(grid, start, goal).unwrap();
    Backtracking::new(config).unwrap().plan(&problem, &budget)
}

fn cells(list: &[(u32, u32)]) -> Vec<Cell> {
    list.iter().map(|&c| c.into()).collect()
}

/// Hand-counted maps: `check(map, start, goal, expect, best)` with expect in [`NAMES`] order.
fn check(map: &str, start: (u32, u32), goal: (u32, u32), expect: [u64; 8], best: &[(u32, u32)]) {
    let grid = Grid::from_ascii(map).unwrap();
    let outcome = plan(
        &grid,
        start.into(),
        goal.into(),
        Config::default(),
        Budget::unlimited(),
    );
    assert_eq!(outcome.status, Status::Found, "{map}");
    assert_eq!(values(&outcome.counters), expect, "{map}");
    assert_eq!(outcome.path.unwrap().cells(), cells(best), "{map}");
    common::check_identities(map, &outcome.counters, 4, true);
}

#[test]
fn hand_counted() {
    // A corridor with a spur, (0,0) to (2,0); calls numbered in order, moves R L D U,
    // b = blocked (or outside), s = on the path, -> = recursion:
    //   1 (0,0): R -> 2 (1,0): R -> 3 (2,0) goal (solution 1, D 2, T 0) back 1
    //                           L (0,0) s
    //                           D -> 4 (1,1): R b, L b, D b, U (1,0) s: dead end; back 2
    //                           U b; back 3
    //            L b, D b, U b
    // 4 calls, 3 x 4 checks, blocked 3 + 1 + 3 = 7, skipped 2, 1 solution, 1 dead end,
    // 3 backtracks, at most 3 cells on the path.
    check(
        "...\n#.#",
        (0, 0),
        (2, 0),
        [4, 12, 7, 2, 1, 1, 3, 3],
        &[(0, 0), (1, 0), (2, 0)],
    );
    // A ring around a pillar, (0,0) to (2,2): two solutions of equal rank (D 4, T 1,
    // Score 5); the first found, over the top, is kept.
    //   1 (0,0): R -> 2 (1,0): R -> 3 (2,0): R b, L s, D -> 4 (2,1): R b, L (1,1) b,
    //                 D -> 5 (2,2) goal; U s. | 3: U b. | 2: L s, D (1,1) b, U b.
    //            L b, D -> 6 (0,1): R (1,1) b, L b, D -> 7 (0,2): R -> 8 (1,2):
    //                 R -> 9 (2,2) goal; L s, D b, U (1,1) b. | 7: L b, D b, U s. | 6: U s.
    //            U b
    // 9 calls, 7 non-goal calls x 4 = 28 checks, 14 blocked, 6 skipped, 2 solutions,
    // no dead end, 8 backtracks, 5 cells at most.
    check(
        "...\n.#.\n...",
        (0, 0),
        (2, 2),
        [9, 28, 14, 6, 2, 0, 8, 5],
        &[(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)],
    );
    // Start = goal: the root is a goal call.
    check("..", (1, 0), (1, 0), [1, 0, 0, 0, 1, 0, 0, 1], &[(1, 0)]);
}

/// The reference's counters, best (rank, cells), every solution's rank, and whether it completed.
type RefRun = ([u64; 8], Option<(PathRank, Vec<Cell>)>, Vec<PathRank>, bool);

// Positions in [`NAMES`].
const EXP: usize = 0;
const CHECKS: usize = 1;
const BLOCKED: usize = 2;
const SKIPPED: usize = 3;
const SOLUTIONS: usize = 4;
const DEAD: usize = 5;
const BACK: usize = 6;
const DEPTH: usize = 7;

/// Seed 000's Fig. 5, transcribed literally as a recursion over `Grid` and
/// `MoveSet::apply`, with the counters of section 2.5 counted one check at a time, and a
/// budget: a call is refused once `budget` calls were made, and then the search stops at
/// once (the refused recursion's check is not counted, and no open call returns).
struct Reference<'a> {
    grid: &'a Grid,
    moves: &'a MoveSet,
    goal: Cell,
    budget: u64,
    visited: Vec<bool>,
    path: Vec<Cell>,
    c: [u64; 8],
    best: Option<(PathRank, Vec<Cell>)>,
    /// The rank of every solution, in the order found.
    ranks: Vec<PathRank>,
}

impl Reference<'_> {
    fn run(grid: &Grid, moves: &MoveSet, start: Cell, goal: Cell, budget: u64) -> RefRun {
        let mut r = Reference {
            grid,
            moves,
            goal,
            budget,
            visited: vec![false; grid.len()],
            path: vec![start],
            c: [0; 8],
            best: None,
            ranks: Vec::new(),
        };
        let complete = budget > 0 && {
            r.visited[grid.index(start)] = true;
            r.call(start)
        };
        (r.c, r.best, r.ranks, complete)
    }

    /// `Backtrack(cell)`; false when the budget stopped the search.
    fn call(&mut self, cell: Cell) -> bool {
        self.c[EXP] += 1;
        self.c[DEPTH] = self.c[DEPTH].max(self.path.len() as u64);
        if cell == self.goal {
            self.c[SOLUTIONS] += 1;
            let rank = Path::new(self.path.clone()).rank();
            self.ranks.push(rank);
            if self.best.as_ref().is_none_or(|(b, _)| rank < *b) {
                self.best = Some((rank, self.path.clone()));
            }
            return true;
        }
        let mut recursed = false;
        for mv in self.moves.moves() {
            match self.moves.apply(self.grid, cell, mv) {
                None => {
                    self.c[CHECKS] += 1;
                    self.c[BLOCKED] += 1;
                }
                Some(next) if self.visited[self.grid.index(next)] => {
                    self.c[CHECKS] += 1;
                    self.c[SKIPPED] += 1;
                }
                Some(next) => {
                    if self.c[EXP] == self.budget {
                        return false;
                    }
                    self.c[CHECKS] += 1;
                    recursed = true;
                    self.visited[self.grid.index(next)] = true;
                    self.path.push(next);
                    if !self.call(next) {
                        return false;
                    }
                    self.path.pop();
                    self.visited[self.grid.index(next)] = false;
                    self.c[BACK] += 1;
                }
            }
        }
        if !recursed {
            self.c[DEAD] += 1;
        }
        true
    }
}

/// Compares the planner with the reference at several budgets, the full run included.
fn compare_with_reference(what: &str, grid: &Grid, start: Cell, goal: Cell, config: &Config) {
    let moves = MoveSet::new(config.moves, config.corner_cutting, &config.order).unwrap();
    let k = moves.moves().len() as u64;
    let (full, best, ranks, complete) = Reference::run(grid, &moves, start, goal, u64::MAX);
    assert!(complete);
    let outcome = plan(grid, start, goal, config.clone(), Budget::unlimited());
    assert_eq!(values(&outcome.counters), full, "{what}: counters");
    common::check_identities(what, &outcome.counters, k, true);
    // The best path: the reference's, and no solution ranks better.
    match (&outcome.path, best) {
        (Some(path), Some((rank, cells))) => {
            assert_eq!(outcome.status, Status::Found, "{what}");
            assert_eq!(path.cells(), cells, "{what}: best path");
            assert_eq!(path.rank(), rank, "{what}");
            assert_eq!(ranks.iter().min(), Some(&rank), "{what}");
            // Ties keep the first found.
            assert_eq!(
                ranks.iter().position(|r| *r == rank),
                ranks.iter().position(|r| *r == path.rank())
            );
            path.validate(grid, PathRule::Moves(&moves)).unwrap();
        }
        (None, None) => assert_eq!(outcome.status, Status::NoPath, "{what}"),
        (p, b) => panic!("{what}: path {p:?} vs reference {b:?}"),
    }
    // Truncated runs: the counters of exactly the work done.
    let n = full[0];
    let mut budgets = vec![0, 1, 2, n / 3, n / 2, n.saturating_sub(1), n];
    if n <= 60 {
        budgets = (0..=n).collect();
    }
    let mut planner = Backtracking::new(config.clone()).unwrap();
    let problem = Problem::new(grid, start, goal).unwrap();
    for budget in budgets {
        let (expect, best, _, complete) = Reference::run(grid, &moves, start, goal, budget);
        let outcome = planner.plan(&problem, &Budget::expansions(budget));
        let what = format!("{what}, budget {budget}");
        assert_eq!(values(&outcome.counters), expect, "{what}: counters");
        common::check_identities(&what, &outcome.counters, k, complete);
        assert_eq!(
            outcome.path.as_ref().map(|p| p.cells().to_vec()),
            best.map(|b| b.1),
            "{what}: best so far"
        );
        let status = match (complete, &outcome.path) {
            (false, _) => Status::BudgetExhausted,
            (true, Some(_)) => Status::Found,
            (true, None) => Status::NoPath,
        };
        assert_eq!(outcome.status, status, "{what}");
    }
}

#[test]
fn paper_map_1_matches_the_reference_at_every_budget() {
    let grid = common::movingai("paper/map01.map");
    compare_with_reference(
        "map01",
        &grid,
        Cell::new(0, 0),
        Cell::new(5, 5),
        &Config::default(),
    );
}

fn random_grid(rng: &mut ChaCha8Rng, max_side: u32, density: f64) -> (Grid, Cell, Cell) {
    let (w, h) = (rng.gen_range(1..=max_side), rng.gen_range(2..=max_side));
    let free = (0..w * h).map(|_| !rng.gen_bool(density)).collect();
    let mut grid = Grid::from_free_cells(w, h, free).unwrap();
    let start = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
    let goal = Cell::new(rng.gen_range(0..w), rng.gen_range(0..h));
    grid.set_free(start, true);
    grid.set_free(goal, true);
    (grid, start, goal)
}

#[test]
fn random_grids_match_the_reference() {
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let configs = [
        (Config::default(), 5, 0.25),
        (
            Config {
                order: "U L D R".parse().unwrap(),
                ..Config::default()
            },
            5,
            0.25,
        ),
        (
            Config {
                moves: Connectivity::Eight,
                ..Config::default()
            },
            4,
            0.35,
        ),
        (
            Config {
                moves: Connectivity::Eight,
                corner_cutting: true,
                ..Config::default()
            },
            4,
            0.4,
        ),
        (
            Config {
                moves: Connectivity::Sixteen,
                ..Config::default()
            },
            4,
            0.4,
        ),
    ];
    for round in 0..60 {
        for (config, side, density) in &configs {
            let (grid, start, goal) = random_grid(&mut rng, *side, *density);
            // Keep the enumeration small enough for the recursive reference.
            let probe = plan(
                &grid,
                start,
                goal,
                config.clone(),
                Budget::expansions(300_000),
            );
            if probe.status == Status::BudgetExhausted {
                continue;
            }
            let what = format!(
                "round {round} {} order {}\n{grid:?}{start} -> {goal}",
                config.moves, config.order
            );
            compare_with_reference(&what, &grid, start, goal, config);
        }
    }
}

#[test]
fn best_steps_equal_bfs_wherever_both_finish() {
    use planner_bfs::{Bfs, Config as BfsConfig};
    let check = |what: &str, grid: &Grid, start: Cell, goal: Cell, moves: Connectivity| {
        let problem = Problem::new(grid, start, goal).unwrap();
        let outcome = Backtracking::new(Config {
            moves,
            ..Config::default()
        })
        .unwrap()
        .plan(&problem, &Budget::expansions(2_000_000));
        if outcome.status == Status::BudgetExhausted {
            return false;
        }
        let bfs = Bfs::new(BfsConfig {
            moves,
            ..BfsConfig::default()
        })
        .unwrap()
        .plan(&problem, &Budget::unlimited());
        let steps = |o: &Outcome| o.path.as_ref().map(|p| p.metrics().steps);
        assert_eq!(steps(&outcome), steps(&bfs), "{what}");
        true
    };
    for (name, grid) in common::paper_maps() {
        let n = grid.width() - 1;
        assert!(check(
            &name,
            &grid,
            Cell::new(0, 0),
            Cell::new(n, n),
            Connectivity::Four
        ));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut finished = 0;
    for round in 0..150 {
        let (grid, start, goal) = random_grid(&mut rng, 7, 0.3);
        let moves = if round % 3 == 0 {
            Connectivity::Eight
        } else {
            Connectivity::Four
        };
        finished += usize::from(check(
            &format!("round {round}\n{grid:?}"),
            &grid,
            start,
            goal,
            moves,
        ));
    }
    assert!(finished > 100, "{finished}");
}

#[test]
fn budget_on_an_open_12x12_grid() {
    let grid = Grid::new(12, 12).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(11, 11)).unwrap();
    let four = MoveSet::standard(Connectivity::Four);
    let mut planner = Backtracking::new(Config::default()).unwrap();
    let outcome = planner.plan(&problem, &Budget::expansions(100_000));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(outcome.counters.get("n_expanded"), Some(100_000));
    common::check_identities("open 12x12", &outcome.counters, 4, false);
    // The counters so far and the best path so far are those of the reference.
    let (expect, best, _, complete) =
        Reference::run(&grid, &four, Cell::new(0, 0), Cell::new(11, 11), 100_000);
    assert!(!complete);
    assert_eq!(values(&outcome.counters), expect);
    let path = outcome.path.unwrap();
    path.validate(&grid, PathRule::Moves(&four)).unwrap();
    assert_eq!(Some(path.cells().to_vec()), best.map(|b| b.1));
    assert!(outcome.counters.get("n_solutions").unwrap() > 0);
    // A zero budget refuses the root.
    let outcome = planner.plan(&problem, &Budget::expansions(0));
    assert_eq!(
        (outcome.status, outcome.path),
        (Status::BudgetExhausted, None)
    );
    assert!(outcome.counters.iter().all(|(_, v)| v == 0));
    // A wall-clock limit ends the search too (the counters then depend on the machine).
    let outcome = planner.plan(
        &problem,
        &Budget::unlimited().with_time(Duration::from_millis(20)),
    );
    assert_eq!(outcome.status, Status::BudgetExhausted);
    outcome
        .path
        .unwrap()
        .validate(&grid, PathRule::Moves(&four))
        .unwrap();
    common::check_identities("open 12x12, timed", &outcome.counters, 4, false);
}

#[test]
fn identities_on_every_map() {
    for (name, grid) in common::paper_maps() {
        let n = grid.width() - 1;
        for (moves, k) in [(Connectivity::Four, 4), (Connectivity::Eight, 8)] {
            let config = Config {
                moves,
                ..Config::default()
            };
            let outcome = plan(
                &grid,
                Cell::new(0, 0),
                Cell::new(n, n),
                config,
                Budget::expansions(1_000_000),
            );
            let complete = outcome.status != Status::BudgetExhausted;
            common::check_identities(&format!("{name} {moves}"), &outcome.counters, k, complete);
        }
    }
    let budget = Budget::expansions(50_000);
    for file in ["wpi/map1.txt", "wpi/map2.txt", "wpi/map3.txt"] {
        let (grid, pairs) = common::wpi(file);
        for &(s, g) in pairs
            .iter()
            .filter(|&&(s, g)| Problem::new(&grid, s, g).is_ok())
        {
            let outcome = plan(&grid, s, g, Config::default(), budget);
            assert_eq!(outcome.status, Status::BudgetExhausted, "{file}");
            common::check_identities(&format!("{file} {s}->{g}"), &outcome.counters, 4, false);
        }
    }
    for map in common::movingai_maps() {
        let grid = common::movingai(&format!("movingai/{map}"));
        let (s, g) = common::first_scenario(&format!("movingai/{map}.scen"));
        let outcome = plan(&grid, s, g, Config::default(), budget);
        let complete = outcome.status != Status::BudgetExhausted;
        common::check_identities(&map, &outcome.counters, 4, complete);
        if let Some(path) = &outcome.path {
            path.validate(
                &grid,
                PathRule::Moves(&MoveSet::standard(Connectivity::Four)),
            )
            .unwrap();
        }
    }
}

#[test]
fn deep_paths_need_no_recursion() {
    // A serpentine corridor on 256 x 255 cells: one path of 32,895 cells (each even row
    // open, odd rows open only at alternating ends), far beyond a thread's call stack in
    // a recursive implementation.
    let (w, h) = (256u32, 255u32);
    let mut grid = Grid::new(w, h).unwrap();
    for y in (1..h).step_by(2) {
        let gap = if y % 4 == 1 { w - 1 } else { 0 };
        for x in (0..w).filter(|&x| x != gap) {
            grid.set_free(Cell::new(x, y), false);
        }
    }
    let goal = Cell::new(if (h - 1) % 4 == 0 { w - 1 } else { 0 }, h - 1);
    let outcome = plan(
        &grid,
        Cell::new(0, 0),
        goal,
        Config::default(),
        Budget::unlimited(),
    );
    assert_eq!(outcome.status, Status::Found);
    let cells_on_path = u64::from(w) * 128 + 127;
    assert_eq!(outcome.path.unwrap().len() as u64, cells_on_path);
    assert_eq!(outcome.counters.get("max_depth"), Some(cells_on_path));
    assert_eq!(outcome.counters.get("n_solutions"), Some(1));
}

#[test]
fn branch_and_bound_keeps_the_best_and_changes_the_counters() {
    let bound = Config {
        prune: Prune::Bound,
        ..Config::default()
    };
    let mut fewer = 0;
    for (name, grid) in common::paper_maps() {
        let n = grid.width() - 1;
        let off = plan(
            &grid,
            Cell::new(0, 0),
            Cell::new(n, n),
            Config::default(),
            Budget::unlimited(),
        );
        let on = plan(
            &grid,
            Cell::new(0, 0),
            Cell::new(n, n),
            bound.clone(),
            Budget::unlimited(),
        );
        assert_eq!(on.status, Status::Found, "{name}");
        assert_eq!(on.path, off.path, "{name}");
        assert_eq!(off.counters.get("n_pruned"), None);
        common::check_identities(&name, &on.counters, 4, true);
        let pruned = on.counters.get("n_pruned").unwrap();
        let (a, b) = (
            on.counters.get("n_expanded").unwrap(),
            off.counters.get("n_expanded").unwrap(),
        );
        assert!(a <= b, "{name}");
        fewer += usize::from(a < b && pruned > 0);
    }
    assert!(fewer >= 6, "{fewer}");
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for round in 0..100 {
        let (grid, start, goal) = random_grid(&mut rng, 5, 0.25);
        let moves = if round % 2 == 0 {
            Connectivity::Four
        } else {
            Connectivity::Eight
        };
        let off = plan(
            &grid,
            start,
            goal,
            Config {
                moves,
                ..Config::default()
            },
            Budget::expansions(500_000),
        );
        if off.status == Status::BudgetExhausted {
            continue;
        }
        let on = plan(
            &grid,
            start,
            goal,
            Config {
                moves,
                ..bound.clone()
            },
            Budget::unlimited(),
        );
        assert_eq!(on.path, off.path, "round {round}\n{grid:?}");
        common::check_identities(
            &format!("round {round}"),
            &on.counters,
            u64::from(moves.n_directions()),
            true,
        );
    }
    // Under a budget the pruned run obeys the truncated identities as well.
    let grid = Grid::new(12, 12).unwrap();
    let on = plan(
        &grid,
        Cell::new(0, 0),
        Cell::new(11, 11),
        bound,
        Budget::expansions(5_000),
    );
    common::check_identities(
        "open 12x12 bound",
        &on.counters,
        4,
        on.status != Status::BudgetExhausted,
    );
}

#[test]
fn eight_connected_identities_use_eight_checks_per_call() {
    let grid = common::movingai("paper/map03.map");
    let config = Config {
        moves: Connectivity::Eight,
        ..Config::default()
    };
    let outcome = plan(
        &grid,
        Cell::new(0, 0),
        Cell::new(5, 5),
        config,
        Budget::unlimited(),
    );
    assert_eq!(outcome.status, Status::Found);
    let c = &outcome.counters;
    let get = |n| c.get(n).unwrap();
    assert_eq!(
        get("n_neighbor_checks"),
        8 * (get("n_expanded") - get("n_solutions"))
    );
    // Diagonals shorten the best path below the 4-connected 10 steps.
    assert!(outcome.path.unwrap().metrics().steps < 10);
}

#[test]
fn planner_is_reusable_across_grids() {
    let mut planner = Backtracking::new(Config::default()).unwrap();
    let maps = common::paper_maps();
    let first: Vec<Outcome> = maps
        .iter()
        .map(|(_, g)| {
            let n = g.width() - 1;
            planner.plan(
                &Problem::new(g, Cell::new(0, 0), Cell::new(n, n)).unwrap(),
                &Budget::unlimited(),
            )
        })
        .collect();
    // Again, after a truncated run on another grid, in reverse order.
    let open = Grid::new(8, 8).unwrap();
    planner.plan(
        &Problem::new(&open, Cell::new(0, 0), Cell::new(7, 7)).unwrap(),
        &Budget::expansions(777),
    );
    for ((_, g), expect) in maps.iter().zip(&first).rev() {
        let n = g.width() - 1;
        let again = planner.plan(
            &Problem::new(g, Cell::new(0, 0), Cell::new(n, n)).unwrap(),
            &Budget::unlimited(),
        );
        assert_eq!(&again, expect);
    }
}

#[test]
fn config_keys_and_errors() {
    let config: Config =
        toml::from_str("moves = 8\ncorner_cutting = true\norder = \"U D L R\"\nprune = \"bound\"")
            .unwrap();
    assert_eq!(
        (config.moves, config.prune),
        (Connectivity::Eight, Prune::Bound)
    );
    assert!(Backtracking::new(config.clone()).is_ok());
    let json = serde_json::to_string(&config).unwrap();
    assert_eq!(serde_json::from_str::<Config>(&json).unwrap(), config);
    assert_eq!(toml::from_str::<Config>("").unwrap(), Config::default());
    assert_eq!(Config::default().prune, Prune::Off);
    assert_eq!(Config::default().order, NeighborOrder::default());
    assert!(toml::from_str::<Config>("prune = \"always\"").is_err());
    assert!(toml::from_str::<Config>("moves = 6").is_err());
    assert!(toml::from_str::<Config>("order = \"R L D X\"").is_err());
    assert!(toml::from_str::<Config>("budget = 5").is_err());
    let err = Backtracking::new(Config {
        order: "R L D".parse().unwrap(),
        ..Config::default()
    })
    .unwrap_err();
    assert!(matches!(err, ConfigError::Order(_)));
    assert!(err.to_string().starts_with("parameter `order`: "), "{err}");
    let err = Backtracking::new(Config {
        corner_cutting: true,
        ..Config::default()
    })
    .unwrap_err();
    assert!(matches!(err, ConfigError::CornerCutting(_)));
    assert!(
        err.to_string().starts_with("parameter `corner_cutting`: "),
        "{err}"
    );
    assert_eq!(
        Backtracking::new(Config::default()).unwrap().name(),
        "backtracking"
    );
}

#[test]
fn parallel_enumeration_is_identical_to_the_serial_run() {
    let parallel = Config {
        parallel: true,
        ..Config::default()
    };
    let mut cases: Vec<(String, Grid, Cell, Cell)> = common::paper_maps()
        .into_iter()
        .map(|(name, g)| {
            let n = g.width() - 1;
            (name, g, Cell::new(0, 0), Cell::new(n, n))
        })
        .collect();
    // The open 5x5 grid from a middle cell: four subtrees.
    cases.push((
        "open 5x5".into(),
        Grid::new(5, 5).unwrap(),
        Cell::new(2, 2),
        Cell::new(4, 0),
    ));
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for round in 0..40 {
        let (g, s, t) = random_grid(&mut rng, 5, 0.2);
        cases.push((format!("round {round}"), g, s, t));
    }
    for (what, grid, start, goal) in &cases {
        for moves in [Connectivity::Four, Connectivity::Eight] {
            if moves == Connectivity::Eight && grid.len() > 16 {
                continue;
            }
            let serial = plan(
                grid,
                *start,
                goal.to_owned(),
                Config {
                    moves,
                    ..Config::default()
                },
                Budget::unlimited(),
            );
            let par = plan(
                grid,
                *start,
                *goal,
                Config {
                    moves,
                    ..parallel.clone()
                },
                Budget::unlimited(),
            );
            assert_eq!(par, serial, "{what} {moves}\n{grid:?}");
        }
    }
    // With a budget the serial search runs.
    let grid = Grid::new(12, 12).unwrap();
    let budget = Budget::expansions(10_000);
    let serial = plan(
        &grid,
        Cell::new(0, 0),
        Cell::new(11, 11),
        Config::default(),
        budget,
    );
    let par = plan(&grid, Cell::new(0, 0), Cell::new(11, 11), parallel, budget);
    assert_eq!(par, serial);
}
