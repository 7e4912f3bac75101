//! Long calls that Ctrl-C interrupts: the work runs on a thread of this module's pool
//! ([`worker_pool`], rebuilt in a forked process) while the calling thread, holding the GIL
//! every 50 ms, asks Python for signals (only the main thread, holding the GIL, can). On a KeyboardInterrupt the caller's `stop` is called
//! (it raises the flags the work watches), the work is waited for, and the exception is
//! raised.

use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::prelude::*;

/// How often the calling thread looks for signals.
const POLL: Duration = Duration::from_millis(50);

/// `work()`'s value, or the KeyboardInterrupt (or other signal handler's exception) that
/// came while it ran, after `stop()` made it end. A panic in `work` is `panicked`.
pub fn interruptible<T: Send>(
    py: Python<'_>,
    stop: impl Fn(),
    panicked: impl FnOnce() -> T,
    work: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let (done, finished) = mpsc::channel::<Option<T>>();
    // Locked by this thread only; the mutex makes the receiver shareable with `detach`.
    let finished = Mutex::new(finished);
    // The work goes to a pool whose threads outlive the call (`worker_pool`): a thread of
    // its own per call (`std::thread::scope`) added 60-80 us to every `plan` on den520d.
    // `in_place_scope` runs this body on the calling thread and waits for the work at its
    // end, so the work may borrow.
    let pool = worker_pool().map_err(|e| {
        pyo3::exceptions::PyRuntimeError::new_err(format!("cannot start worker threads: {e}"))
    })?;
    pool.in_place_scope(|scope| {
        scope.spawn(move |_| {
            let value = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)).ok();
            let _ = done.send(value);
        });
        loop {
            let ended = py.detach(|| {
                let finished = finished.lock().unwrap_or_else(|e| e.into_inner());
                match finished.recv_timeout(POLL) {
                    Ok(value) => Some(value),
                    // The sender is gone only once the work has sent (or unwound).
                    Err(RecvTimeoutError::Disconnected) => Some(None),
                    Err(RecvTimeoutError::Timeout) => None,
                }
            });
            if let Some(value) = ended {
                return Ok(value.unwrap_or_else(panicked));
            }
            if let Err(interrupt) = py.check_signals() {
                stop();
                // The scope's end waits for the work, without the GIL.
                let finished = &finished;
                py.detach(|| {
                    let finished = finished.lock().unwrap_or_else(|e| e.into_inner());
                    let _ = finished.recv();
                });
                return Err(interrupt);
            }
        }
    })
}

/// The pool the interruptible calls run on, built by this process. A process forked from
/// one that built it (Python's `multiprocessing` on Linux) inherits the pool's memory but
/// none of its threads, so work sent there would never run: the child builds its own.
pub fn worker_pool() -> Result<Arc<rayon::ThreadPool>, rayon::ThreadPoolBuildError> {
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
                    .thread_name(|i| format!("gridplan-call-{i}"))
                    .build()?,
            );
            *pool = Some((pid, built.clone()));
            Ok(built)
        }
    }
}
