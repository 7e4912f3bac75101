//! The `paired` section: per-problem ratios against a baseline, checked by hand on records
//! whose times, counters and outcomes the test sets.

use planner_report::{generic_section, paired, Renderer};
use planner_runner::record::{RunRecord, RunStatus};
use planner_runner::sweep::Render;
use planner_runner::{config, run_all, RunOptions};

/// Three labels, three repeats, four problems on an open 4 x 4 map (the fourth starts on
/// its one blocked cell, so it is invalid for every label).
fn experiment(sections: &str) -> config::Experiment {
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir =
        std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-paired-{call}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("open.map"),
        "type octile\nheight 4\nwidth 4\nmap\n....\n....\n....\n...@\n",
    )
    .unwrap();
    let text = format!(
        "name = \"p\"\nrepeats = 3\n{sections}[[maps]]\nfiles = [\"open.map\"]\n\
         pairs = [{{ start = [0, 0], goal = [2, 2] }}, {{ start = [0, 0], goal = [2, 0] }}, \
         {{ start = [0, 1], goal = [2, 1] }}, {{ start = [3, 3], goal = [0, 0] }}]\n\
         [planners.base]\nplanner = \"astar\"\n[planners.other]\nplanner = \"bfs\"\n\
         [planners.none]\nplanner = \"dfs\"\n"
    );
    let experiment = config::parse(&dir.join("p.toml"), &text).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    experiment
}

/// The records of `experiment` with the values the hand computation below uses.
fn records(experiment: &config::Experiment) -> Vec<RunRecord> {
    let mut records = run_all(experiment, &RunOptions::default()).unwrap();
    // The invalid problem is recorded once per label, not per repeat.
    assert_eq!(records.len(), 3 * 3 * 3 + 3);
    // (problem, label): times per repeat, n_expanded, length.
    let values = |problem: usize, label: &str| -> ([f64; 3], u64, f64) {
        match (problem, label) {
            (1, "base") => ([1.0, 2.0, 3.0], 10, 4.0),
            (1, _) => ([1.0, 1.0, 1.0], 5, 4.0),
            (2, "base") => ([4.0, 4.0, 4.0], 10, 4.0),
            (2, _) => ([8.0, 8.0, 8.0], 40, 5.0),
            _ => ([1.0, 1.0, 1.0], 7, 2.0),
        }
    };
    for r in &mut records {
        if r.status == RunStatus::InvalidProblem {
            continue;
        }
        let (times, expanded, length) = values(r.problem, &r.planner);
        r.time_ms = times[r.repeat as usize];
        r.counters.push("n_expanded", expanded);
        r.length = Some(length);
        r.status = RunStatus::Found;
        // `other` fails problem 3 in one repeat; `none` has no run but problem 1's.
        if r.problem == 3 && r.planner == "other" && r.repeat == 1 {
            r.status = RunStatus::NoPath;
            r.length = None;
        }
    }
    records.retain(|r| r.planner != "none" || r.problem == 1);
    records
}

/// Problem 1: time 1 / median(1, 2, 3) = 0.5, expansions 5 / 10, lengths equal. Problem 2:
/// time 8 / 4 = 2, expansions 40 / 10 = 4, length 5 / 4 = 1.25. Problem 3: `other` failed
/// once, so only the baseline solved it. Geometric means: time sqrt(0.5 * 2) = 1 with
/// logarithms -+ ln 2, so s / sqrt(2) = ln 2 and the interval is exp(-+ 12.7062 ln 2)
/// (t(0.975, 1) = 12.706204736174705): 1.496e-4 to 6683 (Python: math.exp(12.706204736174705 * math.log(2)) = 6682.65); expansions sqrt(0.5 * 4) =
/// 1.414; lengths sqrt(1.25) = 1.118.
#[test]
fn ratios_against_the_first_label_by_hand() {
    let experiment = experiment("");
    let records = records(&experiment);
    let half = 12.706204736174705 * 2f64.ln();
    assert_eq!(format!("{:.2e}", (-half).exp()), "1.50e-4");
    assert_eq!(format!("{:.3}", half.exp()), "6682.651");
    let table = paired::table(&experiment, &records.as_slice(), None).unwrap();
    let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| ")).collect();
    assert_eq!(
        rows,
        [
            "| Planner | Problems | Solved by both | Only planner | Only baseline | Expansions ratio | Fewer expansions | Time ratio (95 % interval) | Less time | Length ratio | Largest length ratio |",
            "| other | 3 | 2 | 0 | 1 | 1.414 | 1 of 2 | 1.000 (1.50e-4 to 6682.651) | 1 of 2 | 1.118 | 1.250 |",
            "| none | 1 | 1 | 0 | 0 | 0.500 | 1 of 1 | 0.500 | 1 of 1 | 1.000 | 1.000 |",
        ],
        "{table}"
    );
    assert!(table.contains("Each label against `base`"), "{table}");
}

