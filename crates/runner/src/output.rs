//! The sweep's result files as bytes: runs.csv and runs.json. Writing them to disk (and
//! replacing a results directory safely) is the binary's job.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::config::Experiment;
use crate::record::RunRecord;
use crate::RunnerError;

/// A file of the results directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct OutputFile {
    /// Relative path, e.g. `figures/map01-1-astar.svg`.
    pub path: PathBuf,
    /// Contents.
    pub contents: Vec<u8>,
}

/// The runs as JSON: `{"experiment": ..., "config": ..., "runs": [...]}`, one record per
/// line (compact: a sweep's file stays a few times the CSV's size), each record's fields
/// and counters in their order (the planner's, for counters).
///
/// With `provenance`, the header also holds it (`"provenance"`) and every label's resolved
/// parameters (`"planners"`).
pub fn runs_json(experiment: &Experiment, records: &[RunRecord]) -> Result<Vec<u8>, RunnerError> {
    runs_json_with(experiment, records, None)
}

/// [`runs_json`] with the sweep's provenance and the labels' resolved parameters.
pub fn runs_json_with(
    experiment: &Experiment,
    records: &[RunRecord],
    provenance: Option<&crate::provenance::Provenance>,
) -> Result<Vec<u8>, RunnerError> {
    let mut out = Vec::with_capacity(records.len() * 256 + 128);
    out.extend_from_slice(b"{\"experiment\":");
    serde_json::to_writer(&mut out, &experiment.name).map_err(RunnerError::Json)?;
    out.extend_from_slice(b",\"config\":");
    serde_json::to_writer(&mut out, &experiment.source.display().to_string())
        .map_err(RunnerError::Json)?;
    if let Some(provenance) = provenance {
        out.extend_from_slice(b",\"provenance\":");
        serde_json::to_writer(&mut out, provenance).map_err(RunnerError::Json)?;
        let planners: serde_json::Map<String, serde_json::Value> = experiment
            .planners
            .iter()
            .map(|p| {
                let entry = serde_json::json!({
                    "planner": p.name,
                    "parameters": p.factory.resolved(),
                    "budget": p.budget,
                });
                (p.label.clone(), entry)
            })
            .collect();
        out.extend_from_slice(b",\"planners\":");
        serde_json::to_writer(&mut out, &planners).map_err(RunnerError::Json)?;
    }
    out.extend_from_slice(b",\"runs\":[");
    for (i, record) in records.iter().enumerate() {
        out.extend_from_slice(if i == 0 { b"\n" } else { b",\n" });
        serde_json::to_writer(&mut out, record).map_err(RunnerError::Json)?;
    }
    out.extend_from_slice(b"\n]}\n");
    Ok(out)
}

/// The runs as CSV: fixed columns, then one column per counter name in order of first
/// appearance; a run without that counter leaves the cell empty.
pub fn runs_csv(records: &[RunRecord]) -> Vec<u8> {
    let mut counter_names: Vec<String> = Vec::new();
    for record in records {
        for (name, _) in record.counters.iter() {
            if !counter_names.iter().any(|n| n == name) {
                counter_names.push(name.to_string());
            }
        }
    }
    let mut out = String::from(
        "map,problem,start_x,start_y,goal_x,goal_y,planner,algorithm,repeat,seed,status,steps,turns,score,length,optimal_length,valid,time_ms,setup_ms,peak_heap_bytes,bucket",
    );
    for name in &counter_names {
        out.push(',');
        out.push_str(name);
    }
    out.push('\n');
    let opt = |v: Option<String>| v.unwrap_or_default();
    for r in records {
        let fields = [
            csv_field(&r.map),
            r.problem.to_string(),
            r.start.x.to_string(),
            r.start.y.to_string(),
            r.goal.x.to_string(),
            r.goal.y.to_string(),
            csv_field(&r.planner),
            csv_field(&r.algorithm),
            r.repeat.to_string(),
            opt(r.seed.map(|s| s.to_string())),
            r.status.to_string(),
            opt(r.steps.map(|v| v.to_string())),
            opt(r.turns.map(|v| v.to_string())),
            opt(r.score.map(|v| v.to_string())),
            opt(r.length.map(|v| format!("{v:.6}"))),
            opt(r.optimal_length.map(|v| format!("{v:.6}"))),
            opt(r.valid.map(|v| v.to_string())),
            format!("{:.6}", r.time_ms),
            format!("{:.6}", r.setup_ms),
            r.peak_heap_bytes.to_string(),
            opt(r.bucket.map(|b| b.to_string())),
        ];
        out.push_str(&fields.join(","));
        for name in &counter_names {
            out.push(',');
            if let Some(v) = r.counters.get(name) {
                let _ = write!(out, "{v}");
            }
        }
        out.push('\n');
    }
    out.into_bytes()
}

fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// The kept paths as JSON Lines, one `{"map","problem","planner","repeat","path"}` object per
/// record that has a path, in record order (`paths.jsonl`; runs.json then leaves `path`
/// null). `None` when no record has a path.
pub fn paths_jsonl(records: &[RunRecord]) -> Result<Option<Vec<u8>>, RunnerError> {
    #[derive(serde::Serialize)]
    struct Line<'a> {
        map: &'a str,
        problem: usize,
        planner: &'a str,
        repeat: u32,
        path: &'a planner_api::Path,
    }
    let mut out = Vec::new();
    for r in records {
        if let Some(path) = &r.path {
            let line = Line {
                map: &r.map,
                problem: r.problem,
                planner: &r.planner,
                repeat: r.repeat,
                path,
            };
            serde_json::to_writer(&mut out, &line).map_err(RunnerError::Json)?;
            out.push(b'\n');
        }
    }
    Ok((!out.is_empty()).then_some(out))
}
