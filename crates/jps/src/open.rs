//! OPEN: a 4-ary min-heap of `(key, tie and node)` pairs with lazy deletion by the caller.
//!
//! A 4-ary heap has half the levels of a binary one and its four children share a cache
//! line, which matters when OPEN is popped once per jump point expanded.

/// An entry: the bits of `f` (non-negative floats order like their bits), then the tie
/// value (high 32 bits, smaller for larger `g`) and the node (low 32 bits).
pub(crate) type Entry = (u64, u64);

/// The heap; the least entry comes out first.
#[derive(Debug, Clone, Default)]
pub(crate) struct Open {
    items: Vec<Entry>,
}

impl Open {
    /// Empties the heap, keeping its memory.
    pub(crate) fn clear(&mut self) {
        self.items.clear();
    }

    /// Inserts `entry`.
    #[inline]
    pub(crate) fn push(&mut self, entry: Entry) {
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

    /// Removes and returns the least entry.
    #[inline]
    pub(crate) fn pop(&mut self) -> Option<Entry> {
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
    fn pops_in_order() {
        let mut open = Open::default();
        let mut reference = Vec::new();
        let mut state = 12345u64;
        for round in 0..2000u64 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if state >> 62 == 0 {
                let expected = reference.iter().min().copied();
                if let Some(e) = expected {
                    let at = reference.iter().position(|&x| x == e).unwrap();
                    reference.swap_remove(at);
                }
                assert_eq!(open.pop(), expected, "round {round}");
            } else {
                let entry = ((state >> 40) % 50, round);
                open.push(entry);
                reference.push(entry);
            }
        }
        reference.sort();
        for e in reference {
            assert_eq!(open.pop(), Some(e));
        }
        assert_eq!(open.pop(), None);
    }
}
