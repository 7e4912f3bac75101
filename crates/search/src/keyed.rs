//! A priority queue of vertices with two-part keys whose keys change while queued: the
//! queue U of LPA* and D* Lite (planner-lpastar's engine). A ring of narrow `k1` buckets in
//! front of the least bucket, with lazy deletion by tickets.
//!
//! Unlike the OPEN lists of [`crate::bucket`], which take a node again when it improves
//! and leave the older entry to be skipped, [`KeyedQueue`] holds each vertex at most once
//! and knows which are queued: UpdateVertex's "if u is in U, update its key; else insert
//! it" and "remove u from U" are its operations, and its key changes go either way (up
//! after D* Lite's `km` grew, down when a repair lowers `rhs`).
//!
//! Entries are `(k1, k2, vertex)`, ordered as tuples: the papers' two-part key `[k1; k2]`,
//! then the vertex's index (row-major, so the order of the grid's cells). The papers
//! leave ties of `[k1; k2]` open; the index makes the order total (a vertex is queued at
//! most once), so which vertex comes out first never depends on the queue's history
//! (tested below against a sorted map). Keys are [`planner_api::Cost`] units.
//!
//! ```
//! use planner_search::keyed::KeyedQueue;
//!
//! let mut queue = KeyedQueue::default();
//! queue.reset(4); // vertices 0..4
//! queue.push(30, 10, 2);
//! queue.push(20, 10, 3);
//! queue.push(20, 10, 1);
//! queue.update(40, 0, 3); // a key change: vertex 3 moves behind the others
//! assert!(queue.contains(3));
//! // Equal keys come out by vertex index.
//! assert_eq!(queue.top(), Some((20, 10, 1)));
//! queue.pop_top();
//! queue.remove(2);
//! assert_eq!(queue.top(), Some((40, 0, 3)));
//! queue.pop_top();
//! assert_eq!(queue.top(), None);
//! ```
//!
//! Why buckets: after the agent moves, D* Lite's key modifier `km` grows and the queued
//! keys become lower bounds; each one popped out of date is put back with its larger key
//! (Fig. 4 of the paper). In a heap holding the whole frontier of every earlier search,
//! that key increase sifts down through all its levels (575 instructions each, callgrind on
//! den520d navigations), and re-keying happens about 0.8 times per expansion. Here a
//! larger key usually lands in a later bucket: an append.
//!
//! Layout: bucket `b` holds the keys with `k1 >> BUCKET_SHIFT == b` (an eighth of a cell
//! wide; a quarter and a sixteenth measured the same). The `front` holds every entry whose
//! bucket is at most `current`: a run sorted with the least last (a pop is a vector pop),
//! first the bucket `current` as it was when it came up, and a 4-ary min-heap (branch-free
//! comparisons, bottom-up pops) for the keys pushed since into that bucket or below it.
//! When the run is empty, the heap's entries become the run, sorted at once. Measured with
//! the front as one heap, it held on average 28 entries at a pop in den520d navigations
//! (radius 5) and 108 on random512-10-0 (radii 1 and 5), where most were such pushes (one
//! sorted vector for both, kept sorted on every push, was 20 % slower there). With the run
//! refilled only when it came up, the heap still held 90 to 94 entries on average at a pop
//! on random512-10-0 and gave 83-84 % of the pops there: while the agent knows little, the
//! octile heuristic is exact on most of the known map, so a search's successors share their
//! parent's `k1` and land in the current bucket, ordered by `k2` alone. Sorting them in
//! batches instead cut D* Lite's summed planning time there by a quarter to a third (the
//! D* Lite section of PERFORMANCE.md, sixth round). The ring holds, unordered, the entries of the
//! buckets `current + 1 .. current + RING` (a bit per bucket says which are occupied); the
//! rest wait in `far`. When the front runs empty, `current` moves to the next occupied
//! bucket (or `far`'s least, whichever is first) and that bucket's live entries are sorted
//! into it. So every entry outside the front has a larger `k1` than every entry inside it,
//! and the front's least is the queue's. `current` only grows: a key pushed below it joins
//! the front's heap.
//!
//! Deletion is lazy: each vertex has a ticket (0: not queued), and each entry carries the
//! ticket it was pushed with. A key change or removal issues a new ticket (or 0), which
//! makes the older entry stale; stale entries are dropped when they reach the front's top
//! or when their bucket comes up. When stale entries outnumber the queued ones (twice over,
//! plus `SLACK`, 1,024), every container is filtered at once, so memory stays within a
//! constant factor of the queue's size. Tickets are 32-bit; before they would wrap, the
//! queue is filtered and the queued entries renumbered.
//!
//! A planner's counters (pushes, pops, key changes, removals) are its own, one per operation
//! on the papers' queue U; stale entries are not counted. The containers keep their memory
//! across sessions, so once a map's first searches have grown them, a search allocates
//! nothing.

