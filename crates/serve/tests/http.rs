//! The server over real HTTP on 127.0.0.1: the page and API answer, planning gives
//! `plan --json`'s object, paths out of the served directory and oversized bodies are
//! refused, a run is cancelled.

use std::path::PathBuf;
use std::time::Duration;

use planner_serve::ServeOptions;

use crate::common::{get, post, repo, scratch, send, start};

/// A served directory: map10, an open 30x30 map, a link to /etc/passwd, a link to /etc,
/// a ROS YAML naming an image outside; beside it (outside) a secret file.
fn served() -> (PathBuf, PathBuf) {
    let top = scratch("dir");
    let dir = top.join("served");
    std::fs::create_dir_all(dir.join("paper")).unwrap();
    std::fs::copy(
        repo().join("maps/paper/map10.map"),
        dir.join("paper/map10.map"),
    )
    .unwrap();
    let mut open = String::from("type octile\nheight 30\nwidth 30\nmap\n");
    for _ in 0..30 {
        open.push_str(&".".repeat(30));
        open.push('\n');
    }
    std::fs::write(dir.join("open30.map"), open).unwrap();
    std::fs::write(
        top.join("secret.map"),
        "type octile\nheight 1\nwidth 1\nmap\n.\n",
    )
    .unwrap();
    std::fs::write(top.join("secret.pgm"), "P2\n1 1\n255\n0\n").unwrap();
    std::fs::write(
        dir.join("outside.yaml"),
        "image: ../secret.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("/etc/passwd", dir.join("passwd.map")).unwrap();
        std::os::unix::fs::symlink("/etc", dir.join("etc")).unwrap();
        std::os::unix::fs::symlink(top.join("secret.map"), dir.join("link.map")).unwrap();
        // A name that is not UTF-8: the page could not ask for it by name.
        use std::os::unix::ffi::OsStrExt;
        let latin1 = std::ffi::OsStr::from_bytes(b"caf\xe9.map");
        std::fs::copy(dir.join("open30.map"), dir.join(latin1)).unwrap();
        // A FIFO named like a map, and a link to it inside the directory: neither is a
        // file `/api/map` serves.
        let made = std::process::Command::new("mkfifo")
            .arg(dir.join("ff.map"))
            .status()
            .unwrap();
        assert!(made.success(), "mkfifo: {made}");
        std::os::unix::fs::symlink(dir.join("ff.map"), dir.join("fifo-link.map")).unwrap();
    }
    (top, dir)
}

#[test]
fn the_page_and_the_lists_are_served() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let (status, page) = get(addr, "/");
    assert_eq!(status, 200);
    assert!(
        page.contains("<canvas") || page.contains("app.js"),
        "{page}"
    );
    assert_eq!(get(addr, "/app.js").0, 200);
    assert_eq!(get(addr, "/style.css").0, 200);
    assert_eq!(get(addr, "/nothing").0, 404);
    let (status, maps) = get(addr, "/api/maps");
    assert_eq!(status, 200);
    let maps: serde_json::Value = serde_json::from_str(&maps).unwrap();
    let listed: Vec<&str> = maps["maps"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    assert!(listed.contains(&"paper/map10.map"), "{listed:?}");
    assert!(listed.contains(&"open30.map"), "{listed:?}");
    // Nor is a name that is not UTF-8 (it was, with a replacement character, and opening
    // it answered 404).
    assert!(!listed.iter().any(|m| m.contains('\u{fffd}')), "{listed:?}");
    // Links leading out of the directory are not listed.
    assert!(
        !listed
            .iter()
            .any(|m| m.contains("passwd") || m.contains("link") || m.starts_with("etc")),
        "{listed:?}"
    );
    // Nor is a FIFO (it was, and opening it answered 404 "no such file"): every map listed
    // is a file `/api/map` opens.
    #[cfg(unix)]
    assert!(!listed.iter().any(|m| m.contains("ff.map")), "{listed:?}");
    for map in &listed {
        let path: String = map
            .bytes()
            .map(|b| match b.is_ascii_alphanumeric() || b"._-".contains(&b) {
                true => char::from(b).to_string(),
                false => format!("%{b:02X}"),
            })
            .collect();
        let (status, body) = get(addr, &format!("/api/map?path={path}"));
        assert!(!body.contains("no such file"), "{map}: {status} {body}");
    }
    let (status, planners) = get(addr, "/api/planners");
    assert_eq!(status, 200);
    let planners: serde_json::Value = serde_json::from_str(&planners).unwrap();
    let astar = planners
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["name"] == "astar")
        .unwrap();
    assert!(astar["params"]
        .as_array()
        .unwrap()
        .iter()
        .any(|p| p["key"] == "heuristic"));
    let (status, map) = get(addr, "/api/map?path=paper%2Fmap10.map");
    assert_eq!(status, 200);
    let map: serde_json::Value = serde_json::from_str(&map).unwrap();
    assert_eq!(
        (map["width"].as_u64(), map["height"].as_u64()),
        (Some(12), Some(12))
    );
    assert_eq!(map["cells"].as_str().map(str::len), Some(144));
    stop();
}

