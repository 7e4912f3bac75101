//! The library's warnings as Python warnings.
//!
//! planner-runner and planner-maps say what they doubt or ignore through `tracing` (a ROS
//! map's second YAML document, a scenario naming another map, an inadmissible planner
//! label, a resume stream carried over): the command line prints those events on stderr.
//! Here a [`Collector`], the process's global `tracing` subscriber once the module is
//! imported, keeps each warning's text; every entry point that reads maps or configs or
//! plans (`read_map`, `run_experiment`, `plan`, `Planner.plan`, `Planner.plan_many`) then
//! raises them with `warnings.warn(..., gridplan.GridplanWarning)` on the calling thread
//! ([`emit`]), a run the memory check refused or a path that breaks its planner's rule among
//! them. The collector only takes a lock: events come from worker threads that run
//! while the calling thread has released the GIL, and taking the GIL there could deadlock
//! with a caller that holds it. At most [`MAX_PENDING`] texts are kept per call; the rest
//! are counted and reported as one more warning.
//!
//! Each entry point is a [`Call`]: a warning raised on its calling thread, or on a worker
//! it marks ([`Call::mark_worker`], `plan_many`'s pool), is its own, so two Python threads
//! planning at once each get their own warnings (a test plans on two threads, one whose
//! runs are refused and one whose runs are not). planner-runner's workers
//! (`run_experiment`'s) are not ours to mark: they log inside the span that was current
//! where the sweep began, and the collector's current span on a call's thread stands for
//! that call ([`CALL_SPAN`]), so their warnings are the call's too (a test runs two sweeps
//! at once). A warning from any other thread goes to the one call running if there is
//! one, else to the next call that ends.

use std::cell::{Cell, RefCell};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock};

use pyo3::prelude::*;
use tracing::field::{Field, Visit};
use tracing::span::{Attributes, Id, Record};
use tracing::{Event, Level, Metadata, Subscriber};
use tracing_core::span::Current;

/// The most warnings kept per call (and for no call) until they are raised.
pub const MAX_PENDING: usize = 1000;

/// Warnings not yet raised, by call.
static PENDING: Mutex<Pending> = Mutex::new(Pending {
    calls: Vec::new(),
    loose: Texts::new(),
});

/// The next call's number (0 is no call).
static NEXT_CALL: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// The call this thread works for, 0 for none.
    static CURRENT: Cell<u64> = const { Cell::new(0) };
    /// The calls of the spans this thread entered, innermost last (0 for a span of no
    /// call): planner-runner's workers enter their caller's.
    static ENTERED: RefCell<Vec<u64>> = const { RefCell::new(Vec::new()) };
}

/// The span that stands for a call: the collector's only enabled span, which
/// [`Collector::current_span`] reports on a call's thread (its id is the call's number).
pub const CALL_SPAN: &str = "gridplan_call";

/// The metadata of [`CALL_SPAN`]'s callsite, recorded when [`install`] creates one.
static CALL_METADATA: OnceLock<&'static Metadata<'static>> = OnceLock::new();

/// The span id of "no call" (ids are never 0).
const NO_CALL: u64 = u64::MAX;

/// The call the calling thread works for: the innermost span it entered, else its mark.
fn thread_call() -> u64 {
    ENTERED
        .with(|entered| entered.borrow().last().copied())
        .unwrap_or_else(|| CURRENT.with(Cell::get))
}

/// Warning texts, at most [`MAX_PENDING`], and how many more were dropped.
struct Texts {
    texts: Vec<String>,
    dropped: usize,
}

impl Texts {
    const fn new() -> Texts {
        Texts {
            texts: Vec::new(),
            dropped: 0,
        }
    }

    fn push(&mut self, text: String) {
        if self.texts.len() < MAX_PENDING {
            self.texts.push(text);
        } else {
            self.dropped += 1;
        }
    }
}

/// The calls running and their warnings, and the warnings of no call.
struct Pending {
    calls: Vec<(u64, Texts)>,
    loose: Texts,
}

impl Pending {
    /// Keeps `text` for call `id` (0: the thread works for no call).
    fn keep(&mut self, id: u64, text: String) {
        let only = match self.calls.as_slice() {
            [(only, _)] => Some(*only),
            _ => None,
        };
        let id = if id == 0 { only.unwrap_or(0) } else { id };
        match self.calls.iter_mut().find(|(call, _)| *call == id) {
            Some((_, texts)) => texts.push(text),
            None => self.loose.push(text),
        }
    }
}

/// One entry point's call, from before it releases the GIL until its warnings are raised:
/// see the module docs.
pub struct Call {
    id: u64,
    /// The calling thread's call before this one (none, unless calls nest).
    outer: u64,
}

