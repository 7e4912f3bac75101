//! Figures parsed back as XML: well-formedness, element counts on hand-made grids,
//! geometry of any-angle paths, determinism, escaping, layout choice and size bounds.

use planner_api::{Cell, Grid, Path};
use planner_figures::{
    draw_comparison, draw_path, draw_timeline, Layer, Layout, Marker, StepLabels, Style,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn cells(list: &[(u32, u32)]) -> Path {
    Path::new(list.iter().map(|&c| c.into()).collect())
}

/// Parses `svg` (panicking with the parser's message if it is not well-formed XML) and
/// returns, for each class name asked for, how many elements carry it.
fn counts(svg: &str, classes: &[&str]) -> Vec<usize> {
    let doc = roxmltree::Document::parse(svg).unwrap_or_else(|e| panic!("bad XML: {e}"));
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    classes
        .iter()
        .map(|class| {
            doc.descendants()
                .filter(|n| n.attribute("class") == Some(*class))
                .count()
        })
        .collect()
}

/// The texts of the elements of class `class`, in document order.
fn texts(svg: &str, class: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.attribute("class") == Some(class))
        .map(|n| {
            n.descendants()
                .filter(|t| t.is_text())
                .filter_map(|t| t.text())
                .collect::<String>()
        })
        .collect()
}

/// The number of `rect` children of the obstacle groups.
fn obstacle_rects(svg: &str) -> usize {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("obstacles"))
        .flat_map(|g| g.children().filter(|c| c.has_tag_name("rect")))
        .count()
}

/// The `points` of every polyline of class `path`, as (x, y) pairs.
fn polylines(svg: &str) -> Vec<Vec<(f64, f64)>> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("class") == Some("path"))
        .map(|n| {
            n.attribute("points")
                .unwrap()
                .split(' ')
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect()
        })
        .collect()
}

fn small_grid() -> Grid {
    Grid::from_ascii(
        "
        ....
        .##.
        ...#
        #...
        ",
    )
    .unwrap()
}

const CLASSES: [&str; 5] = ["step", "arrow", "endpoint", "panel", "layer"];

fn check(svg: &str, expect: [usize; 5]) {
    assert_eq!(counts(svg, &CLASSES).as_slice(), expect.as_slice(), "{svg}");
}

#[test]
fn one_path_on_a_hand_made_grid() {
    let grid = small_grid();
    // Down, down, right, right, down, right: 7 cells, 6 moves.
    let path = cells(&[(0, 0), (0, 1), (0, 2), (1, 2), (2, 2), (2, 3), (3, 3)]);
    let layer = Layer::new("astar", Some(&path), "found, D=6 T=3 Score=9");
    let (s, g) = (Cell::new(0, 0), Cell::new(3, 3));
    let svg = draw_path(&grid, s, g, &layer, "hand-made", &Style::default());
    // Labels 1..5 (0 and 6 are S and G), one arrow per move, S and G, one panel, one layer.
    check(&svg, [5, 6, 2, 1, 1]);
    assert_eq!(texts(&svg, "step"), ["1", "2", "3", "4", "5"]);
    // Blocked: row 1 columns 1-2, (3, 2), (0, 3): three runs, none merge.
    assert_eq!(obstacle_rects(&svg), 3);
    assert_eq!(texts(&svg, "label"), ["astar"]);
    assert_eq!(texts(&svg, "note"), ["found, D=6 T=3 Score=9"]);
    assert_eq!(texts(&svg, "title"), ["hand-made"]);
    // The polyline keeps only the corners: (0,0) (0,2) (2,2) (2,3) (3,3).
    let line = &polylines(&svg)[0];
    let (x0, y0) = line[0];
    let rel: Vec<(f64, f64)> = line
        .iter()
        .map(|&(x, y)| ((x - x0) / 48.0, (y - y0) / 48.0))
        .collect();
    assert_eq!(rel, [(0., 0.), (0., 2.), (2., 2.), (2., 3.), (3., 3.)]);

    let never = Style {
        step_labels: StepLabels::Never,
        arrows: false,
        ..Style::default()
    };
    check(
        &draw_path(&grid, s, g, &layer, "hand-made", &never),
        [0, 0, 2, 1, 1],
    );
}

