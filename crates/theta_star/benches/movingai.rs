//! Theta\* and Lazy Theta\* against 8-connected A\* on every Moving AI scenario file, in
//! the same run: lengths and times.
//!
//! `cargo bench -p planner-theta_star --bench movingai` prints one line per map in
//! `maps/movingai`, then one `map=all` line over every scenario:
//! `map=<name> scenarios=<n> astar_ms=<t> theta_ms=<t> lazy_ms=<t> theta_vs_astar=<ratio>
//! lazy_vs_astar=<ratio>`, then the work (`astar_expansions`, `theta_expansions`,
//! `theta_los_checks`, `theta_los_cells`, `lazy_expansions`, `lazy_los_checks`,
//! `lazy_los_cells`), then the lengths: `theta_mean_saving_pct` and `theta_max_saving_pct`
//! (Theta\*'s length below A\*'s optimum, in percent of the optimum, averaged over the
//! scenarios), `theta_over_optimum` (scenarios where Theta\* is longer than A\*; the
//! bound says 0), `lazy_mean_saving_pct`, `lazy_over_optimum` and `lazy_max_over_optimum_pct`
//! (Lazy Theta\* longer than A\*, and by how much at most), `lazy_over_theta`,
//! `lazy_under_theta`, `lazy_max_over_theta_pct` and `lazy_mean_over_theta_pct` (Lazy
//! Theta\* against Theta\*; the mean is over all scenarios, negative when Lazy is
//! shorter on average). "Longer" means by more than a relative `1e-9`.
//!
//! A\* is planner-astar as its own benchmark runs it (octile heuristic, larger g first
//! among equal f, no corner cutting), with all counters on, and every A\* length is
//! checked against the scenario's stated optimum (relative `1e-4`; a mismatch aborts).
//! Each planner runs the whole file `--repeats=N` times (default 3), the three
//! alternating, and its best time counts. Times are wall time, or with `--clock=cpu` the
//! thread's time on a CPU (planner-bench's clocks, as in the A* and JPS benches). Pass map
//! names (`arena`, `den520d`) as arguments to run a subset. With the environment variable
//! `GRIDPLAN_THETA_CHECK_ALL=1`, Theta\* checks line of sight on every relaxation
//! ([`AnyAngle::skip_hopeless`] false), as before the bound test was added: the same paths,
//! more checks.

use std::path::PathBuf;
use std::time::Duration;

use planner_api::{Budget, Connectivity, Grid, Problem};
use planner_astar::{AStar, Config as AStarConfig, Heuristic, TieBreak};
use planner_bench::Repeats;
use planner_maps::{read_map, read_scenarios, Scenario};
use planner_theta_star::{AnyAngle, Config, Variant};

/// One planner's results over a scenario file.
#[derive(Default)]
struct Run {
    best: Option<Duration>,
    lengths: Vec<f64>,
    n_expanded: u64,
    n_los_checks: u64,
    n_los_cells: u64,
}

impl Run {
    fn time(&mut self, elapsed: Duration) {
        self.best = Some(self.best.map_or(elapsed, |b| b.min(elapsed)));
    }

    fn ms(&self) -> f64 {
        self.best.unwrap_or_default().as_secs_f64() * 1e3
    }
}

/// Length statistics of one planner against a reference, over all scenarios.
struct Against {
    mean_saving_pct: f64,
    max_saving_pct: f64,
    n_over: usize,
    n_under: usize,
    max_over_pct: f64,
}

fn against(lengths: &[f64], reference: &[f64]) -> Against {
    let mut out = Against {
        mean_saving_pct: 0.0,
        max_saving_pct: 0.0,
        n_over: 0,
        n_under: 0,
        max_over_pct: 0.0,
    };
    for (&l, &r) in lengths.iter().zip(reference) {
        let saving = if r > 0.0 { (r - l) / r * 100.0 } else { 0.0 };
        out.mean_saving_pct += saving;
        out.max_saving_pct = out.max_saving_pct.max(saving);
        if l > r * (1.0 + 1e-9) {
            out.n_over += 1;
            out.max_over_pct = out.max_over_pct.max(-saving);
        } else if l < r * (1.0 - 1e-9) {
            out.n_under += 1;
        }
    }
    out.mean_saving_pct /= lengths.len().max(1) as f64;
    out
}

