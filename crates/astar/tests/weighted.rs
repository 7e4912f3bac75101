//! A* and Dijkstra (A* with the zero heuristic) on weighted grids against the test kit's
//! oracle, a plain Dijkstra over the weighted graph: 10,000 seeded random grids (weights
//! 1-255, blocked densities 0-0.4, both cost rules), 4- and 8-connected, the heuristics
//! admissible for the moves and every tie rule in rotation: equal costs, valid paths whose cost
//! is the reported one, and unreachable goals reported as such.

use planner_api::{
    Budget, Cell, Connectivity, CostRule, Grid, NeighborOrder, Planner, Problem, Status,
};
use planner_astar::{AStar, Config, Heuristic, TieBreak};
use planner_testkit::{random_weighted_problems, weighted_dijkstra};

fn planners(moves: Connectivity, corner_cutting: bool) -> Vec<(String, AStar)> {
    let heuristics: &[Heuristic] = match moves {
        Connectivity::Four => &[Heuristic::Manhattan, Heuristic::Octile, Heuristic::Zero],
        _ => &[
            Heuristic::Octile,
            Heuristic::Euclidean,
            Heuristic::Chebyshev,
            Heuristic::Zero,
        ],
    };
    let mut out = Vec::new();
    for &heuristic in heuristics {
        for tie_break in [
            TieBreak::Fifo,
            TieBreak::Lifo,
            TieBreak::LowG,
            TieBreak::HighG,
        ] {
            let config = Config {
                moves,
                corner_cutting,
                order: NeighborOrder::default(),
                heuristic,
                weight: 1.0,
                tie_break,
            };
            let label = format!("{moves:?} cc={corner_cutting} {heuristic:?} {tie_break:?}");
            out.push((label, AStar::new(config).unwrap()));
        }
    }
    out
}

#[test]
fn ten_thousand_random_weighted_grids_match_the_oracle() {
    let problems = random_weighted_problems(0x5eed_0032, 10_000);
    let mut sets = [
        planners(Connectivity::Four, false),
        planners(Connectivity::Eight, false),
        planners(Connectivity::Eight, true),
    ];
    let (mut compared, mut mismatches, mut unreachable) = (0u64, 0u64, 0u64);
    for (k, p) in problems.iter().enumerate() {
        // Each grid gets the 4-connected set, the 8-connected one, and every fourth grid
        // the corner-cutting one.
        for set in sets.iter_mut().take(if k % 4 == 0 { 3 } else { 2 }) {
            let oracle = weighted_dijkstra(&p.grid, set[0].1.move_set(), p.start, p.goal);
            unreachable += u64::from(oracle.is_none());
            let problem = Problem::new(&p.grid, p.start, p.goal).unwrap();
            // A quarter of the set per grid, in rotation (each heuristic and tie rule meets
            // 2,500 grids or more).
            for (label, astar) in set.iter_mut().skip(k % 4).step_by(4) {
                let search = astar.search(&problem, &Budget::unlimited());
                compared += 1;
                match (oracle, &search.path) {
                    (None, None) => assert_eq!(search.status, Status::NoPath, "{label}"),
                    (Some(cost), Some(path)) => {
                        let rule = planner_api::PathRule::Moves(astar.move_set());
                        path.validate(&p.grid, rule).unwrap();
                        assert_eq!(path.cells().first(), Some(&p.start));
                        assert_eq!(path.cells().last(), Some(&p.goal));
                        assert_eq!(p.grid.path_cost(path.cells()), search.exact_cost.unwrap());
                        if search.exact_cost != Some(cost) {
                            mismatches += 1;
                            eprintln!(
                                "problem {k} {label}: A* {:?}, oracle {cost:?}",
                                search.exact_cost
                            );
                        }
                    }
                    (oracle, path) => {
                        mismatches += 1;
                        eprintln!("problem {k} {label}: oracle {oracle:?}, path {path:?}");
                    }
                }
            }
        }
    }
    eprintln!("{compared} searches compared, {unreachable} unreachable goals (per set), {mismatches} mismatches");
    assert_eq!(mismatches, 0);
    assert!(compared > 70_000, "{compared}");
    assert!(
        unreachable > 100,
        "the generator must produce unreachable goals"
    );
}

