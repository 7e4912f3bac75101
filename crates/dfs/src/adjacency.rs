//! Per-cell masks of the safe moves, built once per grid from a [`MoveSet`].
//!
//! Cells are indexed in a *padded* row-major layout: the grid surrounded by a border of
//! `reach` cells (the longest move's Chebyshev length), so that every neighbour of a grid
//! cell has an index inside the arrays. Bit `m` of `safe[p]` is set when move `m` of the set
//! (in the set's order) may be taken from cell `p`: the target is in bounds and free and
//! every cell the move passes through (`Move::via`) is free, exactly [`MoveSet::apply`].
//! The hot loop then needs no obstacle test: a clear bit is a blocked check, a set bit gives
//! the neighbour as `p + delta[m]`. Masks are `u64`, enough for the largest set (48 moves).

use planner_api::{Cell, Grid, MoveSet};

/// The safe-move masks of one grid and the padded index offset of each move.
#[derive(Debug, Clone)]
pub(crate) struct Adjacency {
    /// The grid the masks were built for: the cache key.
    grid: Grid,
    /// Border width: the longest move's reach.
    reach: usize,
    /// Padded row length, `width + 2 * reach`.
    stride: usize,
    /// Bit `m` set when move `m` is safe from the padded cell (0 for blocked and border cells).
    pub(crate) safe: Vec<u64>,
    /// Padded index offset `dy * stride + dx` of move `m`; entries past the set's size are 0.
    pub(crate) delta: [isize; 64],
    /// Number of moves in the set.
    pub(crate) n_moves: usize,
}

impl Adjacency {
    /// Builds the masks of `grid` for `moves`.
    pub(crate) fn build(grid: &Grid, moves: &MoveSet) -> Adjacency {
        let width = i64::from(grid.width());
        let height = i64::from(grid.height());
        let free = grid.free_cells();
        let reach = moves
            .moves()
            .iter()
            .map(|m| m.dx.unsigned_abs().max(m.dy.unsigned_abs()) as usize)
            .max()
            .unwrap_or(1);
        let stride = grid.width() as usize + 2 * reach;
        let padded_len = stride * (grid.height() as usize + 2 * reach);
        let mut delta = [0isize; 64];
        for (slot, mv) in delta.iter_mut().zip(moves.moves()) {
            // |dy * stride + dx| < 2^33, far inside isize on every supported target.
            *slot = (i64::from(mv.dy) * stride as i64 + i64::from(mv.dx)) as isize;
        }
        let is_free = |x: i64, y: i64| {
            x >= 0 && y >= 0 && x < width && y < height && free[(y * width + x) as usize]
        };
        let mut safe = vec![0u64; padded_len];
        for (index, &cell_free) in free.iter().enumerate() {
            if !cell_free {
                continue;
            }
            let (x, y) = (index as i64 % width, index as i64 / width);
            let mut mask = 0u64;
            for (m, mv) in moves.moves().iter().enumerate() {
                let ok = is_free(x + i64::from(mv.dx), y + i64::from(mv.dy))
                    && mv
                        .via
                        .iter()
                        .all(|&(vx, vy)| is_free(x + i64::from(vx), y + i64::from(vy)));
                if ok {
                    mask |= 1 << m;
                }
            }
            safe[(y as usize + reach) * stride + x as usize + reach] = mask;
        }
        Adjacency {
            grid: grid.clone(),
            reach,
            stride,
            safe,
            delta,
            n_moves: moves.moves().len(),
        }
    }

    /// Whether these masks were built for `grid`.
    pub(crate) fn is_for(&self, grid: &Grid) -> bool {
        self.grid == *grid
    }

    /// Number of padded cells: the length of per-cell arrays indexed like `safe`.
    pub(crate) fn padded_len(&self) -> usize {
        self.safe.len()
    }

    /// The padded index of `cell`. Precondition: the cell is in the grid.
    pub(crate) fn index(&self, cell: Cell) -> usize {
        (cell.y as usize + self.reach) * self.stride + cell.x as usize + self.reach
    }

    /// The cell at padded index `p`. Precondition: `p` is a grid cell, not a border cell.
    pub(crate) fn cell(&self, p: usize) -> Cell {
        // Both coordinates are below the grid's u32 sides.
        Cell::new(
            (p % self.stride - self.reach) as u32,
            (p / self.stride - self.reach) as u32,
        )
    }

    /// The neighbour of padded cell `p` by move `m`. Precondition: bit `m` of `safe[p]` is set.
    #[inline(always)]
    pub(crate) fn neighbor(&self, p: usize, m: u32) -> usize {
        p.wrapping_add_signed(self.delta[(m & 63) as usize])
    }
}

/// Returns the cached masks for `grid`, rebuilding them when the grid changed.
pub(crate) fn cached<'a>(
    cache: &'a mut Option<Adjacency>,
    grid: &Grid,
    moves: &MoveSet,
) -> &'a Adjacency {
    match cache {
        Some(adjacency) if adjacency.is_for(grid) => {}
        _ => *cache = Some(Adjacency::build(grid, moves)),
    }
    match cache {
        Some(adjacency) => adjacency,
        None => unreachable!("the adjacency cache was just filled"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_api::{Connectivity, NeighborOrder};

    #[test]
    fn masks_agree_with_move_set_apply() {
        let grid = Grid::from_ascii(
            "
            ..#...
            .#..#.
            ......
            ##.#..
            ",
        )
        .unwrap();
        for (connectivity, cutting) in [
            (Connectivity::Four, false),
            (Connectivity::Eight, false),
            (Connectivity::Eight, true),
            (Connectivity::Sixteen, false),
        ] {
            let moves = MoveSet::new(connectivity, cutting, &NeighborOrder::default()).unwrap();
            let adjacency = Adjacency::build(&grid, &moves);
            for cell in grid.cells() {
                let index = adjacency.index(cell);
                assert_eq!(adjacency.cell(index), cell);
                for (m, mv) in moves.moves().iter().enumerate() {
                    let expect = if grid.is_free(cell) {
                        moves.apply(&grid, cell, mv)
                    } else {
                        None
                    };
                    let bit = adjacency.safe[index] >> m & 1 == 1;
                    assert_eq!(bit, expect.is_some(), "{connectivity} {cell} move {m}");
                    if let Some(to) = expect {
                        assert_eq!(adjacency.cell(adjacency.neighbor(index, m as u32)), to);
                    }
                }
            }
        }
    }
}
