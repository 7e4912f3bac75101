//! Streamed sweeps through the real binary: 3 shards merged equal one run, and a sweep
//! killed (SIGKILL) mid-way and resumed equals an uninterrupted one (timing and memory
//! columns aside).

mod common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use common::root;

fn xtask(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gridplan-sweeps-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// runs.csv without its time_ms, setup_ms and peak_heap_bytes columns (17..20).
/// summary.md's deterministic parts: every heading, and every section but the provenance
/// (date, threads) and the aggregates (times); the optimum table included.
fn deterministic_summary(dir: &Path) -> Vec<String> {
    let text = fs::read_to_string(dir.join("summary.md")).unwrap();
    let mut keep = true;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("## ") {
            keep = !line.contains("Provenance") && !line.to_lowercase().contains("aggregate");
            out.push(line.to_string());
        } else if keep && !line.contains(" ms") {
            out.push(line.to_string());
        }
    }
    assert!(out
        .iter()
        .any(|l| l.starts_with("## Lengths against the scenario optima")));
    out
}

fn deterministic_csv(dir: &Path) -> Vec<String> {
    fs::read_to_string(dir.join("runs.csv"))
        .unwrap()
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [&f[..17], &f[20..]].concat().join(",")
        })
        .collect()
}

#[test]
fn three_shards_merged_equal_one_run() {
    let dir = scratch("shards");
    let d = |n: &str| dir.join(n).display().to_string();
    xtask(&[
        "experiment",
        "configs/movingai.toml",
        "--quiet",
        "--output",
        &d("one"),
    ]);
    for k in 1..=3 {
        let shard = format!("{k}/3");
        xtask(&[
            "experiment",
            "configs/movingai.toml",
            "--quiet",
            "--shard",
            &shard,
            "--output",
            &d(&format!("s{k}")),
        ]);
    }
    xtask(&[
        "merge",
        &d("s1"),
        &d("s2"),
        &d("s3"),
        "--output",
        &d("merged"),
    ]);
    let one = deterministic_csv(&dir.join("one"));
    assert!(one.len() > 1000);
    assert_eq!(one, deterministic_csv(&dir.join("merged")));
    assert_eq!(
        deterministic_summary(&dir.join("one")),
        deterministic_summary(&dir.join("merged"))
    );
    let missing = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["merge", &d("s1"), &d("s3")])
        .output()
        .unwrap();
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("shards 2/3"));
}

#[test]
fn killed_and_resumed_equals_uninterrupted() {
    let dir = scratch("resume");
    let config = "configs/bench/arena-repeats.toml";
    let full = dir.join("full").display().to_string();
    xtask(&[
        "experiment",
        config,
        "--quiet",
        "--threads",
        "2",
        "--output",
        &full,
    ]);
    let out = dir.join("res");
    let mut child = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "experiment",
            config,
            "--quiet",
            "--threads",
            "2",
            "--output",
        ])
        .arg(&out)
        .current_dir(root())
        .spawn()
        .unwrap();
    let stream = dir.join(".res.stream/records.jsonl");
    let started = Instant::now();
    while fs::read(&stream).map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count()) < 2 {
        assert!(started.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let lines = fs::read(&stream)
        .unwrap()
        .iter()
        .filter(|&&c| c == b'\n')
        .count();
    assert!(lines < 16_001, "the sweep finished before the kill");
    assert!(!out.join("runs.csv").exists());
    xtask(&[
        "experiment",
        config,
        "--quiet",
        "--threads",
        "2",
        "--resume",
        "--output",
        &out.display().to_string(),
    ]);
    assert_eq!(deterministic_csv(Path::new(&full)), deterministic_csv(&out));
}
