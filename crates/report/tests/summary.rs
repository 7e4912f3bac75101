//! summary.md's header, from a sweep's records: what the report says about the runs.

use std::path::{Path, PathBuf};

use planner_report::Renderer;
use planner_runner::{config, run_all, RunOptions};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Seed 002's TA-star (Manhattan with 8 moves) is recorded as inadmissible, and the
/// summary says such runs are not optimal by design, with no section asked for.
#[test]
fn inadmissible_heuristics_are_named_in_the_summary() {
    let experiment = config::load(&root().join("configs/pastar.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let (summary, _) = Renderer::new(Vec::new())
        .summary(&experiment, &records)
        .unwrap();
    assert!(
        summary.contains("Not optimal by design: `TA-star`, `RA-star2` declare paths that need not be least-cost (for A*: a heuristic that can overestimate under its moves, or a weight above 1); their runs are recorded"),
        "{summary}"
    );
}

/// A sweep over many scenarios of a large map, with no `figures_per_map`: its figures are
/// a sample within the default cells of drawn map (64 comparisons of random512-10-0's
/// 262,144 cells), not one per problem (209 here; a sweep over every scenario of a map
/// drew thousands, all held in memory until written), and summary.md says so. A `figures_per_map` the config gives is obeyed, and needs no note.
#[test]
fn large_sweeps_draw_a_sample_of_figures_and_say_so() {
    let dir = root().join("maps/movingai");
    let config = |extra: &str| {
        let text = format!(
            "name = \"sample\"\nfigures = \"comparisons\"\n{extra}[[maps]]\nfiles = [{:?}]\nscen = {:?}\nevery = 8\n\
             [planners.jps]\nplanner = \"jps\"\n",
            dir.join("random512-10-0.map").display().to_string(),
            dir.join("random512-10-0.map.scen").display().to_string(),
        );
        config::parse(&root().join("configs/sample-test.toml"), &text).unwrap()
    };
    let experiment = config("");
    assert_eq!(experiment.maps[0].problems.len(), 209);
    assert_eq!(experiment.figure_limit(&experiment.maps[0]), 64);
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let files = planner_report::figures::render(&experiment, &records, &Default::default());
    assert_eq!(files.len(), 64);
    let (summary, _) = Renderer::new(Vec::new())
        .summary(&experiment, &records)
        .unwrap();
    assert!(
        summary.contains(
            "Figures of random512-10-0.map: 64 of its 209 problems (`figures_pick`): without `figures_per_map`, as many as keep its figures within 16777216 cells of drawn map, at most 256"
        ),
        "{summary}"
    );
    let asked = config("figures_per_map = 70\n");
    let files = planner_report::figures::render(&asked, &records, &Default::default());
    assert_eq!(files.len(), 70);
    let (summary, _) = Renderer::new(Vec::new()).summary(&asked, &records).unwrap();
    assert!(!summary.contains("Figures of"), "{summary}");
    // No figures asked for: none drawn, and nothing to say of them.
    let mut without = experiment.clone();
    without.figures = config::FigureMode::None;
    assert!(planner_report::figures::render(&without, &records, &Default::default()).is_empty());
    let (summary, _) = Renderer::new(Vec::new())
        .summary(&without, &records)
        .unwrap();
    assert!(!summary.contains("Figures of"), "{summary}");
}

/// A sweep's stop flag raised once its runs are done (Ctrl-C while the report is written)
/// ends the report with `RunnerError::Interrupted` at its next section, figure or file,
/// instead of rendering everything first.
#[test]
fn a_raised_stop_flag_ends_the_report() {
    use std::sync::atomic::{AtomicBool, Ordering};

    use planner_runner::provenance::{Machine, Provenance};
    use planner_runner::sweep::Results;
    use planner_runner::RunnerError;

    let experiment = config::load(&root().join("configs/paper.toml"))
        .unwrap()
        .trimmed_for_test();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let machine = Machine {
        commit: None,
        host: None,
    };
    let provenance = Provenance::collect(&experiment.source, 1, &machine);
    let expanded = Default::default();
    let stop = AtomicBool::new(false);
    let results = Results {
        experiment: &experiment,
        records: &records,
        passes: &records.as_slice(),
        expanded: &expanded,
        provenance: &provenance,
        seconds: 0.0,
        stop: Some(&stop),
    };
    let names = ["optimum", "repeats", "aggregate", "paired", "charts"];
    let renderer = Renderer::new(
        names
            .iter()
            .filter_map(|n| planner_report::generic_section(n))
            .collect(),
    );
    let (files, _) = renderer.files(&results).unwrap();
    assert!(files.iter().any(|f| f.path.starts_with("figures")));
    stop.store(true, Ordering::Relaxed);
    assert!(matches!(
        renderer.files(&results),
        Err(RunnerError::Interrupted)
    ));
    assert!(matches!(
        planner_report::figures::render_until(&experiment, &records, &expanded, Some(&stop)),
        Err(RunnerError::Interrupted)
    ));
}

/// summary.md's "Lengths against the scenario optima" counted repeat 0 only while its
/// text said it counted runs: RRT (seeded) with 2 repeats on 30 den520d scenarios showed
/// runs 30, found 26 and a largest excess of 69.98 % beside runs.csv's 60 runs, 54 found
/// and largest suboptimality of 163.7 %. It counts every run now, as its text and the
/// aggregate tables say: runs, found, optimal and the largest excess are the records'.
#[test]
fn the_optimum_table_counts_every_run() {
    use planner_report::optimum::{matches_optimum, Optimum};
    let map = root().join("maps/movingai/den520d.map");
    let text = format!(
        "name = \"opt\"\nrepeats = 2\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\nscen = {:?}\n\
         lines = [10, 400]\nevery = 5\nlimit = 30\n[planners.rrt]\nplanner = \"rrt\"\n\
         steer = \"eight\"\nmax_iterations = 3000\n",
        map.display().to_string(),
        format!("{}.scen", map.display())
    );
    let experiment = config::parse(&root().join("configs/optimum-test.toml"), &text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    assert_eq!(records.len(), 60);
    let found: Vec<(f64, f64)> = records
        .iter()
        .filter_map(|r| Some((r.length?, r.optimal_length?)))
        .collect();
    let optimal = found
        .iter()
        .filter(|(l, o)| matches_optimum(*l, *o))
        .count();
    let excess = found
        .iter()
        .map(|(l, o)| (l - o) / o.max(1.0))
        .fold(0.0f64, f64::max);
    // The seeds differ: the second repeat finds what the first does not, or longer paths.
    let first: Vec<_> = records.iter().filter(|r| r.repeat == 0).collect();
    let first_found = first.iter().filter(|r| r.length.is_some()).count();
    let first_excess = first
        .iter()
        .filter_map(|r| Some((r.length? - r.optimal_length?) / r.optimal_length?.max(1.0)))
        .fold(0.0f64, f64::max);
    assert!(first_found != found.len() || first_excess != excess);
    let (summary, _) = Renderer::new(vec![Box::new(Optimum)])
        .summary(&experiment, &records)
        .unwrap();
    let row = format!(
        "| rrt | den520d.map | 60 | {} | {optimal} | {:.2} % |",
        found.len(),
        100.0 * excess
    );
    assert!(summary.contains(&row), "{row}\n{summary}");
    assert!(
        summary.contains("Per planner and map, over every run, repeats included"),
        "{summary}"
    );
}

/// A sweep of arena.map with a weight file (12 scenarios) and 16room_000.map without one.
pub fn weighted_sweep() -> (config::Experiment, Vec<planner_runner::RunRecord>) {
    let maps = root().join("maps");
    let text = format!(
        "name = \"weighted-optima\"\nfigures = \"none\"\n\
         [[maps]]\nfiles = [{arena:?}]\nscen = {arena_scen:?}\nevery = 10\nlimit = 12\n\
         costs = {{ weights = {weights:?} }}\n\
         [[maps]]\nfiles = [{room:?}]\nscen = {room_scen:?}\nlimit = 3\n\
         [planners.astar]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"octile\"\n\
         [planners.bfs]\nplanner = \"bfs\"\nmoves = 8\ncosts = \"ignore\"\n",
        arena = maps.join("movingai/arena.map").display().to_string(),
        arena_scen = maps.join("movingai/arena.map.scen").display().to_string(),
        weights = maps
            .join("weighted/arena-weights.csv")
            .display()
            .to_string(),
        room = maps.join("movingai/16room_000.map").display().to_string(),
        room_scen = maps
            .join("movingai/16room_000.map.scen")
            .display()
            .to_string(),
    );
    let experiment = config::parse(&root().join("configs/weighted-optima.toml"), &text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    (experiment, records)
}

/// On a map with cell costs, summary.md compared least-cost paths with the scenario
/// file's unweighted optima: A* on arena with a weight file showed `| astar | arena.map |
/// 12 | 12 | 5 | 30.40 % |` in "Lengths against the scenario optima" and a median
/// suboptimality of 4.71 % in the Aggregates, and no table showed the path `cost`. Such
/// maps are now left out of the optimum table (which says so) and of `Optimal` and the
/// suboptimality; the Aggregates show the median cost, and `paired` the cost ratio beside
/// the (unweighted) length ratio. A map without costs is compared as before.
#[test]
fn maps_with_cell_costs_are_not_compared_with_unweighted_optima() {
    use planner_report::{aggregate::Aggregate, optimum::Optimum, paired::Paired};
    let (experiment, records) = weighted_sweep();
    let astar_arena: Vec<_> = records
        .iter()
        .filter(|r| r.planner == "astar" && r.map == "arena.map")
        .collect();
    // A* finds least-cost paths, longer than the unweighted optima.
    assert!(astar_arena
        .iter()
        .any(|r| r.length.unwrap() > r.optimal_length.unwrap() * 1.01));
    let (summary, _) = Renderer::new(vec![
        Box::new(Optimum),
        Box::new(Aggregate),
        Box::new(Paired),
    ])
    .summary(&experiment, &records)
    .unwrap();
    assert!(
        summary.contains(
            "Maps with cell costs are not compared: the scenario optima are unweighted lengths."
        ),
        "{summary}"
    );
    assert!(
        !summary.contains("| astar | arena.map | 12 | 12 | 5 |"),
        "{summary}"
    );
    assert!(
        summary.contains("| astar | 16room_000.map | 3 | 3 | 3 | 0.00 % |"),
        "{summary}"
    );
    let mut costs: Vec<f64> = astar_arena.iter().filter_map(|r| r.cost).collect();
    assert_eq!(costs.len(), 12);
    costs.sort_by(f64::total_cmp);
    let median = (costs[5] + costs[6]) / 2.0;
    let median = planner_report::aggregate::format_number(median);
    let row = summary
        .lines()
        .find(|l| l.starts_with("| astar | arena.map | 12 | 12 |"))
        .unwrap_or_else(|| panic!("{summary}"));
    let cells: Vec<&str> = row.split(" | ").collect();
    // Optimal, median and largest suboptimality, then the median cost.
    assert_eq!(cells[4], "-", "{row}");
    assert_eq!(&cells[9..12], ["-", "-", median.as_str()], "{row}");
    assert!(summary.contains("| Largest subopt. | Median cost | Peak heap |"));
    // The overall row: 16room's runs alone are compared, all optimal.
    let all = summary
        .lines()
        .find(|l| l.starts_with("| astar | all | 15 | 15 | 3 |"))
        .unwrap_or_else(|| panic!("{summary}"));
    assert!(all.contains("| 0.00 % | 0.00 % |"), "{all}");
    assert!(summary.contains("| Length ratio | Largest length ratio | Cost ratio |"));
    assert!(summary.contains("Length: the Euclidean length, unweighted"));
    // The cost ratio: bfs's cost over A*'s on arena's 12 problems (16room has no costs).
    let cost = |label: &str, problem: usize| {
        records
            .iter()
            .find(|r| r.planner == label && r.map == "arena.map" && r.problem == problem)
            .and_then(|r| r.cost)
            .unwrap()
    };
    let problems: Vec<usize> = astar_arena.iter().map(|r| r.problem).collect();
    let log_mean = problems
        .iter()
        .map(|&p| (cost("bfs", p) / cost("astar", p)).ln())
        .sum::<f64>()
        / problems.len() as f64;
    let paired = summary
        .lines()
        .find(|l| l.starts_with("| bfs | 15 | 15 |"))
        .unwrap_or_else(|| panic!("{summary}"));
    assert!(
        paired.ends_with(&format!("| {:.3} |", log_mean.exp())),
        "{paired}"
    );
    assert!(log_mean > 0.0, "{paired}");
    // The success chart of arena alone has no optimality bars: its optima do not apply.
    let mut arena = experiment.clone();
    arena.maps.retain(|m| m.name == "arena.map");
    let arena_records: Vec<_> = records
        .iter()
        .filter(|r| r.map == "arena.map")
        .cloned()
        .collect();
    let charts = planner_report::charts::charts(&arena, &arena_records.as_slice()).unwrap();
    let success = charts.iter().find(|c| c.file == "success.svg").unwrap();
    assert_eq!(success.title, "Success per planner");
}

/// The seeds table printed a median `n_expanded` with no decimals (`{:.0}`, which rounds
/// half to even): seeds expanding 57 and 58 cells showed 58 there beside 57.50 in the
/// per-map table. It prints medians as the other tables do now; the range stays whole.
#[test]
fn the_seeds_table_prints_median_expansions_as_the_other_tables() {
    use planner_report::aggregate::Aggregate;
    let map = root().join("maps/movingai/arena.map");
    let text = format!(
        "name = \"seeds\"\nrepeats = 2\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\n\
         pairs = [{{ start = [3, 1], goal = [46, 47] }}]\n\
         [planners.rrt]\nplanner = \"rrt\"\nsteer = \"eight\"\nmax_iterations = 3000\n",
        map.display().to_string()
    );
    let experiment = config::parse(&root().join("configs/seeds-test.toml"), &text).unwrap();
    let mut records = run_all(&experiment, &RunOptions::default()).unwrap();
    assert_eq!(records.len(), 2);
    // Two seeds' expansions, whose median is 59.5.
    for (record, expanded) in records.iter_mut().zip([57, 62]) {
        let mut counters = planner_api::Counters::new();
        counters.push("n_expanded".to_string(), expanded);
        record.counters = counters;
    }
    let (summary, _) = Renderer::new(vec![Box::new(Aggregate)])
        .summary(&experiment, &records)
        .unwrap();
    let row = summary
        .lines()
        .rfind(|l| l.starts_with("| rrt | arena.map | 2 | "))
        .unwrap_or_else(|| panic!("{summary}"));
    assert!(row.ends_with("| 59.50 | 57 - 62 |"), "{row}\n{summary}");
}

/// summary.md's head counts an invalid problem's record among its runs, and runs.csv has
/// it, while the Aggregates and the Repeats table leave it out; their texts said "over
/// every run" and "Success rate over all runs on the map" (4 runs, 100 % beside runs.csv's
/// 5 rows, 4 found). The texts now say that they count the runs of valid problems and that
/// invalid problems' records, listed under "Invalid problems (not run)", are not counted.
#[test]
fn the_tables_that_leave_invalid_problems_out_say_so() {
    use planner_report::{aggregate::Aggregate, repeats::Repeats};
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-invalid-texts");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n...@\n",
    )
    .unwrap();
    let text =
        "name = \"invalid\"\nrepeats = 2\nfigures = \"none\"\n[[maps]]\nfiles = [\"open.map\"]\n\
         pairs = [{ start = [0, 0], goal = [2, 2] }, { start = [0, 1], goal = [2, 1] }, \
         { start = [3, 3], goal = [0, 0] }]\n[planners.astar]\nplanner = \"astar\"\n";
    let experiment = config::parse(&dir.join("invalid.toml"), text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    // Two problems twice, and the invalid one's record.
    assert_eq!(records.len(), 5);
    let (summary, _) = Renderer::new(vec![Box::new(Repeats), Box::new(Aggregate)])
        .summary(&experiment, &records)
        .unwrap();
    assert!(summary.contains("Invalid problems (not run):"), "{summary}");
    // The numbers stay: 4 runs of valid problems, all found.
    assert!(
        summary.contains("| astar | open.map | 4 | 100.0 % |"),
        "{summary}"
    );
    assert!(
        summary.contains("| astar | open.map | 4 | 4 |"),
        "{summary}"
    );
    assert!(summary.contains("| astar | all | 4 | 4 |"), "{summary}");
    for text in [
        "Success rate over all runs of the map's valid problems (the records of invalid problems, listed under \"Invalid problems (not run)\", are not counted here)",
        "Per planner label and map, over every run of a valid problem, repeats included (the records of invalid problems, listed under \"Invalid problems (not run)\", are not counted here or in the overall rows)",
        "Overall, per planner label: every run of a valid problem on every map.",
    ] {
        assert!(summary.contains(text), "{text}\n{summary}");
    }
    assert!(!summary.contains("over all runs on the map"), "{summary}");
}

/// The records of a sweep, `times` over: a pass of more than `HELD_RUNS` records from a
/// small sweep.
struct Repeated<'r> {
    records: &'r [planner_runner::RunRecord],
    times: u64,
}

impl planner_runner::passes::RecordPasses for Repeated<'_> {
    fn pass(
        &self,
        visit: &mut dyn FnMut(&planner_runner::RunRecord),
    ) -> Result<(), planner_runner::RunnerError> {
        for _ in 0..self.times {
            self.records.iter().for_each(&mut *visit);
        }
        Ok(())
    }

    fn len(&self) -> u64 {
        self.records.len() as u64 * self.times
    }
}

/// A sweep of more than `HELD_RUNS` runs writes runs.parquet alone (without `outputs`), yet
/// summary.md said "every bucket is in runs.csv's `bucket` column" and "runs.csv's `cost`
/// column", and nothing said runs.csv and runs.json were not written. It now names
/// runs.parquet there and says which tables were left out and why; a smaller sweep's
/// summary names runs.csv and says nothing of the kind.
#[test]
fn a_large_sweeps_summary_names_runs_parquet_and_the_tables_left_out() {
    use planner_report::aggregate::Aggregate;
    let (experiment, records) = weighted_sweep();
    let renderer = Renderer::new(vec![Box::new(Aggregate)]);
    let times = planner_runner::sweep::HELD_RUNS / records.len() as u64 + 1;
    let large = Repeated {
        records: &records,
        times,
    };
    let (summary, _) = renderer
        .summary_passes(&experiment, &[], &large, None)
        .unwrap();
    for text in [
        "every bucket is in runs.parquet's `bucket` column",
        "(runs.parquet's `cost` column)",
        "runs.csv and runs.json are not written: this sweep's",
        "runs.parquet holds every run",
    ] {
        assert!(summary.contains(text), "{text}\n{summary}");
    }
    assert!(!summary.contains("runs.csv's"), "{summary}");
    let (summary, _) = renderer.summary(&experiment, &records).unwrap();
    for text in [
        "every bucket is in runs.csv's `bucket` column",
        "(runs.csv's `cost` column)",
    ] {
        assert!(summary.contains(text), "{text}\n{summary}");
    }
    assert!(!summary.contains("not written"), "{summary}");
}

/// The parameters table showed a label's budget as raw JSON
/// (`{"max_expansions":5000000,"max_time_ms":null}`) and left out the memory limit that
/// applies when the budget sets none (the runner's default, half the machine's memory).
/// It now reads `max_expansions = N, no time limit, max_memory_mb = M (default: half the
/// machine's memory)`, the default written `[memory]` when measurements are redacted.
#[test]
fn the_budget_column_is_readable_with_the_memory_limit_that_applies() {
    use planner_report::aggregate::{parameters, Measured};
    let text = format!(
        "name = \"budget\"\n[[maps]]\nfiles = [{:?}]\npairs = [{{ start = [0, 0], goal = [1, 1] }}]\n\
         [planners.a]\nplanner = \"astar\"\nbudget = {{ max_expansions = 5000000 }}\n\
         [planners.b]\nplanner = \"bfs\"\nbudget = {{ max_time_ms = 1500, max_memory_mb = 64 }}\n",
        root().join("maps/paper/map01.map").display().to_string()
    );
    let experiment = config::parse(&root().join("configs/budget-test.toml"), &text).unwrap();
    let default = planner_runner::run::default_max_memory_mb();
    let default_text = |mb: &str| match default {
        Some(_) => format!("max_memory_mb = {mb} (default: half the machine's memory)"),
        None => "no memory limit".to_string(),
    };
    let shown = parameters(&experiment, Measured::Shown);
    let mb = default.map(|mb| mb.to_string()).unwrap_or_default();
    let row_a = format!(
        "max_expansions = 5000000, no time limit, {} |",
        default_text(&mb)
    );
    let row_b = "no expansion limit, max_time_ms = 1500, max_memory_mb = 64 |";
    for row in [row_a.as_str(), row_b] {
        assert!(shown.contains(row), "{row}\n{shown}");
    }
    assert!(!shown.contains('{'), "{shown}");
    let redacted = parameters(&experiment, Measured::Redacted);
    // The same text on every machine (a snapshot's).
    let row_a = "max_expansions = 5000000, no time limit, max_memory_mb = [memory] (default: half the machine's memory) |";
    assert!(redacted.contains(row_a), "{redacted}");
    assert!(redacted.contains(row_b), "{redacted}");
}