/// A bucket is `2^BUCKET_SHIFT` [`planner_api::Cost`] units wide: an eighth of a cell.
const BUCKET_SHIFT: u32 = planner_api::Cost::FRACTION_BITS - 3;

/// Buckets in the ring (a power of two): with an eighth of a cell each, keys up to 512
/// cells above the current bucket's.
const RING: usize = 4096;

/// Stale entries tolerated beyond twice the queued ones before the queue is filtered.
const SLACK: usize = 1024;

/// A queue entry: the key, the vertex and the ticket it was pushed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Entry {
    k1: u64,
    k2: u64,
    vertex: u32,
    ticket: u32,
}

impl Entry {
    /// The key `[k1; k2]` as one 128-bit number (one comparison, no branches).
    #[inline(always)]
    fn key(&self) -> u128 {
        u128::from(self.k1) << 64 | u128::from(self.k2)
    }

    #[inline(always)]
    fn bucket(&self) -> u64 {
        self.k1 >> BUCKET_SHIFT
    }
}

/// The queue's order: `(k1, k2, vertex)`, then the ticket (which only orders a vertex's
/// stale entries of the same key among themselves and its live one). [`less`] is the same
/// order as a branch-free test, for the heap.
#[inline(always)]
fn order(a: &Entry, b: &Entry) -> std::cmp::Ordering {
    (a.key(), a.vertex, a.ticket).cmp(&(b.key(), b.vertex, b.ticket))
}

/// Whether `a` orders before `b` ([`order`]). Non-short-circuit operators: no branch on
/// the outcome.
#[inline(always)]
fn less(a: &Entry, b: &Entry) -> bool {
    let (ka, kb) = (a.key(), b.key());
    let (ta, tb) = (
        u64::from(a.vertex) << 32 | u64::from(a.ticket),
        u64::from(b.vertex) << 32 | u64::from(b.ticket),
    );
    (ka < kb) | ((ka == kb) & (ta < tb))
}

/// The entries of the buckets up to `current`: a sorted run (the least last, so a pop is a
/// vector pop; first the bucket last entered, later the heap's entries sorted when the run
/// ran empty), and the entries pushed since, which the ring did not take (keys of the
/// current bucket or below), in a heap.
#[derive(Debug, Clone, Default)]
struct Front {
    run: Vec<Entry>,
    heap: Heap,
}

impl Front {
    /// The least entry. When the run is empty the heap's entries become the run, sorted:
    /// one sort instead of a heap pop each.
    #[inline]
    fn peek(&mut self) -> Option<&Entry> {
        if self.run.is_empty() && self.heap.items.len() > 1 {
            self.run.append(&mut self.heap.items);
            self.run.sort_unstable_by(|a, b| order(b, a));
        }
        match (self.run.last(), self.heap.peek()) {
            (Some(r), Some(h)) if less(h, r) => Some(h),
            (Some(r), _) => Some(r),
            (None, h) => h,
        }
    }

    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        match (self.run.last(), self.heap.peek()) {
            (Some(r), Some(h)) if less(h, r) => self.heap.pop(),
            (Some(_), _) => self.run.pop(),
            (None, _) => self.heap.pop(),
        }
    }

    #[inline]
    fn push(&mut self, entry: Entry) {
        self.heap.push(entry);
    }

    fn clear(&mut self) {
        self.run.clear();
        self.heap.clear();
    }

    fn is_empty(&self) -> bool {
        self.run.is_empty() && self.heap.items.is_empty()
    }
}

