//! Two results directories compared run by run (`gridplan compare OLD NEW`): after a change
//! to a planner, which runs changed what the search did, and how much faster or slower it
//! is. A pure function of the two directories' records; no planner runs.
//!
//! Runs are matched by planner label, map, problem (index, start and goal) and repeat. Of
//! the runs in both, every field but the measured ones (`time_ms`, `setup_ms`,
//! `peak_heap_bytes`) is compared: status, path, length, cost, steps, turns, every counter,
//! seed, marks. The first differing runs (one per problem) are listed field by field.
//! Times are compared per label over the problems both ran: per problem the median over
//! the repeats of each side,
//! NEW over OLD, summarised by the geometric mean of those ratios with Student's t 95 %
//! interval on their logarithms ([`planner_stats::geometric_mean`]) and the number of
//! problems NEW is faster on. Times come from two sweeps, possibly on two machines or
//! loads: the provenance of each (summary.md) says where they ran.
//!
//! A run's computed fields are compared through a 64-bit hash of them (SipHash of their
//! JSON): two different records with one hash, about one chance in 2^64 a pair, would pass
//! for equal.
//!
//! Memory: a key, a digest and a time per run of NEW, and a time per run of OLD (about
//! 100 bytes a run), never a whole record but the listed ones; three passes over the
//! records at most (NEW, OLD, then NEW again for the listed runs).

use std::collections::hash_map::DefaultHasher;
use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::hash::{Hash, Hasher};
use std::io::BufReader;
use std::path::{Path, PathBuf};

use planner_runner::readback::ResultsError;
use planner_runner::record::RunRecord;
use planner_runner::stream::StreamReader;
use planner_runner::RunnerError;

/// The fields of a record that are measured, not computed: left out of the comparison.
const MEASURED: [&str; 3] = ["time_ms", "setup_ms", "peak_heap_bytes"];

/// What two results directories' records say about each other.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The two directories, OLD then NEW.
    pub dirs: [PathBuf; 2],
    /// Their runs, OLD then NEW.
    pub runs: [u64; 2],
    /// Where and how each sweep ran (its provenance.json), OLD then NEW.
    pub provenance: [planner_runner::provenance::Provenance; 2],
    /// Runs in both.
    pub both: u64,
    /// Runs of both whose computed fields differ.
    pub differing: u64,
    /// The first differing runs (at most the number asked for, one per problem), in OLD's
    /// run order.
    pub examples: Vec<Difference>,
    /// Per label (in NEW's order), its times NEW over OLD.
    pub times: Vec<LabelTimes>,
}

/// One run whose computed fields differ.
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// The run: label, map, problem, repeat.
    pub run: String,
    /// Each differing field: its name (a counter as `counters.NAME`), OLD's value, NEW's.
    pub fields: Vec<(String, String, String)>,
}

/// One label's times, NEW over OLD, per problem both ran.
#[derive(Debug, Clone, PartialEq)]
pub struct LabelTimes {
    /// The label.
    pub label: String,
    /// Problems with a positive median time on both sides.
    pub problems: u64,
    /// The geometric mean of the per-problem ratios and its 95 % interval.
    pub ratio: Option<planner_stats::GeometricMean>,
    /// Problems where NEW's median time is below OLD's.
    pub faster: u64,
}

impl Comparison {
    /// Whether the two directories hold the same runs with the same computed fields.
    pub fn same(&self) -> bool {
        self.differing == 0 && self.both == self.runs[0] && self.both == self.runs[1]
    }

    /// The comparison as one JSON object for scripts: `old` and `new` (`dir`, `runs`,
    /// `provenance`), `both`, `only_old`, `only_new`, `differing`, `same`, `examples` (each
    /// `run` and its `fields`, `[name, old, new]`) and `times` (per label `label`,
    /// `problems`, `ratio`, `low`, `high` (null without an interval), `faster`).
    pub fn json(&self) -> serde_json::Value {
        use serde_json::json;
        let side = |i: usize| {
            json!({
                "dir": self.dirs[i].display().to_string(),
                "runs": self.runs[i],
                "provenance": self.provenance[i],
            })
        };
        let examples: Vec<serde_json::Value> = self
            .examples
            .iter()
            .map(|e| json!({ "run": e.run, "fields": e.fields }))
            .collect();
        let times: Vec<serde_json::Value> = self
            .times
            .iter()
            .map(|t| {
                let (low, high) = t
                    .ratio
                    .and_then(|g| g.interval)
                    .map_or((None, None), |(low, high)| (Some(low), Some(high)));
                json!({
                    "label": t.label,
                    "problems": t.problems,
                    "ratio": t.ratio.map(|g| g.mean),
                    "low": low,
                    "high": high,
                    "faster": t.faster,
                })
            })
            .collect();
        json!({
            "old": side(0),
            "new": side(1),
            "both": self.both,
            "only_old": self.runs[0] - self.both,
            "only_new": self.runs[1] - self.both,
            "differing": self.differing,
            "same": self.same(),
            "examples": examples,
            "times": times,
        })
    }

