//! A counting global allocator: current and peak heap bytes per thread.
//!
//! Each run of a sweep stays on one rayon thread, so the thread's peak between
//! [`start`] and [`peak_since_start`] is the run's peak heap use: the Rust counterpart of
//! seed 003's "peak memory" (Python's tracemalloc). Frees of memory allocated on another
//! thread are counted on the freeing thread, so a run's figure can be slightly low when it
//! frees what another thread allocated; the runner builds everything a run uses on the
//! run's own thread.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The allocator. A binary installs it (`#[global_allocator] static A: Counting = Counting;`)
/// and passes [`Meter`] to the runner; the library itself installs none.
pub struct Counting;

thread_local! {
    static CURRENT: Cell<isize> = const { Cell::new(0) };
    static PEAK: Cell<isize> = const { Cell::new(0) };
}

fn record(delta: isize) {
    // `try_with` fails only while the thread is being torn down; nothing to count then.
    let _ = CURRENT.try_with(|current| {
        let now = current.get() + delta;
        current.set(now);
        let _ = PEAK.try_with(|peak| {
            if now > peak.get() {
                peak.set(now);
            }
        });
    });
}

// SAFETY: every call is forwarded unchanged to the system allocator; the bookkeeping
// touches only const-initialised thread-locals and never allocates.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc(layout) };
        if !ptr.is_null() {
            record(layout.size() as isize);
        }
        ptr
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        record(-(layout.size() as isize));
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let ptr = unsafe { System.alloc_zeroed(layout) };
        if !ptr.is_null() {
            record(layout.size() as isize);
        }
        ptr
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let new = unsafe { System.realloc(ptr, layout, new_size) };
        if !new.is_null() {
            record(new_size as isize - layout.size() as isize);
        }
        new
    }
}

/// Starts a measurement on this thread: the peak is reset to the current use.
pub fn start() -> isize {
    let current = CURRENT.with(Cell::get);
    PEAK.with(|peak| peak.set(current));
    current
}

/// Peak bytes allocated on this thread above `baseline` (from [`start`]) since then.
pub fn peak_since_start(baseline: isize) -> u64 {
    (PEAK.with(Cell::get) - baseline).max(0) as u64
}

/// The counting allocator as planner-runner's peak-heap hook.
pub struct Meter;

impl crate::run::HeapMeter for Meter {
    fn current(&self) -> i64 {
        CURRENT.with(Cell::get) as i64
    }

    fn start(&self) -> i64 {
        start() as i64
    }

    fn peak_since(&self, baseline: i64) -> u64 {
        peak_since_start(baseline as isize)
    }
}