/// A 4-ary min-heap of entries (the least by [`less`] on top).
#[derive(Debug, Clone, Default)]
struct Heap {
    items: Vec<Entry>,
}

impl Heap {
    #[inline]
    fn peek(&self) -> Option<&Entry> {
        self.items.first()
    }

    fn clear(&mut self) {
        self.items.clear();
    }

    #[inline]
    fn push(&mut self, entry: Entry) {
        let i = self.items.len();
        self.items.push(entry);
        self.sift_up(i, entry);
    }

    /// Removes the least entry: the hole at the root descends along the least children to
    /// a leaf, then the last entry (usually among the largest) rises from there.
    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        let last = self.items.pop()?;
        if self.items.is_empty() {
            return Some(last);
        }
        let top = self.items[0];
        let items = &mut self.items[..];
        let n = items.len();
        let mut i = 0;
        while let Some(least) = least_child(items, 4 * i + 1, n) {
            items[i] = items[least];
            i = least;
        }
        self.sift_up(i, last);
        Some(top)
    }

    /// Restores the heap order of `items` from scratch, in linear time.
    fn heapify(&mut self) {
        let n = self.items.len();
        for start in (0..n.saturating_sub(1).div_ceil(4)).rev() {
            let entry = self.items[start];
            self.sift_down(start, entry);
        }
    }

    /// Places `entry` at `i` or below, moving lesser children up.
    fn sift_down(&mut self, mut i: usize, entry: Entry) {
        let items = &mut self.items[..];
        let n = items.len();
        while let Some(least) = least_child(items, 4 * i + 1, n) {
            if !less(&items[least], &entry) {
                break;
            }
            items[i] = items[least];
            i = least;
        }
        items[i] = entry;
    }

    #[inline(always)]
    fn sift_up(&mut self, mut i: usize, entry: Entry) {
        let items = &mut self.items[..];
        while i > 0 {
            let parent = (i - 1) / 4;
            if !less(&entry, &items[parent]) {
                break;
            }
            items[i] = items[parent];
            i = parent;
        }
        items[i] = entry;
    }
}

/// The least of the children `first..first + 4` (those below `n`), `None` for a leaf.
#[inline(always)]
fn least_child(items: &[Entry], first: usize, n: usize) -> Option<usize> {
    if first + 4 <= n {
        // All four children: a tournament of three comparisons.
        let c = &items[first..first + 4];
        let a = first + usize::from(less(&c[1], &c[0]));
        let b = first + 2 + usize::from(less(&c[3], &c[2]));
        Some(a + (b - a) * usize::from(less(&items[b], &items[a])))
    } else if first < n {
        let mut least = first;
        for child in first + 1..n {
            if less(&items[child], &items[least]) {
                least = child;
            }
        }
        Some(least)
    } else {
        None
    }
}

/// The queue (see the [module docs](self)). Every method that takes a vertex requires it
/// below the `n` of the last [`KeyedQueue::reset`] (a vertex index is a caller's array
/// index; out of range panics).
#[derive(Debug, Clone)]
pub struct KeyedQueue {
    front: Front,
    ring: Vec<Vec<Entry>>,
    /// A bit per ring bucket: set when it holds entries (live or stale).
    occupied: Vec<u64>,
    far: Vec<Entry>,
    /// The least bucket in `far` (`u64::MAX` when empty); always above `current`.
    far_min: u64,
    /// The heap holds the buckets up to this one.
    current: u64,
    /// Per vertex, the ticket of its live entry; 0 when not queued.
    tickets: Vec<u32>,
    next_ticket: u32,
    /// Queued vertices.
    live: usize,
    /// Entries held, live and stale.
    held: usize,
}

