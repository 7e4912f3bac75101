//! Search counters: plain integers while searching, an ordered named list when reported.
//!
//! Planners count into [`SearchStats`], a struct of plain `u64` fields (no map lookups in
//! hot loops). When a search ends, the planner turns the counters that apply to it into
//! [`Counters`], an ordered list of `(name, value)` pairs, and may append counters of its
//! own with [`Counters::push`] without any change here. `Counters` serializes as a map in
//! that order, so snapshots are stable and contain no timing.
//!
//! The names are those of seed 000's Table 2 (section 2.5):
//!
//! | name | paper | meaning |
//! |---|---|---|
//! | `n_expanded` | N_exp | times a state is selected for expansion (a Backtracking call) |
//! | `n_neighbor_checks` | N_nbr | attempted moves to a neighbour |
//! | `n_blocked` | N_blk | attempts rejected because `Safe(x, y) = 0` (blocked or out of bounds) |
//! | `n_skipped` | N_skp | attempts to a CLOSED or visited state |
//! | `n_open_insertions` | N_open | first insertions into OPEN (the start's included) |
//! | `n_relaxations` | N_relax | times a neighbour gets a new parent and g |
//! | `n_solutions` | N_sol | complete start-goal paths found |
//! | `n_dead_ends` | N_dead | non-goal calls that recursed into no neighbour |
//! | `n_backtracks` | N_back | returns from a recursive call |
//! | `peak_open` | - | largest frontier (OPEN, queue or stack) size: the memory indicator of frontier planners |
//! | `max_depth` | - | most cells on the current path: the memory indicator of Backtracking |

use std::borrow::Cow;
use std::fmt;
use std::ops::AddAssign;

use serde::de::{MapAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The standard counters, in Table 2's order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Counter {
    /// `n_expanded`.
    Expanded,
    /// `n_neighbor_checks`.
    NeighborChecks,
    /// `n_blocked`.
    Blocked,
    /// `n_skipped`.
    Skipped,
    /// `n_open_insertions`.
    OpenInsertions,
    /// `n_relaxations`.
    Relaxations,
    /// `n_solutions`.
    Solutions,
    /// `n_dead_ends`.
    DeadEnds,
    /// `n_backtracks`.
    Backtracks,
    /// `peak_open`.
    PeakOpen,
    /// `max_depth`.
    MaxDepth,
}

impl Counter {
    /// Every standard counter, in Table 2's order (then the memory indicators).
    pub const ALL: &'static [Counter] = &[
        Counter::Expanded,
        Counter::NeighborChecks,
        Counter::Blocked,
        Counter::Skipped,
        Counter::OpenInsertions,
        Counter::Relaxations,
        Counter::Solutions,
        Counter::DeadEnds,
        Counter::Backtracks,
        Counter::PeakOpen,
        Counter::MaxDepth,
    ];

    /// What A* reports (seed 000 Tables 5 and 7, plus `peak_open`).
    pub const ASTAR: &'static [Counter] = &[
        Counter::Expanded,
        Counter::NeighborChecks,
        Counter::Blocked,
        Counter::Skipped,
        Counter::OpenInsertions,
        Counter::Relaxations,
        Counter::PeakOpen,
    ];

    /// What Backtracking reports (seed 000 Tables 6 and 8, plus `max_depth`).
    pub const BACKTRACKING: &'static [Counter] = &[
        Counter::Expanded,
        Counter::NeighborChecks,
        Counter::Blocked,
        Counter::Skipped,
        Counter::Solutions,
        Counter::DeadEnds,
        Counter::Backtracks,
        Counter::MaxDepth,
    ];

    /// What uninformed frontier searches (BFS, DFS) report.
    pub const FRONTIER: &'static [Counter] = &[
        Counter::Expanded,
        Counter::NeighborChecks,
        Counter::Blocked,
        Counter::Skipped,
        Counter::PeakOpen,
    ];

    /// The counter's name, as reported.
    pub fn name(self) -> &'static str {
        match self {
            Counter::Expanded => "n_expanded",
            Counter::NeighborChecks => "n_neighbor_checks",
            Counter::Blocked => "n_blocked",
            Counter::Skipped => "n_skipped",
            Counter::OpenInsertions => "n_open_insertions",
            Counter::Relaxations => "n_relaxations",
            Counter::Solutions => "n_solutions",
            Counter::DeadEnds => "n_dead_ends",
            Counter::Backtracks => "n_backtracks",
            Counter::PeakOpen => "peak_open",
            Counter::MaxDepth => "max_depth",
        }
    }
}

/// Plain-integer counters for the hot loop; see the module docs for their meaning.
///
/// `+=` adds the counts and takes the maximum of the two memory indicators (`peak_open`,
/// `max_depth`), which is what summing several searches (PA-star's local searches) means.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash, Serialize)]
pub struct SearchStats {
    /// `n_expanded`.
    pub n_expanded: u64,
    /// `n_neighbor_checks`.
    pub n_neighbor_checks: u64,
    /// `n_blocked`.
    pub n_blocked: u64,
    /// `n_skipped`.
    pub n_skipped: u64,
    /// `n_open_insertions`.
    pub n_open_insertions: u64,
    /// `n_relaxations`.
    pub n_relaxations: u64,
    /// `n_solutions`.
    pub n_solutions: u64,
    /// `n_dead_ends`.
    pub n_dead_ends: u64,
    /// `n_backtracks`.
    pub n_backtracks: u64,
    /// `peak_open`.
    pub peak_open: u64,
    /// `max_depth`.
    pub max_depth: u64,
}

