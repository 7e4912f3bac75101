//! Seed 002's tables (stub).
use crate::config::Experiment;
use crate::run::RunRecord;

/// Renders nothing yet.
pub fn render(_experiment: &Experiment, _records: &[RunRecord]) -> String {
    String::new()
}
