//! The [`Planner`] trait, problems, budgets and outcomes.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use crate::counters::Counters;
use crate::error::{Endpoint, ProblemError};
use crate::grid::{Cell, Grid};
use crate::path::Path;
use crate::specs::PlannerSpecs;

/// A start-goal query on a grid. Construction validates both cells.
#[derive(Debug, Clone, Copy)]
pub struct Problem<'g> {
    grid: &'g Grid,
    start: Cell,
    goal: Cell,
}

impl<'g> Problem<'g> {
    /// A problem from `start` to `goal` on `grid`.
    ///
    /// Errors, naming the cell, when the start or goal is out of bounds or blocked.
    /// A goal that is free but unreachable is not an error: planners report
    /// [`Status::NoPath`].
    pub fn new(grid: &'g Grid, start: Cell, goal: Cell) -> Result<Problem<'g>, ProblemError> {
        for (endpoint, cell) in [(Endpoint::Start, start), (Endpoint::Goal, goal)] {
            if !grid.contains(cell) {
                return Err(ProblemError::OutOfBounds {
                    endpoint,
                    cell,
                    width: grid.width(),
                    height: grid.height(),
                });
            }
            if !grid.is_free(cell) {
                return Err(ProblemError::Blocked { endpoint, cell });
            }
        }
        Ok(Problem { grid, start, goal })
    }

    /// The grid.
    pub fn grid(&self) -> &'g Grid {
        self.grid
    }

    /// The start cell (in bounds and free).
    pub fn start(&self) -> Cell {
        self.start
    }

    /// The goal cell (in bounds and free).
    pub fn goal(&self) -> Cell {
        self.goal
    }
}

/// Limits on one search, and what it records besides its counters. The default is
/// unlimited and records nothing.
///
/// An expansion limit keeps results deterministic; a wall-clock limit does not (what a
/// search reaches in a given time depends on the machine), so configs that snapshot
/// counters should use expansions.
///
/// A memory limit ([`Budget::max_memory_mb`]) bounds what a planner allocates for its
/// per-cell state: before allocating, a planner adds up the bytes its per-cell arrays
/// take for the grid (their full size, what a search that touches every cell commits,
/// even where the arrays are committed lazily) and, when that is over the limit, returns
/// [`Outcome::over_memory`] (status [`Status::BudgetExhausted`], no expansion, and a
/// [`MemoryShortfall`] saying how much it needs) instead of allocating; see
/// [`Budget::check_memory`].
///
/// With [`Budget::record_expanded`] on, a planner that supports it lists the cells it
/// expanded, in expansion order, in [`Outcome::expanded`]. It is off by default and
/// never part of a config (the runner turns it on to draw search-effort figures, in a
/// run apart from the timed one); a planner that does not support it leaves the list
/// empty and says so in its docs.
///
/// A [`Budget::cancel`] flag stops a search from another thread (a server's cancel
/// button, an interrupt): the search ends as if its budget had run out, with status
/// [`Status::BudgetExhausted`] (a cancelled search is one whose budget the caller cut to
/// what it had done; [`BudgetClock::is_cancelled`] tells the two apart). The flag is read
/// where the clock is, every [`BudgetClock::TIME_CHECK_INTERVAL`] expansions, so a search
/// without one pays nothing per expansion. It is never part of a config.
#[derive(Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(
    deny_unknown_fields,
    expecting = "a table of limits (`max_expansions`, `max_time_ms`, `max_memory_mb`)"
)]
pub struct Budget {
    /// Stop after this many expansions (each planner says what one expansion is).
    pub max_expansions: Option<u64>,
    /// Stop after this much wall-clock time, checked every [`BudgetClock::TIME_CHECK_INTERVAL`] expansions.
    #[serde(default, with = "optional_millis", rename = "max_time_ms")]
    pub max_time: Option<Duration>,
    /// Refuse to plan when the planner's per-cell state for the grid would take more
    /// than this many MiB (2^20 bytes). `None`: no limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_memory_mb: Option<u64>,
    /// List the expanded cells in [`Outcome::expanded`]. Not a config key (skipped by
    /// serde); off in timed runs.
    #[serde(skip)]
    pub record_expanded: bool,
    /// Record the search step by step in [`Outcome::events`] (planners that support it).
    /// Not a config key (skipped by serde); off in timed runs.
    #[serde(skip)]
    pub record_events: bool,
    /// Stop when this flag is raised (read every [`BudgetClock::TIME_CHECK_INTERVAL`]
    /// expansions). Not a config key (skipped by serde); `None`: nothing cancels.
    #[serde(skip)]
    pub cancel: Option<CancelFlag>,
}

