//! Nearest-neighbour indexes over a tree's cells.
//!
//! Every index answers the same two exact questions: the node whose cell centre has the
//! least squared Euclidean distance to the query, in integer arithmetic, with ties broken
//! towards the node added first (the smallest node id); and every node within a squared
//! distance of the query (RRT*'s near set). Because the answers are exact and the tie rule
//! is fixed, the choice of index changes the speed of a search, never its result.

use planner_api::Cell;

const NONE: u32 = u32::MAX;

/// Squared Euclidean distance between two cell centres, exact.
///
/// Fits in a `u64` because a grid has at most 2^31 cells, so `dx^2 + dy^2 < 2^63`.
#[inline]
pub fn squared_distance(a: Cell, b: Cell) -> u64 {
    let dx = u64::from(a.x.abs_diff(b.x));
    let dy = u64::from(a.y.abs_diff(b.y));
    dx * dx + dy * dy
}

/// A set of tree nodes (cells) that answers nearest-node queries.
///
/// Nodes get consecutive ids in insertion order, starting at 0 after [`NearestIndex::clear`].
/// Implementations must return exactly the node a linear scan would: least squared
/// Euclidean distance ([`squared_distance`]), ties to the smallest id.
pub trait NearestIndex: Send + Sync {
    /// Empties the index and prepares it for cells of a `width` x `height` grid,
    /// keeping allocated capacity. Preconditions: `width, height >= 1`.
    fn clear(&mut self, width: u32, height: u32);

    /// The bytes the index allocates at most for `nodes` nodes on a `width` x `height`
    /// grid (a planner's memory check).
    fn bytes_for(&self, width: u32, height: u32, nodes: u64) -> u64;

    /// Adds a node at `cell`; its id is the number of nodes added since the last clear.
    /// Precondition: `cell` lies inside the grid given to [`NearestIndex::clear`].
    fn insert(&mut self, cell: Cell);

    /// The id of the node nearest to `query`, ties to the smallest id; `None` when empty.
    /// Precondition: `query` lies inside the grid given to [`NearestIndex::clear`].
    fn nearest(&self, query: Cell) -> Option<u32>;

    /// Appends to `out` the id of every node whose squared distance to `query` is at most
    /// `max_squared`, in no particular order (callers that need an order sort them).
    /// Precondition: `query` lies inside the grid given to [`NearestIndex::clear`].
    fn within(&self, query: Cell, max_squared: u64, out: &mut Vec<u32>);

    /// Number of nodes.
    fn len(&self) -> usize;

    /// Whether the index holds no node.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Grid buckets: nodes are filed by square blocks of cells, and a query searches the
/// blocks in growing square rings around its own block, stopping as soon as no unvisited
/// block can hold a node nearer than (or as near as) the best found.
///
/// Each block keeps an intrusive singly linked list of its nodes in flat arrays (`head`
/// per block, `next` per node), so inserting allocates nothing once the buffers have
/// grown. Rings are clipped to the bounding box of the blocks that hold nodes, so a query
/// far from a small tree visits only the tree's blocks.
///
/// The pruning bound after ring `r` is the distance from the query to the nearest cell
/// outside the `(2r + 1)`-block square around its block: every unvisited node lies at
/// least that far away, so the search stops once the best squared distance is strictly
/// below the bound squared (strictly, so that an equally near node with a smaller id is
/// never missed).
#[derive(Debug, Clone)]
pub struct BucketGrid {
    side: u32,
    blocks_x: u32,
    head: Vec<u32>,
    next: Vec<u32>,
    cells: Vec<Cell>,
    /// Inclusive block bounds `(x0, y0, x1, y1)` of the non-empty blocks.
    bounds: Option<(i64, i64, i64, i64)>,
}

impl BucketGrid {
    /// The block side used by [`BucketGrid::default`]: 4 x 4 cells. On the 4-connected
    /// one-step RRT the tree fills the cells it reaches, so a block holds up to 16 nodes
    /// and a typical query visits a few blocks.
    pub const DEFAULT_BLOCK_SIDE: u32 = 4;

    /// An empty index with blocks of `side` x `side` cells; a side of 0 is taken as 1.
    pub fn with_block_side(side: u32) -> BucketGrid {
        BucketGrid {
            side: side.max(1),
            blocks_x: 0,
            head: Vec::new(),
            next: Vec::new(),
            cells: Vec::new(),
            bounds: None,
        }
    }