impl SearchStats {
    /// The value of one standard counter.
    pub fn get(&self, counter: Counter) -> u64 {
        match counter {
            Counter::Expanded => self.n_expanded,
            Counter::NeighborChecks => self.n_neighbor_checks,
            Counter::Blocked => self.n_blocked,
            Counter::Skipped => self.n_skipped,
            Counter::OpenInsertions => self.n_open_insertions,
            Counter::Relaxations => self.n_relaxations,
            Counter::Solutions => self.n_solutions,
            Counter::DeadEnds => self.n_dead_ends,
            Counter::Backtracks => self.n_backtracks,
            Counter::PeakOpen => self.peak_open,
            Counter::MaxDepth => self.max_depth,
        }
    }

    /// The named counters for the given subset, in the subset's order.
    pub fn report(&self, which: &[Counter]) -> Counters {
        let mut counters = Counters::new();
        for &counter in which {
            counters.push(counter.name(), self.get(counter));
        }
        counters
    }
}

impl AddAssign for SearchStats {
    fn add_assign(&mut self, other: SearchStats) {
        self.n_expanded += other.n_expanded;
        self.n_neighbor_checks += other.n_neighbor_checks;
        self.n_blocked += other.n_blocked;
        self.n_skipped += other.n_skipped;
        self.n_open_insertions += other.n_open_insertions;
        self.n_relaxations += other.n_relaxations;
        self.n_solutions += other.n_solutions;
        self.n_dead_ends += other.n_dead_ends;
        self.n_backtracks += other.n_backtracks;
        self.peak_open = self.peak_open.max(other.peak_open);
        self.max_depth = self.max_depth.max(other.max_depth);
    }
}

/// Reported counters: `(name, value)` pairs in a fixed order, serialized as a map.
#[derive(Debug, Clone, Default, PartialEq, Eq, Hash)]
pub struct Counters {
    entries: Vec<(Cow<'static, str>, u64)>,
}

impl Counters {
    /// No counters.
    pub fn new() -> Counters {
        Counters::default()
    }

    /// Sets `name` to `value`: replaces the value in place when the name is present,
    /// else appends it at the end.
    pub fn push(&mut self, name: impl Into<Cow<'static, str>>, value: u64) {
        let name = name.into();
        match self.entries.iter_mut().find(|(n, _)| *n == name) {
            Some(entry) => entry.1 = value,
            None => self.entries.push((name, value)),
        }
    }

    /// Builder form of [`Counters::push`].
    pub fn with(mut self, name: impl Into<Cow<'static, str>>, value: u64) -> Counters {
        self.push(name, value);
        self
    }

    /// The value of `name`, if reported.
    pub fn get(&self, name: &str) -> Option<u64> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|&(_, v)| v)
    }

    /// The pairs in order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, u64)> + '_ {
        self.entries.iter().map(|(n, v)| (n.as_ref(), *v))
    }

    /// Number of counters.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether no counter is reported.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
}

impl fmt::Display for Counters {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (name, value)) in self.iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            write!(f, "{name}={value}")?;
        }
        Ok(())
    }
}

impl Serialize for Counters {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.entries.len()))?;
        for (name, value) in &self.entries {
            map.serialize_entry(name.as_ref(), value)?;
        }
        map.end()
    }
}

impl<'de> Deserialize<'de> for Counters {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Counters, D::Error> {
        struct CountersVisitor;
        impl<'de> Visitor<'de> for CountersVisitor {
            type Value = Counters;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a map from counter names to non-negative integers")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut access: A) -> Result<Counters, A::Error> {
                let mut counters = Counters::new();
                while let Some((name, value)) = access.next_entry::<String, u64>()? {
                    counters.push(name, value);
                }
                Ok(counters)
            }
        }
        deserializer.deserialize_map(CountersVisitor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn report_keeps_order_and_extensions() {
        let stats = SearchStats {
            n_expanded: 3,
            n_neighbor_checks: 8,
            peak_open: 2,
            ..SearchStats::default()
        };
        let counters = stats.report(Counter::FRONTIER).with("n_custom", 7);
        let json = serde_json::to_string(&counters).unwrap();
        assert_eq!(
            json,
            r#"{"n_expanded":3,"n_neighbor_checks":8,"n_blocked":0,"n_skipped":0,"peak_open":2,"n_custom":7}"#
        );
        let back: Counters = serde_json::from_str(&json).unwrap();
        assert_eq!(back, counters);
        assert_eq!(back.get("n_custom"), Some(7));
        assert_eq!(back.get("n_solutions"), None);
    }

    #[test]
    fn add_assign_sums_counts_and_maxes_peaks() {
        let mut a = SearchStats {
            n_expanded: 2,
            peak_open: 5,
            max_depth: 1,
            ..Default::default()
        };
        a += SearchStats {
            n_expanded: 3,
            peak_open: 4,
            max_depth: 9,
            ..Default::default()
        };
        assert_eq!((a.n_expanded, a.peak_open, a.max_depth), (5, 5, 9));
    }
}
