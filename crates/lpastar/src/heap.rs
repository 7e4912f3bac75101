//! The priority queue U: an indexed 4-ary min-heap (insert, update, remove, pop in
//! `O(log n)`, no stale entries).
//!
//! Entries are `(k1, k2, vertex)`, ordered as tuples: the papers' two-part key `[k1; k2]`,
//! then the vertex's index (row-major, so the order of the grid's cells). The papers
//! leave ties of `[k1; k2]` open; the index makes the order total (a vertex is queued at
//! most once), so which vertex comes out first never depends on the heap's history
//! (tested below).
//!
//! The heap holds exactly the queued vertices. Each vertex's position in it (index + 1,
//! 0 when not queued) is kept by the caller in a [`Slots`] store (the engine's per-vertex
//! record), written whenever an entry moves, so that a key change or a removal finds its
//! entry in O(1) and sifts it from there.

/// A queue entry: `(k1, k2, vertex)`, keys in [`planner_api::Cost`] units.
pub(crate) type Entry = (u64, u64, u32);

/// Where the heap records each vertex's position: `slot(v)` is the index of `v`'s entry
/// plus one, 0 when `v` is not queued.
pub(crate) trait Slots {
    /// Records `slot` as `v`'s position.
    fn set_slot(&mut self, v: u32, slot: u32);
}

/// Whether `a` orders before `b`: the tuple order, with the two-part key compared as one
/// 128-bit number (fewer branches than comparing field by field).
#[inline(always)]
fn less(a: Entry, b: Entry) -> bool {
    let key = |e: Entry| u128::from(e.0) << 64 | u128::from(e.1);
    let (ka, kb) = (key(a), key(b));
    // Non-short-circuit operators: no branch on the outcome.
    (ka < kb) | ((ka == kb) & (a.2 < b.2))
}

/// The slot of index `i` (positions are below 2^32: at most one entry per 32-bit vertex).
#[inline(always)]
fn slot(i: usize) -> u32 {
    (i + 1) as u32
}

/// An indexed 4-ary min-heap of [`Entry`]s (see the [module docs](self)).
#[derive(Debug, Clone, Default)]
pub(crate) struct Heap {
    items: Vec<Entry>,
}

impl Heap {
    /// Empties the heap, keeping its memory. The slots are the caller's to reset.
    pub(crate) fn clear(&mut self) {
        self.items.clear();
    }

    /// Queued entries.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.items.len()
    }

    /// The least entry.
    #[inline]
    pub(crate) fn peek(&self) -> Option<Entry> {
        self.items.first().copied()
    }

    /// Inserts `entry`, whose vertex is not queued.
    #[inline]
    pub(crate) fn push(&mut self, entry: Entry, slots: &mut impl Slots) {
        let i = self.items.len();
        self.items.push(entry);
        self.sift_up(i, entry, slots);
    }

    /// Removes the least entry.
    #[inline]
    pub(crate) fn pop(&mut self, slots: &mut impl Slots) -> Option<Entry> {
        let last = self.items.pop()?;
        slots.set_slot(last.2, 0);
        if self.items.is_empty() {
            return Some(last);
        }
        let top = self.items[0];
        slots.set_slot(top.2, 0);
        // Bottom-up: the hole at the root descends along the least children to a leaf,
        // then `last` (usually among the largest) rises from there.
        let items = &mut self.items[..];
        let n = items.len();
        let mut i = 0;
        while let Some(least) = least_child(items, 4 * i + 1, n) {
            items[i] = items[least];
            slots.set_slot(items[i].2, slot(i));
            i = least;
        }
        self.sift_up(i, last, slots);
        Some(top)
    }

    /// Gives the entry in `slot` (its vertex's position, not 0) the new key of `entry`
    /// (same vertex), moving it up or down.
    #[inline]
    pub(crate) fn update(&mut self, slot: u32, entry: Entry, slots: &mut impl Slots) {
        let i = slot as usize - 1;
        if i > 0 && less(entry, self.items[(i - 1) / 4]) {
            self.sift_up(i, entry, slots);
        } else {
            self.sift_down(i, entry, slots);
        }
    }

    /// Removes the entry in `slot` (its vertex's position, not 0).
    #[inline]
    pub(crate) fn remove(&mut self, slot: u32, slots: &mut impl Slots) {
        let i = slot as usize - 1;
        let Some(last) = self.items.pop() else {
            return;
        };
        if let Some(&removed) = self.items.get(i) {
            slots.set_slot(removed.2, 0);
            self.update(slot, last, slots);
        } else {
            // The removed entry was the last one.
            slots.set_slot(last.2, 0);
        }
    }

    /// Places `entry` at `i` or above, moving greater parents down.
    #[inline(always)]
    fn sift_up(&mut self, mut i: usize, entry: Entry, slots: &mut impl Slots) {
        let items = &mut self.items[..];
        while i > 0 {
            let parent = (i - 1) / 4;
            if !less(entry, items[parent]) {
                break;
            }
            items[i] = items[parent];
            slots.set_slot(items[i].2, slot(i));
            i = parent;
        }
        items[i] = entry;
        slots.set_slot(entry.2, slot(i));
    }

    /// Places `entry` at `i` or below, moving lesser children up.
    #[inline(always)]
    fn sift_down(&mut self, mut i: usize, entry: Entry, slots: &mut impl Slots) {
        let items = &mut self.items[..];
        let n = items.len();
        while let Some(least) = least_child(items, 4 * i + 1, n) {
            let best = items[least];
            if !less(best, entry) {
                break;
            }
            items[i] = best;
            slots.set_slot(best.2, slot(i));
            i = least;
        }
        items[i] = entry;
        slots.set_slot(entry.2, slot(i));
    }
}