/// The fields a derived `Debug` would print, `cancel` only when set: runs hash a budget's
/// `Debug` text to tell whether a resumed sweep is the same, so it must not change for
/// budgets without one.
impl std::fmt::Debug for Budget {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mut out = f.debug_struct("Budget");
        out.field("max_expansions", &self.max_expansions)
            .field("max_time", &self.max_time)
            .field("max_memory_mb", &self.max_memory_mb)
            .field("record_expanded", &self.record_expanded);
        // Only when set, as `cancel`: the text of budgets without it is unchanged.
        if self.record_events {
            out.field("record_events", &self.record_events);
        }
        if let Some(cancel) = self.cancel {
            out.field("cancel", &cancel);
        }
        out.finish()
    }
}

/// A flag that cancels the searches whose [`Budget::cancel`] holds it: a handle (`Copy`,
/// as a [`Budget`] is) to an atomic flag that lives as long as the program.
/// [`CancelFlag::new`] allocates one that is never freed, so a long-running caller keeps
/// a few and [`CancelFlag::reset`]s them for reuse (the server keeps one per concurrent
/// plan); [`CancelFlag::from_static`] wraps a `static` (an interrupt handler's).
///
/// ```
/// use planner_api::{Budget, CancelFlag};
///
/// let flag = CancelFlag::new();
/// let budget = Budget::unlimited().with_cancel(flag);
/// let mut clock = budget.start();
/// assert!(clock.allows(0));
/// flag.cancel();
/// // The flag is read every TIME_CHECK_INTERVAL expansions, as the clock is.
/// let allowed = (1..10_000).take_while(|&n| clock.allows(n)).count();
/// assert!(allowed < 2048 && clock.is_exhausted() && clock.is_cancelled());
/// flag.reset();
/// assert!(!budget.is_cancelled());
/// ```
#[derive(Debug, Clone, Copy)]
pub struct CancelFlag(&'static AtomicBool);

impl CancelFlag {
    /// A new flag, not raised; its one byte is never freed (reuse it: [`CancelFlag::reset`]).
    pub fn new() -> CancelFlag {
        CancelFlag(Box::leak(Box::new(AtomicBool::new(false))))
    }

    /// The flag `flag`, a `static` that the caller raises (say, from a signal handler's
    /// thread) with [`CancelFlag::cancel`] or by storing `true`.
    pub const fn from_static(flag: &'static AtomicBool) -> CancelFlag {
        CancelFlag(flag)
    }

    /// Raises the flag: every search holding it stops at its next check.
    pub fn cancel(self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Lowers the flag, for the next search that holds it.
    pub fn reset(self) {
        self.0.store(false, Ordering::Relaxed);
    }

    /// Whether the flag is raised.
    pub fn is_cancelled(self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

impl Default for CancelFlag {
    /// [`CancelFlag::new`].
    fn default() -> CancelFlag {
        CancelFlag::new()
    }
}

/// Two flags are equal when they are the same flag (copies of one another).
impl PartialEq for CancelFlag {
    fn eq(&self, other: &CancelFlag) -> bool {
        std::ptr::eq(self.0, other.0)
    }
}

impl Eq for CancelFlag {}

/// Cancel flags kept for reuse, since a [`CancelFlag`]'s byte is never freed: a caller
/// that starts searches again and again (a server's plans, a Python batch) takes a lowered
/// flag for each and gives it back when its searches have ended, so the flags made are as
/// many as ever ran at once.
///
/// ```
/// use planner_api::CancelPool;
/// static POOL: CancelPool = CancelPool::new();
/// let flag = POOL.take();
/// flag.cancel();
/// POOL.give(flag);
/// let again = POOL.take();
/// assert!(again == flag && !again.is_cancelled());
/// {
///     let lent = POOL.lend();
///     lent.flag().cancel();
/// } // given back, and lowered when taken again
/// assert!(!POOL.take().is_cancelled());
/// ```
#[derive(Debug, Default)]
pub struct CancelPool(std::sync::Mutex<Vec<CancelFlag>>);

impl CancelPool {
    /// An empty pool.
    pub const fn new() -> CancelPool {
        CancelPool(std::sync::Mutex::new(Vec::new()))
    }

    /// A lowered flag: one given back earlier, else a new one.
    pub fn take(&self) -> CancelFlag {
        let flag = self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .pop()
            .unwrap_or_default();
        flag.reset();
        flag
    }

    /// Gives `flag` back once no search holds it. It stays as it is until it is taken
    /// again ([`CancelPool::take`] lowers it), so the giver may still read whether it was
    /// raised (a server answering "cancelled" after its worker gave the flag back).
    pub fn give(&self, flag: CancelFlag) {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .push(flag);
    }

    /// [`CancelPool::take`], given back when the returned guard is dropped however the
    /// caller's scope ends.
    pub fn lend(&self) -> LentFlag<'_> {
        LentFlag {
            pool: self,
            flag: self.take(),
        }
    }
}

/// A flag lent by [`CancelPool::lend`]; dropping it gives the flag back.
#[derive(Debug)]
pub struct LentFlag<'a> {
    pool: &'a CancelPool,
    flag: CancelFlag,
}

impl LentFlag<'_> {
    /// The flag.
    pub fn flag(&self) -> CancelFlag {
        self.flag
    }
}

impl Drop for LentFlag<'_> {
    fn drop(&mut self) {
        self.pool.give(self.flag);
    }
}

