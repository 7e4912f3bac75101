//! A sweep of more than `sweep::HELD_RUNS` runs (issue 29): its records are not held but
//! read back from its stream on disk, its merge streams through a framed file, and both
//! equal a sweep's tables row for row; its report gets the records in passes.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use planner_runner::config::ConfigError;
use planner_runner::output::OutputFile;
use planner_runner::record::Reproduction;
use planner_runner::shard::Shard;
use planner_runner::sweep::{self, Render, Results, SweepArgs, HELD_RUNS, RESULTS_RECORDS};
use planner_runner::{Experiment, RunnerError};

/// A report step that checks what a report of a large sweep gets: no held records, and
/// passes that visit every run in run order.
#[derive(Default)]
struct Checked {
    passes_seen: AtomicU64,
}

impl Render for Checked {
    fn check(&self, _: &Experiment) -> Result<(), ConfigError> {
        Ok(())
    }

    fn render(
        &self,
        results: &Results<'_>,
    ) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        assert!(
            results.records.is_empty(),
            "a large sweep's records are not held"
        );
        let mut n = 0u64;
        let mut last = None;
        results.passes.pass(&mut |r| {
            let key = (r.problem, r.planner.clone(), r.repeat);
            if let Some(last) = &last {
                // Run order: problem, label, repeat (one map).
                assert!(*last < key, "{last:?} then {key:?}");
            }
            last = Some(key);
            n += 1;
        })?;
        assert_eq!(n, results.passes.len());
        self.passes_seen.store(n, Ordering::Relaxed);
        Ok((Vec::new(), Reproduction::default()))
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-large-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Two labels on two tiny problems: `HELD_RUNS + 4` runs, cheap ones, runs.csv and
/// runs.parquet asked for.
fn config(dir: &Path) -> PathBuf {
    config_with(dir, "outputs = [\"csv\", \"parquet\"]\n")
}

/// [`config`] with `outputs` (a line of top-level keys) instead.
fn config_with(dir: &Path, outputs: &str) -> PathBuf {
    std::fs::write(
        dir.join("tiny.map"),
        "type octile\nheight 2\nwidth 4\nmap\n....\n.@..\n",
    )
    .unwrap();
    let repeats = (HELD_RUNS + 4) / 4;
    let text = format!(
        "name = \"large\"\nrepeats = {repeats}\nfigures = \"none\"\npaths = \"none\"\n{outputs}\
         [[maps]]\nfiles = [\"tiny.map\"]\npairs = [{{ start = [0, 0], goal = [3, 1] }}, {{ start = [0, 1], goal = [3, 0] }}]\n\
         [planners.astar]\nplanner = \"astar\"\nmoves = 8\n\
         [planners.bfs]\nplanner = \"bfs\"\n"
    );
    let path = dir.join("large.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// runs.csv's rows without the measured columns (time_ms, setup_ms, peak_heap_bytes).
fn deterministic(dir: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join("runs.csv")).unwrap();
    text.lines()
        .map(|line| {
            line.split(',')
                .enumerate()
                .filter(|(i, _)| !(17..=19).contains(i))
                .map(|(_, c)| c)
                .collect::<Vec<_>>()
                .join(",")
        })
        .collect()
}

#[test]
fn a_large_sweep_and_its_merged_shards_equal_row_for_row() {
    let dir = scratch("merge");
    let config = config(&dir);
    let render = Checked::default();
    let one = dir.join("one");
    let mut args = SweepArgs::new(&config, &render);
    args.output = Some(&one);
    args.threads = 2;
    args.keep_records = true;
    let report = sweep::experiment(&args).unwrap();
    let n = HELD_RUNS + 4;
    assert_eq!(report.n_runs as u64, n);
    assert_eq!(report.left_out, None, "runs.csv was asked for by name");
    assert!(
        report.records.is_empty(),
        "records beyond HELD_RUNS are not returned"
    );
    assert_eq!(render.passes_seen.load(Ordering::Relaxed), n);
    assert!(one.join(RESULTS_RECORDS).is_file());
    // The stream area is gone once the results are written.
    assert!(!dir.join(".one.stream").exists());

    let mut shards = Vec::new();
    for k in 1..=2 {
        let out = dir.join(format!("s{k}"));
        let mut args = SweepArgs::new(&config, &render);
        args.output = Some(&out);
        args.threads = 2;
        args.shard = Some(Shard::new(k, 2).unwrap());
        sweep::experiment(&args).unwrap();
        shards.push(out);
    }
    let merged = dir.join("merged");
    let render = Checked::default();
    sweep::merge(&shards, Some(&merged), None, &render, &|_| {
        planner_runner::provenance::Machine::default()
    })
    .unwrap();
    assert_eq!(render.passes_seen.load(Ordering::Relaxed), n);
    // The merged stream and its area are removed.
    assert!(!dir.join(".merged.stream").exists());
    let (a, b) = (deterministic(&one), deterministic(&merged));
    assert_eq!(a.len() as u64, n + 1);
    assert!(a == b, "merged shards differ from one run");

    // `report` re-renders from records.stream in passes, and the tables stay.
    let render = Checked::default();
    sweep::report(&merged, None, &render).unwrap();
    assert_eq!(render.passes_seen.load(Ordering::Relaxed), n);
    assert_eq!(deterministic(&merged), a);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sweep's held records were bounded by their number only (`HELD_RUNS`), not their size:
/// a planner that marks every jump point (34 KB a run) held 415 MB for 12,120 runs. Past
/// its byte cap (`held_bytes`, lowered here to a few records' worth) a sweep of few runs
/// lets go of its records and writes its outputs from its stream, as a large one does (its
/// report gets no held records, the passes every run), with the same tables as a sweep
/// that holds them; a resumed one reading back its recorded runs (here, its finished
/// results) too.
#[test]
fn a_sweep_past_its_byte_cap_holds_no_records() {
    let dir = scratch("bytes");
    std::fs::write(
        dir.join("tiny.map"),
        "type octile\nheight 2\nwidth 4\nmap\n....\n.@..\n",
    )
    .unwrap();
    let text = "name = \"bytes\"\nrepeats = 20\nfigures = \"none\"\n\
         [[maps]]\nfiles = [\"tiny.map\"]\npairs = [{ start = [0, 0], goal = [3, 1] }, { start = [0, 1], goal = [3, 0] }]\n\
         [planners.astar]\nplanner = \"astar\"\nmoves = 8\n[planners.bfs]\nplanner = \"bfs\"\n";
    let config = dir.join("bytes.toml");
    std::fs::write(&config, text).unwrap();
    let held = dir.join("held");
    let plain = SweepArgs::new(&config, &crate::common::NoReport);
    let mut args = plain;
    args.output = Some(&held);
    args.keep_records = true;
    let report = sweep::experiment(&args).unwrap();
    assert_eq!(report.records.len(), 80);
    let render = Checked::default();
    for resume in [false, true] {
        let capped = dir.join(format!("capped-{resume}"));
        if resume {
            // Finished results, which --resume reads back as recorded runs.
            let mut args = SweepArgs::new(&config, &crate::common::NoReport);
            args.output = Some(&capped);
            sweep::experiment(&args).unwrap();
        }
        let mut args = SweepArgs::new(&config, &render);
        args.output = Some(&capped);
        args.keep_records = true;
        args.resume = resume;
        args.held_bytes = 8 * sweep::record_bytes(&report.records[0]);
        let capped_report = sweep::experiment(&args).unwrap();
        assert!(capped_report.records.is_empty(), "the records were held");
        assert_eq!(render.passes_seen.load(Ordering::Relaxed), 80);
        assert!(
            deterministic(&capped) == deterministic(&held),
            "resume {resume}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A large sweep without `outputs` writes runs.parquet alone and says so in its report
/// (which the command line prints), as its summary.md does.
#[test]
fn a_large_sweep_says_which_tables_it_left_out() {
    let dir = scratch("left-out");
    let config = config_with(&dir, "");
    let render = Checked::default();
    let out = dir.join("out");
    let mut args = SweepArgs::new(&config, &render);
    args.output = Some(&out);
    args.threads = 2;
    let report = sweep::experiment(&args).unwrap();
    let left_out = report.left_out.expect("the tables left out are said");
    assert!(
        left_out.starts_with("runs.csv and runs.json are not written"),
        "{left_out}"
    );
    assert!(!out.join("runs.csv").exists() && !out.join("runs.json").exists());
    assert!(out.join("runs.parquet").is_dir());
    std::fs::remove_dir_all(&dir).unwrap();
}
