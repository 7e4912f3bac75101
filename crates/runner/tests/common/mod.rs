//! Helpers that several of planner-runner's test files share.

use std::path::{Path, PathBuf};

use planner_runner::config::{ConfigError, Experiment};
use planner_runner::output::OutputFile;
use planner_runner::record::Reproduction;
use planner_runner::sweep::{Render, Results};
use planner_runner::RunnerError;

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An empty scratch directory for the test `name`, under the target directory (replaced
/// by the next run of the test).
pub fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-runner-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A report step that writes nothing.
pub struct NoReport;

impl Render for NoReport {
    fn check(&self, _: &Experiment) -> Result<(), ConfigError> {
        Ok(())
    }

    fn render(&self, _: &Results<'_>) -> Result<(Vec<OutputFile>, Reproduction), RunnerError> {
        Ok((Vec::new(), Reproduction::default()))
    }
}
