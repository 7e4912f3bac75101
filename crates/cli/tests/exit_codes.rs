//! The command line's documented exit codes (README.md): 2 usage, 3 config, 4 map or
//! problem, 5 output refused, 1 anything else; 130 (interrupted) is xtask's sweeps test's,
//! and here a sweep stopped while it waits for another run's lock.

use std::path::{Path, PathBuf};
use std::process::Stdio;

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
    // Its message says what `report` reads, not an `experiment` output's advice (it had
    // told the user to empty or remove their directory, or to use an option `report` lacks).
    assert!(err.contains("has no results marker"), "{err}");
    assert!(
        !err.contains("--output") && !err.contains("remove"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(mine.join("notes.txt")).unwrap(),
        "mine"
    );
    // A replanning experiment's results (the runner's marker, its replans.jsonl): said so.
    let replan = dir.join("replan");
    std::fs::create_dir_all(&replan).unwrap();
    std::fs::write(
        replan.join(".gridplan-results"),
        "format = 1\nexperiment = \"n\"\ngridplan = \"0.1.0\"\nfiles = [\"replans.jsonl\"]\n",
    )
    .unwrap();
    std::fs::write(replan.join("replans.jsonl"), "{}\n").unwrap();
    let (_, err) = gridplan(&["report", &replan.display().to_string()]);
    assert!(
        err.contains("holds a replanning experiment's results"),
        "{err}"
    );
    for (path, what) in [
        (dir.join("none"), "does not exist"),
        (file, "is not a directory"),
    ] {
        let (code, err) = gridplan(&["report", &path.display().to_string()]);
        assert_eq!(code, 5, "{err}");
        assert!(err.contains(what), "{err}");
    }
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

/// A picture that names one of the run's inputs (the map as given or by another path, a
/// link's target, the `.scen` beside it, a ROS map's image, the config, the weight file) is
/// a usage error (exit 2) refused before the run: writing it would replace the user's file.
#[test]
fn a_picture_over_an_input_exits_2_and_leaves_it() {
    let dir = scratch("picture-input");
    let map = dir.join("m.map");
    let text = "type octile\nheight 3\nwidth 3\nmap\n...\n.@.\n...\n";
    std::fs::write(&map, text).unwrap();
    std::fs::write(dir.join("m.map.scen"), "version 1\n").unwrap();
    std::fs::copy(
        root().join("maps/ros-nav2/TenByTen.yaml"),
        dir.join("ten.yaml"),
    )
    .unwrap();
    std::fs::copy(
        root().join("maps/ros-nav2/TenByTen.pgm"),
        dir.join("TenByTen.pgm"),
    )
    .unwrap();
    let image = std::fs::read(dir.join("TenByTen.pgm")).unwrap();
    let weights = dir.join("w.csv");
    std::fs::write(&weights, "1,1,1\n1,1,1\n1,1,1\n").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(&map, dir.join("link.map")).unwrap();
    let path = |name: &str| dir.join(name).display().to_string();
    let dotted = format!("{}/./m.map", dir.display());
    let cases: Vec<(String, &str, Vec<String>)> = vec![
        (path("m.map"), "--svg", vec![]),
        (path("m.map"), "--gif", vec![dotted.clone()]),
        (path("m.map"), "--trace", vec![path("m.map.scen")]),
        (path("ten.yaml"), "--svg", vec![path("TenByTen.pgm")]),
        (path("m.map"), "--svg", vec![path("w.csv")]),
        #[cfg(unix)]
        (path("link.map"), "--svg", vec![path("m.map")]),
    ];
    // `plan MAP` with A* from (0, 0) to `goal` and `extra`.
    let plan = |map: &str, goal: &str, extra: &[&str]| {
        let mut args = vec![
            "plan",
            map,
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            goal,
        ];
        args.extend(extra);
        gridplan(&args)
    };
    for (map_arg, option, target) in cases {
        let target = target.first().cloned().unwrap_or_else(|| map_arg.clone());
        let goal = if map_arg.ends_with("ten.yaml") {
            "1,0"
        } else {
            "2,2"
        };
        let mut extra = vec![option, target.as_str()];
        if target.ends_with("w.csv") {
            extra.extend(["--weights", &target]);
        }
        let (code, err) = plan(&map_arg, goal, &extra);
        assert_eq!(code, 2, "{map_arg} {extra:?}: {err}");
        assert!(
            err.contains("which the run reads"),
            "{map_arg} {extra:?}: {err}"
        );
    }
    assert_eq!(std::fs::read_to_string(&map).unwrap(), text);
    assert_eq!(
        std::fs::read_to_string(dir.join("m.map.scen")).unwrap(),
        "version 1\n"
    );
    assert_eq!(std::fs::read(dir.join("TenByTen.pgm")).unwrap(), image);
    assert_eq!(
        std::fs::read_to_string(&weights).unwrap(),
        "1,1,1\n1,1,1\n1,1,1\n"
    );
    // Another file is written, whole, and nothing is left beside it.
    let out = path("m.svg");
    let (code, err) = plan(&path("m.map"), "2,2", &["--svg", &out]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::read_to_string(&out).unwrap().starts_with("<svg"));
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    let mut expect = vec![
        "TenByTen.pgm",
        "m.map",
        "m.map.scen",
        "m.svg",
        "ten.yaml",
        "w.csv",
    ];
    if cfg!(unix) {
        expect.push("link.map");
        expect.sort();
    }
    assert_eq!(names, expect);
    // A read-only picture stays as it is (the bits decide, for root too).
    let mut permissions = std::fs::metadata(&out).unwrap().permissions();
    permissions.set_readonly(true);
    std::fs::set_permissions(&out, permissions).unwrap();
    let before = std::fs::read(&out).unwrap();
    let (code, err) = plan(&path("m.map"), "1,0", &["--svg", &out]);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("read-only"), "{err}");
    assert_eq!(std::fs::read(&out).unwrap(), before);
}

