//! Search traces in Posthoc's format (ShortestPathLab's search-trace visualiser), written
//! by `gridplan plan --trace FILE`.
//!
//! The layout is that of Posthoc's version 1.4.0 traces (its `parser-v140`, and the
//! `resources/traces/v1.4.0/astar.trace.yaml` example of posthoc-app): an object with
//! `version: "1.4.0"`, `views` (how an event is drawn: here one unit `rect` at the event's
//! `x`, `y`, coloured by its `type`), `pivot` (where the view centres on an event) and
//! `events`, in order:
//!
//! - one `source` event (the start) and one `destination` event (the goal);
//! - for a planner that records its search step by step ([`planner_api::Outcome::events`]:
//!   A\*, whatever its heuristic, Dijkstra included, bidirectional A\*, Theta\*, Lazy
//!   Theta\*, JPS and weighted JPS), one event per step in order:
//!   `generating` (a node first put in OPEN), `updating` (its `g` lowered while in OPEN)
//!   and `expanding`, each with the node's `pId` (its parent's id, absent for the start),
//!   `g` and `f` as the search had them; at most [`planner_api::MAX_SEARCH_EVENTS`] of
//!   them;
//! - for the other planners, one `expanding` event per expanded cell, in expansion order,
//!   from the planner's [`planner_api::Outcome::expanded`] list (so there are `n_expanded`
//!   of them for BFS, DFS and the others whose docs say the list has one cell per
//!   expansion), without `pId`, `g` or `f`, which they do not record; none for a planner
//!   that lists no cells (backtracking, the RRT family, LPA\*, D\* Lite, PA-star, CAPSO);
//! - one `end` event at the goal when a path was found.
//!
//! Every event has `type`, `id` (the cell's row-major index, `y * width + x`, so a cell
//! has one id throughout) and `x`, `y`: what it shows is exactly what the search
//! recorded. The file is JSON, which Posthoc reads as it reads YAML (a `.trace.json` or
//! `.trace.yaml` name both load).

use planner_api::Cell;
use serde::Serialize;

/// The Posthoc trace format version written.
pub const VERSION: &str = "1.4.0";

/// One event.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Event {
    /// `source`, `destination`, `generating`, `updating`, `expanding` or `end`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// The cell's row-major index.
    pub id: u64,
    /// The parent's id, where the search recorded one.
    #[serde(rename = "pId", skip_serializing_if = "Option::is_none")]
    pub parent: Option<u64>,
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
    /// The node's cost so far, where recorded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g: Option<f64>,
    /// Its evaluation, where recorded.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub f: Option<f64>,
}

/// A whole trace.
#[derive(Debug, Clone, Serialize)]
pub struct Trace {
    /// [`VERSION`].
    pub version: &'static str,
    /// How events are drawn.
    pub views: serde_json::Value,
    /// Where the view centres on an event.
    pub pivot: serde_json::Value,
    /// The events in order.
    pub events: Vec<Event>,
}

/// The trace of one search on a grid `width` cells wide: start, goal, the expanded cells
/// in order, and whether a path was found.
///
/// ```
/// use planner_api::Cell;
/// let expanded = [Cell::new(0, 0), Cell::new(1, 0)];
/// let trace = planner_serve::trace::trace(10, Cell::new(0, 0), Cell::new(2, 0), &expanded, true);
/// let kinds: Vec<&str> = trace.events.iter().map(|e| e.kind).collect();
/// assert_eq!(kinds, ["source", "destination", "expanding", "expanding", "end"]);
/// assert_eq!(trace.events[1].id, 2);
/// ```
pub fn trace(width: u32, start: Cell, goal: Cell, expanded: &[Cell], found: bool) -> Trace {
    let steps = expanded.iter().map(|&cell| event(width, "expanding", cell));
    with_ends(width, start, goal, steps, found)
}

