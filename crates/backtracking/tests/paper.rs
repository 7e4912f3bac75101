//! Seed 000's twelve maps: every published Backtracking number (Tables 3, 4, 6, 8) and the
//! counter identities.

use crate::common;

use planner_api::{Budget, Cell, Grid, Outcome, Planner, Problem, Status};
use planner_backtracking::{Backtracking, Config};

fn run(grid: &Grid) -> Outcome {
    let n = grid.width() - 1;
    let problem = Problem::new(grid, Cell::new(0, 0), Cell::new(n, n)).unwrap();
    Backtracking::new(Config::default())
        .unwrap()
        .plan(&problem, &Budget::unlimited())
}

/// The published value of every Backtracking key of `expect` against the run.
fn check(name: &str, outcome: &Outcome, expect: &toml::Table) -> usize {
    assert_eq!(outcome.status, Status::Found, "{name}");
    let m = outcome.path.as_ref().unwrap().metrics();
    let mut n = 0;
    for (key, value) in expect {
        let want = value.as_integer().unwrap() as u64;
        let got = match key.as_str() {
            "steps" => m.steps,
            "turns" => m.turns,
            "score" => m.score,
            counter => outcome
                .counters
                .get(counter)
                .unwrap_or_else(|| panic!("{name}: no {counter}")),
        };
        assert_eq!(got, want, "{name}: {key}");
        n += 1;
    }
    n
}

#[test]
fn reproduces_every_published_backtracking_number() {
    let published = common::published();
    let mut n_numbers = 0;
    for (name, grid) in common::paper_maps() {
        let expect = published[&name]["backtracking"].as_table().unwrap();
        n_numbers += check(&name, &run(&grid), expect);
    }
    // 12 maps x (7 counters + D, T, Score).
    assert_eq!(n_numbers, 120);
}

#[test]
fn identities_on_the_paper_maps() {
    for (name, grid) in common::paper_maps() {
        let outcome = run(&grid);
        common::check_identities(&name, &outcome.counters, 4, true);
    }
}