/// A directory of fake `sbatch` and `scontrol` for `slurm --submit`: sbatch prints job id
/// 41 for the array script and runs `merge` (a shell snippet) for the merge script's call;
/// scontrol prints a MaxArraySize of 1001. The directory, to go first on PATH.
fn fake_slurm(dir: &Path, array: &str, merge: &str) -> String {
    let bin = dir.join("bin");
    std::fs::create_dir_all(&bin).unwrap();
    let write = |name: &str, text: String| {
        let path = bin.join(name);
        std::fs::write(&path, text).unwrap();
        let mut permissions = std::fs::metadata(&path).unwrap().permissions();
        std::os::unix::fs::PermissionsExt::set_mode(&mut permissions, 0o755);
        std::fs::set_permissions(&path, permissions).unwrap();
    };
    write(
        "sbatch",
        format!("#!/bin/sh\ncase \"$*\" in\n*--dependency*) {merge} ;;\n*) {array} ;;\nesac\n"),
    );
    write(
        "scontrol",
        "#!/bin/sh\necho 'MaxArrayRecords         = 1'\necho 'MaxArraySize            = 1001'\n"
            .to_string(),
    );
    format!(
        "{}:{}",
        bin.display(),
        std::env::var("PATH").unwrap_or_default()
    )
}

#[test]
fn a_failed_submission_says_what_is_left() {
    // A space in the directory: the merge command given quotes the script's path.
    let dir = scratch("submit").join("a b");
    std::fs::create_dir_all(&dir).unwrap();
    let cfg = config(&dir, "repeats = 4");
    let output = dir.join("res").display().to_string();
    let args = [
        "slurm", &cfg, "--shards", "2", "--output", &output, "--submit",
    ];
    // The merge job refused after the array was taken: its command and the array's
    // cancellation are given.
    let path = fake_slurm(
        &dir,
        "echo 41",
        "echo 'sbatch: error: Invalid account' >&2; exit 1",
    );
    let out = common::gridplan_with(&root(), &args, &[("PATH", &path)], Stdio::piped());
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    for needle in [
        "Invalid account",
        "the array job 41 was submitted and its merge job was not",
        "sbatch --dependency=afterok:41 --kill-on-invalid-dep=yes '",
        "/a b/res-slurm/merge.sbatch'`",
        "scancel 41",
    ] {
        assert!(out.stderr.contains(needle), "{needle}: {}", out.stderr);
    }
    // An array over the cluster's MaxArraySize: the limit is given.
    let path = fake_slurm(
        &dir,
        "echo 'sbatch: error: Batch job submission failed: Invalid job array specification' >&2; exit 1",
        "echo 42",
    );
    let out = common::gridplan_with(&root(), &args, &[("PATH", &path)], Stdio::piped());
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(
        out.stderr
            .contains("this cluster's MaxArraySize is 1001, so an array has at most 1000 tasks"),
        "{}",
        out.stderr
    );
}

