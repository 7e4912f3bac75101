//! OPEN lists. Every one pops entries in exactly the order of the full key
//! `(f, tie, push sequence)` of a tie rule ([`FIFO`], [`LIFO`], [`LOW_G`], [`HIGH_G`]),
//! with lazy deletion: a node improved while in OPEN gets a second entry and the older one
//! is skipped by the search when it comes out (the node is then CLOSED), or dropped unseen
//! when its bucket comes up after its node was expanded.
//!
//! Two implementations, chosen per search by what the costs allow:
//! - [`BucketOpen`], for any `f`: a ring of narrow `f` buckets in front of the least
//!   bucket, which is sorted when it comes up (a pop is then a vector pop), with a binary
//!   heap and a short sorted front for the entries pushed into it since. `f` and `g` are
//!   [`Cost`]s, so keys are their integer units.
//! - [`IntOpen`], when `f` is an integer that never decreases along an edge and grows by at
//!   most 2 (unit moves, an integer consistent heuristic, weight 0 or 1): one slot per `f`
//!   value in a ring of four, each a FIFO queue, a stack, runs of equal `g` (high g first)
//!   or a heap of `g` and sequence (low g first). All but the last are O(1) amortized.
//!
//! Why these and not one heap: on the Moving AI benchmark a plain lazy binary heap spent
//! three quarters of A*'s time in pop (an indexed 4-ary heap was no better). Most entries
//! go to a later bucket or slot as a cheap append; A*'s usual next node, a child with the
//! popped node's `f` and more `g`, is caught by the front (or lands on top of its slot's
//! runs); and an improved node's older entry, which lies in a later bucket than its newer
//! one, is dropped before it costs a heap operation.

use planner_api::Cost;

// The tie rules among entries of equal `f`, as const-generic parameters. Each rule ends
// with the push sequence, so no two entries tie.
/// Tie rule: the entry pushed first comes out first.
pub const FIFO: u8 = 0;
/// Tie rule: the entry pushed last comes out first.
pub const LIFO: u8 = 1;
/// Tie rule: lower `g` first, then first pushed.
pub const LOW_G: u8 = 2;
/// Tie rule: higher `g` first, then first pushed.
pub const HIGH_G: u8 = 3;

/// An OPEN list.
pub trait Open {
    /// Empties the list, keeping its memory.
    fn clear(&mut self);
    /// Inserts `node` with evaluation `f` and cost so far `g`. Preconditions for
    /// [`IntOpen`]: both are whole numbers, `g` below 2^32, and `f` at least the last
    /// popped entry's `f` and at most 3 above it.
    fn push(&mut self, node: u32, f: Cost, g: Cost);
    /// Removes and returns the entry with the least key, stale ones included, except that
    /// entries whose node `is_closed` says is CLOSED may be dropped unseen (the search
    /// would skip them). Precondition: a node once CLOSED stays CLOSED until `clear`.
    fn pop(&mut self, is_closed: impl Fn(u32) -> bool) -> Option<u32>;
}

/// A heap entry: `f`'s units, the tie value, and the push sequence (high half) with the node
/// (low half), compared in that order as one 192-bit number. The node never decides, as
/// sequences are distinct.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Entry {
    f: u64,
    tie: u64,
    seq_node: u64,
}

impl Entry {
    /// The entry of the `n_pushed`-th push under tie rule `TIE`. Precondition:
    /// `n_pushed < 2^32` (see [`BucketOpen::renumber`]).
    #[inline(always)]
    fn new<const TIE: u8>(node: u32, f: Cost, g: Cost, n_pushed: u64) -> Entry {
        let g = g.units();
        let (tie, seq) = match TIE {
            FIFO => (0, n_pushed),
            LIFO => (0, u64::from(u32::MAX) - n_pushed),
            LOW_G => (g, n_pushed),
            _ => (!g, n_pushed),
        };
        Entry {
            f: f.units(),
            tie,
            seq_node: seq << 32 | u64::from(node),
        }
    }

    /// The node.
    #[inline(always)]
    fn node(&self) -> u32 {
        self.seq_node as u32
    }

    /// Whether `self` comes before `other`: the borrow out of the 192-bit subtraction
    /// `self - other`, without a branch.
    #[inline(always)]
    fn precedes(&self, other: &Entry) -> bool {
        let (_, borrow) = self.seq_node.overflowing_sub(other.seq_node);
        let (tie, b1) = self.tie.overflowing_sub(other.tie);
        let (_, b2) = tie.overflowing_sub(u64::from(borrow));
        let (f, b3) = self.f.overflowing_sub(other.f);
        let (_, b4) = f.overflowing_sub(u64::from(b1 | b2));
        b3 | b4
    }
}

