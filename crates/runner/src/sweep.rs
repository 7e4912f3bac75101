//! Streamed, resumable and sharded sweeps on disk, and merging shards.
//!
//! A sweep appends each batch of records, as it completes, to `records.jsonl` in the
//! output's stream area (`.<name>.stream/` beside the output directory, under its own lock:
//! [`outdir::stream_area`]), flushing after each batch, so a killed sweep leaves every
//! finished batch readable. `--resume` reads that file back: if its header's config hash
//! matches the config's, the runs it holds are kept (a cut last line is dropped) and the
//! sweep continues after them; a changed config is refused. Without `--resume` an old
//! stream is discarded.
//!
//! When the sweep is whole, the final outputs are rendered, in run order, from its records
//! (those of this process, after those a resumed sweep reads back from the stream; the
//! standard counter names of records read back are static strings, not one allocation
//! each) and written atomically by [`outdir::write_results_streamed`]: `runs.json` (a
//! table without paths, [`crate::output::runs_json`]) and `runs.csv` row by row into their
//! files, `summary.md`, figures, and `paths.jsonl` with the paths the config keeps
//! (`paths`). Then the stream area is removed (only while it carries gridplan's marker:
//! [`outdir::StreamArea`]). A shard (`--shard K/N`) instead writes its
//! stream as `shard.jsonl` into its output directory; [`merge`] checks that a set of shard
//! directories is complete and of one config and renders the one sweep's outputs from them.
//!
//! Records read back are checked, not trusted. `--resume` and [`merge`] check every record
//! against the config's run list (its map, problem, planner label and repeat must be those
//! of its run index: [`stream::check_record`]), after the stream header's experiment,
//! config hash and shard, and refuse a mismatch naming the stream or shard file and its
//! line. Versions: a stream header names the gridplan that wrote it; `--resume` refuses a
//! stream of another version (or of none), naming both, so one sweep's records come from
//! one program. `merge` refuses shards whose results markers or stream headers name
//! different gridplan versions, naming both shards and versions, and merges shards all of
//! one other version with a warning naming it and its own.
//!
//! A sweep whose stop flag ([`SweepArgs::stop`], set by the command line on SIGINT or
//! SIGTERM) is raised starts no new run, appends the runs finished before the first one
//! it skipped, and returns a [`Report`] with [`Report::interrupted`] set: nothing is
//! rendered, the old results stay as they were, and the stream stays for `--resume`.

use std::fs::{self, File};
use std::io::{BufReader, Seek as _, SeekFrom, Write as _};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use rayon::prelude::*;

use crate::output::{OutputFile, StreamedFile};
use crate::provenance::Provenance;
use crate::report::Reproduction;
use crate::run::{HeapMeter, RunList};
use crate::shard::{Shard, ShardRuns};
use crate::stream::{self, StreamHeader, StreamReader};
use crate::{
    charts, config, figures, html, ompl, outdir, output as results, report, Experiment, RunOptions,
    RunRecord,
};

/// The stream file of a sweep's stream area, and of a shard's results directory.
const RECORDS: &str = "records.jsonl";

/// A shard's stream in its results directory.
pub const SHARD_FILE: &str = "shard.jsonl";

/// What `experiment` did.
#[derive(Debug, Clone)]
pub struct Report {
    /// Runs done.
    pub n_runs: usize,
    /// Output directory written.
    pub output: PathBuf,
    /// Published numbers compared and matched.
    pub reproduction: Reproduction,
    /// Wall time of the sweep and the writing, in seconds.
    pub seconds: f64,
    /// `Some(n)` when the stop flag ended the sweep with `n` of its `n_runs` runs
    /// recorded (in the stream, for `--resume`); no results were written.
    pub interrupted: Option<u64>,
    /// The records written (paths left out, as in runs.json), when [`SweepArgs::keep_records`]
    /// asked for them; else empty.
    pub records: Vec<RunRecord>,
}

