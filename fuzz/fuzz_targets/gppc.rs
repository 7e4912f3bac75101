//! GPPC dynamic-track files (issue 31): the version-2 scenario reader and the patch-file
//! reader never panic; an error's line and column lie inside its text; a read scenario's
//! commands lie inside it and a read patch has one cell per `width x height`; a scenario
//! that validates against the patches places them on a map of its size (at most 2^16
//! cells) with every changed cell inside the map.
//!
//! The input is the scenario text, a NUL byte, then the patch text (without a NUL, the
//! same text is read as both).
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_api::Grid;
use planner_maps::gppc::{parse_gppc_patches, parse_gppc_scenario, GppcCommand};
use planner_maps::MapError;

/// Asserts that `err` points inside `text` (column 0: the whole line).
fn inside(err: &MapError, text: &str) {
    let lines: Vec<&str> = text.split('\n').collect();
    assert!(err.line >= 1 && err.line <= lines.len(), "{err} ({} lines)", lines.len());
    let line = lines[err.line - 1].strip_suffix('\r').unwrap_or(lines[err.line - 1]);
    let width = line.chars().count();
    assert!(err.column <= width + 1, "{err} (line of {width} characters)");
    let _ = err.to_string();
}

fuzz_target!(|data: &[u8]| {
    let (scen_bytes, patch_bytes) = match data.iter().position(|&b| b == 0) {
        Some(at) => (&data[..at], &data[at + 1..]),
        None => (data, data),
    };
    let (Ok(scen_text), Ok(patch_text)) = (
        std::str::from_utf8(scen_bytes),
        std::str::from_utf8(patch_bytes),
    ) else {
        return;
    };
    let scenario = parse_gppc_scenario(scen_text, "fuzz.scen");
    let patches = parse_gppc_patches(patch_text, "fuzz.patch");
    let n_lines = scen_text.split('\n').count();
    if let Ok(s) = &scenario {
        for command in &s.commands {
            let line = match *command {
                GppcCommand::Patch { line, .. } | GppcCommand::Query { line, .. } => line,
            };
            assert!(line >= 1 && line <= n_lines, "command line {line}");
            if let GppcCommand::Query { cost: Some(c), .. } = *command {
                assert!(c.is_finite() && c >= 0.0, "cost {c}");
            }
        }
    }
    if let Ok(set) = &patches {
        for p in &set.patches {
            assert_eq!(p.free.len() as u64, u64::from(p.width) * u64::from(p.height));
        }
    }
    match (&scenario, &patches) {
        (Err(e), _) => inside(e, scen_text),
        (_, Err(e)) => inside(e, patch_text),
        (Ok(s), Ok(set)) => match s.validate(set, "fuzz.scen") {
            Err(e) => inside(&e, scen_text),
            Ok(()) => {
                if u64::from(s.width) * u64::from(s.height) > 1 << 16 {
                    return;
                }
                let Ok(mut grid) = Grid::new(s.width, s.height) else {
                    return;
                };
                for command in &s.commands {
                    if let GppcCommand::Patch { patch, x, y, .. } = *command {
                        for change in set.apply(&mut grid, patch, x, y) {
                            assert!(grid.contains(change.cell));
                            assert_eq!(grid.is_free(change.cell), change.free);
                        }
                    }
                }
            }
        },
    }
});