#[test]
fn any_angle_segments_go_through_the_listed_centres() {
    let grid = Grid::new(6, 5).unwrap();
    // Two long segments and a reversal-free bend; (3, 1) is the only labelled cell.
    let path = cells(&[(0, 0), (3, 1), (5, 4)]);
    let layer = Layer::new("theta", Some(&path), "");
    let svg = draw_path(
        &grid,
        Cell::new(0, 0),
        Cell::new(5, 4),
        &layer,
        "any-angle",
        &Style::default(),
    );
    check(&svg, [1, 2, 2, 1, 1]);
    assert_eq!(texts(&svg, "step"), ["1"]);
    let line = &polylines(&svg)[0];
    let (x0, y0) = line[0];
    let rel: Vec<(f64, f64)> = line
        .iter()
        .map(|&(x, y)| ((x - x0) / 48.0, (y - y0) / 48.0))
        .collect();
    assert_eq!(rel, [(0., 0.), (3., 1.), (5., 4.)]);
}

#[test]
fn output_is_deterministic() {
    let grid = small_grid();
    let a = cells(&[(0, 0), (1, 0), (2, 0), (3, 0), (3, 1)]);
    let b = cells(&[(0, 0), (0, 1), (0, 2), (1, 2), (2, 2)]);
    let layers = [
        Layer::new("a", Some(&a), "x"),
        Layer::new("b", Some(&b), "y"),
    ];
    let (s, g) = (Cell::new(0, 0), Cell::new(3, 3));
    for layout in [Layout::Panels, Layout::Overlay] {
        let style = Style {
            layout,
            ..Style::default()
        };
        let first = draw_comparison(&grid, s, g, &layers, "t", &style);
        assert_eq!(first, draw_comparison(&grid, s, g, &layers, "t", &style));
        let swapped = [layers[1].clone(), layers[0].clone()];
        assert_ne!(first, draw_comparison(&grid, s, g, &swapped, "t", &style));
    }
    let markers = [Marker {
        cell: Cell::new(3, 1),
        label: "B1".into(),
    }];
    let t = draw_timeline(&grid, &a, &markers, "t", &Style::default());
    assert_eq!(
        t,
        draw_timeline(&grid, &a, &markers, "t", &Style::default())
    );
}

#[test]
fn user_text_is_escaped() {
    let grid = small_grid();
    let path = cells(&[(0, 0), (1, 0)]);
    let label = "<dfs> & \"co\" 'x'\u{1}\u{7f}";
    let layer = Layer::new(label, Some(&path), "</text><script>");
    let svg = draw_path(
        &grid,
        Cell::new(0, 0),
        Cell::new(3, 3),
        &layer,
        "a < b && c > d",
        &Style::default(),
    );
    // Parses, and the texts read back as written, control characters as spaces.
    assert_eq!(texts(&svg, "label"), ["<dfs> & \"co\" 'x'  "]);
    assert_eq!(texts(&svg, "note"), ["</text><script>"]);
    assert_eq!(texts(&svg, "title"), ["a < b && c > d"]);
    assert_eq!(counts(&svg, &["script"]), [0]);
    let markers = [Marker {
        cell: Cell::new(1, 0),
        label: "<&>".into(),
    }];
    let t = draw_timeline(&grid, &path, &markers, "<t>", &Style::default());
    assert_eq!(texts(&t, "marker-label"), ["<&>"]);
}

#[test]
fn layout_follows_map_size_and_override() {
    let small = Grid::new(12, 12).unwrap();
    let large = Grid::new(65, 40).unwrap();
    let a = cells(&[(0, 0), (1, 0), (2, 0)]);
    let b = cells(&[(0, 0), (0, 1), (0, 2)]);
    let layers = [
        Layer::new("a", Some(&a), "x"),
        Layer::new("b", Some(&b), "y"),
    ];
    let (s, g) = (Cell::new(0, 0), Cell::new(11, 11));
    let auto = Style::default();
    let overlay = Style {
        layout: Layout::Overlay,
        ..Style::default()
    };
    let panels = Style {
        layout: Layout::Panels,
        ..Style::default()
    };
    let classes = ["panel", "layer", "legend", "step"];
    // 12x12: two panels, each labelled (cells of 48 px): steps 1 and 2 per panel... minus
    // none, as neither path reaches the goal (11, 11).
    let svg = draw_comparison(&small, s, g, &layers, "t", &auto);
    assert_eq!(counts(&svg, &classes), [2, 2, 0, 4]);
    // 65 wide: overlay, one legend, no step labels under Auto.
    let svg = draw_comparison(&large, s, g, &layers, "t", &auto);
    assert_eq!(counts(&svg, &classes), [0, 2, 1, 0]);
    assert_eq!(texts(&svg, "label"), ["a", "b"]);
    assert_eq!(texts(&svg, "note"), ["x", "y"]);
    // Overrides.
    let svg = draw_comparison(&small, s, g, &layers, "t", &overlay);
    assert_eq!(counts(&svg, &classes), [0, 2, 1, 0]);
    let svg = draw_comparison(&large, s, g, &layers, "t", &panels);
    assert_eq!(counts(&svg, &classes)[0], 2);
    // A single layer is a panel even on a large map; no layer draws the map alone.
    let svg = draw_comparison(&large, s, g, &layers[..1], "t", &auto);
    assert_eq!(counts(&svg, &classes)[..2], [1, 1]);
    let svg = draw_comparison(&small, s, g, &[], "t", &auto);
    assert_eq!(counts(&svg, &["panel", "layer", "endpoint"]), [1, 0, 2]);
}

