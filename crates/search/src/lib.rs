//! The OPEN lists and per-cell node arrays of gridplan's best-first searches, shared by
//! A* (planner-astar), Jump Point Search (planner-jps), Theta* and Lazy Theta*
//! (planner-theta_star) and bidirectional A* (planner-bidirectional_astar), and the queue
//! of the incremental searches, LPA* and D* Lite (planner-lpastar, planner-dstar_lite).
//!
//! - [`bucket`]: OPEN lists that pop in exactly the order of the full key
//!   `(f, tie rule, push sequence)`: [`bucket::BucketOpen`] (a ring of narrow `f` buckets in
//!   front of a binary heap, for any [`planner_api::Cost`], or for keys with fewer
//!   fractional bits, as Theta\*'s) and [`bucket::IntOpen`] (four slots of one integer `f`
//!   each, for unit moves and integer consistent heuristics).
//! - [`keyed::KeyedQueue`]: vertices with two-part keys `[k1; k2]` that change while
//!   queued (in either direction), each queued at most once, with membership, key
//!   changes and removal: LPA*'s and D* Lite's queue U, on the same bucket-ring design.
//! - [`QuadHeap`], a 4-ary min-heap of any ordered entry, and [`FrontHeap`], the same
//!   behind a stack of entries with the last popped key (Jump Point Search's common case).
//! - [`neighbourhood`]: cells as bits in the adjacency's padded layout, read as 3 x 3
//!   neighbourhood codes, and tables from a code to a node's safe moves or to its moves
//!   into CLOSED cells (Theta\* and Lazy Theta\*; A* takes the tables).
//! - [`Stamped`]: per-cell node records with generation stamps, so a search costs the
//!   cells it touches, not the grid.
//!
//! All of them keep their memory between searches: after the first query on a grid, a
//! search allocates nothing. Deletion is lazy everywhere: in the OPEN lists an improved
//! node is pushed again and the search skips the older entry when it comes out; in the
//! keyed queue a changed key makes the older entry stale by its ticket.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod bucket;
pub mod keyed;
pub mod neighbourhood;
mod quad;
mod stamps;

pub use quad::{FrontEntry, FrontHeap, QuadHeap};
pub use stamps::{Stamped, Stamps};