/// A sweep's progress display (a command line's progress bar); the sweep calls it from
/// its own thread, in order: [`Progress::start`], [`Progress::set`] any number of times,
/// [`Progress::finish`].
pub trait Progress: Sync {
    /// The sweep has `total` runs, of which `done` were recorded before (a resume).
    fn start(&self, total: u64, done: u64);
    /// `done` of the runs are recorded.
    fn set(&self, done: u64);
    /// The runs are done (the outputs are being written).
    fn finish(&self);
}

/// What `experiment` is asked to do.
#[derive(Clone, Copy)]
pub struct SweepArgs<'a> {
    /// The config file.
    pub config: &'a Path,
    /// Worker threads (0: the config's).
    pub threads: usize,
    /// Output directory (default: the config's; for a shard, `<that>-shard-K-of-N`).
    pub output: Option<&'a Path>,
    /// Where progress goes (none: nowhere).
    pub progress: Option<&'a dyn Progress>,
    /// Peak-heap measurement per run (none: `peak_heap_bytes` is 0); [`crate::alloc::Meter`]
    /// when the binary installs [`crate::alloc::Counting`].
    pub heap: Option<&'a dyn HeapMeter>,
    /// Keep the runs an interrupted sweep recorded.
    pub resume: bool,
    /// Run one shard only.
    pub shard: Option<Shard>,
    /// Once set, the sweep stops (see the module docs).
    pub stop: Option<&'a AtomicBool>,
    /// Return the records in [`Report::records`] (for a library caller; a whole sweep
    /// holds them anyway to write its reports).
    pub keep_records: bool,
}

