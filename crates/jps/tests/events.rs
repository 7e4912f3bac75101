//! JPS's recorded steps (`Budget::record_events`, what `plan --trace` and the page's
//! frontier show): one `generating` step per insertion into OPEN and one `updating` step
//! per further relaxation, the expanding steps the expanded cells, `f - g` the octile
//! estimate to the goal, every parent a jump point expanded before and in a straight or
//! diagonal-first line of sight of its successor's leg (the cells between are the path's),
//! the parents from the goal back the path's jump points; recording changes nothing. Every
//! variant, with and without goal bounding.

use std::collections::HashSet;

use planner_api::{Cell, Problem, SearchEventKind, Status};
use planner_jps::{Config, Jps};

fn octile(a: Cell, b: Cell) -> f64 {
    let (dx, dy) = (f64::from(a.x.abs_diff(b.x)), f64::from(a.y.abs_diff(b.y)));
    dx.max(dy) + (2f64.sqrt() - 1.0) * dx.min(dy)
}

#[test]
fn recorded_steps_agree_with_the_counters_and_the_path() {
    let problems = planner_testkit::random_problems(53, 60, (2, 28), (0, 3500));
    // The cases the checks met: paths found, and updates (a node reached again cheaper).
    let (mut found, mut updates) = (0, 0);
    for variant in ["jps", "jps_prime", "jps_plus"] {
        for goal_bounding in [false, true] {
            let config: Config = toml::from_str(&format!(
                "variant = {variant:?}\ngoal_bounding = {goal_bounding}"
            ))
            .unwrap();
            let mut planner = Jps::new(config).unwrap();
            for (i, (grid, start, goal)) in problems.iter().enumerate() {
                let what = format!("{variant} bounding {goal_bounding} problem {i}");
                let problem = Problem::new(grid, *start, *goal).unwrap();
                // The start's insertion is the one push that relaxes nothing.
                let recorded = planner_testkit::plan_recorded(&what, &mut planner, &problem, 1);
                check_steps(&what, &recorded, *start, *goal);
                found += usize::from(recorded.status == Status::Found);
                updates += recorded
                    .events
                    .iter()
                    .filter(|e| e.kind == SearchEventKind::Updating)
                    .count();
            }
        }
    }
    assert!(
        found > 100 && updates > 10,
        "found {found}, updates {updates}"
    );
}

/// The steps' values and order, and the parents back from the goal.
fn check_steps(what: &str, outcome: &planner_api::Outcome, start: Cell, goal: Cell) {
    let order = planner_testkit::check_step_order(what, &outcome.events, |e, order| {
        let h = octile(e.cell, goal);
        assert!((e.f - e.g - h).abs() < 1e-9 * (1.0 + e.f), "{what}: {e:?}");
        if e.kind != SearchEventKind::Expanding {
            // At g(parent) plus the octile distance of the jump; never into CLOSED.
            if let Some(parent) = e.parent {
                let g_parent = order.last[&parent].0;
                let jump = octile(parent, e.cell);
                assert!(
                    (e.g - g_parent - jump).abs() < 1e-9 * (1.0 + e.g),
                    "{what}: {e:?}"
                );
            }
            assert!(
                !order.parents.contains_key(&e.cell),
                "{what}: pushed when closed"
            );
        }
    });
    let parents = &order.parents;
    if outcome.status == Status::Found {
        let path: HashSet<Cell> = outcome
            .path
            .as_ref()
            .unwrap()
            .cells()
            .iter()
            .copied()
            .collect();
        let mut at = goal;
        let mut chain = vec![goal];
        while let Some(Some(parent)) = parents.get(&at) {
            chain.push(*parent);
            at = *parent;
        }
        assert_eq!(
            at, start,
            "{what}: the parents from the goal end at the start"
        );
        assert!(chain.iter().all(|c| path.contains(c)), "{what}: {chain:?}");
        // The path's length is the sum of the jumps' octile lengths.
        let jumps: f64 = chain.windows(2).map(|w| octile(w[0], w[1])).sum();
        let length = outcome.path.as_ref().unwrap().metrics().length;
        assert!((jumps - length).abs() < 1e-9 * (1.0 + length), "{what}");
    }
}
