//! Seed 002 through the runner: the generated maps are the committed ones, every PA-star
//! path of every config is valid and its counters are those of its local searches, and the
//! paper's length claims on the 140 x 120 maps; CAPSO's guide and evaluation counters are
//! those of the reference guide and of their formula.

use crate::common;

use common::{configs, root};
use planner_runner::config;
use planner_runner::RunRecord;

/// `cargo xtask gen-pastar-maps` writes exactly the files in maps/pastar/.
#[test]
fn generated_maps_are_the_committed_ones() {
    for map in planner_pastar::generate::specs() {
        let path = root().join("maps/pastar").join(map.name);
        let committed = std::fs::read_to_string(&path).unwrap();
        assert!(
            committed == planner_maps::to_movingai(&map.grid),
            "{} differs from the generator's output: run `cargo xtask gen-pastar-maps`",
            path.display()
        );
        for (start, goal) in &map.pairs {
            assert!(map.grid.is_free(*start) && map.grid.is_free(*goal));
        }
    }
}

/// Every PA-star configuration of every config finds a valid any-angle path from start
/// to goal on every one of its problems (one repeat each).
#[test]
fn every_pastar_path_in_every_config_is_valid_and_passes_its_marks() {
    let mut checked = 0;
    for path in configs() {
        let mut experiment = config::load(&path).unwrap();
        experiment
            .planners
            .retain(|p| p.name == planner_pastar::NAME);
        if experiment.planners.is_empty() {
            continue;
        }
        experiment.repeats = 1;
        for record in common::run(&experiment, 2) {
            let at = format!(
                "{} {} #{} {}",
                path.display(),
                record.map,
                record.problem,
                record.planner
            );
            assert_eq!(record.status.as_str(), "found", "{at}");
            assert_eq!(record.valid, Some(true), "{at}");
            assert_eq!(record.counters.get("n_fallbacks"), Some(0), "{at}");
            // Its marks are the local segments' ends, in pairs along the path.
            let segments = record.counters.get("n_local_segments").unwrap() as usize;
            assert_eq!(record.marks.len(), 2 * segments, "{at}");
            let cells = record.path.as_ref().unwrap().cells();
            let mut from = 0;
            for mark in &record.marks {
                let k = cells[from..].iter().position(|&c| c == mark.cell);
                from += k.unwrap_or_else(|| panic!("{at}: {mark:?} not on the path after {from}"));
            }
            checked += 1;
        }
    }
    assert!(checked >= 50, "{checked}");
}

fn length(records: &[RunRecord], map: &str, planner: &str) -> f64 {
    records
        .iter()
        .find(|r| r.map == map && r.planner == planner && r.repeat == 0)
        .and_then(|r| r.length)
        .unwrap_or_else(|| panic!("no {planner} run on {map}"))
}

/// Tables 6-8: on the no-obstacle and line-obstacle maps PA-star is never longer than
/// TA-star; without obstacles it is the straight line (111.80) and TA-star 120.71.
#[test]
fn pastar_config_lengths_on_the_140x120_maps() {
    let mut experiment = config::load(&root().join("configs/pastar.toml")).unwrap();
    experiment.repeats = 1;
    experiment
        .maps
        .retain(|m| m.grid.width() == 140 && m.grid.height() == 120);
    let records = common::run(&experiment, 2);
    let open = "open-140x120.map";
    assert_eq!(
        format!("{:.2}", length(&records, open, "PA-star")),
        "111.80"
    );
    assert_eq!(
        format!("{:.4}", length(&records, open, "TA-star")),
        "120.7107"
    );
    for map in [open, "two-140x120.map", "several-140x120.map"] {
        for pa in ["PA-star", "PA-star-size"] {
            assert!(
                length(&records, map, pa) <= length(&records, map, "TA-star"),
                "{pa} on {map}"
            );
        }
    }
    // Without obstacles nothing is searched.
    let free = records
        .iter()
        .find(|r| r.map == open && r.planner == "PA-star")
        .unwrap();
    assert_eq!(free.counters.get("n_expanded"), Some(0));
}

/// PA-star's A* counters are the sums of its local searches (peak OPEN their maximum). The
/// marks give each local search's start and goal, so every PA-star run of every config (as
/// snapshotted) is replayed here through `planner_testkit::reference_astar` with the local
/// search's settings (Algorithm 2's neighbourhood, Euclidean h, weight beta, the tie rule):
/// the snapshot's PA-star counters are checked against an independent search. Its own
/// counters too: `n_obstacles_crossed` against `planner_testkit::obstacles_crossed` (a
/// flood fill of the blocked cells on the line), `n_local_segments` against the marks and
/// `n_merged` as their difference (no fallback ran).
#[test]
fn pastar_counters_are_the_reference_local_searches() {
    let n_checked =
        common::for_each_snapshotted_run(planner_pastar::NAME, |path, map, params, r| {
            let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
            let config: planner_pastar::Config = params.clone().try_into().unwrap();
            let planner = planner_pastar::PaStar::new(config.clone()).unwrap();
            let tie = common::tie(config.tie_break);
            assert_eq!(r.counters.get("n_fallbacks"), Some(0), "{what}");
            // Sums of the reference counters, but peak OPEN (the last) their maximum.
            let mut expect = [0u64; 7];
            for pair in r.marks.chunks(2) {
                let (start, goal) = (pair[0].cell, pair[1].cell);
                let h = |c: planner_api::Cell| {
                    let (dx, dy) = (c.x.abs_diff(goal.x), c.y.abs_diff(goal.y));
                    planner_api::Cost::euclidean(dx, dy).scaled(config.beta)
                };
                let (status, _, counters) = planner_testkit::reference_astar(
                    &map.grid,
                    planner.local_moves(),
                    h,
                    tie,
                    start,
                    goal,
                );
                assert_eq!(status, planner_api::Status::Found, "{what}");
                for (sum, value) in expect[..6].iter_mut().zip(counters) {
                    *sum += value;
                }
                expect[6] = expect[6].max(counters[6]);
            }
            let actual = planner_testkit::REFERENCE_COUNTERS.map(|n| r.counters.get(n).unwrap());
            assert_eq!(actual, expect, "{what}");
            // Its own counters: the obstacles the line crosses, by a flood fill of its
            // blocked cells; a local search per pair of marks; the merges the rest.
            let crossed = planner_testkit::obstacles_crossed(&map.grid, r.start, r.goal);
            let local = r.marks.len() as u64 / 2;
            assert_eq!(
                r.counters.get("n_obstacles_crossed"),
                Some(crossed),
                "{what}"
            );
            assert_eq!(r.counters.get("n_local_segments"), Some(local), "{what}");
            assert_eq!(r.counters.get("n_merged"), Some(crossed - local), "{what}");
        });
    // pastar.toml: PA-star and PA-star-size x 7 problems x 2 test repeats = 28; the beta,
    // connecting-distance, radius and threshold studies: 56.
    assert_eq!(n_checked, 28 + 56);
}

