//! The priority queue U: a 4-ary min-heap with lazy deletion.
//!
//! Entries are `(k1, k2, tag)` with `tag = vertex << 32 | generation`, ordered as tuples:
//! the papers' two-part key `[k1; k2]`, then the vertex's index (row-major, so the order
//! of the grid's cells), then the generation. The papers leave ties of `[k1; k2]` open;
//! the index makes the order of the live entries total (a vertex has at most one live
//! entry), so which vertex comes out first never depends on the heap's history (tested
//! below).
//!
//! The heap holds no positions. The engine records, per vertex, the generation of its one
//! live entry (0: not queued); changing a queued vertex's key pushes a new entry with a
//! new generation and removing a vertex only clears its record, so the older entries are
//! *stale* and skipped when they reach the top. Generations come from one counter, so a
//! stale entry never matches a later record. [`Heap::retain`] drops the stale entries
//! and [`Heap::retag`] renumbers the live ones; the engine does so when stale entries outnumber the
//! live ones (so the heap holds at most about twice the queued vertices) and before the
//! counter wraps.

/// A queue entry: `(k1, k2, vertex << 32 | generation)`, keys in [`planner_api::Cost`]
/// units.
pub(crate) type Entry = (u64, u64, u64);

/// Packs a vertex and a generation into an entry's tag.
pub(crate) fn tag(vertex: u32, generation: u32) -> u64 {
    u64::from(vertex) << 32 | u64::from(generation)
}

/// The vertex of a tag.
pub(crate) fn tag_vertex(tag: u64) -> u32 {
    (tag >> 32) as u32
}

/// The generation of a tag.
pub(crate) fn tag_generation(tag: u64) -> u32 {
    tag as u32
}

/// Whether `a` orders before `b`: the tuple order, with the two-part key compared as one
/// 128-bit number (fewer branches than comparing field by field).
#[inline]
fn less(a: Entry, b: Entry) -> bool {
    let key = |e: Entry| u128::from(e.0) << 64 | u128::from(e.1);
    let (ka, kb) = (key(a), key(b));
    // Non-short-circuit operators: no branch on the outcome.
    (ka < kb) | ((ka == kb) & (a.2 < b.2))
}

/// A 4-ary min-heap of [`Entry`]s (see the [module docs](self)).
#[derive(Debug, Clone, Default)]
pub(crate) struct Heap {
    items: Vec<Entry>,
}

impl Heap {
    /// Empties the heap, keeping its memory.
    pub(crate) fn clear(&mut self) {
        self.items.clear();
    }

    /// Entries, stale ones included.
    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// The least entry.
    #[inline]
    pub(crate) fn peek(&self) -> Option<Entry> {
        self.items.first().copied()
    }

    /// Inserts `entry`.
    #[inline]
    pub(crate) fn push(&mut self, entry: Entry) {
        let mut i = self.items.len();
        self.items.push(entry);
        while i > 0 {
            let parent = (i - 1) / 4;
            if !less(entry, self.items[parent]) {
                break;
            }
            self.items[i] = self.items[parent];
            i = parent;
        }
        self.items[i] = entry;
    }

