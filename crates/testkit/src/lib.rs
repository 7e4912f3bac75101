//! Test and benchmark fixtures: the repository's maps under `maps/`, read with
//! planner-maps, for the tests and benches of every crate (dev-dependency only).
//!
//! Every function panics with the file's name on a missing or malformed file: fixtures are
//! part of the repository, so that is a broken checkout, not user input.
//!
//! It also holds the independent methods the snapshots' numbers are checked against: the
//! exact weighted oracle ([`weighted_dijkstra`]) and a `reference_*` search per planner
//! ([`reference_astar`], [`reference_jps`], [`reference_weighted_jps`],
//! [`reference_theta_star`], [`reference_bidirectional_astar`], [`reference_lpa`] and
//! [`ReferenceIncremental`] (LPA\* and D\* Lite through changes and moves),
//! [`reference_lexastar`], [`reference_frontier`], [`reference_coverage`],
//! [`reference_rrt`], [`reference_rrt_connect`], [`reference_rrt_star`],
//! [`reference_capso_guide`] (CAPSO's guide)), each the planner's
//! documented search written again plainly and sharing no code with it.
#![deny(missing_docs)]

use std::collections::HashMap;
use std::path::PathBuf;

mod bidirectional;
mod capso;
mod coverage;
mod frontier;
mod jps;
mod lex;
mod lpa;
mod rrt;
mod theta;
mod weighted_jps;
pub use bidirectional::{reference_bidirectional_astar, BidirectionalSearch};
pub use capso::{reference_capso_guide, CapsoGuideSearch};
pub use coverage::{reference_coverage, Fill, COVERAGE_COUNTERS};
pub use frontier::{reference_frontier, FrontierSearch, FRONTIER_COUNTERS};
pub use jps::{reference_jps, JpsSearch, JpsVariant, JPS_COUNTERS};
pub use lex::{reference_lexastar, LexSearch, LEXASTAR_COUNTERS};
pub use lpa::{reference_lpa, LpaSearch, ReferenceIncremental, LPA_COUNTERS};
pub use rrt::{
    reference_rrt, reference_rrt_connect, reference_rrt_star, RrtSearch, RrtSettings,
    RrtStarSearch, RRT_CONNECT_COUNTERS, RRT_COUNTERS,
};
pub use theta::{reference_theta_star, ThetaSearch, THETA_COUNTERS};
pub use weighted_jps::{reference_weighted_jps, WeightedJpsSearch, WEIGHTED_JPS_COUNTERS};

use planner_api::{Cell, Grid};
use planner_maps::Scenario;

/// `maps/` at the repository root.
pub fn maps_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps")
}

/// Writes a trinary ROS `map_server` map `STEM.yaml` with its image `STEM.pgm` into `dir`
/// (1 m cells, origin at 0): `rows` top first, `#` occupied (0 in the image), `?` unknown
/// (205), anything else free (254). Returns the YAML's path.
pub fn write_ros_map(dir: &std::path::Path, stem: &str, rows: &[&str]) -> PathBuf {
    let width = rows.first().map_or(0, |row| row.len());
    let mut pgm = format!("P5\n{width} {}\n255\n", rows.len()).into_bytes();
    for row in rows {
        pgm.extend(row.bytes().map(|c| match c {
            b'#' => 0u8,
            b'?' => 205,
            _ => 254,
        }));
    }
    std::fs::write(dir.join(format!("{stem}.pgm")), pgm).expect("the image is written");
    let yaml = dir.join(format!("{stem}.yaml"));
    std::fs::write(
        &yaml,
        format!(
            "image: {stem}.pgm\nresolution: 1.0\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n\
             occupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n"
        ),
    )
    .expect("the YAML is written");
    yaml
}

/// Any map file under `maps/`, by relative path (`paper/map01.map`, `wpi/map1.txt`).
pub fn map_file(relative: &str) -> planner_maps::MapFile {
    planner_maps::read_map(&maps_dir().join(relative)).unwrap_or_else(|e| panic!("{e}"))
}

/// A Moving AI map's grid by relative path (`movingai/arena.map`).
pub fn movingai(relative: &str) -> Grid {
    map_file(relative).grid
}