impl Budget {
    /// No limit.
    pub fn unlimited() -> Budget {
        Budget::default()
    }

    /// At most `n` expansions.
    pub fn expansions(n: u64) -> Budget {
        Budget {
            max_expansions: Some(n),
            ..Budget::default()
        }
    }

    /// This budget with a memory limit of `mb` MiB for the planner's per-cell state.
    pub fn with_memory_mb(self, mb: u64) -> Budget {
        Budget {
            max_memory_mb: Some(mb),
            ..self
        }
    }

    /// This budget with [`Budget::record_expanded`] set to `on`.
    pub fn recording_expanded(self, on: bool) -> Budget {
        Budget {
            record_expanded: on,
            ..self
        }
    }

    /// This budget with [`Budget::record_events`] set to `on`.
    pub fn recording_events(self, on: bool) -> Budget {
        Budget {
            record_events: on,
            ..self
        }
    }

    /// Whether per-cell state of `bytes` bytes for `grid` fits [`Budget::max_memory_mb`].
    /// Planners call it before allocating and return [`Outcome::over_memory`] with the
    /// error.
    ///
    /// ```
    /// use planner_api::{Budget, Grid};
    /// let grid = Grid::new(4000, 4000).unwrap();
    /// let budget = Budget::unlimited().with_memory_mb(10);
    /// assert!(budget.check_memory(10 << 20, &grid).is_ok());
    /// let err = budget.check_memory(16_000_000 * 9, &grid).unwrap_err();
    /// assert_eq!(
    ///     err.to_string(),
    ///     "needs 138 MB for a 4000 x 4000 grid, over the max_memory_mb = 10 budget"
    /// );
    /// ```
    pub fn check_memory(&self, bytes: u64, grid: &Grid) -> Result<(), MemoryShortfall> {
        match self.max_memory_mb {
            Some(mb) if bytes > mb.saturating_mul(1 << 20) => Err(MemoryShortfall {
                needed_bytes: bytes,
                max_memory_mb: mb,
                width: grid.width(),
                height: grid.height(),
            }),
            _ => Ok(()),
        }
    }

    /// This budget with a wall-clock limit as well.
    pub fn with_time(self, limit: Duration) -> Budget {
        Budget {
            max_time: Some(limit),
            ..self
        }
    }

    /// This budget cancelled by `flag` ([`Budget::cancel`]).
    pub fn with_cancel(self, flag: CancelFlag) -> Budget {
        Budget {
            cancel: Some(flag),
            ..self
        }
    }

