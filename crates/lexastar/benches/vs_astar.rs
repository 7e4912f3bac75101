//! Time per query of lexastar relative to planner-astar on Moving AI scenarios,
//! 4-connected, same scenarios, same reused planners.
//!
//! `cargo bench -p planner-lexastar` runs den520d; other maps of maps/movingai can be named
//! as arguments (`cargo bench -p planner-lexastar -- arena`). Every third scenario of the
//! `.scen` file is used (297 on den520d), each planner answers all of them `ROUNDS` times,
//! and the best round counts. Both planners must agree on D (both are exact for steps).
//! lexastar runs with its default dominance pruning and without it.

use std::hint::black_box;
use std::time::{Duration, Instant};

use planner_api::{Budget, Cell, Grid, Problem, Status};
use planner_astar::AStar;
use planner_lexastar::LexAStar;

const ROUNDS: usize = 5;
const SCENARIO_STRIDE: usize = 3;

fn read_map(name: &str) -> Grid {
    planner_testkit::movingai(&format!("movingai/{name}.map"))
}

/// Every `SCENARIO_STRIDE`-th scenario of `<name>.map.scen`.
fn read_scenarios(name: &str) -> Vec<(Cell, Cell)> {
    planner_testkit::scenarios(&format!("movingai/{name}.map.scen"))
        .into_iter()
        .step_by(SCENARIO_STRIDE)
        .map(|s| (s.start, s.goal))
        .collect()
}

/// Best of `ROUNDS` total times over all problems, and the results of the last round.
fn time<T>(problems: &[Problem<'_>], mut run: impl FnMut(&Problem<'_>) -> T) -> (Duration, Vec<T>) {
    let mut best = Duration::MAX;
    let mut results = Vec::new();
    for _ in 0..ROUNDS {
        results.clear();
        let started = Instant::now();
        for problem in problems {
            results.push(black_box(run(black_box(problem))));
        }
        best = best.min(started.elapsed());
    }
    (best, results)
}

fn bench(name: &str) {
    let grid = read_map(name);
    let problems: Vec<Problem<'_>> = read_scenarios(name)
        .into_iter()
        .map(|(start, goal)| Problem::new(&grid, start, goal).expect("scenario cells are free"))
        .collect();
    let budget = Budget::unlimited();
    let mut astar = AStar::new(planner_astar::Config::default()).expect("default config");
    let mut lexastar = LexAStar::new(planner_lexastar::Config::default()).expect("default config");
    let (astar_time, astar_results) = time(&problems, |p| astar.search(p, &budget));
    let (lex_time, lex_results) = time(&problems, |p| lexastar.search(p, &budget));
    let mut plain = LexAStar::new(planner_lexastar::Config {
        dominance: false,
        ..planner_lexastar::Config::default()
    })
    .expect("valid config");
    let (plain_time, plain_results) = time(&problems, |p| plain.search(p, &budget));
    let plain_expanded: u64 = plain_results.iter().map(|r| r.stats.n_expanded).sum();
    for (l, p) in lex_results.iter().zip(&plain_results) {
        assert_eq!(l.cost, p.cost, "dominance pruning keeps the optimum");
    }

    let (mut astar_expanded, mut lex_expanded, mut lex_cells) = (0u64, 0u64, 0u64);
    let (mut astar_turns, mut lex_turns, mut fewer_turns) = (0u64, 0u64, 0usize);
    for (a, l) in astar_results.iter().zip(&lex_results) {
        assert_eq!(a.status, Status::Found);
        assert_eq!(l.status, Status::Found);
        let am = a.path.as_ref().expect("found").metrics();
        let lm = l.path.as_ref().expect("found").metrics();
        assert_eq!(am.steps, lm.steps, "both planners are exact for D");
        assert!(
            lm.turns <= am.turns,
            "lexastar has the fewest turns among shortest paths"
        );
        astar_expanded += a.stats.n_expanded;
        lex_expanded += l.stats.n_expanded;
        lex_cells += l.n_cells_expanded;
        astar_turns += am.turns;
        lex_turns += lm.turns;
        fewer_turns += usize::from(lm.turns < am.turns);
    }
    let n = problems.len() as f64;
    let per_query = |d: Duration| d.as_secs_f64() * 1e6 / n;
    println!(
        "{name} ({}x{}), {} scenarios, 4-connected, best of {ROUNDS} rounds:",
        grid.width(),
        grid.height(),
        problems.len()
    );
    println!(
        "  astar     {:>9.1} us/query  n_expanded {:>9} (cells)         turns {:>6}",
        per_query(astar_time),
        astar_expanded,
        astar_turns
    );
    println!(
        "  lexastar  {:>9.1} us/query  n_expanded {:>9} (states), {:>9} cells  turns {:>6} (fewer on {} of {})",
        per_query(lex_time),
        lex_expanded,
        lex_cells,
        lex_turns,
        fewer_turns,
        problems.len()
    );
    println!(
        "  lexastar without dominance {:>9.1} us/query  n_expanded {:>9} (states)",
        per_query(plain_time),
        plain_expanded
    );
    println!(
        "  factor lexastar / astar: time {:.2}x, expansions {:.2}x; without dominance: time {:.2}x, expansions {:.2}x",
        lex_time.as_secs_f64() / astar_time.as_secs_f64(),
        lex_expanded as f64 / astar_expanded as f64,
        plain_time.as_secs_f64() / astar_time.as_secs_f64(),
        plain_expanded as f64 / astar_expanded as f64
    );
}

fn main() {
    let names: Vec<String> = std::env::args()
        .skip(1)
        .filter(|arg| !arg.starts_with("--"))
        .collect();
    if names.is_empty() {
        bench("den520d");
    } else {
        for name in &names {
            bench(name);
        }
    }
}
