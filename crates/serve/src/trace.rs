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
//! - one `expanding` event per expanded cell, in expansion order, from the planner's
//!   [`planner_api::Outcome::expanded`] list (so there are `n_expanded` of them for A*,
//!   BFS, DFS and the others whose docs say the list has one cell per expansion);
//! - one `end` event at the goal when a path was found.
//!
//! Every event has `type`, `id` (the cell's row-major index, `y * width + x`, so a cell
//! has one id throughout) and `x`, `y`. The planners record expanded cells only, not g,
//! f, parents or generated cells, so the trace has no `g`, `f`, `pId` or `generating`
//! events: what it shows is exactly what the search recorded. The file is JSON, which
//! Posthoc reads as it reads YAML (a `.trace.json` or `.trace.yaml` name both load).

use planner_api::Cell;
use serde::Serialize;

/// The Posthoc trace format version written.
pub const VERSION: &str = "1.4.0";

/// One event.
#[derive(Debug, Clone, Serialize, PartialEq, Eq)]
pub struct Event {
    /// `source`, `destination`, `expanding` or `end`.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// The cell's row-major index.
    pub id: u64,
    /// Column.
    pub x: u32,
    /// Row.
    pub y: u32,
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
    let event = |kind, cell: Cell| Event {
        kind,
        id: u64::from(cell.y) * u64::from(width) + u64::from(cell.x),
        x: cell.x,
        y: cell.y,
    };
    let mut events = Vec::with_capacity(expanded.len() + 3);
    events.push(event("source", start));
    events.push(event("destination", goal));
    events.extend(expanded.iter().map(|&cell| event("expanding", cell)));
    if found {
        events.push(event("end", goal));
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
/// cells recorded ([`planner_runner::plan::PlanOptions::record_expanded`]).
pub fn plan_trace_json(
    result: &planner_runner::plan::PlanResult,
) -> Result<String, serde_json::Error> {
    let r = &result.record;
    let found = r.status == planner_runner::record::RunStatus::Found;
    let trace = trace(
        result.grid.width(),
        r.start,
        r.goal,
        &result.expanded,
        found,
    );
    serde_json::to_string(&trace)
}