/// Hand-checked costs: on a 3 x 1 corridor of weights 1, 9, 1 with a detour row of 1s
/// below, the mean rule goes around (cost 4 moves of 1 is 1 + 1 + 1 + 1 = 4 against
/// 5 + 5 = 10 straight), and the entered rule charges 9 + 1 = 10 straight vs 4 around.
#[test]
fn a_detour_around_a_heavy_cell() {
    let grid = Grid::from_ascii("...\n...").unwrap();
    for rule in [CostRule::Mean, CostRule::Entered] {
        let weighted = grid
            .clone()
            .with_weights(vec![1, 9, 1, 1, 1, 1], rule)
            .unwrap();
        let problem = Problem::new(&weighted, Cell::new(0, 0), Cell::new(2, 0)).unwrap();
        let mut astar = AStar::new(Config::default()).unwrap();
        let outcome = astar.plan(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::Found);
        let path = outcome.path.unwrap();
        assert_eq!(path.cells().len(), 5, "{rule:?}: {:?}", path.cells());
        assert_eq!(
            weighted.path_cost(path.cells()),
            planner_api::Cost::steps(4)
        );
    }
    // With the heavy cell at 2 the straight line costs 1.5 + 1.5 = 3 (mean): it wins.
    let light = grid
        .with_weights(vec![1, 2, 1, 1, 1, 1], CostRule::Mean)
        .unwrap();
    let problem = Problem::new(&light, Cell::new(0, 0), Cell::new(2, 0)).unwrap();
    let search = AStar::new(Config::default())
        .unwrap()
        .search(&problem, &Budget::unlimited());
    assert_eq!(search.exact_cost, Some(planner_api::Cost::steps(3)));
    assert_eq!(search.path.unwrap().cells().len(), 3);
}

/// The heuristic is scaled by the smallest weight: on a grid of all 7s, A* with Manhattan
/// expands exactly what it expands on the unweighted grid (f is 7 times the unweighted f,
/// so the order is the same), and the cost is 7 times the length.
#[test]
fn uniform_weight_scales_costs_and_keeps_the_order() {
    let grid = Grid::from_ascii(
        "
        ......
        .####.
        ......
        ",
    )
    .unwrap();
    let weighted = grid
        .clone()
        .with_weights(vec![7; 18], CostRule::Mean)
        .unwrap();
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let heuristic = if moves == Connectivity::Four {
            Heuristic::Manhattan
        } else {
            Heuristic::Octile
        };
        let config = Config {
            moves,
            heuristic,
            ..Config::default()
        };
        let run = |g: &Grid| {
            let problem = Problem::new(g, Cell::new(0, 2), Cell::new(5, 0)).unwrap();
            AStar::new(config.clone())
                .unwrap()
                .search(&problem, &Budget::unlimited())
        };
        let (plain, heavy) = (run(&grid), run(&weighted));
        assert_eq!(
            heavy.exact_cost.unwrap().units(),
            7 * plain.exact_cost.unwrap().units()
        );
        assert_eq!(plain.stats.n_expanded, heavy.stats.n_expanded, "{moves:?}");
    }
}

/// A move of 16, 32 or 48 directions is charged for its two end cells only: on a 7 x 3
/// grid whose columns 2-4 weigh 65,535, one 48-direction move (1, 0) -> (5, 1) crosses
/// them for its length, 4.12. So A* declares cell costs with 4 and 8 directions only, and
/// with longer moves its specs name `moves` and the reason (the runner's refusal says
/// them); 8 directions still pay for the heavy columns, as the oracle does.
#[test]
fn long_moves_declare_no_cell_costs_naming_moves() {
    let grid = Grid::from_ascii(".......\n.......\n.......").unwrap();
    let row = [1, 1, 65_535, 65_535, 65_535, 1, 1];
    let weighted = grid.with_weights(row.repeat(3), CostRule::Mean).unwrap();
    let problem = Problem::new(&weighted, Cell::new(1, 0), Cell::new(5, 1)).unwrap();
    let astar = |moves| {
        AStar::new(Config {
            moves,
            heuristic: Heuristic::Euclidean,
            ..Config::default()
        })
        .unwrap()
    };
    for moves in [
        Connectivity::Sixteen,
        Connectivity::ThirtyTwo,
        Connectivity::FortyEight,
    ] {
        let specs = astar(moves).specs();
        assert!(!specs.cell_costs, "{moves:?}");
        let condition = specs.cell_costs_only_with.expect("a condition");
        assert_eq!((condition.param, condition.values), ("moves", "4 or 8"));
        assert!(
            condition.reason.contains("end cells"),
            "{}",
            condition.reason
        );
    }
    let long = astar(Connectivity::FortyEight).search(&problem, &Budget::unlimited());
    assert_eq!(
        long.path.unwrap().cells().len(),
        2,
        "one move across the heavy columns"
    );
    for moves in [Connectivity::Four, Connectivity::Eight] {
        let mut eight = astar(moves);
        let specs = eight.specs();
        assert!(
            specs.cell_costs && specs.cell_costs_only_with.is_none(),
            "{moves:?}"
        );
        let search = eight.search(&problem, &Budget::unlimited());
        let oracle =
            weighted_dijkstra(&weighted, eight.move_set(), problem.start(), problem.goal());
        assert_eq!(search.exact_cost, oracle, "{moves:?}");
        assert!(search.exact_cost.unwrap() > planner_api::Cost::steps(196_000));
    }
}
