//! Bidirectional A* on weighted grids against the test kit's oracle (a plain Dijkstra over
//! the weighted graph): the same 10,000 seeded random grids as A*'s test (weights 1-255,
//! blocked densities 0-0.4, mean and entered cost rules), 4- and 8-connected: equal costs,
//! valid paths whose cost is the reported one, unreachable goals reported as such.

use planner_api::{Budget, Connectivity, NeighborOrder, Problem, Status};
use planner_bidirectional_astar::{BidirectionalAStar, Config};
use planner_testkit::{random_weighted_problems, weighted_dijkstra};

#[test]
fn ten_thousand_random_weighted_grids_match_the_oracle() {
    let problems = random_weighted_problems(0x5eed_0032, 10_000);
    let mut planners: Vec<BidirectionalAStar> = [Connectivity::Four, Connectivity::Eight]
        .into_iter()
        .map(|moves| {
            BidirectionalAStar::new(Config {
                moves,
                corner_cutting: false,
                order: NeighborOrder::default(),
            })
            .unwrap()
        })
        .collect();
    let (mut compared, mut mismatches, mut found) = (0u64, 0u64, 0u64);
    for (k, p) in problems.iter().enumerate() {
        let problem = Problem::new(&p.grid, p.start, p.goal).unwrap();
        for planner in planners.iter_mut() {
            let moves = match &planner_api::Planner::specs(planner).path_rule {
                planner_api::PathSpec::Moves(moves) => moves.clone(),
                planner_api::PathSpec::AnyAngle => unreachable!(),
            };
            let oracle = weighted_dijkstra(&p.grid, &moves, p.start, p.goal);
            let search = planner.search(&problem, &Budget::unlimited());
            compared += 1;
            match (oracle, &search.path) {
                (None, None) => assert_eq!(search.status, Status::NoPath),
                (Some(cost), Some(path)) => {
                    found += 1;
                    path.validate(&p.grid, planner_api::PathRule::Moves(&moves))
                        .unwrap();
                    assert_eq!(path.cells().first(), Some(&p.start));
                    assert_eq!(path.cells().last(), Some(&p.goal));
                    assert_eq!(p.grid.path_cost(path.cells()), search.exact_cost.unwrap());
                    if search.exact_cost != Some(cost) {
                        mismatches += 1;
                        eprintln!("problem {k}: {:?} vs oracle {cost:?}", search.exact_cost);
                    }
                }
                (oracle, path) => {
                    mismatches += 1;
                    eprintln!("problem {k}: oracle {oracle:?}, path {path:?}");
                }
            }
        }
    }
    eprintln!("{compared} searches, {found} found, {mismatches} mismatches");
    assert_eq!(mismatches, 0);
    assert_eq!(compared, 20_000);
    assert!(found > 10_000 && found < compared);
}