#[test]
fn paths_out_of_the_directory_are_refused() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    for path in [
        "../../etc/passwd",
        "..%2F..%2Fetc%2Fpasswd",
        "%2Fetc%2Fpasswd",
        "/etc/passwd",
        "..%2Fsecret.map",
        "paper/../../secret.map",
        "passwd.map",
        "etc/passwd",
        "link.map",
        "outside.yaml",
    ] {
        let (status, body) = get(addr, &format!("/api/map?path={path}"));
        assert!(status == 403 || status == 404, "{path}: {status} {body}");
        assert!(!body.contains("root:"), "{path}: {body}");
        let plan = format!(
            r#"{{"map":{},"start":[0,0],"goal":[0,0],"planner":"astar"}}"#,
            serde_json::Value::String(planner_serve::server::percent_decode(path))
        );
        let (status, body) = post(addr, "/api/plan", &plan);
        assert!(
            status == 403 || status == 404,
            "plan {path}: {status} {body}"
        );
    }
    for path in ["..", "%2Ftmp", "etc"] {
        let (status, _) = get(addr, &format!("/api/results?path={path}"));
        assert!(status == 403 || status == 404, "results {path}: {status}");
    }
    // The raw URL path is never a file path.
    assert_eq!(get(addr, "/../../etc/passwd").0, 404);
    stop();
}

#[test]
fn a_body_over_the_limit_is_refused_before_it_is_read() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    // A declared 100 MB body: refused on the header, with only a few bytes sent.
    let (status, body) = send(
        addr,
        "POST /api/plan HTTP/1.1\r\nContent-Type: application/json\r\nContent-Length: 104857600",
        &[b' '; 4096],
    );
    assert_eq!(status, 413, "{body}");
    // A body without a length (chunked) is refused; so is a head that never ends.
    let options = ServeOptions {
        max_body_bytes: 1000,
        ..ServeOptions::new(&dir, 0)
    };
    let (small, stop_small) = start(&options);
    let (status, text) = send(
        small,
        "POST /api/plan HTTP/1.1\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked",
        b"bb8\r\n",
    );
    assert_eq!(status, 411, "{text}");
    let (status, text) = send(
        small,
        "POST /api/plan HTTP/1.1\r\nContent-Length: 1001",
        &[b' '; 1001],
    );
    assert_eq!(status, 413, "{text}");
    let long = format!("GET / HTTP/1.1\r\nX-Long: {}", "a".repeat(20_000));
    assert_eq!(send(small, &long, b"").0, 431);
    stop();
    stop_small();
}

