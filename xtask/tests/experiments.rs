//! The experiment runner end to end: every config snapshotted, the paper's numbers,
//! thread-count independence, config errors, atomic output.

mod common;

use common::{configs, root};
use planner_runner::config;
use planner_runner::RunRecord;

/// Every counter and metric of every run of every config (trimmed by its `[test]`
/// limits, which the snapshot's header then says), with timing and memory redacted. Review changes with `cargo insta review`.
#[test]
fn every_config_is_snapshotted() {
    let paths = configs();
    assert!(!paths.is_empty());
    for path in paths {
        let full = config::load(&path).unwrap();
        let trimmed = full.test.problems_per_map.is_some() || full.test.repeats.is_some();
        let experiment = full.trimmed_for_test();
        let records = compact(&common::run(&experiment, 2));
        let name = experiment.name.clone();
        let file = path.file_name().unwrap().to_string_lossy().to_string();
        // The header says which runs these are: a config with `[test]` limits is held to
        // the runs within them (this test is the command that reruns them).
        let description = match trimmed {
            true => format!("the runs of configs/{file} within its [test] limits"),
            false => format!("every run of configs/{file}"),
        };
        // insta's settings are thread-local: assert here, after the parallel runs.
        insta::with_settings!({
            snapshot_path => "../../snapshots",
            prepend_module_to_snapshot => false,
            description => description,
            omit_expression => true,
        }, {
            insta::assert_yaml_snapshot!(name, records, {
                "[].time_ms" => "[time]",
                "[].peak_heap_bytes" => "[memory]",
                "[].setup_ms" => "[time]",
            });
        });
    }
}

/// The records with cells written `x,y` and paths on one line, for readable snapshots.
fn compact(records: &[RunRecord]) -> Vec<serde_json::Value> {
    let cell = |c: planner_api::Cell| format!("{},{}", c.x, c.y);
    records
        .iter()
        .map(|r| {
            let mut value = serde_json::to_value(r).unwrap();
            value["start"] = cell(r.start).into();
            value["goal"] = cell(r.goal).into();
            value["path"] = match &r.path {
                Some(path) => path
                    .cells()
                    .iter()
                    .map(|&c| cell(c))
                    .collect::<Vec<_>>()
                    .join(" ")
                    .into(),
                None => serde_json::Value::Null,
            };
            if !r.marks.is_empty() {
                let marks: Vec<String> = r
                    .marks
                    .iter()
                    .map(|m| format!("{}@{}", m.label, cell(m.cell)))
                    .collect();
                value["marks"] = marks.join(" ").into();
            }
            value
        })
        .collect()
}

fn deterministic_fields(records: &[RunRecord]) -> Vec<RunRecord> {
    records
        .iter()
        .cloned()
        .map(|mut r| {
            r.time_ms = 0.0;
            r.setup_ms = 0.0;
            r.peak_heap_bytes = 0;
            r
        })
        .collect()
}

#[test]
fn thread_count_does_not_change_results() {
    for path in configs() {
        let experiment = config::load(&path).unwrap().trimmed_for_test();
        let one = common::run(&experiment, 1);
        let three = common::run(&experiment, 3);
        let a = serde_json::to_string(&deterministic_fields(&one)).unwrap();
        let b = serde_json::to_string(&deterministic_fields(&three)).unwrap();
        assert_eq!(a, b, "{}", path.display());
    }
}

/// For every number `maps/paper/manifest.json` says a map reproduces, the run gives the
/// value of `maps/paper/published.toml` (seed 000 Tables 3-8).
#[test]
fn paper_config_reproduces_every_published_number() {
    let experiment = config::load(&root().join("configs/paper.toml")).unwrap();
    let records = common::run(&experiment, 2);
    let manifest: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root().join("maps/paper/manifest.json")).unwrap(),
    )
    .unwrap();
    let published = experiment.published.as_ref().unwrap();
    let mut checked = 0;
    for entry in manifest.as_array().unwrap() {
        let file = entry["file"].as_str().unwrap();
        let stem = file.trim_end_matches(".map");
        for (planner, metrics) in entry["reproduces"].as_object().unwrap() {
            let record = records
                .iter()
                .find(|r| r.map == file && r.algorithm == *planner && r.repeat == 0)
                .unwrap_or_else(|| panic!("no {planner} run on {file}"));
            for metric in metrics.as_array().unwrap() {
                let metric = metric.as_str().unwrap();
                let actual = match metric {
                    "steps" => record.steps.unwrap(),
                    "turns" => record.turns.unwrap(),
                    "score" => record.score.unwrap(),
                    counter => record.counters.get(counter).unwrap(),
                };
                let expected = published.get(stem, planner, metric).unwrap();
                assert_eq!(actual as f64, expected, "{file} {planner} {metric}");
                checked += 1;
            }
        }
    }
    let planners: Vec<&str> = experiment.planners.iter().map(|p| p.name).collect();
    let expected = if planners.contains(&"backtracking") {
        228
    } else {
        108
    };
    assert_eq!(checked, expected);
}

