//! Theta*'s and Lazy Theta*'s recorded searches (`Budget::record_expanded`,
//! `Budget::record_events`): the expanded cells and steps agree with the counters, with `f =
//! g + |cell goal|` written out here, and with the path (the parents back from the goal are
//! its waypoints); recording changes nothing.

use std::collections::HashMap;

use planner_api::{Budget, Cell, Problem, SearchEventKind, Status};
use planner_theta_star::{AnyAngle, Config, Variant};

#[test]
fn recorded_steps_agree_with_the_counters_and_the_path() {
    let problems = planner_testkit::random_problems(43, 80, (2, 28), (0, 3500));
    for variant in [Variant::Theta, Variant::Lazy] {
        let mut search = AnyAngle::new(&Config::default()).unwrap();
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let what = format!("{variant:?} problem {i}");
            let problem = Problem::new(grid, *start, *goal).unwrap();
            let plain = search.search(&problem, &Budget::unlimited(), variant);
            assert!(
                plain.expanded.is_empty() && plain.events.is_empty(),
                "{what}"
            );
            let budget = Budget::unlimited()
                .recording_expanded(true)
                .recording_events(true);
            let recorded = search.search(&problem, &budget, variant);
            assert_eq!(
                (recorded.status, &recorded.path, recorded.stats),
                (plain.status, &plain.path, plain.stats),
                "{what}: recording changed the search"
            );
            let stats = recorded.stats;
            let s = stats.search;
            let counts = (s.n_open_insertions, s.n_relaxations, s.n_expanded);
            let (events, expanded) = (&recorded.events, &recorded.expanded);
            planner_testkit::check_step_counts(&what, events, expanded, counts, 1);
            let mut pushed: HashMap<Cell, (f64, Option<Cell>)> = HashMap::new();
            let mut parents: HashMap<Cell, Option<Cell>> = HashMap::new();
            let mut repaired = 0;
            for e in &recorded.events {
                let h = e.cell.euclidean(*goal);
                assert!(
                    (e.f - (e.g + h)).abs() < 1e-9 * (1.0 + e.f),
                    "{what}: {e:?}"
                );
                match e.kind {
                    SearchEventKind::Expanding => {
                        // Lazy Theta* may repair a parent without line of sight when it
                        // expands the node; Theta* expands what it pushed last.
                        if pushed.get(&e.cell) != Some(&(e.g, e.parent)) {
                            assert_eq!(variant, Variant::Lazy, "{what}: {e:?}");
                            repaired += 1;
                        }
                        parents.insert(e.cell, e.parent);
                    }
                    _ => {
                        pushed.insert(e.cell, (e.g, e.parent));
                    }
                }
            }
            assert!(repaired <= stats.n_parent_repairs, "{what}");
            if recorded.status == Status::Found {
                let mut back = vec![*goal];
                while let Some(Some(parent)) = parents.get(back.last().unwrap()) {
                    back.push(*parent);
                }
                back.reverse();
                assert_eq!(
                    Some(back.as_slice()),
                    recorded.path.as_ref().map(|p| p.cells()),
                    "{what}"
                );
            }
        }
    }
}
