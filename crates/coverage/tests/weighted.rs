//! Coverage on weighted grids (crate docs, "Weighted grids"): on 500 seeded random
//! weighted grids (weights 1-255, densities 0-0.4, both cost rules), both patterns, every
//! return leg costs what the test kit's oracle (a plain Dijkstra over the weighted graph,
//! 8-connected without corner cutting) says is least between its ends, and goes to a
//! point left behind that no other point left behind beats: the points left when a return
//! starts are the covered cells with an open 4-neighbour (the crate's invariant), rebuilt
//! here from the path so far.

use std::collections::HashSet;

use planner_api::{
    Budget, Cell, Connectivity, CoveragePlanner, CoverageProblem, Grid, MoveSet, PathRule, Status,
};
use planner_coverage::{Config, Coverage, Pattern};
use planner_testkit::{random_weighted_problems, weighted_costs_from};

/// The covered cells of `covered` with a free, uncovered 4-neighbour.
fn points_left(grid: &Grid, covered: &HashSet<Cell>) -> Vec<Cell> {
    let open = |c: Cell, dx: i64, dy: i64| {
        let (x, y) = (i64::from(c.x) + dx, i64::from(c.y) + dy);
        x >= 0 && y >= 0 && {
            let n = Cell::new(x as u32, y as u32);
            grid.contains(n) && grid.is_free(n) && !covered.contains(&n)
        }
    };
    let mut out: Vec<Cell> = covered
        .iter()
        .copied()
        .filter(|&c| {
            [(1, 0), (-1, 0), (0, 1), (0, -1)]
                .iter()
                .any(|&(dx, dy)| open(c, dx, dy))
        })
        .collect();
    out.sort_by_key(|c| (c.y, c.x));
    out
}

#[test]
fn return_legs_are_least_cost_to_the_cheapest_point_left() {
    let eight = MoveSet::standard(Connectivity::Eight);
    let mut planners = [
        Coverage::new(Config::default()).unwrap(),
        Coverage::new(Config {
            pattern: Pattern::Zigzag,
            ..Config::default()
        })
        .unwrap(),
    ];
    assert!(planners.iter().all(|p| p.specs().cell_costs));
    let (mut legs, mut weighted_choice) = (0u64, 0u64);
    for (k, p) in random_weighted_problems(0xc0_0032, 500).iter().enumerate() {
        let planner = &mut planners[k % 2];
        let problem = CoverageProblem::new(&p.grid, p.start).unwrap();
        let outcome = planner.cover(&problem, &Budget::unlimited());
        assert_eq!(outcome.status, Status::Found, "problem {k}");
        assert!(outcome.metrics.is_complete(), "problem {k}");
        outcome
            .path
            .validate(&p.grid, PathRule::Moves(&eight))
            .unwrap();
        let cells = outcome.path.cells();
        for leg in &outcome.returns {
            legs += 1;
            let (from, to) = (cells[leg.start], cells[leg.end]);
            let cost = p.grid.path_cost(&cells[leg.start..=leg.end]);
            // The oracle's costs from the leg's start to every cell, in one search.
            let weighted = weighted_costs_from(&p.grid, &eight, from);
            assert_eq!(
                weighted[p.grid.index(to)],
                Some(cost),
                "problem {k}: leg {leg:?}"
            );
            let covered: HashSet<Cell> = cells[..=leg.start].iter().copied().collect();
            let left = points_left(&p.grid, &covered);
            assert!(left.contains(&to), "problem {k}: {to} is no point left");
            let costs: Vec<_> = left
                .iter()
                .map(|&c| weighted[p.grid.index(c)].unwrap())
                .collect();
            let least = costs.iter().copied().min().unwrap();
            assert_eq!(
                cost, least,
                "problem {k}: leg {leg:?} is not to the cheapest point"
            );
            // How often weights changed the choice: the octile-nearest point differs.
            let plain = p.grid.without_weights();
            let unweighted = weighted_costs_from(&plain, &eight, from);
            let octile: Vec<_> = left
                .iter()
                .map(|&c| unweighted[plain.index(c)].unwrap())
                .collect();
            let nearest = octile.iter().copied().min().unwrap();
            let to_octile = octile[left.iter().position(|&c| c == to).unwrap()];
            weighted_choice += u64::from(to_octile > nearest);
        }
    }
    // The test means something: many legs, and weights often chose another point than
    // the unweighted rule would.
    eprintln!("{legs} legs, {weighted_choice} to a point the unweighted rule would not choose");
    assert!(legs >= 5_000, "{legs} legs");
    assert!(weighted_choice >= 400, "{weighted_choice} of {legs} legs");
}

#[test]
fn unweighted_runs_are_unchanged_by_weights_of_one() {
    for (k, p) in random_weighted_problems(5, 200).iter().enumerate() {
        let plain = p.grid.without_weights();
        let ones = plain
            .clone()
            .with_weights(vec![1; plain.len()], planner_api::CostRule::Mean)
            .unwrap();
        let mut a = Coverage::new(Config::default()).unwrap();
        let mut b = Coverage::new(Config::default()).unwrap();
        let x = a.cover(
            &CoverageProblem::new(&plain, p.start).unwrap(),
            &Budget::unlimited(),
        );
        let y = b.cover(
            &CoverageProblem::new(&ones, p.start).unwrap(),
            &Budget::unlimited(),
        );
        assert_eq!(x.path, y.path, "problem {k}");
        assert_eq!(x.returns, y.returns, "problem {k}");
    }
}