#[test]
fn panels_go_side_by_side_and_fit_max_px() {
    let grid = Grid::new(12, 12).unwrap();
    let p = cells(&[(0, 0), (1, 0)]);
    let layers: Vec<Layer> = (0..6).map(|_| Layer::new("p", Some(&p), "n")).collect();
    let svg = draw_comparison(
        &grid,
        Cell::new(0, 0),
        Cell::new(11, 11),
        &layers,
        "six",
        &Style::default(),
    );
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let root = doc.root_element();
    let width: f64 = root.attribute("width").unwrap().parse().unwrap();
    let height: f64 = root.attribute("height").unwrap().parse().unwrap();
    assert!(width <= 1200.0 && height <= 1200.0, "{width}x{height}");
    // Six in one row would give (1200 - 24 - 5 * 24) / 72 = 14 px cells, under the 24 px
    // wanted; three columns in two rows give (1200 - 24 - 2 * 24) / 36 = 31 px.
    let xs: std::collections::BTreeSet<String> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("panel"))
        .map(|n| n.first_element_child().unwrap())
        .map(|m| m.first_element_child().unwrap())
        .map(|r| r.attribute("x").unwrap().to_owned())
        .collect();
    assert_eq!(xs.len(), 3, "{xs:?}");
}

#[test]
fn timeline_counts() {
    let grid = Grid::new(5, 3).unwrap();
    // A sweep: 15 cells, 14 moves; rows alternate direction.
    let mut list = Vec::new();
    for y in 0..3u32 {
        for i in 0..5u32 {
            list.push(if y % 2 == 0 { (i, y) } else { (4 - i, y) });
        }
    }
    let path = cells(&list);
    let markers = [
        Marker {
            cell: Cell::new(4, 0),
            label: "B1".into(),
        },
        Marker {
            cell: Cell::new(9, 9),
            label: "outside".into(),
        },
    ];
    let svg = draw_timeline(&grid, &path, &markers, "sweep", &Style::default());
    // 14 moves -> 14 one-move colour chunks; steps 1..13 labelled (0 and 14 are S and E);
    // 14 arrows; one marker drawn (the other is outside the grid).
    assert_eq!(polylines(&svg).len(), 14);
    assert_eq!(
        counts(
            &svg,
            &["step", "arrow", "endpoint", "marker", "marker-label"]
        ),
        [13, 14, 2, 1, 1]
    );
    // The first chunk is the start of the ramp (#440154), the last its end (#fde725).
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let strokes: Vec<&str> = doc
        .descendants()
        .filter(|n| n.attribute("class") == Some("path"))
        .map(|n| n.attribute("stroke").unwrap())
        .collect();
    // Chunk k is coloured at its middle index k + 0 (integer middle of k and k + 1) over 14.
    assert_eq!(strokes[0], "#440154");
    assert_eq!(strokes[13], planner_figures_ramp(13.0 / 14.0));
}