    /// Whether its [`Budget::cancel`] flag has been raised.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_some_and(CancelFlag::is_cancelled)
    }

    /// Starts the clock for one search.
    pub fn start(&self) -> BudgetClock {
        let deadline = self.max_time.map(|limit| Instant::now() + limit);
        BudgetClock {
            max_expansions: self.max_expansions.unwrap_or(u64::MAX),
            periodic: deadline.is_some() || self.cancel.is_some(),
            deadline,
            cancel: self.cancel,
            until_time_check: BudgetClock::TIME_CHECK_INTERVAL,
            exhausted: false,
            cancelled: false,
        }
    }
}

mod optional_millis {
    use std::time::Duration;

    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(value: &Option<Duration>, s: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(d) => s.serialize_some(&(d.as_millis() as u64)),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Duration>, D::Error> {
        Ok(Option::<u64>::deserialize(d)?.map(Duration::from_millis))
    }
}

/// The running state of a [`Budget`] during one search.
///
/// Call [`BudgetClock::allows`] before each expansion with the number done so far.
#[derive(Debug, Clone)]
pub struct BudgetClock {
    max_expansions: u64,
    /// Whether there is a deadline or a cancel flag to look at periodically.
    periodic: bool,
    deadline: Option<Instant>,
    cancel: Option<CancelFlag>,
    until_time_check: u32,
    exhausted: bool,
    cancelled: bool,
}

impl BudgetClock {
    /// How many expansions pass between two reads of the clock.
    pub const TIME_CHECK_INTERVAL: u32 = 1024;

    /// Whether one more expansion is allowed after `n_expanded` of them. Once it has said
    /// no it keeps saying no, and [`BudgetClock::is_exhausted`] turns true.
    #[inline]
    pub fn allows(&mut self, n_expanded: u64) -> bool {
        if self.exhausted {
            return false;
        }
        if n_expanded >= self.max_expansions {
            self.exhausted = true;
            return false;
        }
        self.tick()
    }

    /// Whether work that the planner does not count as expansions (a route computed before
    /// the search proper, say) may go on: the cancel flag and the deadline, read every
    /// [`BudgetClock::TIME_CHECK_INTERVAL`] calls as [`BudgetClock::allows`] reads them,
    /// without the expansion limit. Once it has said no it keeps saying no.
    #[inline]
    pub fn allows_uncounted(&mut self) -> bool {
        !self.exhausted && self.tick()
    }

    /// One step towards the next periodic check, and that check when it is due.
    #[inline(always)]
    fn tick(&mut self) -> bool {
        if self.periodic {
            self.until_time_check -= 1;
            if self.until_time_check == 0 {
                self.until_time_check = Self::TIME_CHECK_INTERVAL;
                return self.periodic_check();
            }
        }
        true
    }

    /// The check made every [`BudgetClock::TIME_CHECK_INTERVAL`] expansions: the cancel
    /// flag, then the deadline.
    #[cold]
    fn periodic_check(&mut self) -> bool {
        if self.cancel.is_some_and(CancelFlag::is_cancelled) {
            self.cancelled = true;
            self.exhausted = true;
            return false;
        }
        if self
            .deadline
            .is_some_and(|deadline| Instant::now() >= deadline)
        {
            self.exhausted = true;
            return false;
        }
        true
    }

    /// Whether the budget has run out (a cancelled search's too).
    pub fn is_exhausted(&self) -> bool {
        self.exhausted
    }

    /// Whether the search was stopped by its [`Budget::cancel`] flag.
    pub fn is_cancelled(&self) -> bool {
        self.cancelled
    }
}

/// A planner's per-cell state for a grid that does not fit [`Budget::max_memory_mb`]:
/// the planner did not allocate it and did not search.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct MemoryShortfall {
    /// The bytes the planner's per-cell state would take.
    pub needed_bytes: u64,
    /// The limit, in MiB.
    pub max_memory_mb: u64,
    /// The grid's width.
    pub width: u32,
    /// The grid's height.
    pub height: u32,
}

impl std::fmt::Display for MemoryShortfall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "needs {} MB for a {} x {} grid, over the max_memory_mb = {} budget",
            self.needed_bytes.div_ceil(1 << 20),
            self.width,
            self.height,
            self.max_memory_mb
        )
    }
}

impl std::error::Error for MemoryShortfall {}

/// How a search ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A path was found; exhaustive planners found the best one.
    Found,
    /// The search completed and proved there is no path.
    NoPath,
    /// The budget ran out first; the outcome carries the best path found so far, if any.
    BudgetExhausted,
}