/// A seed 003 map (`wpi/map1.txt`) with its start-goal pairs in file order.
pub fn wpi(relative: &str) -> (Grid, Vec<(Cell, Cell)>) {
    let file = map_file(relative);
    let pairs = file.problems.iter().map(|p| (p.start, p.goal)).collect();
    (file.grid, pairs)
}

/// The scenarios of a `.scen` file by relative path (`movingai/den520d.map.scen`).
pub fn scenarios(relative: &str) -> Vec<Scenario> {
    planner_maps::read_scenarios(&maps_dir().join(relative)).unwrap_or_else(|e| panic!("{e}"))
}

/// Start and goal of a `.scen` file's first scenario.
pub fn first_scenario(relative: &str) -> (Cell, Cell) {
    let first = scenarios(relative)
        .into_iter()
        .next()
        .unwrap_or_else(|| panic!("{relative} has no scenario"));
    (first.start, first.goal)
}

/// Seed 000's twelve maps as (`mapNN`, grid); each is solved from (0,0) to (N-1,N-1).
pub fn paper_maps() -> Vec<(String, Grid)> {
    (1..=12)
        .map(|i| {
            let name = format!("map{i:02}");
            let grid = movingai(&format!("paper/{name}.map"));
            (name, grid)
        })
        .collect()
}

/// `maps/paper/published.toml`: seed 000's Tables 3-8 as `[mapNN.planner] metric = value`.
pub fn published() -> toml::Table {
    let path = maps_dir().join("paper/published.toml");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.parse()
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// File names of the Moving AI maps in `maps/movingai/`, sorted.
pub fn movingai_maps() -> Vec<String> {
    let dir = maps_dir().join("movingai");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".map"))
        .collect();
    names.sort();
    names
}

/// Checks a search's recorded steps (planner-api's `Outcome::events`) against its counters
/// `(n_open_insertions, n_relaxations, n_expanded)`: one `generating` step per insertion into
/// OPEN, one `updating` step per relaxation beyond the `ends` insertions that relax nothing
/// (the start's; a bidirectional search's two ends), and the `expanding` steps' cells are
/// `expanded`, one per expansion. `what` names the case in a failure.
pub fn check_step_counts(
    what: &str,
    events: &[planner_api::SearchEvent],
    expanded: &[Cell],
    (n_open_insertions, n_relaxations, n_expanded): (u64, u64, u64),
    ends: u64,
) {
    use planner_api::SearchEventKind;
    let count = |kind| events.iter().filter(|e| e.kind == kind).count() as u64;
    assert_eq!(
        count(SearchEventKind::Generating),
        n_open_insertions,
        "{what}"
    );
    assert_eq!(
        count(SearchEventKind::Updating),
        n_relaxations + ends - n_open_insertions,
        "{what}"
    );
    let expanding: Vec<Cell> = events
        .iter()
        .filter(|e| e.kind == SearchEventKind::Expanding)
        .map(|e| e.cell)
        .collect();
    assert_eq!(expanding, expanded, "{what}");
    assert_eq!(expanding.len() as u64, n_expanded, "{what}");
}

/// Plans `problem` with `planner` twice, plainly and recording its expanded cells and
/// steps; checks that the plain run recorded nothing, that recording changed neither the
/// counters, the path nor the status, and the steps' counts against the counters
/// ([`check_step_counts`], with `ends` insertions that relax nothing); returns the
/// recorded outcome. `what` names the case in a failure.
pub fn plan_recorded(
    what: &str,
    planner: &mut dyn planner_api::Planner,
    problem: &planner_api::Problem<'_>,
    ends: u64,
) -> planner_api::Outcome {
    use planner_api::Budget;
    let plain = planner.plan(problem, &Budget::unlimited());
    assert!(
        plain.events.is_empty() && plain.expanded.is_empty(),
        "{what}"
    );
    let budget = Budget::unlimited()
        .recording_expanded(true)
        .recording_events(true);
    let recorded = planner.plan(problem, &budget);
    assert_eq!(
        (&recorded.counters, &recorded.path, recorded.status),
        (&plain.counters, &plain.path, plain.status),
        "{what}: recording changed the search"
    );
    let counter = |name| {
        recorded
            .counters
            .get(name)
            .unwrap_or_else(|| panic!("{what}: no {name}"))
    };
    let counts = (
        counter("n_open_insertions"),
        counter("n_relaxations"),
        counter("n_expanded"),
    );
    check_step_counts(what, &recorded.events, &recorded.expanded, counts, ends);
    recorded
}

