//! Cell costs on the page's API (issue 32): a map read with a weight file or graded shows
//! its weights, a plan on it answers the path's cost (held to the test kit's weighted
//! Dijkstra), and a planner that cannot honour costs is refused unless told to ignore them.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::time::Duration;

use planner_api::{Cell, Connectivity, CostRule, MoveSet};
use planner_serve::{ServeOptions, Server};

fn maps() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps")
}

fn start() -> (SocketAddr, impl Fn()) {
    let server = Server::bind(&ServeOptions::new(&maps(), 0)).unwrap();
    let addr = server.addr().unwrap();
    let stop = server.stopper();
    std::thread::spawn(move || server.run());
    (addr, stop)
}

/// Sends one request; the status and the body of the answer.
fn send(addr: SocketAddr, head: &str, body: &[u8]) -> (u16, String) {
    let mut stream = TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    let mut request = format!("{head}\r\nHost: {addr}\r\nConnection: close\r\n");
    if !body.is_empty() {
        request.push_str(&format!(
            "Content-Type: application/json\r\nContent-Length: {}\r\n",
            body.len()
        ));
    }
    request.push_str("\r\n");
    stream.write_all(request.as_bytes()).unwrap();
    stream.write_all(body).unwrap();
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let text = String::from_utf8_lossy(&answer).into_owned();
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0);
    let body = text
        .split_once("\r\n\r\n")
        .map_or(String::new(), |(_, b)| b.to_string());
    (status, body)
}

fn json(body: &str) -> serde_json::Value {
    serde_json::from_str(body).unwrap_or_else(|e| panic!("{e}: {body}"))
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
    let (addr, stop) = start();
    let url = "/api/map?path=movingai%2Farena.map&weights=weighted%2Farena-weights.csv";
    let (status, body) = send(addr, &format!("GET {url} HTTP/1.1"), b"");
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
    let (_, body) = send(addr, "GET /api/map?path=movingai%2Farena.map HTTP/1.1", b"");
    assert!(json(&body)["weights"].is_null(), "{body}");

    let eight = MoveSet::standard(Connectivity::Eight);
    let oracle =
        planner_testkit::weighted_dijkstra(&grid, &eight, Cell::new(3, 1), Cell::new(46, 47))
            .unwrap()
            .to_f64();
    let request = r#"{"map":"movingai/arena.map","start":[3,1],"goal":[46,47],"planner":"astar","set":["moves=8","heuristic=octile"],"costs":{"weights":"weighted/arena-weights.csv"}}"#;
    let (status, body) = send(addr, "POST /api/plan HTTP/1.1", request.as_bytes());
    assert_eq!(status, 200, "{body}");
    let cost = json(&body)["plan"]["cost"].as_f64().unwrap();
    assert!((cost - oracle).abs() < 1e-6, "{cost} vs {oracle}");

    // BFS cannot honour costs: refused, unless told to ignore them.
    let bfs = request
        .replace("astar", "bfs")
        .replace(r#","heuristic=octile""#, "");
    let (status, body) = send(addr, "POST /api/plan HTTP/1.1", bfs.as_bytes());
    assert_eq!(status, 400, "{body}");
    assert!(body.contains("does not honour cell costs"), "{body}");
    let ignore = bfs.replace(r#""costs""#, r#""ignore_costs":true,"costs""#);
    let (status, body) = send(addr, "POST /api/plan HTTP/1.1", ignore.as_bytes());
    assert_eq!(status, 200, "{body}");
    assert!(json(&body)["plan"]["cost"].as_f64().unwrap() >= cost);

    // Graded ROS maps: weights 1 + nav2's cost (TenByTen's grey is 55: weight 56).
    let (status, body) = send(
        addr,
        "GET /api/map?path=ros-graded%2FTenByTen-scale.yaml&graded=1 HTTP/1.1",
        b"",
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
        let (status, body) = send(addr, &format!("GET {url} HTTP/1.1"), b"");
        assert!(matches!(status, 400 | 403 | 404), "{url}: {status} {body}");
    }
    stop();
}
