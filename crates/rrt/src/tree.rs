//! A tree over grid cells, the shared storage of RRT, RRT* and RRT-Connect.
//!
//! Nodes are distinct cells with consecutive ids in insertion order (the root is node 0),
//! stored as flat arrays: each node's cell and parent, a per-grid-cell map from cell to
//! node, and a [`NearestIndex`] over the nodes' cells. Every buffer is kept between
//! searches, so resetting the tree for a grid of the same size allocates nothing.

use planner_api::{Cell, Grid};

use crate::index::{BucketGrid, NearestIndex};

/// A node id: its position in insertion order.
pub type NodeId = u32;

const NONE: u32 = u32::MAX;

/// A tree of distinct grid cells with parent links and a nearest-neighbour index.
#[derive(Debug, Clone)]
pub struct Tree<I: NearestIndex = BucketGrid> {
    index: I,
    cells: Vec<Cell>,
    parents: Vec<u32>,
    /// Per grid cell (flat index): the node there, or `NONE`.
    node_at: Vec<u32>,
    width: u32,
}

impl Default for Tree {
    fn default() -> Tree {
        Tree::with_index(BucketGrid::default())
    }
}

impl<I: NearestIndex> Tree<I> {
    /// An empty tree that finds nearest nodes with `index`.
    pub fn with_index(index: I) -> Tree<I> {
        Tree {
            index,
            cells: Vec::new(),
            parents: Vec::new(),
            node_at: Vec::new(),
            width: 0,
        }
    }

    /// The bytes [`Tree::reset`] and a tree of every free cell of `grid` (`n_free` of
    /// them, [`Grid::n_free`], counted once by the caller) allocate at most: a 4-byte node
    /// slot per cell, per free cell its 8-byte cell and 4-byte parent, and the nearest-node
    /// index's.
    pub fn bytes_for(&self, grid: &Grid, n_free: u64) -> u64 {
        4 * grid.len() as u64
            + 12 * n_free
            + self.index.bytes_for(grid.width(), grid.height(), n_free)
    }

    /// Empties the tree for `grid` and adds `root` as node 0. Reserves room for every free
    /// cell, the most a tree of distinct free cells can hold.
    /// Precondition: `root` lies inside `grid`.
    pub fn reset(&mut self, grid: &Grid, root: Cell) {
        self.width = grid.width();
        self.node_at.clear();
        self.node_at.resize(grid.len(), NONE);
        self.cells.clear();
        self.parents.clear();
        self.cells.reserve(grid.n_free());
        self.parents.reserve(grid.n_free());
        self.index.clear(grid.width(), grid.height());
        self.push(root, NONE);
    }

    fn flat(&self, cell: Cell) -> usize {
        cell.y as usize * self.width as usize + cell.x as usize
    }

    fn push(&mut self, cell: Cell, parent: u32) -> NodeId {
        let id = self.cells.len() as u32;
        let flat = self.flat(cell);
        self.node_at[flat] = id;
        self.cells.push(cell);
        self.parents.push(parent);
        self.index.insert(cell);
        id
    }

    /// Adds a node at `cell` with parent `parent` and returns its id.
    /// Preconditions: `cell` lies inside the grid and holds no node; `parent` is a node.
    pub fn add(&mut self, cell: Cell, parent: NodeId) -> NodeId {
        self.push(cell, parent)
    }

    /// The node at `cell`, if any. Precondition: `cell` lies inside the grid.
    pub fn node_at(&self, cell: Cell) -> Option<NodeId> {
        let node = self.node_at[self.flat(cell)];
        (node != NONE).then_some(node)
    }

    /// The node nearest to `query` (least squared Euclidean distance, ties to the smallest
    /// id); `None` only before the first [`Tree::reset`].
    pub fn nearest(&self, query: Cell) -> Option<NodeId> {
        self.index.nearest(query)
    }

    /// Appends to `out` every node within squared distance `max_squared` of `query`, in
    /// no particular order ([`NearestIndex::within`]).
    pub fn within(&self, query: Cell, max_squared: u64, out: &mut Vec<NodeId>) {
        self.index.within(query, max_squared, out);
    }

    /// The cell of node `node`. Precondition: `node` is a node.
    pub fn cell(&self, node: NodeId) -> Cell {
        self.cells[node as usize]
    }

    /// The parent of node `node`; `None` for the root.
    pub fn parent(&self, node: NodeId) -> Option<NodeId> {
        let parent = self.parents[node as usize];
        (parent != NONE).then_some(parent)
    }

    /// Makes `parent` the parent of `node` (RRT*'s rewiring). Preconditions: both are
    /// nodes, `node` is not the root, and `parent` is not `node` or one of its descendants.
    pub fn set_parent(&mut self, node: NodeId, parent: NodeId) {
        self.parents[node as usize] = parent;
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// Whether the tree has no node (only before the first [`Tree::reset`]).
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }

    /// The cells from the root to `node`, root first. Follows at most [`Tree::len`] links,
    /// so a broken precondition of [`Tree::set_parent`] cannot make it loop forever.
    pub fn path_to(&self, node: NodeId) -> Vec<Cell> {
        let mut cells = Vec::new();
        let mut node = node;
        while node != NONE && cells.len() < self.cells.len() {
            cells.push(self.cells[node as usize]);
            node = self.parents[node as usize];
        }
        cells.reverse();
        cells
    }

    /// Each node's cell and its parent's cell (`None` for the root), in insertion order.
    pub fn edges(&self) -> impl Iterator<Item = (Cell, Option<Cell>)> + '_ {
        self.cells
            .iter()
            .zip(&self.parents)
            .map(|(&cell, &parent)| {
                let parent = (parent != NONE).then(|| self.cells[parent as usize]);
                (cell, parent)
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn add_find_and_read_paths() {
        let grid = Grid::new(4, 3).unwrap();
        let mut tree = Tree::default();
        tree.reset(&grid, Cell::new(1, 1));
        assert_eq!(tree.len(), 1);
        let a = tree.add(Cell::new(2, 1), 0);
        let b = tree.add(Cell::new(3, 2), a);
        let c = tree.add(Cell::new(0, 0), 0);
        assert_eq!((a, b, c), (1, 2, 3));
        assert_eq!(tree.node_at(Cell::new(3, 2)), Some(2));
        assert_eq!(tree.node_at(Cell::new(3, 0)), None);
        assert_eq!(tree.parent(0), None);
        assert_eq!(tree.parent(b), Some(a));
        assert_eq!(
            tree.path_to(b),
            [Cell::new(1, 1), Cell::new(2, 1), Cell::new(3, 2)]
        );
        assert_eq!(tree.nearest(Cell::new(3, 0)), Some(a));
        let mut near = Vec::new();
        tree.within(Cell::new(1, 0), 2, &mut near);
        near.sort_unstable();
        assert_eq!(near, [0, 1, 3]);
        tree.set_parent(b, c);
        assert_eq!(
            tree.path_to(b),
            [Cell::new(1, 1), Cell::new(0, 0), Cell::new(3, 2)]
        );
        // Reset: a fresh tree with the new root only.
        tree.reset(&grid, Cell::new(3, 2));
        assert_eq!((tree.len(), tree.node_at(Cell::new(2, 1))), (1, None));
        assert_eq!(tree.edges().collect::<Vec<_>>(), [(Cell::new(3, 2), None)]);
    }
}