/// What [`check_step_order`] read from a search's steps.
#[derive(Debug, Default)]
pub struct StepOrder {
    /// Per cell, the `g` and parent of its last push.
    pub last: HashMap<Cell, (f64, Option<Cell>)>,
    /// Per expanded cell, its parent when it was (last) expanded.
    pub parents: HashMap<Cell, Option<Cell>>,
    /// The `updating` steps.
    pub updates: usize,
}

/// Checks the order of a best-first search's recorded steps: every push (`generating`,
/// `updating`) comes from the node being expanded, which is its parent (the first push,
/// the start's, has none); a cell's first push is `generating` and a later one `updating`,
/// with a lower `g`; a node expands with the `g` and parent of its last push. `extra` is
/// called on each step with what was read before it. Returns what was read.
pub fn check_step_order(
    what: &str,
    events: &[planner_api::SearchEvent],
    mut extra: impl FnMut(&planner_api::SearchEvent, &StepOrder),
) -> StepOrder {
    use planner_api::SearchEventKind::{Expanding, Generating, Updating};
    let mut order = StepOrder::default();
    let mut expanding: Option<Cell> = None;
    for e in events {
        extra(e, &order);
        match e.kind {
            Generating | Updating => {
                assert_eq!(e.parent, expanding, "{what}: {e:?}");
                let known = order.last.get(&e.cell).map(|&(g, _)| g);
                assert_eq!(known.is_some(), e.kind == Updating, "{what}: {e:?}");
                if let Some(g) = known {
                    assert!(e.g < g, "{what}: an update that does not lower g: {e:?}");
                    order.updates += 1;
                }
                order.last.insert(e.cell, (e.g, e.parent));
            }
            Expanding => {
                assert_eq!(
                    order.last.get(&e.cell),
                    Some(&(e.g, e.parent)),
                    "{what}: {e:?}"
                );
                order.parents.insert(e.cell, e.parent);
                expanding = Some(e.cell);
            }
        }
    }
    order
}

/// Asserts the counter identities of a BFS or DFS run with `k` moves per cell (see the
/// planner-bfs crate docs); `what` names the run in failure messages.
pub fn check_frontier_identities(what: &str, outcome: &planner_api::Outcome, k: u64) {
    use planner_api::Status;
    let c = &outcome.counters;
    let get = |name: &str| c.get(name).unwrap_or_else(|| panic!("{what}: no {name}"));
    let (exp, checks, blocked, skipped) = (
        get("n_expanded"),
        get("n_neighbor_checks"),
        get("n_blocked"),
        get("n_skipped"),
    );
    let (peak, inserted) = (get("peak_open"), get("n_open_insertions"));
    assert_eq!(
        checks,
        blocked + skipped + (inserted - 1),
        "{what}: checks = blk + skp + ins - 1; {c}"
    );
    assert!(
        peak >= 1 && peak <= inserted,
        "{what}: 1 <= peak_open <= insertions; {c}"
    );
    match outcome.status {
        Status::Found => assert_eq!(checks, k * (exp - 1), "{what}: checks = k (exp - 1); {c}"),
        Status::NoPath => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert_eq!(inserted, exp, "{what}: every inserted cell expanded; {c}");
        }
        Status::BudgetExhausted => {
            assert_eq!(checks, k * exp, "{what}: checks = k exp; {c}");
            assert!(inserted > exp, "{what}: cells left in the frontier; {c}");
        }
    }
}

/// An independent fewest-moves search: plain breadth-first search over
/// [`planner_api::MoveSet::apply`] with a queue and a distance table. The number of moves
/// of a shortest path from `start` to `goal`, or `None` when there is none.
pub fn fewest_moves(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    start: Cell,
    goal: Cell,
) -> Option<u64> {
    let mut dist = vec![u64::MAX; grid.len()];
    let mut queue = std::collections::VecDeque::from([start]);
    dist[grid.index(start)] = 0;
    while let Some(cell) = queue.pop_front() {
        let d = dist[grid.index(cell)];
        if cell == goal {
            return Some(d);
        }
        for mv in moves.moves() {
            if let Some(next) = moves.apply(grid, cell, mv) {
                if dist[grid.index(next)] == u64::MAX {
                    dist[grid.index(next)] = d + 1;
                    queue.push_back(next);
                }
            }
        }
    }
    None
}

