//! Cancelling stops the search itself, not only the answer: a search that would run for
//! hours ends at its next budget check once its flag is raised, with status
//! `budget_exhausted` and no recorded cells, and the server's worker frees its place.

use std::net::SocketAddr;
use std::path::Path;
use std::time::{Duration, Instant};

use planner_api::{CancelFlag, Cell, Grid};
use planner_runner::record::RunStatus;
use planner_serve::query::{self, Caps, Query};
use planner_serve::{ServeOptions, Server};

/// An open `n` x `n` grid: Backtracking enumerates its simple paths, about forever.
fn open(n: u32) -> Grid {
    let row = ".".repeat(n as usize);
    Grid::from_ascii(&vec![row; n as usize].join("\n")).unwrap()
}

/// Caps that let a search run far past any test's patience.
fn unbounded() -> Caps {
    Caps {
        max_expansions: u64::MAX,
        ..Caps::default()
    }
}

#[test]
fn a_cancelled_search_stops_with_budget_exhausted() {
    let flag = CancelFlag::new();
    let cancel = flag;
    let worker = std::thread::spawn(move || {
        let path = Path::new("open64.map");
        let set: Vec<String> = Vec::new();
        let query = Query {
            map_name: "open64.map",
            map_path: path,
            start: Cell::new(0, 0),
            goal: Cell::new(63, 63),
            planner: "backtracking",
            set: &set,
            max_expansions: Some(u64::MAX),
            ignore_costs: false,
            cancel: Some(cancel),
        };
        query::plan(&query, open(64), &unbounded())
    });
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        !worker.is_finished(),
        "the search ended before it was cancelled"
    );
    flag.cancel();
    let result = worker.join().unwrap().unwrap();
    assert_eq!(result.record.status, RunStatus::BudgetExhausted);
    assert!(
        result.expanded.is_empty(),
        "a cancelled run records no cells"
    );
    let expanded = result.record.counters.get("n_expanded").unwrap();
    assert!(expanded > 0 && expanded < u64::MAX, "{expanded}");
}

fn post(addr: SocketAddr, url: &str, body: &str) -> u16 {
    use std::io::{Read, Write};
    let mut stream = std::net::TcpStream::connect(addr).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    let request = format!(
        "POST {url} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{body}",
        body.len()
    );
    stream.write_all(request.as_bytes()).unwrap();
    let mut answer = String::new();
    let _ = stream.read_to_string(&mut answer);
    answer
        .split(' ')
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(0)
}

