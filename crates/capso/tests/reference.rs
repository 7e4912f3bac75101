//! CAPSO's guide against `planner_testkit::reference_capso_guide`, its block-level A\*
//! written again from the module docs of `guide`, and CAPSO's counters against the
//! reference and the crate docs' formulas.

use planner_api::{Budget, Cell, Grid, PathRule, Planner, Problem, Status};
use planner_capso::collision::BitGrid;
use planner_capso::guide::{Guide, Route};
use planner_capso::{Capso, Config};
use planner_testkit::{reference_capso_guide, xorshift, CapsoGuideSearch};

/// `Guide::find` on `grid` as the reference reports it.
fn guide(grid: &Grid, start: Cell, goal: Cell) -> CapsoGuideSearch {
    let mut bits = BitGrid::new();
    bits.load(grid);
    let mut guide = Guide::default();
    let mut clock = Budget::unlimited().start();
    let route = guide.find(&bits, start, goal, &mut clock);
    assert_ne!(
        route,
        Route::Stopped,
        "an unlimited budget stopped the guide"
    );
    assert_eq!(route == Route::Found, guide.block > 0);
    CapsoGuideSearch {
        block: guide.block,
        n_expanded: guide.n_expanded,
        polyline: if route == Route::Found {
            guide.polyline.clone()
        } else {
            Vec::new()
        },
    }
}

/// A `w` x `h` grid with `rectangles` random blocked rectangles of sides up to `size`, and
/// with `wall` a blocked column across it, with a gap of 1 to 3 cells when `gap`; start and
/// goal drawn at random and made free.
fn blocks_problem(
    next: &mut impl FnMut() -> u64,
    (w, h): (u32, u32),
    rectangles: u32,
    size: u32,
    wall: bool,
    gap: bool,
) -> (Grid, Cell, Cell) {
    let mut grid = Grid::new(w, h).unwrap();
    let mut draw = |n: u32| (next() % u64::from(n)) as u32;
    for _ in 0..rectangles {
        let (x0, y0) = (draw(w), draw(h));
        let (rw, rh) = (1 + draw(size), 1 + draw(size));
        for y in y0..(y0 + rh).min(h) {
            for x in x0..(x0 + rw).min(w) {
                grid.set_free(Cell::new(x, y), false);
            }
        }
    }
    if wall {
        let x = w / 4 + draw(w / 2);
        let (g0, g1) = if gap {
            let g0 = draw(h);
            (g0, g0 + 1 + draw(3))
        } else {
            (h, h)
        };
        for y in (0..h).filter(|y| !(g0..g1).contains(y)) {
            grid.set_free(Cell::new(x, y), false);
        }
    }
    let start = Cell::new(draw(w), draw(h));
    let goal = Cell::new(draw(w), draw(h));
    grid.set_free(start, true);
    grid.set_free(goal, true);
    (grid, start, goal)
}

/// What the problems of a comparison covered, so that a generator that stops exercising a
/// rule fails the test instead of passing it vacuously.
#[derive(Debug, Default)]
struct Seen {
    problems: u64,
    /// Found with blocks of more than one cell.
    coarse: u64,
    /// Found after at least one halving.
    halved: u64,
    unreachable: u64,
    /// Unreachable after more than one level.
    unreachable_coarse: u64,
    shortened: u64,
    /// Polylines with a piece that crosses a blocked cell.
    blocked: u64,
}

/// Compares the guide with the reference on every problem and tallies what they covered.
fn compare(problems: &[(Grid, Cell, Cell)], seen: &mut Seen) {
    for (k, (grid, start, goal)) in problems.iter().enumerate() {
        let (start, goal) = (*start, *goal);
        let expect = reference_capso_guide(grid, start, goal);
        let actual = guide(grid, start, goal);
        assert_eq!(
            actual,
            expect,
            "problem {k}: {}x{} {start} -> {goal}",
            grid.width(),
            grid.height()
        );
        let first = grid.width().max(grid.height()).div_ceil(64);
        seen.problems += 1;
        seen.coarse += u64::from(expect.block > 1);
        seen.halved += u64::from(expect.block != first && expect.block > 0);
        seen.unreachable += u64::from(expect.block == 0);
        seen.unreachable_coarse += u64::from(expect.block == 0 && first > 1);
        // Only a piece from the start or to the goal may cross blocked cells (of their
        // blocks, which count as free: the module docs, step 4).
        let pieces = expect.polyline.windows(2);
        let blocked: Vec<&[Cell]> = pieces
            .filter(|p| !planner_api::segment_is_free(grid, p[0], p[1]))
            .collect();
        assert!(
            blocked.iter().all(|p| p[0] == start || p[1] == goal),
            "problem {k}: {blocked:?}"
        );
        seen.blocked += u64::from(!blocked.is_empty());
        // Fewer waypoints than a route over adjacent blocks would have.
        let (d, b) = (
            start.x.abs_diff(goal.x).max(start.y.abs_diff(goal.y)),
            expect.block.max(1),
        );
        seen.shortened += u64::from(expect.block > 0 && (expect.polyline.len() as u32) < d / b);
    }
}

