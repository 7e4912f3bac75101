//! Helpers shared by the runner's test files.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

/// Runs `experiment` on `threads` threads, without progress or heap measurement.
pub fn run(
    experiment: &planner_runner::Experiment,
    threads: usize,
) -> Vec<planner_runner::RunRecord> {
    let options = planner_runner::RunOptions {
        threads,
        ..Default::default()
    };
    planner_runner::run_all(experiment, &options).unwrap()
}

/// The repository root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every experiment config under `configs/`, sorted.
pub fn configs() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(root().join("configs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    paths
}

/// planner-astar's tie rule as `planner_testkit::reference_astar` takes it.
pub fn tie(rule: planner_astar::TieBreak) -> planner_testkit::Tie {
    use planner_astar::TieBreak;
    use planner_testkit::Tie;
    match rule {
        TieBreak::Fifo => Tie::Fifo,
        TieBreak::Lifo => Tie::Lifo,
        TieBreak::LowG => Tie::LowG,
        TieBreak::HighG => Tie::HighG,
    }
}

/// The settings of `planner_testkit`'s RRT references for record `r` of a planner with
/// these parameters: the seed the run recorded (the runner's, `seed + repeat`), else the
/// configured one.
pub fn rrt_settings(
    r: &planner_runner::RunRecord,
    seed: u64,
    goal_bias: f64,
    max_iterations: u64,
    steer: planner_rrt::Steer,
    step: u32,
) -> planner_testkit::RrtSettings {
    planner_testkit::RrtSettings {
        seed: r.seed.unwrap_or(seed),
        goal_bias,
        max_iterations,
        eight: steer == planner_rrt::Steer::Eight,
        step,
    }
}

/// Asserts that record `r` (of config file `path`) has a reference search's outcome: its
/// status, its path's cells, and exactly the counters `counters`, names and order.
pub fn assert_reference_run<S: AsRef<str>>(
    path: &Path,
    r: &planner_runner::RunRecord,
    status: planner_api::Status,
    cells: Option<Vec<planner_api::Cell>>,
    counters: impl IntoIterator<Item = (S, u64)>,
) {
    let what = format!(
        "{} {} #{} {} seed {:?}",
        path.display(),
        r.map,
        r.problem,
        r.planner,
        r.seed
    );
    assert_eq!(r.status.as_str(), status.as_str(), "{what}");
    let actual: Vec<(&str, u64)> = r.counters.iter().collect();
    let expected: Vec<(String, u64)> = counters
        .into_iter()
        .map(|(name, value)| (name.as_ref().to_string(), value))
        .collect();
    let expected: Vec<(&str, u64)> = expected.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    assert_eq!(actual, expected, "{what}");
    assert_eq!(r.path.as_ref().map(|p| p.cells().to_vec()), cells, "{what}");
}

/// Calls `check(config file, map, planner parameters, record)` for every run of the
/// registry planner `algorithm` in every config, trimmed by its `[test]` limits as the
/// snapshots are, except invalid problems (they never reach the planner). Returns how
/// many runs it checked.
pub fn for_each_snapshotted_run(
    algorithm: &str,
    mut check: impl FnMut(
        &Path,
        &planner_runner::config::MapEntry,
        &toml::Table,
        &planner_runner::RunRecord,
    ),
) -> usize {
    let mut n_checked = 0;
    for path in configs() {
        let mut experiment = planner_runner::config::load(&path)
            .unwrap()
            .trimmed_for_test();
        // Only `algorithm`'s planners run: a run's record does not depend on the other
        // planners of its config (its seed is the experiment's and the repeat's).
        experiment.planners.retain(|p| p.name == algorithm);
        if experiment.planners.is_empty() {
            continue;
        }
        let records = run(&experiment, 2);
        let runs = records
            .iter()
            .filter(|r| r.algorithm == algorithm && !r.is_invalid());
        for record in runs {
            let spec = experiment
                .planners
                .iter()
                .find(|p| p.label == record.planner);
            let map = experiment.maps.iter().find(|m| m.name == record.map);
            check(&path, map.unwrap(), &spec.unwrap().params, record);
            n_checked += 1;
        }
    }
    n_checked
}

/// Gives the child `command` starts the default SIGINT disposition, whatever this test
/// inherited: a parent that ran `trap '' INT` (nohup-style launchers, some CI runners)
/// leaves SIGINT ignored, the child would inherit that and, by gridplan's rule (README),
/// keep ignoring it, so a test that stops a sweep with SIGINT would wait for nothing.
#[cfg(unix)]
#[allow(unsafe_code)]
pub fn default_sigint(command: &mut std::process::Command) -> &mut std::process::Command {
    use std::os::unix::process::CommandExt as _;
    // SAFETY: signal(2) is async-signal-safe, as code between fork and exec must be.
    unsafe {
        command.pre_exec(|| {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        })
    }
}
