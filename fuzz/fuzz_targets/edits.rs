//! Grids edited in place (a robot's map changing as it drives): every registered planner,
//! reused across edits, gives exactly a fresh planner's outcome (status, path, counters)
//! on the edited grid, and every path it returns keeps its declared rule there. The
//! planners' per-grid tables follow edits through `Grid::changed_since` (adjacency masks,
//! free-cell bits, JPS's rows, padded weights, summed-area tables, LPA*'s map), so a
//! missed or misplaced update shows as a difference here.
//!
//! A planner that repairs its search (LPA*, D* Lite: `IncrementalPlanner`) is also driven
//! the way the replanning runner drives it: reset on the first grid, then each batch's
//! changes applied (`apply`) and a `replan`, whose path must cost exactly what planner-
//! testkit's weighted Dijkstra (the oracle, independent of the planners) says for the
//! edited grid, or find nothing where the oracle finds nothing.
//!
//! The input: byte 0 picks the planner (every registry entry, with its `moves = 8`
//! variant where it has one), bytes 1-2 the size (1 to 24 cells a side), byte 3 whether
//! the grid carries weights (planners that honour cell costs only), then a bit per cell
//! (1 = blocked), start and goal (two bytes each, made free), then edits of three bytes:
//! `x`, `y` and an operation (`op & 3`: 0 block, 1 free, 2 set the weight
//! `1 + (op >> 2) % 9`, 3 toggle), a set top bit ending a batch. After every batch the
//! reused planner and a fresh one plan on the grid as it is; at most 8 batches and 96
//! edits, a budget of 4,000 expansions a plan.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_api::{
    Budget, Cell, CellChange, CostRule, CoverageProblem, Grid, PathSpec, Problem, Status,
};
use planner_registry::{Built, Factory, PLANNERS};

const BUDGET: u64 = 4_000;
const MAX_BATCHES: usize = 8;
const MAX_EDITS: usize = 96;

/// Every registry entry's variants (`Entry::variants`: its defaults, and `moves = 8` where
/// its config takes that key).
fn factories() -> Vec<Factory> {
    PLANNERS
        .iter()
        .flat_map(|entry| entry.variants().expect("defaults are valid"))
        .collect()
}

/// A plan's outcome as compared.
#[derive(Debug, PartialEq)]
struct Seen {
    status: Status,
    cells: Option<Vec<Cell>>,
    counters: planner_api::Counters,
}

fn run(built: &mut Built, grid: &Grid, start: Cell, goal: Cell, seed: Option<u64>) -> Seen {
    let budget = Budget::expansions(BUDGET);
    match built {
        Built::Path(planner) => {
            if let Some(seed) = seed {
                planner.reseed(seed);
            }
            planner.prepare(grid);
            let problem = Problem::new(grid, start, goal).expect("start and goal are free");
            let outcome = planner.plan(&problem, &budget);
            Seen {
                status: outcome.status,
                cells: outcome.path.map(|path| path.cells().to_vec()),
                counters: outcome.counters,
            }
        }
        Built::Coverage(planner) => {
            let problem = CoverageProblem::new(grid, start).expect("the start is free");
            let outcome = planner.cover(&problem, &budget);
            Seen {
                status: outcome.status,
                cells: Some(outcome.path.cells().to_vec()),
                counters: outcome.counters,
            }
        }
    }
}