    /// The block side in cells.
    pub fn block_side(&self) -> u32 {
        self.side
    }

    #[inline]
    fn scan_block(&self, query: Cell, bx: i64, by: i64, best: &mut (u64, u32)) {
        // Callers pass blocks inside `bounds`, hence inside the block grid.
        let block = by as usize * self.blocks_x as usize + bx as usize;
        let mut node = self.head[block];
        while node != NONE {
            let d2 = squared_distance(query, self.cells[node as usize]);
            if (d2, node) < *best {
                *best = (d2, node);
            }
            node = self.next[node as usize];
        }
    }
}

impl Default for BucketGrid {
    fn default() -> BucketGrid {
        BucketGrid::with_block_side(Self::DEFAULT_BLOCK_SIDE)
    }
}

impl NearestIndex for BucketGrid {
    /// A 4-byte head per block, and per node a 4-byte link and its 8-byte cell.
    fn bytes_for(&self, width: u32, height: u32, nodes: u64) -> u64 {
        let blocks = u64::from(width.div_ceil(self.side)) * u64::from(height.div_ceil(self.side));
        4 * blocks + 12 * nodes
    }

    fn clear(&mut self, width: u32, height: u32) {
        self.blocks_x = width.div_ceil(self.side);
        let blocks_y = height.div_ceil(self.side);
        self.head.clear();
        self.head
            .resize(self.blocks_x as usize * blocks_y as usize, NONE);
        self.next.clear();
        self.cells.clear();
        self.bounds = None;
    }

    fn insert(&mut self, cell: Cell) {
        let id = self.cells.len() as u32;
        let (bx, by) = (cell.x / self.side, cell.y / self.side);
        let block = by as usize * self.blocks_x as usize + bx as usize;
        self.next.push(self.head[block]);
        self.head[block] = id;
        self.cells.push(cell);
        let (bx, by) = (i64::from(bx), i64::from(by));
        self.bounds = Some(match self.bounds {
            None => (bx, by, bx, by),
            Some((x0, y0, x1, y1)) => (x0.min(bx), y0.min(by), x1.max(bx), y1.max(by)),
        });
    }

    fn nearest(&self, query: Cell) -> Option<u32> {
        let (x0, y0, x1, y1) = self.bounds?;
        let side = i64::from(self.side);
        let (qx, qy) = (i64::from(query.x), i64::from(query.y));
        let (bx, by) = (qx / side, qy / side);
        let mut best = (u64::MAX, NONE);
        // Rings closer than the bounding box are empty: start at its Chebyshev block distance.
        let mut r = 0.max(x0 - bx).max(bx - x1).max(y0 - by).max(by - y1);
        loop {
            // Ring r: blocks at Chebyshev block distance exactly r, clipped to the bounds.
            // Since r is at least the distance to the bounds, every range below is non-empty.
            for j in (by - r).max(y0)..=(by + r).min(y1) {
                if j == by - r || j == by + r {
                    for i in (bx - r).max(x0)..=(bx + r).min(x1) {
                        self.scan_block(query, i, j, &mut best);
                    }
                } else {
                    if bx - r >= x0 {
                        self.scan_block(query, bx - r, j, &mut best);
                    }
                    if bx + r <= x1 {
                        self.scan_block(query, bx + r, j, &mut best);
                    }
                }
            }
            if bx - r <= x0 && bx + r >= x1 && by - r <= y0 && by + r >= y1 {
                break;
            }
            // Every cell outside the square of rings 0..=r is at least `bound` away along x or y.
            let bound = (qx - ((bx - r) * side - 1))
                .min((bx + r + 1) * side - qx)
                .min(qy - ((by - r) * side - 1))
                .min((by + r + 1) * side - qy);
            // bound >= 1 and bound <= width + height < 2^32, so its square fits.
            if best.0 < (bound * bound) as u64 {
                break;
            }
            r += 1;
        }
        (best.1 != NONE).then_some(best.1)
    }