#[test]
fn planning_gives_plan_json_and_the_expanded_cells() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    for (planner, set) in [
        ("astar", ""),
        ("bfs", ""),
        ("astar", r#""heuristic=octile","moves=8""#),
    ] {
        let body = format!(
            r#"{{"map":"paper/map10.map","start":[0,0],"goal":[11,11],"planner":"{planner}","set":[{set}]}}"#
        );
        let (status, answer) = post(addr, "/api/plan", &body);
        assert_eq!(status, 200, "{answer}");
        let answer: serde_json::Value = serde_json::from_str(&answer).unwrap();
        let args = planner_runner::plan::PlanArgs {
            map: dir.join("paper/map10.map"),
            planner: planner.to_string(),
            start: Some(planner_api::Cell::new(0, 0)),
            goal: Some(planner_api::Cell::new(11, 11)),
            set: set
                .split(',')
                .filter(|s| !s.is_empty())
                .map(|s| s.trim_matches('"').to_string())
                .collect(),
            ..planner_runner::plan::PlanArgs::default()
        };
        let cli: serde_json::Value =
            serde_json::from_str(&planner_runner::plan::run(&args).unwrap().to_json().unwrap())
                .unwrap();
        assert_eq!(answer["plan"], cli, "{planner} {set}");
        let n_expanded = cli["counters"]["n_expanded"].as_u64().unwrap();
        assert_eq!(
            answer["expanded"].as_array().unwrap().len() as u64,
            n_expanded
        );
        assert_eq!(answer["expanded_total"].as_u64(), Some(n_expanded));
    }
    // A wall across the map's first column changes the answer; an edit off the grid is an error.
    let walled = r#"{"map":"open30.map","start":[0,0],"goal":[0,29],"planner":"astar","edits":[[0,10,0],[1,10,0]]}"#;
    let (status, answer) = post(addr, "/api/plan", walled);
    assert_eq!(status, 200, "{answer}");
    let answer: serde_json::Value = serde_json::from_str(&answer).unwrap();
    let path = answer["plan"]["path"].as_array().unwrap();
    assert!(!path
        .iter()
        .any(|c| c == &serde_json::json!([0, 10]) || c == &serde_json::json!([1, 10])));
    assert_eq!(answer["plan"]["metrics"]["steps"].as_u64(), Some(33));
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"open30.map","start":[0,0],"goal":[0,29],"planner":"astar","edits":[[30,0,0]]}"#,
    );
    assert_eq!(status, 400, "{answer}");
    assert!(answer.contains("outside the 30x30 grid"), "{answer}");
    // `free` is 0 or 1: another value is refused, naming the edit and the value.
    for free in [2, 7, 255] {
        let body = format!(
            r#"{{"map":"open30.map","start":[0,0],"goal":[0,29],"planner":"astar","edits":[[0,10,0],[3,4,{free}]]}}"#
        );
        let (status, answer) = post(addr, "/api/plan", &body);
        assert_eq!(status, 400, "free {free}: {answer}");
        assert!(
            answer.contains(&format!("wall edit 1 [3, 4, {free}]"))
                && answer.contains(&format!("not {free}")),
            "{answer}"
        );
    }
    // Unknown planner and parameter name themselves; a wall start names the cell.
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"open30.map","start":[0,0],"goal":[1,1],"planner":"nope"}"#,
    );
    assert_eq!(status, 400);
    assert!(answer.contains("nope"), "{answer}");
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"open30.map","start":[0,0],"goal":[1,1],"planner":"astar","set":["colour=red"]}"#,
    );
    assert_eq!(status, 400);
    assert!(answer.contains("colour"), "{answer}");
    // A number beyond 64 bits is said to be one, as plan --set says it.
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"open30.map","start":[0,0],"goal":[1,1],"planner":"astar","set":["weight=1e400"]}"#,
    );
    assert_eq!(status, 400);
    assert!(
        answer.contains("weight=1e400") && answer.contains("not a number"),
        "{answer}"
    );
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"open30.map","start":[0,0],"goal":[1,1],"planner":"astar","edits":[[1,1,0]]}"#,
    );
    assert_eq!(status, 400);
    assert!(answer.contains("(1, 1)"), "{answer}");
    let (status, _) = post(addr, "/api/plan", "{not json");
    assert_eq!(status, 400);
    stop();
}

/// `set` is parsed as `plan --set` is, with its refusals and their messages: one key with
/// two values (which would win is not for the server to guess), a setting without a key;
/// the same value twice is one setting.
#[test]
fn settings_are_refused_as_plan_set_refuses_them() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let plan_error = |set: &[&str]| {
        let args = planner_runner::plan::PlanArgs {
            map: dir.join("open30.map"),
            planner: "astar".to_string(),
            start: Some(planner_api::Cell::new(0, 0)),
            goal: Some(planner_api::Cell::new(29, 29)),
            set: set.iter().map(|s| s.to_string()).collect(),
            ..planner_runner::plan::PlanArgs::default()
        };
        match planner_runner::plan::run(&args) {
            Ok(_) => panic!("plan --set {set:?} was accepted"),
            Err(e) => e.to_string(),
        }
    };
    for set in [
        &["moves=4", "moves=8"][..],
        &["moves=8", " moves = 4 "],
        &["=4"],
        &["weight=1e400"],
    ] {
        let body = serde_json::json!({
            "map": "open30.map", "start": [0, 0], "goal": [29, 29], "planner": "astar", "set": set,
        });
        let (status, answer) = post(addr, "/api/plan", &body.to_string());
        assert_eq!(status, 400, "{set:?}: {answer}");
        let want = plan_error(set);
        assert_eq!(
            crate::common::json(&answer)["error"].as_str(),
            Some(want.as_str()),
            "{set:?}"
        );
    }
    assert!(plan_error(&["moves=4", "moves=8"]).contains("given twice"));
    let twice = r#"{"map":"open30.map","start":[0,0],"goal":[29,29],"planner":"astar","set":["moves=8","moves=8"]}"#;
    let (status, answer) = post(addr, "/api/plan", twice);
    assert_eq!(status, 200, "{answer}");
    assert_eq!(
        crate::common::json(&answer)["plan"]["metrics"]["steps"].as_u64(),
        Some(29)
    );
    stop();
}