/// A layer's markers (a planner's marks) are drawn in panels and overlays alike, in the
/// layer's colour; those outside the grid are left out.
#[test]
fn layer_markers_in_panels_and_overlays() {
    let grid = Grid::new(12, 12).unwrap();
    let a = cells(&[(0, 0), (1, 0), (2, 0), (3, 0)]);
    let b = cells(&[(0, 0), (0, 1), (0, 2)]);
    let marks_a = [
        Marker::new(Cell::new(1, 0), "H1"),
        Marker::new(Cell::new(3, 0), "H1'"),
        Marker::new(Cell::new(40, 0), "outside"),
    ];
    let marks_b = [Marker::new(Cell::new(0, 1), "X")];
    let layers = [
        Layer::new("a", Some(&a), "x").with_markers(&marks_a),
        Layer::new("b", Some(&b), "y").with_markers(&marks_b),
    ];
    let (s, g) = (Cell::new(0, 0), Cell::new(11, 11));
    for layout in [Layout::Panels, Layout::Overlay] {
        let style = Style {
            layout,
            ..Style::default()
        };
        let svg = draw_comparison(&grid, s, g, &layers, "t", &style);
        assert_eq!(
            counts(&svg, &["marker", "marker-label"]),
            [3, 3],
            "{layout:?}"
        );
        assert_eq!(
            texts(&svg, "marker-label"),
            ["H1", "H1'", "X"],
            "{layout:?}"
        );
        // Each layer's marks in its own colour: the palette's first two.
        let doc = roxmltree::Document::parse(&svg).unwrap();
        let colours: Vec<&str> = doc
            .descendants()
            .filter(|n| n.attribute("class") == Some("marker"))
            // Frames (labelled cells) are stroked, diamonds filled.
            .map(|n| match n.attribute("fill") {
                Some("none") | None => n.attribute("stroke").unwrap(),
                Some(fill) => fill,
            })
            .collect();
        assert_eq!(colours[0], colours[1], "{layout:?}");
        assert_ne!(colours[0], colours[2], "{layout:?}");
    }
}

/// Viridis between the anchors, recomputed independently of the crate for the test.
fn planner_figures_ramp(t: f64) -> String {
    let anchors = [
        0x440154, 0x482878, 0x3E4A89, 0x31688E, 0x26828E, 0x1F9E89, 0x35B779, 0x6DCD59, 0xB4DE2C,
        0xFDE725,
    ];
    let pos = t * 9.0;
    let i = (pos.floor() as usize).min(8);
    let f = pos - i as f64;
    let ch = |c: u32, s: u32| f64::from((c >> s) & 0xff);
    let mix = |s| {
        let (a, b) = (ch(anchors[i], s), ch(anchors[i + 1], s));
        (a + (b - a) * f).round() as u32
    };
    format!("#{:02x}{:02x}{:02x}", mix(16), mix(8), mix(0))
}

#[test]
fn degenerate_inputs_still_draw() {
    let grid = Grid::new(1, 1).unwrap();
    let empty = Path::new(vec![]);
    let one = cells(&[(0, 0)]);
    let outside = cells(&[(5, 5), (6, 5), (0, 0)]);
    let weird = Style {
        cell_px: f64::NAN,
        max_px: -3.0,
        ..Style::default()
    };
    let tiny = Style {
        max_px: 5.0,
        ..Style::default()
    };
    for style in [Style::default(), weird, tiny] {
        for path in [&empty, &one, &outside] {
            let layer = Layer::new("", Some(path), "");
            let far = Cell::new(u32::MAX, u32::MAX);
            for (s, g) in [(Cell::new(0, 0), Cell::new(0, 0)), (far, far)] {
                counts(&draw_path(&grid, s, g, &layer, "", &style), &[]);
                let ls = [layer.clone(), Layer::new("none", None, "no path")];
                counts(&draw_comparison(&grid, s, g, &ls, "", &style), &[]);
                let overlay = Style {
                    layout: Layout::Overlay,
                    ..style.clone()
                };
                counts(&draw_comparison(&grid, s, g, &ls, "", &overlay), &[]);
            }
            counts(&draw_timeline(&grid, path, &[], "", &style), &[]);
        }
    }
}

/// A seeded random grid with about `density` of its cells blocked.
fn random_grid(width: u32, height: u32, density: f64, seed: u64) -> Grid {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let free = (0..width * height)
        .map(|_| rng.gen::<f64>() >= density)
        .collect();
    Grid::from_free_cells(width, height, free).unwrap()
}

