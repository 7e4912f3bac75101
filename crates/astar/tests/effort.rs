//! The opt-in list of expanded cells and the memory budget.

use planner_api::{Budget, Cell, Connectivity, CostRule, Grid, Planner, Problem, Status};
use planner_astar::{AStar, Config, Heuristic, TieBreak};

/// Plans `problem` with and without recording and checks that recording lists exactly
/// the `n_expanded` expanded cells (distinct, free, start first, goal last when found)
/// and changes nothing else. Returns the number of expanded cells.
fn check(config: &Config, problem: &Problem<'_>, budget: Budget, what: &str) -> usize {
    let mut astar = AStar::new(config.clone()).unwrap();
    let plain = astar.plan(problem, &budget);
    assert!(plain.expanded.is_empty(), "{what}: recorded while off");
    let recorded = astar.plan(problem, &budget.recording_expanded(true));
    let n_expanded = recorded.counters.get("n_expanded").unwrap();
    assert_eq!(recorded.expanded.len() as u64, n_expanded, "{what}");
    assert_eq!(
        (&recorded.counters, &recorded.path, recorded.status),
        (&plain.counters, &plain.path, plain.status),
        "{what}: recording changed the search"
    );
    let mut distinct = recorded.expanded.clone();
    distinct.sort_by_key(|c| (c.y, c.x));
    distinct.dedup();
    assert_eq!(distinct.len(), recorded.expanded.len(), "{what}: repeats");
    assert!(recorded.expanded.iter().all(|&c| problem.grid().is_free(c)));
    assert_eq!(recorded.expanded.first(), Some(&problem.start()), "{what}");
    if recorded.status == Status::Found {
        assert_eq!(recorded.expanded.last(), Some(&problem.goal()), "{what}");
    }
    recorded.expanded.len()
}

#[test]
fn recorded_cells_are_the_expanded_ones_for_every_heuristic() {
    let maps = ["den520d.map", "random512-10-0.map", "arena.map"];
    for map in maps {
        let grid = planner_testkit::movingai(&format!("movingai/{map}"));
        let scenarios = planner_testkit::scenarios(&format!("movingai/{map}.scen"));
        for scenario in scenarios.iter().rev().step_by(97).take(4) {
            let problem = Problem::new(&grid, scenario.start, scenario.goal).unwrap();
            for (moves, heuristic, tie_break, weight) in crate::RECORDING_SETTINGS {
                let config = Config {
                    moves,
                    heuristic,
                    tie_break,
                    weight,
                    ..Config::default()
                };
                let what = format!("{map} {moves:?} {heuristic:?} {tie_break:?} {weight}");
                check(&config, &problem, Budget::unlimited(), &what);
            }
        }
    }
}

/// The same on weighted maps (a recording search is the loop's weighted copy with the
/// heuristic read at run time): den520d with seeded weights 1-9 under both cost rules.
#[test]
fn recorded_cells_are_the_expanded_ones_on_weighted_maps() {
    let grid = planner_testkit::movingai("movingai/den520d.map");
    let scenarios = planner_testkit::scenarios("movingai/den520d.map.scen");
    for rule in [CostRule::Mean, CostRule::Entered] {
        let weighted = planner_bench::seeded_weights(&grid, 32, 9, rule);
        for scenario in scenarios.iter().rev().step_by(211).take(3) {
            let problem = Problem::new(&weighted, scenario.start, scenario.goal).unwrap();
            for (moves, heuristic, tie_break) in [
                (Connectivity::Four, Heuristic::Manhattan, TieBreak::Fifo),
                (Connectivity::Eight, Heuristic::Octile, TieBreak::HighG),
                (Connectivity::Eight, Heuristic::Zero, TieBreak::LowG),
            ] {
                let config = Config {
                    moves,
                    heuristic,
                    tie_break,
                    ..Config::default()
                };
                let what = format!("{rule:?} {moves:?} {heuristic:?} {tie_break:?}");
                check(&config, &problem, Budget::unlimited(), &what);
            }
        }
    }
}

