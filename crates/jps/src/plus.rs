//! JPS+ jump distances (Harabor and Grastien 2014, section "Preprocessing-based Symmetry
//! Breaking"): for every cell and each of the eight directions, where the jump from that
//! cell ends when the goal is not on the way.
//!
//! An entry `k > 0` says the jump reaches a jump point `k` cells on; `k <= 0` says it
//! ends at a wall after `-k` free cells (0: the first move is not allowed). Entries are
//! one byte (the table is read once or more per expansion, so its size is what decides
//! how much of it the cache holds); a jump of 127 cells or more is stored as a *far*
//! entry ([`FAR_JUMP`], [`FAR_WALL`]) that says to move [`SPAN`] = 63 cells and read
//! again, so any grid size works. A straight
//! jump point is a forced cell (`BitGrid::forced`); a diagonal one is a cell from which a
//! straight jump along one of the two component directions reaches a jump point. These are
//! the online jumps' rules exactly, so JPS+ expands the same jump points as online JPS
//! except where the goal is near (see the crate docs on target jump points).

use crate::bits::{diagonal, BitGrid, DX, DY};

/// An entry meaning "the jump goes on for 127 cells or more, towards a jump point":
/// move [`SPAN`] cells and read the entry there.
pub(crate) const FAR_JUMP: Entry = Entry::MAX;
/// As [`FAR_JUMP`], towards a wall.
pub(crate) const FAR_WALL: Entry = Entry::MIN;
/// How far a far entry moves before the next read. Less than half the far threshold, so
/// the cell it reaches lies strictly before the jump's end and its entry keeps the sign.
pub(crate) const SPAN: u32 = (Entry::MAX as u32).div_ceil(2) - 1;

/// A table entry.
pub(crate) type Entry = i8;

/// The jump distances of one grid, eight one-byte entries per cell, row-major.
#[derive(Debug, Clone, Default)]
pub(crate) struct JumpTable {
    width: usize,
    distances: Vec<[Entry; 8]>,
}

impl JumpTable {
    /// The distances for `bits`, computed by dynamic programming in eight sweeps (each
    /// direction's entry depends on the neighbour's in that direction), the straight
    /// directions first since the diagonal ones read them.
    pub(crate) fn build(bits: &BitGrid) -> JumpTable {
        let (w, h) = (bits.width() as usize, bits.height() as usize);
        let mut distances = vec![[0; 8]; w * h];
        // The current direction's exact distances, before they are encoded.
        let mut exact = vec![0i32; w * h];
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
                    let entry = if !bits.allowed(x as i32, y as i32, dir) {
                        0
                    } else {
                        let next = ny as usize * w + nx as usize;
                        let stops = if dir < 4 {
                            bits.forced(nx, ny, dir)
                        } else {
                            let straight = &distances[next];
                            straight[usize::from(dx < 0)] > 0
                                || straight[2 + usize::from(dy < 0)] > 0
                        };
                        if stops {
                            1
                        } else if exact[next] > 0 {
                            exact[next] + 1
                        } else {
                            exact[next] - 1
                        }
                    };
                    exact[y * w + x] = entry;
                    distances[y * w + x][dir] = match entry {
                        e if e >= i32::from(FAR_JUMP) => FAR_JUMP,
                        e if e <= -i32::from(FAR_JUMP) => FAR_WALL,
                        e => e as Entry,
                    };
                }
            }
        }
        debug_assert!((4..8).all(|d| diagonal(DX[d], DY[d]) == d));
        JumpTable {
            width: w,
            distances,
        }
    }

    /// The entry of cell `(x, y)` in direction `dir`.
    #[inline(always)]
    pub(crate) fn entry(&self, x: u32, y: u32, dir: usize) -> Entry {
        self.distances[y as usize * self.width + x as usize][dir]
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.distances.len() * std::mem::size_of::<[Entry; 8]>()
    }
}
