//! OMPL benchmark logs (the text format of OMPL's `Benchmark::saveResultsToStream`, which
//! `ompl_benchmark_statistics` turns into the SQLite database Planner Arena loads).
//!
//! One log per map (`ompl/<map>.log`, an OMPL "experiment"): every label is a planner
//! with its resolved parameters as settings, and every run of it on the map's problems is
//! one run line, with `problem`, `repeat` and gridplan's metrics and counters as run
//! properties: `time` (s), `solved`, `status` (an ENUM of gridplan's statuses, declared in
//! the header as `status|found|no_path|budget_exhausted|invalid_problem` and written as
//! the index), `memory` (MB), `solution length`, on a map with cell costs `cost` (the
//! path's weighted cost, empty without a path), and one INTEGER property per counter
//! (empty where a planner does not report it). A problem that never ran (status
//! `invalid_problem`: a start or goal on a wall, say) has an empty `time` and `memory`
//! (NULL in OMPL's database), so Planner Arena's distributions hold measured runs only.
//! Lengths, costs and memory are the shortest decimal that reads back as the same double
//! (runs.csv's [`planner_runner::output::csv_float`]); times are in seconds to the
//! nanosecond.
//!
//! OMPL's header has one time limit and one memory limit for the whole experiment, while a
//! gridplan budget is a label's: the header gives the limit that applied to the labels'
//! runs, the largest when they differ, and 0 (no limit) when a label has none. A label
//! without `max_memory_mb` ran with the runner's default memory limit, half the machine's
//! memory ([`planner_runner::run::effective_budget`]), which is the limit written for it.
//! Each label's own limits are among its common properties (`budget.max_time_s`,
//! `budget.max_memory_mb`, `budget.max_expansions`, where set; `budget.max_memory_mb`
//! also when it is the default).
//!
//! Config text is data here too. OMPL's reader is line-oriented (Python's universal
//! newlines: `\n`, `\r` and `\r\n` end a line) and takes some values as one word, so
//! free text (the config path, map name, CPU) goes through `line`, which turns every
//! control character into a space, and names (labels, counters, host) through `one_word`,
//! which also joins whitespace with `_` and, when it changed anything, appends a short hash
//! of the original so `x y` and `x_y` stay two planners. The log of a map is
//! `ompl/<map>.log` with `<map>` derived by [`crate::file_part`], and a name
//! another map's log took already (letter case aside) gets a hash of the map's name
//! ([`crate::FileNames`]): every map's runs reach a log of their own.

use std::collections::HashMap;
use std::fmt::Write as _;

use planner_runner::config::{Experiment, PlannerSpec};
use planner_runner::output::{csv_float, OutputFile};
use planner_runner::provenance::Provenance;
use planner_runner::record::{RunRecord, RunStatus};
use planner_runner::run::effective_budget;

/// The fixed run properties, before `cost` and the counters: name and SQL type.
const FIXED: [(&str, &str); 12] = [
    ("problem", "INTEGER"),
    ("repeat", "INTEGER"),
    ("seed", "INTEGER"),
    ("time", "REAL"),
    ("solved", "BOOLEAN"),
    ("status", "ENUM"),
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
    let mut names = crate::FileNames::default();
    // The runs of each map and label, grouped once: a scan per label was labels x runs.
    let mut grouped: HashMap<(&str, &str), Vec<&RunRecord>> = HashMap::new();
    for r in records {
        grouped
            .entry((r.map.as_str(), r.planner.as_str()))
            .or_default()
            .push(r);
    }
    for map in &experiment.maps {
        let stem = crate::file_part(planner_runner::config::map_stem(&map.name));
        let mut out = String::new();
        let _ = writeln!(out, "gridplan version {}", provenance.version);
        let _ = writeln!(out, "Experiment {}-{stem}", experiment.name);
        let _ = writeln!(
            out,
            "Running on {}",
            one_word(provenance.host.as_deref().unwrap_or("unknown"))
        );
        let _ = writeln!(out, "Starting at {}", line(&provenance.date));
        let _ = writeln!(
            out,
            "<<<|\n{}\n|>>>",
            line(&format!(
                "config {} (sha256 {}), map {}, {} problems, commit {}",
                experiment.source.display(),
                provenance.config_sha256.as_deref().unwrap_or("unknown"),
                map.name,
                map.problems.len(),
                provenance.commit.as_deref().unwrap_or("unknown")
            ))
        );
        if let Some(cpu) = &provenance.cpu {
            let _ = writeln!(out, "<<<|\n{}\n|>>>", line(cpu));
        }
        let _ = writeln!(out, "{} is the random seed", experiment.seed);
        let time_limit = shared_limit(experiment, |p| p.budget.max_time.map(|d| d.as_secs_f64()));
        let memory_limit = shared_limit(experiment, |p| {
            effective_budget(p).max_memory_mb.map(|mb| mb as f64)
        });
        let _ = writeln!(out, "{time_limit} seconds per run");
        let _ = writeln!(out, "{memory_limit} MB per run");
        let per_planner = experiment
            .planners
            .first()
            .and_then(|p| grouped.get(&(map.name.as_str(), p.label.as_str())))
            .map_or(0, Vec::len);
        let _ = writeln!(out, "{per_planner} runs per planner");
        let _ = writeln!(out, "{seconds:.3} seconds spent to collect the data");
        out.push_str(&enum_types());
        let _ = writeln!(out, "{} planners", experiment.planners.len());
        let weighted = map.grid.is_weighted();
        for planner in &experiment.planners {
            let mine = grouped.get(&(map.name.as_str(), planner.label.as_str()));
            planner_block(
                &mut out,
                planner,
                experiment.seed,
                mine.map_or(&[], Vec::as_slice),
                weighted,
            );
        }
        files.push(OutputFile {
            path: names.claim(format!("ompl/{stem}.log"), &map.name).into(),
            contents: out.into_bytes(),
        });
    }
    files
}