impl Status {
    /// The snake-case name used in results: `found`, `no_path`, `budget_exhausted`.
    pub fn as_str(self) -> &'static str {
        match self {
            Status::Found => "found",
            Status::NoPath => "no_path",
            Status::BudgetExhausted => "budget_exhausted",
        }
    }
}

/// The result of one [`Planner::plan`] call.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// How the search ended.
    pub status: Status,
    /// The path: present when found; for an exhausted budget, the best found so far if any.
    pub path: Option<Path>,
    /// The counters that apply to this planner, in its order.
    pub counters: Counters,
    /// Cells the planner points out in its result, in its order (PA-star's handover
    /// points); usually none. Figures draw them and run records list them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub marks: Vec<Mark>,
    /// Named sequences a planner records along its search, such as a swarm's best fitness
    /// per iteration or an optimising planner's cost after each improvement; usually none.
    /// Reports chart them and run records keep them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub series: Vec<Series>,
    /// The cells the search expanded, in expansion order, when the budget asked for them
    /// ([`Budget::record_expanded`]) and the planner records them; otherwise empty. Its
    /// length is then the planner's `n_expanded` counter, unless the planner's docs say
    /// what it lists instead (JPS lists its expanded jump points).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub expanded: Vec<Cell>,
    /// The search step by step, when the budget asked for it ([`Budget::record_events`])
    /// and the planner records it (its docs say so); otherwise empty: each node generated
    /// (put in OPEN), updated (its `g` lowered while in OPEN) and expanded, in order, with
    /// its parent, `g` and `f`. What a search trace (`plan --trace`) shows.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<SearchEvent>,
    /// Set when the planner refused to search because its per-cell state would not fit
    /// [`Budget::max_memory_mb`] (the status is then [`Status::BudgetExhausted`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub memory: Option<MemoryShortfall>,
    /// Set when the planner's search ended because the costs it compares reached
    /// [`crate::Cost::MAX`] (about 4.29e9, where fixed-point costs saturate) before it
    /// could trace a path (the status is then [`Status::BudgetExhausted`], without a
    /// path). Only weights can make costs so large ([`crate::weights`], "The range").
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub cost_overflow: bool,
}

/// The most [`SearchEvent`]s a search records ([`Budget::record_events`]): 2^22, 168 MB at
/// 40 bytes each (a test holds the size); a longer search's list stops there, so that
/// recording stays bounded whatever the budget (each expansion of an 8-connected search can
/// add nine).
pub const MAX_SEARCH_EVENTS: usize = 1 << 22;

/// One step of a search ([`Outcome::events`]): a node generated, updated or expanded, with
/// its parent (the node it was reached from; `None` for the start), its cost so far `g`
/// and its evaluation `f`, as the search had them at that step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SearchEvent {
    /// What happened.
    pub kind: SearchEventKind,
    /// The node's cell.
    pub cell: Cell,
    /// The node it was reached from, if any.
    pub parent: Option<Cell>,
    /// Its cost so far.
    pub g: f64,
    /// Its evaluation (`g` plus the heuristic's estimate, weighted as the search weighs it).
    pub f: f64,
}

/// What a [`SearchEvent`] records (the names of Posthoc's search-trace events).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SearchEventKind {
    /// First put in OPEN.
    Generating,
    /// Its `g` lowered while in OPEN (a new parent).
    Updating,
    /// Taken from OPEN and expanded.
    Expanding,
}

impl SearchEventKind {
    /// Posthoc's name of the event: `generating`, `updating` or `expanding`.
    pub fn name(self) -> &'static str {
        match self {
            SearchEventKind::Generating => "generating",
            SearchEventKind::Updating => "updating",
            SearchEventKind::Expanding => "expanding",
        }
    }
}

/// A named sequence of (x, y) points a planner records during one search, for example
/// (iteration, best cost). Points are in the order they were recorded.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Series {
    /// What the sequence is, e.g. `best_fitness`.
    pub name: String,
    /// What x counts, e.g. `iteration`.
    pub x: String,
    /// The points.
    pub points: Vec<[f64; 2]>,
}

