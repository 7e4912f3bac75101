//! Long calls that Ctrl-C interrupts: the work runs on a thread of its own while the
//! calling thread, holding the GIL every 50 ms, asks Python for signals (only the main
//! thread, holding the GIL, can). On a KeyboardInterrupt the caller's `stop` is called
//! (it raises the flags the work watches), the work is waited for, and the exception is
//! raised.

use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Mutex;
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
    let (done, finished) = mpsc::channel::<()>();
    // Locked by this thread only; the mutex makes the receiver shareable with `detach`.
    let finished = Mutex::new(finished);
    std::thread::scope(|scope| {
        let worker = scope.spawn(move || {
            let value = work();
            let _ = done.send(());
            value
        });
        loop {
            let ended = py.detach(|| {
                let finished = finished.lock().unwrap_or_else(|e| e.into_inner());
                finished.recv_timeout(POLL) != Err(RecvTimeoutError::Timeout)
            });
            if ended {
                return Ok(py.detach(|| worker.join()).unwrap_or_else(|_| panicked()));
            }
            if let Err(interrupt) = py.check_signals() {
                stop();
                py.detach(|| {
                    let _ = worker.join();
                });
                return Err(interrupt);
            }
        }
    })
}