#[test]
fn a_running_plan_is_cancelled() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    // Backtracking enumerates the simple paths of an open 30x30 map: it runs until its
    // ten-million-expansion budget, seconds.
    let body = r#"{"map":"open30.map","start":[0,0],"goal":[29,29],"planner":"backtracking","run":"slow-1"}"#;
    let planning = std::thread::spawn(move || {
        let started = std::time::Instant::now();
        let answer = post(addr, "/api/plan", body);
        (answer, started.elapsed())
    });
    let mut cancelled = false;
    for _ in 0..100 {
        std::thread::sleep(Duration::from_millis(20));
        if post(addr, "/api/cancel?run=slow-1", "").0 == 200 {
            cancelled = true;
            break;
        }
    }
    let ((status, answer), elapsed) = planning.join().unwrap();
    assert!(cancelled, "the cancel request found no run");
    assert_eq!(status, 409, "{answer}");
    assert!(answer.contains("cancelled"));
    assert!(elapsed < Duration::from_secs(3), "{elapsed:?}");
    assert_eq!(post(addr, "/api/cancel?run=slow-1", "").0, 404);
    stop();
}

#[test]
fn a_results_directory_opens_with_its_runs_and_paths() {
    let (_top, dir) = served();
    std::fs::write(
        dir.join("mine.toml"),
        "name = \"mine\"\n[[maps]]\nfiles = [\"paper/map10.map\"]\npairs = [{ start = [0, 0], goal = [11, 11] }]\n[planners.astar]\nplanner = \"astar\"\n[planners.bfs]\nplanner = \"bfs\"\n",
    )
    .unwrap();
    let config = dir.join("mine.toml");
    let output = dir.join("results/mine");
    let renderer = planner_paper::renderer();
    let report = planner_runner::sweep::experiment(&planner_runner::sweep::SweepArgs {
        threads: 1,
        output: Some(&output),
        ..planner_runner::sweep::SweepArgs::new(&config, &renderer)
    })
    .unwrap();
    assert_eq!(report.n_runs, 2);
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let (status, maps) = get(addr, "/api/maps");
    assert_eq!(status, 200);
    assert!(maps.contains("\"results/mine\""), "{maps}");
    let (status, results) = get(addr, "/api/results?path=results%2Fmine");
    assert_eq!(status, 200, "{results}");
    let results: serde_json::Value = serde_json::from_str(&results).unwrap();
    let columns = results["runs"]["columns"].as_array().unwrap();
    let rows = results["runs"]["data"].as_array().unwrap();
    assert_eq!(rows.len(), 2);
    let planner = columns.iter().position(|c| c == "planner").unwrap();
    let labels: Vec<&str> = rows.iter().map(|r| r[planner].as_str().unwrap()).collect();
    assert_eq!(labels, ["astar", "bfs"]);
    // The map the runs name is found under the served directory, and each kept path is
    // the one `plan` finds.
    assert_eq!(results["maps"]["map10.map"], "paper/map10.map");
    let paths = results["paths"].as_array().unwrap();
    assert_eq!(paths.len(), 2);
    for kept in paths {
        let args = planner_runner::plan::PlanArgs {
            map: dir.join("paper/map10.map"),
            planner: kept["planner"].as_str().unwrap().to_string(),
            start: Some(planner_api::Cell::new(0, 0)),
            goal: Some(planner_api::Cell::new(11, 11)),
            ..planner_runner::plan::PlanArgs::default()
        };
        let cli: serde_json::Value =
            serde_json::from_str(&planner_runner::plan::run(&args).unwrap().to_json().unwrap())
                .unwrap();
        assert_eq!(kept["path"], cli["path"]);
    }
    // A directory that is not a results directory is refused.
    assert_eq!(get(addr, "/api/results?path=paper").0, 404);
    // Results without runs.json (written by a config whose `outputs` leaves it out) are
    // listed, and opening them says why they cannot be drawn.
    std::fs::remove_file(output.join("runs.json")).unwrap();
    let (status, answer) = get(addr, "/api/results?path=results%2Fmine");
    assert_eq!(status, 404);
    assert!(
        answer.contains("has no runs.json: its config's `outputs` left runs.json out"),
        "{answer}"
    );
    std::fs::write(output.join("replans.jsonl"), "{}\n").unwrap();
    let (_, answer) = get(addr, "/api/results?path=results%2Fmine");
    assert!(
        answer.contains("a replanning experiment's results"),
        "{answer}"
    );
    stop();
}