/// OPEN as a ring of buckets of width `2^-shift` in `f`, ahead of a heap (a sorted
/// run, a binary heap and a short front) that holds the current (least) bucket: pushes
/// into later buckets are appends, and the heap stays small.
///
/// Invariant: the heap holds every entry whose bucket `floor(f * 2^shift)` is at most `cur`,
/// the ring every entry whose bucket lies in `(cur, cur + ring.len())`, at the slot
/// `bucket % ring.len()`, and `overflow` (a heap) every entry above. The heap's least entry
/// is then the least of all, whatever the heuristic: with an inconsistent one, an entry may
/// land below `cur` and simply joins the heap.
///
/// Precondition: [`BucketOpen::configure`] before the first push.
#[derive(Debug, Clone, Default)]
pub struct BucketOpen<const TIE: u8> {
    /// A bucket is `f`'s units shifted right by this much.
    shift: u32,
    cur: u64,
    heap: MinHeap,
    ring: Vec<Vec<Entry>>,
    in_ring: usize,
    /// Whether the heap's run is the current bucket's ring slot's vector, lent when the
    /// bucket came up ([`BucketOpen::enter_bucket`]) and given back, empty, when the
    /// bucket is left, so that every slot keeps its own capacity.
    lent: bool,
    overflow: MinHeap,
    n_pushed: u64,
    /// Sequences are 32 bits: at this many pushes the entries are renumbered.
    seq_limit: u64,
}

impl<const TIE: u8> BucketOpen<TIE> {
    /// Sets the bucket width for moves costing at most `max_cost` and the weight `weight`:
    /// with a consistent heuristic, the `f` values in OPEN span at most
    /// `(1 + weight) * max_cost`, which the ring then covers.
    pub fn configure(&mut self, max_cost: Cost, weight: f64) {
        self.configure_scaled(max_cost, weight, 1);
    }

    /// [`BucketOpen::configure`] with buckets `scale` times wider (rounded up to a power
    /// of two), for costs `scale` times larger than move lengths: a weighted grid's, whose
    /// move costs are lengths times weights up to `scale`. The buckets per unit of `f`
    /// then match the unweighted search's per unit of length, so the ring is not walked
    /// through empty buckets. The order popped is the same for any width.
    pub fn configure_scaled(&mut self, max_cost: Cost, weight: f64, scale: u64) {
        let widen = scale.max(1).next_power_of_two().trailing_zeros().min(24);
        self.configure_units(max_cost.to_f64(), weight, Cost::FRACTION_BITS, widen);
    }

    /// [`BucketOpen::configure`] for keys that are not [`Cost`]s: `f` and `g` passed as
    /// `Cost::from_units` of numbers with `fraction_bits` fractional bits (`f` rounded to
    /// `2^-fraction_bits`, as Theta\*'s OPEN keys), moves costing at most `max_cost`
    /// (lengths), and `g` any `u64` whose order is the tie rule's. Precondition:
    /// `4 <= fraction_bits <= 32`.
    pub fn configure_fraction(&mut self, max_cost: f64, weight: f64, fraction_bits: u32) {
        self.configure_units(max_cost, weight, fraction_bits, 0);
    }

    /// Buckets `16 / 2^widen` per unit of `f` (which has `fraction_bits` fractional bits),
    /// enough ring slots to cover `(1 + weight) * max_cost`.
    fn configure_units(&mut self, max_cost: f64, weight: f64, fraction_bits: u32, widen: u32) {
        const BUCKETS_PER_UNIT: f64 = 16.0;
        debug_assert!((4..=Cost::FRACTION_BITS).contains(&fraction_bits));
        let per_unit = BUCKETS_PER_UNIT / f64::from(1u32 << widen);
        let span = (1.0 + weight) * max_cost * per_unit;
        let slots = if span.is_finite() && span < 4096.0 {
            (span as usize + 2).next_power_of_two()
        } else {
            4096
        };
        self.shift = fraction_bits - BUCKETS_PER_UNIT.log2() as u32 + widen;
        self.seq_limit = 1 << 32;
        self.ring.resize_with(slots, Vec::new);
        self.clear();
    }

    /// Places `entry` by its bucket.
    #[inline(always)]
    fn place(&mut self, entry: Entry) {
        let bucket = self.bucket(entry.f);
        let slots = self.ring.len() as u64;
        if bucket <= self.cur {
            Self::push_parts(&mut self.heap, entry.f, entry.tie, entry.seq_node);
        } else if bucket - self.cur < slots {
            self.ring[(bucket & (slots - 1)) as usize].push(entry);
            self.in_ring += 1;
        } else {
            Self::push_parts(&mut self.overflow, entry.f, entry.tie, entry.seq_node);
        }
    }

    /// `heap.push` of the entry with these fields. The fields are passed as scalars (in
    /// registers) so that the caller need not build the entry in memory: a 24-byte entry
    /// stored on the stack field by field and then copied into a ring slot with wider
    /// loads stalled store-to-load forwarding (the profile's hottest instruction).
    #[inline(never)]
    fn push_parts(heap: &mut MinHeap, f: u64, tie: u64, seq_node: u64) {
        heap.push(Entry { f, tie, seq_node });
    }