/// The least of the children `first..first + 4` (those below `n`), `None` for a leaf.
#[inline(always)]
fn least_child(items: &[Entry], first: usize, n: usize) -> Option<usize> {
    if first + 4 <= n {
        // All four children: a tournament of three comparisons.
        let c = &items[first..first + 4];
        let a = first + usize::from(less(c[1], c[0]));
        let b = first + 2 + usize::from(less(c[3], c[2]));
        Some(a + (b - a) * usize::from(less(items[b], items[a])))
    } else if first < n {
        let mut least = first;
        for child in first + 1..n {
            if less(items[child], items[least]) {
                least = child;
            }
        }
        Some(least)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeMap;

    impl Slots for Vec<u32> {
        fn set_slot(&mut self, v: u32, slot: u32) {
            self[v as usize] = slot;
        }
    }

    /// Random pushes, key changes (of any entry and of the top, as the engine's
    /// re-keying), removals and pops against a `BTreeMap` of the queued keys: the least
    /// entry is always the least `(k1, k2, v)`, so equal `[k1; k2]` come out by index, and
    /// every slot points at its vertex's entry.
    #[test]
    fn matches_a_sorted_map() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 64;
        let mut heap = Heap::default();
        let mut slots = vec![0u32; n];
        let mut model: BTreeMap<u32, (u64, u64)> = BTreeMap::new();
        for _ in 0..20_000 {
            let v = rng.gen_range(0..n as u32);
            let (k1, k2) = (rng.gen_range(0..4u64), rng.gen_range(0..3u64));
            let at = slots[v as usize];
            match rng.gen_range(0..5) {
                0 if at != 0 => {
                    heap.remove(at, &mut slots);
                    model.remove(&v);
                }
                1 => {
                    let popped = heap.pop(&mut slots);
                    let least = model.iter().map(|(&u, &(a, b))| (a, b, u)).min();
                    assert_eq!(popped, least);
                    if let Some((_, _, u)) = least {
                        model.remove(&u);
                    }
                }
                2 => {
                    if let Some((_, _, u)) = heap.peek() {
                        heap.update(1, (k1, k2, u), &mut slots);
                        model.insert(u, (k1, k2));
                    }
                }
                _ if at != 0 => {
                    heap.update(at, (k1, k2, v), &mut slots);
                    model.insert(v, (k1, k2));
                }
                _ => {
                    heap.push((k1, k2, v), &mut slots);
                    model.insert(v, (k1, k2));
                }
            }
            assert_eq!(heap.len(), model.len());
            for (u, &s) in slots.iter().enumerate() {
                assert_eq!(s != 0, model.contains_key(&(u as u32)));
                if s != 0 {
                    assert_eq!(heap.items[s as usize - 1].2, u as u32);
                }
            }
            let least = model.iter().map(|(&u, &(a, b))| (a, b, u)).min();
            assert_eq!(heap.peek(), least);
        }
        heap.clear();
        assert!(heap.peek().is_none());
    }
}