    /// The comparison as text for a person.
    pub fn text(&self) -> String {
        let mut out = String::new();
        for (i, side) in ["OLD", "NEW"].iter().enumerate() {
            let p = &self.provenance[i];
            let _ = writeln!(
                out,
                "{side} {}: {} runs (gridplan {}, commit {}, {} on {}, {}, {} threads)",
                one_line(&self.dirs[i].display().to_string()),
                self.runs[i],
                one_line(&p.version),
                one_line(p.commit.as_deref().unwrap_or("unknown")),
                one_line(&p.date),
                one_line(p.host.as_deref().unwrap_or("an unknown host")),
                one_line(p.cpu.as_deref().unwrap_or("an unknown CPU")),
                p.threads
            );
        }
        let _ = writeln!(
            out,
            "runs in both: {}, only in OLD: {}, only in NEW: {}",
            self.both,
            self.runs[0] - self.both,
            self.runs[1] - self.both
        );
        if self.differing == 0 {
            let _ = writeln!(
                out,
                "computed fields (status, path, length, cost, counters, ...): the same in all {} runs in both",
                self.both
            );
        } else {
            let _ = writeln!(
                out,
                "computed fields (status, path, length, cost, counters, ...): {} of {} runs in both differ; the first {} (one run per problem):",
                self.differing,
                self.both,
                self.examples.len()
            );
            for example in &self.examples {
                let fields: Vec<String> = example
                    .fields
                    .iter()
                    .map(|(name, old, new)| format!("{name} {old} -> {new}"))
                    .collect();
                let _ = writeln!(out, "  {}: {}", example.run, fields.join("; "));
            }
        }
        out.push_str("time, NEW over OLD (per problem the medians over repeats; geometric mean over problems, 95 % interval):\n");
        for label in &self.times {
            let ratio = match label.ratio {
                Some(g) => match g.interval {
                    Some((low, high)) => format!("{:.3} ({low:.3} to {high:.3})", g.mean),
                    None => format!("{:.3}", g.mean),
                },
                None => "-".into(),
            };
            let _ = writeln!(
                out,
                "  {:?}: {ratio}, NEW faster on {} of {} problems",
                label.label, label.faster, label.problems
            );
        }
        out
    }
}

/// `text` on one line of the text report: as it is, or, when it holds a line break or another
/// control character, with Rust's escapes (`\n`), so that a host name or a directory's name
/// cannot add a line. (Labels and map names are written quoted and escaped, `{:?}`.)
fn one_line(text: &str) -> std::borrow::Cow<'_, str> {
    match text
        .chars()
        .any(|c| c.is_control() || matches!(c, '\u{2028}' | '\u{2029}'))
    {
        true => std::borrow::Cow::Owned(text.escape_debug().to_string()),
        false => std::borrow::Cow::Borrowed(text),
    }
}

/// Interned names, so that a key holds numbers.
#[derive(Default)]
struct Names(HashMap<String, u32>);

impl Names {
    fn id(&mut self, name: &str) -> u32 {
        let next = self.0.len() as u32;
        *self.0.entry(name.to_string()).or_insert(next)
    }
}

/// A problem: label, map, problem index, start, goal.
type ProblemKey = (u32, u32, usize, (u32, u32), (u32, u32));
/// A run: its problem and repeat.
type RunKey = (ProblemKey, u32);

fn run_key(names: &mut Names, r: &RunRecord) -> RunKey {
    let problem = (
        names.id(&r.planner),
        names.id(&r.map),
        r.problem,
        (r.start.x, r.start.y),
        (r.goal.x, r.goal.y),
    );
    (problem, r.repeat)
}

