//! `gridplan compare OLD NEW`: two results directories written by real sweeps, compared
//! run by run.

use std::path::{Path, PathBuf};

use planner_report::compare::compare;
use planner_report::Renderer;
use planner_runner::sweep::{experiment, SweepArgs};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A scratch directory for one test, emptied first.
fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gridplan-compare-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs a config of two labels (A* with `heuristic`, BFS, and `extra` labels) on seed
/// 000's map01 and map02, 2 repeats, into `dir/name`.
fn sweep(dir: &Path, name: &str, heuristic: &str, extra: &str) -> PathBuf {
    let maps = root().join("maps/paper");
    let config = dir.join(format!("{name}.toml"));
    std::fs::write(
        &config,
        format!(
            "name = \"{name}\"\nrepeats = 2\n[[maps]]\nfiles = [{:?}, {:?}]\nproblems = \"corners\"\n\
             [planners.astar]\nplanner = \"astar\"\nheuristic = \"{heuristic}\"\n\
             [planners.bfs]\nplanner = \"bfs\"\n{extra}",
            maps.join("map01.map").display().to_string(),
            maps.join("map02.map").display().to_string(),
        ),
    )
    .unwrap();
    let output = dir.join(name);
    let render = Renderer::new(Vec::new());
    experiment(&SweepArgs {
        threads: 1,
        output: Some(&output),
        ..SweepArgs::new(&config, &render)
    })
    .unwrap();
    output
}

