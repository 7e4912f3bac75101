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

use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::sync::{Arc, Mutex};
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
