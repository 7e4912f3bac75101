//! The results directory through the real `cargo xtask experiment` binary: a directory that
//! is not gridplan's survives byte for byte, files, links, read-only directories and foreign
//! leftovers are refused and leave nothing behind, concurrent runs end with one complete
//! result, a killed run leaves the old results or the new ones, and a crash's leftovers and
//! stale locks never stop the next run (src/outdir.rs documents the rules).

use crate::common;

use std::collections::BTreeMap;
use std::fs;
use std::io::{BufRead as _, BufReader};
use std::os::unix::fs::{symlink, PermissionsExt as _};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::Duration;

use common::root;
use planner_runner::outdir::{self, Marker, OutdirError, OutputFile, MARKER};

/// A fresh empty directory for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-output-{name}"));
    if dir.exists() {
        make_writable(&dir);
        fs::remove_dir_all(&dir).unwrap();
    }
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn make_writable(dir: &Path) {
    if let Ok(metadata) = fs::symlink_metadata(dir) {
        if metadata.is_dir() {
            fs::set_permissions(dir, fs::Permissions::from_mode(0o755)).unwrap();
            for entry in fs::read_dir(dir).unwrap() {
                make_writable(&entry.unwrap().path());
            }
        }
    }
}

/// A small config (map01's corner problems, A*) in its own directory, outside any output.
fn small_config() -> &'static Path {
    static CONFIG: OnceLock<PathBuf> = OnceLock::new();
    CONFIG.get_or_init(|| {
        let dir = scratch("config");
        let config = dir.join("small.toml");
        let map = root().join("maps/paper/map01.map");
        fs::write(
            &config,
            format!(
                "name = \"small\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n\
                 [planners.a]\nplanner = \"astar\"\n",
                map.display().to_string()
            ),
        )
        .unwrap();
        config
    })
}

/// The paper's config: 60 runs and 180 figures, so a write takes a while.
fn paper_config() -> PathBuf {
    root().join("configs/paper.toml")
}

fn command(config: &Path, output: &Path) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_xtask"));
    // The killed-run test stops it with SIGINT too, also when run with SIGINT ignored.
    common::default_sigint(&mut command)
        .arg("experiment")
        .arg(config)
        .arg("--output")
        .arg(output)
        .arg("--quiet")
        .arg("--threads")
        .arg("1")
        .current_dir(root())
        .env_remove("RUST_LOG");
    command
}

