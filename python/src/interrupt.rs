//! Long calls that Ctrl-C interrupts: the work runs on another thread while the calling
//! thread, holding the GIL every 50 ms, asks Python for signals (only the main thread,
//! holding the GIL, can). On a KeyboardInterrupt the caller's `stop` is called (it raises
//! the flags the work watches), the work is waited for, and the exception is raised.
//!
//! The work of a sweep or a batch ([`interruptible`]) gets a thread of its own; a single
//! query's ([`interruptible_query`]) goes to a pool whose threads outlive the call
//! ([`query_pool`]), since a thread of its own added 60-80 us to every `plan` on den520d
//! (`python/bench/plan_calls.py`), and only queries queue there: a long sweep never holds
//! a query up.
//!
//! A value that calls take turns with and may wait long for ([`Exclusive`], a `Planner`'s
//! state) is waited for in steps, so that the wait too can be given up on a signal.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use pyo3::prelude::*;

/// How often the calling thread looks for signals.
const POLL: Duration = Duration::from_millis(50);

/// `work()`'s value, or the KeyboardInterrupt (or other signal handler's exception) that
/// came while it ran, after `stop()` made it end. A panic in `work` is `panicked`. The
/// work runs on a thread of its own.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    stop: impl Fn(),
    panicked: impl FnOnce() -> T,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let (job, finished) = job(work);
    std::thread::scope(|scope| {
        scope.spawn(job);
        // The scope's end joins the thread, which has sent by then.
        watch(py, &stop, panicked, finished)
    })
}

/// [`interruptible`] for one query: the work runs on [`query_pool`].
pub fn interruptible_query<T: Send>(
    py: Python<'_>,
    stop: impl Fn(),
    panicked: impl FnOnce() -> T,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let pool = query_pool().map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("cannot start worker threads: {e}"))
    })?;
    let (job, finished) = job(work);
    // `in_place_scope` runs this body on the calling thread and waits for the work at its
    // end, so the work may borrow.
    pool.in_place_scope(|scope| {
        scope.spawn(|_| job());
        watch(py, &stop, panicked, finished)
    })
}

/// `work` as a job for another thread, which sends its value (`None` if it panicked) to
/// the receiver returned beside it.
fn job<T: Send>(work: impl FnOnce() -> T + Send) -> (impl FnOnce() + Send, Receiver<Option<T>>) {
    let (done, finished) = mpsc::channel::<Option<T>>();
    let job = move || {
        let value = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).ok();
        let _ = done.send(value);
    };
    (job, finished)
}

/// Waits for the work's value on `finished`, asking Python for signals every [`POLL`]; on
/// a signal's exception, calls `stop`, waits for the work to end and returns the exception.
fn watch<T: Send>(
    py: Python<'_>,
    stop: &impl Fn(),
    panicked: impl FnOnce() -> T,
    finished: Receiver<Option<T>>,
) -> PyResult<T> {
    // Locked by this thread only; the mutex makes the receiver shareable with `detach`.
    let finished = Mutex::new(finished);
    let receive = |timeout: Option<Duration>| {
        py.detach(|| {
            let finished = finished.lock().unwrap_or_else(|e| e.into_inner());
            match timeout.map_or_else(
                || finished.recv().map_err(|_| RecvTimeoutError::Disconnected),
                |t| finished.recv_timeout(t),
            ) {
                Ok(value) => Some(value),
                // The sender is gone only once the work has sent (or unwound).
                Err(RecvTimeoutError::Disconnected) => Some(None),
                Err(RecvTimeoutError::Timeout) => None,
            }
        })
    };
    loop {
        if let Some(value) = receive(Some(POLL)) {
            return Ok(value.unwrap_or_else(panicked));
        }
        if let Err(interrupt) = py.check_signals() {
            stop();
            let _ = receive(None);
            return Err(interrupt);
        }
    }
}