/// A record's computed fields as JSON (the measured ones left out).
fn computed(r: &RunRecord) -> serde_json::Map<String, serde_json::Value> {
    let mut value = match serde_json::to_value(r) {
        Ok(serde_json::Value::Object(map)) => map,
        _ => serde_json::Map::new(),
    };
    for field in MEASURED {
        value.remove(field);
    }
    value
}

fn digest(r: &RunRecord) -> u64 {
    let mut hasher = DefaultHasher::new();
    serde_json::Value::Object(computed(r))
        .to_string()
        .hash(&mut hasher);
    hasher.finish()
}

/// Calls `visit` on every record of the results directory `dir`. A stream that holds
/// another number of runs than its header's `total_runs`, or ends in a cut record, is
/// refused (the check `gridplan report` makes), never read as the runs it holds: a cut
/// stream's missing runs are no differences. Every error says `compare` and is of
/// `report`'s class for the same damage ([`RunnerError::class`]: results that are not
/// complete, `Output`: exit 5, `OutputError`), never exit 1, which means "the runs differ".
fn pass(dir: &Path, visit: &mut dyn FnMut(RunRecord)) -> Result<u64, RunnerError> {
    let damaged = |e| planner_runner::readback::damaged("compare", dir, e);
    let (path, file) = planner_runner::sweep::open_results(dir, "compare")?;
    let (header, mut reader) =
        StreamReader::new(BufReader::new(file), &path.display().to_string()).map_err(damaged)?;
    let mut n = 0;
    while let Some((_, record)) = reader.next_run().map_err(damaged)? {
        n += 1;
        visit(record);
    }
    if n != header.total_runs || reader.was_cut() {
        return Err(ResultsError::Short {
            command: "compare",
            file: path.display().to_string(),
            held: n,
            runs: header.total_runs,
        }
        .into());
    }
    Ok(n)
}

/// The provenance of the results directory `dir`, an error of it classed as [`pass`]'s.
fn provenance(dir: &Path) -> Result<planner_runner::provenance::Provenance, RunnerError> {
    planner_runner::sweep::read_provenance(dir)
        .map_err(|e| planner_runner::readback::damaged("compare", dir, e))
}