impl Series {
    /// An empty series named `name` whose x axis counts `x`.
    pub fn new(name: impl Into<String>, x: impl Into<String>) -> Series {
        Series {
            name: name.into(),
            x: x.into(),
            points: Vec::new(),
        }
    }
}

/// A cell a planner points out in its result, with a short label (a few characters, as
/// figures write it beside the cell).
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct Mark {
    /// The marked cell.
    pub cell: Cell,
    /// Its label, e.g. `H1`.
    pub label: String,
}

impl Mark {
    /// A mark from its parts.
    pub fn new(cell: Cell, label: impl Into<String>) -> Mark {
        Mark {
            cell,
            label: label.into(),
        }
    }
}

impl Outcome {
    /// An outcome from its status, path and counters, without marks or series.
    pub fn new(status: Status, path: Option<Path>, counters: Counters) -> Outcome {
        Outcome {
            status,
            path,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
            expanded: Vec::new(),
            events: Vec::new(),
            memory: None,
            cost_overflow: false,
        }
    }

    /// A found path.
    pub fn found(path: Path, counters: Counters) -> Outcome {
        Outcome {
            status: Status::Found,
            path: Some(path),
            counters,
            marks: Vec::new(),
            series: Vec::new(),
            expanded: Vec::new(),
            events: Vec::new(),
            memory: None,
            cost_overflow: false,
        }
    }

    /// A completed search without a path.
    pub fn no_path(counters: Counters) -> Outcome {
        Outcome {
            status: Status::NoPath,
            path: None,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
            expanded: Vec::new(),
            events: Vec::new(),
            memory: None,
            cost_overflow: false,
        }
    }

    /// A refused search: the planner's per-cell state would not fit the memory budget.
    /// Status [`Status::BudgetExhausted`], no path, and `counters` (usually all zero).
    pub fn over_memory(shortfall: MemoryShortfall, counters: Counters) -> Outcome {
        Outcome {
            memory: Some(shortfall),
            ..Outcome::budget_exhausted(None, counters)
        }
    }

    /// A search that ended when its costs reached [`crate::Cost::MAX`] before it could
    /// trace a path ([`Outcome::cost_overflow`]): status [`Status::BudgetExhausted`], no
    /// path, and `counters`.
    pub fn over_cost_range(counters: Counters) -> Outcome {
        Outcome {
            cost_overflow: true,
            ..Outcome::budget_exhausted(None, counters)
        }
    }

    /// This outcome with `expanded` as its list of expanded cells.
    pub fn with_expanded(self, expanded: Vec<Cell>) -> Outcome {
        Outcome { expanded, ..self }
    }

    /// An exhausted budget, with the best path so far if any.
    pub fn budget_exhausted(path: Option<Path>, counters: Counters) -> Outcome {
        Outcome {
            status: Status::BudgetExhausted,
            path,
            counters,
            marks: Vec::new(),
            series: Vec::new(),
            expanded: Vec::new(),
            events: Vec::new(),
            memory: None,
            cost_overflow: false,
        }
    }
}

/// A start-goal path planner.
///
/// Implementations are built from their own validated config (each planner crate owns a
/// `#[serde(deny_unknown_fields)]` config struct), may keep scratch buffers that they
/// reuse across calls (hence `&mut self`), do no I/O, and return counters that are a pure
/// function of (grid, problem, config, seed) whenever the budget has no wall-clock limit.
///
/// A planner is built once and may serve many queries, on one grid or several: the
/// runner calls [`Planner::prepare`] for a grid before timing queries on it (so per-grid
/// tables are setup, not planning time) and, for a seeded planner, [`Planner::reseed`]
/// before each query.
pub trait Planner: Send + Sync {
    /// The planner's registry name, e.g. `astar`.
    fn name(&self) -> &str;

    /// What the planner is: seeded or not, and the rule its paths obey.
    fn specs(&self) -> PlannerSpecs;

    /// Sets the seed of the next [`Planner::plan`] call. Seeded planners must override
    /// it; the default, for unseeded ones, does nothing.
    fn reseed(&mut self, _seed: u64) {}

    /// Builds whatever per-grid tables the planner keeps (move masks, node arrays), so a
    /// following [`Planner::plan`] on `grid` does not. Optional: `plan` must work without
    /// it. The default does nothing.
    fn prepare(&mut self, _grid: &Grid) {}

