//! The bit-packed line of sight ([`SightGrid::walk`]) against planner-api's
//! [`walk_segment`]: the same answer and the same cell count (up to and including the first
//! blocked cell) on every segment between random cells of seeded random maps, of sides that
//! straddle the 64-bit words, at densities from empty to mostly blocked, and with ends
//! outside the grid.

use planner_api::{walk_segment, Cell, Grid};
use planner_theta_star::SightGrid;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_grid(rng: &mut ChaCha8Rng, width: u32, height: u32, density: f64) -> Grid {
    let free = (0..width as usize * height as usize)
        .map(|_| !rng.gen_bool(density))
        .collect();
    Grid::from_free_cells(width, height, free).unwrap()
}

#[test]
fn agrees_with_walk_segment_on_random_segments() {
    let mut rng = ChaCha8Rng::seed_from_u64(30);
    let (mut n_segments, mut n_free, mut n_blocked_late) = (0u64, 0u64, 0u64);
    for round in 0..300 {
        let width = rng.gen_range(1..=200u32);
        let height = rng.gen_range(1..=200u32);
        let density = [0.0, 0.01, 0.05, 0.2, 0.5, 0.9][round % 6];
        let grid = random_grid(&mut rng, width, height, density);
        let sight = SightGrid::new(&grid);
        assert!(sight.is_for(&grid));
        for _ in 0..400 {
            let a = Cell::new(rng.gen_range(0..width), rng.gen_range(0..height));
            // Short segments often (Theta*'s), and ones along a row, a column or a diagonal.
            let b = match rng.gen_range(0..4) {
                0 => Cell::new(rng.gen_range(0..width), rng.gen_range(0..height)),
                1 => Cell::new(
                    a.x.saturating_add_signed(rng.gen_range(-5..=5))
                        .min(width - 1),
                    a.y.saturating_add_signed(rng.gen_range(-5..=5))
                        .min(height - 1),
                ),
                2 => {
                    let d = rng.gen_range(-60i32..=60);
                    Cell::new(
                        a.x.saturating_add_signed(d).min(width - 1),
                        a.y.saturating_add_signed(d * [1, -1][rng.gen_range(0..2)])
                            .min(height - 1),
                    )
                }
                _ => {
                    // Slopes with many exact vertex crossings: odd multiples of (1, 1),
                    // (3, 1), (1, 3), (3, 5), ...
                    let (p, q) =
                        [(1, 1), (3, 1), (1, 3), (3, 5), (5, 3), (7, 1)][rng.gen_range(0..6)];
                    let k = 2 * rng.gen_range(0..8) + 1;
                    let (sx, sy) = (rng.gen_range(0..2) * 2 - 1, rng.gen_range(0..2) * 2 - 1);
                    Cell::new(
                        a.x.saturating_add_signed(sx * p * k).min(width - 1),
                        a.y.saturating_add_signed(sy * q * k).min(height - 1),
                    )
                }
            };
            let expected = walk_segment(&grid, a, b);
            assert_eq!(
                sight.walk(&grid, a, b),
                expected,
                "{width}x{height} density {density}: {a} to {b}"
            );
            n_segments += 1;
            n_free += u64::from(expected.free);
            n_blocked_late += u64::from(!expected.free && expected.n_cells > 2);
        }
    }
    // The segments cover both outcomes, and blocked cells past the first steps.
    assert_eq!(n_segments, 120_000);
    assert!(
        n_free > 30_000 && n_blocked_late > 10_000,
        "{n_free} {n_blocked_late}"
    );
}

#[test]
fn every_segment_of_small_maps() {
    // All pairs of cells of small random maps: every slope and vertex pattern there is.
    let mut rng = ChaCha8Rng::seed_from_u64(31);
    for round in 0..40 {
        let (width, height) = (rng.gen_range(1..=13u32), rng.gen_range(1..=13u32));
        let grid = random_grid(&mut rng, width, height, [0.1, 0.3][round % 2]);
        let sight = SightGrid::new(&grid);
        let cells: Vec<Cell> = grid.cells().collect();
        for &a in &cells {
            for &b in &cells {
                assert_eq!(
                    sight.walk(&grid, a, b),
                    walk_segment(&grid, a, b),
                    "{a} to {b}"
                );
            }
        }
    }
}

#[test]
fn ends_outside_the_grid_go_to_walk_segment() {
    let grid = Grid::from_ascii("....\n.#..\n....").unwrap();
    let sight = SightGrid::new(&grid);
    for (a, b) in [
        (Cell::new(0, 0), Cell::new(9, 1)),
        (Cell::new(5, 5), Cell::new(0, 0)),
        (Cell::new(0, 2), Cell::new(3, 7)),
    ] {
        assert_eq!(
            sight.walk(&grid, a, b),
            walk_segment(&grid, a, b),
            "{a} to {b}"
        );
    }
}

#[test]
fn a_cache_rebuilds_for_another_grid() {
    let open = Grid::from_ascii("....\n....").unwrap();
    let wall = Grid::from_ascii("..#.\n..#.").unwrap();
    let mut cache = None;
    let (a, b) = (Cell::new(0, 0), Cell::new(3, 1));
    assert!(SightGrid::cached(&mut cache, &open).walk(&open, a, b).free);
    assert!(!SightGrid::cached(&mut cache, &wall).walk(&wall, a, b).free);
    // An equal grid of another revision is recognised, not rebuilt wrongly.
    let copy = Grid::from_ascii("..#.\n..#.").unwrap();
    assert!(SightGrid::cached(&mut cache, &copy).is_for(&copy));
    assert!(SightGrid::cached(&mut cache, &open).walk(&open, a, b).free);
}
