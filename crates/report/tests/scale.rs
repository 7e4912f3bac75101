//! A sweep of more than `HELD_RUNS` runs over as many distinct problems keeps its report's
//! memory bounded: `paths = "figures"` (the default) keeps a path per problem and label in
//! paths.jsonl, which the runner now writes from a pass over the stream; the report used
//! to collect every such record, path included, before writing it. Heap bytes are counted
//! on the calling thread (the runner's counting allocator, installed for this test binary;
//! other tests' threads keep their own counts), where the sweep's results are written.

use std::fmt::Write as _;
use std::path::Path;

use planner_report::Renderer;
use planner_runner::alloc;
use planner_runner::sweep::{self, SweepArgs, HELD_RUNS};

#[global_allocator]
static GLOBAL: alloc::Counting = alloc::Counting;

#[test]
fn a_large_sweeps_paths_are_written_from_a_pass() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-scale");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Every (start, goal) pair of a free 20 x 20 map, HELD_RUNS + 4 of them.
    let side = 20u32;
    let mut map = format!("type octile\nheight {side}\nwidth {side}\nmap\n");
    for _ in 0..side {
        map.push_str(&".".repeat(side as usize));
        map.push('\n');
    }
    std::fs::write(dir.join("free.map"), map).unwrap();
    let n = HELD_RUNS as usize + 4;
    let cells: Vec<(u32, u32)> = (0..side)
        .flat_map(|y| (0..side).map(move |x| (x, y)))
        .collect();
    let mut scen = String::from("version 1\n");
    for (s, g) in cells
        .iter()
        .flat_map(|&s| cells.iter().map(move |&g| (s, g)))
        .take(n)
    {
        let (dx, dy) = (s.0.abs_diff(g.0), s.1.abs_diff(g.1));
        let optimal = f64::from(dx.max(dy)) + (2f64.sqrt() - 1.0) * f64::from(dx.min(dy));
        let _ = writeln!(
            scen,
            "0\tfree.map\t{side}\t{side}\t{}\t{}\t{}\t{}\t{optimal:.8}",
            s.0, s.1, g.0, g.1
        );
    }
    std::fs::write(dir.join("free.map.scen"), scen).unwrap();
    std::fs::write(
        dir.join("scale.toml"),
        "name = \"scale\"\nfigures = \"none\"\noutputs = [\"csv\"]\n[[maps]]\nfiles = [\"free.map\"]\n\
         scen = \"free.map.scen\"\n[planners.a]\nplanner = \"astar\"\nmoves = 8\nheuristic = \"octile\"\n",
    )
    .unwrap();
    let render = Renderer::new(Vec::new());
    let config = dir.join("scale.toml");
    let out = dir.join("out");
    let mut args = SweepArgs::new(&config, &render);
    args.output = Some(&out);
    args.threads = 2;
    let baseline = alloc::start();
    let report = sweep::experiment(&args).unwrap();
    let peak = alloc::peak_since_start(baseline);
    assert_eq!(report.n_runs, n);
    let paths = std::fs::read_to_string(out.join("paths.jsonl")).unwrap();
    assert_eq!(paths.lines().count(), n);
    let first: serde_json::Value = serde_json::from_str(paths.lines().next().unwrap()).unwrap();
    assert_eq!(
        (first["problem"].as_u64(), first["repeat"].as_u64()),
        (Some(1), Some(0))
    );
    // The paths alone are 14 MB of JSON, their records more than 60 MB held.
    assert!(peak < 40 << 20, "peak {peak} bytes on the writing thread");
}

/// A sweep of more labels than a chart draws ([`planner_report::charts::MAX_CHART_LABELS`]):
/// the charts of labels draw the first ones and say so; their files stay the size of a
/// chart (10,000 labels made 11 MB box plots).
#[test]
fn charts_of_many_labels_draw_the_first_and_say_so() {
    use planner_report::charts::MAX_CHART_LABELS;
    let n = MAX_CHART_LABELS + 30;
    let (out, weights) = many_labels("report-many-labels", n);
    let note = format!("the first {MAX_CHART_LABELS} of {n} labels");
    for chart in ["time-box.svg", "expansions-box.svg", "success.svg"] {
        let svg = std::fs::read_to_string(out.join("charts").join(chart)).unwrap();
        assert!(svg.contains(&note), "{chart}");
        // Each drawn label's name once (in the key); the last label's is not there.
        assert!(svg.contains("a[weight=1.99]"), "{chart}");
        let last = format!("a[weight={}]", weights[n - 1]);
        assert!(!svg.contains(&last), "{chart}: {last}");
    }
    let paired = std::fs::read_to_string(out.join("charts/paired-expansions.svg")).unwrap();
    assert!(paired.contains(&format!("the first {MAX_CHART_LABELS} of {} labels", n - 1)));
    // summary.md's tables keep every label.
    let summary = std::fs::read_to_string(out.join("summary.md")).unwrap();
    assert!(summary.contains(&format!("a[weight={}]", weights[n - 1])));
}