    /// The bytes [`Planner::prepare`] allocates for `grid`: what a memory limit must allow
    /// before it is called ([`Planner::prepare_within`]). A planner whose `prepare` builds
    /// per-cell tables must say; the default, for one whose `prepare` builds nothing, is 0.
    fn prepare_bytes(&self, _grid: &Grid) -> u64 {
        0
    }

    /// [`Planner::prepare`] when its tables fit `budget`'s memory limit
    /// ([`Planner::prepare_bytes`]), else nothing: the following [`Planner::plan`] then
    /// refuses by its own check, with nothing allocated beyond the limit. Callers that hold a
    /// budget prepare through this.
    fn prepare_within(&mut self, grid: &Grid, budget: &Budget) {
        if budget.check_memory(self.prepare_bytes(grid), grid).is_ok() {
            self.prepare(grid);
        }
    }

    /// Searches `problem` within `budget`. Never panics on a valid problem.
    ///
    /// Honours every part of the budget: the expansion and time limits through
    /// [`Budget::start`]; the memory limit by checking the per-cell state it is about to
    /// allocate with [`Budget::check_memory`] and returning [`Outcome::over_memory`] when it
    /// does not fit; and, when [`Budget::record_expanded`] is set and the planner supports
    /// it, by listing its expanded cells in [`Outcome::expanded`] (the planner's docs say
    /// whether it does). Recording must not change the search: the counters, status and
    /// path are the same with it on or off.
    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// What `MAX_SEARCH_EVENTS`' docs say a recorded search can take: 40 bytes a step.
    #[test]
    fn a_search_event_takes_40_bytes() {
        assert_eq!(std::mem::size_of::<SearchEvent>(), 40);
        assert_eq!(MAX_SEARCH_EVENTS * 40, 167_772_160);
    }

    #[test]
    fn problem_validation_names_the_cell() {
        let grid = Grid::from_ascii("..\n.#").unwrap();
        let err = Problem::new(&grid, Cell::new(0, 0), Cell::new(1, 1)).unwrap_err();
        assert_eq!(err.to_string(), "goal (1, 1) is blocked");
        let err = Problem::new(&grid, Cell::new(2, 0), Cell::new(0, 1)).unwrap_err();
        assert_eq!(err.to_string(), "start (2, 0) is outside the 2x2 grid");
        assert!(Problem::new(&grid, Cell::new(0, 0), Cell::new(0, 0)).is_ok());
    }

    #[test]
    fn budget_clock() {
        let mut clock = Budget::expansions(3).start();
        assert!(clock.allows(0) && clock.allows(2));
        assert!(!clock.allows(3));
        assert!(clock.is_exhausted());
        assert!(!clock.allows(0));
        let mut unlimited = Budget::unlimited().start();
        assert!(unlimited.allows(u64::MAX - 1));
        let mut timed = Budget::unlimited().with_time(Duration::ZERO).start();
        let allowed = (0..2 * BudgetClock::TIME_CHECK_INTERVAL as u64)
            .take_while(|&n| timed.allows(n))
            .count();
        assert_eq!(allowed, BudgetClock::TIME_CHECK_INTERVAL as usize - 1);
        assert!(!timed.allows_uncounted());
        // Uncounted work ignores the expansion limit but not the clock, and shares its
        // countdown with the expansions.
        let mut counted = Budget::expansions(0).start();
        assert!(counted.allows_uncounted());
        let mut timed = Budget::expansions(0).with_time(Duration::ZERO).start();
        let uncounted = (0..2 * BudgetClock::TIME_CHECK_INTERVAL)
            .take_while(|_| timed.allows_uncounted())
            .count();
        assert_eq!(uncounted, BudgetClock::TIME_CHECK_INTERVAL as usize - 1);
        assert!(timed.is_exhausted() && !timed.allows(0));
    }

    #[test]
    fn budget_toml_shape() {
        let budget: Budget =
            serde_json::from_str(r#"{"max_expansions": 5, "max_time_ms": 20}"#).unwrap();
        assert_eq!(
            budget,
            Budget::expansions(5).with_time(Duration::from_millis(20))
        );
        assert!(serde_json::from_str::<Budget>(r#"{"max_steps": 5}"#).is_err());
    }
}
