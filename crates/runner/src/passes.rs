//! Passes over a whole sweep's records, in run order, without holding them.
//!
//! A report that must stay in memory bounded by its groups (label x map x bucket), not by
//! the runs, reads the records through [`RecordPasses`]: each pass visits every record
//! once, in run order, and a section may make as many passes as it needs (a first pass
//! for counts and sums, then passes that select exact quantiles). A slice of records in
//! memory is one source; a stream file on disk ([`StreamPasses`]: the framed resume
//! stream or a JSON Lines stream, read back record by record) is the other.
//!
//! ```
//! use planner_runner::passes::RecordPasses;
//! use planner_runner::RunRecord;
//!
//! let records: Vec<RunRecord> = Vec::new();
//! let mut seen = 0;
//! let passes: &dyn RecordPasses = &records.as_slice();
//! passes.pass(&mut |_| seen += 1).unwrap();
//! assert_eq!(seen, 0);
//! assert_eq!(passes.len(), 0);
//! ```

use std::io::BufReader;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::stream::{self, Place, StreamError, StreamProblem, StreamReader};
use crate::{RunRecord, RunnerError};

/// A whole sweep's records, readable any number of times, in run order.
pub trait RecordPasses: Sync {
    /// Calls `visit` on every record, in run order.
    fn pass(&self, visit: &mut dyn FnMut(&RunRecord)) -> Result<(), RunnerError>;

    /// The number of records a pass visits.
    fn len(&self) -> u64;

    /// Whether a pass visits no record.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl RecordPasses for &[RunRecord] {
    fn pass(&self, visit: &mut dyn FnMut(&RunRecord)) -> Result<(), RunnerError> {
        self.iter().for_each(visit);
        Ok(())
    }

    fn len(&self) -> u64 {
        <[RunRecord]>::len(self) as u64
    }
}

/// The records of a complete stream file (its header states `runs` records), read from
/// disk at each pass, one record at a time.
#[derive(Debug, Clone)]
pub struct StreamPasses {
    path: PathBuf,
    runs: u64,
}

impl StreamPasses {
    /// The records of the stream file `path`, which holds `runs` of them.
    pub fn new(path: &Path, runs: u64) -> StreamPasses {
        StreamPasses {
            path: path.to_path_buf(),
            runs,
        }
    }

    /// The stream file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

impl RecordPasses for StreamPasses {
    /// Reads the file once; a file that ends early, holds more records than stated or
    /// ends in a cut record (it changed since the sweep) is an error.
    fn pass(&self, visit: &mut dyn FnMut(&RunRecord)) -> Result<(), RunnerError> {
        let file = stream::open_regular(&self.path).map_err(|e| RunnerError::io(&self.path, e))?;
        let what = self.path.display().to_string();
        let (_, mut reader) = StreamReader::new(BufReader::with_capacity(1 << 16, file), &what)?;
        let mut n = 0u64;
        while let Some((_, record)) = reader.next_run()? {
            n += 1;
            if n > self.runs {
                break;
            }
            visit(&record);
        }
        if n != self.runs || reader.was_cut() {
            let problem = StreamProblem::Changed {
                read: n,
                runs: self.runs,
            };
            return Err(StreamError::new(&what, Place::File, problem).into());
        }
        Ok(())
    }

    fn len(&self) -> u64 {
        self.runs
    }
}

/// Passes over `inner` that end early once `stop` is raised (Ctrl-C while a sweep's report
/// is written): a pass started after it, or one under way, visits no further record and
/// returns [`RunnerError::Interrupted`], so what reads the records in passes stops within
/// a record instead of finishing its work.
pub struct StoppablePasses<'a> {
    inner: &'a dyn RecordPasses,
    stop: &'a AtomicBool,
}

impl<'a> StoppablePasses<'a> {
    /// `inner`'s passes, stopped by `stop`.
    pub fn new(inner: &'a dyn RecordPasses, stop: &'a AtomicBool) -> StoppablePasses<'a> {
        StoppablePasses { inner, stop }
    }
}

impl RecordPasses for StoppablePasses<'_> {
    fn pass(&self, visit: &mut dyn FnMut(&RunRecord)) -> Result<(), RunnerError> {
        let mut stopped = self.stop.load(Ordering::Relaxed);
        if !stopped {
            self.inner.pass(&mut |r| {
                if stopped || self.stop.load(Ordering::Relaxed) {
                    stopped = true;
                    return;
                }
                visit(r);
            })?;
        }
        match stopped {
            true => Err(RunnerError::Interrupted),
            false => Ok(()),
        }
    }

    fn len(&self) -> u64 {
        self.inner.len()
    }
}
