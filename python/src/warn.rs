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
//! with a caller that holds it. At most [`MAX_PENDING`] texts are kept between two
//! [`emit`]s; the rest are counted and reported as one more warning.

use std::sync::Mutex;

use pyo3::prelude::*;
use tracing::field::{Field, Visit};
use tracing::span::{Attributes, Id, Record};
use tracing::{Event, Level, Metadata, Subscriber};

/// The most warnings kept between two [`emit`]s.
pub const MAX_PENDING: usize = 1000;

/// Warnings not yet raised, and how many more were dropped.
static PENDING: Mutex<(Vec<String>, usize)> = Mutex::new((Vec::new(), 0));

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
        // More severe levels order lower.
        *metadata.level() <= Level::WARN
    }

    fn new_span(&self, _: &Attributes<'_>) -> Id {
        Id::from_u64(1)
    }

    fn record(&self, _: &Id, _: &Record<'_>) {}

    fn record_follows_from(&self, _: &Id, _: &Id) {}

    fn event(&self, event: &Event<'_>) {
        let mut message = Message(String::new());
        event.record(&mut message);
        if let Ok(mut pending) = PENDING.lock() {
            if pending.0.len() < MAX_PENDING {
                pending.0.push(message.0);
            } else {
                pending.1 += 1;
            }
        }
    }

    fn enter(&self, _: &Id) {}

    fn exit(&self, _: &Id) {}
}

/// Makes [`Collector`] the process's `tracing` subscriber, unless the process has one.
pub fn install() {
    let _ = tracing::subscriber::set_global_default(Collector);
}

/// Raises the warnings kept since the last call as `gridplan.GridplanWarning`s (with the
/// warnings filter deciding: an `"error"` filter makes the first one an exception).
pub fn emit(py: Python<'_>) -> PyResult<()> {
    let (texts, dropped) = match PENDING.lock() {
        Ok(mut pending) => (
            std::mem::take(&mut pending.0),
            std::mem::take(&mut pending.1),
        ),
        Err(_) => return Ok(()),
    };
    if texts.is_empty() && dropped == 0 {
        return Ok(());
    }
    let warnings = py.import("warnings")?;
    let class = py.import("gridplan._errors")?.getattr("GridplanWarning")?;
    let more = (dropped > 0).then(|| format!("{dropped} more gridplan warnings were dropped"));
    for text in texts.into_iter().chain(more) {
        warnings.call_method1("warn", (text, &class, 2))?;
    }
    Ok(())
}

/// `result`, after raising the warnings its call left ([`emit`]); the call's own error
/// wins over a warning turned into an exception.
pub fn after<T>(py: Python<'_>, result: PyResult<T>) -> PyResult<T> {
    let emitted = emit(py);
    let value = result?;
    emitted.map(|()| value)
}
