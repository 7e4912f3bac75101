//! Collision checking of tree edges, shared by RRT, RRT* and RRT-Connect.
//!
//! An edge is the segment between two cell centres; it is free when every cell it touches
//! is free, by planner-api's exact traversal ([`for_each_segment_cell`]), the same rule
//! [`PathRule::AnyAngle`](planner_api::PathRule::AnyAngle) validates paths with. For a
//! diagonal unit move that traversal visits both side cells, so an edge never cuts a
//! blocked corner, and an axis unit move touches only its two cells: unit-move edges are
//! therefore valid exactly when the 4- or 8-connected move without corner cutting is.

use planner_api::{for_each_segment_cell, Cell, Grid};

/// Counts the segment checks and the cells they visit while answering them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct SegmentChecker {
    /// Segments checked.
    pub n_checks: u64,
    /// Cells visited by the checks (a check stops at its first blocked cell).
    pub n_cells: u64,
}

impl SegmentChecker {
    /// Whether the segment from the centre of `from` to the centre of `to` touches only
    /// free cells of `grid` (cells outside the grid count as blocked).
    pub fn is_free(&mut self, grid: &Grid, from: Cell, to: Cell) -> bool {
        self.n_checks += 1;
        let mut n_cells = 0;
        let free = for_each_segment_cell(from, to, |cell| {
            n_cells += 1;
            grid.is_free(cell)
        });
        self.n_cells += n_cells;
        free
    }
}

#[cfg(test)]
mod tests {
    use rand_chacha::rand_core::{RngCore, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    #[test]
    fn counts_checks_and_cells() {
        let grid = Grid::from_ascii("....\n.#..").unwrap();
        let mut checker = SegmentChecker::default();
        assert!(checker.is_free(&grid, Cell::new(0, 0), Cell::new(3, 0)));
        assert_eq!((checker.n_checks, checker.n_cells), (1, 4));
        // (0, 1) -> (3, 1) stops at the blocked (1, 1): two cells visited.
        assert!(!checker.is_free(&grid, Cell::new(0, 1), Cell::new(3, 1)));
        assert_eq!((checker.n_checks, checker.n_cells), (2, 6));
        // The diagonal (0, 1) -> (1, 0) passes the corner shared with the blocked (1, 1):
        // the traversal visits the side cell (1, 1) second and stops there.
        assert!(!checker.is_free(&grid, Cell::new(0, 1), Cell::new(1, 0)));
        assert_eq!((checker.n_checks, checker.n_cells), (3, 8));
    }

    /// RRT* checks an edge once and uses the answer for both directions (choose-parent
    /// checks near -> new, rewiring uses new -> near), so the traversal must be symmetric.
    #[test]
    fn the_traversal_is_symmetric() {
        let mut rng = ChaCha8Rng::from_seed([3; 32]);
        for _ in 0..2000 {
            let mut coordinate = || (rng.next_u64() % 13) as u32;
            let (a, b) = (
                Cell::new(coordinate(), coordinate()),
                Cell::new(coordinate(), coordinate()),
            );
            let mut forward = Vec::new();
            for_each_segment_cell(a, b, |c| {
                forward.push(c);
                true
            });
            let mut backward = Vec::new();
            for_each_segment_cell(b, a, |c| {
                backward.push(c);
                true
            });
            forward.sort();
            backward.sort();
            assert_eq!(forward, backward, "{a} -> {b}");
        }
    }
}
