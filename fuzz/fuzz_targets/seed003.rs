//! Seed 003 `.txt` reader: never panics; pairs and errors name lines inside the text.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::{MapFormat, ReadOptions};

fuzz_target!(|data: &[u8]| {
    let options = ReadOptions {
        max_cells: 1 << 20,
        ..ReadOptions::default()
    };
    let n_lines = data.iter().filter(|&&b| b == b'\n').count() + 1;
    match MapFormat::Seed003.parse_bytes(data, "fuzz.txt", &options) {
        Ok(read) => {
            for spec in &read.file.problems {
                assert!(spec.line >= 1 && spec.line <= n_lines);
                // Validation against the grid may fail, but must not panic.
                let _ = spec.problem(&read.file.grid).map_err(|e| e.to_string());
            }
        }
        Err(err) => {
            assert!(err.line <= n_lines, "{err} ({n_lines} lines)");
            let _ = err.to_string();
        }
    }
});
