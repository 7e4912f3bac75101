//! `gridplan plan` on maps with cell costs (issue 32): a weight file or graded ROS map, the
//! cost options as flags, the path cost in `--json` (held to the test kit's weighted
//! Dijkstra), and the refusal of a planner that cannot honour costs.

use crate::common::{self, root};

use planner_api::{Cell, Connectivity, CostRule, MoveSet};
use planner_maps::{read_map_with, read_weights, CostOptions, ReadOptions};
use planner_testkit::weighted_dijkstra;

/// Runs gridplan with `args` from the repository's root; returns its exit code, stdout
/// and stderr.
fn gridplan(args: &[&str]) -> (i32, String, String) {
    let out = common::gridplan(&root(), args);
    (out.code.unwrap(), out.stdout, out.stderr)
}

/// `plan ARENA --planner PLANNER` and `rest`: its exit code, stdout and stderr.
fn plan_arena(planner: &str, rest: &[&str]) -> (i32, String, String) {
    let mut args = vec!["plan", ARENA, "--planner", planner];
    args.extend_from_slice(rest);
    gridplan(&args)
}

/// Asserts that `plan ARENA --planner PLANNER` and `rest` exits with `code`, its stderr
/// holding `message`.
fn refused(planner: &str, rest: &[&str], code: i32, message: &str) {
    let (got, _, err) = plan_arena(planner, rest);
    assert_eq!(got, code, "{rest:?}: {err}");
    assert!(err.contains(message), "{message}: {err}");
}

