//! Where a sweep's output cannot be written, or its stream cannot be kept: each refusal or
//! failure says what it is and what to do, and keeps what the user has (their files, the
//! recorded runs). Cases that need a mount (a bind mount, a small tmpfs) run as root only,
//! and say so when skipped.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use planner_runner::config::{ConfigError, Experiment};
use planner_runner::outdir::OutdirError;
use planner_runner::output::OutputFile;
use planner_runner::readback::ResumeError;
use planner_runner::record::Reproduction;
use planner_runner::sweep::{self, experiment, Progress, Render, Results, SweepArgs};
use planner_runner::{ErrorClass, RunnerError};

use crate::common::{scratch, NoReport};

/// A 6x6 map, free but for `wall` (a cell index, if any).
fn map_text(wall: Option<usize>) -> String {
    let mut cells = [b'.'; 36];
    if let Some(wall) = wall {
        cells[wall] = b'@';
    }
    let rows: Vec<String> = cells
        .chunks(6)
        .map(|row| String::from_utf8_lossy(row).into_owned())
        .collect();
    format!("type octile\nheight 6\nwidth 6\nmap\n{}\n", rows.join("\n"))
}

/// `dir/w.toml`: the maps `dir/maps/*.map` (`a.map` written), corners, A* and BFS,
/// `repeats` repeats.
fn config(dir: &Path, repeats: u32) -> PathBuf {
    std::fs::create_dir_all(dir.join("maps")).unwrap();
    std::fs::write(dir.join("maps/a.map"), map_text(None)).unwrap();
    let text = format!(
        "name = \"w\"\nrepeats = {repeats}\nfigures = \"none\"\n[[maps]]\nfiles = [\"maps/*.map\"]\n\
         problems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n"
    );
    let path = dir.join("w.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn args<'a>(config: &'a Path, output: &'a Path, render: &'a dyn Render) -> SweepArgs<'a> {
    SweepArgs {
        output: Some(output),
        threads: 2,
        ..SweepArgs::new(config, render)
    }
}

/// Whether this test process may mount (root); else says that `test` is skipped.
fn may_mount(test: &str) -> bool {
    // /proc/self belongs to the process's effective user.
    let root = std::os::unix::fs::MetadataExt::uid(&std::fs::metadata("/proc/self").unwrap()) == 0;
    if !root {
        eprintln!("{test}: skipped, it mounts and needs root");
    }
    root
}

/// Runs `mount args`; whether it worked (a container may forbid it: then skipped, said).
fn mount(args: &[&str], test: &str) -> bool {
    let ok = Command::new("mount")
        .args(args)
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("{test}: skipped, mount {args:?} failed");
    }
    ok
}

fn umount(path: &Path) {
    let status = Command::new("umount").arg(path).status().unwrap();
    assert!(status.success(), "umount {}", path.display());
}

/// Runs `body` with `mount args` done (skipped, said, where the mount fails), and unmounts
/// `at` after it, whether it panicked or not (the panic then goes on).
fn with_mount(test: &str, args: &[&str], at: &Path, body: impl FnOnce()) {
    if !mount(args, test) {
        return;
    }
    let outcome = std::panic::catch_unwind(std::panic::AssertUnwindSafe(body));
    umount(at);
    if let Err(panic) = outcome {
        std::panic::resume_unwind(panic);
    }
}

/// [`with_mount`] of a tmpfs of `size` (`256k`) at `disk`, made first.
fn with_tmpfs(test: &str, disk: &Path, size: &str, body: impl FnOnce()) {
    std::fs::create_dir_all(disk).unwrap();
    let size = format!("size={size}");
    let args = ["-t", "tmpfs", "-o", &size, "tmpfs", disk.to_str().unwrap()];
    with_mount(test, &args, disk, body);
}