/// CAPSO's counters that an independent method fixes, on every CAPSO run of every config
/// (`configs/pastar.toml` and `configs/capso-control-points.toml`, as snapshotted): the
/// guide's `n_guide_expanded` and `guide_block` are `planner_testkit::reference_capso_guide`'s
/// on the run's map, start and goal (the guide's block A* written again from its module
/// docs); the budget never runs out, so `n_fitness_evaluations` (= `n_expanded`) is
/// `P + T P` and `n_iterations` is `T` for the label's population `P` and iterations `T`
/// (none when the guide finds no route); a found path is valid and touches no blocked
/// cell. The seeded swarm's counters (segments, cache hits, reseeds, restarts) and the
/// whole run are held to the reference swarm in `capso.rs`.
#[test]
fn every_capso_run_matches_the_reference_guide() {
    let entry = planner_registry::find("capso").unwrap();
    let n_checked = common::for_each_snapshotted_run(entry.name, |path, map, params, r| {
        let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
        // The label's parameters as resolved, the defaults included.
        let resolved = (entry.factory)(params).unwrap().resolved().clone();
        let param = |key: &str| resolved[key].as_u64().unwrap();
        let (p, t) = (param("population"), param("iterations"));
        let get = |name: &str| r.counters.get(name).unwrap();
        // A run whose start is its goal returns the one-cell path before the guide.
        let guide = planner_testkit::reference_capso_guide(&map.grid, r.start, r.goal);
        let (expanded, block) = match r.start == r.goal {
            true => (0, 0),
            false => (guide.n_expanded, u64::from(guide.block)),
        };
        assert_eq!(get("n_guide_expanded"), expanded, "{what}");
        assert_eq!(get("guide_block"), block, "{what}");
        let (evaluations, iterations) = match block {
            0 => (0, 0),
            _ => (p + t * p, t),
        };
        assert_ne!(r.status.as_str(), "budget_exhausted", "{what}");
        assert_eq!(get("n_fitness_evaluations"), evaluations, "{what}");
        assert_eq!(get("n_expanded"), evaluations, "{what}");
        assert_eq!(get("n_iterations"), iterations, "{what}");
        if r.status.as_str() == "found" {
            assert_eq!(r.valid, Some(true), "{what}");
            assert_eq!(get("final_collision_cells"), 0, "{what}");
            assert_eq!(get("final_collision_length_milli"), 0, "{what}");
        }
    });
    // pastar.toml: CAPSO x 7 problems x 2 test repeats = 14; capso-control-points.toml:
    // 4 labels x 1 problem x 2 repeats = 8.
    assert_eq!(n_checked, 14 + 8);
}

/// `cargo xtask plan` prints PA-star's marks (text and JSON): its local segments' ends.
#[test]
fn plan_prints_pastar_marks() {
    let args = planner_runner::plan::PlanArgs {
        map: root().join("maps/pastar/two-140x120.map"),
        planner: planner_pastar::NAME.into(),
        start: Some(planner_api::Cell::new(20, 10)),
        goal: Some(planner_api::Cell::new(70, 110)),
        ..Default::default()
    };
    let result = planner_runner::plan::run(&args).unwrap();
    let problem = planner_api::Problem::new(
        &result.grid,
        planner_api::Cell::new(20, 10),
        planner_api::Cell::new(70, 110),
    )
    .unwrap();
    let report = planner_pastar::PaStar::new(planner_pastar::Config::default())
        .unwrap()
        .plan_detailed(&problem, &planner_api::Budget::unlimited());
    let ends: Vec<String> = report
        .segments
        .iter()
        .map(|s| format!("{}, {}", s.start, s.goal))
        .collect();
    assert_eq!(ends, ["(38, 46), (51, 73)"]);
    let text = result.to_text();
    assert!(
        text.contains("marks: H1 (38, 46), H1' (51, 73)\n"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_str(&result.to_json().unwrap()).unwrap();
    assert_eq!(json["marks"][1]["label"], "H1'");
    assert_eq!(json["marks"][1]["cell"], serde_json::json!([51, 73]));
}