impl Default for KeyedQueue {
    fn default() -> KeyedQueue {
        KeyedQueue {
            front: Front::default(),
            ring: vec![Vec::new(); RING],
            occupied: vec![0; RING / 64],
            far: Vec::new(),
            far_min: u64::MAX,
            current: 0,
            tickets: Vec::new(),
            next_ticket: 1,
            live: 0,
            held: 0,
        }
    }
}

impl KeyedQueue {
    /// Empties the queue for vertices `0 .. n`, keeping its memory.
    pub fn reset(&mut self, n: usize) {
        if self.tickets.len() == n {
            // Only the queued vertices have tickets; held entries name every one of them.
            let tickets = &mut self.tickets;
            let mut forget = |e: &Entry| {
                if let Some(t) = tickets.get_mut(e.vertex as usize) {
                    *t = 0;
                }
            };
            while let Some(e) = self.front.pop() {
                forget(&e);
            }
            for (b, bucket) in self.ring.iter_mut().enumerate() {
                if self.occupied[b / 64] >> (b % 64) & 1 == 1 {
                    bucket.iter().for_each(&mut forget);
                    bucket.clear();
                }
            }
            self.far.iter().for_each(&mut forget);
        } else {
            self.tickets.clear();
            self.tickets.resize(n, 0);
            self.front.clear();
            self.ring.iter_mut().for_each(Vec::clear);
        }
        self.occupied.fill(0);
        self.far.clear();
        self.far_min = u64::MAX;
        self.current = 0;
        self.next_ticket = 1;
        self.live = 0;
        self.held = 0;
    }

    /// Whether `vertex` is queued.
    #[inline]
    pub fn contains(&self, vertex: u32) -> bool {
        self.tickets[vertex as usize] != 0
    }

    /// Queues `vertex`, which is not queued, with key `[k1; k2]`.
    #[inline]
    pub fn push(&mut self, k1: u64, k2: u64, vertex: u32) {
        self.live += 1;
        self.requeue(k1, k2, vertex);
    }

    /// Gives the queued `vertex` the key `[k1; k2]`.
    #[inline]
    pub fn update(&mut self, k1: u64, k2: u64, vertex: u32) {
        self.requeue(k1, k2, vertex);
    }

    /// Takes the queued `vertex` out of the queue.
    #[inline]
    pub fn remove(&mut self, vertex: u32) {
        self.tickets[vertex as usize] = 0;
        self.live -= 1;
    }

    /// The least queued entry `(k1, k2, vertex)`, left queued.
    #[inline]
    pub fn top(&mut self) -> Option<(u64, u64, u32)> {
        loop {
            let Some(&e) = self.front.peek() else {
                if self.advance() {
                    continue;
                }
                return None;
            };
            if self.tickets[e.vertex as usize] == e.ticket {
                return Some((e.k1, e.k2, e.vertex));
            }
            self.front.pop();
            self.held -= 1;
        }
    }

    /// Takes out the entry [`KeyedQueue::top`] returned (precondition: nothing changed since).
    #[inline]
    pub fn pop_top(&mut self) {
        if let Some(e) = self.front.pop() {
            self.tickets[e.vertex as usize] = 0;
            self.live -= 1;
            self.held -= 1;
        }
    }

    /// Gives the entry [`KeyedQueue::top`] returned the key `[k1; k2]` (precondition: nothing
    /// changed since): [`KeyedQueue::update`] of its vertex, with the old entry taken out now
    /// rather than skipped later.
    #[inline]
    pub fn rekey_top(&mut self, k1: u64, k2: u64) {
        if let Some(e) = self.front.pop() {
            self.held -= 1;
            self.requeue(k1, k2, e.vertex);
        }
    }

    /// Pushes a new entry for `vertex` with a fresh ticket; an older one becomes stale.
    #[inline]
    fn requeue(&mut self, k1: u64, k2: u64, vertex: u32) {
        if self.next_ticket == u32::MAX || self.held >= 2 * self.live + SLACK {
            self.compact();
        }
        let ticket = self.next_ticket;
        self.next_ticket += 1;
        self.tickets[vertex as usize] = ticket;
        self.held += 1;
        self.insert(Entry {
            k1,
            k2,
            vertex,
            ticket,
        });
    }

