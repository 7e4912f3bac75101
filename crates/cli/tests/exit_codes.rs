//! The command line's documented exit codes (README.md): 2 usage, 3 config, 4 map or
//! problem, 5 output refused, 1 anything else; 130 (interrupted) is xtask's sweeps test's.

use std::path::{Path, PathBuf};

use crate::common::{self, root};

fn scratch(name: &str) -> PathBuf {
    common::scratch("exit", name)
}

/// Runs gridplan with `args` from the repository's root; returns its exit code and stderr.
fn gridplan(args: &[&str]) -> (i32, String) {
    let out = common::gridplan(&root(), args);
    (out.code.unwrap(), out.stderr)
}

/// A config of one seed-000 map and BFS, with `extra` top-level keys.
fn config(dir: &Path, extra: &str) -> String {
    let map = root().join("maps/paper/map01.map");
    let path = dir.join("c.toml");
    std::fs::write(
        &path,
        format!(
            "name = \"c\"\n{extra}\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"bfs\"\n",
            map.display().to_string()
        ),
    )
    .unwrap();
    path.display().to_string()
}

#[test]
fn usage_errors_exit_2() {
    assert_eq!(gridplan(&[]).0, 2, "clap's own usage error");
    let (code, err) = gridplan(&["plan", "maps/paper/map01.map", "--planner", "nosuch"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("unknown planner `nosuch`"), "{err}");
    let (code, err) = gridplan(&["planners", "nosuch"]);
    assert_eq!(code, 2, "{err}");
    let dir = scratch("usage");
    let (code, err) = gridplan(&["experiment", &config(&dir, ""), "--shard", "3/2"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn config_errors_exit_3_with_their_position() {
    let dir = scratch("config");
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "name = 5\n").unwrap();
    let (code, err) = gridplan(&["experiment", &bad.display().to_string()]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("bad.toml:1:"), "{err}");
    // An unknown summary section is the report's to refuse, still a config error at its key.
    let (code, err) = gridplan(&["experiment", &config(&dir, "sections = [\"nosuch\"]")]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("c.toml:2:12: key `sections`: unknown section \"nosuch\""),
        "{err}"
    );
    let (code, err) = gridplan(&["experiment", &config(&dir, "sections = [\"seed002\"]")]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("needs `proposed`"), "{err}");
}

#[test]
fn map_and_problem_errors_exit_4() {
    let dir = scratch("map");
    let map = dir.join("bad.map");
    std::fs::write(&map, "type octile\nheight x\n").unwrap();
    let (code, err) = gridplan(&["plan", &map.display().to_string(), "--planner", "astar"]);
    assert_eq!(code, 4, "{err}");
    let (code, err) = gridplan(&[
        "plan",
        "maps/paper/map01.map",
        "--planner",
        "astar",
        "--start",
        "0,0",
        "--goal",
        "9999,9999",
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("goal"), "{err}");
}

#[test]
fn a_refused_output_exits_5_and_is_left_alone() {
    let dir = scratch("output");
    let file = dir.join("not-a-dir");
    std::fs::write(&file, "mine").unwrap();
    let (code, err) = gridplan(&[
        "experiment",
        &config(&dir, ""),
        "--quiet",
        "--output",
        &file.display().to_string(),
    ]);
    assert_eq!(code, 5, "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "mine");
    // `report` refuses a directory that is not gridplan's results the same way.
    let mine = dir.join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("notes.txt"), "mine").unwrap();
    let (code, err) = gridplan(&["report", &mine.display().to_string()]);
    assert_eq!(code, 5, "{err}");
}

/// `slurm` writes into an existing `DIR-slurm/` only when it is gridplan's (its marker) or
/// empty: a foreign one exits 5 and is left as it was; its own is written again.
#[test]
fn slurm_refuses_a_foreign_work_directory() {
    let dir = scratch("slurm-foreign");
    let cfg = config(&dir, "");
    let out = dir.join("r");
    let work = dir.join("r-slurm");
    std::fs::create_dir_all(&work).unwrap();
    std::fs::write(work.join("thesis.tex"), "mine").unwrap();
    let out_arg = out.display().to_string();
    let (code, err) = gridplan(&["slurm", &cfg, "--shards", "1", "--output", &out_arg]);
    assert_eq!(code, 5, "{err}");
    assert!(
        err.contains("r-slurm") && err.contains(".gridplan-slurm"),
        "{err}"
    );
    let names: Vec<_> = std::fs::read_dir(&work)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(
        names,
        ["thesis.tex"],
        "the foreign directory was written into"
    );
    // An empty one is claimed (its marker written), and then written again.
    std::fs::remove_file(work.join("thesis.tex")).unwrap();
    for _ in 0..2 {
        let (code, err) = gridplan(&["slurm", &cfg, "--shards", "1", "--output", &out_arg]);
        assert_eq!(code, 0, "{err}");
    }
    assert!(work.join(".gridplan-slurm").is_file());
    assert!(work.join("array.sbatch").is_file());
}

/// One file named by two of `plan`'s picture options is a usage error (typed, exit 2),
/// refused before anything is written.
#[test]
fn one_file_for_two_pictures_exits_2() {
    let dir = scratch("pictures");
    let file = dir.join("x.svg").display().to_string();
    let (code, err) = gridplan(&[
        "plan",
        "maps/paper/map01.map",
        "--planner",
        "astar",
        "--svg",
        &file,
        "--trace",
        &file,
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("given for two of --svg, --trace and --gif"),
        "{err}"
    );
    assert!(!dir.join("x.svg").exists());
}
