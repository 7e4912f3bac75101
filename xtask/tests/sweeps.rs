//! Streamed sweeps through the real binary: 3 shards merged equal one run (figures with
//! expanded cells included), `report` re-renders a results directory byte for byte, and a sweep
//! killed (SIGKILL) mid-way and resumed equals an uninterrupted one (timing and memory
//! columns aside); SIGINT and SIGTERM stop a sweep with exit status 130, the finished
//! runs recorded and the old results untouched, and resuming then equals an
//! uninterrupted run; `--resume` after a finished sweep runs nothing again; a real Slurm
//! job array of 3 tasks plus its afterok merge equals a local run, and a task requeued
//! while it runs resumes its recorded runs (both skipped, saying why, without a running
//! Slurm, unless `GRIDPLAN_SLURM_TEST=1`, which CI sets after `scripts/slurm-start.sh`).

use crate::common;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use common::root;

/// Runs xtask with `args` from the repository root; returns its stdout.
fn xtask(args: &[&str]) -> String {
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
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Runs xtask with each of `runs` at once from the repository root; each must succeed.
fn xtask_all(runs: &[Vec<&str>]) {
    let children: Vec<_> = runs
        .iter()
        .map(|args| {
            Command::new(env!("CARGO_BIN_EXE_xtask"))
                .args(args)
                .current_dir(root())
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    for (args, child) in runs.iter().zip(children) {
        let out = child.wait_with_output().unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// Runs `experiment CONFIG --quiet --threads 2` with `extra` and `--output OUTPUT`, which
/// must succeed.
fn sweep(config: &str, output: &Path, extra: &[&str]) {
    let output = output.display().to_string();
    let mut args = vec!["experiment", config, "--quiet", "--threads", "2"];
    args.extend_from_slice(extra);
    args.extend(["--output", &output]);
    xtask(&args);
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-sweeps-{name}"));
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
    let mut paired = false;
    let mut out = Vec::new();
    for line in text.lines() {
        if line.starts_with("## ") {
            keep = !line.contains("Provenance") && !line.to_lowercase().contains("aggregate");
            paired = line.contains("Planners compared problem by problem");
            out.push(line.to_string());
        } else if paired && line.starts_with("| ") {
            // The paired table's time columns (8 and 9 of 11) are measured.
            let mut cells: Vec<&str> = line.split(" | ").collect();
            assert_eq!(cells.len(), 11, "{line}");
            cells[7] = "[time]";
            cells[8] = "[time]";
            out.push(cells.join(" | "));
        } else if keep && !line.contains(" ms") {
            out.push(line.to_string());
        }
    }
    assert!(out
        .iter()
        .any(|l| l.starts_with("## Lengths against the scenario optima")));
    out
}

/// Every file of a results directory (but its marker) by relative path, with its bytes.
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    fn walk(base: &Path, dir: &Path, out: &mut std::collections::BTreeMap<String, Vec<u8>>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(base, &path, out);
            } else {
                let name = path.strip_prefix(base).unwrap().display().to_string();
                if name != ".gridplan-results" {
                    out.insert(name, fs::read(&path).unwrap());
                }
            }
        }
    }
    let mut out = std::collections::BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// The figures of a results directory (drawn from deterministic values only).
fn figures(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    files(dir)
        .into_iter()
        .filter(|(name, _)| name.starts_with("figures/"))
        .collect()
}

/// The OMPL logs of a results directory without what timing decides: the `Starting at`
/// and `seconds spent` lines, and the `time` and `memory` values (fields 4 and 7, after
/// `solved` and `status`) of each run line.
fn ompl_logs(dir: &Path) -> std::collections::BTreeMap<String, Vec<String>> {
    let logs: std::collections::BTreeMap<String, Vec<String>> = files(dir)
        .into_iter()
        .filter(|(name, _)| name.starts_with("ompl/"))
        .map(|(name, bytes)| {
            let text = String::from_utf8(bytes).unwrap();
            let lines = text
                .lines()
                .filter(|l| !l.starts_with("Starting at ") && !l.contains("seconds spent"))
                .map(|l| {
                    let mut fields: Vec<&str> = l.split("; ").collect();
                    if fields.len() > 7 {
                        fields[3] = "";
                        fields[6] = "";
                    }
                    fields.join("; ")
                })
                .collect();
            (name, lines)
        })
        .collect();
    assert!(!logs.is_empty(), "no OMPL logs in {}", dir.display());
    logs
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
    // The whole sweep and its three shards are independent processes: they run at once.
    let shards: Vec<[String; 2]> = (1..=3)
        .map(|k| [format!("{k}/3"), d(&format!("s{k}"))])
        .collect();
    let one = d("one");
    let mut runs = vec![vec![
        "experiment",
        "configs/movingai.toml",
        "--quiet",
        "--output",
        &one,
    ]];
    for [shard, output] in &shards {
        runs.push(vec![
            "experiment",
            "configs/movingai.toml",
            "--quiet",
            "--shard",
            shard,
            "--output",
            output,
        ]);
    }
    xtask_all(&runs);
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
    // Merged shards draw the same figures, the expanded cells included (each shard
    // records those of the drawn runs it holds; the merge runs no planner).
    let one_files = files(&dir.join("one"));
    assert_eq!(
        one_files.keys().collect::<Vec<_>>(),
        files(&dir.join("merged")).keys().collect::<Vec<_>>()
    );
    assert!(one_files.keys().any(|f| f.ends_with("-expanded.svg")));
    assert_eq!(figures(&dir.join("one")), figures(&dir.join("merged")));
    // The OMPL logs too, timing aside (the collection time and start date, and each
    // run's time and memory, as runs.csv's comparison leaves them out).
    assert_eq!(ompl_logs(&dir.join("one")), ompl_logs(&dir.join("merged")));
    // `report` re-renders a results directory in place from what it holds, byte for byte
    // (its provenance and times are the recorded ones); on the merged shards too.
    xtask(&["report", &d("one")]);
    assert!(
        one_files == files(&dir.join("one")),
        "report changed a file of one run"
    );
    let merged_files = files(&dir.join("merged"));
    xtask(&["report", &d("merged")]);
    assert!(
        merged_files == files(&dir.join("merged")),
        "report changed a merged file"
    );
    let missing = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["merge", &d("s1"), &d("s3")])
        .output()
        .unwrap();
    assert!(!missing.status.success());
    assert!(String::from_utf8_lossy(&missing.stderr).contains("shards 2/3"));
    // A shard is not a sweep's results: `report` says to merge, and leaves it as it is.
    let shard_files = files(&dir.join("s1"));
    let shard = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["report", &d("s1")])
        .output()
        .unwrap();
    assert!(!shard.status.success());
    let message = String::from_utf8_lossy(&shard.stderr);
    assert!(
        message.contains("holds one shard of a sweep (shard.stream)")
            && message.contains("gridplan merge"),
        "{message}"
    );
    assert!(
        shard_files == files(&dir.join("s1")),
        "report touched a shard"
    );
}

#[test]
fn killed_and_resumed_equals_uninterrupted() {
    let dir = scratch("resume");
    let config = "configs/bench/arena-repeats.toml";
    let full = dir.join("full");
    sweep(config, &full, &[]);
    let out = dir.join("res");
    let mut child = start_sweep(config, &out, &[]);
    let stream = dir.join(".res.stream/records.stream");
    let started = Instant::now();
    while recorded(&stream) < 1 {
        assert!(started.elapsed() < Duration::from_secs(60));
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    assert!(
        recorded(&stream) < 16_000,
        "the sweep finished before the kill"
    );
    assert!(!out.join("runs.csv").exists());
    sweep(config, &out, &["--resume"]);
    assert_eq!(deterministic_csv(&full), deterministic_csv(&out));
}

/// `--resume` after a sweep finished (a requeued cluster task, a script that always passes
/// it) runs nothing again: the output's records are carried over, their times included, so
/// the tables come back as they were; so for a shard. The results of another config under
/// the same output, or another shard's, are refused (exit 2) and left as they were; without
/// `--resume` they are replaced.
#[test]
fn resuming_a_finished_sweep_runs_nothing_again() {
    let dir = scratch("finished");
    let config = "configs/bench/arena-repeats.toml";
    let out = dir.join("res");
    sweep(config, &out, &[]);
    let before = files(&out);
    sweep(config, &out, &["--resume"]);
    let after = files(&out);
    for name in ["runs.csv", "records.stream"] {
        assert!(
            before[name] == after[name],
            "{name} changed: runs ran again"
        );
    }
    // runs.json's table, times included (its provenance says when the sweep ran).
    let table =
        |bytes: &[u8]| serde_json::from_slice::<serde_json::Value>(bytes).unwrap()["runs"].clone();
    assert!(table(&before["runs.json"]) == table(&after["runs.json"]));
    assert!(!dir.join(".res.stream").exists());
    let shard = dir.join("shard");
    sweep(config, &shard, &["--shard", "2/3"]);
    let stream = fs::read(shard.join("shard.stream")).unwrap();
    sweep(config, &shard, &["--shard", "2/3", "--resume"]);
    assert!(stream == fs::read(shard.join("shard.stream")).unwrap());
    // Shard 1's records are not shard 2's, nor paper.toml's arena-repeats': refused.
    let refused = |config: &str, output: &Path, extra: &[&str]| {
        let mut args = vec!["experiment", config, "--quiet", "--threads", "2"];
        args.extend_from_slice(extra);
        let output = output.display().to_string();
        args.extend(["--resume", "--output", &output]);
        let run = Command::new(env!("CARGO_BIN_EXE_xtask"))
            .args(&args)
            .current_dir(root())
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains("Run without --resume to start over"),
            "{stderr}"
        );
    };
    refused(config, &shard, &["--shard", "1/3"]);
    assert!(stream == fs::read(shard.join("shard.stream")).unwrap());
    refused("configs/paper.toml", &out, &[]);
    assert!(after["runs.csv"] == fs::read(out.join("runs.csv")).unwrap());
    sweep("configs/paper.toml", &out, &[]);
    let paper = fs::read_to_string(out.join("runs.csv")).unwrap();
    assert!(paper.contains("backtracking") && !paper.contains("arena"));
}

/// The runs a sweep's framed resume stream holds (0 before it has a header), and whether
/// it ends in a cut frame.
fn read_stream(stream: &Path) -> (usize, bool) {
    let Ok(file) = fs::File::open(stream) else {
        return (0, false);
    };
    let Ok((_, mut reader)) =
        planner_runner::stream::StreamReader::new(std::io::BufReader::new(file), "stream")
    else {
        return (0, false);
    };
    let mut n = 0;
    while let Ok(Some(_)) = reader.next_run() {
        n += 1;
    }
    (n, reader.was_cut())
}

/// The runs a sweep's framed resume stream holds.
fn recorded(stream: &Path) -> usize {
    read_stream(stream).0
}

/// Starts `experiment CONFIG --quiet --threads 2` with `extra` and `--output OUTPUT`, its
/// stderr piped and its SIGINT disposition the default, without waiting for it.
fn start_sweep(config: &str, output: &Path, extra: &[&str]) -> std::process::Child {
    let mut command = Command::new(env!("CARGO_BIN_EXE_xtask"));
    // SIGINT stops it, also when this test runs with SIGINT ignored.
    common::default_sigint(&mut command)
        .args(["experiment", config, "--quiet", "--threads", "2"])
        .args(extra)
        .arg("--output")
        .arg(output)
        .current_dir(root())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap()
}

/// Starts `experiment config --threads 2 --output out` (with `extra`), waits until its
/// stream holds a few batches, sends `signal` and returns its exit status and stderr.
fn interrupt(config: &str, out: &Path, extra: &[&str], signal: &str) -> (Option<i32>, String) {
    let child = start_sweep(config, out, extra);
    let stream = out.with_file_name(".res.stream/records.stream");
    let before = recorded(&stream);
    let started = Instant::now();
    while recorded(&stream) < before + 2048 {
        assert!(started.elapsed() < Duration::from_secs(120), "no progress");
        std::thread::sleep(Duration::from_millis(5));
    }
    let status = Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn sigint_and_sigterm_stop_cleanly_and_resume_equals_uninterrupted() {
    let dir = scratch("signals");
    let config = "configs/bench/arena-repeats.toml";
    let full = dir.join("full");
    sweep(config, &full, &[]);
    // An older result in the output, which an interrupted sweep must leave as it was.
    let out = dir.join("res");
    let paper = "configs/paper.toml";
    xtask(&[
        "experiment",
        paper,
        "--quiet",
        "--output",
        &out.display().to_string(),
    ]);
    let old_csv = fs::read(out.join("runs.csv")).unwrap();
    let stream = dir.join(".res.stream/records.stream");
    for (signal, extra) in [("-INT", &[][..]), ("-TERM", &["--resume"][..])] {
        let (code, stderr) = interrupt(config, &out, extra, signal);
        assert_eq!(code, Some(130), "{signal}: {stderr}");
        // The runs in order, and those finished after a run the stop cancelled.
        let n = recorded(&stream) + recorded(&stream.with_file_name("ahead.stream"));
        assert!(n < 16_000, "{signal}: the sweep finished first");
        assert!(
            stderr.contains(&format!(
                "interrupted after {n} of 16000 runs; rerun with --resume to continue"
            )),
            "{signal}: {n} recorded; {stderr}"
        );
        // Complete frames only: the stop came between batches, not mid-write.
        assert!(!read_stream(&stream).1, "{signal}: a cut frame");
        assert_eq!(fs::read(out.join("runs.csv")).unwrap(), old_csv, "{signal}");
    }
    sweep(config, &out, &["--resume"]);
    assert_eq!(deterministic_csv(&full), deterministic_csv(&out));
    assert!(!stream.exists());
}

/// runs.json's table without its timing and memory columns: (columns, rows).
fn deterministic_records(dir: &Path) -> (Vec<serde_json::Value>, Vec<Vec<serde_json::Value>>) {
    let text = fs::read_to_string(dir.join("runs.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let columns = json["runs"]["columns"].as_array().unwrap();
    let keep: Vec<usize> = (0..columns.len())
        .filter(|&i| {
            !["time_ms", "setup_ms", "peak_heap_bytes"].contains(&columns[i].as_str().unwrap())
        })
        .collect();
    let rows = json["runs"]["data"]
        .as_array()
        .unwrap()
        .iter()
        .map(|row| keep.iter().map(|&i| row[i].clone()).collect())
        .collect();
    (keep.iter().map(|&i| columns[i].clone()).collect(), rows)
}

/// Why the Slurm test cannot run here (no sbatch, or no controller answering), if so.
fn slurm_missing() -> Option<String> {
    let ping = match Command::new("scontrol").arg("ping").output() {
        Err(e) => return Some(format!("no Slurm here (scontrol: {e})")),
        Ok(out) => String::from_utf8_lossy(&out.stdout).into_owned(),
    };
    if Command::new("sbatch").arg("--version").output().is_err() {
        return Some("no sbatch on PATH".into());
    }
    if !ping.contains("UP") {
        return Some(format!("no Slurm controller answers: {}", ping.trim()));
    }
    None
}

/// squeue's lines for `jobs`: empty once they have all left the queue.
fn queued(jobs: &str) -> String {
    let out = Command::new("squeue")
        .args(["-h", "-j", jobs, "-o", "%i %T %r"])
        .output()
        .unwrap();
    String::from_utf8_lossy(&out.stdout).trim().to_string()
}

/// Skips the calling test (true) when no Slurm answers here, unless GRIDPLAN_SLURM_TEST=1.
fn skip_without_slurm() -> bool {
    let Some(reason) = slurm_missing() else {
        return false;
    };
    assert!(
        std::env::var("GRIDPLAN_SLURM_TEST").as_deref() != Ok("1"),
        "GRIDPLAN_SLURM_TEST=1 but {reason}; start one with scripts/slurm-start.sh"
    );
    eprintln!("skipped: {reason} (scripts/slurm-start.sh starts a one-node cluster)");
    true
}

/// A submitted `slurm` sweep: its job ids and its work directory.
struct Submitted {
    array: String,
    merge: String,
    work: PathBuf,
}

impl Submitted {
    /// `xtask slurm CONFIG --shards N --output MERGED --submit` with `extra`.
    fn new(config: &str, shards: &str, merged: &Path, extra: &[&str]) -> Submitted {
        let output = merged.display().to_string();
        let mut args = vec!["slurm", config, "--shards", shards, "--output", &output];
        args.extend_from_slice(extra);
        args.push("--submit");
        let printed = xtask(&args);
        let id = |what: &str| {
            printed
                .lines()
                .find_map(|l| l.strip_prefix(what))
                .unwrap_or_else(|| panic!("no {what:?} in {printed}"))
                .trim()
                .to_string()
        };
        let mut work = merged.as_os_str().to_os_string();
        work.push("-slurm");
        Submitted {
            array: id("array job "),
            merge: id("merge job "),
            work: PathBuf::from(work),
        }
    }

    /// Every task's and the merge's log, each under its path.
    fn logs(&self) -> String {
        let mut text = String::new();
        for entry in fs::read_dir(&self.work).into_iter().flatten().flatten() {
            if entry.path().extension().is_some_and(|e| e == "log") {
                text += &format!(
                    "--- {}\n{}\n",
                    entry.path().display(),
                    fs::read_to_string(entry.path()).unwrap_or_default()
                );
            }
        }
        text
    }

    /// Cancels both jobs and fails with `what`, the queue and the logs.
    fn fail(&self, what: &str) -> ! {
        let _ = Command::new("scancel")
            .arg(&self.array)
            .arg(&self.merge)
            .status();
        let jobs = format!("{},{}", self.array, self.merge);
        panic!("{what}: {}\n{}", queued(&jobs), self.logs());
    }

    /// Waits until both jobs have left the queue (within 300 s) and the merge completed.
    fn wait_completed(&self) {
        let jobs = format!("{},{}", self.array, self.merge);
        let started = Instant::now();
        while !queued(&jobs).is_empty() {
            if started.elapsed() > Duration::from_secs(300) {
                self.fail(&format!("jobs {jobs} still queued after 300 s"));
            }
            std::thread::sleep(Duration::from_millis(250));
        }
        let show = Command::new("scontrol")
            .args(["show", "job", &self.merge])
            .output()
            .unwrap();
        let show = String::from_utf8_lossy(&show.stdout);
        assert!(
            show.contains("JobState=COMPLETED"),
            "merge job {}: {show}\n{}",
            self.merge,
            self.logs()
        );
    }
}

#[test]
fn slurm_array_and_merge_equal_a_local_run() {
    if skip_without_slurm() {
        return;
    }
    let dir = scratch("slurm");
    // The absolute config path, as the Slurm scripts name it (summary.md quotes it).
    let config = root()
        .join("configs/movingai.toml")
        .canonicalize()
        .unwrap()
        .display()
        .to_string();
    let merged = dir.join("merged");
    let submitted = Submitted::new(&config, "3", &merged, &[]);
    // The same command again while the array is queued or running: refused (exit 5),
    // naming the jobs squeue still lists; nothing is submitted.
    let output = merged.display().to_string();
    let again = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "slurm", &config, "--shards", "3", "--output", &output, "--submit",
        ])
        .current_dir(root())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&again.stderr);
    if again.status.code() != Some(5)
        || !stderr.contains(&format!("jobs {}", submitted.array))
        || !stderr.contains("of an earlier submission of this output")
    {
        submitted.fail(&format!("a second submission was not refused: {stderr}"));
    }
    let local = dir.join("local").display().to_string();
    xtask(&["experiment", &config, "--quiet", "--output", &local]);
    submitted.wait_completed();
    let records = deterministic_records(Path::new(&local));
    assert!(records.1.len() > 1000);
    assert!(records == deterministic_records(&merged), "records differ");
    assert_eq!(
        deterministic_csv(Path::new(&local)),
        deterministic_csv(&merged)
    );
    assert_eq!(
        deterministic_summary(Path::new(&local)),
        deterministic_summary(&merged)
    );
    for k in 1..=3 {
        assert!(dir
            .join(format!("merged-slurm/shard-{k}/shard.stream"))
            .exists());
    }
}

/// A task that Slurm requeues while it runs (`scontrol requeue`, as after a node failure or
/// a preemption) is stopped by SIGTERM with its finished runs recorded, and its next start
/// resumes them (the array script always passes --resume): its log, appended to, says
/// both, each start after a line naming its job and restart count, and the merge equals a
/// local run.
#[test]
fn a_requeued_slurm_task_resumes_its_runs() {
    if skip_without_slurm() {
        return;
    }
    let dir = scratch("requeue");
    // Dijkstra on every den520d scenario, 40 times: seconds per task, so that the
    // requeue comes while task 1 runs.
    let config = dir.join("requeue.toml");
    let maps = root().join("maps/movingai").canonicalize().unwrap();
    let maps = maps
        .display()
        .to_string()
        .replace('\\', "\\\\")
        .replace('"', "\\\"");
    fs::write(
        &config,
        format!(
            "name = \"requeue\"\nrepeats = 40\n\
             [[maps]]\nfiles = [\"{maps}/den520d.map\"]\nscen = \"{maps}/den520d.map.scen\"\n\
             [planners.dijkstra]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"zero\"\n"
        ),
    )
    .unwrap();
    let config = config.display().to_string();
    let merged = dir.join("merged");
    let submitted = Submitted::new(&config, "2", &merged, &["--cpus-per-task", "1"]);
    let task = format!("{}_1", submitted.array);
    let stream = submitted.work.join(".shard-1.stream/records.stream");
    let started = Instant::now();
    while recorded(&stream) < 500 {
        if started.elapsed() > Duration::from_secs(120) {
            submitted.fail("task 1 recorded no runs within 120 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let requeue = Command::new("scontrol")
        .args(["requeue", &task])
        .output()
        .unwrap();
    if !requeue.status.success() {
        submitted.fail(&format!(
            "scontrol requeue {task}: {}",
            String::from_utf8_lossy(&requeue.stderr)
        ));
    }
    // Slurm holds a requeued job back for a while (pending, reason BeginTime): a start
    // within the second the first run's credential was revoked fails ("Job credential
    // revoked", as a release at once did in CI). After two seconds it may start again.
    let started = Instant::now();
    loop {
        let state = queued(&task);
        if state.is_empty() || state.contains("RUNNING") {
            break;
        }
        if state.contains("PENDING") && started.elapsed() > Duration::from_secs(2) {
            let _ = Command::new("scontrol")
                .args(["update", &format!("JobId={task}"), "StartTime=now"])
                .output();
        }
        if started.elapsed() > Duration::from_secs(120) {
            submitted.fail(&format!("task {task} not started again within 120 s"));
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    let local = dir.join("local").display().to_string();
    xtask(&["experiment", &config, "--quiet", "--output", &local]);
    submitted.wait_completed();
    let log = fs::read_to_string(submitted.work.join("task-1.log")).unwrap();
    let stopped = log
        .lines()
        .find_map(|l| l.strip_prefix("interrupted after "))
        .and_then(|rest| rest.split(' ').next())
        .unwrap_or_else(|| submitted.fail("task 1's log says no interruption"));
    assert!(
        log.contains(&format!(
            "resuming: {stopped} of 17760 runs already recorded"
        )),
        "{log}"
    );
    assert!(stopped.parse::<u64>().unwrap() >= 500, "{log}");
    for restart in ["restart 0", "restart 1"] {
        let said = log.lines().any(|l| {
            l.starts_with("== ")
                && l.contains(" start: job ")
                && l.ends_with(&format!(", array task 1, {restart}"))
        });
        assert!(said, "no start line with {restart}: {log}");
    }
    let records = deterministic_records(Path::new(&local));
    assert_eq!(records.1.len(), 35_520);
    assert!(records == deterministic_records(&merged), "records differ");
}