/// Parses `text` as a config in `configs/` and compares the error with `expect`.
fn check_error(text: &str, expect: &str) {
    let path = root().join("configs/bad.toml");
    let error = config::parse(&path, text).map(|_| ()).unwrap_err();
    let shown = error
        .to_string()
        .replace(&path.display().to_string(), "bad.toml");
    assert_eq!(shown, expect);
}

const MAPS: &str = "[[maps]]\nfiles = [\"../maps/paper/map01.map\"]\nproblems = \"corners\"\n";

#[test]
fn config_errors_name_file_line_column_and_key() {
    check_error(
        &format!("name = \"x\"\nthreds = 2\n{MAPS}[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:2:1: unknown field `threds`, expected one of `name`, `description`, `output`, `threads`, `repeats`, `seed`, `budget`, `figures`, `figures_per_map`, `figures_pick`, `figures_expanded`, `charts`, `ompl`, `paths`, `outputs`, `published`, `test`, `sections`, `maps`, `planners`",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = \"astr\"\n"),
        &format!("bad.toml:6:11: planner `a`: unknown planner \"astr\" in key `planner`, expected one of {}", planner_registry::names().join(", ")),
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.fast]\nplanner = \"astar\"\nbeta = 2\n"),
        "bad.toml:7:1: planner `fast` (astar): unknown field `beta`, expected one of `moves`, `corner_cutting`, `order`, `heuristic`, `weight`, `tie_break`",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = \"astar\"\nmoves = 4\nweight = \"heavy\"\n"),
        "bad.toml:8:1: planner `a` (astar): parameter `weight`: expected a number, got the string \"heavy\"",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = \"astar\"\nweight = -2.0\n"),
        "bad.toml:7:1: planner `a` (astar): parameter `weight` must be a finite number >= 0, got -2",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = \"astar\"\nmoves = 6\n"),
        "bad.toml:7:1: planner `a` (astar): parameter `moves`: unsupported connectivity 6, expected one of 4, 8, 16, 32, 48",
    );
    check_error(
        "name = \"x\"\n[[maps]]\nfiles = [\"../maps/nowhere/*.map\"]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
        &format!(
            "bad.toml:3:9: maps[0]: key `files`: nothing matches \"../maps/nowhere/*.map\" (looked for {})",
            root().join("configs/../maps/nowhere/*.map").display()
        ),
    );
    check_error(
        "name = \"x\"\n[[maps]]\nfiles = [\"../maps/paper/map01.map\"]\n[planners.a]\nplanner = \"astar\"\n",
        "bad.toml:2:1: maps[0]: give exactly one of `problems` (\"corners\", \"file\" or \"start\"), `pairs`, `points` or `scen`",
    );
    // An empty label was accepted; `[planners]` and `maps = []` had no line and column;
    // a planner name that is no string was an "unknown planner \"5\""; Rust type names
    // (`untagged enum RawSection`, `struct RawCosts`, `struct Budget`) said what was
    // expected; `lines` and `inflate_unknown` were said at the `[[maps]]` header, and
    // `lines = [0, 2]` was accepted.
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.\"\"]\nplanner = \"astar\"\n"),
        "bad.toml:5:11: key `planners`: label \"\" is empty; a label names its planner's runs, figures and files (`[planners.LABEL]`)",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners]\n"),
        "bad.toml:5:2: key `planners`: at least one planner is needed",
    );
    check_error(
        "name = \"x\"\nmaps = []\n[planners.a]\nplanner = \"astar\"\n",
        "bad.toml:2:1: key `maps`: at least one map is needed",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = 5\n"),
        &format!("bad.toml:6:11: planner `a`, key `planner`: expected a registry name (a string: one of {}), found integer 5", planner_registry::names().join(", ")),
    );
    check_error(
        &format!("name = \"x\"\nsections = [1]\n{MAPS}[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:2:12: key `sections[0]`: expected a section name (a string) or a table { name = \"...\", ... }, got 1",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}costs = \"ignore\"\n[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:5:9: key `maps[0].costs`: expected a table of cell-cost options (`rule`, `lethal`, `unknown`, `weights`, `swamp`, `water`), got the string \"ignore\"",
    );
    check_error(
        &format!("name = \"x\"\nbudget = 5\n{MAPS}[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:2:10: key `budget`: expected a table of limits (`max_expansions`, `max_time_ms`, `max_memory_mb`), got 5",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nplanner = \"astar\"\nbudget = 5\n"),
        "bad.toml:7:10: planner `a`, key `budget`: expected a table of limits (`max_expansions`, `max_time_ms`, `max_memory_mb`), got 5",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}inflate_unknown = true\n[planners.a]\nplanner = \"astar\"\n"),
        &format!(
            "bad.toml:5:19: maps[0]: `inflation` and `inflate_unknown` apply to ROS `.yaml` maps, not {}",
            root().join("configs/../maps/paper/map01.map").display()
        ),
    );
    let scen = "name = \"x\"\n[[maps]]\nfiles = [\"../maps/movingai/arena.map\"]\nscen = \"../maps/movingai/arena.map.scen\"\n";
    for (selection, expect) in [
        ("lines = [0, 2]", "bad.toml:5:9: maps[0]: key `lines`: [0, 2]: lines are 1-based (the file's first line is line 1)"),
        ("lines = [3, 2]", "bad.toml:5:9: maps[0]: key `lines`: [3, 2] starts after it ends (the first line, then the last)"),
        ("every = 0", "bad.toml:5:9: maps[0]: key `every` must be at least 1"),
    ] {
        check_error(
            &format!("{scen}{selection}\n[planners.a]\nplanner = \"astar\"\n"),
            expect,
        );
    }
    check_error(
        &format!("name = \"my results\"\n{MAPS}[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:1:8: key `name`: \"my results\" must be non-empty letters, digits, '-' or '_' (it names the output directory)",
    );
    check_error(
        &format!("name = \"x\"\nrepeats = 0\n{MAPS}[planners.a]\nplanner = \"astar\"\n"),
        "bad.toml:2:11: key `repeats` must be at least 1",
    );
    check_error(
        &format!("name = \"x\"\n{MAPS}[planners.a]\nheuristic = \"octile\"\n"),
        &format!(
            "bad.toml:5:11: planner `a`: key `planner` is missing (one of {})",
            planner_registry::names().join(", ")
        ),
    );
}