/// The guide's block size, expansions over all levels and shortened polyline equal the
/// reference's on 2,740 grids: random ones of every size (a single level of cells up to
/// 64 cells a side, first blocks of 2 to 5 cells above), ones with rectangles of obstacles
/// and walls with narrow gaps that force the block size down, and unreachable goals (every
/// level searched). Only a piece from the start or to the goal of a polyline crosses
/// blocked cells.
#[test]
fn the_guide_is_the_reference_guide() {
    let mut seen = Seen::default();
    // Up to 64 cells a side: blocks of one cell, at every obstacle density.
    compare(
        &planner_testkit::random_problems(34, 2000, (2, 64), (0, 4000)),
        &mut seen,
    );
    // 65 to 320 cells a side: first blocks of 2 to 5 cells; up to 10 % of scattered
    // obstacles leave few of them free, so the search often halves the blocks.
    compare(
        &planner_testkit::random_problems(35, 400, (65, 200), (0, 1000)),
        &mut seen,
    );
    compare(
        &planner_testkit::random_problems(36, 40, (200, 320), (0, 30)),
        &mut seen,
    );
    // 100 to 300 cells a side, rectangles of obstacles, and in three rounds of four a
    // wall: with a gap of 1 to 3 cells in two (narrower than most blocks), closed in one.
    let mut next = xorshift(0x5eed_0034);
    let mut problems = Vec::new();
    for round in 0..300u32 {
        let side = |n: u64| 100 + (n % 201) as u32;
        let size = (side(next()), side(next()));
        let rectangles = (next() % 40) as u32;
        let (wall, gap) = (round % 4 != 0, round % 4 != 3);
        problems.push(blocks_problem(&mut next, size, rectangles, 30, wall, gap));
    }
    compare(&problems, &mut seen);
    assert_eq!(seen.problems, 2740);
    let Seen {
        coarse,
        halved,
        unreachable,
        unreachable_coarse,
        shortened,
        blocked,
        ..
    } = seen;
    assert!(
        coarse >= 200
            && halved >= 100
            && unreachable >= 300
            && unreachable_coarse >= 50
            && shortened >= 1000
            && blocked >= 10,
        "{seen:?}"
    );
}

/// By hand: a corridor of 5 cells (blocks of one cell) expands every cell (f = 20 for all,
/// ties to the lower index) and shortens to its ends; on a 130 x 20 grid (blocks of 3
/// cells) a wall in column 64 with a gap of one cell leaves no free block in its column of
/// blocks, so the 21 x 7 blocks left of it are expanded before the search goes down to
/// the cells (by hand with the gap closed too).
#[test]
fn the_guide_by_hand() {
    let corridor = Grid::new(5, 1).unwrap();
    let (s, t) = (Cell::new(0, 0), Cell::new(4, 0));
    let expect = CapsoGuideSearch {
        block: 1,
        n_expanded: 5,
        polyline: vec![s, t],
    };
    assert_eq!(guide(&corridor, s, t), expect);
    assert_eq!(reference_capso_guide(&corridor, s, t), expect);
    // The start is the goal: one block expanded, the one-cell polyline.
    let one = CapsoGuideSearch {
        block: 1,
        n_expanded: 1,
        polyline: vec![s],
    };
    assert_eq!(guide(&corridor, s, s), one);
    assert_eq!(reference_capso_guide(&corridor, s, s), one);
    let mut walled = Grid::new(130, 20).unwrap();
    for y in (0..20).filter(|&y| y != 10) {
        walled.set_free(Cell::new(64, y), false);
    }
    let (s, t) = (Cell::new(5, 2), Cell::new(125, 2));
    let expect = reference_capso_guide(&walled, s, t);
    assert_eq!(guide(&walled, s, t), expect);
    assert_eq!(expect.block, 1);
    assert!(expect.n_expanded > 21 * 7, "{expect:?}");
    assert_eq!(expect.polyline.first(), Some(&s));
    assert_eq!(expect.polyline.last(), Some(&t));
    // The gap closed: the 147 blocks at size 3, then (3 / 2 = 1) the 64 x 20 cells left
    // of the wall.
    walled.set_free(Cell::new(64, 10), false);
    let closed = CapsoGuideSearch {
        block: 0,
        n_expanded: 147 + 64 * 20,
        polyline: Vec::new(),
    };
    assert_eq!(guide(&walled, s, t), closed);
    assert_eq!(reference_capso_guide(&walled, s, t), closed);
}

