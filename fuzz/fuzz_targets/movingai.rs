//! Moving AI `.map` reader: never panics; a grid it reads writes back to the same grid;
//! an error's line is inside the text.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::{parse_movingai, to_movingai, MapFormat, ReadOptions};

fuzz_target!(|data: &[u8]| {
    let options = ReadOptions {
        max_cells: 1 << 20,
        ..ReadOptions::default()
    };
    match MapFormat::MovingAi.parse_bytes(data, "fuzz.map", &options) {
        Ok(read) => {
            let text = to_movingai(&read.file.grid);
            assert_eq!(
                parse_movingai(&text, "again.map").ok(),
                Some(read.file.grid)
            );
        }
        Err(err) => {
            let n_lines = data.iter().filter(|&&b| b == b'\n').count() + 1;
            assert!(err.line <= n_lines, "{err} ({n_lines} lines)");
            let _ = err.to_string();
        }
    }
});