    /// Gives the entries in OPEN the sequences `0..n` (FIFO and the g rules) or the top
    /// `n` values (LIFO) in their current order, so that 32-bit sequences never wrap.
    /// Precondition: fewer than 2^32 entries.
    #[cold]
    fn renumber(&mut self) {
        let mut entries = Vec::new();
        self.heap.drain_into(&mut entries);
        self.overflow.drain_into(&mut entries);
        for slot in &mut self.ring {
            entries.append(slot);
        }
        self.in_ring = 0;
        entries.sort_unstable_by_key(|e| (e.f, e.tie, e.seq_node));
        let n = entries.len() as u64;
        let first = if TIE == LIFO {
            u64::from(u32::MAX) + 1 - n
        } else {
            0
        };
        for (rank, entry) in (first..).zip(entries) {
            self.place(Entry {
                seq_node: rank << 32 | u64::from(entry.node()),
                ..entry
            });
        }
        self.n_pushed = n;
    }

    #[inline(always)]
    fn bucket(&self, f_units: u64) -> u64 {
        f_units >> self.shift
    }

    /// Gives the current bucket's slot its vector back from the run, if lent. The slot is
    /// empty while its bucket is the current one (its entries go to the heap, and bucket
    /// `cur + ring.len()` to the overflow), and the run once the bucket is done.
    #[inline]
    fn give_back(&mut self) {
        if self.lent {
            let slot = (self.cur & (self.ring.len() as u64 - 1)) as usize;
            debug_assert!(self.ring[slot].is_empty());
            std::mem::swap(&mut self.heap.run, &mut self.ring[slot]);
            self.lent = false;
        }
    }

    /// Moves the entries of bucket `cur`'s slot into the heap, and from `overflow` the
    /// entries now inside the ring's window. Entries of CLOSED nodes are dropped here: an
    /// improved node's older entry usually lies in a later bucket than its newer one, so
    /// by the time it would enter the heap its node has been expanded.
    fn enter_bucket(&mut self, is_closed: impl Fn(u32) -> bool) {
        let slots = self.ring.len() as u64;
        let mask = slots - 1;
        while let Some(&entry) = self.overflow.peek() {
            let bucket = self.bucket(entry.f);
            if bucket > self.cur && bucket - self.cur >= slots {
                break;
            }
            self.overflow.pop();
            if bucket <= self.cur {
                self.heap.items.push(entry);
            } else {
                self.ring[(bucket & mask) as usize].push(entry);
                self.in_ring += 1;
            }
        }
        let slot = &mut self.ring[(self.cur & mask) as usize];
        if !slot.is_empty() {
            self.in_ring -= slot.len();
            // The heap is empty here (its pop found nothing), run included: the slot's
            // vector is lent to the run, filtered in place (no copy of the entries), and
            // the slot holds the run's empty one until `give_back`.
            debug_assert!(self.heap.run.is_empty() && !self.lent);
            std::mem::swap(&mut self.heap.run, slot);
            self.lent = true;
            // Without a branch per entry: a quarter (weighted) to two thirds (8-connected
            // Moving AI bench lines) of them are dropped, unpredictably.
            let run = &mut self.heap.run;
            let mut kept = 0;
            for i in 0..run.len() {
                let entry = run[i];
                run[kept] = entry;
                kept += usize::from(!is_closed(entry.node()));
            }
            run.truncate(kept);
        }
        self.heap.sort_into_run();
    }
}

impl<const TIE: u8> Open for BucketOpen<TIE> {
    fn clear(&mut self) {
        self.heap.clear();
        self.overflow.clear();
        if self.in_ring > 0 {
            for slot in &mut self.ring {
                slot.clear();
            }
        }
        self.in_ring = 0;
        // After the slots are emptied: a search stopped early leaves its entries there, and
        // `configure` resizes the ring before it clears, so the current bucket's slot
        // need not be empty before.
        self.give_back();
        self.cur = 0;
        self.n_pushed = 0;
    }

    #[inline]
    fn push(&mut self, node: u32, f: Cost, g: Cost) {
        if self.n_pushed == self.seq_limit {
            self.renumber();
        }
        let entry = Entry::new::<TIE>(node, f, g, self.n_pushed);
        self.n_pushed += 1;
        self.place(entry);
    }

    #[inline]
    fn pop(&mut self, is_closed: impl Fn(u32) -> bool) -> Option<u32> {
        loop {
            if let Some(entry) = self.heap.pop() {
                return Some(entry.node());
            }
            self.give_back();
            if self.in_ring > 0 {
                self.cur += 1;
            } else {
                let &least = self.overflow.peek()?;
                self.cur = self.bucket(least.f);
            }
            self.enter_bucket(&is_closed);
        }
    }
}

/// OPEN for integral `f` in a window of four values (see the module docs).
///
/// Invariant: every entry's `f` lies in `cur..cur + 4` and sits in slot `f % 4`; a slot
/// holds one `f` value, so its order is the tie rule's alone.
#[derive(Debug, Clone, Default)]
pub struct IntOpen<const TIE: u8> {
    /// Scratch space for [`Slot::sort_in_pending`].
    scratch: Scratch,
    cur: u64,
    /// Whether a push since `clear` has set `cur` (the first one, the start, does).
    started: bool,
    len: usize,
    slots: [Slot; 4],
}

