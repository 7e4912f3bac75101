//! OMPL benchmark logs (the text format of OMPL's `Benchmark::saveResultsToStream`, which
//! `ompl_benchmark_statistics` turns into the SQLite database Planner Arena loads).
//!
//! One log per map (`ompl/<map>.log`, an OMPL "experiment"): every label is a planner
//! with its resolved parameters as settings, and every run of it on the map's problems is
//! one run line, with `problem`, `repeat` and gridplan's metrics and counters as run
//! properties: `time` (s), `solved`, `memory` (MB), `solution length`, and one INTEGER
//! property per counter (empty where a planner does not report it).

use std::fmt::Write as _;

use planner_runner::config::{Experiment, PlannerSpec};
use planner_runner::output::OutputFile;
use planner_runner::provenance::Provenance;
use planner_runner::record::RunRecord;

/// The fixed run properties, before the counters: name and SQL type.
const FIXED: [(&str, &str); 11] = [
    ("problem", "INTEGER"),
    ("repeat", "INTEGER"),
    ("seed", "INTEGER"),
    ("time", "REAL"),
    ("solved", "BOOLEAN"),
    ("memory", "REAL"),
    ("solution length", "REAL"),
    ("optimal length", "REAL"),
    ("steps", "INTEGER"),
    ("turns", "INTEGER"),
    ("valid", "BOOLEAN"),
];

/// The OMPL logs of the sweep, one per map.
pub fn logs(
    experiment: &Experiment,
    records: &[RunRecord],
    provenance: &Provenance,
    seconds: f64,
) -> Vec<OutputFile> {
    let mut files = Vec::new();
    for map in &experiment.maps {
        let runs: Vec<&RunRecord> = records.iter().filter(|r| r.map == map.name).collect();
        let mut out = String::new();
        let _ = writeln!(out, "gridplan version {}", provenance.version);
        let _ = writeln!(
            out,
            "Experiment {}-{}",
            experiment.name,
            one_word(planner_runner::config::map_stem(&map.name))
        );
        let _ = writeln!(
            out,
            "Running on {}",
            one_word(provenance.host.as_deref().unwrap_or("unknown"))
        );
        let _ = writeln!(out, "Starting at {}", provenance.date);
        let _ = writeln!(
            out,
            "<<<|\nconfig {} (sha256 {}), map {}, {} problems, commit {}\n|>>>",
            experiment.source.display(),
            provenance.config_sha256.as_deref().unwrap_or("unknown"),
            map.name,
            map.problems.len(),
            provenance.commit.as_deref().unwrap_or("unknown")
        );
        if let Some(cpu) = &provenance.cpu {
            let _ = writeln!(out, "<<<|\n{cpu}\n|>>>");
        }
        let _ = writeln!(out, "{} is the random seed", experiment.seed);
        let time_limit = experiment
            .planners
            .first()
            .and_then(|p| p.budget.max_time)
            .map_or(0.0, |d| d.as_secs_f64());
        let _ = writeln!(out, "{time_limit} seconds per run");
        let _ = writeln!(out, "0 MB per run");
        let per_planner = experiment
            .planners
            .first()
            .map_or(0, |p| runs.iter().filter(|r| r.planner == p.label).count());
        let _ = writeln!(out, "{per_planner} runs per planner");
        let _ = writeln!(out, "{seconds:.3} seconds spent to collect the data");
        let _ = writeln!(out, "{} planners", experiment.planners.len());
        for planner in &experiment.planners {
            planner_block(&mut out, planner, &runs);
        }
        files.push(OutputFile {
            path: format!(
                "ompl/{}.log",
                one_word(planner_runner::config::map_stem(&map.name))
            )
            .into(),
            contents: out.into_bytes(),
        });
    }
    files
}

/// One planner's block of a log: its name, its settings as common properties, the
/// properties of each run, and one line per run of `runs` (the map's) it made.
fn planner_block(out: &mut String, planner: &PlannerSpec, runs: &[&RunRecord]) {
    let mine: Vec<&RunRecord> = runs
        .iter()
        .copied()
        .filter(|r| r.planner == planner.label)
        .collect();
    let _ = writeln!(out, "{}", one_word(&planner.label));
    let settings: Vec<String> = match planner.factory.resolved() {
        serde_json::Value::Object(m) => m
            .iter()
            .map(|(k, v)| format!("{k} = {v}"))
            .chain(std::iter::once(format!("planner = {}", planner.name)))
            .collect(),
        _ => vec![format!("planner = {}", planner.name)],
    };
    let _ = writeln!(out, "{} common properties", settings.len());
    for s in &settings {
        let _ = writeln!(out, "{}", s.replace('\n', " "));
    }
    let mut counters: Vec<&str> = Vec::new();
    for r in &mine {
        for (name, _) in r.counters.iter() {
            if !counters.contains(&name) {
                counters.push(name);
            }
        }
    }
    let _ = writeln!(
        out,
        "{} properties for each run",
        FIXED.len() + counters.len()
    );
    for (name, kind) in FIXED {
        let _ = writeln!(out, "{name} {kind}");
    }
    for name in &counters {
        let _ = writeln!(out, "{} INTEGER", one_word(name));
    }
    let _ = writeln!(out, "{} runs", mine.len());
    for r in &mine {
        let opt = |v: Option<String>| v.unwrap_or_default();
        let mut values = vec![
            r.problem.to_string(),
            r.repeat.to_string(),
            opt(r.seed.map(|s| s.to_string())),
            format!("{:.9}", r.time_ms / 1e3),
            u8::from(r.is_found()).to_string(),
            format!("{:.6}", r.peak_heap_bytes as f64 / 1048576.0),
            opt(r.length.map(|v| format!("{v:.6}"))),
            opt(r.optimal_length.map(|v| format!("{v:.6}"))),
            opt(r.steps.map(|v| v.to_string())),
            opt(r.turns.map(|v| v.to_string())),
            opt(r.valid.map(|v| u8::from(v).to_string())),
        ];
        values.extend(
            counters
                .iter()
                .map(|n| opt(r.counters.get(n).map(|v| v.to_string()))),
        );
        for v in values {
            out.push_str(&v);
            out.push_str("; ");
        }
        out.push('\n');
    }
    out.push_str(".\n");
}

/// `text` with whitespace replaced by `_` (OMPL's parser splits lines on spaces).
fn one_word(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join("_")
}
