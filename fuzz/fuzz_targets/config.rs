//! Experiment configs and published-values files: `planner_runner::config::parse` and
//! `parse_published` never panic on any bytes, and an error's line is inside the text.
//!
//! The config is parsed as if it were `configs/fuzz.toml`, so the seeds' relative map
//! paths (`../maps/...`) resolve to the repository's maps and a mutated config reads real
//! map, scenario and published files. The same text is also parsed as a published-values
//! file.
#![no_main]

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use libfuzzer_sys::fuzz_target;
use planner_runner::config::{parse, parse_published, ConfigError};

fn origin() -> &'static Path {
    static ORIGIN: OnceLock<PathBuf> = OnceLock::new();
    ORIGIN.get_or_init(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../configs/fuzz.toml"))
}

/// The error's line is 0 (the whole file) or one of the text's lines.
fn check_position(error: &ConfigError, text: &str) {
    if error.file == origin() {
        let n_lines = text.split('\n').count();
        assert!(error.line <= n_lines, "{error} ({n_lines} lines)");
    }
}

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Err(error) = parse(origin(), text) {
        check_position(&error, text);
    }
    if let Err(error) = parse_published(origin(), text) {
        check_position(&error, text);
    }
});