fn main() {
    let (repeats, filter) = Repeats::parse(std::env::args().skip(1)).unwrap_or_else(|e| {
        eprintln!("{e}");
        std::process::exit(2)
    });
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai");
    let mut names: Vec<String> = std::fs::read_dir(&root)
        .unwrap_or_else(|e| panic!("{}: {e}", root.display()))
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter_map(|n| n.strip_suffix(".map").map(str::to_string))
        .filter(|n| filter.is_empty() || filter.contains(n))
        .collect();
    names.sort();
    let mut all: [Run; 3] = Default::default();
    let mut n_all = 0;
    for name in &names {
        let grid = read_map(&root.join(format!("{name}.map")))
            .unwrap_or_else(|e| panic!("{e}"))
            .grid;
        let scenarios = read_scenarios(&root.join(format!("{name}.map.scen")))
            .unwrap_or_else(|e| panic!("{e}"));
        let runs = run(&grid, &scenarios, repeats);
        report(name, scenarios.len(), &runs);
        for (total, run) in all.iter_mut().zip(runs) {
            total.best = Some(total.best.unwrap_or_default() + run.best.unwrap_or_default());
            total.lengths.extend(run.lengths);
            total.n_expanded += run.n_expanded;
            total.n_los_checks += run.n_los_checks;
            total.n_los_cells += run.n_los_cells;
        }
        n_all += scenarios.len();
    }
    report("all", n_all, &all);
}

/// A*, Theta* and Lazy Theta* over `scenarios`, `repeats` times each, alternating.
fn run(grid: &Grid, scenarios: &[Scenario], Repeats(repeats, clock): Repeats) -> [Run; 3] {
    // The clock was read once by `Repeats::parse`; it stays readable.
    let now = || {
        clock
            .now()
            .unwrap_or_else(|| panic!("the clock became unavailable"))
    };
    let mut astar = AStar::new(AStarConfig {
        moves: Connectivity::Eight,
        heuristic: Heuristic::Octile,
        tie_break: TieBreak::HighG,
        ..AStarConfig::default()
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let mut any_angle = AnyAngle::new(&Config::default()).unwrap_or_else(|e| panic!("{e}"));
    any_angle.skip_hopeless = std::env::var_os("GRIDPLAN_THETA_CHECK_ALL").is_none();
    let problems: Vec<Problem<'_>> = scenarios
        .iter()
        .map(|s| Problem::new(grid, s.start, s.goal).unwrap_or_else(|e| panic!("{e}")))
        .collect();
    let mut runs: [Run; 3] = Default::default();
    for repeat in 0..repeats {
        let first = repeat == 0;
        let t = now();
        for (s, problem) in scenarios.iter().zip(&problems) {
            let search = astar.search(problem, &Budget::unlimited());
            if first {
                let cost = search.cost.unwrap_or(f64::NAN);
                let ok = (cost - s.optimal_length).abs() <= 1e-4 * s.optimal_length.max(1.0);
                assert!(
                    ok,
                    "A* {cost} vs optimum {} at line {}",
                    s.optimal_length, s.line
                );
                runs[0].lengths.push(cost);
                runs[0].n_expanded += search.stats.n_expanded;
            }
        }
        runs[0].time(now().saturating_sub(t));
        for (slot, variant) in [(1, Variant::Theta), (2, Variant::Lazy)] {
            let t = now();
            for problem in &problems {
                let search = any_angle.search(problem, &Budget::unlimited(), variant);
                if first {
                    let run = &mut runs[slot];
                    run.lengths.push(search.cost.unwrap_or(f64::NAN));
                    run.n_expanded += search.stats.search.n_expanded;
                    run.n_los_checks += search.stats.n_los_checks;
                    run.n_los_cells += search.stats.n_los_cells;
                }
            }
            runs[slot].time(now().saturating_sub(t));
        }
    }
    runs
}

fn report(name: &str, n: usize, [astar, theta, lazy]: &[Run; 3]) {
    let t = against(&theta.lengths, &astar.lengths);
    let l = against(&lazy.lengths, &astar.lengths);
    let lt = against(&lazy.lengths, &theta.lengths);
    println!(
        "map={name} scenarios={n} astar_ms={:.1} theta_ms={:.1} lazy_ms={:.1} theta_vs_astar={:.2} lazy_vs_astar={:.2} \
         astar_expansions={} theta_expansions={} theta_los_checks={} theta_los_cells={} \
         lazy_expansions={} lazy_los_checks={} lazy_los_cells={} \
         theta_mean_saving_pct={:.3} theta_max_saving_pct={:.3} theta_over_optimum={} \
         lazy_mean_saving_pct={:.3} lazy_over_optimum={} lazy_max_over_optimum_pct={:.4} \
         lazy_over_theta={} lazy_under_theta={} lazy_max_over_theta_pct={:.4} lazy_mean_over_theta_pct={:.4}",
        astar.ms(),
        theta.ms(),
        lazy.ms(),
        theta.ms() / astar.ms(),
        lazy.ms() / astar.ms(),
        astar.n_expanded,
        theta.n_expanded,
        theta.n_los_checks,
        theta.n_los_cells,
        lazy.n_expanded,
        lazy.n_los_checks,
        lazy.n_los_cells,
        t.mean_saving_pct,
        t.max_saving_pct,
        t.n_over,
        l.mean_saving_pct,
        l.n_over,
        l.max_over_pct,
        lt.n_over,
        lt.n_under,
        lt.max_over_pct,
        -lt.mean_saving_pct,
    );
}
