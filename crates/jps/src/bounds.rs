//! Goal bounding over jump points: for a jump point `n` and each of the eight directions
//! `d`, the bounding box of the cells `v` such that some shortest path from `n` to `v`
//! begins with the move `d` (Rabin and Sturtevant, "Combining Bounding Boxes and JPS to
//! Prune Grid Pathfinding", AAAI 2016, <https://doi.org/10.1609/aaai.v30i1.10381>: the
//! geometric containers of Wagner, Willhalm and Zaroliagis as boxes), stored only for
//! jump points (Hu, Harabor, Qin and Yin, "Regarding Goal Bounding and Jump Point
//! Search", JAIR 70, 2021, <https://doi.org/10.1613/jair.1.12255>). A search expanding
//! `n` skips every direction whose box does not hold the goal.
//!
//! **Why it keeps the paths optimal.** Let `n` lie on the path the search would find
//! without the boxes, leaving `n` by direction `d`. Its rest from `n` is a shortest path
//! from `n` to the goal that begins with `d`, so the goal is in `n`'s box for `d` and the
//! path is never cut. Every path that survives is a path of the grid, so A* still returns
//! the least cost (the path may be another of equal cost, and the counters drop).
//!
//! **Choice.** Rabin and Sturtevant build the boxes under JPS's canonical ordering, which
//! gives smaller boxes; these hold every shortest path (a cell reached at equal cost by
//! several first moves is in each of their boxes). That is a superset of theirs, so the
//! argument above needs no property of JPS's pruning, and the same boxes serve online JPS,
//! JPS' and JPS+.
//!
//! **Cost.** One Dijkstra search over the whole grid per jump point: time `O(J N log N)`
//! for `J` jump points and `N` free cells (den520d: 28,178 free cells; the bench prints
//! the jump points and the time), spread over the rayon pool; memory 4 bytes per node
//! record and 64 per jump point. The jump points are the cells where a jump of the table
//! ends ([`JumpTable`]), straight or diagonal; nodes without boxes (the start, the goal's
//! target jump points off them) keep all their directions. (JPS' and JPS+ expand no
//! diagonal jump point as such, but a target jump point can be one: boxes for the straight
//! jumps' ends alone, a build of this file tried for issue 30 and not kept, took about a
//! third of the time to build on den520d, and JPS+ then expanded about a tenth more nodes
//! and took about a tenth longer; the figures are in that note.)

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use crate::bits::{BitGrid, DX, DY};
use crate::cost::Cost;
use crate::plus::JumpTable;

/// A box `[x0, x1, y0, y1]`, empty when `x0 > x1`.
type Bounds = [u16; 4];

/// The empty box.
const EMPTY: Bounds = [u16::MAX, 0, u16::MAX, 0];

/// The boxes of one grid's jump points.
#[derive(Debug, Clone, Default)]
pub(crate) struct GoalBounds {
    /// Per node record (`y << shift | x`): 1 + the index of its boxes, 0 for none.
    slot: Vec<u32>,
    /// Per jump point, a box per direction.
    boxes: Vec<[Bounds; 8]>,
}

/// A build of the boxes given up at its caller's request (a budget's time limit or
/// cancel flag).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Stopped;

/// The goal bounds' build runs its Dijkstra searches in this many groups of jump points,
/// each with one [`Scratch`], on the rayon pool: at most this many scratches exist at a
/// time whatever the pool's size, so the build's memory, and whether a search fits a
/// memory budget, do not depend on the machine.
pub(crate) const BUILD_GROUPS: u64 = 8;

/// Bytes per grid cell of one [`Scratch`]: the costs, first moves and stamps (13), the
/// settled list (4 a cell, 8 with a vector's doubling), and the heap counted at one 16-byte
/// entry a cell. The heap holds the search's frontier and the stale entries lazy deletion
/// leaves, which on grid maps stay far below one a cell; a heap that outgrew the allowance
/// (at most 8 entries a cell, one per improving move) would exceed the estimate.
pub(crate) const SCRATCH_BYTES_PER_CELL: u64 = 13 + 8 + 16;

/// One Dijkstra search's scratch, reused across sources.
struct Scratch {
    cost: Vec<Cost>,
    /// The first moves (a bit per direction) of the shortest paths found to each cell.
    first: Vec<u8>,
    /// The source whose search last reached each cell, plus one (0: none yet).
    seen: Vec<u32>,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    /// The cells reached, in the order they were settled.
    settled: Vec<u32>,
}

