//! Cell cost readers: a weight `.csv` (`parse_weights`) for a map of a size taken from the
//! first two bytes (1-64 x 1-64), and a graded image (`mode: scale` or `raw` by the third
//! byte, nav2's bands with `lethal` and `unknown` from the next two) through
//! `ros_map_from_image_bytes`, cap 2^16 cells. Never panics; a weight file gives exactly
//! width x height weights, each from 1 to 65535, or an error whose line and column lie
//! inside the text; a graded map's weights are one per cell, from 1, and blocked cells
//! are exactly those the bands block.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::{parse_weights, CostBands, CostOptions, ReadOptions, RosMode, RosYaml};

fuzz_target!(|data: &[u8]| {
    if data.len() < 5 {
        return;
    }
    let (width, height) = (u32::from(data[0] % 64) + 1, u32::from(data[1] % 64) + 1);
    let rest = &data[5..];
    if let Ok(text) = std::str::from_utf8(rest) {
        match parse_weights(text, "fuzz.csv", width, height) {
            Ok(weights) => {
                assert_eq!(weights.len() as u64, u64::from(width) * u64::from(height));
                assert!(weights.iter().all(|&w| w >= 1));
            }
            Err(err) => {
                let n_lines = text.split('\n').count();
                assert!(err.line >= 1 && err.line <= n_lines, "{err} ({n_lines} lines)");
                let line = text.split('\n').nth(err.line - 1).unwrap_or("");
                assert!(
                    err.column >= 1 && err.column <= line.chars().count() + 1,
                    "{err}: line {line:?}"
                );
            }
        }
    }
    let mut yaml = RosYaml::defaults("fuzz.pgm");
    yaml.mode = if data[2] % 2 == 0 {
        RosMode::Scale
    } else {
        RosMode::Raw
    };
    let bands = CostBands {
        lethal: data[3].max(1),
        unknown: (data[4] < 255).then_some(data[4]),
    };
    let options = ReadOptions {
        max_cells: 1 << 16,
        costs: CostOptions {
            graded: true,
            bands,
            ..CostOptions::default()
        },
        ..ReadOptions::default()
    };
    if let Ok(map) = planner_maps::ros_map_from_image_bytes(rest, "fuzz.pgm", Some(yaml), &options)
    {
        let grid = &map.grid;
        assert_eq!(map.occupancy.len(), grid.len());
        if let Some(weights) = grid.weights() {
            assert_eq!(weights.cells().len(), grid.len());
            assert!(weights.min() >= 1);
            for (i, &occupancy) in map.occupancy.iter().enumerate() {
                let passable = bands.weight(planner_maps::costmap_cost(occupancy)).is_some();
                if !passable {
                    assert!(!grid.free_cells()[i], "cell {i}: occupancy {occupancy}");
                }
            }
        }
    }
});
