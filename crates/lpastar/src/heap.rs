//! The priority queue U: an indexed binary min-heap with decrease- and increase-key and
//! removal of any vertex.
//!
//! Entries are ordered by the full key `(k1, k2, vertex index)`: the papers' two-part key
//! and then the vertex's row-major index. The papers leave ties of `[k1; k2]` open; the
//! index makes the order total, so which vertex comes out first never depends on the
//! heap's insertion history (tested below).

/// A key `[k1; k2]` in units of [`planner_api::Cost`], with the vertex index last.
pub(crate) type Key = (u64, u64, u32);

/// The heap and each vertex's position in it (`pos[v] = index + 1`, 0 when absent).
#[derive(Debug, Clone, Default)]
pub(crate) struct Heap {
    entries: Vec<Key>,
    pos: Vec<u32>,
}

impl Heap {
    /// Sizes the position table for `n` vertices and empties the heap.
    pub(crate) fn fit(&mut self, n: usize) {
        self.clear();
        if self.pos.len() != n {
            self.pos = vec![0; n];
        }
    }

    /// Empties the heap (clearing only the positions of the entries it held).
    pub(crate) fn clear(&mut self) {
        for &(_, _, v) in &self.entries {
            self.pos[v as usize] = 0;
        }
        self.entries.clear();
    }

    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.entries.len()
    }

    pub(crate) fn contains(&self, v: u32) -> bool {
        self.pos[v as usize] != 0
    }

    /// The least entry.
    pub(crate) fn top(&self) -> Option<Key> {
        self.entries.first().copied()
    }

    /// Inserts `v`, which is not in the heap, with key `(k1, k2)`.
    pub(crate) fn push(&mut self, v: u32, k1: u64, k2: u64) {
        self.entries.push((k1, k2, v));
        let i = self.entries.len() - 1;
        self.pos[v as usize] = i as u32 + 1;
        self.sift_up(i);
    }

    /// Sets the key of `v`, which is in the heap.
    pub(crate) fn update(&mut self, v: u32, k1: u64, k2: u64) {
        let i = self.pos[v as usize] as usize - 1;
        let old = self.entries[i];
        self.entries[i] = (k1, k2, v);
        if (k1, k2, v) < old {
            self.sift_up(i);
        } else {
            self.sift_down(i);
        }
    }

    /// Removes `v`, which is in the heap.
    pub(crate) fn remove(&mut self, v: u32) {
        let i = self.pos[v as usize] as usize - 1;
        self.pos[v as usize] = 0;
        let last = self.entries.len() - 1;
        if i != last {
            let moved = self.entries[last];
            self.entries[i] = moved;
            self.pos[moved.2 as usize] = i as u32 + 1;
            self.entries.pop();
            if moved < self.entries[i.saturating_sub(1) / 2] && i > 0 {
                self.sift_up(i);
            } else {
                self.sift_down(i);
            }
        } else {
            self.entries.pop();
        }
    }

    fn sift_up(&mut self, mut i: usize) {
        let entry = self.entries[i];
        while i > 0 {
            let parent = (i - 1) / 2;
            if self.entries[parent] <= entry {
                break;
            }
            self.entries[i] = self.entries[parent];
            self.pos[self.entries[i].2 as usize] = i as u32 + 1;
            i = parent;
        }
        self.entries[i] = entry;
        self.pos[entry.2 as usize] = i as u32 + 1;
    }

    fn sift_down(&mut self, mut i: usize) {
        let entry = self.entries[i];
        let n = self.entries.len();
        loop {
            let left = 2 * i + 1;
            if left >= n {
                break;
            }
            let right = left + 1;
            let child = if right < n && self.entries[right] < self.entries[left] {
                right
            } else {
                left
            };
            if self.entries[child] >= entry {
                break;
            }
            self.entries[i] = self.entries[child];
            self.pos[self.entries[i].2 as usize] = i as u32 + 1;
            i = child;
        }
        self.entries[i] = entry;
        self.pos[entry.2 as usize] = i as u32 + 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeMap;

    /// Random pushes, updates and removals against a `BTreeMap` of the same keys: the
    /// top is always the least `(k1, k2, v)`, so equal `[k1; k2]` come out by index.
    #[test]
    fn matches_a_sorted_map() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let n = 64;
        let mut heap = Heap::default();
        heap.fit(n);
        let mut model: BTreeMap<u32, (u64, u64)> = BTreeMap::new();
        for _ in 0..20_000 {
            let v = rng.gen_range(0..n as u32);
            let (k1, k2) = (rng.gen_range(0..4u64), rng.gen_range(0..3u64));
            match (heap.contains(v), rng.gen_range(0..3)) {
                (false, _) => {
                    heap.push(v, k1, k2);
                    model.insert(v, (k1, k2));
                }
                (true, 0) => {
                    heap.remove(v);
                    model.remove(&v);
                }
                (true, _) => {
                    heap.update(v, k1, k2);
                    model.insert(v, (k1, k2));
                }
            }
            let least = model.iter().map(|(&v, &(a, b))| (a, b, v)).min();
            assert_eq!(heap.top(), least);
            assert_eq!(heap.len(), model.len());
        }
        heap.clear();
        assert!(heap.top().is_none() && (0..n as u32).all(|v| !heap.contains(v)));
    }
}
