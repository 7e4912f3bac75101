//! JPS+ jump distances (Harabor and Grastien 2014, section "Preprocessing-based Symmetry
//! Breaking"): for every cell and each of the eight directions, where the jump from that
//! cell ends when the goal is not on the way.
//!
//! An entry `k > 0` says the jump reaches a jump point `k` cells on; `k <= 0` says it
//! ends at a wall after `-k` free cells (0: the first move is not allowed). A straight
//! jump point is a forced cell (`BitGrid::forced`); a diagonal one is a cell from which a
//! straight jump along one of the two component directions reaches a jump point. These are
//! the online jumps' rules exactly, so JPS+ expands the same jump points as online JPS
//! except where the goal is near (see the crate docs on target jump points).

use crate::bits::{diagonal, BitGrid, DX, DY};

/// The jump distances of one grid, eight per cell, row-major.
#[derive(Debug, Clone, Default)]
pub(crate) struct JumpTable {
    width: usize,
    distances: Vec<[i32; 8]>,
}

impl JumpTable {
    /// The distances for `bits`, computed by dynamic programming in eight sweeps (each
    /// direction's entry depends on the neighbour's in that direction).
    pub(crate) fn build(bits: &BitGrid) -> JumpTable {
        let (w, h) = (bits.width() as usize, bits.height() as usize);
        let mut distances = vec![[0i32; 8]; w * h];
        // Straight directions first: the diagonal ones read them.
        for dir in 0..8 {
            let (dx, dy) = (DX[dir], DY[dir]);
            // Visit every cell after its neighbour in direction `dir`.
            let xs: Vec<usize> = if dx > 0 {
                (0..w).rev().collect()
            } else {
                (0..w).collect()
            };
            let ys: Vec<usize> = if dy > 0 {
                (0..h).rev().collect()
            } else {
                (0..h).collect()
            };
            for &y in &ys {
                for &x in &xs {
                    let (nx, ny) = (x as i32 + dx, y as i32 + dy);
                    let allowed = bits.free(nx, ny)
                        && (dir < 4 || (bits.free(nx, y as i32) && bits.free(x as i32, ny)));
                    let entry = if !allowed {
                        0
                    } else {
                        let next = &distances[ny as usize * w + nx as usize];
                        let stops = if dir < 4 {
                            bits.forced(nx, ny, dir)
                        } else {
                            next[usize::from(dx < 0)] > 0 || next[2 + usize::from(dy < 0)] > 0
                        };
                        if stops {
                            1
                        } else if next[dir] > 0 {
                            next[dir] + 1
                        } else {
                            next[dir] - 1
                        }
                    };
                    distances[y * w + x][dir] = entry;
                }
            }
        }
        debug_assert!((0..8).all(|d| d < 4 || diagonal(DX[d], DY[d]) == d));
        JumpTable {
            width: w,
            distances,
        }
    }

    /// The eight entries of cell `(x, y)`.
    #[inline(always)]
    pub(crate) fn entries(&self, x: u32, y: u32) -> &[i32; 8] {
        &self.distances[y as usize * self.width + x as usize]
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.distances.len() * std::mem::size_of::<[i32; 8]>()
    }
}