/// A ROS map's unknown cells are sent apart from its occupied ones (`2` in `cells`, where
/// the grid blocks them: planning is unchanged), for the page to draw them grey; a map
/// without unknown cells (a Moving AI map, or a ROS image with none) has no `2`.
#[test]
fn a_ros_maps_unknown_cells_are_told_apart_from_its_walls() {
    let maps = repo().join("maps");
    let (addr, stop) = start(&ServeOptions::new(&maps, 0));
    for name in ["ros-nav2/tb3_sandbox.yaml", "ros-nav2/testmap.png"] {
        let (status, body) = get(addr, &format!("/api/map?path={}", name.replace('/', "%2F")));
        assert_eq!(status, 200, "{body}");
        let cells = crate::common::json(&body)["cells"]
            .as_str()
            .unwrap()
            .to_string();
        let path = maps.join(name);
        let ros = if name.ends_with(".yaml") {
            planner_maps::read_ros_map(&path, &planner_maps::RosOptions::default()).unwrap()
        } else {
            let bytes = std::fs::read(&path).unwrap();
            planner_maps::ros_map_from_image_bytes(&bytes, name, None, &Default::default()).unwrap()
        };
        let grid = planner_maps::read_map(&path).unwrap().grid;
        let want: String = grid
            .free_cells()
            .iter()
            .zip(&ros.occupancy)
            .map(|(&free, &value)| match (free, value) {
                (true, _) => '0',
                (false, -1) => '2',
                (false, _) => '1',
            })
            .collect();
        // The first cell that differs, rather than the whole strings.
        let differs = cells.chars().zip(want.chars()).position(|(a, b)| a != b);
        assert_eq!(
            (cells.len(), differs),
            (want.len(), None),
            "{name}: cells vs the grid and occupancy"
        );
        let count = |c: char| cells.chars().filter(|&d| d == c).count();
        assert!(count('1') > 0, "{name}");
        if name.ends_with(".yaml") {
            assert!(count('2') > 1000, "{name}: {}", count('2'));
        }
        // Unknown cells stay blocked: a plan from one is refused, naming the cell.
        if let Some(i) = cells.find('2') {
            let (x, y) = (i as u32 % grid.width(), i as u32 / grid.width());
            let free = cells.find('0').unwrap() as u32;
            let body = serde_json::json!({
                "map": name, "planner": "astar", "start": [x, y],
                "goal": [free % grid.width(), free / grid.width()],
            });
            let (status, answer) = post(addr, "/api/plan", &body.to_string());
            assert_eq!(status, 400, "{answer}");
            assert!(answer.contains(&format!("({x}, {y})")), "{answer}");
        }
    }
    let (_, body) = get(addr, "/api/map?path=movingai%2Farena.map");
    let cells = crate::common::json(&body)["cells"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(cells.chars().all(|c| c == '0' || c == '1'));
    stop();
}

/// `path` relative to the current directory (`..` where they part), as a user gives a
/// config to `experiment` from another directory.
fn relative_to_cwd(path: &std::path::Path) -> PathBuf {
    let cwd = std::env::current_dir().unwrap().canonicalize().unwrap();
    let path = path.canonicalize().unwrap();
    let common = cwd
        .components()
        .zip(path.components())
        .take_while(|(a, b)| a == b)
        .count();
    let mut out = PathBuf::new();
    for _ in common..cwd.components().count() {
        out.push("..");
    }
    out.extend(path.components().skip(common));
    out
}

/// A run is drawn on the map its config read, never on another of the same file name: the
/// results record the config (its path as given and its SHA-256), whose `files` say which
/// file a map name is. Without the config, a file name alone locates a map only when one
/// file has it; and a map that does not hold the runs' cells is never theirs. What is not
/// located is said, by name.
#[test]
fn a_results_map_is_located_by_its_config_not_by_its_file_name() {
    let (_top, dir) = served();
    let exp = dir.join("exp");
    std::fs::create_dir_all(exp.join("aa")).unwrap();
    // The 49 x 49 arena the runs use, and a 12 x 12 map by the same name beside it.
    let arena = repo().join("maps/movingai/arena.map");
    std::fs::copy(&arena, exp.join("arena.map")).unwrap();
    std::fs::copy(
        repo().join("maps/paper/map10.map"),
        exp.join("aa/arena.map"),
    )
    .unwrap();
    let config = exp.join("c.toml");
    std::fs::write(
        &config,
        "name = \"r\"\n[[maps]]\nfiles = [\"arena.map\"]\npairs = [{ start = [3, 1], goal = [46, 47] }]\n[planners.a]\nplanner = \"astar\"\n",
    )
    .unwrap();
    // Given as a path relative to the directory the test runs in (recorded as given).
    let given = relative_to_cwd(&config);
    let renderer = planner_paper::renderer();
    let output = exp.join("res");
    planner_runner::sweep::experiment(&planner_runner::sweep::SweepArgs {
        threads: 1,
        output: Some(&output),
        ..planner_runner::sweep::SweepArgs::new(&given, &renderer)
    })
    .unwrap();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let open = || {
        let (status, body) = get(addr, "/api/results?path=exp%2Fres");
        assert_eq!(status, 200, "{body}");
        crate::common::json(&body)
    };
    let results = open();
    assert_eq!(results["maps"]["arena.map"], "exp/arena.map", "{results}");
    assert_eq!(results["map_notes"], serde_json::json!({}));
    // Without the config (an edited one is not the config that ran), the file name is
    // ambiguous: nothing is located, and the answer says why.
    std::fs::write(&config, "# edited\n").unwrap();
    let results = open();
    assert!(results["maps"]["arena.map"].is_null(), "{results}");
    let note = results["map_notes"]["arena.map"].as_str().unwrap();
    assert!(
        note.contains("not under the served directory with the SHA-256")
            && note.contains("2 map files")
            && note.contains("exp/aa/arena.map, exp/arena.map"),
        "{note}"
    );
    // One file by that name, but too small for the runs' cells: not theirs.
    std::fs::remove_file(exp.join("arena.map")).unwrap();
    let results = open();
    assert!(results["maps"]["arena.map"].is_null(), "{results}");
    let note = results["map_notes"]["arena.map"].as_str().unwrap();
    assert!(
        note.contains("exp/aa/arena.map is 12 x 12, and its runs use cells up to (46, 47)"),
        "{note}"
    );
    // One file by that name that holds them: located, with a note that the name alone
    // found it.
    std::fs::remove_dir_all(exp.join("aa")).unwrap();
    std::fs::copy(&arena, exp.join("arena.map")).unwrap();
    let results = open();
    assert_eq!(results["maps"]["arena.map"], "exp/arena.map", "{results}");
    let note = results["map_notes"]["arena.map"].as_str().unwrap();
    assert!(note.contains("found by its file name alone"), "{note}");
    stop();
}

/// What a page of another site could make the user's browser send is refused: a `Host`
/// that is a DNS name other than localhost (DNS rebinding, which let that page read the
/// served maps and results) and an `Origin` of another site (which let it start plans);
/// localhost, IP addresses and same-origin requests are answered.
#[test]
fn requests_from_other_sites_are_refused() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let (status, answer) = send(addr, "GET /api/maps HTTP/1.1\r\nHost: rebound.example", b"");
    assert_eq!(status, 403, "{answer}");
    assert!(
        answer.contains("is not an address of this server"),
        "{answer}"
    );
    let port = addr.port();
    for host in [
        format!("localhost:{port}"),
        format!("LOCALHOST:{port}"),
        format!("127.0.0.1:{port}"),
        format!("[::1]:{port}"),
        "localhost".to_string(),
    ] {
        let (status, answer) = send(
            addr,
            &format!("GET /api/maps HTTP/1.1\r\nHost: {host}"),
            b"",
        );
        assert_eq!(status, 200, "{host}: {answer}");
    }
    for host in [
        "localhost.rebound.example",
        "127.0.0.1.nip.io",
        "[::1",
        "localhost:http",
    ] {
        let (status, _) = send(
            addr,
            &format!("GET /api/maps HTTP/1.1\r\nHost: {host}"),
            b"",
        );
        assert_eq!(status, 403, "{host}");
    }
    let body =
        r#"{"map":"paper/map10.map","start":[0,0],"goal":[11,11],"planner":"astar","set":[]}"#;
    let (status, answer) = send(
        addr,
        &format!("POST /api/plan HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://evil.example\r\nContent-Type: text/plain"),
        body.as_bytes(),
    );
    assert_eq!(status, 403, "{answer}");
    assert!(answer.contains("another site"), "{answer}");
    let (status, answer) = send(
        addr,
        &format!("POST /api/plan HTTP/1.1\r\nHost: {addr}\r\nOrigin: http://{addr}\r\nContent-Type: application/json"),
        body.as_bytes(),
    );
    assert_eq!(status, 200, "{answer}");
    stop();
}