/// A directory with an open 64 x 64 map, served one plan at a time without an expansion
/// cap (so only a cancel can end a Backtracking search there), and its server's address and
/// stopper.
fn one_place_server(name: &str) -> (std::path::PathBuf, SocketAddr, impl Fn()) {
    let dir =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("planner-serve-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from("type octile\nheight 64\nwidth 64\nmap\n");
    for _ in 0..64 {
        text.push_str(&".".repeat(64));
        text.push('\n');
    }
    std::fs::write(dir.join("open64.map"), text).unwrap();
    let options = ServeOptions {
        caps: unbounded(),
        max_running: 1,
        ..ServeOptions::new(&dir, 0)
    };
    let server = Server::bind(&options).unwrap();
    let addr = server.addr().unwrap();
    let stop = server.stopper();
    std::thread::spawn(move || server.run());
    (dir, addr, stop)
}

/// Posts a quick plan until it is taken (not 503 busy), for at most 60 s; its status.
fn quick_plan_when_free(addr: SocketAddr) -> u16 {
    let quick = r#"{"map":"open64.map","start":[0,0],"goal":[5,5],"planner":"astar"}"#;
    let started = Instant::now();
    loop {
        let status = post(addr, "/api/plan", quick);
        if status != 503 || started.elapsed() > Duration::from_secs(60) {
            return status;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn a_cancelled_plan_frees_its_place() {
    let (dir, addr, stop) = one_place_server("cancel");
    let slow = r#"{"map":"open64.map","start":[0,0],"goal":[63,63],"planner":"backtracking","max_expansions":18000000000000000000,"run":"forever"}"#;
    let planning = std::thread::spawn(move || post(addr, "/api/plan", slow));
    let mut cancelled = false;
    for _ in 0..500 {
        std::thread::sleep(Duration::from_millis(20));
        if post(addr, "/api/cancel?run=forever", "") == 200 {
            cancelled = true;
            break;
        }
    }
    assert!(cancelled, "the cancel request found no run");
    assert_eq!(planning.join().unwrap(), 409);
    // The worker's place is free once its search has stopped: a new plan is taken (not
    // 503 busy). Without the search stopping it would stay busy for hours.
    assert_eq!(quick_plan_when_free(addr), 200, "still busy");
    stop();
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_plan_whose_client_left_frees_its_place() {
    use std::io::Write;
    let (dir, addr, stop) = one_place_server("gone");
    // No run id, so no cancel request can reach it: only its client's leaving can.
    let slow = r#"{"map":"open64.map","start":[0,0],"goal":[63,63],"planner":"backtracking","max_expansions":18000000000000000000}"#;
    let mut stream = std::net::TcpStream::connect(addr).unwrap();
    let request = format!(
        "POST /api/plan HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\nContent-Length: {}\r\n\r\n{slow}",
        slow.len()
    );
    stream.write_all(request.as_bytes()).unwrap();
    // The search is running: the one place is taken.
    std::thread::sleep(Duration::from_millis(300));
    let quick = r#"{"map":"open64.map","start":[0,0],"goal":[5,5],"planner":"astar"}"#;
    assert_eq!(
        post(addr, "/api/plan", quick),
        503,
        "the slow plan is not running"
    );
    // The client leaves without reading its answer.
    drop(stream);
    assert_eq!(
        quick_plan_when_free(addr),
        200,
        "still busy after the client left"
    );
    stop();
    let _ = std::fs::remove_dir_all(&dir);
}

/// A plan that would run for minutes within the expansion cap (CAPSO with a large swarm,
/// many samples per segment: ten thousand evaluations a second against ten million) ends
/// at the server's wall-clock limit with status `budget_exhausted` and no recorded cells,
/// and is not run again to record them.
#[test]
fn a_slow_plan_stops_at_the_time_limit() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("planner-serve-time-limit");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from("type octile\nheight 30\nwidth 40\nmap\n");
    for _ in 0..30 {
        text.push_str(&".".repeat(40));
        text.push('\n');
    }
    std::fs::write(dir.join("open40x30.map"), text).unwrap();
    let limit = Duration::from_secs(1);
    let options = ServeOptions {
        caps: Caps {
            max_time: limit,
            ..Caps::default()
        },
        ..ServeOptions::new(&dir, 0)
    };
    let (addr, stop) = crate::common::start(&options);
    let slow = r#"{"map":"open40x30.map","start":[0,0],"goal":[39,29],"planner":"capso","set":["population=10000","iterations=100000","samples_per_segment=1000","control_points=20"]}"#;
    let started = Instant::now();
    let (status, answer) = crate::common::post(addr, "/api/plan", slow);
    let took = started.elapsed();
    assert_eq!(status, 200, "{answer}");
    let answer = crate::common::json(&answer);
    assert_eq!(answer["plan"]["status"], "budget_exhausted", "{answer}");
    let evaluations = answer["plan"]["counters"]["n_fitness_evaluations"]
        .as_u64()
        .unwrap();
    assert!(evaluations > 0, "{answer}");
    assert_eq!(answer["expanded_total"].as_u64(), Some(0), "{answer}");
    assert!(
        took < limit + Duration::from_secs(5),
        "the plan took {took:?} under a limit of {limit:?}"
    );
    stop();
    let _ = std::fs::remove_dir_all(&dir);
}