    /// Removes the least entry.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
        let last = self.items.pop()?;
        if self.items.is_empty() {
            return Some(last);
        }
        let top = self.items[0];
        // Bottom-up: the hole at the root descends along the least children to a leaf,
        // then `last` (usually among the largest) rises from there.
        let items = &mut self.items[..];
        let n = items.len();
        let mut i = 0;
        loop {
            let first = 4 * i + 1;
            let least = if first + 4 <= n {
                let c = &items[first..first + 4];
                let a = first + usize::from(less(c[1], c[0]));
                let b = first + 2 + usize::from(less(c[3], c[2]));
                a + (b - a) * usize::from(less(items[b], items[a]))
            } else if first < n {
                let mut least = first;
                for child in first + 1..n {
                    if less(items[child], items[least]) {
                        least = child;
                    }
                }
                least
            } else {
                break;
            };
            items[i] = items[least];
            i = least;
        }
        while i > 0 {
            let parent = (i - 1) / 4;
            if !less(last, items[parent]) {
                break;
            }
            items[i] = items[parent];
            i = parent;
        }
        items[i] = last;
        Some(top)
    }

    /// Replaces the least entry by `entry` (a pop and a push in one pass down).
    /// Precondition: the heap is not empty.
    #[inline]
    pub(crate) fn replace_top(&mut self, entry: Entry) {
        self.sift_down(0, entry);
    }

    /// Places `entry` at `i` or below, moving lesser children up.
    #[inline]
    fn sift_down(&mut self, mut i: usize, entry: Entry) {
        let items = &mut self.items[..];
        let n = items.len();
        loop {
            let first = 4 * i + 1;
            let least = if first + 4 <= n {
                // All four children: a tournament of three comparisons.
                let c = &items[first..first + 4];
                let a = first + usize::from(less(c[1], c[0]));
                let b = first + 2 + usize::from(less(c[3], c[2]));
                let pick_b = less(items[b], items[a]);
                a + (b - a) * usize::from(pick_b)
            } else if first < n {
                let mut least = first;
                for child in first + 1..n {
                    if less(items[child], items[least]) {
                        least = child;
                    }
                }
                least
            } else {
                break;
            };
            let best = items[least];
            if !less(best, entry) {
                break;
            }
            items[i] = best;
            i = least;
        }
        items[i] = entry;
    }

    /// Keeps only the entries `is_live` accepts and restores the heap order.
    pub(crate) fn retain(&mut self, is_live: impl FnMut(u64) -> bool) {
        let mut is_live = is_live;
        self.items.retain(|entry| is_live(entry.2));
        self.heapify();
    }

    /// Gives every entry the tag `renumber` returns for the vertex of its tag. Only
    /// after [`Heap::retain`] left one entry a vertex: the order is then decided by
    /// `(k1, k2, vertex)` alone, so it stays a heap.
    pub(crate) fn retag(&mut self, mut renumber: impl FnMut(u32) -> u64) {
        for entry in &mut self.items {
            entry.2 = renumber(tag_vertex(entry.2));
        }
    }

    /// Restores the heap order of all entries.
    fn heapify(&mut self) {
        let n = self.items.len();
        if n < 2 {
            return;
        }
        for i in (0..=(n - 2) / 4).rev() {
            let entry = self.items[i];
            self.sift_down(i, entry);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeMap;

    /// Random pushes, key changes and removals, done lazily with generation records as the
    /// engine does, against a `BTreeMap` of the live keys: the least live entry is always
    /// the least `(k1, k2, v)`, so equal `[k1; k2]` come out by index, and compaction
    /// keeps exactly the live entries.
    #[test]
    fn matches_a_sorted_map() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 64;
        let mut heap = Heap::default();
        let mut record = vec![0u32; n];
        let mut next = 1u32;
        let mut model: BTreeMap<u32, (u64, u64)> = BTreeMap::new();
        let least_live = |heap: &mut Heap, record: &[u32]| loop {
            let (k1, k2, t) = heap.peek()?;
            if record[tag_vertex(t) as usize] == tag_generation(t) {
                return Some((k1, k2, tag_vertex(t)));
            }
            heap.pop();
        };
        for round in 0..20_000 {
            let v = rng.gen_range(0..n as u32);
            let (k1, k2) = (rng.gen_range(0..4u64), rng.gen_range(0..3u64));
            if record[v as usize] != 0 && rng.gen_range(0..3) == 0 {
                record[v as usize] = 0;
                model.remove(&v);
            } else if let (Some((_, _, t)), 0) = (heap.peek(), rng.gen_range(0..4)) {
                // The engine's re-keying: the top entry, live or stale, gets a new key.
                let u = tag_vertex(t);
                heap.replace_top((k1, k2, t));
                if record[u as usize] == tag_generation(t) {
                    model.insert(u, (k1, k2));
                }
            } else {
                record[v as usize] = next;
                heap.push((k1, k2, tag(v, next)));
                next += 1;
                model.insert(v, (k1, k2));
            }
            if round % 97 == 0 {
                next = 1;
                heap.retain(|t| record[tag_vertex(t) as usize] == tag_generation(t));
                heap.retag(|v| {
                    record[v as usize] = next;
                    next += 1;
                    tag(v, next - 1)
                });
                assert_eq!(heap.len(), model.len());
            }
            let least = model.iter().map(|(&v, &(a, b))| (a, b, v)).min();
            assert_eq!(least_live(&mut heap, &record), least);
        }
        heap.clear();
        assert!(heap.peek().is_none());
    }
}