/// A map changed on disk after the page loaded it: a plan that gives back the `version`
/// `/api/map` answered is refused (409, saying so), whether the new file has another size
/// or the same size with other walls; given the new version, it plans. (The server planned
/// on the new file, and the page drew its path and cells on the old map: a 12 x 6 map's
/// path on the 8 x 5 map drawn, or a path through walls drawn as free.)
#[test]
fn a_plan_on_a_map_changed_since_it_was_loaded_is_refused() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let write = |width: usize, height: usize, walls: &[(usize, usize)]| {
        let mut text = format!("type octile\nheight {height}\nwidth {width}\nmap\n");
        for y in 0..height {
            for x in 0..width {
                text.push(if walls.contains(&(x, y)) { '@' } else { '.' });
            }
            text.push('\n');
        }
        std::fs::write(dir.join("e.map"), text).unwrap();
    };
    let version = || {
        let (status, body) = get(addr, "/api/map?path=e.map");
        assert_eq!(status, 200, "{body}");
        crate::common::json(&body)["version"]
            .as_str()
            .unwrap()
            .to_string()
    };
    let plan = |version: &str| {
        let body = serde_json::json!({
            "map": "e.map", "start": [0, 0], "goal": [7, 4], "planner": "astar",
            "map_version": version,
        });
        post(addr, "/api/plan", &body.to_string())
    };
    write(8, 5, &[]);
    let loaded = version();
    assert_eq!(plan(&loaded).0, 200);
    for (width, height, walls) in [(12, 6, vec![(3, 3), (4, 3)]), (8, 5, vec![(3, 0), (3, 1)])] {
        write(width, height, &walls);
        let (status, answer) = plan(&loaded);
        assert_eq!(status, 409, "{width}x{height}: {answer}");
        assert_eq!(
            crate::common::json(&answer)["error"].as_str(),
            Some(planner_serve::server::MAP_CHANGED)
        );
        let now = version();
        assert_ne!(now, loaded);
        assert_eq!(plan(&now).0, 200, "{width}x{height}");
    }
    // The same cells written again are the same map.
    write(8, 5, &[]);
    assert_eq!(version(), loaded);
    assert_eq!(plan(&loaded).0, 200);
    stop();
}

