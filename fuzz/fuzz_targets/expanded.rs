//! A results directory's `expanded.jsonl` (the cells each drawn run expanded, read back by
//! `report`): `ExpandedCells::from_jsonl` never panics; an error names a line inside the
//! text; what reads writes back (`to_jsonl`) to text that reads to the same cells.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_runner::expanded::ExpandedCells;
use planner_runner::stream::Place;
use planner_runner::RunnerError;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match ExpandedCells::from_jsonl(text, "expanded.jsonl") {
        Ok(cells) => {
            let written = cells.to_jsonl().expect("cells serialize");
            let again = String::from_utf8(written).expect("JSON is UTF-8");
            let reread = ExpandedCells::from_jsonl(&again, "again").expect("written cells read");
            assert_eq!(again.into_bytes(), reread.to_jsonl().expect("cells serialize"));
        }
        Err(RunnerError::Stream(error)) => {
            let Place::Line(line) = error.place else {
                panic!("{error}: not at a line");
            };
            assert!(line >= 1 && line as usize <= text.lines().count(), "{error}");
        }
        Err(other) => panic!("{other}"),
    }
});