/// Every `<text>` of an SVG: its x, y and content.
fn svg_texts(svg: &str) -> Vec<(f64, f64, String)> {
    let attr = |tag: &str, name: &str| -> f64 {
        let at = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
        tag[at..].split('"').next().unwrap().parse().unwrap()
    };
    svg.split("<text")
        .skip(1)
        .map(|rest| {
            let (tag, after) = rest.split_once('>').unwrap();
            let content = after.split("</text>").next().unwrap().trim().to_string();
            (attr(tag, "x"), attr(tag, "y"), content)
        })
        .collect()
}

/// Charts of 40 labels (the probe's sweep of weights and tie rules): the box plots' and
/// success chart's x axis numbers the labels, at most 21 numbers written, and a key beside
/// the plot says which label each number is, one line each, the page tall enough for all
/// (the legend covered the boxes, ran past the page's 520 px, and the names along x
/// overlapped into a smear).
#[test]
fn charts_of_many_labels_key_every_label_beside_the_plot() {
    let n = 40;
    let (out, weights) = many_labels("report-keyed-labels", n);
    for chart in ["time-box.svg", "expansions-box.svg", "success.svg"] {
        let svg = std::fs::read_to_string(out.join("charts").join(chart)).unwrap();
        let height: f64 = svg
            .split("height=\"")
            .nth(1)
            .and_then(|h| h.split('"').next())
            .and_then(|h| h.parse().ok())
            .unwrap();
        let texts = svg_texts(&svg);
        for (i, weight) in weights.iter().enumerate() {
            // The label shows the weight as a number (1.00 is 1.0).
            let shown: f64 = weight.parse().unwrap();
            let line = format!("{} a[weight={shown:?}]", i + 1);
            let found: Vec<_> = texts
                .iter()
                .filter(|(_, _, t)| t.starts_with(&line))
                .collect();
            assert_eq!(found.len(), 1, "{chart}: {line}");
            let (x, y, _) = found[0];
            assert!(
                *x > 1000.0 - 330.0 && *y < height,
                "{chart}: {line} at ({x}, {y})"
            );
        }
        // The numbers along x: category numbers only, every k-th.
        let numbers = texts
            .iter()
            .filter(|(_, _, t)| t.parse::<usize>().is_ok_and(|k| (1..=n).contains(&k)))
            .count();
        assert!(
            (10..=21).contains(&numbers),
            "{chart}: {numbers} numbers along x"
        );
    }
}

/// A sweep of `n` A* labels (weights 1.00, 1.01, ...) on a tiny map into `name`'s scratch
/// directory: its output directory and the weights.
fn many_labels(name: &str, n: usize) -> (std::path::PathBuf, Vec<String>) {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("tiny.map"),
        "type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n",
    )
    .unwrap();
    let weights: Vec<String> = (0..n)
        .map(|i| format!("{:.2}", 1.0 + i as f64 / 100.0))
        .collect();
    std::fs::write(
        dir.join("many.toml"),
        format!(
            "name = \"many\"\nfigures = \"none\"\noutputs = [\"csv\"]\n[[maps]]\nfiles = [\"tiny.map\"]\n\
             pairs = [{{ start = [0, 0], goal = [3, 2] }}]\n[planners.a]\nplanner = \"astar\"\n\
             weight = [{}]\n",
            weights.join(", ")
        ),
    )
    .unwrap();
    let render = Renderer::new(Vec::new());
    let config = dir.join("many.toml");
    let out = dir.join("out");
    let mut args = SweepArgs::new(&config, &render);
    args.output = Some(&out);
    sweep::experiment(&args).unwrap();
    (out, weights)
}