fuzz_target!(|data: &[u8]| {
    thread_local! {
        static FACTORIES: Vec<Factory> = factories();
    }
    if data.len() < 4 {
        return;
    }
    FACTORIES.with(|factories| {
        let factory = &factories[usize::from(data[0]) % factories.len()];
        let (w, h) = (1 + u32::from(data[1]) % 24, 1 + u32::from(data[2]) % 24);
        let weighted = data[3] & 1 == 1 && factory.specs().cell_costs;
        let mut rest = &data[4..];
        let mut take = |n: usize| {
            let (head, tail) = rest.split_at(n.min(rest.len()));
            rest = tail;
            head
        };
        let n = (w * h) as usize;
        let bits = take(n.div_ceil(8));
        let free: Vec<bool> = (0..n)
            .map(|i| bits.get(i / 8).is_none_or(|byte| byte >> (i % 8) & 1 == 0))
            .collect();
        let mut grid = Grid::from_free_cells(w, h, free).expect("the cells fit the size");
        if weighted {
            let weights = (0..n).map(|i| 1 + (i * 7 % 9) as u16).collect();
            grid = grid
                .with_weights(weights, CostRule::Mean)
                .expect("weights from 1");
        }
        let cell = |bytes: &[u8]| {
            let byte = |i: usize| u32::from(bytes.get(i).copied().unwrap_or(0));
            Cell::new(byte(0) % w, byte(1) % h)
        };
        let (start, goal) = (cell(take(2)), cell(take(2)));
        grid.set_free(start, true);
        grid.set_free(goal, true);
        let seed = factory.seed_for(7, 0);
        let rule = factory.specs().path_rule.clone();
        let mut reused = factory.build().expect("a valid factory builds");
        run(&mut reused, &grid, start, goal, seed);
        let mut incremental = factory.build_incremental().map(|built| {
            let mut planner = built.expect("a valid factory builds");
            let problem = Problem::new(&grid, start, goal).expect("start and goal are free");
            planner.reset(&problem);
            planner.replan(&Budget::expansions(BUDGET));
            planner
        });
        let edits: Vec<&[u8]> = rest.chunks_exact(3).take(MAX_EDITS).collect();
        for batch in edits
            .split_inclusive(|edit| edit[2] & 0x80 != 0)
            .take(MAX_BATCHES)
        {
            let mut changes = Vec::new();
            for edit in batch {
                let target = Cell::new(u32::from(edit[0]) % w, u32::from(edit[1]) % h);
                let op = edit[2] & 0x7f;
                let keep_free = target == start || target == goal;
                let change = match op & 3 {
                    0 if !keep_free => CellChange::blocked(target),
                    1 => CellChange::freed(target),
                    2 if weighted => CellChange {
                        cell: target,
                        free: grid.is_free(target),
                        weight: Some(1 + u16::from(op >> 2) % 9),
                    },
                    3 if !keep_free && grid.is_free(target) => CellChange::blocked(target),
                    3 if !keep_free => CellChange::freed(target),
                    _ => continue,
                };
                grid.set_free(change.cell, change.free);
                if let Some(weight) = change.weight {
                    grid.set_weight(change.cell, weight);
                }
                changes.push(change);
            }
            if let Some(planner) = incremental.as_mut() {
                planner.apply(&changes).expect("changes inside the map");
                let outcome = planner.replan(&Budget::expansions(BUDGET));
                let PathSpec::Moves(moves) = &rule else {
                    panic!("{}: an incremental planner without moves", factory.name());
                };
                let oracle = planner_testkit::weighted_dijkstra(&grid, moves, start, goal);
                match outcome.status {
                    Status::Found => {
                        let path = outcome.path.expect("a found path");
                        if let Err(error) = path.validate(&grid, rule.rule()) {
                            panic!(
                                "{}: the replanned path breaks its rule: {error}",
                                factory.name()
                            );
                        }
                        assert_eq!(
                            Some(grid.path_cost(path.cells())),
                            oracle,
                            "{}: the replanned path is not the least cost",
                            factory.name()
                        );
                    }
                    Status::NoPath => assert_eq!(
                        oracle,
                        None,
                        "{}: replanning found no path where one exists",
                        factory.name()
                    ),
                    _ => {}
                }
            }
            let again = run(&mut reused, &grid, start, goal, seed);
            let mut fresh = factory.build().expect("a valid factory builds");
            let first = run(&mut fresh, &grid, start, goal, seed);
            assert_eq!(
                again,
                first,
                "{}: a planner reused across edits differs from a fresh one",
                factory.name()
            );
            if let Some(cells) = &first.cells {
                let path = planner_api::Path::new(cells.clone());
                if let Err(error) = path.validate(&grid, rule.rule()) {
                    panic!("{}: the path breaks its rule: {error}", factory.name());
                }
            }
        }
    });
});