impl GoalBounds {
    /// The boxes of the jump points of `table` on `bits`, for node records
    /// `y << shift | x`; `Ok(None)` when a coordinate does not fit the boxes' 16 bits, and
    /// [`Stopped`] when `stop` said so before a jump point's search (read before each).
    pub(crate) fn build(
        bits: &BitGrid,
        table: &JumpTable,
        shift: u32,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<GoalBounds>, Stopped> {
        let (w, h) = (bits.width(), bits.height());
        if w > u32::from(u16::MAX) || h > u32::from(u16::MAX) {
            return Ok(None);
        }
        let n = w as usize * h as usize;
        // The legal moves of every cell, a bit per direction (no corner cutting).
        let moves: Vec<u8> = (0..n)
            .map(|i| {
                let (x, y) = ((i % w as usize) as i32, (i / w as usize) as i32);
                if !bits.free(x, y) {
                    return 0;
                }
                (0..8).fold(0u8, |m, d| m | u8::from(bits.allowed(x, y, d)) << d)
            })
            .collect();
        // A cell is a jump point when a jump of the table ends there: the cell before it
        // in that direction reads 1.
        let mut jump_point = vec![false; n];
        for y in 0..h {
            for x in 0..w {
                for d in 0..8 {
                    if table.entry(x, y, d) == 1 {
                        let (tx, ty) = (x as i32 + DX[d], y as i32 + DY[d]);
                        jump_point[ty as usize * w as usize + tx as usize] = true;
                    }
                }
            }
        }
        let sources: Vec<u32> = (0..n as u32).filter(|&i| jump_point[i as usize]).collect();
        // Contiguous groups: every search covers the whole grid, so they take about as long.
        let group_len = sources.len().div_ceil(BUILD_GROUPS as usize).max(1);
        let groups: Option<Vec<Vec<[Bounds; 8]>>> = sources
            .par_chunks(group_len)
            .map(|group| {
                let mut scratch = Scratch {
                    cost: vec![Cost::default(); n],
                    first: vec![0; n],
                    seen: vec![0; n],
                    heap: BinaryHeap::new(),
                    settled: Vec::new(),
                };
                group
                    .iter()
                    .map(|&source| (!stop()).then(|| boxes_from(source, w, &moves, &mut scratch)))
                    .collect()
            })
            .collect();
        let boxes: Vec<[Bounds; 8]> = groups.ok_or(Stopped)?.into_iter().flatten().collect();
        let mut slot = vec![0u32; (h as usize) << shift];
        for (k, &source) in sources.iter().enumerate() {
            let (x, y) = (source % w, source / w);
            slot[((y as usize) << shift) | x as usize] = k as u32 + 1;
        }
        Ok(Some(GoalBounds { slot, boxes }))
    }

    /// The directions of node record `p` whose boxes hold `(gx, gy)`, a bit per direction;
    /// all eight when `p` is not a jump point.
    #[inline(always)]
    pub(crate) fn toward(&self, p: u32, gx: u32, gy: u32) -> u8 {
        let slot = self.slot[p as usize];
        if slot == 0 {
            return 0xff;
        }
        let boxes = &self.boxes[slot as usize - 1];
        let mut out = 0u8;
        for (d, b) in boxes.iter().enumerate() {
            let inside = u32::from(b[0]) <= gx
                && gx <= u32::from(b[1])
                && u32::from(b[2]) <= gy
                && gy <= u32::from(b[3]);
            out |= u8::from(inside) << d;
        }
        out
    }

    /// The jump points with boxes.
    pub(crate) fn n_jump_points(&self) -> usize {
        self.boxes.len()
    }

    /// Bytes held.
    pub(crate) fn memory_bytes(&self) -> usize {
        self.slot.len() * 4 + self.boxes.len() * std::mem::size_of::<[Bounds; 8]>()
    }
}

/// The boxes of `source` (a cell index `y w + x`): Dijkstra's search from it over the
/// whole grid, exact costs, each cell's first moves the union of those of its shortest
/// paths (a cell settles after every cell that can precede it on one, as moves cost more
/// than 0).
fn boxes_from(source: u32, w: u32, moves: &[u8], s: &mut Scratch) -> [Bounds; 8] {
    let stamp = source + 1;
    let straight = Cost {
        straight: 1,
        diagonal: 0,
    };
    let diagonal = Cost {
        straight: 0,
        diagonal: 1,
    };
    s.heap.clear();
    s.settled.clear();
    let src = source as usize;
    s.seen[src] = stamp;
    s.cost[src] = Cost::default();
    s.first[src] = 0;
    s.heap.push(Reverse((0, source)));
    while let Some(Reverse((key, u))) = s.heap.pop() {
        let ui = u as usize;
        if key != s.cost[ui].value().to_bits() {
            continue; // An older entry of a cell whose cost fell since.
        }
        // Settled (a later entry for it cannot have a lower key).
        s.settled.push(u);
        let (x, y) = ((u % w) as i32, (u / w) as i32);
        let from = if u == source { 0 } else { s.first[ui] };
        let mut legal = moves[ui];
        while legal != 0 {
            let d = legal.trailing_zeros() as usize;
            legal &= legal - 1;
            let v = ((y + DY[d]) as u32 * w + (x + DX[d]) as u32) as usize;
            let via = s.cost[ui] + if d < 4 { straight } else { diagonal };
            let first = if u == source { 1 << d } else { from };
            if s.seen[v] != stamp || via < s.cost[v] {
                s.seen[v] = stamp;
                s.cost[v] = via;
                s.first[v] = first;
                s.heap.push(Reverse((via.value().to_bits(), v as u32)));
            } else if via == s.cost[v] {
                s.first[v] |= first;
            }
        }
    }
    let mut boxes = [EMPTY; 8];
    for &v in &s.settled {
        let mut first = s.first[v as usize];
        let (x, y) = ((v % w) as u16, (v / w) as u16);
        while first != 0 {
            let d = first.trailing_zeros() as usize;
            first &= first - 1;
            let b = &mut boxes[d];
            *b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
        }
    }
    boxes
}
