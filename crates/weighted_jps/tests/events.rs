//! Weighted JPS's recorded steps (`Budget::record_events`): one `generating` step per
//! insertion into OPEN, one `updating` step per further relaxation (a push that only adds
//! a direction to a node at its own cost is none; its expansion again is a step), the
//! expanding steps the expanded cells (again-expanded ones included); `f - g` the octile
//! estimate times the smallest weight; every push's parent the node being expanded; a
//! node expands with its last push's g and parent; the parents from the goal back the
//! path's jump points, the goal's g the path's cost; recording changes nothing.

use planner_api::{Cell, Problem, Status};
use planner_weighted_jps::{Config, WeightedJps};

fn octile(a: Cell, b: Cell) -> f64 {
    let (dx, dy) = (f64::from(a.x.abs_diff(b.x)), f64::from(a.y.abs_diff(b.y)));
    dx.max(dy) + (2f64.sqrt() - 1.0) * dx.min(dy)
}

#[test]
fn recorded_steps_agree_with_the_counters_and_the_path() {
    let mut planner = WeightedJps::new(Config::default()).unwrap();
    let (mut found, mut updates) = (0, 0);
    for (i, p) in planner_testkit::random_weighted_problems(59, 200)
        .iter()
        .enumerate()
    {
        let what = format!("problem {i}");
        let problem = Problem::new(&p.grid, p.start, p.goal).unwrap();
        // The start's insertion is the one push that relaxes nothing.
        let outcome = planner_testkit::plan_recorded(&what, &mut planner, &problem, 1);
        let min_weight = f64::from(p.grid.weights().map_or(1, |w| w.min()));
        let order = planner_testkit::check_step_order(&what, &outcome.events, |e, _| {
            let h = octile(e.cell, p.goal) * min_weight;
            assert!((e.f - e.g - h).abs() < 1e-6 * (1.0 + e.f), "{what}: {e:?}");
        });
        updates += order.updates;
        let (last, parents) = (&order.last, &order.parents);
        if outcome.status == Status::Found {
            found += 1;
            let path = outcome.path.as_ref().unwrap();
            let mut at = p.goal;
            while let Some(Some(parent)) = parents.get(&at) {
                assert!(path.cells().contains(parent), "{what}");
                at = *parent;
            }
            assert_eq!(at, p.start, "{what}");
            let goal_g = last[&p.goal].0;
            let cost = p.grid.path_cost(path.cells()).to_f64();
            assert!((goal_g - cost).abs() < 1e-6 * (1.0 + cost), "{what}");
        }
    }
    // The cases met: paths and cheaper reaches (expansions again do not occur on these
    // grids: the oracle test finds none in 10,000).
    assert!(found > 100 && updates > 100, "{found} {updates}");
}
