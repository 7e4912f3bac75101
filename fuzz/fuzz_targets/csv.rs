//! `.csv` matrix reader: never panics; the two conventions agree on errors and read
//! complementary grids; the inversion hint is consistent with them.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_api::Cell;
use planner_maps::{csv_inversion_hint, CsvConvention, MapFormat, ReadOptions};

fuzz_target!(|data: &[u8]| {
    let read = |csv| {
        let options = ReadOptions {
            max_cells: 1 << 20,
            csv,
            ..ReadOptions::default()
        };
        MapFormat::Matrix.parse_bytes(data, "fuzz.csv", &options)
    };
    let zero = read(CsvConvention::ZeroIsObstacle);
    let one = read(CsvConvention::OneIsObstacle);
    match (zero, one) {
        (Ok(a), Ok(b)) => {
            let (a, b) = (a.file.grid, b.file.grid);
            assert_eq!((a.width(), a.height()), (b.width(), b.height()));
            assert!(a
                .free_cells()
                .iter()
                .zip(b.free_cells())
                .all(|(x, y)| x != y));
            let corner = Cell::new(a.width() - 1, a.height() - 1);
            let hint =
                csv_inversion_hint(&a, CsvConvention::ZeroIsObstacle, Cell::new(0, 0), corner);
            assert_eq!(
                hint.is_some(),
                b.is_free(Cell::new(0, 0)) && b.is_free(corner)
            );
        }
        (Err(a), Err(b)) => {
            assert_eq!(a, b);
            let n_lines = data.iter().filter(|&&b| b == b'\n').count() + 1;
            assert!(a.line <= n_lines, "{a} ({n_lines} lines)");
        }
        (a, b) => panic!("conventions disagree: {:?} / {:?}", a.err(), b.err()),
    }
});
