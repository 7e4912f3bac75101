//! Bidirectional A*'s recorded steps (`Budget::record_events`): counted as its counters
//! count, each expansion's cell in the expanded list, every `f - g` the estimate to one of
//! the two ends (written out here, times the smallest weight), every parent a neighbour
//! expanded before; recording changes nothing.

use planner_api::{Cell, Problem, SearchEventKind};
use planner_bidirectional_astar::{BidirectionalAStar, Config};

fn octile(a: Cell, b: Cell) -> f64 {
    let (dx, dy) = (f64::from(a.x.abs_diff(b.x)), f64::from(a.y.abs_diff(b.y)));
    dx.max(dy) + (2f64.sqrt() - 1.0) * dx.min(dy)
}

fn manhattan(a: Cell, b: Cell) -> f64 {
    f64::from(a.x.abs_diff(b.x) + a.y.abs_diff(b.y))
}

#[test]
fn recorded_steps_agree_with_the_counters() {
    let mut problems: Vec<(planner_api::Grid, Cell, Cell)> =
        planner_testkit::random_problems(47, 60, (2, 26), (0, 3500));
    problems.extend(
        planner_testkit::random_weighted_problems(47, 40)
            .into_iter()
            .map(|p| (p.grid, p.start, p.goal)),
    );
    for eight in [false, true] {
        let config: Config =
            toml::from_str(&format!("moves = {}", if eight { 8 } else { 4 })).unwrap();
        let mut planner = BidirectionalAStar::new(config).unwrap();
        let estimate = |a, b| if eight { octile(a, b) } else { manhattan(a, b) };
        for (i, (grid, start, goal)) in problems.iter().enumerate() {
            let what = format!("eight {eight} problem {i}");
            let problem = Problem::new(grid, *start, *goal).unwrap();
            // Both ends are inserted without a relaxation.
            let recorded = planner_testkit::plan_recorded(&what, &mut planner, &problem, 2);
            let min_weight = grid.weights().map_or(1.0, |w| f64::from(w.min()));
            let mut expanded_so_far = std::collections::HashSet::new();
            for e in &recorded.events {
                let h = e.f - e.g;
                let ends = [estimate(e.cell, *goal), estimate(e.cell, *start)];
                assert!(
                    ends.iter()
                        .any(|end| (h - end * min_weight).abs() < 1e-6 * (1.0 + e.f)),
                    "{what}: {e:?}"
                );
                if let Some(parent) = e.parent {
                    let (dx, dy) = (parent.x.abs_diff(e.cell.x), parent.y.abs_diff(e.cell.y));
                    assert!(dx <= 1 && dy <= 1 && dx + dy > 0, "{what}: {e:?}");
                    assert!(expanded_so_far.contains(&parent), "{what}: {e:?}");
                }
                if e.kind == SearchEventKind::Expanding {
                    expanded_so_far.insert(e.cell);
                }
            }
        }
    }
}