/// A bind-mounted output (a Docker volume `--output /results`) ran every run, then failed
/// to swap ("cannot exchange the new results with ...: Device or resource busy", exit 5),
/// every `--resume` the same way, and `report` of such a directory too. It is refused
/// before anything runs, with the hint to write inside it, and nothing is created.
#[test]
fn a_mount_point_output_is_refused_before_any_run() {
    const TEST: &str = "a_mount_point_output_is_refused_before_any_run";
    if !may_mount(TEST) {
        return;
    }
    let dir = scratch("writes-mount");
    let config = config(&dir, 1);
    let (source, mnt) = (dir.join("volume"), dir.join("mnt"));
    std::fs::create_dir_all(&source).unwrap();
    std::fs::create_dir_all(&mnt).unwrap();
    // Results written first, so that `report` of the mounted directory is tried too.
    experiment(&args(&config, &source, &NoReport)).unwrap();
    let (source_str, mnt_str) = (source.to_str().unwrap(), mnt.to_str().unwrap());
    with_mount(TEST, &["--bind", source_str, mnt_str], &mnt, || {
        for resume in [false, true] {
            let error = experiment(&SweepArgs {
                resume,
                ..args(&config, &mnt, &NoReport)
            })
            .unwrap_err();
            assert!(
                matches!(error, RunnerError::Output(OutdirError::MountPoint { .. })),
                "{error:?}"
            );
            assert_eq!(error.class(), ErrorClass::Output);
            let text = error.to_string();
            assert!(
                text.contains("is a mount point, which cannot be swapped atomically")
                    && text.contains(&format!("e.g. {}", mnt.join("results").display())),
                "{text}"
            );
        }
        let error = sweep::report(&mnt, Some(&config), &NoReport).unwrap_err();
        assert!(error.to_string().contains("is a mount point"), "{error}");
        // Nothing was created beside it; writing inside it works.
        let beside: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|name| name.starts_with(".mnt"))
            .collect();
        assert!(beside.is_empty(), "{beside:?}");
        experiment(&args(&config, &mnt.join("results"), &NoReport)).unwrap();
        assert!(mnt.join("results/runs.csv").is_file());
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Ctrl-C or SIGTERM while a sweep waited (up to 120 s) for another run's lock on the
/// same output kept it waiting until the other run ended, then left an empty stream area
/// beside the other's results, after which `--resume` found "nothing to resume". The wait
/// now polls the stop flag: the sweep ends at once, with nothing created.
#[test]
fn a_stop_while_waiting_for_the_lock_ends_the_wait_at_once() {
    let dir = scratch("writes-lock-stop");
    let config = config(&dir, 1);
    let output = dir.join("o");
    // Another run's lock on the output's stream area.
    let lock_path = dir.join(".o.stream.lock");
    let lock = std::fs::File::create(&lock_path).unwrap();
    fs4::FileExt::lock(&lock).unwrap();
    let stop = AtomicBool::new(false);
    let started = Instant::now();
    let error = std::thread::scope(|scope| {
        let waiting = scope.spawn(|| {
            experiment(&SweepArgs {
                stop: Some(&stop),
                lock_wait: Duration::from_secs(20),
                ..args(&config, &output, &NoReport)
            })
        });
        std::thread::sleep(Duration::from_millis(300));
        stop.store(true, Ordering::SeqCst);
        waiting.join().unwrap().unwrap_err()
    });
    assert!(
        started.elapsed() < Duration::from_secs(5),
        "waited {:?}",
        started.elapsed()
    );
    assert!(
        matches!(error, RunnerError::Output(OutdirError::Stopped { .. })),
        "{error:?}"
    );
    assert!(error.to_string().contains("nothing was written"), "{error}");
    assert!(!dir.join(".o.stream").exists(), "a stream area was left");
    assert!(!output.exists());
    drop(lock);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A report step that, while rendering, drops a file of "the user's" into the output
/// directory (which the write then refuses to replace), or returns one file of `big`
/// bytes (to fill a small disk).
struct Meddling {
    output: PathBuf,
    big: usize,
}

impl Render for Meddling {
    fn check(&self, _: &Experiment) -> Result<(), ConfigError> {
        Ok(())
    }

    fn render(&self, _: &Results<'_>) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        if self.big == 0 {
            std::fs::write(self.output.join("notes.txt"), "mine").unwrap();
            return Ok((Vec::new(), Reproduction::default()));
        }
        let file = OutputFile {
            path: "big.bin".into(),
            contents: vec![7; self.big],
        };
        Ok((vec![file], Reproduction::default()))
    }
}

/// A progress display that counts the runs that a sweep started with and says what a
/// discarded stream held.
#[derive(Default)]
struct Said {
    started: Mutex<Option<u64>>,
    discarding: Mutex<Vec<String>>,
    stop_at: Option<(u64, &'static AtomicBool)>,
}

impl Progress for Said {
    fn start(&self, _: u64, done: u64) {
        *self.started.lock().unwrap() = Some(done);
    }
    fn set(&self, done: u64) {
        if let Some((at, stop)) = self.stop_at {
            if done >= at {
                stop.store(true, Ordering::SeqCst);
            }
        }
    }
    fn finish(&self) {}
    fn discarding(&self, message: &str) {
        self.discarding.lock().unwrap().push(message.to_string());
    }
}

/// Once every run was recorded, a failure to write the results (a file of the user's that
/// appeared in the output during a --resume, a full disk) ended with the bare error (exit
/// 5), not saying that the runs are kept. It now says that all N runs are recorded in the
/// stream and that --resume writes the results without running any again; and it does.
#[test]
fn results_that_cannot_be_written_say_every_run_is_kept() {
    let dir = scratch("writes-kept");
    let config = config(&dir, 2);
    let output = dir.join("res");
    experiment(&args(&config, &output, &NoReport)).unwrap();
    let meddling = Meddling {
        output: output.clone(),
        big: 0,
    };
    let error = experiment(&args(&config, &output, &meddling)).unwrap_err();
    let stream = dir.join(".res.stream/records.stream");
    let text = error.to_string();
    assert!(
        text.contains("notes.txt")
            && text.contains(&format!(
                "all 4 runs are recorded in {}: free space or fix the cause, then rerun with \
                 --resume to write the results without running any again",
                stream.display()
            )),
        "{text}"
    );
    // Still the output's refusal, exit 5.
    assert_eq!(error.class(), ErrorClass::Output, "{error}");
    assert!(stream.is_file());
    // The cause removed, --resume writes the results and runs nothing again.
    std::fs::remove_file(output.join("notes.txt")).unwrap();
    let said = Said::default();
    experiment(&SweepArgs {
        resume: true,
        progress: Some(&said),
        ..args(&config, &output, &NoReport)
    })
    .unwrap();
    assert_eq!(*said.started.lock().unwrap(), Some(4));
    assert!(!dir.join(".res.stream").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A full disk while writing the results ("cannot write .../.o.partial/summary.md: No space
/// left on device", exit 5) said nothing of the runs, and was classed as an output
/// gridplan may not write. It says the runs are kept and is a failure (exit 1), as a full
/// disk while writing the stream is.
#[test]
fn a_full_disk_while_writing_the_results_keeps_every_run() {
    const TEST: &str = "a_full_disk_while_writing_the_results_keeps_every_run";
    if !may_mount(TEST) {
        return;
    }
    let dir = scratch("writes-full");
    let config = config(&dir, 2);
    let disk = dir.join("disk");
    let output = disk.join("res");
    with_tmpfs(TEST, &disk, "256k", || {
        let meddling = Meddling {
            output: output.clone(),
            big: 1 << 20,
        };
        let error = experiment(&args(&config, &output, &meddling)).unwrap_err();
        let text = error.to_string();
        assert!(
            text.contains("No space left on device")
                && text.contains("all 4 runs are recorded in")
                && text.contains("rerun with --resume to write the results"),
            "{text}"
        );
        assert_eq!(error.class(), ErrorClass::Other, "{error}");
        // Space freed (a smaller report), --resume writes them.
        let said = Said::default();
        experiment(&SweepArgs {
            resume: true,
            progress: Some(&said),
            ..args(&config, &output, &NoReport)
        })
        .unwrap();
        assert_eq!(*said.started.lock().unwrap(), Some(4));
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A full disk while appending to the resume stream ended with "error:
/// .../records.stream: No space left on device" (exit 1), not saying that the runs before
/// are kept. It now says how many are recorded and that --resume continues.
#[test]
fn a_full_stream_says_how_many_runs_are_kept() {
    const TEST: &str = "a_full_stream_says_how_many_runs_are_kept";
    if !may_mount(TEST) {
        return;
    }
    let dir = scratch("writes-stream-full");
    // 2 x 5,000 runs: more than a page of records.
    let config = config(&dir, 5000);
    let disk = dir.join("disk");
    let output = disk.join("res");
    // Four pages: the lock file, the area's marker, records.stream, ahead.stream.
    with_tmpfs(TEST, &disk, "16k", || {
        let error = experiment(&args(&config, &output, &NoReport)).unwrap_err();
        let text = error.to_string();
        let area = disk.join(".res.stream");
        let Some(RunnerError::StreamNotWritten { kept, runs, .. }) = Some(&error) else {
            panic!("{error:?}");
        };
        assert_eq!(*runs, 10_000);
        assert!(*kept < 10_000);
        assert!(
            text.contains("No space left on device")
                && text.contains(&format!(
                    "{kept} of 10000 runs are recorded in {} and kept: free space or fix the \
                     cause, then rerun with --resume to continue",
                    area.display()
                )),
            "{text}"
        );
        assert_eq!(error.class(), ErrorClass::Other);
        // Space made, --resume keeps exactly the runs said.
        let grown = mount(&["-o", "remount,size=4m", disk.to_str().unwrap()], TEST);
        if grown {
            let said = Said::default();
            experiment(&SweepArgs {
                resume: true,
                progress: Some(&said),
                ..args(&config, &output, &NoReport)
            })
            .unwrap();
            assert_eq!(*said.started.lock().unwrap(), Some(*kept));
        }
    });
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A refused --resume after only a map file's content changed (the config unchanged byte
/// for byte) said "recorded by a different config (... config hash 77cf...); cfg.toml
/// resolves to ... hash fe4b...", leaving the user to guess. It names the changed map
/// file, and the maps a glob now matches besides.
#[test]
fn a_refused_resume_says_which_input_changed() {
    let dir = scratch("writes-changed");
    let config = config(&dir, 1);
    let output = dir.join("res");
    experiment(&args(&config, &output, &NoReport)).unwrap();
    std::fs::write(dir.join("maps/a.map"), map_text(Some(14))).unwrap();
    let resume = |config: &Path| {
        experiment(&SweepArgs {
            resume: true,
            ..args(config, &output, &NoReport)
        })
        .unwrap_err()
    };
    let error = resume(&config);
    assert!(
        matches!(&error, RunnerError::Resume(e) if matches!(**e, ResumeError::OtherConfig { .. })),
        "{error:?}"
    );
    let text = error.to_string();
    assert!(
        text.contains("a.map's content changed since the recorded runs")
            && text.contains("map file ")
            && !text.contains("settings"),
        "{text}"
    );
    // Back as it was, and another map matched by the glob.
    std::fs::write(dir.join("maps/a.map"), map_text(None)).unwrap();
    std::fs::write(dir.join("maps/b.map"), map_text(None)).unwrap();
    let text = resume(&config).to_string();
    assert!(
        text.contains("a glob of its map sets matches other files")
            && text.contains("now also b.map")
            && !text.contains("content changed"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A refused --resume after a setting changed said "the config's settings (name, repeats,
/// seed, figures, paths, sections or planners) changed", also when the `[budget]` changed,
/// which that list leaves out. It names the setting that changed: the budget's limit and
/// the planner it applies to, a planner's parameters, a planner added, the repeats.
#[test]
fn a_refused_resume_names_the_setting_that_changed() {
    let dir = scratch("writes-changed-setting");
    let output = dir.join("res");
    let write = |budget: &str, repeats: u32, planners: &str| {
        std::fs::create_dir_all(dir.join("maps")).unwrap();
        std::fs::write(dir.join("maps/a.map"), map_text(None)).unwrap();
        let text = format!(
            "name = \"w\"\nrepeats = {repeats}\nfigures = \"none\"\n[budget]\n{budget}\n\
             [[maps]]\nfiles = [\"maps/*.map\"]\nproblems = \"corners\"\n{planners}"
        );
        let path = dir.join("w.toml");
        std::fs::write(&path, text).unwrap();
        path
    };
    let planners = "[planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n";
    let config = write("max_expansions = 20000", 2, planners);
    experiment(&args(&config, &output, &NoReport)).unwrap();
    let cases: [(&str, u32, String, &[&str]); 4] = [
        (
            "max_expansions = 20001",
            2,
            planners.to_string(),
            &[
                "budget's `max_expansions` of planner \"a\"",
                "of planner \"b\"",
            ],
        ),
        (
            "max_expansions = 20000",
            3,
            planners.to_string(),
            &["`repeats`"],
        ),
        (
            "max_expansions = 20000",
            2,
            planners.replace("\"astar\"", "\"astar\"\nmoves = 8"),
            &["planner \"a\"'s registry name, parameters or `compare` changed"],
        ),
        (
            "max_expansions = 20000",
            2,
            format!("{planners}[planners.c]\nplanner = \"dfs\"\n"),
            &["planner \"c\"'s registry name, parameters or `compare` was added"],
        ),
    ];
    for (budget, repeats, planners, said) in cases {
        let config = write(budget, repeats, &planners);
        let error = experiment(&SweepArgs {
            resume: true,
            ..args(&config, &output, &NoReport)
        })
        .unwrap_err();
        assert!(
            matches!(&error, RunnerError::Resume(e) if matches!(**e, ResumeError::OtherConfig { .. })),
            "{error:?}"
        );
        let text = error.to_string();
        for words in said {
            assert!(text.contains(words), "{budget}, {repeats}: {text}");
        }
        assert!(!text.contains("settings ("), "{text}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Starting over without --resume silently discarded an interrupted sweep's recorded runs
/// (the stream shrank from 766 KB to 170 KB). It says so, with how many and where.
#[test]
fn starting_over_says_it_discards_the_recorded_runs() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = scratch("writes-discard");
    let config = config(&dir, 400);
    let output = dir.join("res");
    let said = Said {
        stop_at: Some((50, &STOP)),
        ..Said::default()
    };
    let report = experiment(&SweepArgs {
        stop: Some(&STOP),
        progress: Some(&said),
        ..args(&config, &output, &NoReport)
    })
    .unwrap();
    let recorded = report.interrupted.unwrap();
    assert!(said.discarding.lock().unwrap().is_empty());
    let again = Said::default();
    experiment(&SweepArgs {
        progress: Some(&again),
        ..args(&config, &output, &NoReport)
    })
    .unwrap();
    let stream = dir.join(".res.stream/records.stream");
    assert_eq!(
        *again.discarding.lock().unwrap(),
        [format!(
            "discarding {recorded} recorded runs of an interrupted sweep of this config at {} \
             (rerun with --resume to keep them)",
            stream.display()
        )]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A link planted at a stream file's name (records.stream, ahead.stream in the stream
/// area) blocked even a fresh run with "cannot open ...: Too many levels of symbolic
/// links (os error 40)" and no hint. It is refused as a linked lock is, naming the link,
/// and the file it points to is left alone.
#[cfg(unix)]
#[test]
fn a_linked_stream_file_is_refused_and_left_alone() {
    let dir = scratch("writes-linked");
    let config = config(&dir, 1);
    let output = dir.join("res");
    let area = dir.join(".res.stream");
    let victim = dir.join("victim");
    std::fs::write(&victim, "precious").unwrap();
    for name in ["records.stream", "ahead.stream"] {
        std::fs::create_dir_all(&area).unwrap();
        std::fs::write(area.join(".gridplan-stream"), "").unwrap();
        let link = area.join(name);
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        for resume in [false, true] {
            let error = experiment(&SweepArgs {
                resume,
                ..args(&config, &output, &NoReport)
            })
            .unwrap_err();
            assert!(
                matches!(error, RunnerError::Output(OutdirError::LinkedStream { .. })),
                "{name}, resume {resume}: {error:?}"
            );
            assert_eq!(
                error.to_string(),
                format!(
                    "`{}` is a symbolic link; gridplan does not follow links in its stream \
                     directory (the file it points to is left untouched): remove the link",
                    link.display()
                )
            );
            assert_eq!(error.class(), ErrorClass::Output);
            assert_eq!(std::fs::read_to_string(&victim).unwrap(), "precious");
        }
        std::fs::remove_dir_all(&area).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A damaged resume stream (bytes flipped in a frame with frames after it) ended with
/// "... fails its checksum and frames follow it; the stream is damaged" (exit 1) and no
/// word of what to do. It says to run without --resume to start over, or to remove the
/// stream area.
#[test]
fn a_damaged_stream_says_what_to_do() {
    let dir = scratch("writes-damaged");
    // 2 x 1,500 runs: three frames of records.
    let config = config(&dir, 1500);
    let output = dir.join("res");
    experiment(&args(&config, &output, &NoReport)).unwrap();
    // The finished records, as an interrupted sweep's stream with a byte flipped in its
    // first frame.
    let area = dir.join(".res.stream");
    std::fs::create_dir_all(&area).unwrap();
    std::fs::write(area.join(".gridplan-stream"), "").unwrap();
    let mut bytes = std::fs::read(output.join(sweep::RESULTS_RECORDS)).unwrap();
    let header = bytes.iter().position(|&b| b == b'\n').unwrap() + 1;
    bytes[header + 40] ^= 0xff;
    std::fs::write(area.join("records.stream"), &bytes).unwrap();
    let error = experiment(&SweepArgs {
        resume: true,
        ..args(&config, &output, &NoReport)
    })
    .unwrap_err();
    let text = error.to_string();
    assert!(
        text.contains("fails its checksum and frames follow it; the stream is damaged")
            && text.contains(&format!(
                "run without --resume to start over (they are discarded and run again), or \
                 remove `{}` yourself",
                area.display()
            )),
        "{text}"
    );
    assert_eq!(error.class(), ErrorClass::Other);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `merge --shards-in sin --shards 3` with shard 3 interrupted (no sin/shard-3, its run
/// recorded in sin/.shard-3.stream) said "merge: sin/shard-3 is not a shard's output
/// (shard.stream: No such file or directory)". It says the shard is not finished, where
/// its runs are, and the command that finishes it; without a recorded run, that the
/// directory does not exist.
#[test]
fn merging_an_interrupted_shard_says_how_to_finish_it() {
    static STOP: AtomicBool = AtomicBool::new(false);
    let dir = scratch("writes-merge");
    let config = config(&dir, 2000);
    let sin = dir.join("sin");
    let shard_dir = |k: u64| sin.join(format!("shard-{k}"));
    for k in 1..=2 {
        let out = shard_dir(k);
        experiment(&SweepArgs {
            shard: Some(planner_runner::shard::Shard::new(k, 3).unwrap()),
            ..args(&config, &out, &NoReport)
        })
        .unwrap();
    }
    let said = Said {
        stop_at: Some((20, &STOP)),
        ..Said::default()
    };
    let third = shard_dir(3);
    let report = experiment(&SweepArgs {
        shard: Some(planner_runner::shard::Shard::new(3, 3).unwrap()),
        stop: Some(&STOP),
        progress: Some(&said),
        ..args(&config, &third, &NoReport)
    })
    .unwrap();
    assert!(report.interrupted.is_some());
    let dirs: Vec<PathBuf> = (1..=3).map(shard_dir).collect();
    let machine = |_: &Path| planner_runner::provenance::Machine {
        commit: None,
        host: None,
    };
    let merge =
        || sweep::merge(&dirs, Some(&dir.join("sm")), None, &NoReport, &machine).unwrap_err();
    let error = merge();
    let stream = sin.join(".shard-3.stream/records.stream");
    assert_eq!(
        error.to_string(),
        format!(
            "merge: shard 3 ({}) is not finished: an interrupted run of it is recorded in {}; \
             finish it with `gridplan experiment {} --shard 3/3 --output {} --resume`",
            third.display(),
            stream.display(),
            config.display(),
            third.display()
        )
    );
    assert_eq!(error.class(), ErrorClass::Other);
    let missing = || {
        let error = merge();
        assert!(
            error.to_string().starts_with(&format!(
                "merge: shard directory {} does not exist and no run of it is recorded \
                 beside it",
                third.display()
            )),
            "{error}"
        );
    };
    // A link planted at the stream's name is not followed (nor read).
    #[cfg(unix)]
    {
        let elsewhere = dir.join("elsewhere.stream");
        std::fs::rename(&stream, &elsewhere).unwrap();
        std::os::unix::fs::symlink(&elsewhere, &stream).unwrap();
        missing();
    }
    std::fs::remove_dir_all(sin.join(".shard-3.stream")).unwrap();
    missing();
    std::fs::remove_dir_all(&dir).unwrap();
}
