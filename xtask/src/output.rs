//! Writing a sweep's results atomically: runs.csv, runs.json, summary.md, figures.
//!
//! Everything is written into a fresh sibling directory `.<name>.partial`, which then
//! replaces the output directory by two renames (old aside, new in place) and the old one
//! is removed. A failed or interrupted sweep therefore never leaves a half-written file in
//! the output directory: either the previous results are there untouched (or, if the
//! process dies between the two renames, under `.<name>.previous`), or the new ones are.

use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use crate::config::Experiment;
use crate::run::RunRecord;

/// A file to write, relative to the output directory.
pub struct OutputFile {
    /// Relative path, e.g. `figures/map01-1-astar.svg`.
    pub path: PathBuf,
    /// Contents.
    pub contents: Vec<u8>,
}

/// Writes `files` as the new contents of `dir`, atomically as described in the module docs.
pub fn write_atomically(dir: &Path, files: &[OutputFile]) -> Result<(), String> {
    let name = dir
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .ok_or_else(|| format!("output directory {} has no name", dir.display()))?;
    let parent = dir.parent().map(Path::to_path_buf).unwrap_or_default();
    let parent = if parent.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        parent
    };
    fs::create_dir_all(&parent).map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    let partial = parent.join(format!(".{name}.partial"));
    let previous = parent.join(format!(".{name}.previous"));
    for stale in [&partial, &previous] {
        if stale.exists() {
            fs::remove_dir_all(stale)
                .map_err(|e| format!("cannot remove {}: {e}", stale.display()))?;
        }
    }
    let result = (|| {
        for file in files {
            let target = partial.join(&file.path);
            if let Some(dir) = target.parent() {
                fs::create_dir_all(dir)
                    .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
            }
            fs::write(&target, &file.contents)
                .map_err(|e| format!("cannot write {}: {e}", target.display()))?;
        }
        if dir.exists() {
            fs::rename(dir, &previous)
                .map_err(|e| format!("cannot move {} aside: {e}", dir.display()))?;
        }
        fs::rename(&partial, dir)
            .map_err(|e| format!("cannot move results into {}: {e}", dir.display()))?;
        if previous.exists() {
            fs::remove_dir_all(&previous)
                .map_err(|e| format!("cannot remove {}: {e}", previous.display()))?;
        }
        Ok(())
    })();
    if result.is_err() && partial.exists() {
        let _ = fs::remove_dir_all(&partial);
    }
    result
}

/// The runs as JSON: `{"experiment": ..., "runs": [...]}`.
pub fn runs_json(experiment: &Experiment, records: &[RunRecord]) -> Result<Vec<u8>, String> {
    let value = serde_json::json!({
        "experiment": experiment.name,
        "config": experiment.source.display().to_string(),
        "runs": records,
    });
    let mut text = serde_json::to_string_pretty(&value).map_err(|e| e.to_string())?;
    text.push('\n');
    Ok(text.into_bytes())
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
        "map,problem,start_x,start_y,goal_x,goal_y,planner,algorithm,repeat,seed,status,steps,turns,score,length,optimal_length,valid,time_ms,peak_heap_bytes",
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
            r.status.clone(),
            opt(r.steps.map(|v| v.to_string())),
            opt(r.turns.map(|v| v.to_string())),
            opt(r.score.map(|v| v.to_string())),
            opt(r.length.map(|v| format!("{v:.6}"))),
            opt(r.optimal_length.map(|v| format!("{v:.6}"))),
            opt(r.valid.map(|v| v.to_string())),
            format!("{:.6}", r.time_ms),
            r.peak_heap_bytes.to_string(),
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
