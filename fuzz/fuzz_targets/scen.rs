//! Moving AI `.scen` reader: never panics; every scenario's line is inside the text, an
//! error's too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::parse_scenarios;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let n_lines = text.split('\n').count();
    match parse_scenarios(text, "fuzz.scen") {
        Ok(scenarios) => {
            for s in &scenarios {
                assert!(s.line >= 2 && s.line <= n_lines, "line {}", s.line);
                assert!(s.optimal_length.is_finite() && s.optimal_length >= 0.0);
                let _ = s.map_name();
            }
        }
        Err(err) => {
            assert!(err.line <= n_lines, "{err} ({n_lines} lines)");
            let _ = err.to_string();
        }
    }
});