#[test]
fn a_failed_sweep_leaves_previous_results_and_writes_nothing() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-atomic");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let good = dir.join("good.toml");
    let maps = root().join("maps/paper/map01.map");
    std::fs::write(
        &good,
        format!("name = \"t\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n", maps.display().to_string()),
    )
    .unwrap();
    let out = dir.join("results");
    experiment(&good, &out).unwrap();
    let before = std::fs::read(out.join("runs.json")).unwrap();
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        "name = \"t\"\nmaps = []\n[planners.a]\nplanner = \"nope\"\n",
    )
    .unwrap();
    assert!(experiment(&bad, &out).is_err());
    assert_eq!(std::fs::read(out.join("runs.json")).unwrap(), before);
    let entries: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        entries.len(),
        3,
        "only the two configs and results/: {entries:?}"
    );
    let fresh = dir.join("fresh");
    assert!(experiment(&bad, &fresh).is_err());
    assert!(!fresh.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn plan_prints_one_json_object_and_names_bad_input() {
    let args = planner_runner::plan::PlanArgs {
        map: root().join("maps/paper/map01.map"),
        planner: "astar".into(),
        ..Default::default()
    };
    let json: serde_json::Value =
        serde_json::from_str(&planner_runner::plan::run(&args).unwrap().to_json().unwrap())
            .unwrap();
    // Seed 000 Tables 3 and 5, map 1: D 10, T 2, Score 12, 15 expansions.
    assert_eq!(json["status"], "found");
    assert_eq!(json["metrics"]["steps"], 10);
    assert_eq!(json["metrics"]["turns"], 2);
    assert_eq!(json["metrics"]["score"], 12);
    assert_eq!(json["counters"]["n_expanded"], 15);
    assert_eq!(json["path"][0], serde_json::json!([0, 0]));
    let blocked = planner_runner::plan::PlanArgs {
        map: root().join("maps/wpi/map2.txt"),
        planner: "bfs".into(),
        problem: Some(2),
        ..Default::default()
    };
    let error = planner_runner::plan::run(&blocked)
        .err()
        .unwrap()
        .to_string();
    assert!(error.ends_with("goal (12, 3) is blocked"), "{error}");
    let unknown = planner_runner::plan::PlanArgs {
        set: vec!["beta=2".into()],
        ..args
    };
    assert!(planner_runner::plan::run(&unknown)
        .err()
        .unwrap()
        .to_string()
        .contains("unknown field `beta`"));
}

#[test]
fn corner_cutting_paths_are_validated_by_their_own_rule() {
    // Only a corner-cutting diagonal joins (0,0) and (1,1): the any-angle rule rejects it,
    // the 8-connected rule with corner cutting accepts it.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-cutting");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("x.map"),
        "type octile\nheight 2\nwidth 2\nmap\n.@\n@.\n",
    )
    .unwrap();
    let text = "name = \"c\"\n[[maps]]\nfiles = [\"x.map\"]\nproblems = \"corners\"\n[planners.cut]\nplanner = \"astar\"\nmoves = 8\ncorner_cutting = true\nheuristic = \"octile\"\n";
    let experiment = config::parse(&dir.join("c.toml"), text).unwrap();
    let records = common::run(&experiment, 1);
    assert_eq!(records[0].status.as_str(), "found");
    assert_eq!(records[0].steps, Some(1));
    assert_eq!(records[0].valid, Some(true));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Seed 003's Tables I-II path lengths for BFS, DFS and A* (maps/wpi/published.toml).
#[test]
fn wpi_config_reproduces_the_reports_path_lengths() {
    let experiment = config::load(&root().join("configs/wpi.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = common::run(&experiment, 2);
    let (_, reproduction) = planner_paper::renderer()
        .summary(&experiment, &records)
        .unwrap();
    assert_eq!((reproduction.matched, reproduction.compared), (15, 15));
}

/// A* with the octile heuristic solves the Moving AI problem exactly: every length equals
/// the scenario file's optimum.
#[test]
fn movingai_config_matches_the_scenario_optima() {
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = common::run(&experiment, 2);
    let exact = ["octile", "octile_high_g", "dijkstra"];
    let mut checked = 0;
    for r in records
        .iter()
        .filter(|r| exact.contains(&r.planner.as_str()))
    {
        let (length, optimal) = (r.length.unwrap(), r.optimal_length.unwrap());
        assert!(
            planner_report::optimum::matches_optimum(length, optimal),
            "{} {} #{}: {length} vs {optimal}",
            r.planner,
            r.map,
            r.problem
        );
        checked += 1;
    }
    assert_eq!(checked, 3 * 3 * 12);
}

/// Every A* run of every config (as snapshotted) has exactly the path and counters of
/// `planner_testkit::reference_astar`, a plain transcription of seed 000's Fig. 4 with
/// std's `BinaryHeap`: the snapshot's A* numbers, weighted and 8-connected ones included,
/// are checked against an independent search, not only pinned.
#[test]
fn every_astar_run_matches_the_reference_search() {
    let mut n_weighted = 0;
    let n_checked = common::for_each_snapshotted_run("astar", |path, map, params, r| {
        // On a weighted grid the heuristic is multiplied by the smallest weight (the
        // reference charges each move its cost under the grid's rule); costs are also held
        // to the weighted oracle by `every_weighted_run_matches_the_oracle`.
        let min_weight = map.grid.weights().map_or(1, |w| u64::from(w.min()));
        n_weighted += u64::from(map.grid.is_weighted());
        let config: planner_astar::Config = params.clone().try_into().unwrap();
        let moves =
            planner_api::MoveSet::new(config.moves, config.corner_cutting, &config.order).unwrap();
        let (goal, weight, heuristic) = (r.goal, config.weight, config.heuristic);
        let h = |c: planner_api::Cell| {
            heuristic
                .cost(c.x, c.y, goal.x, goal.y)
                .times(min_weight)
                .scaled(weight)
        };
        let tie = common::tie(config.tie_break);
        let (status, cells, counters) =
            planner_testkit::reference_astar(&map.grid, &moves, h, tie, r.start, r.goal);
        let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
        assert_eq!(r.status.as_str(), status.as_str(), "{what}");
        let actual = planner_testkit::REFERENCE_COUNTERS.map(|n| r.counters.get(n).unwrap());
        assert_eq!(actual, counters, "{what}");
        assert_eq!(r.path.as_ref().map(|p| p.cells().to_vec()), cells, "{what}");
    });
    // paper: 12 maps; wpi: 8 valid problems x 3 test repeats; movingai: 4 A* settings x 36
    // problems; pastar: TA-star, RA-star1 and RA-star2 x 7 problems x 2 test repeats;
    // incremental: 16 problems; weighted: 4 A* labels x 10 problems.
    assert_eq!(n_weighted, 40);
    assert_eq!(n_checked, 12 + 24 + 144 + 42 + 16 + 40);
}

/// Every JPS run of every config (as snapshotted), in each variant, has exactly the status,
/// path and counters of `planner_testkit::reference_jps`, JPS written again with every jump
/// walked cell by cell and std's `BinaryHeap`: the snapshot's JPS numbers (`n_scanned`,
/// `n_lookups` and the rest) are checked against an independent search, not only pinned.
#[test]
fn every_jps_run_matches_the_reference_search() {
    let n_checked = common::for_each_snapshotted_run("jps", |path, map, params, r| {
        let config: planner_jps::Config = params.clone().try_into().unwrap();
        assert!(!config.goal_bounding, "the reference has no goal bounds");
        let variant = match config.variant {
            planner_jps::Variant::Jps => planner_testkit::JpsVariant::Jps,
            planner_jps::Variant::JpsPrime => planner_testkit::JpsVariant::JpsPrime,
            planner_jps::Variant::JpsPlus => planner_testkit::JpsVariant::JpsPlus,
        };
        let (status, chain, counters) =
            planner_testkit::reference_jps(&map.grid, r.start, r.goal, variant);
        let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
        assert_eq!(r.status.as_str(), status.as_str(), "{what}");
        let actual: Vec<u64> = r.counters.iter().map(|(_, value)| value).collect();
        assert_eq!(actual, counters, "{what}");
        // The path's jump points: its ends and the marks between (the crate's own test
        // compares every cell).
        let ends = |p: &planner_api::Path| (p.cells()[0], p.cells()[p.cells().len() - 1]);
        let jump_points = r.path.as_ref().map(|p| {
            let (first, last) = ends(p);
            let marks = r.marks.iter().map(|m| m.cell);
            std::iter::once(first)
                .chain(marks)
                .chain(std::iter::once(last))
                .collect()
        });
        let chain = chain.map(|c| match c.len() {
            1 => vec![c[0], c[0]],
            _ => c,
        });
        assert_eq!(jump_points, chain, "{what}");
    });
    // movingai: the three variants x 36 problems.
    assert_eq!(n_checked, 3 * 36);
}

/// Every Theta\* and Lazy Theta\* run of every config (as snapshotted) has exactly the
/// status, waypoints and counters of `planner_testkit::reference_theta_star`, the search
/// written again with planner-api's line-of-sight walk and std's `BinaryHeap`: the
/// snapshot's `n_los_checks`, `n_los_cells`, `n_parent_repairs` and A\*'s counters are
/// checked against an independent search, not only pinned.
#[test]
fn every_theta_star_run_matches_the_reference_search() {
    let mut n_checked = 0;
    for (algorithm, lazy) in [("theta_star", false), ("lazy_theta_star", true)] {
        n_checked += common::for_each_snapshotted_run(algorithm, |path, map, _, r| {
            let (status, waypoints, counters) =
                planner_testkit::reference_theta_star(&map.grid, r.start, r.goal, lazy, true);
            let names = &planner_testkit::THETA_COUNTERS[..9 + usize::from(lazy)];
            let counters = names.iter().copied().zip(counters);
            common::assert_reference_run(path, r, status, waypoints, counters);
        });
    }
    // movingai: 36 problems each; pastar: 7 problems x 2 test repeats each.
    assert_eq!(n_checked, 2 * (36 + 14));
}

/// Every bidirectional A\* run of every config (as snapshotted), weighted ones included,
/// has exactly the status, path and counters of
/// `planner_testkit::reference_bidirectional_astar`, the search written again with std's
/// binary heaps and planner-api's moves and move costs: the snapshot's forward, backward
/// and meeting counters are checked against an independent search, not only pinned.
#[test]
fn every_bidirectional_astar_run_matches_the_reference_search() {
    let n_checked =
        common::for_each_snapshotted_run("bidirectional_astar", |path, map, params, r| {
            let config: planner_bidirectional_astar::Config = params.clone().try_into().unwrap();
            assert_eq!(
                config.order,
                planner_api::NeighborOrder::default(),
                "the reference's order"
            );
            let (status, cells, counters) = planner_testkit::reference_bidirectional_astar(
                &map.grid,
                config.moves,
                r.start,
                r.goal,
            );
            common::assert_reference_run(path, r, status, cells, counters);
        });
    // movingai: 36 problems; weighted: 2 labels x 10 problems.
    assert_eq!(n_checked, 36 + 20);
}

/// Every LPA\* and D\* Lite run of every config (as snapshotted: first searches) has
/// exactly the status, path and counters of `planner_testkit::reference_lpa`, the papers'
/// ComputeShortestPath written again with a `BTreeSet` for the queue: the snapshot's queue
/// and `rhs` counters are checked against an independent search, not only pinned.
#[test]
fn every_lpastar_and_dstar_lite_run_matches_the_reference_search() {
    let mut n_checked = 0;
    for (algorithm, dstar) in [("lpastar", false), ("dstar_lite", true)] {
        n_checked += common::for_each_snapshotted_run(algorithm, |path, map, params, r| {
            let config: planner_lpastar::Config = params.clone().try_into().unwrap();
            assert!(!map.grid.is_weighted(), "the reference has no weights");
            let (status, cells, counters) = planner_testkit::reference_lpa(
                &map.grid,
                config.moves == 8,
                r.start,
                r.goal,
                dstar,
            );
            let counters = planner_testkit::LPA_COUNTERS.iter().copied().zip(counters);
            common::assert_reference_run(path, r, status, cells, counters);
        });
    }
    // incremental: 2 labels x 16 problems each.
    assert_eq!(n_checked, 2 * 32);
}

/// Every BFS and DFS run of every config (as snapshotted) has exactly the status, path and
/// counters of `planner_testkit::reference_frontier`, seed 003's definitions written again
/// with a `VecDeque`: the snapshot's frontier counters (seed 003's maps among them) are
/// checked against an independent search, not only pinned.
#[test]
fn every_bfs_and_dfs_run_matches_the_reference_search() {
    let mut n_checked = 0;
    for (algorithm, lifo) in [("bfs", false), ("dfs", true)] {
        let n = common::for_each_snapshotted_run(algorithm, |path, map, params, r| {
            // planner-dfs takes planner-bfs's parameters.
            let config: planner_bfs::Config = params.clone().try_into().unwrap();
            let moves =
                planner_api::MoveSet::new(config.moves, config.corner_cutting, &config.order)
                    .unwrap();
            let (status, cells, counters) =
                planner_testkit::reference_frontier(&map.grid, &moves, r.start, r.goal, lifo);
            let counters = planner_testkit::FRONTIER_COUNTERS.into_iter().zip(counters);
            common::assert_reference_run(path, r, status, cells, counters);
        });
        n_checked += n;
    }
    // paper: 12 maps each; wpi: 8 valid problems x 3 test repeats each; weighted: BFS with
    // `costs = "ignore"` on 10 problems.
    assert_eq!(n_checked, 2 * (12 + 24) + 10);
}

/// Every RRT run of every config (as snapshotted), each with its recorded seed, has exactly
/// the status, path and counters of `planner_testkit::reference_rrt`, the run written
/// again from planner-rrt's documented draws with a linear scan for the nearest node: the
/// snapshot's seeded RRT numbers are checked against an independent run, not only pinned.
#[test]
fn every_rrt_run_matches_the_reference_run() {
    let n_checked = common::for_each_snapshotted_run("rrt", |path, map, params, r| {
        let config: planner_rrt::Config = params.clone().try_into().unwrap();
        let settings = common::rrt_settings(
            r,
            config.seed,
            config.goal_bias,
            config.max_iterations,
            config.steer,
            config.step,
        );
        let (status, cells, counters) =
            planner_testkit::reference_rrt(&map.grid, r.start, r.goal, settings);
        let counters = planner_testkit::RRT_COUNTERS.into_iter().zip(counters);
        common::assert_reference_run(path, r, status, cells, counters);
    });
    // wpi: the rrt and rrt_eight4 labels x 8 valid problems x 3 test repeats.
    assert_eq!(n_checked, 2 * 24);
}

/// Every RRT-Connect run of every config (as snapshotted), each with its recorded seed, has
/// exactly the status, path and counters of `planner_testkit::reference_rrt_connect`.
#[test]
fn every_rrt_connect_run_matches_the_reference_run() {
    let n_checked = common::for_each_snapshotted_run("rrt_connect", |path, map, params, r| {
        let config: planner_rrt_connect::Config = params.clone().try_into().unwrap();
        let settings = common::rrt_settings(
            r,
            config.seed,
            0.0,
            config.max_iterations,
            config.steer,
            config.step,
        );
        let (status, cells, counters) =
            planner_testkit::reference_rrt_connect(&map.grid, r.start, r.goal, settings);
        let counters = planner_testkit::RRT_CONNECT_COUNTERS
            .into_iter()
            .zip(counters);
        common::assert_reference_run(path, r, status, cells, counters);
    });
    // wpi: 8 valid problems x 3 test repeats.
    assert_eq!(n_checked, 24);
}

/// Every RRT* run of every config (as snapshotted), each with its recorded seed, has exactly
/// the status, path and counters of `planner_testkit::reference_rrt_star`.
#[test]
fn every_rrt_star_run_matches_the_reference_run() {
    let n_checked = common::for_each_snapshotted_run("rrt_star", |path, map, params, r| {
        let config: planner_rrt_star::Config = params.clone().try_into().unwrap();
        let settings = common::rrt_settings(
            r,
            config.seed,
            config.goal_bias,
            config.max_iterations,
            config.steer,
            config.step,
        );
        let (status, cells, counters, _) = planner_testkit::reference_rrt_star(
            &map.grid,
            r.start,
            r.goal,
            settings,
            config.iterations_after_solution,
            config.gamma,
        );
        common::assert_reference_run(path, r, status, cells, counters);
    });
    // wpi: the rrt_star and rrt_star_eight4 labels x 8 valid problems x 3 test repeats.
    assert_eq!(n_checked, 2 * 24);
}

/// Every lexastar run of every config (as snapshotted) finds the best (D, T), hence
/// Score, that `planner_testkit::fewest_moves_then_turns` (plain Dijkstra over (cell,
/// heading) states) finds, and a valid path: its snapshot metrics are checked against an
/// independent search, on the Moving AI maps too, where enumerating paths is hopeless.
/// Its counters and path are those of `planner_testkit::reference_lexastar`.
#[test]
fn every_lexastar_run_is_best_by_steps_then_turns() {
    let n_checked = common::for_each_snapshotted_run("lexastar", |path, map, params, r| {
        let config: planner_lexastar::Config = params.clone().try_into().unwrap();
        assert_eq!(config.objective, planner_lexastar::Objective::Lexicographic);
        let moves =
            planner_api::MoveSet::new(config.moves, config.corner_cutting, &config.order).unwrap();
        let best = planner_testkit::fewest_moves_then_turns(&map.grid, &moves, r.start, r.goal);
        let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
        assert_eq!(r.steps.zip(r.turns), best, "{what}");
        assert_eq!(r.score, best.map(|(d, t)| d + t), "{what}");
        assert_eq!(r.valid, best.map(|_| true), "{what}");
        // Its counters and path: `planner_testkit::reference_lexastar`, the search written
        // again with flat arrays and std's binary heap.
        assert!(!map.grid.is_weighted(), "the reference has no weights");
        let (status, cells, counters) = planner_testkit::reference_lexastar(
            &map.grid,
            &moves,
            r.start,
            r.goal,
            config.dominance,
        );
        let counters = planner_testkit::LEXASTAR_COUNTERS.into_iter().zip(counters);
        common::assert_reference_run(path, r, status, cells, counters);
    });
    // paper: 12 maps; movingai: 36 problems.
    assert_eq!(n_checked, 12 + 36);
}

/// `inflation` blocks every cell within that many cells of an occupied one in a ROS map.
#[test]
fn ros_maps_take_an_inflation_radius() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-ros");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // A 5x5 plain PGM, white (free) but for a black (occupied) centre pixel.
    let mut pgm = String::from("P2\n5 5\n255\n");
    for y in 0..5 {
        let row: Vec<&str> = (0..5)
            .map(|x| if (x, y) == (2, 2) { "0" } else { "255" })
            .collect();
        pgm.push_str(&row.join(" "));
        pgm.push('\n');
    }
    std::fs::write(dir.join("room.pgm"), pgm).unwrap();
    std::fs::write(
        dir.join("room.yaml"),
        "image: room.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n",
    )
    .unwrap();
    let config = |extra: &str| {
        format!("name = \"r\"\n[[maps]]\nfiles = [\"room.yaml\"]\npairs = [{{ start = [0, 0], goal = [4, 4] }}]\n{extra}[planners.b]\nplanner = \"bfs\"\n")
    };
    let plain = config::parse(&dir.join("c.toml"), &config("")).unwrap();
    let inflated = config::parse(&dir.join("c.toml"), &config("inflation = 1\n")).unwrap();
    // Without inflation only the centre is blocked; radius 1 (Euclidean distance between
    // cell centres, planner-maps' rule) adds its four edge neighbours.
    assert_eq!(plain.maps[0].grid.n_free(), 24);
    assert_eq!(inflated.maps[0].grid.n_free(), 20);
    let paper = root().join("maps/paper/map01.map").display().to_string();
    let error = config::parse(
        &dir.join("c.toml"),
        &format!("name = \"r\"\n[[maps]]\nfiles = [{paper:?}]\nproblems = \"corners\"\ninflation = 2\n[planners.b]\nplanner = \"bfs\"\n"),
    );
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(error
        .unwrap_err()
        .message
        .contains("apply to ROS `.yaml` maps"));
}

/// `cargo xtask plan <map> --planner rrt --set seed=7 --json` is reproducible, and the seed
/// is what varies the result.
#[test]
fn plan_with_a_seed_is_reproducible() {
    let run = |seed: u64| {
        let args = planner_runner::plan::PlanArgs {
            map: root().join("maps/wpi/map3.txt"),
            planner: "rrt".into(),
            problem: Some(1),
            set: vec![format!("seed={seed}")],
            ..Default::default()
        };
        planner_runner::plan::run(&args).unwrap().to_json().unwrap()
    };
    assert_eq!(run(7), run(7));
    let outputs: std::collections::BTreeSet<String> = (0..5).map(run).collect();
    assert!(outputs.len() > 1, "five seeds gave one result");
    let json: serde_json::Value = serde_json::from_str(&run(7)).unwrap();
    assert_eq!(json["status"], "found");
    assert_eq!(json["path"][0], serde_json::json!([0, 0]));
    assert_eq!(
        json["path"].as_array().unwrap().last().unwrap(),
        &serde_json::json!([49, 19])
    );
}

/// The aggregate tables of configs/movingai.toml (trimmed by its `[test]` limits), with
/// time and memory redacted: every count, expansion and suboptimality is a pure function
/// of the records, themselves snapshotted and checked against the scenario optima.
#[test]
fn movingai_aggregates_are_snapshotted() {
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = common::run(&experiment, 2);
    let tables = planner_report::streamed::aggregate_tables(
        &experiment,
        &records.as_slice(),
        planner_report::aggregate::Measured::Redacted,
    )
    .unwrap();
    // The overall row of A* with the octile heuristic: 36 runs, all found and optimal.
    assert!(
        tables.contains("| octile | all | 36 | 36 | 36 |"),
        "{tables}"
    );
    insta::with_settings!({
        snapshot_path => "../../snapshots",
        prepend_module_to_snapshot => false,
        description => "aggregate tables of configs/movingai.toml (time and memory redacted)",
        omit_expression => true,
    }, {
        insta::assert_snapshot!("movingai-aggregates", tables);
    });
}

/// Runs the experiment `config` into `output` with one worker, as the command line does.
fn experiment(
    config: &std::path::Path,
    output: &std::path::Path,
) -> Result<planner_runner::sweep::Report, String> {
    let renderer = planner_paper::renderer();
    planner_runner::sweep::experiment(&planner_runner::sweep::SweepArgs {
        threads: 1,
        output: Some(output),
        ..planner_runner::sweep::SweepArgs::new(config, &renderer)
    })
    .map_err(|e| e.to_string())
}

/// Every run on a weighted map, in every config (as snapshotted), replayed through the
/// test kit's oracle, a plain Dijkstra over the weighted graph: a planner that honours
/// cell costs returns a path whose exact weighted cost is the oracle's least cost, and
/// the record's `cost` is that path's cost; a planner run with `costs = "ignore"` returns
/// a valid path costing at least as much. Unreachable goals must agree too. Weighted JPS's
/// runs also give exactly the counters of `planner_testkit::reference_weighted_jps`, its
/// search written again with jumps walked cell by cell (so `snapshots/weighted.snap`'s
/// `n_jumps` and the rest are checked against an independent method).
#[test]
fn every_weighted_run_matches_the_oracle() {
    let (mut n_checked, mut n_weighted_jps) = (0, 0);
    for path in configs() {
        let experiment = config::load(&path).unwrap().trimmed_for_test();
        if !experiment.maps.iter().any(|m| m.grid.is_weighted()) {
            continue;
        }
        let records = common::run(&experiment, 2);
        let mut oracle = std::collections::HashMap::new();
        for r in &records {
            let Some(map) = experiment.maps.iter().find(|m| m.name == r.map) else {
                panic!("record of an unknown map {}", r.map);
            };
            if !map.grid.is_weighted() || r.status == planner_runner::RunStatus::InvalidProblem {
                continue;
            }
            let planner = experiment
                .planners
                .iter()
                .find(|p| p.label == r.planner)
                .unwrap();
            let specs = planner.factory.specs();
            let planner_api::PathSpec::Moves(moves) = &specs.path_rule else {
                panic!("{}: weighted runs need a move set", r.planner);
            };
            let best = *oracle
                .entry((r.map.clone(), r.problem, format!("{moves:?}")))
                .or_insert_with(|| {
                    planner_testkit::weighted_dijkstra(&map.grid, moves, r.start, r.goal)
                });
            let what = format!("{} {} #{} {}", path.display(), r.map, r.problem, r.planner);
            match (&r.path, best) {
                (Some(found), Some(best)) => {
                    let cost = map.grid.path_cost(found.cells());
                    assert_eq!(r.cost, Some(cost.to_f64()), "{what}");
                    assert_eq!(r.valid, Some(true), "{what}");
                    if specs.cell_costs {
                        assert_eq!(cost, best, "{what}");
                    } else {
                        assert!(planner.ignore_costs && cost >= best, "{what}");
                    }
                }
                (None, None) => assert_eq!(r.status, planner_runner::RunStatus::NoPath, "{what}"),
                (found, best) => panic!("{what}: path {:?} vs oracle {best:?}", found.is_some()),
            }
            if r.algorithm == "weighted_jps" {
                // Every counter of weighted JPS as its independent transcription counts it.
                let (_, _, counters) =
                    planner_testkit::reference_weighted_jps(&map.grid, r.start, r.goal);
                for (name, want) in planner_testkit::WEIGHTED_JPS_COUNTERS.iter().zip(counters) {
                    assert_eq!(r.counters.get(name), Some(want), "{what}: {name}");
                }
                n_weighted_jps += 1;
            }
            n_checked += 1;
        }
    }
    assert!(n_checked >= 70, "{n_checked}");
    assert!(n_weighted_jps >= 10, "{n_weighted_jps}");
}

/// A planner that does not honour cell costs is refused a weighted map at config time, by
/// an error naming the planner and the map, unless its table says `costs = "ignore"`; bad
/// `costs` values name their key.
#[test]
fn planners_without_cell_costs_refuse_weighted_maps() {
    let path = root().join("configs/costs-test.toml");
    let text = |planner: &str| {
        format!(
            "name = \"c\"\n[[maps]]\nfiles = [\"../maps/movingai/arena.map\"]\npairs = [{{ start = [3, 1], goal = [46, 47] }}]\ncosts = {{ weights = \"../maps/weighted/arena-weights.csv\" }}\n[planners.p]\n{planner}\n"
        )
    };
    for (planner, name) in [
        ("planner = \"bfs\"\nmoves = 8", "bfs"),
        ("planner = \"jps\"", "jps"),
        ("planner = \"theta_star\"", "theta_star"),
    ] {
        let err = config::parse(&path, &text(planner))
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(&format!(
                "planner `p` ({name}) does not honour cell costs, and map `arena.map` has them"
            )),
            "{err}"
        );
        assert!(err.contains(":6:"), "{err}");
        let ignored = format!("{planner}\ncosts = \"ignore\"");
        assert!(config::parse(&path, &text(&ignored)).is_ok());
    }
    for planner in ["planner = \"astar\"", "planner = \"bidirectional_astar\""] {
        assert!(config::parse(&path, &text(planner)).is_ok(), "{planner}");
    }
    let err = config::parse(&path, &text("planner = \"bfs\"\ncosts = \"honour\""))
        .unwrap_err()
        .to_string();
    assert!(err.contains("key `costs`: expected \"ignore\""), "{err}");
    let bad_weights = text("planner = \"astar\"").replace("arena-weights.csv", "missing.csv");
    let err = config::parse(&path, &bad_weights).unwrap_err().to_string();
    assert!(
        err.contains("key `costs.weights`") && err.contains("missing.csv"),
        "{err}"
    );
}