#[test]
fn dijkstra_expands_more_than_astar_and_budgets_cut_the_list() {
    let grid = planner_testkit::movingai("movingai/den520d.map");
    let scenarios = planner_testkit::scenarios("movingai/den520d.map.scen");
    let last = scenarios.last().unwrap();
    let problem = Problem::new(&grid, last.start, last.goal).unwrap();
    let with = |heuristic| Config {
        moves: Connectivity::Eight,
        heuristic,
        ..Config::default()
    };
    let astar = check(
        &with(Heuristic::Octile),
        &problem,
        Budget::unlimited(),
        "octile",
    );
    let dijkstra = check(
        &with(Heuristic::Zero),
        &problem,
        Budget::unlimited(),
        "zero",
    );
    assert!(dijkstra > 2 * astar, "Dijkstra {dijkstra}, A* {astar}");
    let cut = check(
        &with(Heuristic::Zero),
        &problem,
        Budget::expansions(100),
        "cut",
    );
    assert_eq!(cut, 100);
    // A goal walled off: the whole component is expanded and listed.
    let walled = Grid::from_ascii(
        "
        ..#..
        ..#..
        ###..
        ",
    )
    .unwrap();
    let problem = Problem::new(&walled, Cell::new(0, 0), Cell::new(4, 2)).unwrap();
    let n = check(&Config::default(), &problem, Budget::unlimited(), "walled");
    assert_eq!(n, 4);
}

#[test]
fn a_tiny_memory_budget_refuses_before_allocating() {
    let grid = Grid::new(1000, 1000).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(999, 999)).unwrap();
    for (moves, heuristic, mb) in [
        // 1002 x 1002 padded cells of 13.125 bytes and one bit: 13,303,053 bytes, 12.7 MiB.
        (Connectivity::Eight, Heuristic::Octile, 12),
        // 1004 x 1004 padded cells of 13.125 bytes and an 8-byte mask, and the adjacency's
        // copy of the grid: 22,294,338 bytes, 21.3 MiB.
        (Connectivity::Sixteen, Heuristic::Euclidean, 21),
    ] {
        let config = Config {
            moves,
            heuristic,
            ..Config::default()
        };
        let mut astar = AStar::new(config).unwrap();
        let outcome = astar.plan(&problem, &Budget::unlimited().with_memory_mb(mb));
        assert_eq!(outcome.status, Status::BudgetExhausted);
        assert_eq!(outcome.counters.get("n_expanded"), Some(0));
        let message = outcome.memory.expect("a memory shortfall").to_string();
        assert!(
            message.ends_with(&format!(
                "MB for a 1000 x 1000 grid, over the max_memory_mb = {mb} budget"
            )),
            "{message}"
        );
        let needed: u64 = message["needs ".len()..]
            .split(' ')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(needed, mb + 1, "{message}");
        // One more MB is enough, and the same planner then finds the path.
        let outcome = astar.plan(&problem, &Budget::unlimited().with_memory_mb(mb + 1));
        assert_eq!(outcome.status, Status::Found, "{moves:?}");
        assert!(outcome.memory.is_none());
    }
}

#[test]
fn tables_are_sized_by_bits_not_by_eight_bytes_per_cell() {
    // Issue 18: one query on a large open grid held 8 bytes of move masks per cell (and
    // 8 of g, written in full) before the search began. With 8 moves the tables are now
    // the bit grid alone: one bit per padded cell (4002 x 4002 / 8 bytes, and 2 x 512
    // bytes of neighbourhood tables).
    let grid = Grid::new(4000, 4000).unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 0), Cell::new(3999, 3999)).unwrap();
    let mut astar = AStar::new(Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        tie_break: TieBreak::HighG,
        ..Config::default()
    })
    .unwrap();
    let outcome = astar.plan(&problem, &Budget::expansions(1000));
    assert_eq!(outcome.status, Status::BudgetExhausted);
    assert_eq!(astar.table_bytes(), 4002 * 4002 / 8 + 3 + 2 * 512);
}