fn capso(population: u32, iterations: u32, seed: u64) -> Capso {
    Capso::new(Config {
        seed,
        control_points: 4,
        population,
        iterations,
        ..Config::default()
    })
    .unwrap()
}

/// CAPSO's counters: the guide's as the reference's; `P + T P` fitness evaluations and
/// `T` iterations when the guide finds a route (none when it does not); a found path is
/// valid any-angle with no collision.
#[test]
fn capso_counters_are_the_reference_guide_and_the_formulas() {
    let mut problems = Vec::new();
    for map in ["two-140x120.map", "several-140x120.map", "random200-1.map"] {
        let grid = planner_testkit::movingai(&format!("pastar/{map}"));
        problems.push((grid, Cell::new(20, 10), Cell::new(70, 110)));
    }
    let scenario = planner_testkit::movingai("pastar/scenario500.map");
    problems.push((scenario, Cell::new(50, 250), Cell::new(400, 200)));
    // A wall with a gap of one cell: blocks of 3, then of 1.
    let mut walled = Grid::new(130, 20).unwrap();
    for y in (0..20).filter(|&y| y != 10) {
        walled.set_free(Cell::new(64, y), false);
    }
    problems.push((walled, Cell::new(5, 2), Cell::new(125, 2)));
    let mut next = xorshift(0x5eed_1034);
    for round in 0..6 {
        let (wall, gap) = (round % 3 != 0, round % 3 == 1);
        let problem = blocks_problem(&mut next, (120, 90), 12, 20, wall, gap);
        problems.push(problem);
    }
    let (mut found, mut unreachable, mut halved) = (0, 0, 0);
    for (k, (grid, start, goal)) in problems.iter().enumerate() {
        let problem = Problem::new(grid, *start, *goal).unwrap();
        let (population, iterations) = (4 + k as u32 % 5, 3 + k as u32 % 7);
        let outcome = capso(population, iterations, k as u64).plan(&problem, &Budget::unlimited());
        let reference = reference_capso_guide(grid, *start, *goal);
        let first = grid.width().max(grid.height()).div_ceil(64);
        halved += u32::from(reference.block != first && reference.block > 0);
        let get = |name: &str| outcome.counters.get(name).unwrap();
        let what = format!("problem {k}: {start} -> {goal}, {}", outcome.counters);
        assert_eq!(get("n_guide_expanded"), reference.n_expanded, "{what}");
        assert_eq!(get("guide_block"), u64::from(reference.block), "{what}");
        let (p, t) = (u64::from(population), u64::from(iterations));
        let (evaluations, done) = match reference.block {
            0 => (0, 0),
            _ => (p + t * p, t),
        };
        assert_eq!(get("n_fitness_evaluations"), evaluations, "{what}");
        assert_eq!(get("n_expanded"), evaluations, "{what}");
        assert_eq!(get("n_iterations"), done, "{what}");
        match outcome.status {
            Status::Found => {
                let path = outcome.path.as_ref().unwrap();
                assert_eq!(path.validate(grid, PathRule::AnyAngle), Ok(()), "{what}");
                assert_eq!(get("final_collision_cells"), 0, "{what}");
                assert_eq!(get("final_collision_length_milli"), 0, "{what}");
                found += 1;
            }
            Status::NoPath => {
                assert_eq!(reference.block, 0, "{what}: no_path with a guide route");
                unreachable += 1;
            }
            // The swarm's iterations ran out before a collision-free path.
            Status::BudgetExhausted => assert!(get("final_collision_cells") > 0, "{what}"),
        }
    }
    assert!(
        found >= 6 && unreachable >= 1 && halved >= 1,
        "{found} found, {unreachable} unreachable, {halved} halved"
    );
    // The start is the goal: the one-cell path, no guide and no evaluation.
    let grid = Grid::new(10, 10).unwrap();
    let problem = Problem::new(&grid, Cell::new(3, 3), Cell::new(3, 3)).unwrap();
    let outcome = capso(4, 3, 0).plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found);
    assert!(
        outcome.counters.iter().all(|(_, v)| v == 0),
        "{}",
        outcome.counters
    );
}
