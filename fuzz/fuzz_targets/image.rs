//! Image decoding (PGM, PNG) as a map, with a 2^16-cell cap and an inflation radius of
//! `len % 5`: never panics, never decodes more than the cap, one occupancy value per cell.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_maps::{MapFormat, ReadOptions, RosOptions};

fuzz_target!(|data: &[u8]| {
    let options = ReadOptions {
        max_cells: 1 << 16,
        ros: RosOptions {
            inflation_radius: (data.len() % 5) as u32,
            inflate_unknown: data.len() % 2 == 0,
        },
        ..ReadOptions::default()
    };
    match planner_maps::ros_map_from_image_bytes(data, "fuzz.png", None, &options) {
        Ok(map) => {
            assert!(map.grid.len() as u64 <= options.max_cells);
            assert_eq!(map.occupancy.len(), map.grid.len());
        }
        Err(err) => {
            assert_eq!((err.line, err.column), (0, 0), "{err}");
            let _ = err.to_string();
        }
    }
    // The same bytes through the format dispatch.
    let _ = MapFormat::Image.parse_bytes(data, "fuzz.pgm", &options);
});
