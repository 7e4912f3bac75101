//! OPEN: a 4-ary min-heap of `(key, tie and node)` pairs with lazy deletion by the caller,
//! behind a stack of entries whose key equals the last key popped.
//!
//! A 4-ary heap has half the levels of a binary one and its four children share a cache
//! line. The stack (the *front*) holds entries pushed with the key of the last entry
//! popped; when keys never drop below the last one popped (a consistent heuristic, as
//! octile distance is on jump point graphs), those entries are among the least, so they
//! come out first, last in first out, without heap operations. That is the common case:
//! a successor on the way to the goal keeps its parent's `f`.

/// An entry: the bits of `f` (non-negative floats order like their bits), then the tie
/// value (high 32 bits, smaller for larger `g`) and the node (low 32 bits).
pub(crate) type Entry = (u64, u64);

/// The heap; the least entry comes out first.
#[derive(Debug, Clone)]
pub(crate) struct Open {
    items: Vec<Entry>,
    front: Vec<Entry>,
    /// The key of the last entry popped from `items` (`u64::MAX` before the first).
    front_key: u64,
}

impl Default for Open {
    fn default() -> Open {
        Open {
            items: Vec::new(),
            front: Vec::new(),
            front_key: u64::MAX,
        }
    }
}

impl Open {
    /// Empties the heap, keeping its memory.
    pub(crate) fn clear(&mut self) {
        self.items.clear();
        self.front.clear();
        self.front_key = u64::MAX;
    }

    /// Inserts `entry`.
    #[inline]
    pub(crate) fn push(&mut self, entry: Entry) {
        if entry.0 == self.front_key {
            self.front.push(entry);
            return;
        }
        let mut i = self.items.len();
        self.items.push(entry);
        while i > 0 {
            let parent = (i - 1) / 4;
            if self.items[parent] <= entry {
                break;
            }
            self.items[i] = self.items[parent];
            i = parent;
        }
        self.items[i] = entry;
    }

    /// Removes and returns an entry with the least key: the front's last, else the
    /// heap's least. Precondition: no key pushed is below the last key popped.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
        if let Some(entry) = self.front.pop() {
            return Some(entry);
        }
        let entry = self.pop_heap()?;
        self.front_key = entry.0;
        Some(entry)
    }

    /// Removes and returns the heap's least entry.
    #[inline]
    fn pop_heap(&mut self) -> Option<Entry> {
        let last = self.items.pop()?;
        let n = self.items.len();
        if n == 0 {
            return Some(last);
        }
        let top = self.items[0];
        let mut i = 0;
        loop {
            let first = 4 * i + 1;
            if first >= n {
                break;
            }
            let mut least = first;
            for child in first + 1..(first + 4).min(n) {
                if self.items[child] < self.items[least] {
                    least = child;
                }
            }
            if self.items[least] >= last {
                break;
            }
            self.items[i] = self.items[least];
            i = least;
        }
        self.items[i] = last;
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pops_a_least_key_when_keys_never_drop() {
        let mut open = Open::default();
        let mut reference: Vec<Entry> = Vec::new();
        let mut state = 12345u64;
        let mut last_key = 0;
        for round in 0..4000u64 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if state >> 62 == 0 {
                let least = reference.iter().map(|e| e.0).min();
                let popped = open.pop();
                assert_eq!(popped.map(|e| e.0), least, "round {round}");
                if let Some(e) = popped {
                    let at = reference.iter().position(|&x| x == e).unwrap();
                    reference.swap_remove(at);
                    last_key = e.0;
                }
            } else {
                // Keys at or above the last popped, often equal to it.
                let entry = (last_key + (state >> 40) % 3, round);
                open.push(entry);
                reference.push(entry);
            }
        }
        while let Some(least) = reference.iter().map(|e| e.0).min() {
            let e = open.pop().unwrap();
            assert_eq!(e.0, least);
            let at = reference.iter().position(|&x| x == e).unwrap();
            reference.swap_remove(at);
        }
        assert_eq!(open.pop(), None);
    }
}
