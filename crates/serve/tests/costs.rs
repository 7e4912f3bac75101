//! Cell costs on the page's API (issue 32): a map read with a weight file or graded shows
//! its weights, a plan on it answers the path's cost (held to the test kit's weighted
//! Dijkstra), and a planner that cannot honour costs is refused unless told to ignore them.

use std::path::PathBuf;

use planner_api::{Cell, Connectivity, CostRule, MoveSet};
use planner_serve::ServeOptions;

use crate::common::{get, json, post, repo, start};

fn maps() -> PathBuf {
    repo().join("maps")
}

/// The arena map with its weight file, read as the server reads it.
fn weighted_arena() -> planner_api::Grid {
    let options = planner_maps::ReadOptions::default();
    let grid = planner_maps::read_map_with(&maps().join("movingai/arena.map"), &options)
        .unwrap()
        .file
        .grid;
    planner_maps::read_weights(
        &maps().join("weighted/arena-weights.csv"),
        grid,
        CostRule::Mean,
        &options,
    )
    .unwrap()
}

#[test]
fn weighted_maps_show_their_weights_and_plans_answer_the_cost() {
    let (addr, stop) = start(&ServeOptions::new(&maps(), 0));
    let url = "/api/map?path=movingai%2Farena.map&weights=weighted%2Farena-weights.csv";
    let (status, body) = get(addr, url);
    assert_eq!(status, 200, "{body}");
    let map = json(&body);
    let grid = weighted_arena();
    let weights: Vec<u64> = map["weights"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_u64().unwrap())
        .collect();
    let expected: Vec<u64> = grid
        .weights()
        .unwrap()
        .cells()
        .iter()
        .map(|&w| u64::from(w))
        .collect();
    assert_eq!(weights, expected);
    assert_eq!(map["cost_rule"], "mean");
    // Without costs: no weights.
    let (_, body) = get(addr, "/api/map?path=movingai%2Farena.map");
    assert!(json(&body)["weights"].is_null(), "{body}");

    let eight = MoveSet::standard(Connectivity::Eight);
    let oracle =
        planner_testkit::weighted_dijkstra(&grid, &eight, Cell::new(3, 1), Cell::new(46, 47))
            .unwrap()
            .to_f64();
    let request = r#"{"map":"movingai/arena.map","start":[3,1],"goal":[46,47],"planner":"astar","set":["moves=8","heuristic=octile"],"costs":{"weights":"weighted/arena-weights.csv"}}"#;
    let (status, body) = post(addr, "/api/plan", request);
    assert_eq!(status, 200, "{body}");
    let cost = json(&body)["plan"]["cost"].as_f64().unwrap();
    assert!((cost - oracle).abs() < 1e-6, "{cost} vs {oracle}");

    // BFS cannot honour costs: refused, unless told to ignore them.
    let bfs = request
        .replace("astar", "bfs")
        .replace(r#","heuristic=octile""#, "");
    let (status, body) = post(addr, "/api/plan", &bfs);
    assert_eq!(status, 400, "{body}");
    assert!(body.contains("does not honour cell costs"), "{body}");
    let ignore = bfs.replace(r#""costs""#, r#""ignore_costs":true,"costs""#);
    let (status, body) = post(addr, "/api/plan", &ignore);
    assert_eq!(status, 200, "{body}");
    assert!(json(&body)["plan"]["cost"].as_f64().unwrap() >= cost);

    // Graded ROS maps: weights 1 + nav2's cost (TenByTen's grey is 55: weight 56).
    let (status, body) = get(
        addr,
        "/api/map?path=ros-graded%2FTenByTen-scale.yaml&graded=1",
    );
    assert_eq!(status, 200, "{body}");
    let weights = json(&body)["weights"].clone();
    assert!(
        weights.as_array().unwrap().iter().any(|w| w == 56),
        "{weights}"
    );
    // Bad cost options are the user's: 400 or a refusal, never a panic.
    for url in [
        "/api/map?path=movingai%2Farena.map&graded=1",
        "/api/map?path=movingai%2Farena.map&weights=..%2F..%2FCargo.toml",
        "/api/map?path=movingai%2Farena.map&weights=paper%2Fmap01.map",
    ] {
        let (status, body) = get(addr, url);
        assert!(matches!(status, 400 | 403 | 404), "{url}: {status} {body}");
    }
    stop();
}