/// Marsaglia's xorshift64 sequence (shifts 13, 7, 17) from `seed` (nonzero): each call
/// returns the next state. The seeded generator of the randomised tests.
pub fn xorshift(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    }
}

/// `rounds` small random problems, deterministic in `seed` (a xorshift generator): sides
/// from 2 to 10 cells, about 30% of cells blocked, then start and goal (drawn uniformly,
/// possibly equal) made free. Many have no path, which is the point for searches that
/// must tell.
pub fn small_random_problems(seed: u64, rounds: usize) -> Vec<(Grid, Cell, Cell)> {
    let mut next = xorshift(seed);
    (0..rounds)
        .map(|_| {
            let (w, h) = (2 + (next() % 9) as u32, 2 + (next() % 9) as u32);
            let free: Vec<bool> = (0..w * h).map(|_| next() % 100 >= 30).collect();
            with_start_and_goal(random_grid(w, h, free), &mut next)
        })
        .collect()
}

/// `rounds` random problems, deterministic in `seed` (xorshift): sides drawn from
/// `sides.0 ..= sides.1` cells, each grid's share of blocked cells drawn from
/// `blocked.0 ..= blocked.1` per 10,000 and each cell blocked with that chance, then start
/// and goal drawn uniformly (possibly equal) and made free. For the reference tests on
/// grids larger than [`small_random_problems`]'.
pub fn random_problems(
    seed: u64,
    rounds: usize,
    sides: (u32, u32),
    blocked: (u64, u64),
) -> Vec<(Grid, Cell, Cell)> {
    let mut next = xorshift(seed | 1);
    (0..rounds)
        .map(|_| {
            let span = u64::from(sides.1 - sides.0) + 1;
            let (w, h) = (
                sides.0 + (next() % span) as u32,
                sides.0 + (next() % span) as u32,
            );
            let density = blocked.0 + next() % (blocked.1 - blocked.0 + 1);
            let free: Vec<bool> = (0..w * h).map(|_| next() % 10_000 >= density).collect();
            with_start_and_goal(random_grid(w, h, free), &mut next)
        })
        .collect()
}

/// `grid` with a start and a goal drawn uniformly by `next` (x, then y, start first;
/// possibly equal) and made free: the end of every random problem of this kit.
fn with_start_and_goal(mut grid: Grid, next: &mut impl FnMut() -> u64) -> (Grid, Cell, Cell) {
    let (w, h) = (u64::from(grid.width()), u64::from(grid.height()));
    let mut cell = || Cell::new((next() % w) as u32, (next() % h) as u32);
    let (start, goal) = (cell(), cell());
    grid.set_free(start, true);
    grid.set_free(goal, true);
    (grid, start, goal)
}

/// The `w` x `h` grid of `free` cells (a random problem's: the sizes are valid).
fn random_grid(w: u32, h: u32, free: Vec<bool>) -> Grid {
    Grid::from_free_cells(w, h, free).unwrap_or_else(|e| panic!("a {w}x{h} grid: {e}"))
}

/// `rounds` of [`small_random_problems`] followed by every pair of seed 003's maps that
/// makes a problem (`maps/wpi/map1-3.txt`), for the frontier searches' reference tests.
pub fn small_and_wpi_problems(seed: u64, rounds: usize) -> Vec<(Grid, Cell, Cell)> {
    let mut problems = small_random_problems(seed, rounds);
    for file in ["wpi/map1.txt", "wpi/map2.txt", "wpi/map3.txt"] {
        let (grid, pairs) = wpi(file);
        for (s, g) in pairs {
            if planner_api::Problem::new(&grid, s, g).is_ok() {
                problems.push((grid.clone(), s, g));
            }
        }
    }
    problems
}