fn json(stdout: &str) -> serde_json::Value {
    serde_json::from_str(stdout).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

const ARENA: &str = "maps/movingai/arena.map";
const WEIGHTS: &str = "maps/weighted/arena-weights.csv";

/// The arena map with its weight file, as the test kit reads it, under `rule`.
fn weighted_arena(rule: CostRule) -> planner_api::Grid {
    let grid = read_map_with(&root().join(ARENA), &ReadOptions::default())
        .unwrap()
        .file
        .grid;
    read_weights(&root().join(WEIGHTS), grid, rule, &ReadOptions::default()).unwrap()
}

#[test]
fn plan_with_a_weight_file_prints_the_oracle_cost() {
    for (rule, flag) in [(CostRule::Mean, "mean"), (CostRule::Entered, "entered")] {
        let grid = weighted_arena(rule);
        let eight = MoveSet::standard(Connectivity::Eight);
        let oracle = weighted_dijkstra(&grid, &eight, Cell::new(3, 1), Cell::new(46, 47))
            .unwrap()
            .to_f64();
        for (planner, heuristic) in [
            ("astar", "heuristic=octile"),
            ("bidirectional_astar", "moves=8"),
        ] {
            let (code, out, err) = plan_arena(
                planner,
                &[
                    "--set",
                    "moves=8",
                    "--set",
                    heuristic,
                    "--start",
                    "3,1",
                    "--goal",
                    "46,47",
                    "--weights",
                    WEIGHTS,
                    "--cost-rule",
                    flag,
                    "--json",
                ],
            );
            assert_eq!(code, 0, "{err}");
            let v = json(&out);
            assert_eq!(v["status"], "found");
            let cost = v["cost"].as_f64().unwrap();
            assert!(
                (cost - oracle).abs() < 1e-6,
                "{planner} {flag}: {cost} vs {oracle}"
            );
            // The cost is that of the path printed.
            let cells: Vec<Cell> = v["path"]
                .as_array()
                .unwrap()
                .iter()
                .map(|c| Cell::new(c[0].as_u64().unwrap() as u32, c[1].as_u64().unwrap() as u32))
                .collect();
            assert_eq!(grid.path_cost(&cells).to_f64(), cost);
        }
    }
    // lexastar, 4-connected: its first criterion is the cost, the oracle's 4-connected one.
    let grid = weighted_arena(CostRule::Mean);
    let four = MoveSet::standard(Connectivity::Four);
    let oracle = weighted_dijkstra(&grid, &four, Cell::new(3, 1), Cell::new(46, 47)).unwrap();
    let query = ["--start", "3,1", "--goal", "46,47", "--weights", WEIGHTS];
    let (code, out, err) = plan_arena("lexastar", &[&query[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!((json(&out)["cost"].as_f64().unwrap() - oracle.to_f64()).abs() < 1e-6);
    // The text output names the cost too.
    let (code, out, err) = plan_arena("astar", &query);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("(cell weights, mean rule)"), "{out}");
    // Without costs there is no cost key.
    let (_, out, _) = plan_arena("astar", &["--json"]);
    assert!(json(&out).get("cost").is_none(), "{out}");
}

#[test]
fn plan_with_graded_ros_maps_and_terrain_weights() {
    let yaml = "maps/ros-graded/TenByTen-raw.yaml";
    let options = ReadOptions {
        costs: CostOptions {
            graded: true,
            bands: planner_maps::CostBands {
                lethal: 254,
                unknown: Some(250),
            },
            ..CostOptions::default()
        },
        ..ReadOptions::default()
    };
    let grid = read_map_with(&root().join(yaml), &options)
        .unwrap()
        .file
        .grid;
    assert!(grid.is_weighted());
    let eight = MoveSet::standard(Connectivity::Eight);
    let oracle = weighted_dijkstra(&grid, &eight, Cell::new(0, 0), Cell::new(9, 9))
        .unwrap()
        .to_f64();
    let (code, out, err) = gridplan(&[
        "plan",
        yaml,
        "--planner",
        "astar",
        "--set",
        "moves=8",
        "--set",
        "heuristic=octile",
        "--start",
        "0,0",
        "--goal",
        "9,9",
        "--unknown",
        "250",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        (json(&out)["cost"].as_f64().unwrap() - oracle).abs() < 1e-6,
        "{out}"
    );
    // Moving AI terrain on a map with swamp: arena has none, so weight 1 everywhere and
    // the cost is the octile length.
    let (code, out, err) = plan_arena(
        "astar",
        &[
            "--set",
            "moves=8",
            "--set",
            "heuristic=octile",
            "--swamp",
            "5",
            "--json",
        ],
    );
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let length = v["metrics"]["length"].as_f64().unwrap();
    assert!((v["cost"].as_f64().unwrap() - length).abs() < 1e-6, "{out}");
}

#[test]
fn plan_refuses_what_cannot_honour_costs_and_bad_cost_flags() {
    refused(
        "bfs",
        &["--weights", WEIGHTS],
        2,
        "planner `bfs` (bfs) does not honour cell costs, and map `arena.map` has them",
    );
    let (code, out, err) = plan_arena("bfs", &["--weights", WEIGHTS, "--ignore-costs", "--json"]);
    assert_eq!(code, 0, "{err}");
    // BFS ran without the weights; the cost printed is still the map's.
    assert!(json(&out)["cost"].as_f64().is_some(), "{out}");
    // A planner that would honour them with another setting names it.
    refused(
        "lexastar",
        &["--set", "moves=8", "--weights", WEIGHTS],
        2,
        "planner `lexastar` (lexastar) honours cell costs only with `moves` = 4 (",
    );
    refused(
        "astar",
        &["--set", "moves=16", "--weights", WEIGHTS],
        2,
        "planner `astar` (astar) honours cell costs only with `moves` = 4 or 8 (",
    );
    for (args, message) in [
        (vec!["--graded"], "apply to ROS maps"),
        (vec!["--water", "3"], "--water needs --swamp"),
        (vec!["--cost-rule", "entered"], "--cost-rule needs costs"),
        (
            vec!["--weights", WEIGHTS, "--swamp", "2"],
            "does not go with",
        ),
        (
            vec!["--cost-rule", "median"],
            "[possible values: mean, entered]",
        ),
    ] {
        refused("astar", &args, 2, message);
    }
    // A bad weight file: file, line and column.
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-costs-cli");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.csv");
    std::fs::write(&bad, "1 1 1 1 1 1\n1 1 1 -2 1 1\n").unwrap();
    let (code, _, err) = gridplan(&[
        "plan",
        "maps/paper/map01.map",
        "--planner",
        "astar",
        "--weights",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("bad.csv:2:7: expected a weight (an integer from 1 to 65535), found '-2', a negative number"), "{err}");
}

/// `--ignore-costs` with a picture: the run recorded for the picture plans on the same map
/// without its weights as the timed run (it planned on the weights, and weighted JPS, LPA*
/// and D* Lite failed with "runs must be deterministic (a bug)").
#[test]
fn ignored_costs_draw_and_trace_the_run_they_timed() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-ignored");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    for planner in ["weighted_jps", "lpastar", "dstar_lite", "astar"] {
        let (svg, trace) = (
            dir.join(format!("{planner}.svg")),
            dir.join(format!("{planner}.json")),
        );
        let (svg, trace) = (svg.display().to_string(), trace.display().to_string());
        let (code, out, err) = plan_arena(
            planner,
            &[
                "--weights",
                WEIGHTS,
                "--ignore-costs",
                "--problem",
                "1",
                "--json",
                "--svg",
                &svg,
                "--trace",
                &trace,
            ],
        );
        assert_eq!(code, 0, "{planner}: {err}");
        assert_eq!(json(&out)["status"], "found", "{planner}");
        assert!(
            std::fs::read_to_string(&svg).unwrap().starts_with("<svg"),
            "{planner}"
        );
        assert!(std::fs::metadata(&trace).unwrap().len() > 0, "{planner}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// configs/README.md's `costs` row names every planner whose defaults honour cell weights,
/// as `planners NAME` describes it (the row named neither lpastar nor dstar_lite), and no
/// planner that refuses them.
#[test]
fn the_config_guide_names_the_planners_that_honour_costs() {
    let guide = std::fs::read_to_string(root().join("configs/README.md")).unwrap();
    let row = guide
        .lines()
        .find(|line| line.starts_with("| `costs` |") && line.contains("is refused a weighted map"))
        .expect("configs/README.md has the planner tables' `costs` row");
    let (code, listing, err) = gridplan(&["planners"]);
    assert_eq!(code, 0, "{err}");
    let names: Vec<&str> = listing
        .lines()
        .filter_map(|line| line.split_whitespace().next())
        .filter(|name| name.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
        .collect();
    assert!(names.len() >= 18, "{listing}");
    for name in names {
        let (code, described, err) = gridplan(&["planners", name]);
        assert_eq!(code, 0, "{name}: {err}");
        let honours = described.contains("honours cell weights");
        assert!(
            honours || described.contains("refuses weighted maps"),
            "{name}: {described}"
        );
        assert_eq!(
            row.contains(&format!("`{name}`")),
            honours,
            "{name} (honours cell weights: {honours}) in configs/README.md's costs row: {row}"
        );
    }
}

/// `plan` gave every `budget_exhausted` run with an error the memory hint: LPA* whose costs
/// saturate on a 70,000-cell corridor of weight 65,535 printed "(not run: its costs reached
/// 4.294967e9, ...; raise it with --max-memory-mb)", and `--json` put that in `not_run`,
/// though it ran and more memory changes nothing. The hint (and `not_run`) are now for a
/// memory shortfall only; the saturation is said as it is (`--json`: `error`).
#[test]
fn saturated_costs_get_no_memory_hint() {
    let dir = common::scratch("costs", "saturated");
    let width = 70_000;
    let row = ".".repeat(width);
    std::fs::write(
        dir.join("long.map"),
        format!("type octile\nheight 2\nwidth {width}\nmap\n{row}\n{row}\n"),
    )
    .unwrap();
    let weights = vec!["65535"; width].join(",");
    std::fs::write(dir.join("longw.csv"), format!("{weights}\n{weights}\n")).unwrap();
    let base = [
        "plan",
        "long.map",
        "--planner",
        "lpastar",
        "--weights",
        "longw.csv",
    ];
    let out = common::gridplan(&dir, &base);
    assert_eq!(out.code, Some(0), "{}", out.describe());
    assert!(
        out.stdout.contains("where gridplan's costs saturate")
            && !out.stdout.contains("not run")
            && !out.stdout.contains("--max-memory-mb"),
        "{}",
        out.stdout
    );
    let out = common::gridplan(&dir, &[&base[..], &["--json"]].concat());
    assert_eq!(out.code, Some(0), "{}", out.describe());
    let json = json(&out.stdout);
    assert!(json.get("not_run").is_none(), "{json}");
    assert!(
        json["error"]
            .as_str()
            .is_some_and(|e| e.contains("where gridplan's costs saturate")),
        "{json}"
    );
    // A memory shortfall still gets the hint.
    let out = common::gridplan(&dir, &[&base[..], &["--max-memory-mb", "0"]].concat());
    assert!(
        out.stdout.contains("(not run: needs ")
            && out.stdout.contains("raise it with --max-memory-mb"),
        "{}",
        out.describe()
    );
}