impl Call {
    /// Begins a call on the calling thread.
    pub fn begin() -> Call {
        let id = NEXT_CALL.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut pending) = PENDING.lock() {
            pending.calls.push((id, Texts::new()));
        }
        let outer = CURRENT.with(|current| current.replace(id));
        Call { id, outer }
    }

    /// Marks the calling thread, a worker of this call, until the mark is dropped.
    pub fn mark_worker(&self) -> WorkerMark {
        WorkerMark {
            outer: CURRENT.with(|current| current.replace(self.id)),
        }
    }

    /// `result`, after raising the warnings this call left ([`emit`]); the call's own
    /// error wins over a warning turned into an exception.
    pub fn end<T>(self, py: Python<'_>, result: PyResult<T>) -> PyResult<T> {
        let emitted = emit(py, self.id);
        let value = result?;
        emitted.map(|()| value)
    }
}

impl Drop for Call {
    fn drop(&mut self) {
        CURRENT.with(|current| current.set(self.outer));
        if let Ok(mut pending) = PENDING.lock() {
            pending.calls.retain(|(call, _)| *call != self.id);
        }
    }
}

/// A worker thread's mark ([`Call::mark_worker`]); dropping it restores the thread's.
pub struct WorkerMark {
    outer: u64,
}

impl Drop for WorkerMark {
    fn drop(&mut self) {
        CURRENT.with(|current| current.set(self.outer));
    }
}

/// The `tracing` subscriber that keeps warnings and errors ([`PENDING`]).
pub struct Collector;

/// The text of an event's `message` field (its format string, filled in).
struct Message(String);

impl Visit for Message {
    fn record_debug(&mut self, field: &Field, value: &dyn std::fmt::Debug) {
        if field.name() == "message" {
            self.0 = format!("{value:?}");
        }
    }

    fn record_str(&mut self, field: &Field, value: &str) {
        if field.name() == "message" {
            self.0 = value.to_string();
        }
    }
}

impl Subscriber for Collector {
    fn enabled(&self, metadata: &Metadata<'_>) -> bool {
        if metadata.is_span() {
            return metadata.name() == CALL_SPAN;
        }
        // More severe levels order lower.
        *metadata.level() <= Level::WARN
    }

    /// A new span stands for the calling thread's call.
    fn new_span(&self, attributes: &Attributes<'_>) -> Id {
        let _ = CALL_METADATA.set(attributes.metadata());
        match thread_call() {
            0 => Id::from_u64(NO_CALL),
            call => Id::from_u64(call),
        }
    }

    /// The calling thread's call as a span, so that `Span::current()` where a sweep
    /// begins carries the call to the workers that enter it.
    fn current_span(&self) -> Current {
        match (thread_call(), CALL_METADATA.get()) {
            (0, _) | (_, None) => Current::none(),
            (call, Some(metadata)) => Current::new(Id::from_u64(call), metadata),
        }
    }

    fn record(&self, _: &Id, _: &Record<'_>) {}

    fn record_follows_from(&self, _: &Id, _: &Id) {}

    fn event(&self, event: &Event<'_>) {
        let mut message = Message(String::new());
        event.record(&mut message);
        let id = thread_call();
        if let Ok(mut pending) = PENDING.lock() {
            pending.keep(id, message.0);
        }
    }

    fn enter(&self, span: &Id) {
        let call = match span.into_u64() {
            NO_CALL => 0,
            call => call,
        };
        ENTERED.with(|entered| entered.borrow_mut().push(call));
    }

    fn exit(&self, _: &Id) {
        ENTERED.with(|entered| entered.borrow_mut().pop());
    }
}

/// Makes [`Collector`] the process's `tracing` subscriber, unless the process has one.
pub fn install() {
    if tracing::subscriber::set_global_default(Collector).is_ok() {
        // Records the call span's metadata ([`Collector::current_span`] needs it).
        drop(tracing::warn_span!(CALL_SPAN));
    }
}

/// Raises call `id`'s warnings and those of no call as `gridplan.GridplanWarning`s (with
/// the warnings filter deciding: an `"error"` filter makes the first one an exception).
fn emit(py: Python<'_>, id: u64) -> PyResult<()> {
    let (texts, dropped) = match PENDING.lock() {
        Ok(mut pending) => {
            let loose = std::mem::replace(&mut pending.loose, Texts::new());
            let own = pending
                .calls
                .iter_mut()
                .find(|(call, _)| *call == id)
                .map_or_else(Texts::new, |(_, texts)| {
                    std::mem::replace(texts, Texts::new())
                });
            let dropped = loose.dropped + own.dropped;
            (
                loose.texts.into_iter().chain(own.texts).collect::<Vec<_>>(),
                dropped,
            )
        }
        Err(_) => return Ok(()),
    };
    if texts.is_empty() && dropped == 0 {
        return Ok(());
    }
    let warnings = py.import("warnings")?;
    let class = py.import("gridplan._errors")?.getattr("GridplanWarning")?;
    let more = (dropped > 0).then(|| format!("{dropped} more gridplan warnings were dropped"));
    for text in texts.into_iter().chain(more) {
        warnings.call_method1("warn", (planner_text::terminal(&text), &class, 2))?;
    }
    Ok(())
}