/// The trace of one search that recorded its steps (`events`, [`planner_api::Outcome::events`]):
/// start, goal, each step with its parent, `g` and `f`, and whether a path was found.
///
/// ```
/// use planner_api::{Cell, SearchEvent, SearchEventKind};
/// let step = |kind, x, parent: Option<(u32, u32)>, g: f64| SearchEvent {
///     kind,
///     cell: Cell::new(x, 0),
///     parent: parent.map(|(x, y)| Cell::new(x, y)),
///     g,
///     f: 2.0,
/// };
/// let events = [
///     step(SearchEventKind::Generating, 0, None, 0.0),
///     step(SearchEventKind::Expanding, 0, None, 0.0),
///     step(SearchEventKind::Generating, 1, Some((0, 0)), 1.0),
/// ];
/// let trace = planner_serve::trace::trace_of_steps(10, Cell::new(0, 0), Cell::new(2, 0), &events, false);
/// let text = serde_json::to_string(&trace.events[4]).unwrap();
/// assert_eq!(text, r#"{"type":"generating","id":1,"pId":0,"x":1,"y":0,"g":1.0,"f":2.0}"#);
/// ```
pub fn trace_of_steps(
    width: u32,
    start: Cell,
    goal: Cell,
    events: &[planner_api::SearchEvent],
    found: bool,
) -> Trace {
    let steps = events.iter().map(|step| Event {
        parent: step.parent.map(|p| id(width, p)),
        g: Some(step.g),
        f: Some(step.f),
        ..event(width, step.kind.name(), step.cell)
    });
    with_ends(width, start, goal, steps, found)
}

/// A cell's id: its row-major index (also the page's cell index, `server`'s answers).
pub(crate) fn id(width: u32, cell: Cell) -> u64 {
    u64::from(cell.y) * u64::from(width) + u64::from(cell.x)
}

/// An event of `kind` at `cell`, without parent, `g` or `f`.
fn event(width: u32, kind: &'static str, cell: Cell) -> Event {
    Event {
        kind,
        id: id(width, cell),
        parent: None,
        x: cell.x,
        y: cell.y,
        g: None,
        f: None,
    }
}

/// `source`, `destination`, the `steps`, and `end` when `found`, with the views.
fn with_ends(
    width: u32,
    start: Cell,
    goal: Cell,
    steps: impl ExactSizeIterator<Item = Event>,
    found: bool,
) -> Trace {
    let mut events = Vec::with_capacity(steps.len() + 3);
    events.push(event(width, "source", start));
    events.push(event(width, "destination", goal));
    events.extend(steps);
    if found {
        events.push(event(width, "end", goal));
    }
    Trace {
        version: VERSION,
        views: serde_json::json!({
            "main": [{
                "$": "rect",
                "width": 1,
                "height": 1,
                "x": "${{ $.x }}",
                "y": "${{ $.y }}",
                "fill": "${{ color[$.type] }}",
            }]
        }),
        pivot: serde_json::json!({ "x": "${{ $.x + 0.5 }}", "y": "${{ $.y + 0.5 }}", "scale": 1 }),
        events,
    }
}

/// The trace of a `plan` run as JSON text (`plan --trace FILE`): the run needs its expanded
/// cells recorded ([`planner_runner::plan::PlanOptions::record_expanded`]), and its steps
/// for `generating` events, parents, `g` and `f`
/// ([`planner_runner::plan::PlanOptions::record_events`]) where the planner records them.
pub fn plan_trace_json(
    result: &planner_runner::plan::PlanResult,
) -> Result<String, serde_json::Error> {
    let r = &result.record;
    let found = r.status == planner_runner::record::RunStatus::Found;
    let width = result.grid.width();
    let trace = match result.events.is_empty() {
        true => trace(width, r.start, r.goal, &result.expanded, found),
        false => trace_of_steps(width, r.start, r.goal, &result.events, found),
    };
    serde_json::to_string(&trace)
}