/// A second `slurm --submit` to an output whose array was still queued or running was
/// accepted silently: both arrays ran the whole sweep at once, and both merges. `--submit`
/// records its job ids in `DIR-slurm/jobs` now, asks `squeue` about them before it
/// submits again, and refuses with exit 5 while one is listed, submitting nothing; once
/// squeue lists none (or no longer knows them), it submits; when squeue cannot answer, it
/// warns and submits. Fake `sbatch` and `squeue` on PATH.
#[test]
fn a_second_submission_while_the_first_runs_is_refused() {
    let dir = scratch("resubmit");
    let cfg = config(&dir, "repeats = 4");
    let output = dir.join("res").display().to_string();
    let args = [
        "slurm", &cfg, "--shards", "2", "--output", &output, "--submit",
    ];
    // sbatch logs each call; squeue prints the file `queue` for the id asked, fails on an
    // id in `gone` as Slurm does for a job it no longer knows, and on any id when `down`
    // exists.
    let calls = dir.join("calls");
    let path = fake_slurm(
        &dir,
        &format!("echo array >> '{0}'; echo 55", calls.display()),
        &format!("echo merge >> '{0}'; echo 56", calls.display()),
    );
    let squeue = dir.join("bin/squeue");
    std::fs::write(
        &squeue,
        format!(
            "#!/bin/sh
cd '{}'
id=$(echo \"$*\" | sed 's/.*--jobs //')
\
             if [ -e down ]; then echo 'squeue: error: Unable to contact slurm controller' >&2; exit 1; fi\n\
             if grep -qx \"$id\" gone 2>/dev/null; then echo 'slurm_load_jobs error: Invalid job id specified' >&2; exit 1; fi\n\
             grep \"^$id\" queue 2>/dev/null; exit 0\n",
            dir.display()
        ),
    )
    .unwrap();
    let mut permissions = std::fs::metadata(&squeue).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut permissions, 0o755);
    std::fs::set_permissions(&squeue, permissions).unwrap();
    let submit = || common::gridplan_with(&root(), &args, &[("PATH", &path)], Stdio::piped());
    let sbatch_calls = || {
        std::fs::read_to_string(&calls)
            .unwrap_or_default()
            .lines()
            .count()
    };
    let out = submit();
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(
        out.stdout.contains("array job 55\nmerge job 56\n"),
        "{}",
        out.stdout
    );
    let jobs = std::fs::read_to_string(dir.join("res-slurm/jobs")).unwrap();
    assert!(jobs.ends_with("\n55\n56\n"), "{jobs}");
    assert_eq!(sbatch_calls(), 2);
    // The array still runs: refused, nothing submitted.
    std::fs::write(dir.join("queue"), "55_[1-2]\n56\n").unwrap();
    let out = submit();
    assert_eq!(out.code, Some(5), "{}", out.stderr);
    assert!(
        out.stderr
            .contains("jobs 55, 56 of an earlier submission of this output (listed in ")
            && out
                .stderr
                .contains("res-slurm/jobs) are still queued or running; scancel them or wait"),
        "{}",
        out.stderr
    );
    assert_eq!(sbatch_calls(), 2);
    // Only the merge is pending: still refused, naming it.
    std::fs::write(dir.join("queue"), "56\n").unwrap();
    let out = submit();
    assert_eq!(out.code, Some(5), "{}", out.stderr);
    assert!(
        out.stderr.contains("error: jobs 56 of an earlier"),
        "{}",
        out.stderr
    );
    // Squeue cannot answer: a warning, and it submits.
    std::fs::write(dir.join("down"), "").unwrap();
    let out = submit();
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(
        out.stderr.contains("warning: squeue --jobs 55 failed: squeue: error: Unable to contact slurm controller")
            && out.stderr.contains("whether jobs 55, 56 of an earlier submission of this output still run is unknown; submitting anyway"),
        "{}",
        out.stderr
    );
    assert_eq!(sbatch_calls(), 4);
    // The ids not known to have ended are kept with the new ones.
    let jobs = std::fs::read_to_string(dir.join("res-slurm/jobs")).unwrap();
    assert!(jobs.ends_with("\n55\n56\n55\n56\n"), "{jobs}");
    // Gone from the queue, or no longer known: it submits, and lists only its own jobs.
    std::fs::remove_file(dir.join("down")).unwrap();
    std::fs::write(dir.join("queue"), "").unwrap();
    std::fs::write(dir.join("gone"), "55\n").unwrap();
    let out = submit();
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(!out.stderr.contains("warning"), "{}", out.stderr);
    assert_eq!(sbatch_calls(), 6);
    let jobs = std::fs::read_to_string(dir.join("res-slurm/jobs")).unwrap();
    assert!(
        jobs.ends_with("submits again only when squeue lists none of them.\n55\n56\n"),
        "{jobs}"
    );
}