/// How many obstacles the segment between the centres of `a` and `b` crosses: the
/// 8-connected components of blocked cells (cells touching at a corner are one obstacle)
/// that hold a cell of planner-api's exact traversal of the segment. PA-star's
/// `n_obstacles_crossed`, computed here by a flood fill from the crossed cells.
pub fn obstacles_crossed(grid: &Grid, a: Cell, b: Cell) -> u64 {
    let mut crossed = Vec::new();
    planner_api::for_each_segment_cell(a, b, |c| {
        if grid.contains(c) && !grid.is_free(c) {
            crossed.push(c);
        }
        true
    });
    let mut component = vec![usize::MAX; grid.len()];
    let mut n = 0;
    for &c in &crossed {
        if component[grid.index(c)] != usize::MAX {
            continue;
        }
        component[grid.index(c)] = n;
        let mut stack = vec![c];
        while let Some(p) = stack.pop() {
            for (dx, dy) in [
                (-1, -1),
                (0, -1),
                (1, -1),
                (-1, 0),
                (1, 0),
                (-1, 1),
                (0, 1),
                (1, 1),
            ] {
                let Some(q) = p.checked_offset(dx, dy).filter(|&q| grid.contains(q)) else {
                    continue;
                };
                if !grid.is_free(q) && component[grid.index(q)] == usize::MAX {
                    component[grid.index(q)] = n;
                    stack.push(q);
                }
            }
        }
        n += 1;
    }
    n as u64
}

/// The cells of the path through `chain`'s jump points (at least one), each leg diagonal
/// first, then straight: how JPS and weighted JPS lay a path between jump points, written
/// here for their reference tests rather than taken from planner-api.
pub fn cells_through(chain: &[Cell]) -> Vec<Cell> {
    let mut cells = vec![chain[0]];
    for leg in chain.windows(2) {
        let (mut x, mut y) = (i64::from(leg[0].x), i64::from(leg[0].y));
        let (tx, ty) = (i64::from(leg[1].x), i64::from(leg[1].y));
        while (x, y) != (tx, ty) {
            let diagonal = x != tx && y != ty;
            if diagonal || x != tx {
                x += (tx - x).signum();
            }
            if diagonal || y != ty {
                y += (ty - y).signum();
            }
            cells.push(Cell::new(x as u32, y as u32));
        }
    }
    cells
}

/// The cells from `start` to `goal` along `parent` links (indices by [`Grid::index`]),
/// the way the reference searches read their paths back. Precondition: the links lead
/// from `goal` to `start`.
pub fn path_from_parents(grid: &Grid, parent: &[usize], start: Cell, goal: Cell) -> Vec<Cell> {
    let (s, mut node) = (grid.index(start), grid.index(goal));
    let mut cells = vec![goal];
    while node != s {
        node = parent[node];
        cells.push(grid.cell(node));
    }
    cells.reverse();
    cells
}

/// The counters of a BFS or DFS run that hand counts give, in the order `n_expanded`,
/// `n_neighbor_checks`, `n_blocked`, `n_skipped`, `peak_open`, `n_open_insertions`.
pub fn frontier_counters(outcome: &planner_api::Outcome) -> [u64; 6] {
    [
        "n_expanded",
        "n_neighbor_checks",
        "n_blocked",
        "n_skipped",
        "peak_open",
        "n_open_insertions",
    ]
    .map(|name| {
        outcome
            .counters
            .get(name)
            .unwrap_or_else(|| panic!("no {name} in {}", outcome.counters))
    })
}

/// Tie rules of [`reference_astar`], as planner-astar's `TieBreak` defines them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tie {
    /// The entry pushed first among equal `f`.
    Fifo,
    /// The entry pushed last among equal `f`.
    Lifo,
    /// Lower `g` first, then FIFO.
    LowG,
    /// Higher `g` first, then FIFO.
    HighG,
}

/// Asserts that a planner's `outcome` is a reference search's: its status, its path's
/// cells, and the counters `names` with the reference's `values` (each present in the
/// outcome); `what` names the case in a failure.
pub fn assert_reference_outcome<const N: usize>(
    outcome: &planner_api::Outcome,
    reference: (planner_api::Status, Option<Vec<Cell>>),
    names: [&str; N],
    values: [u64; N],
    what: &str,
) {
    assert_eq!(outcome.status, reference.0, "{what}");
    let actual = names.map(|name| {
        outcome
            .counters
            .get(name)
            .unwrap_or_else(|| panic!("{what}: no counter {name}"))
    });
    assert_eq!(actual, values, "{what}");
    let path = outcome.path.as_ref().map(|p| p.cells().to_vec());
    assert_eq!(path, reference.1, "{what}");
}

/// What [`reference_astar`] found: status, path cells, and the counters named in
/// [`REFERENCE_COUNTERS`], in that order.
pub type ReferenceSearch = (planner_api::Status, Option<Vec<Cell>>, [u64; 7]);