    /// Files `e` by its bucket: the heap, the ring or `far`.
    #[inline]
    fn insert(&mut self, e: Entry) {
        let b = e.bucket();
        if b <= self.current {
            self.front.push(e);
        } else if b - self.current < RING as u64 {
            let slot = b as usize % RING;
            self.ring[slot].push(e);
            self.occupied[slot / 64] |= 1 << (slot % 64);
        } else {
            self.far.push(e);
            self.far_min = self.far_min.min(b);
        }
    }

    /// Moves `current` to the next bucket holding entries and heaps them (the heap is
    /// empty); false when the queue holds nothing.
    fn advance(&mut self) -> bool {
        let next = self.next_occupied();
        if self.far_min != u64::MAX && next.is_none_or(|b| self.far_min <= b) {
            // `far`'s least bucket comes first: it becomes current, and `far` is filed
            // again against the new window (the ring's buckets all lie above it).
            self.current = self.far_min;
            self.far_min = u64::MAX;
            // In place: the entries now inside the window move to the front or the ring,
            // the stale ones are dropped, the rest stay (no allocation).
            let mut far = std::mem::take(&mut self.far);
            far.retain(|&e| {
                if self.tickets[e.vertex as usize] != e.ticket {
                    self.held -= 1;
                    return false;
                }
                let b = e.bucket();
                if b - self.current < RING as u64 {
                    self.insert(e);
                    return false;
                }
                self.far_min = self.far_min.min(b);
                true
            });
            self.far = far;
            return true;
        }
        let Some(b) = next else {
            return false;
        };
        self.current = b;
        let slot = b as usize % RING;
        self.occupied[slot / 64] &= !(1 << (slot % 64));
        // The front is empty here: the bucket becomes its sorted run.
        debug_assert!(self.front.is_empty());
        let bucket = &mut self.ring[slot];
        let before = bucket.len();
        let tickets = &self.tickets;
        let run = &mut self.front.run;
        run.extend(
            bucket
                .drain(..)
                .filter(|e| tickets[e.vertex as usize] == e.ticket),
        );
        self.held -= before - run.len();
        // Descending: the least last.
        run.sort_unstable_by(|a, b| order(b, a));
        true
    }

    /// The least occupied ring bucket above `current`, if any.
    fn next_occupied(&self) -> Option<u64> {
        let start = (self.current as usize + 1) % RING;
        let words = RING / 64;
        let (w0, bit0) = (start / 64, start % 64);
        // The first word from bit0 on, then the others in ring order, then the first
        // word's bits below bit0 (the ring's last positions).
        for k in 0..=words {
            let w = (w0 + k) % words;
            let mut word = self.occupied[w];
            if k == 0 {
                word &= !0u64 << bit0;
            } else if k == words {
                word &= !(!0u64 << bit0);
            }
            if word != 0 {
                let slot = w * 64 + word.trailing_zeros() as usize;
                let distance = (slot + RING - start) % RING;
                return Some(self.current + 1 + distance as u64);
            }
        }
        None
    }

    /// Drops every stale entry and renumbers the tickets of the live ones from 1, in place.
    fn compact(&mut self) {
        let tickets = &mut self.tickets;
        let mut next = 1u32;
        // Keeps `e` when it is live, with the next ticket (the order among live entries,
        // at most one per vertex, does not depend on tickets).
        let mut renumber = |e: &mut Entry| {
            let ticket = &mut tickets[e.vertex as usize];
            if *ticket != e.ticket {
                return false;
            }
            *ticket = next;
            e.ticket = next;
            next += 1;
            true
        };
        self.front.run.retain_mut(&mut renumber);
        self.front.heap.items.retain_mut(&mut renumber);
        self.front.heap.heapify();
        for (b, bucket) in self.ring.iter_mut().enumerate() {
            if self.occupied[b / 64] >> (b % 64) & 1 == 1 {
                bucket.retain_mut(&mut renumber);
                if bucket.is_empty() {
                    self.occupied[b / 64] &= !(1 << (b % 64));
                }
            }
        }
        self.far.retain_mut(&mut renumber);
        self.far_min = self.far.iter().map(Entry::bucket).min().unwrap_or(u64::MAX);
        self.next_ticket = next;
        self.held = (next - 1) as usize;
    }

