//! The tables computed in passes over the records (planner_report::streamed, exact
//! quantiles in memory bounded by the groups) equal the in-memory computation of
//! `oracle` (every group's runs collected and sorted) byte for byte, on 100,000 runs and
//! more.

use crate::oracle;

use std::io::BufReader;
use std::path::{Path, PathBuf};

use oracle::tables;
use planner_api::Counters;
use planner_report::aggregate::Measured;
use planner_report::Context;
use planner_runner::config::{self, Experiment};
use planner_runner::index::ResultsIndex;
use planner_runner::passes::StreamPasses;
use planner_runner::shard::Shard;
use planner_runner::stream::{self, StreamHeader, StreamReader};
use planner_runner::{run_all, RunOptions, RunRecord};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A small deterministic generator (SplitMix64).
struct Mix(u64);

impl Mix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
}

/// `experiment` run once per (map, problem, label), each record then repeated `repeats`
/// times with varied times (ties included), counters, lengths and heap, in run order.
fn synthetic(mut experiment: Experiment, repeats: u32) -> (Experiment, Vec<RunRecord>) {
    experiment.repeats = 1;
    let base = run_all(&experiment, &RunOptions::default()).unwrap();
    experiment.repeats = repeats;
    let mut mix = Mix(29);
    let mut records = Vec::new();
    for record in &base {
        let reps = if record.is_invalid() { 1 } else { repeats };
        for r in 0..reps {
            let mut copy = record.clone();
            copy.repeat = r;
            copy.path = None;
            let roll = mix.next();
            // Times: a few ties (whole microseconds) among many distinct values.
            copy.time_ms = match roll % 4 {
                0 => (roll >> 40) as f64 / 1e3,
                _ => (roll >> 11) as f64 / (1u64 << 53) as f64 * 3.0,
            };
            copy.peak_heap_bytes = roll >> 44;
            let mut counters = Counters::new();
            for (name, value) in record.counters.iter() {
                let varied = match name {
                    "n_expanded" => value + (roll >> 20) % 97,
                    _ => value ^ ((roll >> 8) % 5),
                };
                counters.push(name.to_string(), varied);
            }
            if r % 7 == 3 {
                // A counter only some runs report.
                counters.push("n_extra", roll % 1_000);
            }
            copy.counters = counters;
            if let Some(length) = copy.length {
                if r % 5 == 1 {
                    copy.length = Some(length * (1.0 + (roll % 1000) as f64 / 1e4));
                }
            }
            records.push(copy);
        }
    }
    (experiment, records)
}

fn in_memory(experiment: &Experiment, records: &[RunRecord], measured: Measured) -> String {
    let index = ResultsIndex::new(records);
    let options = toml::Table::new();
    let context = Context {
        experiment,
        records,
        index: &index,
        passes: &records,
        charts: None,
        options: &options,
    };
    tables(&context, measured)
}

/// Writes `records` as a JSON Lines stream file and reads it back, so both computations
/// see the same (round-tripped) values.
fn through_file(
    experiment: &Experiment,
    records: &[RunRecord],
    name: &str,
) -> (PathBuf, Vec<RunRecord>) {
    let path = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!(
        "gridplan-streamed-{name}-{}.jsonl",
        std::process::id()
    ));
    let header = StreamHeader::new(experiment, Shard::ALL, records.len() as u64);
    let mut bytes = header.to_line().unwrap();
    for (run, record) in records.iter().enumerate() {
        stream::encode(&mut bytes, run as u64, record).unwrap();
    }
    std::fs::write(&path, bytes).unwrap();
    let file = std::fs::File::open(&path).unwrap();
    let (_, mut reader) = StreamReader::new(BufReader::new(file), "test").unwrap();
    let mut back = Vec::new();
    while let Some((_, record)) = reader.next_run().unwrap() {
        back.push(record);
    }
    (path, back)
}

/// configs/movingai.toml (optima, scenario buckets, several labels and maps) at 100,000+
/// runs: every table equal, from the records in memory and from the stream file on disk.
#[test]
fn streamed_aggregates_equal_the_in_memory_ones_on_100000_runs() {
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let n_base = experiment.n_runs();
    let repeats = (100_000 / n_base + 1) as u32;
    let (experiment, records) = synthetic(experiment, repeats);
    assert!(records.len() >= 100_000, "{} runs", records.len());
    // The comparison through the file runs on a thread of its own beside the ones in memory
    // (the slowest test of this binary: it would otherwise end alone on one core).
    let (experiment, records) = (&experiment, &records);
    std::thread::scope(|scope| {
        let from_file = scope.spawn(|| {
            let (path, back) = through_file(experiment, records, "movingai");
            let passes = StreamPasses::new(&path, back.len() as u64);
            let got =
                planner_report::streamed::aggregate_tables(experiment, &passes, Measured::Shown);
            let want = in_memory(experiment, &back, Measured::Shown);
            std::fs::remove_file(&path).unwrap();
            assert_eq!(got.unwrap(), want);
        });
        for measured in [Measured::Shown, Measured::Redacted] {
            let want = in_memory(experiment, records, measured);
            let got = planner_report::streamed::aggregate_tables(
                experiment,
                &records.as_slice(),
                measured,
            )
            .unwrap();
            assert_eq!(got, want);
            if measured == Measured::Shown {
                assert!(want.contains("By scenario bucket"), "{want}");
                assert!(want.contains("| n_extra |"), "{want}");
            }
        }
        from_file.join().unwrap();
    });
}