/// A plan request whose value does not fit its key is refused naming the key (with the
/// index into a list) and what the key takes, without the body's line and column (it said
/// `invalid value: integer -1, expected u32 at line 1 column 54`, naming no key).
#[test]
fn a_plan_request_value_that_does_not_fit_names_its_key() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let base = r#""map":"paper/map10.map","planner":"astar""#;
    for (fields, key, takes) in [
        (
            r#""start":[0,0],"goal":[-1,11]"#,
            "`goal[0]`",
            "`goal` takes a cell [x, y]",
        ),
        (
            r#""start":[0,0],"goal":[4294967296,11]"#,
            "`goal[0]`",
            "`goal` takes a cell",
        ),
        (
            r#""start":[0,1.5],"goal":[1,11]"#,
            "`start[1]`",
            "`start` takes a cell",
        ),
        (
            r#""start":[0,0],"goal":[0,11],"max_expansions":18446744073709551616"#,
            "`max_expansions`",
            "`max_expansions` takes a whole number",
        ),
        (
            r#""start":[0,0],"goal":[0,11],"max_expansions":-5"#,
            "`max_expansions`",
            "`max_expansions` takes a whole number",
        ),
        (
            r#""start":[0,0],"goal":[0,11],"edits":[[1,1,256]]"#,
            "`edits[0][2]`",
            "`edits` takes a list of wall edits",
        ),
    ] {
        let (status, answer) = post(addr, "/api/plan", &format!("{{{base},{fields}}}"));
        assert_eq!(status, 400, "{fields}: {answer}");
        let error = crate::common::json(&answer)["error"]
            .as_str()
            .unwrap()
            .to_string();
        assert!(
            error.starts_with(&format!("plan request: {key}: ")) && error.contains(takes),
            "{fields}: {error}"
        );
        assert!(!error.contains("at line"), "{fields}: {error}");
    }
    // A missing or unknown key is named by serde's own message.
    let (status, answer) = post(addr, "/api/plan", &format!("{{{base},\"start\":[0,0]}}"));
    assert_eq!(status, 400);
    assert!(answer.contains("missing field `goal`"), "{answer}");
    stop();
}

