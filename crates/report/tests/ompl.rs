//! OMPL benchmark logs: the header's limits from the labels' budgets, each label's limits
//! among its common properties, and no time or memory for a problem that never ran.

use planner_report::ompl;
use planner_runner::provenance::{Machine, Provenance};
use planner_runner::{config, run_all, RunOptions};

/// The log of a sweep on an open 4 x 4 map with a blocked corner: two problems, the
/// second starting on the wall (so it never runs), and the labels of `planners`.
fn log(planners: &str) -> String {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("gridplan-ompl");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n...@\n",
    )
    .unwrap();
    let text = format!(
        "name = \"o\"\nompl = true\n[[maps]]\nfiles = [\"open.map\"]\n\
         pairs = [{{ start = [0, 0], goal = [2, 2] }}, {{ start = [3, 3], goal = [0, 0] }}]\n\
         {planners}"
    );
    let experiment = config::parse(&dir.join("o.toml"), &text).unwrap();
    let records = run_all(&experiment, &RunOptions::default()).unwrap();
    let machine = Machine {
        commit: None,
        host: None,
    };
    let provenance = Provenance::collect(&experiment.source, 1, &machine);
    let logs = ompl::logs(&experiment, &records, &provenance, 1.0);
    assert_eq!(logs.len(), 1);
    String::from_utf8(logs[0].contents.clone()).unwrap()
}

/// The header said `0 MB per run` whatever the budgets, and took the time limit from the
/// first label alone.
#[test]
fn the_header_gives_the_largest_limit_the_labels_set() {
    let text = log(
        "[planners.a]\nplanner = \"astar\"\nbudget = { max_time_ms = 1500, max_memory_mb = 64 }\n\
         [planners.b]\nplanner = \"bfs\"\nbudget = { max_time_ms = 2500, max_memory_mb = 32, max_expansions = 99 }\n",
    );
    assert!(text.contains("\n2.5 seconds per run\n"), "{text}");
    assert!(text.contains("\n64 MB per run\n"), "{text}");
    for property in [
        "budget.max_time_s = 1.5",
        "budget.max_memory_mb = 64",
        "budget.max_time_s = 2.5",
        "budget.max_memory_mb = 32",
        "budget.max_expansions = 99",
    ] {
        assert!(
            text.contains(&format!("\n{property}\n")),
            "{property}: {text}"
        );
    }
    // A label without a limit: the experiment has none.
    let text = log(
        "[planners.a]\nplanner = \"astar\"\nbudget = { max_time_ms = 1500, max_memory_mb = 64 }\n\
         [planners.b]\nplanner = \"bfs\"\n",
    );
    assert!(
        text.contains("\n0 seconds per run\n0 MB per run\n"),
        "{text}"
    );
}

/// A problem that never ran (its start on a wall) was a run of time 0 and memory 0,
/// pulling Planner Arena's distributions down; its time and memory are now empty (NULL).
#[test]
fn a_problem_that_never_ran_has_no_time_or_memory() {
    let text = log("[planners.a]\nplanner = \"astar\"\n");
    let runs: Vec<Vec<&str>> = text
        .lines()
        .filter(|line| line.ends_with("; "))
        .map(|line| line.split("; ").collect())
        .collect();
    assert_eq!(runs.len(), 2, "{text}");
    // problem, repeat, seed, time, solved, memory, ...
    let (ran, never) = (&runs[0], &runs[1]);
    assert_eq!((ran[0], never[0]), ("1", "2"), "{text}");
    assert!(
        ran[3].parse::<f64>().is_ok() && ran[5].parse::<f64>().is_ok(),
        "{text}"
    );
    assert_eq!((never[3], never[4], never[5]), ("", "0", ""), "{text}");
}