/// The counters of a [`ReferenceSearch`], in its order (peak OPEN last).
pub const REFERENCE_COUNTERS: [&str; 7] = [
    "n_expanded",
    "n_neighbor_checks",
    "n_blocked",
    "n_skipped",
    "n_open_insertions",
    "n_relaxations",
    "peak_open",
];

/// A* as seed 000's Fig. 4 reads, written for clarity and not speed: std's `BinaryHeap`
/// with lazy deletion and the full key `(f, tie, push sequence)`, per-cell tables the size
/// of the grid, moves through [`planner_api::MoveSet::apply`]. Costs are exact
/// [`planner_api::Cost`]s ([`planner_api::Move::exact_cost`] per move, or on a weighted
/// grid [`Grid::move_cost`], the move's cost under the grid's rule), so equal path
/// costs tie exactly; `h` is the weighted heuristic of a cell (`f = g + h`).
/// planner-astar must agree with it on every path and counter; its OPEN lists are nothing
/// like this one.
pub fn reference_astar(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    h: impl Fn(Cell) -> planner_api::Cost,
    tie: Tie,
    start: Cell,
    goal: Cell,
) -> ReferenceSearch {
    use planner_api::Cost;
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    // The tie value is g (low g first) or its negation (high g first); LIFO negates the
    // sequence.
    let key = |f: Cost, g: Cost, seq: u64| {
        let g = i128::from(g.units());
        let (tie, seq) = match tie {
            Tie::Fifo => (0, i128::from(seq)),
            Tie::Lifo => (0, -i128::from(seq)),
            Tie::LowG => (g, i128::from(seq)),
            Tie::HighG => (-g, i128::from(seq)),
        };
        (f, tie, seq)
    };
    let n = grid.len();
    let mut g = vec![Cost::MAX; n];
    let mut parent = vec![usize::MAX; n];
    let mut in_open = vec![false; n];
    let mut closed = vec![false; n];
    let mut heap = BinaryHeap::new();
    let [mut exp, mut checks, mut blocked, mut skipped, mut ins, mut rel] = [0u64; 6];
    let (s, t) = (grid.index(start), grid.index(goal));
    g[s] = Cost::ZERO;
    in_open[s] = true;
    heap.push(Reverse((key(h(start), Cost::ZERO, 0), s)));
    let mut seq = 1u64;
    ins += 1;
    let (mut n_open, mut peak) = (1u64, 1u64);
    while let Some(Reverse((_, p))) = heap.pop() {
        if closed[p] {
            continue;
        }
        closed[p] = true;
        in_open[p] = false;
        n_open -= 1;
        exp += 1;
        if p == t {
            let cells = path_from_parents(grid, &parent, start, goal);
            let counters = [exp, checks, blocked, skipped, ins, rel, peak];
            return (planner_api::Status::Found, Some(cells), counters);
        }
        let from = grid.cell(p);
        for mv in moves.moves() {
            checks += 1;
            let Some(to) = moves.apply(grid, from, mv) else {
                blocked += 1;
                continue;
            };
            let q = grid.index(to);
            if closed[q] {
                skipped += 1;
                continue;
            }
            // On a weighted grid the move's cost under the grid's rule (planner-api's
            // definition), else its exact length.
            let step = match grid.is_weighted() {
                true => grid.move_cost(from, to),
                false => mv.exact_cost(),
            };
            let g_new = g[p] + step;
            if !in_open[q] || g_new < g[q] {
                rel += 1;
                if !in_open[q] {
                    ins += 1;
                    n_open += 1;
                    peak = peak.max(n_open);
                }
                in_open[q] = true;
                g[q] = g_new;
                parent[q] = p;
                heap.push(Reverse((key(g_new + h(to), g_new, seq), q)));
                seq += 1;
            }
        }
    }
    let counters = [exp, checks, blocked, skipped, ins, rel, peak];
    (planner_api::Status::NoPath, None, counters)
}

