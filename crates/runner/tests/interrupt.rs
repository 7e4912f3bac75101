//! Stopped and killed sweeps: a stop keeps every run that finished, a kill loses only the
//! runs in progress and the last moments' runs, and a resumed sweep equals a serial one
//! whatever order its runs finished in.

use std::collections::{BTreeMap, BTreeSet};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Mutex;

use planner_runner::config;
use planner_runner::shard::{Shard, ShardRuns};
use planner_runner::stream::{run_stream, Delivery, StreamReader};
use planner_runner::sweep::{experiment, Progress, SweepArgs};
use planner_runner::{RunOptions, RunRecord};

use crate::common::{root, scratch, NoReport};

/// A config of `repeats` x 320 short runs (arena.map's 160 scenarios, A* and BFS; paths
/// kept for every run, so that they are compared too) in `dir`.
fn config(dir: &Path, repeats: u32) -> PathBuf {
    let map = root().join("maps/movingai/arena.map");
    let text = format!(
        "name = \"k\"\nrepeats = {repeats}\nfigures = \"none\"\npaths = \"all\"\n[[maps]]\nfiles = [{:?}]\n\
         scen = {:?}\n[planners.a]\nplanner = \"astar\"\nmoves = 8\n[planners.b]\nplanner = \"bfs\"\n",
        map.display().to_string(),
        format!("{}.scen", map.display())
    );
    let path = dir.join("k.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// A progress display that remembers what the sweep said, and raises `stop` once `at`
/// runs are done.
#[derive(Default)]
struct Watch<'a> {
    stop: Option<(&'a AtomicBool, u64)>,
    started: AtomicU64,
    done: AtomicU64,
    resumed: Mutex<Option<u64>>,
}

impl Progress for Watch<'_> {
    fn start(&self, _: u64, done: u64) {
        self.started.store(done, Ordering::SeqCst);
        self.done.store(done, Ordering::SeqCst);
    }

    fn set(&self, done: u64) {
        self.done.fetch_max(done, Ordering::SeqCst);
        if let Some((stop, at)) = self.stop {
            if done >= at {
                stop.store(true, Ordering::SeqCst);
            }
        }
    }

    fn finish(&self) {}

    fn resumed(&self, done: u64, _: u64, _: &Path) {
        *self.resumed.lock().unwrap() = Some(done);
    }
}

/// `record` without what is measured (times, heap): what a serial sweep repeats.
fn computed(mut record: RunRecord) -> RunRecord {
    record.time_ms = 0.0;
    record.setup_ms = 0.0;
    record.peak_heap_bytes = 0;
    record
}

/// The (run, record) pairs of the stream file `path`, and whether it ends cut.
fn read_stream(path: &Path) -> (Vec<(u64, RunRecord)>, bool) {
    let file = std::fs::File::open(path).unwrap();
    let (_, mut reader) = StreamReader::new(std::io::BufReader::new(file), "stream").unwrap();
    let mut runs = Vec::new();
    while let Some(run) = reader.next_run().unwrap() {
        runs.push(run);
    }
    (runs, reader.was_cut())
}

/// The records of an uninterrupted sweep of `config` on one thread (into `dir`), as its
/// results directory keeps them (with the paths the config keeps).
fn serial(config: &Path, dir: &Path, shard: Option<Shard>) -> Vec<RunRecord> {
    let report = experiment(&SweepArgs {
        threads: 1,
        output: Some(dir),
        shard,
        ..SweepArgs::new(config, &NoReport)
    })
    .unwrap();
    assert_eq!(report.interrupted, None);
    let file = match shard {
        Some(_) => planner_runner::sweep::SHARD_FILE,
        None => planner_runner::sweep::RESULTS_RECORDS,
    };
    let runs = read_stream(&dir.join(file)).0;
    runs.into_iter().map(|(_, r)| computed(r)).collect()
}

/// A stop raised while four workers run (by the progress display, once 200 runs are
/// done) keeps every run that finished: the sweep reports as many recorded runs as the
/// progress counted, records.stream and ahead.stream hold exactly those (the first of the
/// run order, then those finished after a run the stop cancelled), and the resumed
/// sweep runs only the others and equals a serial sweep. (Each worker ran a slice of a
/// batch of 2,048 runs, and a stop kept only the runs before the first one skipped: 75
/// finished runs and more were dropped.)
#[test]
fn a_stop_keeps_every_finished_run() {
    let dir = scratch("interrupt-stop");
    let config = config(&dir, 20);
    let want = serial(&config, &dir.join("serial"), None);
    let output = dir.join("res");
    let stop = AtomicBool::new(false);
    let watch = Watch {
        stop: Some((&stop, 200)),
        ..Watch::default()
    };
    let report = experiment(&SweepArgs {
        threads: 4,
        output: Some(&output),
        progress: Some(&watch),
        stop: Some(&stop),
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    let finished = watch.done.load(Ordering::SeqCst);
    assert!((200..6400).contains(&finished), "{finished} runs finished");
    assert_eq!(
        report.interrupted,
        Some(finished),
        "finished runs were dropped"
    );
    // records.stream holds the first runs of the run order; a run in progress that the
    // stop cancelled is not recorded, so the runs finished after it wait in ahead.stream.
    let (runs, cut) = read_stream(&dir.join(".res.stream/records.stream"));
    assert!(!cut);
    let indices: Vec<u64> = runs.iter().map(|(run, _)| *run).collect();
    assert_eq!(indices, (0..indices.len() as u64).collect::<Vec<_>>());
    let (ahead, cut) = read_stream(&dir.join(".res.stream/ahead.stream"));
    assert!(!cut);
    let mut all: Vec<u64> = ahead.iter().map(|(run, _)| *run).collect();
    assert!(
        all.iter().all(|&run| run > indices.len() as u64),
        "a run ahead follows a gap"
    );
    all.extend(&indices);
    all.sort_unstable();
    all.dedup();
    assert_eq!(
        all.len() as u64,
        finished,
        "every finished run is kept once"
    );

    let watch = Watch::default();
    let resumed = experiment(&SweepArgs {
        threads: 3,
        output: Some(&output),
        progress: Some(&watch),
        resume: true,
        keep_records: true,
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    assert_eq!(resumed.interrupted, None);
    assert_eq!(*watch.resumed.lock().unwrap(), Some(finished));
    assert_eq!(watch.started.load(Ordering::SeqCst), finished);
    let results = read_stream(&output.join(planner_runner::sweep::RESULTS_RECORDS)).0;
    let got: Vec<RunRecord> = results.into_iter().map(|(_, r)| computed(r)).collect();
    assert!(got == want, "the resumed sweep differs from a serial one");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Writes the stream file `path`: its header line as it is, then `runs` as frames of the
/// given sizes, then `cut` bytes of one more frame (as a kill mid-write leaves it).
fn write_stream(path: &Path, runs: &[(u64, RunRecord)], frames: &[usize], cut: usize) {
    let bytes = std::fs::read(path).unwrap();
    let header = &bytes[..=bytes.iter().position(|&b| b == b'\n').unwrap()];
    let mut out = header.to_vec();
    let mut at = 0;
    for &n in frames {
        out.extend(planner_runner::frames::encode_frames(&runs[at..at + n]).unwrap());
        at += n;
    }
    assert_eq!(at, runs.len());
    if cut > 0 {
        let last = planner_runner::frames::encode_frames(&runs[..1]).unwrap();
        out.extend(&last[..cut.min(last.len() - 1)]);
    }
    std::fs::File::create(path)
        .unwrap()
        .write_all(&out)
        .unwrap();
}

/// The stream area that a kill mid-sweep leaves, laid out by hand for `shard` of
/// `config` into `output`: records.stream holds the shard's first `prefix` runs and a
/// cut frame; ahead.stream the runs at the positions `ahead` (after the prefix, in the
/// order they finished, over two frames), one of the prefix (handed in order since) and
/// a cut frame. The records are `want`'s, the serial sweep's.
fn killed_area(config: &Path, output: &Path, shard: Option<Shard>, want: &[RunRecord]) {
    // A sweep stopped before its first run makes the area and its headers.
    let stop = AtomicBool::new(true);
    let report = experiment(&SweepArgs {
        output: Some(output),
        shard,
        stop: Some(&stop),
        ..SweepArgs::new(config, &NoReport)
    })
    .unwrap();
    assert_eq!(report.interrupted, Some(0));
    let experiment = config::load(config).unwrap();
    let runs: Vec<u64> = ShardRuns::new(&experiment, shard.unwrap_or(Shard::ALL))
        .iter()
        .collect();
    let at = |position: usize| (runs[position], want[position].clone());
    let area = output.with_file_name(format!(
        ".{}.stream",
        output.file_name().unwrap().to_string_lossy()
    ));
    let prefix: Vec<(u64, RunRecord)> = (0..100).map(at).collect();
    write_stream(&area.join("records.stream"), &prefix, &[64, 36], 20);
    let ahead: Vec<(u64, RunRecord)> = [103, 101, 99, 150, 120].into_iter().map(at).collect();
    write_stream(&area.join("ahead.stream"), &ahead, &[2, 3], 30);
}

/// A sweep killed while runs finished out of order (a slow run holding back the runs
/// after it) leaves the runs that finished ahead in ahead.stream, and `--resume` keeps
/// them as well as records.stream's: it says 104 runs are recorded (100 in order, 4
/// ahead; run 99 of ahead.stream is in records.stream already, and both cut frames are
/// dropped), runs only the others, and its results equal a serial sweep's; so for a
/// shard, whose runs are not the run list's. (--resume kept the in-order prefix only: a
/// SIGKILL lost up to a whole batch, eight resumes in a row at "resuming: 1024 of 4832".)
#[test]
fn a_resume_after_a_kill_keeps_the_runs_finished_ahead() {
    let dir = scratch("interrupt-kill");
    let config = config(&dir, 4);
    for shard in [None, Some(Shard::new(2, 3).unwrap())] {
        let want = serial(&config, &dir.join("serial"), shard);
        let output = dir.join("res");
        killed_area(&config, &output, shard, &want);
        let watch = Watch::default();
        let resumed = experiment(&SweepArgs {
            threads: 2,
            output: Some(&output),
            progress: Some(&watch),
            resume: true,
            shard,
            ..SweepArgs::new(&config, &NoReport)
        })
        .unwrap();
        assert_eq!(resumed.interrupted, None);
        assert_eq!(*watch.resumed.lock().unwrap(), Some(104), "{shard:?}");
        assert_eq!(watch.done.load(Ordering::SeqCst), want.len() as u64);
        let file = match shard {
            Some(_) => planner_runner::sweep::SHARD_FILE,
            None => planner_runner::sweep::RESULTS_RECORDS,
        };
        let results = read_stream(&output.join(file)).0;
        let got: Vec<RunRecord> = results.into_iter().map(|(_, r)| computed(r)).collect();
        assert!(
            got == want,
            "{shard:?}: the resumed sweep differs from a serial one"
        );
        std::fs::remove_dir_all(&output).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A peak-heap hook that holds the first run it measures for `hold` (a slow run, in
/// whichever worker takes it first) and, `copy_after` into it, copies the stream area's
/// files to `copy`: what a SIGKILL at that moment would leave.
struct SlowFirstRun<'a> {
    started: AtomicBool,
    hold: std::time::Duration,
    copy_after: std::time::Duration,
    area: &'a Path,
    copy: &'a Path,
}

impl planner_runner::run::HeapMeter for SlowFirstRun<'_> {
    fn current(&self) -> i64 {
        0
    }

    fn start(&self) -> i64 {
        if !self.started.swap(true, Ordering::SeqCst) {
            std::thread::sleep(self.copy_after);
            std::fs::create_dir_all(self.copy).unwrap();
            for name in ["records.stream", "ahead.stream"] {
                std::fs::copy(self.area.join(name), self.copy.join(name)).unwrap();
            }
            std::thread::sleep(self.hold - self.copy_after);
        }
        0
    }

    fn peak_since(&self, _: i64) -> u64 {
        0
    }
}

/// A sweep killed while a slow run holds back the runs after it: the runs that finished
/// behind it are on disk all the same (in ahead.stream, a tenth of a second after they
/// finish), and the sweep resumed from what the kill left keeps them, runs the others,
/// and equals a serial sweep. (Runs were written a whole batch at a time, in order: a
/// SIGKILL lost every run of the batch, and eight resumes in a row, each killed within a
/// second, stayed at "resuming: 1024 of 4832".)
#[test]
fn a_kill_while_a_slow_run_holds_the_order_keeps_the_runs_behind_it() {
    let dir = scratch("interrupt-slow");
    let config = config(&dir, 4);
    let want = serial(&config, &dir.join("serial"), None);
    let output = dir.join("res");
    let area = dir.join(".res.stream");
    let copy = dir.join("copy");
    let slow = SlowFirstRun {
        started: AtomicBool::new(false),
        hold: std::time::Duration::from_millis(900),
        copy_after: std::time::Duration::from_millis(600),
        area: &area,
        copy: &copy,
    };
    let report = experiment(&SweepArgs {
        threads: 2,
        output: Some(&output),
        heap: Some(&slow),
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    assert_eq!(report.interrupted, None);
    let (in_order, _) = read_stream(&copy.join("records.stream"));
    let (ahead, _) = read_stream(&copy.join("ahead.stream"));
    // The slow run is run 0 or 1; the other worker ran on behind it.
    assert!(in_order.len() <= 1, "{} runs in order", in_order.len());
    assert!(ahead.len() >= 100, "{} runs ahead", ahead.len());
    assert!(ahead.iter().all(|(run, _)| *run > in_order.len() as u64));

    // The area of a sweep stopped at once, with the copy's files in it.
    std::fs::remove_dir_all(&output).unwrap();
    let stop = AtomicBool::new(true);
    experiment(&SweepArgs {
        output: Some(&output),
        stop: Some(&stop),
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    for name in ["records.stream", "ahead.stream"] {
        std::fs::copy(copy.join(name), area.join(name)).unwrap();
    }
    let watch = Watch::default();
    let resumed = experiment(&SweepArgs {
        threads: 2,
        output: Some(&output),
        progress: Some(&watch),
        resume: true,
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    assert_eq!(resumed.interrupted, None);
    let kept = (in_order.len() + ahead.len()) as u64;
    assert_eq!(*watch.resumed.lock().unwrap(), Some(kept));
    let results = read_stream(&output.join(planner_runner::sweep::RESULTS_RECORDS)).0;
    let got: Vec<RunRecord> = results.into_iter().map(|(_, r)| computed(r)).collect();
    assert!(got == want, "the resumed sweep differs from a serial one");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// [`run_stream`] on eight workers (12,800 runs) hands every run in order exactly once, the done runs
/// it is given without running them, each run handed ahead once and never a done one,
/// and a catch-up after the last run handed ahead; stopped (by the progress hook, after
/// 300 runs), every run it ran is handed, in order or ahead.
#[test]
fn run_stream_hands_every_finished_run_once() {
    let dir = scratch("interrupt-deliveries");
    let experiment = config::load(&config(&dir, 40)).unwrap();
    let options = RunOptions {
        threads: 8,
        ..RunOptions::default()
    };
    let all = planner_runner::run_all(&experiment, &options).unwrap();
    let done: BTreeMap<u64, RunRecord> = [5u64, 6, 7000, 12799]
        .into_iter()
        .map(|i| (i, all[i as usize].clone()))
        .collect();
    for stop_at in [None, Some(300u64)] {
        let stop = AtomicBool::new(false);
        let hook = |n: u64| {
            if stop_at.is_some_and(|at| n >= at) {
                stop.store(true, Ordering::SeqCst);
            }
        };
        let options = RunOptions {
            threads: 8,
            progress: Some(&hook),
            stop: Some(&stop),
            ..RunOptions::default()
        };
        let (mut in_order, mut ahead, mut behind) = (Vec::new(), BTreeSet::new(), true);
        let streamed = run_stream(&experiment, 0..12800, done.clone(), &options, |delivery| {
            match delivery {
                Delivery::InOrder(batch) => {
                    for (run, record) in batch {
                        assert!(computed(record) == computed(all[run as usize].clone()));
                        in_order.push(run);
                    }
                }
                Delivery::Ahead(batch) => {
                    for (run, _) in batch {
                        assert!(!done.contains_key(run) && !in_order.contains(run));
                        assert!(ahead.insert(*run), "run {run} handed ahead twice");
                    }
                    behind = true;
                }
                Delivery::CaughtUp => {
                    assert!(ahead.iter().all(|run| in_order.contains(run)));
                    behind = false;
                }
            }
            Ok(())
        })
        .unwrap();
        let n = in_order.len() as u64;
        assert_eq!(in_order, (0..n).collect::<Vec<_>>());
        assert_eq!(streamed.in_order, n);
        let left: BTreeSet<u64> = ahead.iter().copied().filter(|r| *r >= n).collect();
        let done_left = done.keys().filter(|r| **r >= n).count() as u64;
        assert_eq!(streamed.ahead, left.len() as u64 + done_left);
        let ran_in_order = n - done.keys().filter(|r| **r < n).count() as u64;
        assert_eq!(streamed.ran, ran_in_order + left.len() as u64);
        match stop_at {
            None => assert!(n == 12800 && !behind && streamed.ran == 12796),
            Some(at) => assert!(streamed.ran >= at && n < 12800, "{streamed:?}"),
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A config `name` on an open 8x8 map in `dir`: two problems, A* (`a`) and backtracking
/// (`bt`, which enumerates paths and runs until its budget of `expansions` ends), one
/// thread; runs in order: A*, backtracking, A*, backtracking.
fn long_config(dir: &Path, name: &str, expansions: u64) -> PathBuf {
    let map = "type octile\nheight 8\nwidth 8\nmap\n".to_string() + &"........\n".repeat(8);
    std::fs::write(dir.join("open8.map"), map).unwrap();
    let text = format!(
        "name = \"{name}\"\nthreads = 1\nfigures = \"none\"\npaths = \"all\"\n\
         [[maps]]\nfiles = [\"open8.map\"]\n\
         pairs = [{{ start = [0, 0], goal = [7, 7] }}, {{ start = [0, 1], goal = [7, 6] }}]\n\
         [planners.a]\nplanner = \"astar\"\n\
         [planners.bt]\nplanner = \"backtracking\"\nbudget = {{ max_expansions = {expansions} }}\n"
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// A stop raised while a run is in progress cancels it: a sweep whose backtracking run
/// would take hours (10^11 expansions) returns once stopped, with no run recorded (the
/// first A* run finishes before the stop, which the progress display raises once it is
/// done; the backtracking run, cut short, is not recorded, so the stream keeps only
/// finished runs). (The sweep ran on until the run's budget ended: over ten minutes
/// for a SIGTERM, which Slurm follows with a SIGKILL.)
#[test]
fn a_stop_cancels_the_runs_in_progress() {
    let dir = scratch("interrupt-cancel");
    let config = long_config(&dir, "long", 100_000_000_000);
    let output = dir.join("res");
    let (sent, received) = std::sync::mpsc::channel();
    let thread_output = output.clone();
    std::thread::spawn(move || {
        let stop = AtomicBool::new(false);
        let watch = Watch {
            stop: Some((&stop, 1)),
            ..Watch::default()
        };
        let report = experiment(&SweepArgs {
            output: Some(&thread_output),
            progress: Some(&watch),
            stop: Some(&stop),
            ..SweepArgs::new(&config, &NoReport)
        });
        let _ = sent.send(report.map(|r| r.interrupted).map_err(|e| e.to_string()));
    });
    // A run of 10^11 expansions takes hours; a cancelled one ends within a budget check.
    let interrupted = received
        .recv_timeout(std::time::Duration::from_secs(120))
        .expect("the stopped sweep did not return: its run in progress was not cancelled");
    assert_eq!(interrupted, Ok(Some(1)));
    let (runs, cut) = read_stream(&dir.join(".res.stream/records.stream"));
    assert!(!cut);
    let indices: Vec<u64> = runs.iter().map(|(run, _)| *run).collect();
    assert_eq!(indices, [0], "the cancelled run was recorded");
    assert!(read_stream(&dir.join(".res.stream/ahead.stream"))
        .0
        .is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A run cancelled by a stop is run again by `--resume`, which then equals a serial
/// sweep: the stop (raised once the first A* run is done) cuts the backtracking run
/// short (5 * 10^6 expansions: a second or so), which is not recorded, so the stream holds
/// one run; the resumed sweep runs the three others in full. (The cancelled run was
/// recorded as `budget_exhausted` after however many expansions it had done.)
#[test]
fn a_run_cancelled_by_a_stop_is_run_again_by_resume() {
    let dir = scratch("interrupt-cancel-resume");
    let config = long_config(&dir, "cut", 5_000_000);
    let want = serial(&config, &dir.join("serial"), None);
    assert_eq!(
        want[1].status,
        planner_runner::record::RunStatus::BudgetExhausted
    );
    let output = dir.join("res");
    let stop = AtomicBool::new(false);
    let watch = Watch {
        stop: Some((&stop, 1)),
        ..Watch::default()
    };
    let report = experiment(&SweepArgs {
        output: Some(&output),
        progress: Some(&watch),
        stop: Some(&stop),
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    assert_eq!(
        report.interrupted,
        Some(1),
        "the cancelled run was recorded"
    );
    let watch = Watch::default();
    let resumed = experiment(&SweepArgs {
        output: Some(&output),
        progress: Some(&watch),
        resume: true,
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    assert_eq!(resumed.interrupted, None);
    assert_eq!(*watch.resumed.lock().unwrap(), Some(1));
    let results = read_stream(&output.join(planner_runner::sweep::RESULTS_RECORDS)).0;
    let got: Vec<RunRecord> = results.into_iter().map(|(_, r)| computed(r)).collect();
    assert!(got == want, "the resumed sweep differs from a serial one");
    std::fs::remove_dir_all(&dir).unwrap();
}
