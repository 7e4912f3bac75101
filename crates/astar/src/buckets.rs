//! OPEN as buckets of equal f: a small heap of the distinct f values in OPEN, and per
//! value a heap of (tie, sequence) entries, with lazy deletion.
//!
//! Entries come out in exactly the order of the full key (f, tie, sequence), the order
//! of a lazy-deletion binary heap, but most comparisons now happen inside one bucket, where
//! entries are few, and the outer heap holds only the handful of distinct f values OPEN
//! spans. A node improved while in OPEN gets a second entry; the older one is skipped when
//! it comes out (the node is then CLOSED).

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};
use std::hash::{BuildHasherDefault, Hasher};

/// A heap key, compared lexicographically: `f`, the tie value, the insertion sequence (see
/// `AStar::search` for the encoding).
pub(crate) type Key = (u64, u64, u64);

/// A multiplicative hasher for the f keys (bit patterns of floats): one multiply.
#[derive(Default)]
pub(crate) struct FHasher(u64);

impl Hasher for FHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
        }
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (value ^ (value >> 29)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

type Bucket = BinaryHeap<Reverse<(u64, u64, u32)>>;

/// The bucketed OPEN list.
#[derive(Debug, Default, Clone)]
pub(crate) struct Buckets {
    values: BinaryHeap<Reverse<u64>>,
    index: HashMap<u64, usize, BuildHasherDefault<FHasher>>,
    buckets: Vec<Bucket>,
    free: Vec<usize>,
    len: usize,
}

impl Buckets {
    pub(crate) fn clear(&mut self) {
        for (_, slot) in self.index.drain() {
            self.buckets[slot].clear();
            self.free.push(slot);
        }
        self.values.clear();
        self.len = 0;
    }

    /// Entries, stale ones included.
    pub(crate) fn len(&self) -> usize {
        self.len
    }

    pub(crate) fn push(&mut self, node: u32, (f, tie, seq): Key) {
        let slot = match self.index.get(&f) {
            Some(&slot) => slot,
            None => {
                let slot = self.free.pop().unwrap_or_else(|| {
                    self.buckets.push(BinaryHeap::new());
                    self.buckets.len() - 1
                });
                self.index.insert(f, slot);
                self.values.push(Reverse(f));
                slot
            }
        };
        self.buckets[slot].push(Reverse((tie, seq, node)));
        self.len += 1;
    }

    /// Removes and returns the entry with the least key.
    pub(crate) fn pop(&mut self) -> Option<u32> {
        let &Reverse(f) = self.values.peek()?;
        let slot = *self.index.get(&f)?;
        let Reverse((_, _, node)) = self.buckets[slot].pop()?;
        self.len -= 1;
        if self.buckets[slot].is_empty() {
            self.values.pop();
            self.index.remove(&f);
            self.free.push(slot);
        }
        Some(node)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_in_full_key_order() {
        // Independent check: sort all keys.
        let mut buckets = Buckets::default();
        let mut reference = Vec::new();
        let mut state = 99u64;
        for round in 0..3 {
            for seq in 0..3000u64 {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let key = ((state % 17) as f64 * 0.5f64.sqrt()).to_bits();
                let tie = (state >> 20) % 3;
                let node = (seq % 700) as u32;
                buckets.push(node, (key, tie, seq));
                reference.push(((key, tie, seq), node));
            }
            reference.sort();
            for &(_, node) in &reference {
                assert_eq!(buckets.pop(), Some(node), "round {round}");
            }
            assert_eq!(buckets.pop(), None);
            reference.clear();
            buckets.clear();
        }
    }
}
