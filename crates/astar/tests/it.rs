//! planner-astar's integration tests, one test binary (`cargo test -p planner-astar --test it`): each
//! module is a file of this directory that used to be a test binary of its own. A new
//! test file here is declared below (`mod NAME;`), or tidy refuses it (ARCHITECTURE.md,
//! "Tests").

mod allocations;
mod counters;
mod effort;
mod events;
mod paper;
mod reference;
mod weighted;

use planner_api::Connectivity;
use planner_astar::{Heuristic, TieBreak};

/// A* settings the recording tests (`effort`, `events`) run: (moves, heuristic, tie rule,
/// weight), every heuristic and tie rule, 4, 8 and 16 moves, a weight above 1.
const RECORDING_SETTINGS: [(Connectivity, Heuristic, TieBreak, f64); 6] = [
    (
        Connectivity::Four,
        Heuristic::Manhattan,
        TieBreak::Fifo,
        1.0,
    ),
    (Connectivity::Four, Heuristic::Zero, TieBreak::Fifo, 1.0),
    (Connectivity::Eight, Heuristic::Octile, TieBreak::HighG, 1.0),
    (
        Connectivity::Eight,
        Heuristic::Euclidean,
        TieBreak::LowG,
        1.0,
    ),
    (
        Connectivity::Eight,
        Heuristic::Chebyshev,
        TieBreak::Lifo,
        1.5,
    ),
    (
        Connectivity::Sixteen,
        Heuristic::Euclidean,
        TieBreak::Fifo,
        1.0,
    ),
];