/// Scratch space for [`Slot::sort_in_pending`]: entries as `(g, node)`, and counts.
#[derive(Debug, Clone, Default)]
struct Scratch {
    entries: Vec<(u32, u32)>,
    counts: Vec<usize>,
}

/// The entries of one `f` value.
///
/// - FIFO and LIFO: `queue[head..]` in push order.
/// - High g first: `levels`, runs of equal `g` in increasing `g` over `queue`, each
///   popped from its front; the top run ends at the end of `queue`. A push with the top's
///   `g` or above extends `queue`: in the current slot that is every push, as a child
///   of the popped node (the highest `g`) has one more. Other pushes wait in `pending`
///   (in push order, so newer than everything in `levels`) until the next pop sorts them in.
/// - Low g first: a min-heap of `g << 32 | seq`, where `seq` counts this slot's pushes.
#[derive(Debug, Clone, Default)]
struct Slot {
    queue: Vec<u32>,
    head: usize,
    levels: Vec<Level>,
    pending: Vec<(u32, u32)>,
    heap: std::collections::BinaryHeap<std::cmp::Reverse<(u64, u32)>>,
    n_pushed: u32,
}

/// A run of entries with one `g` in [`Slot::queue`]: `start..` up to the next run's start,
/// the entries before `head` already popped.
#[derive(Debug, Clone, Copy)]
struct Level {
    g: u32,
    start: usize,
    head: usize,
}

impl Slot {
    fn clear(&mut self) {
        self.queue.clear();
        self.head = 0;
        self.levels.clear();
        self.pending.clear();
        self.heap.clear();
        self.n_pushed = 0;
    }

    /// High g first: a push of `node` with cost `g`.
    #[inline(always)]
    fn push_high_g(&mut self, g: u32, node: u32) {
        if self.pending.is_empty() {
            match self.levels.last() {
                Some(top) if top.g == g => {
                    self.queue.push(node);
                    return;
                }
                Some(top) if top.g > g => {}
                _ => {
                    let start = self.queue.len();
                    self.levels.push(Level {
                        g,
                        start,
                        head: start,
                    });
                    self.queue.push(node);
                    return;
                }
            }
        }
        self.pending.push((g, node));
    }

    /// High g first: the entry with the highest `g`, the first pushed among equals.
    /// Entries of CLOSED nodes dropped on the way are subtracted from `len`.
    #[inline]
    fn pop_high_g(
        &mut self,
        scratch: &mut Scratch,
        is_closed: impl Fn(u32) -> bool,
        len: &mut usize,
    ) -> Option<u32> {
        if !self.pending.is_empty() {
            *len -= self.sort_in_pending(scratch, is_closed);
        }
        let top = self.levels.last_mut()?;
        let node = self.queue[top.head];
        top.head += 1;
        if top.head == self.queue.len() {
            self.queue.truncate(top.start);
            self.levels.pop();
        }
        Some(node)
    }

    /// Rebuilds `levels` from their entries and `pending`'s, dropping entries of CLOSED
    /// nodes. Sorting is by `g` alone and stable, which keeps push order among equal `g`
    /// as `pending` is newer than `levels`: a counting sort when the `g` values are dense
    /// (the usual case: a slot's `g` values span about its size), else a merge sort.
    #[cold]
    /// Returns the number of entries dropped.
    fn sort_in_pending(&mut self, scratch: &mut Scratch, is_closed: impl Fn(u32) -> bool) -> usize {
        let entries = &mut scratch.entries;
        entries.clear();
        let (mut low, mut high) = (u32::MAX, 0);
        let mut n_dropped = 0;
        let mut keep = |g: u32, node: u32| {
            if is_closed(node) {
                n_dropped += 1;
            } else {
                low = low.min(g);
                high = high.max(g);
                entries.push((g, node));
            }
        };
        for (i, level) in self.levels.iter().enumerate() {
            let end = self
                .levels
                .get(i + 1)
                .map_or(self.queue.len(), |next| next.start);
            for &node in &self.queue[level.head..end] {
                keep(level.g, node);
            }
        }
        for &(g, node) in &self.pending {
            keep(g, node);
        }
        self.pending.clear();
        self.queue.clear();
        self.levels.clear();
        if entries.is_empty() {
            return n_dropped;
        }
        let span = (high - low) as usize + 1;
        if span <= 4 * entries.len() + 64 {
            // Counting sort: `next[g - low]` becomes the next free position of `g`'s run.
            let next = &mut scratch.counts;
            next.clear();
            next.resize(span, 0);
            for &(g, _) in entries.iter() {
                next[(g - low) as usize] += 1;
            }
            let mut start = 0;
            for (g, slot) in (low..).zip(next.iter_mut()) {
                if *slot > 0 {
                    self.levels.push(Level {
                        g,
                        start,
                        head: start,
                    });
                    let count = *slot;
                    *slot = start;
                    start += count;
                }
            }
            self.queue.resize(entries.len(), 0);
            for &(g, node) in entries.iter() {
                let at = &mut next[(g - low) as usize];
                self.queue[*at] = node;
                *at += 1;
            }
        } else {
            entries.sort_by_key(|&(g, _)| g);
            for &(g, node) in entries.iter() {
                if self.levels.last().is_none_or(|top| top.g != g) {
                    let start = self.queue.len();
                    self.levels.push(Level {
                        g,
                        start,
                        head: start,
                    });
                }
                self.queue.push(node);
            }
        }
        n_dropped
    }