/// An independent search for seed 000's best path by (D, T): plain Dijkstra over states
/// (cell, direction of the last move), where a move costs one step plus one turn when its
/// direction differs from the last (the first move never turns), with pair costs compared
/// lexicographically. Returns `(D, T)` of a best path, or `None` when there is none. Score
/// is `D + T` for such a path, so this also fixes the best Score.
pub fn fewest_moves_then_turns(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    start: Cell,
    goal: Cell,
) -> Option<(u64, u64)> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    // State `cell * slots + heading`; heading `n` (one past the moves) is "no move yet".
    let n = moves.moves().len();
    let slots = n + 1;
    let mut best = vec![(u64::MAX, u64::MAX); grid.len() * slots];
    let mut heap = BinaryHeap::new();
    let first = grid.index(start) * slots + n;
    best[first] = (0, 0);
    heap.push(Reverse(((0u64, 0u64), first)));
    while let Some(Reverse((cost, state))) = heap.pop() {
        if cost > best[state] {
            continue;
        }
        let (cell, heading) = (grid.cell(state / slots), state % slots);
        if cell == goal {
            return Some(cost);
        }
        for (direction, mv) in moves.moves().iter().enumerate() {
            let Some(next) = moves.apply(grid, cell, mv) else {
                continue;
            };
            let turn = u64::from(heading != n && heading != direction);
            let next_cost = (cost.0 + 1, cost.1 + turn);
            let next_state = grid.index(next) * slots + direction;
            if next_cost < best[next_state] {
                best[next_state] = next_cost;
                heap.push(Reverse((next_cost, next_state)));
            }
        }
    }
    None
}

/// Runs `planner` on `problem` without a budget, then again within half the expansions
/// that took, and checks the cut run: budget exhausted after exactly that many expansions,
/// and the BFS/DFS counter identities with `k` moves per cell
/// ([`check_frontier_identities`]). Returns the full run's outcome.
pub fn check_budget_cut(
    planner: &mut dyn planner_api::Planner,
    problem: &planner_api::Problem<'_>,
    what: &str,
    k: u64,
) -> planner_api::Outcome {
    use planner_api::{Budget, Status};
    let full = planner.plan(problem, &Budget::unlimited());
    check_frontier_identities(what, &full, k);
    let cut = full.counters.get("n_expanded").unwrap_or(0) / 2;
    if cut > 0 {
        let outcome = planner.plan(problem, &Budget::expansions(cut));
        assert_eq!(outcome.status, Status::BudgetExhausted, "{what}");
        assert_eq!(outcome.counters.get("n_expanded"), Some(cut), "{what}");
        check_frontier_identities(&format!("{what} cut"), &outcome, k);
    }
    full
}

/// An outcome as hand-checked tests write it: `status <s>`, then `path (x,y) (x,y) ...`
/// (`-` without a path), then the counters as `name=value` pairs.
pub fn outcome_text(outcome: &planner_api::Outcome) -> String {
    let path = match &outcome.path {
        Some(path) => path
            .cells()
            .iter()
            .map(|c| format!("({},{})", c.x, c.y))
            .collect::<Vec<_>>()
            .join(" "),
        None => "-".to_string(),
    };
    format!(
        "status {}\npath {path}\n{}",
        outcome.status.as_str(),
        outcome.counters
    )
}

/// The least cost from `start` to `goal` on `grid` under `moves` and the grid's cell
/// weights ([`planner_api::weights`]; plain move lengths on an unweighted grid), in exact
/// [`Cost`](planner_api::Cost) units, or `None` when the goal is unreachable: a plain
/// Dijkstra over the weighted graph, the oracle for every weighted search.
///
/// Independent of the planners' code: cells by [`Grid::index`], moves applied with
/// [`MoveSet::apply`](planner_api::MoveSet::apply) (bounds, blocked cells and corner rule
/// checked cell by cell), a `BinaryHeap` with lazy deletion, and the move cost computed
/// here from the rule's definition in 128-bit integers: half the move's length in units
/// (rounded down) times `k_from * w(from) + k_to * w(to)`.
pub fn weighted_dijkstra(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    start: Cell,
    goal: Cell,
) -> Option<planner_api::Cost> {
    let dist = dijkstra_until(grid, moves, start, Some(goal));
    exact_cost(dist[grid.index(goal)])
}

/// The least cost from `start` to every cell of `grid` (by [`Grid::index`]; `None` where
/// unreachable): [`weighted_dijkstra`]'s search run to the end, for a test that needs the
/// costs to many goals from one start.
pub fn weighted_costs_from(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    start: Cell,
) -> Vec<Option<planner_api::Cost>> {
    dijkstra_until(grid, moves, start, None)
        .into_iter()
        .map(exact_cost)
        .collect()
}