    /// Sets the next ticket (tests of the renumbering).
    #[cfg(test)]
    fn set_next_ticket(&mut self, ticket: u32) {
        if ticket > self.next_ticket {
            self.next_ticket = ticket;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::collections::BTreeMap;

    /// Random pushes, key changes (of any vertex and of the top, as the engine's
    /// re-keying), removals and pops against a `BTreeMap` of the queued keys, with keys
    /// drawn near the current least (same bucket, next buckets), far above it (beyond the
    /// ring) and below it: the top is always the least `(k1, k2, v)`, so equal `[k1; k2]`
    /// come out by index.
    fn check(seed: u64, n: usize, steps: usize, first_ticket: u32) {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut queue = KeyedQueue::default();
        queue.reset(n);
        queue.set_next_ticket(first_ticket);
        let mut model: BTreeMap<u32, (u64, u64)> = BTreeMap::new();
        let width = 1u64 << BUCKET_SHIFT;
        let mut base = 10 * width;
        let mut peak = 0;
        for _ in 0..steps {
            let v = rng.gen_range(0..n as u32);
            let k1 = match rng.gen_range(0..6) {
                0 => base + rng.gen_range(0..4),
                1 => base + rng.gen_range(0..4 * width),
                2 => base + rng.gen_range(0..2 * RING as u64 * width),
                3 => base.saturating_sub(rng.gen_range(0..8 * width)),
                _ => base + rng.gen_range(0..64 * width),
            };
            let k2 = rng.gen_range(0..3u64);
            match rng.gen_range(0..6) {
                0 if queue.contains(v) => {
                    queue.remove(v);
                    model.remove(&v);
                }
                1 | 2 => {
                    let top = queue.top();
                    let least = model.iter().map(|(&u, &(a, b))| (a, b, u)).min();
                    assert_eq!(top, least);
                    if let Some((k1, _, u)) = top {
                        queue.pop_top();
                        model.remove(&u);
                        base = k1;
                    }
                }
                3 => {
                    if let Some((_, _, u)) = queue.top() {
                        let k1 = k1.max(base);
                        queue.rekey_top(k1, k2);
                        model.insert(u, (k1, k2));
                    }
                }
                _ if queue.contains(v) => {
                    queue.update(k1, k2, v);
                    model.insert(v, (k1, k2));
                }
                _ => {
                    queue.push(k1, k2, v);
                    model.insert(v, (k1, k2));
                }
            }
            assert_eq!(queue.live, model.len());
            for u in 0..n as u32 {
                assert_eq!(queue.contains(u), model.contains_key(&u));
            }
            // Stale entries stay within twice the queued ones (plus the slack) as long as
            // nothing was removed since the last push; removals only shrink `live`.
            peak = peak.max(queue.live);
            assert!(queue.held <= 2 * peak + SLACK + 1);
        }
        // Drain: everything comes out in order.
        let mut out = Vec::new();
        while let Some(e) = queue.top() {
            queue.pop_top();
            out.push(e);
        }
        let expected: Vec<_> = model.iter().map(|(&u, &(a, b))| (a, b, u)).collect();
        let mut sorted = expected.clone();
        sorted.sort_unstable();
        assert_eq!(out, sorted);
        queue.reset(n);
        assert!(queue.top().is_none());
        assert!((0..n as u32).all(|u| !queue.contains(u)));
    }

    #[test]
    fn matches_a_sorted_map() {
        check(7, 64, 20_000, 1);
        check(8, 3000, 30_000, 1);
    }

    #[test]
    fn tickets_renumber_before_they_wrap() {
        check(9, 64, 5_000, u32::MAX - 2_000);
    }
}