    fn within(&self, query: Cell, max_squared: u64, out: &mut Vec<u32>) {
        let Some((x0, y0, x1, y1)) = self.bounds else {
            return;
        };
        // Every cell within the distance lies in the square of half side `reach` around
        // the query; visit the blocks that square meets, clipped to the occupied bounds.
        let reach = i64::from(max_squared.isqrt().min(u64::from(u32::MAX)) as u32);
        let side = i64::from(self.side);
        let (qx, qy) = (i64::from(query.x), i64::from(query.y));
        let (bx0, bx1) = (
            ((qx - reach).max(0) / side).max(x0),
            ((qx + reach) / side).min(x1),
        );
        let (by0, by1) = (
            ((qy - reach).max(0) / side).max(y0),
            ((qy + reach) / side).min(y1),
        );
        for by in by0..=by1 {
            for bx in bx0..=bx1 {
                let block = by as usize * self.blocks_x as usize + bx as usize;
                let mut node = self.head[block];
                while node != NONE {
                    if squared_distance(query, self.cells[node as usize]) <= max_squared {
                        out.push(node);
                    }
                    node = self.next[node as usize];
                }
            }
        }
    }

    fn len(&self) -> usize {
        self.cells.len()
    }
}

#[cfg(test)]
mod tests {
    use rand_chacha::rand_core::{RngCore, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    use super::*;

    /// The independent reference: a linear scan with the same order.
    fn linear(cells: &[Cell], query: Cell) -> Option<u32> {
        (0..cells.len() as u32).min_by_key(|&i| (squared_distance(query, cells[i as usize]), i))
    }

    #[test]
    fn ties_go_to_the_first_node() {
        let mut index = BucketGrid::with_block_side(2);
        index.clear(9, 9);
        assert_eq!(index.nearest(Cell::new(4, 4)), None);
        // Four nodes at distance 2 from (4, 4), added in this order.
        for cell in [(6, 4), (4, 2), (2, 4), (4, 6)] {
            index.insert(cell.into());
        }
        assert_eq!(index.nearest(Cell::new(4, 4)), Some(0));
        // (2, 2) is at squared distance 4 from (2, 4) and (4, 2): node 1 (4, 2) came first.
        assert_eq!(index.nearest(Cell::new(2, 2)), Some(1));
        assert_eq!(index.nearest(Cell::new(0, 8)), Some(2));
        assert_eq!(index.len(), 4);
    }

    #[test]
    fn within_agrees_with_a_linear_scan() {
        let mut rng = ChaCha8Rng::from_seed([11; 32]);
        let mut below = |n: u32| (rng.next_u64() % u64::from(n)) as u32;
        let mut out = Vec::new();
        for case in 0..200 {
            let (width, height) = (1 + below(30), 1 + below(30));
            let side = 1 + case % 6;
            let mut index = BucketGrid::with_block_side(side);
            index.clear(width, height);
            let mut cells = Vec::new();
            out.clear();
            index.within(Cell::new(0, 0), 100, &mut out);
            assert!(out.is_empty());
            for _ in 0..1 + below(60) {
                let cell = Cell::new(below(width), below(height));
                index.insert(cell);
                cells.push(cell);
                for _ in 0..3 {
                    let query = Cell::new(below(width), below(height));
                    let max_squared = u64::from(below(80));
                    out.clear();
                    index.within(query, max_squared, &mut out);
                    out.sort_unstable();
                    let expect: Vec<u32> = (0..cells.len() as u32)
                        .filter(|&i| squared_distance(query, cells[i as usize]) <= max_squared)
                        .collect();
                    assert_eq!(out, expect, "case {case}, query {query}, r2 {max_squared}");
                }
            }
        }
    }

    #[test]
    fn agrees_with_a_linear_scan() {
        let mut rng = ChaCha8Rng::from_seed([7; 32]);
        let mut below = |n: u32| (rng.next_u64() % u64::from(n)) as u32;
        for case in 0..200 {
            let (width, height) = (1 + below(40), 1 + below(40));
            let side = 1 + case % 6;
            let mut index = BucketGrid::with_block_side(side);
            index.clear(width, height);
            let mut cells = Vec::new();
            let n = 1 + below(60);
            for _ in 0..n {
                // Clustered points make the far-query and tie cases common.
                let cell = Cell::new(below(width.min(8)), below(height));
                index.insert(cell);
                cells.push(cell);
                for _ in 0..5 {
                    let query = Cell::new(below(width), below(height));
                    assert_eq!(
                        index.nearest(query),
                        linear(&cells, query),
                        "case {case}, {width}x{height}, side {side}, query {query}"
                    );
                }
            }
        }
    }
}