/// The `baseline` option turns the ratios round; `none`, which ran problem 1 only, is
/// compared on it (the baseline's 1 over its 1: ratio 1, no fewer expansions).
#[test]
fn the_baseline_option_names_the_label_compared_with() {
    let experiment = experiment("sections = [{ name = \"paired\", baseline = \"other\" }]\n");
    let records = records(&experiment);
    let renderer = Renderer::new(vec![generic_section("paired").unwrap()]);
    renderer.check(&experiment).unwrap();
    let (summary, _) = renderer.summary(&experiment, &records).unwrap();
    let rows: Vec<&str> = summary
        .lines()
        .filter(|l| l.starts_with("| base") || l.starts_with("| none"))
        .collect();
    assert_eq!(
        rows,
        [
            "| base | 3 | 2 | 1 | 0 | 0.707 | 1 of 2 | 1.000 (1.50e-4 to 6682.651) | 1 of 2 | 0.894 | 1.000 |",
            "| none | 1 | 1 | 0 | 0 | 1.000 | 0 of 1 | 1.000 | 0 of 1 | 1.000 | 1.000 |",
        ],
        "{summary}"
    );
    assert!(summary.contains("Each label against `other`"), "{summary}");
}

/// A baseline that is not a label, or not a string, and an unknown option are config
/// errors at the `sections` key.
#[test]
fn a_baseline_that_is_no_label_is_refused() {
    let renderer = Renderer::new(vec![generic_section("paired").unwrap()]);
    for (options, expected) in [
        (
            "baseline = \"astar\"",
            "section \"paired\": no planner label \"astar\", expected one of base, other, none",
        ),
        (
            "baseline = 1",
            "section \"paired\": `baseline` is a planner label of the config, a string",
        ),
        (
            "against = \"base\"",
            "section \"paired\" takes no option `against` (only `baseline`)",
        ),
    ] {
        let experiment = experiment(&format!(
            "sections = [{{ name = \"paired\", {options} }}]\n"
        ));
        let error = renderer.check(&experiment).unwrap_err();
        assert!(error.to_string().contains(expected), "{error}");
    }
}

/// The paired charts: per problem solved by both, the label's median expansions and time
/// against the baseline's on log-log axes (problem 1: expansions (10, 5) for both labels;
/// problem 2: (10, 40) for `other`), one circle per point; past
/// `PAIRED_POINTS` problems a label, 1 in k is drawn and the legend says so.
#[test]
fn the_paired_charts_draw_one_point_per_problem_solved_by_both() {
    let experiment = experiment("");
    let records = records(&experiment);
    let charts = planner_report::charts::charts(&experiment, &records.as_slice()).unwrap();
    let chart = |file: &str| charts.iter().find(|c| c.file == file).unwrap().svg.clone();
    for file in ["paired-expansions.svg", "paired-time.svg"] {
        let svg = chart(file);
        roxmltree::Document::parse(&svg).unwrap();
        // Three points (the key beside the plot marks its labels with squares).
        assert_eq!(svg.matches("<circle").count(), 3, "{file}");
        assert!(svg.contains("other (2 problems)") && svg.contains("none (1 problem)"));
    }
    // 2,500 problems solved by both: 1 in 2 drawn.
    let mut many = Vec::new();
    for k in 0..2500 {
        for r in records
            .iter()
            .filter(|r| r.problem == 1 && r.planner != "none")
        {
            let mut r = r.clone();
            r.problem = 10 + k;
            many.push(r);
        }
    }
    let charts = planner_report::charts::charts(&experiment, &many.as_slice()).unwrap();
    let svg = &charts
        .iter()
        .find(|c| c.file == "paired-time.svg")
        .unwrap()
        .svg;
    // 1,250 points.
    assert_eq!(svg.matches("<circle").count(), 1250);
    assert!(svg.contains("other (1 in 2 of 2500 problems)"), "{svg}");
    assert!(svg.contains("at most 2000 problems a label drawn"));
}