    /// Gives the heap's entries the sequences `0..n` in their current order, so that
    /// 32-bit sequences never wrap. Precondition: fewer than 2^32 entries.
    #[cold]
    fn renumber(&mut self) {
        let entries = std::mem::take(&mut self.heap).into_sorted_vec();
        // Sorted by `Reverse`: the least key is last.
        for (seq, std::cmp::Reverse((key, node))) in (0u32..).zip(entries.into_iter().rev()) {
            let key = key & !u64::from(u32::MAX) | u64::from(seq);
            self.heap.push(std::cmp::Reverse((key, node)));
        }
        self.n_pushed = self.heap.len() as u32;
    }
}

impl<const TIE: u8> IntOpen<TIE> {
    /// Whether this OPEN can hold `f = g + weight * h` for unit moves (costs `move_costs`),
    /// the heuristic values being integers that change by at most 1 along a move
    /// (`consistent_integer_h`).
    pub fn fits(
        move_costs: impl IntoIterator<Item = Cost>,
        weight: f64,
        consistent_integer_h: bool,
    ) -> bool {
        consistent_integer_h
            && (weight == 0.0 || weight == 1.0)
            && move_costs.into_iter().all(|cost| cost == Cost::ONE)
    }
}

impl<const TIE: u8> Open for IntOpen<TIE> {
    fn clear(&mut self) {
        for slot in &mut self.slots {
            slot.clear();
        }
        self.len = 0;
        self.started = false;
    }

    // Always inlined (with `Slot::push_high_g`): with `#[inline]` the compiler kept it a
    // call from A*'s loop, which took 23 % of the 4-connected bench's samples; inlined, the
    // bench's 4-connected lines took 12 % (den520d) and 10 % (random512-10-0) less time.
    #[inline(always)]
    fn push(&mut self, node: u32, f: Cost, g: Cost) {
        // Both are whole numbers by the precondition.
        let (f, g) = (f.whole(), g.whole());
        if !self.started {
            // The first push after `clear` (the start) opens the window.
            self.cur = f;
            self.started = true;
        }
        debug_assert!(
            f >= self.cur && f - self.cur < 4,
            "f {f} outside the window at {}",
            self.cur
        );
        self.len += 1;
        let slot = &mut self.slots[(f & 3) as usize];
        match TIE {
            FIFO | LIFO => slot.queue.push(node),
            HIGH_G => slot.push_high_g(g as u32, node),
            _ => {
                if slot.n_pushed == u32::MAX {
                    slot.renumber();
                }
                let key = u64::from(g as u32) << 32 | u64::from(slot.n_pushed);
                slot.n_pushed += 1;
                slot.heap.push(std::cmp::Reverse((key, node)));
            }
        }
    }

    #[inline]
    fn pop(&mut self, is_closed: impl Fn(u32) -> bool) -> Option<u32> {
        if self.len == 0 {
            return None;
        }
        // The invariant puts an entry within four slots of `cur`.
        for _ in 0..4 {
            let slot = &mut self.slots[(self.cur & 3) as usize];
            let node = match TIE {
                FIFO if slot.head < slot.queue.len() => {
                    let node = slot.queue[slot.head];
                    slot.head += 1;
                    if slot.head == slot.queue.len() {
                        slot.queue.clear();
                        slot.head = 0;
                    }
                    Some(node)
                }
                LIFO => slot.queue.pop(),
                HIGH_G => slot.pop_high_g(&mut self.scratch, &is_closed, &mut self.len),
                LOW_G => {
                    let entry = slot.heap.pop().map(|std::cmp::Reverse((_, node))| node);
                    if slot.heap.is_empty() {
                        slot.n_pushed = 0;
                    }
                    entry
                }
                _ => None,
            };
            if node.is_some() {
                self.len -= 1;
                return node;
            }
            self.cur += 1;
        }
        None
    }
}

/// A binary min-heap of entries behind a short sorted `front`, beside a sorted `run`.
///
/// The `run` is a bucket's entries sorted when the bucket came up (least last). Sorting
/// them at once and popping the run's end took 9 % less time than making them a heap and
/// popping that, in A*'s 8-connected Moving AI bench lines (PERFORMANCE.md's A* section);
/// an earlier callgrind count of a similar variant (buckets of at most 32 entries sorted)
/// found about as many instructions either way, so the time is likely the heap pops'
/// unpredictable branches and scattered loads. Entries pushed since go to the heap, or to
/// `front` when they precede the heap's top (sorted, least last), and `pop` takes the
/// least of the three minima. That is A*'s common pattern: a child
/// that is the new minimum (equal `f`, one more `g`) and is popped next costs a short
/// insertion instead of a sift to the root and back. When `front` is full its greatest
/// entry moves to the heap.
///
/// The heap's `pop` is Floyd's: the hole left at the root goes down to a leaf along the
/// lesser children (one comparison per level), and the last entry rises from there; it
/// usually belongs near the bottom.
#[derive(Debug, Clone, Default)]
struct MinHeap {
    items: Vec<Entry>,
    front: Vec<Entry>,
    /// Entries sorted with the least last (a bucket sorted when it came up).
    run: Vec<Entry>,
}

