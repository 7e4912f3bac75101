//! The opt-in search steps (`Budget::record_events`, what `plan --trace` writes): checked
//! against the counters, the expanded cells, the path and the heuristic written out here,
//! on random grids (weighted ones too) and every heuristic and tie rule.

use std::collections::HashMap;

use planner_api::{Cell, Connectivity, Outcome, Problem, SearchEventKind, Status};
use planner_astar::{AStar, Config, Heuristic, TieBreak};

/// The estimate from `c` to `goal`, in cells, written out from each heuristic's definition.
fn estimate(heuristic: Heuristic, c: Cell, goal: Cell) -> f64 {
    let (dx, dy) = (
        f64::from(c.x.abs_diff(goal.x)),
        f64::from(c.y.abs_diff(goal.y)),
    );
    match heuristic {
        Heuristic::Manhattan => dx + dy,
        Heuristic::Octile => dx.max(dy) + (2f64.sqrt() - 1.0) * dx.min(dy),
        Heuristic::Euclidean => (dx * dx + dy * dy).sqrt(),
        Heuristic::Chebyshev => dx.max(dy),
        Heuristic::Zero => 0.0,
    }
}

/// Checks `events` of a search that gave `outcome` (and `expanded`, recorded with them).
fn check(what: &str, config: &Config, problem: &Problem<'_>, outcome: &Outcome, min_weight: f64) {
    let events = &outcome.events;
    // A node expands with the g and parent of its last push, and f = g + weight * h.
    let mut last: HashMap<Cell, (f64, Option<Cell>)> = HashMap::new();
    let mut parents: HashMap<Cell, Option<Cell>> = HashMap::new();
    let mut previous_f = f64::NEG_INFINITY;
    for e in events {
        let h = estimate(config.heuristic, e.cell, problem.goal()) * min_weight * config.weight;
        assert!(
            (e.f - (e.g + h)).abs() <= 1e-6 * (1.0 + e.f.abs()),
            "{what}: {e:?}, h {h}"
        );
        match e.kind {
            SearchEventKind::Generating => {
                assert!(
                    !last.contains_key(&e.cell),
                    "{what}: generated twice: {e:?}"
                );
                last.insert(e.cell, (e.g, e.parent));
            }
            SearchEventKind::Updating => {
                let (g, _) = last[&e.cell];
                assert!(e.g < g, "{what}: an update that does not lower g: {e:?}");
                assert!(
                    !parents.contains_key(&e.cell),
                    "{what}: updated after its expansion"
                );
                last.insert(e.cell, (e.g, e.parent));
            }
            SearchEventKind::Expanding => {
                assert_eq!(last.get(&e.cell), Some(&(e.g, e.parent)), "{what}: {e:?}");
                if let Some(parent) = e.parent {
                    assert!(parents.contains_key(&parent), "{what}: parent not expanded");
                }
                parents.insert(e.cell, e.parent);
                // With a consistent heuristic at weight 1, f never decreases.
                if config.weight == 1.0 && config.heuristic != Heuristic::Chebyshev {
                    assert!(e.f >= previous_f - 1e-9, "{what}: f fell to {e:?}");
                    previous_f = e.f;
                }
            }
        }
    }
    if outcome.status == Status::Found {
        // The parents from the goal back are the path.
        let mut back = vec![problem.goal()];
        while let Some(Some(parent)) = parents.get(back.last().unwrap()) {
            back.push(*parent);
        }
        back.reverse();
        assert_eq!(
            Some(back.as_slice()),
            outcome.path.as_ref().map(|p| p.cells()),
            "{what}"
        );
    }
}

#[test]
fn search_steps_agree_with_the_counters_the_path_and_the_heuristic() {
    let problems = planner_testkit::random_problems(41, 60, (2, 30), (0, 4000));
    for (moves, heuristic, tie_break, weight) in crate::RECORDING_SETTINGS {
        let config = Config {
            moves,
            heuristic,
            tie_break,
            weight,
            ..Config::default()
        };
        let mut astar = AStar::new(config.clone()).unwrap();
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let what = format!("{config:?} problem {i}");
            // The start's insertion is the one push that relaxes nothing.
            let recorded = planner_testkit::plan_recorded(&what, &mut astar, &problem, 1);
            check(&what, &config, &problem, &recorded, 1.0);
        }
    }
    // Weighted grids: g in cost units, the heuristic times the smallest weight.
    let config = Config {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        tie_break: TieBreak::HighG,
        ..Config::default()
    };
    let mut astar = AStar::new(config.clone()).unwrap();
    for (i, p) in planner_testkit::random_weighted_problems(41, 60)
        .iter()
        .enumerate()
    {
        let problem = Problem::new(&p.grid, p.start, p.goal).unwrap();
        let what = format!("weighted problem {i}");
        // The start's insertion is the one push that relaxes nothing.
        let recorded = planner_testkit::plan_recorded(&what, &mut astar, &problem, 1);
        let min_weight = f64::from(p.grid.weights().unwrap().min());
        check(&what, &config, &problem, &recorded, min_weight);
    }
}