/// A random walk of `n` cells inside the grid, ignoring obstacles (drawing does not care).
fn random_walk(grid: &Grid, n: usize, seed: u64) -> Path {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut c = Cell::new(grid.width() / 2, grid.height() / 2);
    let mut out = vec![c];
    while out.len() < n {
        let (dx, dy) = [(1, 0), (-1, 0), (0, 1), (0, -1)][rng.gen_range(0..4)];
        if let Some(next) = grid.offset(c, dx, dy) {
            c = next;
            out.push(c);
        }
    }
    Path::new(out)
}

#[test]
fn large_maps_stay_small() {
    // 30 % random blocks: the worst case for run merging (random512-10-0 is 10 %).
    let grid = random_grid(512, 512, 0.3, 7);
    let a = random_walk(&grid, 20_000, 1);
    let b = random_walk(&grid, 20_000, 2);
    let (s, g) = (Cell::new(0, 0), Cell::new(511, 511));
    let layer = Layer::new("walk", Some(&a), "n");
    let layers = [layer.clone(), Layer::new("walk 2", Some(&b), "n")];
    let style = Style::default();
    let one = draw_path(&grid, s, g, &layer, "512", &style);
    let two = draw_comparison(&grid, s, g, &layers, "512", &style);
    // A full sweep: the longest path a figure will get.
    let mut sweep = Vec::new();
    for y in 0..512 {
        for i in 0..512 {
            sweep.push(if y % 2 == 0 { (i, y) } else { (511 - i, y) });
        }
    }
    let sweep = cells(&sweep);
    let time = draw_timeline(&grid, &sweep, &[], "512", &style);
    for svg in [&one, &two, &time] {
        assert!(svg.len() < 3_000_000, "{} bytes", svg.len());
        let doc = roxmltree::Document::parse(svg).unwrap();
        let w: f64 = doc
            .root_element()
            .attribute("width")
            .unwrap()
            .parse()
            .unwrap();
        let h: f64 = doc
            .root_element()
            .attribute("height")
            .unwrap()
            .parse()
            .unwrap();
        assert!(w <= 1200.0 && h <= 1200.0, "{w}x{h}");
        // Sparse: at most 60 arrows per path (40 on a timeline), no step labels.
        let [steps, arrows] = counts(svg, &["step", "arrow"])[..] else {
            unreachable!()
        };
        assert_eq!(steps, 0);
        assert!(arrows <= 120, "{arrows}");
    }
    // Run merging: the rectangles number exactly the maximal runs of blocked cells in rows,
    // counted here directly, less those merged with an identical run right above.
    let mut runs = 0;
    let mut merged = 0;
    let mut above: Vec<(u32, u32)> = Vec::new();
    for y in 0..512 {
        let mut row = Vec::new();
        let mut x = 0;
        while x < 512 {
            if grid.is_free(Cell::new(x, y)) {
                x += 1;
                continue;
            }
            let start = x;
            while x < 512 && !grid.is_free(Cell::new(x, y)) {
                x += 1;
            }
            row.push((start, x));
        }
        runs += row.len();
        merged += row.iter().filter(|r| above.contains(r)).count();
        above = row;
    }
    assert_eq!(obstacle_rects(&one), runs - merged);
    assert!(runs - merged < 60_000, "{runs} runs, {merged} merged");
}

#[test]
fn sparse_arrows_are_evenly_spaced() {
    // A straight 511-move path on a 512x512 open grid: cells of (1200 - 24 - 30 - 42) / 512
    // = 2.156 -> 2.15 px (height-bound), 1098.65 px of path, spacing max(60, 1098.65 / 60)
    // = 60 px, arrows at 30, 90, ..., 1050: 18 of them.
    let grid = Grid::new(512, 512).unwrap();
    let path = cells(&(0..512).map(|x| (x, 0)).collect::<Vec<_>>());
    let layer = Layer::new("line", Some(&path), "n");
    let svg = draw_path(
        &grid,
        Cell::new(0, 0),
        Cell::new(511, 0),
        &layer,
        "line",
        &Style::default(),
    );
    assert_eq!(counts(&svg, &["arrow"]), [18]);
}

#[test]
fn style_reads_from_config() {
    let style: Style = toml::from_str(
        r#"
        max_px = 800.0
        step_labels = "never"
        layout = "overlay"
        "#,
    )
    .unwrap();
    let expect = Style {
        max_px: 800.0,
        step_labels: StepLabels::Never,
        layout: Layout::Overlay,
        ..Style::default()
    };
    assert_eq!(style, expect);
    assert!(toml::from_str::<Style>("colour = 1").is_err());
}
