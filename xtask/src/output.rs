//! Writing a sweep's results directory atomically: runs.csv, runs.json, summary.md, figures.
//!
//! Everything is written into a fresh sibling directory `.<name>.partial`, which then
//! replaces the output directory by two renames (old aside, new in place) and the old one
//! is removed. A failed or interrupted sweep therefore never leaves a half-written file in
//! the output directory: either the previous results are there untouched (or, if the
//! process dies between the two renames, under `.<name>.previous`), or the new ones are.

use std::fs;
use std::path::{Path, PathBuf};

use planner_runner::output::OutputFile;

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