/// `compare` exits 0 when two results directories hold the same runs with the same
/// computed fields, 1 when they differ (after printing the comparison), and refuses a
/// directory that is not complete results (none, a shard's, a cut stream) as `report`
/// does (5).
#[test]
fn compare_exits_1_when_the_runs_differ() {
    let dir = scratch("compare");
    let path = |name: &str| dir.join(name).display().to_string();
    let run = |config: &str, out: &str| {
        let (code, err) = gridplan(&["experiment", config, "--quiet", "--output", &path(out)]);
        assert_eq!(code, 0, "{err}");
    };
    let plain = config(&dir, "");
    run(&plain, "a");
    run(&plain, "b");
    let out = common::gridplan(&root(), &["compare", &path("a"), &path("b")]);
    assert_eq!(out.code, Some(0), "{}", out.stderr);
    assert!(
        out.stdout.contains("the same in all 1 runs in both"),
        "{}",
        out.stdout
    );
    let repeated = config(&dir, "repeats = 2");
    run(&repeated, "c");
    let out = common::gridplan(&root(), &["compare", &path("a"), &path("c")]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    assert!(out.stdout.contains("only in NEW: 1"), "{}", out.stdout);
    assert!(
        out.stderr.contains("1 runs are in one directory only"),
        "{}",
        out.stderr
    );
    let out = common::gridplan(&root(), &["compare", &path("a"), &path("c"), "--json"]);
    assert_eq!(out.code, Some(1), "{}", out.stderr);
    let json: serde_json::Value = serde_json::from_str(&out.stdout).unwrap();
    assert_eq!(
        (&json["only_new"], &json["same"]),
        (&1.into(), &false.into())
    );
    let (code, err) = gridplan(&["compare", &path("a"), &dir.display().to_string()]);
    assert_eq!(code, 5, "{err}");
    // No error of compare exits 1, which means "the runs differ": a shard's directory
    // and a cut records.stream were exit 1; they are results that are not complete, exit
    // 5 as for a directory that is not results, and `report` gives the same.
    let (code, err) = gridplan(&[
        "experiment",
        &plain,
        "--quiet",
        "--shard",
        "1/2",
        "--output",
        &path("s1"),
    ]);
    assert_eq!(code, 0, "{err}");
    for command in [
        &["compare", &path("a"), &path("s1")][..],
        &["report", &path("s1")],
    ] {
        let (code, err) = gridplan(command);
        assert_eq!(code, 5, "{command:?}: {err}");
        assert!(err.contains("holds one shard of a sweep"), "{err}");
    }
    config(&dir, ""); // b's config again (c above rewrote it)
    let stream = dir.join("b/records.stream");
    let whole = std::fs::read(&stream).unwrap();
    std::fs::write(&stream, &whole[..whole.len() - 1]).unwrap();
    for command in [
        &["compare", &path("a"), &path("b")][..],
        &["report", &path("b")],
    ] {
        let (code, err) = gridplan(command);
        assert_eq!(code, 5, "{command:?}: {err}");
        assert!(err.contains("records.stream holds 0 of 1 runs"), "{err}");
    }
}

/// A picture over a device, a named pipe or a link to one (`--svg /dev/null`) is a usage
/// error (exit 2) refused before the run: a picture replaces its file whole, which put a
/// regular file in place of `/dev/null` and of the `/dev/stdout` link. (A pipe of the
/// test's own stands for them: were the check gone, this test must not replace the
/// machine's `/dev/null`.)
#[cfg(unix)]
#[test]
fn a_picture_over_a_device_or_pipe_exits_2_and_leaves_it() {
    use std::os::unix::fs::FileTypeExt as _;
    let dir = scratch("picture-device");
    let fifo = dir.join("pipe");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo");
    let to_fifo = dir.join("pipe-link");
    std::os::unix::fs::symlink(&fifo, &to_fifo).unwrap();
    for (file, option) in [(&fifo, "--svg"), (&fifo, "--trace"), (&to_fifo, "--gif")] {
        let file_arg = file.display().to_string();
        let (code, err) = gridplan(&[
            "plan",
            "maps/paper/map01.map",
            "--planner",
            "astar",
            option,
            &file_arg,
        ]);
        assert_eq!(code, 2, "{file_arg}: {err}");
        assert!(err.contains("not a file"), "{file_arg}: {err}");
    }
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
    assert!(std::fs::symlink_metadata(&to_fifo)
        .unwrap()
        .file_type()
        .is_symlink());
}

/// A trace of a planner that lists no expanded cells holds no steps, and `plan` says so
/// (the trace was silently empty beside `n_expanded 230`); a planner that lists them
/// gets no note.
#[test]
fn a_trace_without_steps_is_said() {
    let dir = scratch("trace-steps");
    for (planner, said) in [("backtracking", true), ("lpastar", true), ("bfs", false)] {
        let trace = dir.join(format!("{planner}.json")).display().to_string();
        let (code, err) = gridplan(&[
            "plan",
            "maps/paper/map10.map",
            "--planner",
            planner,
            "--start",
            "0,0",
            "--goal",
            "11,11",
            "--trace",
            &trace,
        ]);
        assert_eq!(code, 0, "{planner}: {err}");
        assert_eq!(
            err.contains("records no search steps"),
            said,
            "{planner}: {err}"
        );
    }
}

/// Coverage lists no expanded cells (not its return legs' A* either), so its trace has
/// no steps; the note fired only for a planner counting `n_expanded`, which coverage does
/// not (its returns count `n_return_expansions`), so the empty trace went unsaid. The
/// RRT family counts no `n_expanded` either.
#[test]
fn a_trace_without_steps_is_said_for_coverage_and_rrt() {
    let dir = scratch("trace-coverage");
    let trace = dir.join("coverage.json").display().to_string();
    let (code, err) = gridplan(&[
        "plan",
        "maps/coverage/rooms30-1.map",
        "--planner",
        "coverage",
        "--start",
        "0,1",
        "--trace",
        &trace,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note: coverage records no search steps"),
        "{err}"
    );
    let trace = dir.join("rrt.json").display().to_string();
    let (code, err) = gridplan(&[
        "plan",
        "maps/paper/map10.map",
        "--planner",
        "rrt",
        "--start",
        "0,0",
        "--goal",
        "11,11",
        "--trace",
        &trace,
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("note: rrt records no search steps"), "{err}");
}

/// A pipe whose reader is gone, as stderr is in `gridplan ... 2>&1 | head -1` once `head`
/// has exited: every write to it fails (EPIPE).
fn closed_pipe() -> Stdio {
    let mut reader = std::process::Command::new("true")
        .stdin(Stdio::piped())
        .spawn()
        .unwrap();
    let writer = reader.stdin.take().unwrap();
    reader.wait().unwrap();
    Stdio::from(writer)
}

/// Runs gridplan with `args` in `dir`, its stderr a closed pipe; returns its exit code.
fn gridplan_without_stderr(dir: &Path, args: &[&str]) -> i32 {
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_gridplan"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(closed_pipe())
        .spawn()
        .unwrap();
    common::finish(child, &format!("gridplan {args:?}"))
        .code
        .unwrap()
}

#[test]
fn a_closed_stderr_loses_its_lines_and_nothing_else() {
    // Before, a warning (tracing-subscriber reports its failed write with `eprintln!`) or
    // an error line panicked: status 101, and the sweep wrote no results.
    let dir = scratch("closed-stderr");
    std::fs::write(dir.join("s.map"), common::SMALL).unwrap();
    // Manhattan under eight moves can overestimate: the config warns as it is read.
    std::fs::write(
        dir.join("c.toml"),
        "name = \"w\"\n[[maps]]\nfiles = [\"s.map\"]\npairs = [{ start = [0, 0], goal = [2, 2] }]\n\
         [planners.a]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"manhattan\"\n",
    )
    .unwrap();
    let warned = common::gridplan(&dir, &["experiment", "c.toml", "--output", "seen"]);
    assert!(warned.stderr.contains("WARN"), "{}", warned.describe());
    let args = ["experiment", "c.toml", "--output", "out", "--quiet"];
    assert_eq!(gridplan_without_stderr(&dir, &args), 0);
    assert!(dir.join("out/runs.csv").is_file());
    // An error's line is lost too; its status still says what happened.
    let args = ["plan", "missing.map", "--planner", "astar"];
    assert_eq!(gridplan_without_stderr(&dir, &args), 4);
}

#[test]
fn a_replanning_experiment_in_a_job_array_is_refused() {
    // Before, a shard from the environment was ignored for navigate and dynamic configs:
    // every task of an array ran the whole experiment into the same output.
    let dir = scratch("replan-array");
    crate::common::write_navigate_config(&dir, "arena", "1", 2);
    let args = ["experiment", "nav.toml", "--output", "out"];
    let env = [
        ("SLURM_ARRAY_TASK_ID", "1"),
        ("SLURM_ARRAY_TASK_COUNT", "2"),
    ];
    let out = common::gridplan_with(&dir, &args, &env, Stdio::piped());
    common::refused(&out, 2, "navigate and dynamic configs run whole");
    assert!(!dir.join("out").exists());
    // Outside an array it runs, and says what it checked.
    let out = common::gridplan(&dir, &args);
    common::succeeded(&out);
    assert!(
        out.stdout
            .contains("replans checked against A* from scratch, 0 mismatches"),
        "{}",
        out.describe()
    );
}

/// A picture that is a link to one of the run's inputs (`ln/fig.svg -> m.map` beside
/// `ln/m.map`, the map reached through a linked directory, the `.scen` beside it) is
/// refused as the input itself is (exit 2, before the run): the link stays a link and the
/// input is intact. It exited 0 and replaced the link with the SVG.
#[cfg(unix)]
#[test]
fn a_picture_that_is_a_link_to_an_input_exits_2_and_keeps_the_link() {
    let dir = scratch("picture-link-input");
    let ln = dir.join("ln");
    std::fs::create_dir_all(&ln).unwrap();
    let map = ln.join("m.map");
    let text = "type octile\nheight 3\nwidth 3\nmap\n...\n.@.\n...\n";
    std::fs::write(&map, text).unwrap();
    std::fs::write(ln.join("m.map.scen"), "version 1\n").unwrap();
    std::os::unix::fs::symlink("ln", dir.join("via")).unwrap();
    std::os::unix::fs::symlink("m.map", ln.join("fig.svg")).unwrap();
    std::os::unix::fs::symlink("../ln/m.map", ln.join("up.gif")).unwrap();
    std::os::unix::fs::symlink("m.map.scen", ln.join("trace.json")).unwrap();
    std::os::unix::fs::symlink(&map, dir.join("abs.svg")).unwrap();
    let path = |name: &str| dir.join(name).display().to_string();
    let cases = [
        (path("ln/m.map"), "--svg", path("ln/fig.svg")),
        (path("via/m.map"), "--svg", path("ln/fig.svg")),
        (path("ln/m.map"), "--gif", path("ln/up.gif")),
        (path("ln/m.map"), "--trace", path("ln/trace.json")),
        (path("ln/m.map"), "--trace", path("via/fig.svg")),
        (path("via/m.map"), "--svg", path("abs.svg")),
    ];
    for (map_arg, option, picture) in &cases {
        let (code, err) = gridplan(&[
            "plan",
            map_arg,
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            "2,2",
            option,
            picture,
        ]);
        assert_eq!(code, 2, "{map_arg} {option} {picture}: {err}");
        assert!(
            err.contains("which the run reads"),
            "{map_arg} {option} {picture}: {err}"
        );
    }
    assert_eq!(std::fs::read_to_string(&map).unwrap(), text);
    assert_eq!(
        std::fs::read_to_string(ln.join("m.map.scen")).unwrap(),
        "version 1\n"
    );
    for link in ["ln/fig.svg", "ln/up.gif", "ln/trace.json", "abs.svg"] {
        assert!(
            std::fs::symlink_metadata(dir.join(link))
                .unwrap()
                .is_symlink(),
            "{link}"
        );
    }
    // A link to a file that is not an input, and a dangling link, are written through as
    // before (the picture replaces the link).
    std::fs::write(ln.join("old.svg"), "old").unwrap();
    std::os::unix::fs::symlink("old.svg", ln.join("other.svg")).unwrap();
    std::os::unix::fs::symlink("nowhere.svg", ln.join("dangling.svg")).unwrap();
    for picture in ["ln/other.svg", "ln/dangling.svg"] {
        let (code, err) = gridplan(&[
            "plan",
            &path("ln/m.map"),
            "--planner",
            "astar",
            "--start",
            "0,0",
            "--goal",
            "2,2",
            "--svg",
            &path(picture),
        ]);
        assert_eq!(code, 0, "{picture}: {err}");
        assert!(std::fs::read_to_string(dir.join(picture))
            .unwrap()
            .starts_with("<svg"));
    }
}

/// SIGTERM (or Ctrl-C) while a sweep waited, up to 120 s, for another run's lock on its
/// output printed "stopping: finishing the runs in progress" and kept waiting until the
/// other run ended (exit 130 only then), leaving an empty stream area beside the other's
/// results. It ends the wait at once: exit 130, saying so, with nothing created.
#[test]
fn a_sigterm_while_waiting_for_the_lock_exits_130_at_once() {
    use std::process::Command;
    use std::time::{Duration, Instant};
    let dir = scratch("sigterm-lock");
    let config = config(&dir, "");
    // Another run's lock on the output's stream area (flock(1) takes the same flock).
    let lock = dir.join(".o.stream.lock");
    std::fs::write(&lock, "").unwrap();
    let Ok(mut holder) = Command::new("flock")
        .arg(&lock)
        .args(["sleep", "60"])
        .spawn()
    else {
        eprintln!("skipped: no flock(1) to hold the lock");
        return;
    };
    std::thread::sleep(Duration::from_millis(300));
    let child = Command::new(env!("CARGO_BIN_EXE_gridplan"))
        .args(["experiment", &config, "--quiet", "--output"])
        .arg(dir.join("o"))
        .env_remove("RUST_LOG")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(800));
    let sent = Instant::now();
    let killed = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let out = common::finish(child, "the waiting sweep");
    let waited = sent.elapsed();
    let _ = holder.kill();
    let _ = holder.wait();
    assert!(
        waited < Duration::from_secs(5),
        "ended {waited:?} after SIGTERM"
    );
    assert_eq!(out.code, Some(130), "{}", out.describe());
    assert!(
        out.stderr.contains("waiting up to 120 s")
            && out
                .stderr
                .contains("stopped while waiting for another gridplan run's lock")
            && out.stderr.contains("nothing was written"),
        "{}",
        out.describe()
    );
    assert!(!dir.join(".o.stream").exists(), "a stream area was left");
    assert!(!dir.join("o").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
