//! Lookups into a sweep's records by (map, problem, planner label, repeat).
//!
//! The index maps each (map, problem, label) to its records once (in record order, which
//! for a sweep is repeat order), and every report section and figure looks runs up
//! through it instead of scanning the records.

use std::collections::HashMap;

use crate::record::RunRecord;

/// An index over a sweep's records.
#[derive(Debug, Clone)]
pub struct ResultsIndex<'r> {
    records: &'r [RunRecord],
    positions: HashMap<(&'r str, usize, &'r str), Vec<usize>>,
}

impl<'r> ResultsIndex<'r> {
    /// Indexes `records`.
    pub fn new(records: &'r [RunRecord]) -> ResultsIndex<'r> {
        let mut positions: HashMap<(&str, usize, &str), Vec<usize>> = HashMap::new();
        for (i, r) in records.iter().enumerate() {
            let key = (r.map.as_str(), r.problem, r.planner.as_str());
            positions.entry(key).or_default().push(i);
        }
        ResultsIndex { records, positions }
    }

    /// Every record.
    pub fn records(&self) -> &'r [RunRecord] {
        self.records
    }

    /// The runs of `label` on problem `problem` of `map`, in record order.
    pub fn runs(&self, map: &str, problem: usize, label: &str) -> Vec<&'r RunRecord> {
        let records = self.records;
        self.positions
            .get(&(map, problem, label))
            .map_or_else(Vec::new, |p| p.iter().map(|&i| &records[i]).collect())
    }

    /// Repeat `repeat` of `label` on problem `problem` of `map`.
    pub fn get(
        &self,
        map: &str,
        problem: usize,
        label: &str,
        repeat: u32,
    ) -> Option<&'r RunRecord> {
        let records = self.records;
        self.positions
            .get(&(map, problem, label))?
            .iter()
            .map(|&i| &records[i])
            .find(|r| r.repeat == repeat)
    }

    /// Repeat 0, where deterministic values are read.
    pub fn first(&self, map: &str, problem: usize, label: &str) -> Option<&'r RunRecord> {
        self.get(map, problem, label, 0)
    }
}