fn experiment(config: &Path, output: &Path) -> Output {
    command(config, output).output().unwrap()
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// What a path holds, links not followed: the kind, permission bits and contents.
#[derive(Debug, PartialEq)]
enum Entry {
    Dir(u32),
    File(u32, Vec<u8>),
    Link(PathBuf),
}

/// Everything under `dir`, by path relative to it.
fn tree(dir: &Path) -> BTreeMap<PathBuf, Entry> {
    fn walk(base: &Path, dir: &Path, out: &mut BTreeMap<PathBuf, Entry>) {
        for entry in fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            let relative = path.strip_prefix(base).unwrap().to_path_buf();
            let metadata = fs::symlink_metadata(&path).unwrap();
            let mode = metadata.permissions().mode();
            if metadata.file_type().is_symlink() {
                out.insert(relative, Entry::Link(fs::read_link(&path).unwrap()));
            } else if metadata.is_dir() {
                out.insert(relative, Entry::Dir(mode));
                walk(base, &path, out);
            } else {
                out.insert(relative, Entry::File(mode, fs::read(&path).unwrap()));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// The names of a directory's entries, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// The relative paths of the files a solo run of `config` writes.
fn result_files(config: &Path) -> Vec<PathBuf> {
    let name = config.file_stem().unwrap().to_string_lossy().into_owned();
    let out = scratch(&format!("reference-{name}")).join("results");
    let run = experiment(config, &out);
    assert!(run.status.success(), "{}", stderr(&run));
    let files: Vec<PathBuf> = tree(&out)
        .into_iter()
        .filter(|(_, entry)| matches!(entry, Entry::File(..)))
        .map(|(path, _)| path)
        .collect();
    fs::remove_dir_all(out.parent().unwrap()).unwrap();
    files
}

fn small_files() -> &'static [PathBuf] {
    static FILES: OnceLock<Vec<PathBuf>> = OnceLock::new();
    FILES.get_or_init(|| result_files(small_config()))
}

/// Asserts that `dir` holds exactly one complete result of `experiment`: the marker, the
/// files in `expected`, and a runs.json with as many runs as runs.csv has rows.
fn assert_complete(dir: &Path, experiment: &str, expected: &[PathBuf]) {
    let marker = Marker::read(dir).unwrap();
    let files: Vec<PathBuf> = tree(dir)
        .into_iter()
        .filter(|(_, entry)| matches!(entry, Entry::File(..)))
        .map(|(path, _)| path)
        .collect();
    assert_eq!(files, expected, "{}", dir.display());
    // The marker lists exactly the other files.
    let listed: Vec<&Path> = files
        .iter()
        .map(PathBuf::as_path)
        .filter(|path| *path != Path::new(MARKER))
        .collect();
    assert_eq!(marker, Marker::listing(experiment, &listed));
    let json: serde_json::Value =
        serde_json::from_slice(&fs::read(dir.join("runs.json")).unwrap()).unwrap();
    let n_rows = fs::read_to_string(dir.join("runs.csv"))
        .unwrap()
        .lines()
        .count();
    assert_eq!(json["runs"]["data"].as_array().unwrap().len() + 1, n_rows);
    assert!(n_rows > 1);
}

/// Runs the small experiment into the `--output` that `setup` makes in a fresh directory:
/// it must fail with an error containing `expect` and leave the whole directory byte for
/// byte as it was. After `fix` (what a user would do), the same output must then be
/// written, completely, with nothing left beside it.
fn check(name: &str, setup: impl FnOnce(&Path) -> PathBuf, expect: &str, fix: impl FnOnce(&Path)) {
    let dir = scratch(name);
    let output = setup(&dir);
    let before = tree(&dir);
    let run = experiment(small_config(), &output);
    assert!(!run.status.success(), "{name}: the run succeeded");
    let message = stderr(&run);
    assert!(message.contains(expect), "{name}: {message}");
    assert!(
        message.contains(&output.display().to_string()),
        "{name}: the error names no output: {message}"
    );
    assert_eq!(tree(&dir), before, "{name}: the run touched something");
    fix(&dir);
    let rerun = experiment(small_config(), &output);
    assert!(rerun.status.success(), "{name}: {}", stderr(&rerun));
    assert_complete(&output, "small", small_files());
    let leftovers: Vec<String> = names(&dir)
        .into_iter()
        .filter(|n| n.ends_with(".lock") || n.ends_with(".partial") || n.ends_with(".previous"))
        .collect();
    assert!(leftovers.is_empty(), "{name}: leftovers {leftovers:?}");
    fs::remove_dir_all(&dir).unwrap();
}

fn write(path: &Path, text: &str) {
    fs::create_dir_all(path.parent().unwrap()).unwrap();
    fs::write(path, text).unwrap();
}

/// A user's directory: a thesis and its chapters.
fn thesis(dir: &Path) {
    write(&dir.join("thesis.tex"), "\\documentclass{book}\n");
    write(&dir.join("chapters/intro.tex"), "\\chapter{Intro}\n");
    write(&dir.join(".hidden"), "mine\n");
}

fn empty_dir(dir: &Path) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            fs::remove_dir_all(path).unwrap();
        } else {
            fs::remove_file(path).unwrap();
        }
    }
}

#[test]
fn an_unrelated_directory_survives_byte_for_byte() {
    check(
        "unrelated",
        |dir| {
            thesis(&dir.join("mydata"));
            dir.join("mydata")
        },
        "is not a gridplan results directory: it holds 3 entries (.hidden, chapters, thesis.tex) and no `.gridplan-results` marker",
        |dir| empty_dir(&dir.join("mydata")),
    );
}