/// A seeded planner's spread over seeds (configs/capso-control-points.toml's labels).
#[test]
fn streamed_seed_spreads_equal_the_in_memory_ones() {
    let experiment = config::load(&root().join("configs/capso-control-points.toml"))
        .unwrap()
        .trimmed_for_test();
    let (experiment, records) = synthetic(experiment, 3_000);
    let want = in_memory(&experiment, &records, Measured::Shown);
    assert!(
        want.contains("Seeded planners over their 3000 seeds"),
        "{want}"
    );
    let got = planner_report::streamed::aggregate_tables(
        &experiment,
        &records.as_slice(),
        Measured::Shown,
    )
    .unwrap();
    assert_eq!(got, want);
}

/// A stream file that lost records since it was counted is an error, not a table.
#[test]
fn a_stream_shorter_than_stated_is_an_error() {
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let (experiment, records) = synthetic(experiment, 2);
    let (path, back) = through_file(&experiment, &records, "short");
    let passes = StreamPasses::new(&path, back.len() as u64 + 1);
    let result = planner_report::streamed::aggregate_tables(&experiment, &passes, Measured::Shown);
    std::fs::remove_file(&path).unwrap();
    let message = result.unwrap_err().to_string();
    assert!(message.contains("read"), "{message}");
}

/// summary.md of a sweep whose records are not held (its head, `optimum`, `repeats` and
/// `aggregate`, all from passes over a stream) equals the one rendered with the records
/// in memory, and its sections equal the oracle's in-memory tables.
#[test]
fn a_summary_from_passes_equals_the_in_memory_summary() {
    use planner_report::{aggregate::Aggregate, optimum::Optimum, repeats::Repeats, Renderer};
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let (experiment, records) = synthetic(experiment, 40);
    let (path, records) = through_file(&experiment, &records, "summary");
    let renderer = Renderer::new(vec![
        Box::new(Optimum),
        Box::new(Repeats),
        Box::new(Aggregate),
    ]);
    let (want, _) = renderer.summary(&experiment, &records).unwrap();
    let index = ResultsIndex::new(&records);
    let options = toml::Table::new();
    let context = Context {
        experiment: &experiment,
        records: &records,
        index: &index,
        passes: &records.as_slice(),
        charts: None,
        options: &options,
    };
    let sections = format!(
        "{}{}{}",
        oracle::optimum_table(&context),
        oracle::repeat_table(&context),
        tables(&context, Measured::Shown)
    );
    assert!(
        sections.contains("## Repeats (40 per planner and problem)"),
        "{sections}"
    );
    assert!(
        sections.contains("## Lengths against the scenario optima"),
        "{sections}"
    );
    assert!(want.ends_with(&sections), "{want}\n---\n{sections}");
    let passes = StreamPasses::new(&path, records.len() as u64);
    let got = renderer.summary_passes(&experiment, &[], &passes, None);
    std::fs::remove_file(&path).unwrap();
    assert_eq!(got.unwrap().0, want);
}

/// The charts of a sweep too large to hold (over 100,000 runs, read from a stream file)
/// equal those drawn from the same records in memory, and the time box plot's median
/// is the sorted values' median.
#[test]
fn charts_from_a_stream_equal_the_charts_from_memory() {
    let experiment = config::load(&root().join("configs/movingai.toml"))
        .unwrap()
        .trimmed_for_test();
    let n_base = experiment.n_runs();
    let repeats = (100_000 / n_base + 1) as u32;
    let (experiment, records) = synthetic(experiment, repeats);
    let (path, records) = through_file(&experiment, &records, "charts");
    assert!(records.len() > 100_000, "{} runs", records.len());
    let want = planner_report::charts::charts(&experiment, &records.as_slice()).unwrap();
    let passes = StreamPasses::new(&path, records.len() as u64);
    let got = planner_report::charts::charts(&experiment, &passes);
    std::fs::remove_file(&path).unwrap();
    let got = got.unwrap();
    assert_eq!(got, want);
    let files: Vec<&str> = got.iter().map(|c| c.file.as_str()).collect();
    for file in [
        "time-box.svg",
        "expansions-box.svg",
        "expansions-by-bucket.svg",
        "success.svg",
    ] {
        assert!(files.contains(&file), "{files:?}");
    }
    let label = &experiment.planners[0].label;
    let times: Vec<f64> = records
        .iter()
        .filter(|r| !r.is_invalid() && r.planner == *label)
        .map(|r| r.time_ms)
        .collect();
    let (median, _, _) = planner_report::median_iqr(&times).unwrap();
    let box_plot = &got[0].svg;
    assert!(
        box_plot.contains(&format!("{label} (median {median:.3})")),
        "{box_plot}"
    );
}

/// On a sweep with a map with cell costs (and one without), the tables from passes equal
/// the oracle's: the optimum table leaves the weighted map out, the Aggregates show the
/// median cost.
#[test]
fn a_weighted_summary_from_passes_equals_the_in_memory_tables() {
    use planner_report::{aggregate::Aggregate, optimum::Optimum, Renderer};
    let (experiment, records) = crate::summary::weighted_sweep();
    let renderer = Renderer::new(vec![Box::new(Optimum), Box::new(Aggregate)]);
    let (want, _) = renderer.summary(&experiment, &records).unwrap();
    let index = ResultsIndex::new(&records);
    let options = toml::Table::new();
    let context = Context {
        experiment: &experiment,
        records: &records,
        index: &index,
        passes: &records.as_slice(),
        charts: None,
        options: &options,
    };
    let sections = format!(
        "{}{}",
        oracle::optimum_table(&context),
        tables(&context, Measured::Shown)
    );
    assert!(sections.contains("| Median cost |"), "{sections}");
    assert!(want.ends_with(&sections), "{want}\n---\n{sections}");
}