#[test]
fn the_same_sweep_twice_is_the_same() {
    let dir = scratch("same");
    let (old, new) = (
        sweep(&dir, "old", "manhattan", ""),
        sweep(&dir, "new", "manhattan", ""),
    );
    let c = compare(&old, &new, 10).unwrap();
    // 2 maps x 1 problem x 2 labels x 2 repeats.
    assert_eq!((c.runs, c.both, c.differing), ([8, 8], 8, 0));
    assert!(c.same() && c.examples.is_empty());
    // Times per label over the 2 problems both ran.
    let labels: Vec<(&str, u64)> = c
        .times
        .iter()
        .map(|t| (t.label.as_str(), t.problems))
        .collect();
    assert_eq!(labels, [("astar", 2), ("bfs", 2)]);
    let text = c.text();
    assert!(text.contains("the same in all 8 runs in both"), "{text}");
    // Each side's provenance: where and how its times were measured.
    let first = format!(
        "OLD {}: 8 runs (gridplan {}",
        old.display(),
        env!("CARGO_PKG_VERSION")
    );
    assert!(text.starts_with(&first), "{text}");
    assert!(text.contains(", 1 threads)\nNEW "), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A* with the zero heuristic (Dijkstra) expands more than with Manhattan on both maps:
/// its 4 runs differ, listed once a problem with the counters that changed; BFS's do not;
/// a label only NEW has is counted apart.
#[test]
fn changed_runs_are_listed_by_field_and_extra_runs_counted() {
    let dir = scratch("changed");
    let old = sweep(&dir, "old", "manhattan", "");
    let new = sweep(&dir, "new", "zero", "[planners.dfs]\nplanner = \"dfs\"\n");
    let c = compare(&old, &new, 10).unwrap();
    assert_eq!((c.runs, c.both, c.differing), ([8, 12], 8, 4));
    assert!(!c.same());
    assert_eq!(c.examples.len(), 2, "{:?}", c.examples);
    for example in &c.examples {
        assert!(
            example.run.starts_with("label \"astar\", map \"map0"),
            "{}",
            example.run
        );
        let fields: Vec<&str> = example.fields.iter().map(|f| f.0.as_str()).collect();
        assert!(fields.contains(&"counters.n_expanded"), "{fields:?}");
        // The old and new values are the records' own.
        let expanded = example
            .fields
            .iter()
            .find(|f| f.0 == "counters.n_expanded")
            .unwrap();
        assert_ne!(expanded.1, expanded.2);
    }
    let text = c.text();
    assert!(
        text.contains("runs in both: 8, only in OLD: 0, only in NEW: 4"),
        "{text}"
    );
    assert!(text.contains("4 of 8 runs in both differ"), "{text}");
    // The same as one JSON object.
    let json = c.json();
    assert_eq!(
        (
            &json["both"],
            &json["only_new"],
            &json["differing"],
            &json["same"]
        ),
        (&8.into(), &4.into(), &4.into(), &false.into())
    );
    assert_eq!(json["new"]["runs"], 12);
    assert_eq!(json["examples"].as_array().map(Vec::len), Some(2));
    let field = &json["examples"][0]["fields"][0];
    assert_eq!(field.as_array().map(Vec::len), Some(3), "{field}");
    assert_eq!(json["times"][0]["label"], "astar");
    assert_eq!(json["times"][0]["problems"], 2);
    // With no examples asked for, the counts alone.
    assert!(compare(&old, &new, 0).unwrap().examples.is_empty());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Labels, map names and directory names with line breaks stay on their lines of the text:
/// written escaped, never as a line of their own that could pass for the report's.
#[test]
fn names_with_line_breaks_cannot_add_lines() {
    let dir = scratch("lines");
    let maps = dir.join("maps");
    std::fs::create_dir_all(&maps).unwrap();
    std::fs::copy(
        root().join("maps/paper/map01.map"),
        maps.join("new\nfake: 1.000 map.map"),
    )
    .unwrap();
    let run = |name: &str, heuristic: &str| {
        let config = dir.join(format!("{name}.toml"));
        std::fs::write(
            &config,
            format!(
                "name = \"lines\"\n[[maps]]\nfiles = [\"maps/*.map\"]\nproblems = \"corners\"\n\
                 [planners.\"a\\nfake: 1.000 label\"]\nplanner = \"astar\"\nheuristic = \"{heuristic}\"\n"
            ),
        )
        .unwrap();
        let output = dir.join(format!("{name}\nfake: dir"));
        let render = Renderer::new(Vec::new());
        experiment(&SweepArgs {
            threads: 1,
            output: Some(&output),
            ..SweepArgs::new(&config, &render)
        })
        .unwrap();
        output
    };
    let (old, new) = (run("old", "manhattan"), run("new", "zero"));
    let c = compare(&old, &new, 10).unwrap();
    assert_eq!((c.both, c.differing, c.examples.len()), (1, 1, 1));
    let text = c.text();
    // Two provenance lines, the counts, the differing runs' head and its one run, the times'
    // head and its one label: nothing starts with the names' `fake`.
    assert_eq!(text.lines().count(), 7, "{text}");
    assert!(!text.lines().any(|line| line.starts_with("fake")), "{text}");
    assert!(
        text.contains("label \"a\\nfake: 1.000 label\", map \"new\\nfake: 1.000 map.map\""),
        "{text}"
    );
    assert!(text.contains("old\\nfake: dir: 1 runs"), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_directory_that_is_not_results_is_refused() {
    let dir = scratch("refused");
    let old = sweep(&dir, "old", "manhattan", "");
    let error = compare(&old, &dir.join("missing"), 10)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("missing") && error.contains("does not exist"),
        "{error}"
    );
    let error = compare(&dir, &old, 10).unwrap_err().to_string();
    assert!(error.contains("has no results marker"), "{error}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A results directory whose records.stream was cut (to its header, to half its bytes) is
/// refused with an error naming the file, of the class `gridplan report` gives the same
/// damage (so the same exit status and Python exception), never read as the runs it holds
/// (which compare would report as runs only in the other directory). The class is that of
/// results that are not complete (exit 5, `OutputError`): it was `Other`, exit 1, which
/// `compare` also gives for "the runs differ". Garbage in place of records is refused
/// alike, by both.
#[test]
fn a_cut_records_stream_is_refused_as_report_refuses_it() {
    use planner_runner::ErrorClass;
    let dir = scratch("cut");
    let old = sweep(&dir, "old", "manhattan", "");
    let new = sweep(&dir, "new", "manhattan", "");
    let stream = new.join("records.stream");
    let whole = std::fs::read(&stream).unwrap();
    let header = whole.iter().position(|&b| b == b'\n').unwrap() + 1;
    let garbage = [&whole[..header], &b"\x00garbage, not records\n"[..]].concat();
    let cuts = [
        whole[..header].to_vec(),
        // Halfway through the records (the header holds each setting's hash: over half
        // of this small stream).
        whole[..header + (whole.len() - header) / 2].to_vec(),
        whole[..whole.len() - 1].to_vec(),
        garbage,
    ];
    for (i, cut) in cuts.iter().enumerate() {
        std::fs::write(&stream, cut).unwrap();
        for (a, b) in [(&old, &new), (&new, &old)] {
            let error = compare(a, b, 10).unwrap_err();
            let text = error.to_string();
            assert!(
                text.starts_with("compare: ") && text.contains(&stream.display().to_string()),
                "{text}"
            );
            if i < 3 {
                let held = format!("{} holds ", stream.display());
                assert!(
                    text.contains(&held) && text.ends_with(" of 8 runs"),
                    "{text}"
                );
            }
            let render = Renderer::new(Vec::new());
            let report = planner_runner::sweep::report(&new, None, &render).unwrap_err();
            assert!(report.to_string().starts_with("report: "), "{report}");
            assert_eq!(error.class(), ErrorClass::Output, "{error}");
            assert_eq!(error.class(), report.class(), "{error} / {report}");
        }
    }
    // The whole stream again: compared.
    std::fs::write(&stream, &whole).unwrap();
    assert!(compare(&old, &new, 10).unwrap().same());
    std::fs::remove_dir_all(&dir).unwrap();
}