/// The most entries [`MinHeap::front`] holds.
const FRONT: usize = 8;

impl MinHeap {
    fn clear(&mut self) {
        self.items.clear();
        self.front.clear();
        self.run.clear();
    }

    fn peek(&self) -> Option<&Entry> {
        let least = match (self.front.last(), self.items.first()) {
            (Some(front), Some(top)) if top.precedes(front) => Some(top),
            (Some(front), _) => Some(front),
            (None, top) => top,
        };
        match (self.run.last(), least) {
            (Some(run), Some(other)) if other.precedes(run) => Some(other),
            (Some(run), _) => Some(run),
            (None, other) => other,
        }
    }

    /// Moves every entry into `entries`, in no particular order.
    fn drain_into(&mut self, entries: &mut Vec<Entry>) {
        entries.append(&mut self.items);
        entries.append(&mut self.front);
        entries.append(&mut self.run);
    }

    /// Sorts the heap's entries and the run's into the run. Precondition: the front is
    /// empty, and the run unsorted (a bucket's entries, just moved in).
    fn sort_into_run(&mut self) {
        debug_assert!(self.front.is_empty());
        self.run.append(&mut self.items);
        self.run
            .sort_unstable_by_key(|e| std::cmp::Reverse((e.f, e.tie, e.seq_node)));
    }

    #[inline]
    fn push(&mut self, item: Entry) {
        if self.items.first().is_some_and(|top| !item.precedes(top)) {
            self.push_heap(item);
            return;
        }
        if self.front.len() == FRONT {
            let greatest = self.front.remove(0);
            self.push_heap(greatest);
        }
        let mut at = self.front.len();
        while at > 0 && self.front[at - 1].precedes(&item) {
            at -= 1;
        }
        self.front.insert(at, item);
    }

    // Always inlined: with `#[inline]` it stayed a call that returned the entry through
    // memory, and `perf` put 5.6 % of the weighted bench's den520d samples in it; inlined,
    // one pass of that bench line executes 2.9 % fewer instructions in A* (callgrind).
    #[inline(always)]
    fn pop(&mut self) -> Option<Entry> {
        if let Some(run) = self.run.last() {
            let other_first = match (self.front.last(), self.items.first()) {
                (Some(front), Some(top)) => front.precedes(run) || top.precedes(run),
                (Some(least), None) | (None, Some(least)) => least.precedes(run),
                (None, None) => false,
            };
            if !other_first {
                return self.run.pop();
            }
        }
        match (self.front.last(), self.items.first()) {
            (Some(front), Some(top)) if top.precedes(front) => self.pop_heap(),
            (Some(_), _) => self.front.pop(),
            (None, _) => self.pop_heap(),
        }
    }

    #[inline]
    fn push_heap(&mut self, item: Entry) {
        self.items.push(item);
        let items = &mut self.items[..];
        let mut hole = items.len() - 1;
        while hole > 0 {
            let parent = (hole - 1) / 2;
            if !item.precedes(&items[parent]) {
                break;
            }
            items[hole] = items[parent];
            hole = parent;
        }
        items[hole] = item;
    }

    #[inline]
    fn pop_heap(&mut self) -> Option<Entry> {
        let last = self.items.pop()?;
        let items = &mut self.items[..];
        let Some(&top) = items.first() else {
            return Some(last);
        };
        let len = items.len();
        let mut hole = 0;
        let mut child = 1;
        while child + 1 < len {
            child += usize::from(items[child + 1].precedes(&items[child]));
            items[hole] = items[child];
            hole = child;
            child = 2 * hole + 1;
        }
        if child + 1 == len {
            items[hole] = items[child];
            hole = child;
        }
        while hole > 0 {
            let parent = (hole - 1) / 2;
            if !last.precedes(&items[parent]) {
                break;
            }
            items[hole] = items[parent];
            hole = parent;
        }
        items[hole] = last;
        Some(top)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    /// The reference key of a push: `(f, tie, seq)` with the tie rule's meaning, compared
    /// as numbers (`f` and `g` as the [`Cost`] units pushed).
    fn reference_key<const TIE: u8>(f: Cost, g: Cost, seq: u64) -> (u64, i128, i128) {
        let g = i128::from(g.units());
        let tie = match TIE {
            FIFO | LIFO => 0,
            LOW_G => g,
            _ => -g,
        };
        let seq = if TIE == LIFO {
            -i128::from(seq)
        } else {
            i128::from(seq)
        };
        (f.units(), tie, seq)
    }

    /// The test's floats as `Cost`s, as A* pushes them.
    fn as_costs(f: f64, g: f64) -> (Cost, Cost) {
        (Cost::from_f64(f), Cost::from_f64(g))
    }

    /// Pushes and pops pseudo-random entries, interleaved, and checks every pop against an
    /// ordered set of the reference keys. `f` values come from `fs`, `g` from `gs`, pushed as
    /// `encode` makes them keys.
    fn check<O: Open + Default, const TIE: u8>(
        mut open: O,
        fs: &[f64],
        gs: &[f64],
        push_share: u64,
        encode: impl Fn(f64, f64) -> (Cost, Cost),
    ) {
        let mut reference = BTreeSet::new();
        let mut state = 99u64;
        let mut n_pushed = 0u64;
        for round in 0..20_000u64 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if state % 100 < push_share || reference.is_empty() {
                let f = fs[(state >> 8) as usize % fs.len()];
                let g = gs[(state >> 24) as usize % gs.len()];
                let node = (round % 700) as u32;
                let (f, g) = encode(f, g);
                open.push(node, f, g);
                reference.insert((reference_key::<TIE>(f, g, n_pushed), node));
                n_pushed += 1;
            } else {
                let least = reference.pop_first().map(|(_, node)| node);
                assert_eq!(open.pop(|_| false), least, "rule {TIE} round {round}");
            }
        }
        while let Some((_, node)) = reference.pop_first() {
            assert_eq!(open.pop(|_| false), Some(node));
        }
        assert_eq!(open.pop(|_| false), None);
    }

