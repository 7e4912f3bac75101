//! Replanning experiment configs (`kind = "navigate"` / `"dynamic"`, issue 31):
//! `planner_replan::experiment::parse` never panics, and an error's line and column lie
//! inside the text (0: the whole file or line). Parsed as if read from
//! `configs/replan/fuzz.toml`; parsing reads no file.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use planner_replan::experiment::{parse, ExperimentError};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let lines: Vec<&str> = text.split('\n').collect();
    let (line, column) = match parse(Path::new("configs/replan/fuzz.toml"), text) {
        Ok(_) => return,
        Err(ExperimentError::Parse { line, column, .. })
        | Err(ExperimentError::Invalid { line, column, .. }) => (line, column),
        Err(e) => panic!("parsing alone gave {e}"),
    };
    assert!(line <= lines.len(), "line {line} of {}", lines.len());
    if line > 0 {
        let width = lines[line - 1].chars().count();
        assert!(column <= width + 1, "column {column} of a line of {width}");
    }
});