/// The pool single queries run on, built by this process. A process forked from one that
/// built it (Python's `multiprocessing` on Linux) inherits the pool's memory but none of
/// its threads, so work sent there would never run: the child builds its own.
pub fn query_pool() -> Result<Arc<rayon::ThreadPool>, rayon::ThreadPoolBuildError> {
    static POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);
    let pid = std::process::id();
    let mut pool = POOL.lock().unwrap_or_else(|e| e.into_inner());
    match &*pool {
        Some((owner, built)) if *owner == pid => Ok(built.clone()),
        _ => {
            // A pool inherited from the parent has no threads to stop: it is left as it is.
            if let Some(inherited) = pool.take() {
                std::mem::forget(inherited);
            }
            let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
            let built = Arc::new(
                rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .thread_name(|i| format!("gridplan-query-{i}"))
                    .build()?,
            );
            *pool = Some((pid, built.clone()));
            Ok(built)
        }
    }
}

/// A value that one thread at a time works with, for calls that may wait long for it:
/// the wait can be given up (on Ctrl-C), and a process forked while a thread of its parent
/// held the value (a thread the child does not have, which will never let go of it) is
/// told so instead of waiting forever.
///
/// The holder's process id is the lock: a thread takes the value by swapping its process's
/// id in for 0, then locks the mutex, which no other thread holds then (it only gives safe
/// access to the value); letting go unlocks the mutex, then stores 0. A process that finds
/// another process's id there was forked while that process held the value.
pub struct Exclusive<T> {
    /// The process id of the thread that holds the value, 0 when none does.
    holder: AtomicU32,
    value: Mutex<T>,
}

/// The value of an [`Exclusive`], held until this is dropped.
pub struct Held<'a, T> {
    /// Dropped first (fields drop in order): the mutex is unlocked before the holder is
    /// cleared, so no other thread ever waits on it.
    value: MutexGuard<'a, T>,
    _release: Release<'a>,
}

/// Clears an [`Exclusive`]'s holder when dropped.
struct Release<'a>(&'a AtomicU32);

impl Drop for Release<'_> {
    fn drop(&mut self) {
        self.0.store(0, Ordering::Release);
    }
}

impl<T> std::ops::Deref for Held<'_, T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.value
    }
}

impl<T> std::ops::DerefMut for Held<'_, T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.value
    }
}

/// Why [`Exclusive::hold`] ended without the value.
pub enum Unheld {
    /// `give_up()` said so while another thread held it.
    GaveUp,
    /// A thread of the process this one was forked from held it at the fork.
    Forked,
}

impl<T> Exclusive<T> {
    /// The longest pause between two tries to take a value another thread holds.
    const RETRY: Duration = Duration::from_millis(1);

    /// `value`, held by no thread.
    pub fn new(value: T) -> Exclusive<T> {
        Exclusive {
            holder: AtomicU32::new(0),
            value: Mutex::new(value),
        }
    }

    /// The value, once no other thread holds it. While another does, `give_up()` is asked
    /// between tries (pauses growing from 10 us to [`Self::RETRY`]) and ends the wait when
    /// it says so.
    pub fn hold(&self, give_up: impl Fn() -> bool) -> Result<Held<'_, T>, Unheld> {
        let pid = std::process::id();
        let mut pause = Duration::from_micros(10);
        loop {
            match self
                .holder
                .compare_exchange(0, pid, Ordering::Acquire, Ordering::Relaxed)
            {
                Ok(_) => {
                    // A panic while the value was held is caught by the holder's caller
                    // (`guarded`); a poisoned lock still holds the value it left.
                    let value = self.value.lock().unwrap_or_else(|e| e.into_inner());
                    return Ok(Held {
                        value,
                        _release: Release(&self.holder),
                    });
                }
                Err(holder) if holder != pid => return Err(Unheld::Forked),
                Err(_) => {}
            }
            if give_up() {
                return Err(Unheld::GaveUp);
            }
            std::thread::sleep(pause);
            pause = (pause * 2).min(Self::RETRY);
        }
    }
}