    /// A bucket OPEN; `seq_limit` lowers the renumbering threshold to test it, `scale`
    /// widens its buckets (weighted grids' [`BucketOpen::configure_scaled`]).
    fn bucket_open<const TIE: u8>(
        max_cost: f64,
        seq_limit: Option<u64>,
        scale: u64,
    ) -> BucketOpen<TIE> {
        let mut open = BucketOpen::default();
        open.configure_scaled(Cost::from_f64(max_cost), 1.0, scale);
        if let Some(limit) = seq_limit {
            open.seq_limit = limit;
        }
        open
    }

    fn check_every_rule(fs: &[f64], gs: &[f64], max_cost: f64, push_share: u64) {
        for (seq_limit, scale) in [(None, 1), (Some(3000), 1), (None, 255), (Some(3000), 4)] {
            check::<_, FIFO>(
                bucket_open::<FIFO>(max_cost, seq_limit, scale),
                fs,
                gs,
                push_share,
                as_costs,
            );
            check::<_, LIFO>(
                bucket_open::<LIFO>(max_cost, seq_limit, scale),
                fs,
                gs,
                push_share,
                as_costs,
            );
            check::<_, LOW_G>(
                bucket_open::<LOW_G>(max_cost, seq_limit, scale),
                fs,
                gs,
                push_share,
                as_costs,
            );
            check::<_, HIGH_G>(
                bucket_open::<HIGH_G>(max_cost, seq_limit, scale),
                fs,
                gs,
                push_share,
                as_costs,
            );
        }
    }