/// A cost of [`dijkstra_until`] as a [`Cost`](planner_api::Cost): `None` when beyond 64
/// bits, which includes the unreached cells' `u128::MAX`.
fn exact_cost(d: u128) -> Option<planner_api::Cost> {
    u64::try_from(d).ok().map(planner_api::Cost::from_units)
}

/// The oracle's Dijkstra from `start`: the cost of every cell, `u128::MAX` where unreached.
/// It stops once `goal` is settled; the costs are then exact for the settled cells (the
/// goal among them) and may be too high for the others. With no goal every reachable cell
/// is settled.
fn dijkstra_until(
    grid: &Grid,
    moves: &planner_api::MoveSet,
    start: Cell,
    goal: Option<Cell>,
) -> Vec<u128> {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;
    let rule = grid.weights().map(|w| w.rule());
    let cost = |from: Cell, to: Cell, mv: &planner_api::Move| -> u128 {
        let length = u128::from(mv.exact_cost().units());
        match rule {
            None => length,
            Some(rule) => {
                let (k_from, k_to) = rule.factors();
                let factor = u128::from(k_from) * u128::from(grid.weight(from))
                    + u128::from(k_to) * u128::from(grid.weight(to));
                length / 2 * factor
            }
        }
    };
    let mut dist = vec![u128::MAX; grid.len()];
    let mut heap = BinaryHeap::new();
    dist[grid.index(start)] = 0;
    heap.push(Reverse((0u128, grid.index(start))));
    while let Some(Reverse((d, i))) = heap.pop() {
        if d > dist[i] {
            continue;
        }
        let cell = grid.cell(i);
        if Some(cell) == goal {
            break;
        }
        for mv in moves.moves() {
            if let Some(to) = moves.apply(grid, cell, mv) {
                let next = d + cost(cell, to, mv);
                let j = grid.index(to);
                if next < dist[j] {
                    dist[j] = next;
                    heap.push(Reverse((next, j)));
                }
            }
        }
    }
    dist
}

/// One random weighted problem of [`random_weighted_problems`].
#[derive(Debug, Clone)]
pub struct WeightedProblem {
    /// The grid, with weights.
    pub grid: Grid,
    /// Start (free).
    pub start: Cell,
    /// Goal (free).
    pub goal: Cell,
    /// The density of blocked cells it was drawn with.
    pub density: f64,
}

/// `rounds` random weighted problems, deterministic in `seed` (xorshift): sides from 2 to
/// 24 cells, a blocked-cell density drawn from 0 to 0.4, every cell a weight from 1 to 255
/// (half the grids uniform, half in patches of equal weight, so that ties and terrain
/// borders both occur), the cost rule alternating mean and entered, start and goal drawn
/// uniformly (possibly equal) and made free.
pub fn random_weighted_problems(seed: u64, rounds: usize) -> Vec<WeightedProblem> {
    let mut next = xorshift(seed | 1);
    (0..rounds)
        .map(|round| {
            let (w, h) = (2 + (next() % 23) as u32, 2 + (next() % 23) as u32);
            let density = (next() % 41) as f64 / 100.0;
            let free: Vec<bool> = (0..w * h)
                .map(|_| (next() % 10_000) as f64 >= density * 10_000.0)
                .collect();
            let weights: Vec<u16> = if round % 2 == 0 {
                (0..w * h).map(|_| 1 + (next() % 255) as u16).collect()
            } else {
                let patch = 2 + (next() % 4) as u32;
                let cols = w.div_ceil(patch);
                let rows = h.div_ceil(patch);
                let patches: Vec<u16> = (0..cols * rows)
                    .map(|_| 1 + (next() % 255) as u16)
                    .collect();
                (0..w * h)
                    .map(|i| patches[((i / w / patch) * cols + (i % w) / patch) as usize])
                    .collect()
            };
            let rule = if round % 4 < 2 {
                planner_api::CostRule::Mean
            } else {
                planner_api::CostRule::Entered
            };
            let grid = Grid::from_free_cells(w, h, free)
                .and_then(|g| g.with_weights(weights, rule))
                .unwrap_or_else(|e| panic!("a {w}x{h} grid: {e}"));
            let (grid, start, goal) = with_start_and_goal(grid, &mut next);
            WeightedProblem {
                grid,
                start,
                goal,
                density,
            }
        })
        .collect()
}