/// The smaller refusals say what is wrong: a plan's error names the map by its path under
/// the served directory (it named the server's absolute path); a directory asked for as a
/// map is said to be one (it said `no such file`); `/api/map` and `/api/results` without
/// `path` say it is missing (400; they said `"": outside the served directory`, 403);
/// `graded=yes` is refused (it read as false); a 405 has an `Allow` header and `HEAD` a
/// GET path's head (it was 405); the page's icon is served (a 404 on every load).
#[test]
fn refusals_name_the_relative_path_the_missing_parameter_and_the_allowed_methods() {
    let (_top, dir) = served();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"paper/map10.map","start":[0,0],"goal":[12,11],"planner":"astar"}"#,
    );
    assert_eq!(status, 400, "{answer}");
    let error = crate::common::json(&answer)["error"]
        .as_str()
        .unwrap()
        .to_string();
    assert!(
        error.starts_with("paper/map10.map: goal (12, 11)"),
        "{error}"
    );
    let root = dir.canonicalize().unwrap();
    assert!(!error.contains(&*root.to_string_lossy()), "{error}");
    let (status, answer) = post(
        addr,
        "/api/plan",
        r#"{"map":"paper","start":[0,0],"goal":[1,1],"planner":"astar"}"#,
    );
    assert_eq!(status, 400, "{answer}");
    assert!(answer.contains("is a directory"), "{answer}");
    for url in ["/api/map", "/api/map?weights=w.csv", "/api/results"] {
        let (status, answer) = get(addr, url);
        assert_eq!(status, 400, "{url}: {answer}");
        assert!(
            answer.contains("`path` parameter is missing"),
            "{url}: {answer}"
        );
    }
    let (status, answer) = get(addr, "/api/map?path=open30.map&graded=yes");
    assert_eq!(status, 400, "{answer}");
    assert!(answer.contains("graded"), "{answer}");
    assert_eq!(get(addr, "/api/map?path=open30.map&graded=false").0, 200);
    assert_eq!(get(addr, "/favicon.svg").0, 200);
    let raw = |request: &str| {
        use std::io::{Read as _, Write as _};
        let mut stream = std::net::TcpStream::connect(addr).unwrap();
        stream
            .write_all(format!("{request}\r\nHost: {addr}\r\n\r\n").as_bytes())
            .unwrap();
        let mut text = String::new();
        let _ = stream.read_to_string(&mut text);
        text
    };
    for (request, allow) in [
        ("PUT /api/maps HTTP/1.1", "GET, HEAD"),
        ("GET /api/plan HTTP/1.1", "POST"),
        ("DELETE / HTTP/1.1", "GET, HEAD"),
    ] {
        let answer = raw(request);
        assert!(answer.starts_with("HTTP/1.1 405"), "{request}: {answer}");
        assert!(
            answer.contains(&format!("\r\nAllow: {allow}\r\n")),
            "{request}: {answer}"
        );
    }
    let answer = raw("HEAD / HTTP/1.1");
    assert!(answer.starts_with("HTTP/1.1 200"), "{answer}");
    let (head, body) = answer.split_once("\r\n\r\n").unwrap();
    assert!(
        head.contains("Content-Length: ") && body.is_empty(),
        "{answer}"
    );
    stop();
}

/// `.csv` weight files are not listed as maps (maps/weighted/arena-weights.csv was, and
/// loading it as a map failed); a 0/1 `.csv` map is.
#[test]
fn weight_files_are_not_listed_as_maps() {
    let (_top, dir) = served();
    std::fs::copy(
        repo().join("maps/weighted/arena-weights.csv"),
        dir.join("arena-weights.csv"),
    )
    .unwrap();
    std::fs::write(dir.join("costs.csv"), "# costs\n3,1,1\n1,1,9\n").unwrap();
    std::fs::write(dir.join("grid.csv"), "# a map\n0,1,0\n0,0,0\n").unwrap();
    let (addr, stop) = start(&ServeOptions::new(&dir, 0));
    let (status, maps) = get(addr, "/api/maps");
    assert_eq!(status, 200);
    let maps = crate::common::json(&maps);
    let listed: Vec<&str> = maps["maps"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|v| v.as_str())
        .collect();
    assert!(listed.contains(&"grid.csv"), "{listed:?}");
    assert!(
        !listed.contains(&"arena-weights.csv") && !listed.contains(&"costs.csv"),
        "{listed:?}"
    );
    stop();
}
