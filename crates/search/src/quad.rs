//! 4-ary min-heaps with lazy deletion by the caller.
//!
//! A 4-ary heap has half the levels of a binary one and its four children share a cache
//! line (for entries of 16 bytes or less).
//!
//! - [`QuadHeap`]: any `Ord + Copy` entry; the least comes out first. With entries that
//!   never compare equal (a push sequence in the key), the pop order is the key order,
//!   exactly as `std::collections::BinaryHeap` over the reversed key gives it.
//! - [`FrontHeap`]: `(key, tie)` pairs behind a stack of entries whose key equals the last
//!   key popped. When keys never drop below the last one popped (a consistent heuristic,
//!   as octile distance is on jump point graphs), those entries are among the least, so
//!   they come out first, last in first out, without heap operations. That is the common
//!   case of Jump Point Search: a successor on the way to the goal keeps its parent's `f`.

/// A 4-ary min-heap.
///
/// ```
/// use planner_search::QuadHeap;
///
/// let mut heap = QuadHeap::default();
/// for x in [5u32, 1, 4, 1, 3] {
///     heap.push(x);
/// }
/// let mut out = Vec::new();
/// while let Some(x) = heap.pop() {
///     out.push(x);
/// }
/// assert_eq!(out, [1, 1, 3, 4, 5]);
/// ```
#[derive(Debug, Clone)]
pub struct QuadHeap<E> {
    items: Vec<E>,
}

impl<E> Default for QuadHeap<E> {
    fn default() -> QuadHeap<E> {
        QuadHeap { items: Vec::new() }
    }
}

impl<E: Ord + Copy> QuadHeap<E> {
    /// Empties the heap, keeping its memory.
    pub fn clear(&mut self) {
        self.items.clear();
    }

    /// The number of entries.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the heap is empty.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The least entry, left in the heap.
    pub fn peek(&self) -> Option<&E> {
        self.items.first()
    }

    /// Inserts `entry`.
    #[inline]
    pub fn push(&mut self, entry: E) {
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
    pub fn pop(&mut self) -> Option<E> {
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
            let least = if first + 4 <= n {
                // Four children: a tournament whose outcomes are added to indices instead of
                // branched on (under callgrind's branch simulation, the branches of the scan
                // below took 50.5 of JPS's 119.5 million mispredictions on random512-10-0).
                // The earliest of equal children wins, as in the scan.
                let items = &self.items;
                let left = first + usize::from(items[first + 1] < items[first]);
                let right = first + 2 + usize::from(items[first + 3] < items[first + 2]);
                if items[right] < items[left] {
                    right
                } else {
                    left
                }
            } else {
                let mut least = first;
                for child in first + 1..n {
                    if self.items[child] < self.items[least] {
                        least = child;
                    }
                }
                least
            };
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

/// A [`FrontHeap`] entry: the key (for example the bits of `f`: non-negative floats order
/// like their bits), then the tie value and node (compared only inside the heap).
pub type FrontEntry = (u64, u64);

/// A 4-ary heap of [`FrontEntry`]s behind a stack of the entries pushed with the key of
/// the last entry popped (see the module docs).
///
/// Among entries with the least key, the stack's come out first, last in first out; the
/// heap's in `(key, tie)` order. Precondition: no key pushed is below the last key popped.
///
/// Each entry is held as one `u128`, the key in the high half: the same order as the
/// pair's, but a comparison is one 128-bit compare without branches (callgrind: a JPS+ pass on
/// den520d took 51.6 M instructions against 53.7 M with the pairs).
#[derive(Debug, Clone)]
pub struct FrontHeap {
    heap: QuadHeap<u128>,
    front: Vec<u128>,
    /// The key of the last entry popped from `heap` (`u64::MAX` before the first).
    front_key: u64,
}

impl Default for FrontHeap {
    fn default() -> FrontHeap {
        FrontHeap {
            heap: QuadHeap::default(),
            front: Vec::new(),
            front_key: u64::MAX,
        }
    }
}

/// `entry` as one `u128` that orders as the pair does.
#[inline(always)]
fn pack((key, tie): FrontEntry) -> u128 {
    u128::from(key) << 64 | u128::from(tie)
}

/// The pair [`pack`] packed.
#[inline(always)]
fn unpack(entry: u128) -> FrontEntry {
    ((entry >> 64) as u64, entry as u64)
}

impl FrontHeap {
    /// Empties the heap, keeping its memory.
    pub fn clear(&mut self) {
        self.heap.clear();
        self.front.clear();
        self.front_key = u64::MAX;
    }

    /// Inserts `entry`.
    #[inline(always)]
    pub fn push(&mut self, entry: FrontEntry) {
        if entry.0 == self.front_key {
            self.front.push(pack(entry));
        } else {
            self.heap.push(pack(entry));
        }
    }

    /// Removes and returns an entry with the least key: the front's last, else the
    /// heap's least.
    #[inline(always)]
    pub fn pop(&mut self) -> Option<FrontEntry> {
        if let Some(entry) = self.front.pop() {
            return Some(unpack(entry));
        }
        let entry = unpack(self.heap.pop()?);
        self.front_key = entry.0;
        Some(entry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn front_heap_pops_a_least_key_when_keys_never_drop() {
        let mut open = FrontHeap::default();
        let mut reference: Vec<FrontEntry> = Vec::new();
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

    #[test]
    fn quad_heap_pops_in_the_order_of_a_reversed_binary_heap() {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        let mut ours = QuadHeap::default();
        let mut std_heap = BinaryHeap::new();
        let mut state = 777u64;
        for round in 0..20_000u64 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if state >> 62 == 0 {
                assert_eq!(ours.pop(), std_heap.pop().map(|Reverse(e)| e), "{round}");
            } else {
                // Many equal keys; the round makes entries distinct.
                let entry = ((state >> 40) % 50, round);
                ours.push(entry);
                std_heap.push(Reverse(entry));
            }
            assert_eq!(ours.len(), std_heap.len());
        }
        while let Some(Reverse(e)) = std_heap.pop() {
            assert_eq!(ours.pop(), Some(e));
        }
        assert!(ours.is_empty());
    }
}