    /// Like [`check`] for [`IntOpen`]: pushes respect its precondition, `f` from the last
    /// popped value to 3 above it (as A* with a consistent heuristic pushes children).
    /// With `closing`, every node popped becomes CLOSED (as A* closes it): the list may then
    /// drop its later entries unseen or return them, and the search skips them, so the
    /// entries of open nodes must still come out in key order, none lost.
    fn check_int<const TIE: u8>(push_share: u64, g_spread: u64, closing: bool) {
        let mut open = IntOpen::<TIE>::default();
        open.clear();
        let mut reference = BTreeSet::new();
        let mut closed = [false; 700];
        // The list's next entry of an open node, skipping those of closed ones as A* does.
        let pop_open = |open: &mut IntOpen<TIE>, closed: &[bool; 700]| {
            let is_closed = |node: u32| closed[node as usize];
            std::iter::from_fn(|| Some(open.pop(is_closed)))
                .find(|got| got.is_none_or(|n| !is_closed(n)))
                .flatten()
        };
        let mut state = 7u64;
        let mut n_pushed = 0u64;
        let (mut floor, mut last_g, mut prev_g) = (10u64, 0u64, 0u64);
        for round in 0..20_000u64 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if state % 100 < push_share || reference.is_empty() {
                let f = floor + if n_pushed == 0 { 0 } else { (state >> 8) % 4 };
                // Half the time a child's g, one above the last popped; a quarter the
                // last push's g or one below (decreasing runs, as a later slot often
                // receives them); else anything.
                let g = match state >> 40 & 3 {
                    0 | 1 => last_g + 1,
                    2 => prev_g.saturating_sub(state >> 42 & 1),
                    _ => (state >> 24) % g_spread,
                };
                prev_g = g;
                let node = (round % 700) as u32;
                open.push(node, Cost::steps(f), Cost::steps(g));
                let key = reference_key::<TIE>(Cost::steps(f), Cost::steps(g), n_pushed);
                reference.insert((key, node, g));
                n_pushed += 1;
            } else {
                let is_closed = |node: u32| closed[node as usize];
                // The least entry of an open node (popping closed ones on the way).
                let least = std::iter::from_fn(|| reference.pop_first())
                    .find(|&(_, node, _)| !is_closed(node));
                let node = least.map(|(_, node, _)| node);
                assert_eq!(
                    pop_open(&mut open, &closed),
                    node,
                    "rule {TIE} round {round}"
                );
                match least {
                    Some(((f_bits, _, _), node, g)) => {
                        floor = Cost::from_units(f_bits).whole();
                        last_g = g;
                        closed[node as usize] = closing;
                    }
                    // Only closed nodes' entries were left and the list ran empty, as a
                    // search's OPEN when it ends: start anew.
                    None => {
                        open.clear();
                        n_pushed = 0;
                    }
                }
            }
        }
        let is_closed = |node: u32| closed[node as usize];
        while let Some((_, node, _)) = reference.pop_first() {
            if !is_closed(node) {
                assert_eq!(pop_open(&mut open, &closed), Some(node));
            }
        }
        assert!(std::iter::from_fn(|| open.pop(is_closed)).all(is_closed));
    }

    #[test]
    fn integer_slots_pop_in_full_key_order() {
        for push_share in [35, 55, 75] {
            // Dense g values take the counting sort, sparse ones (100000) the merge sort.
            for g_spread in [1, 3, 40, 100_000] {
                for closing in [false, true] {
                    check_int::<FIFO>(push_share, g_spread, closing);
                    check_int::<LIFO>(push_share, g_spread, closing);
                    check_int::<LOW_G>(push_share, g_spread, closing);
                    check_int::<HIGH_G>(push_share, g_spread, closing);
                }
            }
        }
    }

    /// Keys that are not `Cost`s ([`BucketOpen::configure_fraction`]), as Theta\* pushes
    /// them: `f` rounded to `2^-24` in those units, `g` as its `f64` bits, larger `g` first.
    #[test]
    fn fraction_keys_pop_in_full_key_order() {
        let fs: Vec<f64> = (0..60).map(|i| f64::from(i) * 0.3f64.sqrt()).collect();
        let gs = [0.0, 0.5, 2f64.sqrt(), 3.0, 10.25];
        let encode = |f: f64, g: f64| {
            let f_units = (f * f64::from(1u32 << 24)).round() as u64;
            (Cost::from_units(f_units), Cost::from_units(g.to_bits()))
        };
        for (max_cost, push_share) in [(2f64.sqrt(), 40), (2f64.sqrt(), 70), (0.01, 55)] {
            let mut open = BucketOpen::<HIGH_G>::default();
            open.configure_fraction(max_cost, 1.0, 24);
            check::<_, HIGH_G>(open, &fs, &gs, push_share, encode);
        }
    }

    /// A search that stops while its bucket's vector is lent to the heap's run, then a
    /// reconfiguration (a ring of another size, as a weighted grid with another largest
    /// weight asks) and a new search: the new search pops its own entries only, in order,
    /// and an emptied list pops nothing. With a ring of 2048 slots (buckets of 1/16 for
    /// costs up to 40) the current bucket 1600 (f = 100) is slot 1600, and f = 128 is
    /// bucket 2048, slot 0; the ring shrunk to 64 slots keeps slot 0, whose index is the
    /// current bucket's there (1600 % 64 = 0).
    #[test]
    fn a_lent_bucket_comes_back_across_clear_and_configure() {
        let (f, g) = (Cost::from_f64, Cost::from_f64);
        for second in [1.0, 40.0, 0.01] {
            let mut open = BucketOpen::<HIGH_G>::default();
            open.configure(f(40.0), 1.0);
            open.push(7, f(100.0), g(0.0));
            for node in 0..50u32 {
                open.push(100 + node, f(128.0), g(f64::from(node)));
            }
            // Bucket 1600 comes up (its vector lent) and the search stops in it.
            assert_eq!(open.pop(|_| false), Some(7));
            open.configure(f(second), 1.0);
            for node in 1000..1100u32 {
                let key = f64::from(1100 - node) * 0.7;
                open.push(node, f(key), g(key));
            }
            let popped: Vec<u32> = std::iter::from_fn(|| open.pop(|_| false)).collect();
            assert_eq!(popped, (1000..1100).rev().collect::<Vec<_>>(), "{second}");
            open.clear();
            assert_eq!(open.pop(|_| false), None);
        }
    }

    #[test]
    fn buckets_pop_in_full_key_order() {
        // Irrational values with exact ties, spread over many buckets and beyond the ring
        // (overflow), pushed in any order (entries below the current bucket).
        let fs: Vec<f64> = (0..40).map(|i| f64::from(i) * 0.5f64.sqrt()).collect();
        let gs = [0.0, 0.25, 1.5, 2.0, 7.0];
        for push_share in [30, 55, 80] {
            check_every_rule(&fs, &gs, 1.0, push_share);
            // A tiny ring: most entries overflow.
            check_every_rule(&fs, &gs, 0.01, push_share);
        }
        // Huge values saturate at the largest cost; zero and negative zero are one value.
        let fs = [0.0, -0.0, 1e300, f64::MAX, 3.0];
        check_every_rule(&fs, &gs, 1.0, 60);
    }
}