/// Compares the records of the results directories `old` and `new` (module docs), listing
/// at most `examples` differing runs.
pub fn compare(old: &Path, new: &Path, examples: usize) -> Result<Comparison, RunnerError> {
    let mut names = Names::default();
    let mut labels: Vec<String> = Vec::new();
    // NEW: each run's digest and time.
    let mut new_runs: HashMap<RunKey, (u64, f64)> = HashMap::new();
    let n_new = pass(new, &mut |r| {
        if !labels.contains(&r.planner) {
            labels.push(r.planner.clone());
        }
        new_runs.insert(run_key(&mut names, &r), (digest(&r), r.time_ms));
    })?;
    // OLD: matched, compared; the times of each problem on both sides.
    let mut times: BTreeMap<ProblemKey, (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    let (mut both, mut differing) = (0u64, 0u64);
    let mut listed: Vec<(RunKey, RunRecord)> = Vec::new();
    let mut listed_problems = std::collections::HashSet::new();
    let n_old = pass(old, &mut |r| {
        let key = run_key(&mut names, &r);
        let Some(&(new_digest, new_time)) = new_runs.get(&key) else {
            return;
        };
        both += 1;
        let problem = times.entry(key.0).or_default();
        problem.0.push(r.time_ms);
        problem.1.push(new_time);
        if digest(&r) != new_digest {
            differing += 1;
            // One run per problem: its other repeats usually differ alike.
            if listed.len() < examples && listed_problems.insert(key.0) {
                listed.push((key, r));
            }
        }
    })?;
    drop(new_runs);
    // NEW again, for the listed runs' records.
    let mut wanted: HashMap<RunKey, usize> = listed
        .iter()
        .enumerate()
        .map(|(i, (key, _))| (*key, i))
        .collect();
    let mut found: Vec<Option<RunRecord>> = vec![None; listed.len()];
    if !wanted.is_empty() {
        pass(new, &mut |r| {
            if let Some(i) = wanted.remove(&run_key(&mut names, &r)) {
                found[i] = Some(r);
            }
        })?;
    }
    let examples = listed
        .iter()
        .zip(found)
        .filter_map(|((_, old), new)| Some(difference(old, &new?)))
        .collect();
    Ok(Comparison {
        dirs: [old.to_path_buf(), new.to_path_buf()],
        runs: [n_old, n_new],
        provenance: [provenance(old)?, provenance(new)?],
        both,
        differing,
        examples,
        times: label_times(&labels, &mut names, &times),
    })
}

/// The differing computed fields of one run in OLD and NEW.
fn difference(old: &RunRecord, new: &RunRecord) -> Difference {
    let (a, b) = (computed(old), computed(new));
    let mut fields = Vec::new();
    let short = |v: Option<&serde_json::Value>| {
        let text = v.map_or("(none)".to_string(), |v| v.to_string());
        match text.chars().count() > 60 {
            true => format!("{}...", text.chars().take(57).collect::<String>()),
            false => text,
        }
    };
    let keys: Vec<&String> = a.keys().chain(b.keys()).collect();
    let mut seen = std::collections::HashSet::new();
    for key in keys {
        if !seen.insert(key) || a.get(key) == b.get(key) {
            continue;
        }
        match (key.as_str(), a.get(key), b.get(key)) {
            (
                "counters",
                Some(serde_json::Value::Object(x)),
                Some(serde_json::Value::Object(y)),
            ) => {
                let names: Vec<&String> = x.keys().chain(y.keys()).collect();
                let mut done = std::collections::HashSet::new();
                for name in names {
                    if done.insert(name) && x.get(name) != y.get(name) {
                        fields.push((
                            format!("counters.{name}"),
                            short(x.get(name)),
                            short(y.get(name)),
                        ));
                    }
                }
            }
            ("path", x, y) => {
                let cells = |v: Option<&serde_json::Value>| {
                    v.and_then(|v| v.as_array()).map_or(0, Vec::len)
                };
                fields.push((
                    "path".into(),
                    format!("{} cells", cells(x)),
                    format!("{} cells (other cells)", cells(y)),
                ));
            }
            (name, x, y) => fields.push((name.to_string(), short(x), short(y))),
        }
    }
    Difference {
        run: format!(
            "label {:?}, map {:?} problem {} {} -> {}, repeat {}",
            new.planner, new.map, new.problem, new.start, new.goal, new.repeat
        ),
        fields,
    }
}

/// Per label, NEW's median time over OLD's per problem both ran with positive times.
fn label_times(
    labels: &[String],
    names: &mut Names,
    times: &BTreeMap<ProblemKey, (Vec<f64>, Vec<f64>)>,
) -> Vec<LabelTimes> {
    let median = |values: &[f64]| crate::median_iqr(values).map(|(m, _, _)| m);
    labels
        .iter()
        .map(|label| {
            let id = names.id(label);
            let ratios: Vec<f64> = times
                .iter()
                .filter(|(key, _)| key.0 == id)
                .filter_map(|(_, (old, new))| {
                    let (old, new) = (median(old)?, median(new)?);
                    (old > 0.0 && new > 0.0).then_some(new / old)
                })
                .collect();
            LabelTimes {
                label: label.clone(),
                problems: ratios.len() as u64,
                ratio: planner_stats::geometric_mean(&ratios, 0.95).ok(),
                faster: ratios.iter().filter(|&&r| r < 1.0).count() as u64,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Problem A: OLD 1, 2, 3 (median 2), NEW 1, 1, 1: ratio 0.5; problem B: OLD 4, NEW 8:
    /// ratio 2; problem C: a zero time, left out. Geometric mean sqrt(0.5 * 2) = 1, NEW
    /// faster on 1 of 2; another label's problem is not this label's.
    #[test]
    fn times_are_compared_per_problem_by_hand() {
        let mut names = Names::default();
        let (a, b) = (names.id("a"), names.id("b"));
        let map = names.id("m.map");
        let key = |label, problem| (label, map, problem, (0, 0), (1, 1));
        let times = BTreeMap::from([
            (key(a, 1), (vec![1.0, 2.0, 3.0], vec![1.0, 1.0, 1.0])),
            (key(a, 2), (vec![4.0], vec![8.0])),
            (key(a, 3), (vec![0.0], vec![8.0])),
            (key(b, 1), (vec![1.0], vec![3.0])),
        ]);
        let labels = ["a".to_string(), "b".to_string()];
        let out = label_times(&labels, &mut names, &times);
        assert_eq!((out[0].problems, out[0].faster), (2, 1));
        let ratio = out[0].ratio.unwrap();
        assert!((ratio.mean - 1.0).abs() < 1e-12);
        assert_eq!((out[1].problems, out[1].faster), (1, 0));
        assert!((out[1].ratio.unwrap().mean - 3.0).abs() < 1e-12);
    }
}