/// The header's enum types: one, `status`, with gridplan's statuses in the order of
/// [`RunStatus::ALL`] (a run's `status` property is its index).
fn enum_types() -> String {
    let names: Vec<&str> = RunStatus::ALL.iter().map(|s| s.as_str()).collect();
    format!("1 enum type\nstatus|{}\n", names.join("|"))
}

/// `status`'s index among [`RunStatus::ALL`].
fn status_index(status: RunStatus) -> usize {
    RunStatus::ALL
        .iter()
        .position(|&s| s == status)
        .unwrap_or_default()
}

/// The experiment-wide limit of OMPL's header from each label's `limit`: 0 (none) when a
/// label has none, else the largest.
fn shared_limit(experiment: &Experiment, limit: impl Fn(&PlannerSpec) -> Option<f64>) -> f64 {
    let limits: Option<Vec<f64>> = experiment.planners.iter().map(limit).collect();
    limits.map_or(0.0, |all| all.into_iter().fold(0.0, f64::max))
}

/// One planner's block of a log (`seed`: the experiment's base seed): its name, its
/// settings as common properties (its parameters as its runs use them), the
/// properties of each run (`cost` on a `weighted` map), and one line per run of `mine`
/// (its runs on the map).
fn planner_block(
    out: &mut String,
    planner: &PlannerSpec,
    seed: u64,
    mine: &[&RunRecord],
    weighted: bool,
) {
    let _ = writeln!(out, "{}", one_word(&planner.label));
    let mut settings: Vec<String> = match &*planner.parameters(seed) {
        serde_json::Value::Object(m) => m.iter().map(|(k, v)| format!("{k} = {v}")).collect(),
        _ => Vec::new(),
    };
    settings.push(format!("planner = {}", planner.name));
    // The limits that applied: the label's, with the runner's default memory limit.
    let budget = effective_budget(planner);
    if let Some(time) = budget.max_time {
        settings.push(format!("budget.max_time_s = {}", time.as_secs_f64()));
    }
    if let Some(mb) = budget.max_memory_mb {
        settings.push(format!("budget.max_memory_mb = {mb}"));
    }
    if let Some(n) = budget.max_expansions {
        settings.push(format!("budget.max_expansions = {n}"));
    }
    let _ = writeln!(out, "{} common properties", settings.len());
    for s in &settings {
        let _ = writeln!(out, "{}", line(s));
    }
    let mut counters: Vec<&str> = Vec::new();
    for r in mine {
        for (name, _) in r.counters.iter() {
            if !counters.contains(&name) {
                counters.push(name);
            }
        }
    }
    let _ = writeln!(
        out,
        "{} properties for each run",
        FIXED.len() + usize::from(weighted) + counters.len()
    );
    for (name, kind) in FIXED {
        let _ = writeln!(out, "{name} {kind}");
    }
    if weighted {
        out.push_str("cost REAL\n");
    }
    for name in &counters {
        let _ = writeln!(out, "{} INTEGER", one_word(name));
    }
    let _ = writeln!(out, "{} runs", mine.len());
    for r in mine {
        let opt = |v: Option<String>| v.unwrap_or_default();
        // A problem that never ran has no time or memory to report.
        let ran = !r.is_invalid();
        let mut values = vec![
            r.problem.to_string(),
            r.repeat.to_string(),
            opt(r.seed.map(|s| s.to_string())),
            opt(ran.then(|| format!("{:.9}", r.time_ms / 1e3))),
            u8::from(r.is_found()).to_string(),
            status_index(r.status).to_string(),
            opt(ran.then(|| csv_float(r.peak_heap_bytes as f64 / 1048576.0))),
            opt(r.length.map(csv_float)),
            opt(r.optimal_length.map(csv_float)),
            opt(r.steps.map(|v| v.to_string())),
            opt(r.turns.map(|v| v.to_string())),
            opt(r.valid.map(|v| u8::from(v).to_string())),
        ];
        if weighted {
            values.push(opt(r.cost.map(csv_float)));
        }
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

/// `text` on one line: every control character (line breaks included) becomes a space.
fn line(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() || matches!(c, '\u{2028}' | '\u{2029}') {
                ' '
            } else {
                c
            }
        })
        .collect()
}

/// `text` as one word for OMPL's parser: whitespace runs and control characters become
/// `_`; if anything changed, `-` and a short hash of `text` follow, so distinct names stay
/// distinct.
fn one_word(text: &str) -> String {
    let word: String = line(text).split_whitespace().collect::<Vec<_>>().join("_");
    if word == text && !word.is_empty() {
        word
    } else {
        format!("{word}-{}", crate::short_hash(text))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_one_word_and_text_one_line() {
        assert_eq!(one_word("astar"), "astar");
        assert_ne!(one_word("x y"), one_word("x_y"));
        assert!(!one_word("a\nb c").contains(char::is_whitespace));
        assert_eq!(line("a\r\n|>>>b"), "a  |>>>b");
    }
}