/// The user's additions inside gridplan's own results: a note at the top and a file in
/// its figures.
#[test]
fn files_added_to_results_are_not_replaced() {
    for (name, added) in [
        ("notes.txt", "notes.txt"),
        ("figures/mine.svg", "figures/mine.svg"),
    ] {
        check(
            &format!("added-{}", name.replace('/', "-")),
            |dir| {
                let output = dir.join("results");
                let run = experiment(small_config(), &output);
                assert!(run.status.success(), "{}", stderr(&run));
                write(&output.join(added), "mine\n");
                output
            },
            &format!("holds what gridplan did not write there ({added})"),
            |dir| fs::remove_file(dir.join("results").join(added)).unwrap(),
        );
    }
    // A directory of the user's is named once, with its slash.
    check(
        "added-dir",
        |dir| {
            let output = dir.join("results");
            let run = experiment(small_config(), &output);
            assert!(run.status.success(), "{}", stderr(&run));
            thesis(&output.join("mine"));
            output
        },
        "holds what gridplan did not write there (mine/)",
        |dir| fs::remove_dir_all(dir.join("results/mine")).unwrap(),
    );
}

#[test]
fn a_file_is_refused_and_kept() {
    check(
        "file",
        |dir| {
            write(&dir.join("results"), "my notes\n");
            dir.join("results")
        },
        "is a file, not a directory",
        |dir| fs::remove_file(dir.join("results")).unwrap(),
    );
}

#[test]
fn a_parent_that_is_a_file_is_refused_and_kept() {
    check(
        "parent-file",
        |dir| {
            write(&dir.join("notes"), "mine\n");
            dir.join("notes/results")
        },
        "Not a directory",
        |dir| fs::remove_file(dir.join("notes")).unwrap(),
    );
}

#[test]
fn a_link_to_an_unrelated_directory_is_refused_and_its_target_kept() {
    check(
        "link-unrelated",
        |dir| {
            thesis(&dir.join("mydata"));
            symlink(dir.join("mydata"), dir.join("results")).unwrap();
            dir.join("results")
        },
        "is not a gridplan results directory",
        |dir| empty_dir(&dir.join("mydata")),
    );
}

#[test]
fn a_dangling_link_is_refused() {
    check(
        "link-dangling",
        |dir| {
            symlink(dir.join("elsewhere"), dir.join("results")).unwrap();
            dir.join("results")
        },
        "is a symbolic link to",
        |dir| fs::create_dir(dir.join("elsewhere")).unwrap(),
    );
}

#[test]
fn a_link_to_a_file_is_refused() {
    check(
        "link-file",
        |dir| {
            write(&dir.join("notes.txt"), "mine\n");
            symlink(dir.join("notes.txt"), dir.join("results")).unwrap();
            dir.join("results")
        },
        "is a symbolic link to a file, not a directory",
        |dir| fs::remove_file(dir.join("results")).unwrap(),
    );
}

#[test]
fn a_read_only_results_directory_is_refused_untouched() {
    let previous_results = |dir: &Path| {
        let output = dir.join("results");
        let run = experiment(small_config(), &output);
        assert!(run.status.success(), "{}", stderr(&run));
        output
    };
    check(
        "read-only",
        |dir| {
            let output = previous_results(dir);
            fs::set_permissions(&output, fs::Permissions::from_mode(0o555)).unwrap();
            output
        },
        "is read-only",
        |dir| make_writable(&dir.join("results")),
    );
    check(
        "read-only-inside",
        |dir| {
            let output = previous_results(dir);
            let figures = output.join("figures");
            fs::set_permissions(figures, fs::Permissions::from_mode(0o500)).unwrap();
            output
        },
        "figures` has no write permission",
        |dir| make_writable(&dir.join("results")),
    );
}

#[test]
fn a_leftover_that_is_not_gridplans_is_refused_and_kept() {
    // What today's main leaves after `--output` named a file: the user's file moved aside.
    check(
        "foreign-previous",
        |dir| {
            write(&dir.join(".results.previous"), "my notes\n");
            dir.join("results")
        },
        ".results.previous` is in the way of writing",
        |dir| fs::remove_file(dir.join(".results.previous")).unwrap(),
    );
    check(
        "foreign-partial",
        |dir| {
            thesis(&dir.join(".results.partial"));
            dir.join("results")
        },
        ".results.partial` is in the way of writing",
        |dir| fs::remove_dir_all(dir.join(".results.partial")).unwrap(),
    );
}