impl<'a> SweepArgs<'a> {
    /// A plain sweep of `config`: the config's threads and output, no progress, no heap
    /// measurement, not resumed, not sharded.
    pub fn new(config: &'a Path) -> SweepArgs<'a> {
        SweepArgs {
            config,
            threads: 0,
            output: None,
            progress: None,
            heap: None,
            resume: false,
            shard: None,
            keep_records: false,
            stop: None,
        }
    }
}

/// Runs (or resumes) a sweep and writes its results directory (or its shard's).
pub fn experiment(args: &SweepArgs) -> Result<Report, String> {
    let started = Instant::now();
    let experiment = config::load(args.config).map_err(|e| e.to_string())?;
    if args.threads > config::MAX_THREADS {
        // Refused before the output's stream area is made, so nothing is written.
        return Err(crate::RunnerError::Threads(args.threads).to_string());
    }
    let shard = args.shard.unwrap_or(Shard::ALL);
    let dir = match (args.output, args.shard) {
        (Some(dir), _) => dir.to_path_buf(),
        (None, Some(s)) => {
            let mut name = experiment.output.as_os_str().to_os_string();
            name.push(format!("-shard-{}-of-{}", s.index, s.count));
            PathBuf::from(name)
        }
        (None, None) => experiment.output.clone(),
    };
    outdir::check(&dir).map_err(|e| e.to_string())?;
    let area = outdir::stream_area(&dir, outdir::DEFAULT_LOCK_WAIT).map_err(|e| e.to_string())?;
    let runs = ShardRuns::new(&experiment, shard);
    let header = StreamHeader::new(&experiment, shard, runs.len());
    let path = area.dir.join(RECORDS);
    let done = if args.resume {
        resume_point(&path, &header, &runs, &experiment)?
    } else {
        None
    };
    let (mut file, n_done) = match done {
        Some((bytes, n)) => {
            let mut file = area.open_write(RECORDS, false).map_err(|e| e.to_string())?;
            file.set_len(bytes)
                .and_then(|()| file.seek(SeekFrom::End(0)).map(drop))
                .map_err(|e| format!("{}: {e}", path.display()))?;
            eprintln!("resuming: {n} of {} runs already recorded", runs.len());
            (file, n)
        }
        None => {
            if args.resume {
                eprintln!("nothing to resume for {}: running every run", dir.display());
            }
            let mut file = area.open_write(RECORDS, true).map_err(|e| e.to_string())?;
            file.write_all(&header.to_line().map_err(|e| e.to_string())?)
                .map_err(|e| format!("{}: {e}", path.display()))?;
            (file, 0)
        }
    };
    tracing::info!(experiment = %experiment.name, runs = runs.len(), %shard, "sweep");
    if let Some(progress) = args.progress {
        progress.start(runs.len(), n_done);
    }
    let tick = |n: u64| {
        if let Some(progress) = args.progress {
            progress.set(n_done + n);
        }
    };
    let options = RunOptions {
        threads: args.threads,
        progress: Some(&tick),
        heap: args.heap,
        stop: args.stop,
    };
    // A whole sweep keeps its records for the final outputs (a resumed one reads back
    // those recorded before); a shard only streams them.
    let keep = args.shard.is_none();
    let mut records: Vec<RunRecord> = Vec::new();
    if keep {
        records.reserve_exact(runs.len().min(1 << 20) as usize);
        if n_done > 0 {
            file.flush()
                .map_err(|e| format!("{}: {e}", path.display()))?;
            records = read_records(&path, records)?;
        }
    }
    let mut buffer = Vec::new();
    let n_ran = stream::run_stream(
        &experiment,
        runs.iter().skip(n_done as usize),
        &options,
        |batch| {
            // Encoded in parallel on the sweep's workers (the sink runs in their pool).
            let lines: Vec<Vec<u8>> = batch
                .par_iter()
                .map(|(run, record)| {
                    let mut line = Vec::with_capacity(512);
                    stream::encode(&mut line, *run, record).map(|()| line)
                })
                .collect::<Result<_, _>>()?;
            buffer.clear();
            for line in &lines {
                buffer.extend_from_slice(line);
            }
            file.write_all(&buffer)
                .and_then(|()| file.flush())
                .map_err(|e| crate::RunnerError::Stream(format!("{}: {e}", path.display())))?;
            if keep {
                records.extend(batch.into_iter().map(|(_, record)| record));
            }
            Ok(())
        },
    )
    .map_err(|e| e.to_string())?;
    if let Some(progress) = args.progress {
        progress.finish();
    }
    drop(file);
    if n_done + n_ran < runs.len() {
        return Ok(Report {
            n_runs: runs.len() as usize,
            output: dir,
            reproduction: Reproduction::default(),
            seconds: started.elapsed().as_secs_f64(),
            interrupted: Some(n_done + n_ran),
            records: Vec::new(),
        });
    }
    let (reproduction, records) = if !keep {
        // The stream is copied, not read into memory.
        let copy = StreamedFile {
            path: SHARD_FILE.into(),
            write: Box::new(|out| {
                let mut file = File::open(&path)
                    .map_err(|e| crate::RunnerError::Stream(format!("{}: {e}", path.display())))?;
                std::io::copy(&mut file, out)
                    .map(drop)
                    .map_err(|e| crate::RunnerError::Stream(format!("{}: {e}", path.display())))
            }),
        };
        outdir::write_results_streamed(
            &dir,
            &experiment.name,
            &[],
            &[copy],
            outdir::DEFAULT_LOCK_WAIT,
        )
        .map_err(|e| e.to_string())?;
        (Reproduction::default(), Vec::new())
    } else {
        if records.len() as u64 != header.runs {
            return Err(format!(
                "{}: {} of {} runs recorded",
                path.display(),
                records.len(),
                header.runs
            ));
        }
        let threads = worker_threads(args.threads, experiment.threads);
        let provenance = Provenance::collect(args.config, threads);
        let seconds = started.elapsed().as_secs_f64();
        let (reproduction, records) = finish(&experiment, records, &dir, &provenance, seconds)?;
        (
            reproduction,
            if args.keep_records {
                records
            } else {
                Vec::new()
            },
        )
    };
    if let Err(e) = area.remove() {
        tracing::warn!(
            "the results are written, but the stream area {} could not be removed: {e}",
            area.dir.display()
        );
    }
    Ok(Report {
        n_runs: runs.len() as usize,
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
        interrupted: None,
        records,
    })
}

/// The worker count a sweep runs with: the argument, else the config's, else one per core.
fn worker_threads(argument: usize, configured: usize) -> usize {
    match (argument, configured) {
        (0, 0) => std::thread::available_parallelism().map_or(1, |n| n.get()),
        (0, c) => c,
        (a, _) => a,
    }
}

/// Where an interrupted sweep's stream `path` ends: (bytes of complete lines, runs), or
/// `None` if there is no stream. Refuses a stream of another config or shard.
fn resume_point(
    path: &Path,
    header: &StreamHeader,
    runs: &ShardRuns,
    experiment: &Experiment,
) -> Result<Option<(u64, u64)>, String> {
    let file = match stream::open_regular(path) {
        Ok(file) => file,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(e) => return Err(format!("{}: {e}", path.display())),
    };
    let what = path.display().to_string();
    let (found, mut reader) = match StreamReader::new(BufReader::new(file), &what) {
        Ok(opened) => opened,
        // Killed before its header was complete: nothing was recorded.
        Err(_) if fs::metadata(path).map(|m| m.len()).unwrap_or(0) < 4096 => return Ok(None),
        Err(e) => return Err(e.to_string()),
    };
    if found.config_hash != header.config_hash || found.experiment != header.experiment {
        return Err(format!(
            "--resume: {what} was recorded by a different config (experiment {:?}, config hash {}); \
             {} resolves to experiment {:?}, hash {}. Run without --resume to start over.",
            found.experiment, found.config_hash, header.config, header.experiment, header.config_hash
        ));
    }
    if found.gridplan != header.gridplan {
        return Err(format!(
            "--resume: {what} was written by gridplan {}, this is gridplan {}; records of two \
             versions are not mixed in one sweep. Run without --resume to start over.",
            found
                .gridplan
                .as_deref()
                .unwrap_or("of unknown version (its header names none)"),
            header.gridplan.as_deref().unwrap_or("?")
        ));
    }
    if (found.shard, found.shards) != (header.shard, header.shards) {
        return Err(format!(
            "--resume: {what} holds shard {}/{}, not {}/{}",
            found.shard, found.shards, header.shard, header.shards
        ));
    }
    let list = RunList::new(experiment);
    let mut expected = runs.iter();
    let mut n = 0u64;
    while let Some((run, record)) = reader.next_run().map_err(|e| e.to_string())? {
        if expected.next() != Some(run) {
            return Err(format!(
                "--resume: {what}: run {run} is out of order; run without --resume"
            ));
        }
        // The header line is line 1: record n is line n + 2.
        stream::check_record(experiment, &list, run, &record)
            .map_err(|e| format!("--resume: {what} line {}: {e}; run without --resume", n + 2))?;
        n += 1;
    }
    Ok(Some((reader.complete_bytes(), n)))
}

/// The records of the stream file `path`, appended to `records`.
fn read_records(path: &Path, mut records: Vec<RunRecord>) -> Result<Vec<RunRecord>, String> {
    let file = stream::open_regular(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let what = path.display().to_string();
    let (_, mut reader) =
        StreamReader::new(BufReader::new(file), &what).map_err(|e| e.to_string())?;
    while let Some((_, record)) = reader.next_run().map_err(|e| e.to_string())? {
        records.push(record);
    }
    Ok(records)
}

/// Renders the outputs of a whole sweep's `records` (in run order): runs.json, runs.csv,
/// paths.jsonl, summary.md, figures, charts, report.html and, when the config asks, OMPL
/// logs; and writes them to `dir`, runs.json and runs.csv row by row into their files.
/// `seconds` is the sweep's wall time so far (OMPL's experiment time).
fn finish(
    experiment: &Experiment,
    mut records: Vec<RunRecord>,
    dir: &Path,
    provenance: &Provenance,
    seconds: f64,
) -> Result<(Reproduction, Vec<RunRecord>), String> {
    let (summary, reproduction) = report::render_with(experiment, &records, Some(provenance));
    let mut files = figures::render_checked(experiment, &records).map_err(|e| e.to_string())?;
    files.extend(charts::render(experiment, &records));
    if experiment.ompl {
        files.extend(ompl::logs(experiment, &records, provenance, seconds));
    }
    if let Some(paths) = results::paths_jsonl(&records).map_err(|e| e.to_string())? {
        files.push(OutputFile {
            path: "paths.jsonl".into(),
            contents: paths,
        });
    }
    for record in &mut records {
        record.path = None;
    }
    let mut all = vec![OutputFile {
        path: "summary.md".into(),
        contents: summary.into_bytes(),
    }];
    all.append(&mut files);
    let page = html::report_html(&experiment.name, &summary_text(&all), &all);
    all.push(OutputFile {
        path: "report.html".into(),
        contents: page.into_bytes(),
    });
    let rows = &records;
    let tables = [
        StreamedFile {
            path: "runs.json".into(),
            write: Box::new(move |out| {
                results::write_runs_json(out, experiment, rows, Some(provenance))
            }),
        },
        StreamedFile {
            path: "runs.csv".into(),
            write: Box::new(move |out| results::write_runs_csv(out, rows)),
        },
    ];
    outdir::write_results_streamed(
        dir,
        &experiment.name,
        &all,
        &tables,
        outdir::DEFAULT_LOCK_WAIT,
    )
    .map_err(|e| e.to_string())?;
    drop(tables);
    Ok((reproduction, records))
}

/// Merges the shard directories `dirs` into the one sweep's results in `output` (default:
/// the config's). `config` overrides the config file the shards name.
pub fn merge(
    dirs: &[PathBuf],
    output: Option<&Path>,
    config: Option<&Path>,
) -> Result<Report, String> {
    let started = Instant::now();
    if dirs.is_empty() {
        return Err("merge: no shard directories given".into());
    }
    let mut shards: Vec<(PathBuf, StreamHeader, StreamReader<BufReader<File>>)> = Vec::new();
    for dir in dirs {
        let path = dir.join(SHARD_FILE);
        let file = stream::open_regular(&path).map_err(|e| {
            format!(
                "merge: {} is not a shard's output ({}: {e})",
                dir.display(),
                SHARD_FILE
            )
        })?;
        let (header, reader) = StreamReader::new(BufReader::new(file), &path.display().to_string())
            .map_err(|e| e.to_string())?;
        shards.push((dir.clone(), header, reader));
    }
    let first = shards[0].1.clone();
    for (dir, header, _) in &shards[1..] {
        if header.config_hash != first.config_hash
            || header.shards != first.shards
            || header.experiment != first.experiment
        {
            return Err(format!(
                "merge: {} (experiment {:?}, config hash {}, {} shards) and {} (experiment {:?}, config hash {}, {} shards) are shards of different sweeps",
                shards[0].0.display(), first.experiment, first.config_hash, first.shards,
                dir.display(), header.experiment, header.config_hash, header.shards
            ));
        }
    }
    let mut missing = Vec::new();
    for k in 1..=first.shards {
        let holders: Vec<&PathBuf> = shards
            .iter()
            .filter(|(_, h, _)| h.shard == k)
            .map(|(d, _, _)| d)
            .collect();
        match holders.len() {
            0 => missing.push(format!("{k}/{}", first.shards)),
            1 => {}
            _ => {
                return Err(format!(
                    "merge: shard {k}/{} given twice: {}",
                    first.shards,
                    holders
                        .iter()
                        .map(|d| d.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            }
        }
    }
    if !missing.is_empty() {
        return Err(format!(
            "merge: shards {} of experiment {:?} are missing (given: {})",
            missing.join(", "),
            first.experiment,
            dirs.iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    check_versions(&shards)?;
    let config_path = config.map_or_else(|| PathBuf::from(&first.config), Path::to_path_buf);
    let experiment = config::load(&config_path).map_err(|e| format!("merge: {e}"))?;
    let hash = stream::config_hash(&experiment);
    if hash != first.config_hash {
        return Err(format!(
            "merge: {} now resolves to config hash {hash}, but the shards were run with {}; \
             rerun the shards or pass the config they ran with (--config)",
            config_path.display(),
            first.config_hash
        ));
    }
    // K-way merge by run index: every index 0..total exactly once, each record checked
    // against the config's run list.
    let list = RunList::new(&experiment);
    // Per shard: the line of its head record (the header is line 1).
    let mut lines: Vec<u64> = vec![2; shards.len()];
    let mut heads: Vec<Option<(u64, RunRecord)>> = Vec::with_capacity(shards.len());
    for (_, _, reader) in &mut shards {
        heads.push(reader.next_run().map_err(|e| e.to_string())?);
    }
    let mut records = Vec::with_capacity(first.total_runs.min(1 << 24) as usize);
    for expected in 0..first.total_runs {
        let Some(i) = heads
            .iter()
            .position(|h| h.as_ref().is_some_and(|(run, _)| *run == expected))
        else {
            return Err(format!(
                "merge: run {expected} of {} is in no shard (a shard is incomplete: {})",
                first.total_runs,
                shards
                    .iter()
                    .map(|(d, h, _)| format!(
                        "{} holds shard {}/{}",
                        d.display(),
                        h.shard,
                        h.shards
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        };
        let next = shards[i].2.next_run().map_err(|e| e.to_string())?;
        if let Some((run, record)) = std::mem::replace(&mut heads[i], next) {
            stream::check_record(&experiment, &list, run, &record).map_err(|e| {
                format!(
                    "merge: {} line {}: {e}",
                    shards[i].0.join(SHARD_FILE).display(),
                    lines[i]
                )
            })?;
            lines[i] += 1;
            records.push(record);
        }
    }
    if let Some(i) = heads.iter().position(Option::is_some) {
        return Err(format!(
            "merge: {} holds runs past the sweep's end",
            shards[i].0.display()
        ));
    }
    let dir = output.map_or_else(|| experiment.output.clone(), Path::to_path_buf);
    outdir::check(&dir).map_err(|e| e.to_string())?;
    let n_runs = records.len();
    let provenance = Provenance::collect(&config_path, worker_threads(0, experiment.threads));
    let seconds = started.elapsed().as_secs_f64();
    let (reproduction, _) = finish(&experiment, records, &dir, &provenance, seconds)?;
    Ok(Report {
        n_runs,
        output: dir,
        reproduction,
        seconds: started.elapsed().as_secs_f64(),
        interrupted: None,
        records: Vec::new(),
    })
}

/// The gridplan version of each shard: its results marker's (`.gridplan-results`) and its
/// stream header's. Shards written by different versions are refused, naming both (their
/// planners may count differently, so the merged tables would mix two programs); shards
/// of one version other than this gridplan's are merged with a warning naming both.
fn check_versions(
    shards: &[(PathBuf, StreamHeader, StreamReader<BufReader<File>>)],
) -> Result<(), String> {
    let mut seen: Vec<(String, String)> = Vec::new();
    for (dir, header, _) in shards {
        let marker = outdir::Marker::read(dir).ok().map(|m| m.gridplan);
        for version in [marker, header.gridplan.clone()].into_iter().flatten() {
            match seen.iter().find(|(v, _)| *v != version) {
                Some((other, other_dir)) => {
                    return Err(format!(
                        "merge: {other_dir} was written by gridplan {other} and {} by gridplan \
                         {version}; rerun the shards with one gridplan version",
                        dir.display()
                    ))
                }
                None => seen.push((version, dir.display().to_string())),
            }
        }
    }
    let this = env!("CARGO_PKG_VERSION");
    if let Some((version, dir)) = seen.iter().find(|(v, _)| v != this) {
        tracing::warn!(
            "merging shards written by gridplan {version} ({dir}) with gridplan {this}: the \
             records are kept as that version computed them"
        );
    }
    Ok(())
}

/// The summary.md among `files`, as text.
fn summary_text(files: &[OutputFile]) -> String {
    files
        .iter()
        .find(|f| f.path.as_os_str() == "summary.md")
        .map(|f| String::from_utf8_lossy(&f.contents).into_owned())
        .unwrap_or_default()
}