#[test]
fn empty_marked_linked_and_missing_directories_are_written() {
    let dir = scratch("written");
    // Empty.
    fs::create_dir(dir.join("empty")).unwrap();
    // Marked: a former result, rewritten, with a file an older run wrote and listed.
    let marked = dir.join("marked");
    assert!(experiment(small_config(), &marked).status.success());
    fs::write(marked.join("stale.txt"), "from an older run").unwrap();
    let listing = fs::read_to_string(marked.join(MARKER)).unwrap();
    assert!(listing.ends_with(",\n]\n"), "{listing}");
    let listing = format!("{}\n    \"stale.txt\",\n]\n", &listing[..listing.len() - 3]);
    fs::write(marked.join(MARKER), listing).unwrap();
    // Marked by a gridplan from before the listing: replaced whole, as then.
    let legacy = dir.join("legacy");
    assert!(experiment(small_config(), &legacy).status.success());
    fs::write(legacy.join("stale.txt"), "from an older run").unwrap();
    fs::write(
        legacy.join(MARKER),
        "format = 1\nexperiment = \"small\"\ngridplan = \"0.1.0\"\n",
    )
    .unwrap();
    // A link to an empty directory: written through, the link kept.
    fs::create_dir(dir.join("target")).unwrap();
    symlink(dir.join("target"), dir.join("link")).unwrap();
    // Missing parents are created.
    let nested = dir.join("a/b/results");
    for output in [dir.join("empty"), marked, legacy, dir.join("link"), nested] {
        let run = experiment(small_config(), &output);
        assert!(
            run.status.success(),
            "{}: {}",
            output.display(),
            stderr(&run)
        );
        assert_complete(&output, "small", small_files());
    }
    assert!(fs::symlink_metadata(dir.join("link"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert_complete(&dir.join("target"), "small", small_files());
    // Writing through the link again works: its target now carries the marker.
    assert!(experiment(small_config(), &dir.join("link"))
        .status
        .success());
    assert_eq!(
        names(&dir),
        ["a", "empty", "legacy", "link", "marked", "target"]
    );
    assert_eq!(names(&dir.join("a/b")), ["results"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn concurrent_runs_end_with_one_complete_result() {
    let config = paper_config();
    let expected = result_files(&config);
    let dir = scratch("concurrent");
    let output = dir.join("results");
    for round in 0..2 {
        let children: Vec<Child> = (0..3)
            .map(|_| {
                command(&config, &output)
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        for child in children {
            let run = child.wait_with_output().unwrap();
            assert!(run.status.success(), "round {round}: {}", stderr(&run));
        }
        assert_complete(&output, "paper", &expected);
        assert_eq!(names(&dir), ["results"], "round {round}");
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// Holds the lock on `output` as another run would: an OS lock on `.<name>.lock`.
fn hold_lock(output: &Path, pid: &str) -> fs::File {
    let lock = output.parent().unwrap().join(format!(
        ".{}.lock",
        output.file_name().unwrap().to_string_lossy()
    ));
    fs::write(&lock, pid).unwrap();
    let file = fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&lock)
        .unwrap();
    fs4::FileExt::lock(&file).unwrap();
    file
}

#[test]
fn a_second_run_waits_for_the_lock_with_a_message() {
    let dir = scratch("waits");
    let output = dir.join("results");
    let lock = hold_lock(&output, "4242\n");
    let mut child = command(small_config(), &output)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut lines = BufReader::new(child.stderr.take().unwrap()).lines();
    let waiting = lines.next().unwrap().unwrap();
    assert!(
        waiting
            .contains("is being written by another gridplan run (pid 4242); waiting up to 120 s"),
        "{waiting}"
    );
    assert!(!output.exists(), "written while the lock was held");
    fs4::FileExt::unlock(&lock).unwrap();
    drop(lock);
    let rest: Vec<String> = lines.map(Result::unwrap).collect();
    assert!(child.wait().unwrap().success(), "{rest:?}");
    assert_complete(&output, "small", small_files());
    assert_eq!(names(&dir), ["results"]);
    fs::remove_dir_all(&dir).unwrap();
}

fn small_result() -> Vec<OutputFile> {
    vec![
        OutputFile {
            path: "runs.json".into(),
            contents: b"{}\n".to_vec(),
        },
        OutputFile {
            path: "figures/one.svg".into(),
            contents: b"<svg/>\n".to_vec(),
        },
    ]
}

#[test]
fn a_lock_held_too_long_is_a_clear_error_and_nothing_is_written() {
    let dir = scratch("locked");
    let output = dir.join("results");
    let _lock = hold_lock(&output, "4242\n");
    let error = outdir::write_results(&output, "t", &small_result(), Duration::from_millis(200))
        .unwrap_err();
    assert!(matches!(error, OutdirError::Locked { .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("another gridplan run (pid 4242)"),
        "{message}"
    );
    assert!(message.contains(".results.lock"), "{message}");
    assert_eq!(names(&dir), [".results.lock"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_stale_lock_and_a_crashs_leftovers_never_stop_the_next_run() {
    let dir = scratch("leftovers");
    let output = dir.join("results");
    let marked = |path: &Path, extra: &str| {
        write(&path.join(MARKER), "format = 1\n");
        write(&path.join(extra), "half written");
    };
    // A dead run's lock file (no process holds its OS lock), a half-written partial, a
    // previous left between the two renames with the output absent.
    write(&dir.join(".results.lock"), "999999999\n");
    marked(&dir.join(".results.partial"), "figures/half.svg");
    marked(&dir.join(".results.previous"), "runs.json");
    let run = experiment(small_config(), &output);
    assert!(run.status.success(), "{}", stderr(&run));
    assert_complete(&output, "small", small_files());
    assert_eq!(names(&dir), ["results"]);
    // The same beside existing results, with an empty partial (a kill right after mkdir).
    fs::create_dir(dir.join(".results.partial")).unwrap();
    marked(&dir.join(".results.previous"), "runs.csv");
    let run = experiment(small_config(), &output);
    assert!(run.status.success(), "{}", stderr(&run));
    assert_complete(&output, "small", small_files());
    assert_eq!(names(&dir), ["results"]);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_killed_run_leaves_the_old_results_or_the_new_ones() {
    let config = paper_config();
    let expected = result_files(&config);
    let dir = scratch("killed");
    let output = dir.join("results");
    let started = std::time::Instant::now();
    let first = experiment(&config, &output);
    let mut run_time = started.elapsed();
    assert!(first.status.success(), "{}", stderr(&first));
    // Kills spread from mid-sweep to past the end, where the writing is, as a share of the
    // last whole run's time (the machine's load varies).
    let n_rounds = 12;
    let signals = ["KILL", "TERM", "INT"];
    let mut seen = BTreeMap::new();
    for round in 0..n_rounds {
        let signal = signals[round % signals.len()];
        let old = fs::read(output.join("runs.json")).unwrap();
        let delay = run_time.mul_f64(0.5 + 0.7 * round as f64 / n_rounds as f64);
        let mut child = command(&config, &output)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(delay);
        let killed = Command::new("kill")
            .arg(format!("-{signal}"))
            .arg(child.id().to_string())
            .status()
            .unwrap();
        assert!(killed.success());
        child.wait().unwrap();
        // Old or new, complete either way.
        assert_complete(&output, "paper", &expected);
        let which = if fs::read(output.join("runs.json")).unwrap() == old {
            "old"
        } else {
            "new"
        };
        let left: Vec<String> = names(&dir).into_iter().filter(|n| n != "results").collect();
        println!("round {round} (SIG{signal} after {delay:?}): {which} results, left {left:?}");
        *seen.entry(which).or_insert(0) += 1;
        // The next run is never stopped by what the killed one left.
        let started = std::time::Instant::now();
        let next = experiment(&config, &output);
        run_time = started.elapsed();
        assert!(next.status.success(), "round {round}: {}", stderr(&next));
        assert_complete(&output, "paper", &expected);
        assert_eq!(names(&dir), ["results"], "round {round}");
    }
    println!("{seen:?}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_result_paths_are_refused() {
    let dir = scratch("bad-paths");
    for path in ["../escape.txt", "/abs.txt", MARKER, ""] {
        let files = vec![OutputFile {
            path: path.into(),
            contents: Vec::new(),
        }];
        let error =
            outdir::write_results(&dir.join("results"), "t", &files, Duration::ZERO).unwrap_err();
        assert!(
            matches!(error, OutdirError::BadFile { .. }),
            "{path}: {error:?}"
        );
    }
    assert!(names(&dir).is_empty());
    fs::remove_dir_all(&dir).unwrap();
}
