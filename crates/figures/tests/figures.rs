//! Figures parsed back as XML: well-formedness, element counts on hand-made grids,
//! geometry of any-angle paths, determinism, escaping, layout choice and size bounds;
//! large maps' pictures decoded and checked pixel by pixel, the memory drawing takes, unknown
//! cells, and weighted maps' costs, scale and expanded cells.

use std::alloc::{GlobalAlloc, Layout as AllocLayout, System};
use std::cell::Cell as StdCell;

use planner_api::{Cell, CostRule, Grid, Path};
use planner_figures::{
    draw_comparison, draw_path, draw_timeline, Layer, Layout, MapView, Marker, StepLabels, Style,
    RASTER_MAX_SIDE, VECTOR_MAX_CELLS,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Counts the bytes the calling thread holds allocated, and the most it held since
/// [`reset_peak`]: what drawing one figure takes, whatever the other tests' threads do.
struct Counting;

thread_local! {
    static HELD: StdCell<isize> = const { StdCell::new(0) };
    static PEAK: StdCell<isize> = const { StdCell::new(0) };
}

fn count(delta: isize) {
    let _ = HELD.try_with(|held| {
        let now = held.get() + delta;
        held.set(now);
        let _ = PEAK.try_with(|peak| peak.set(peak.get().max(now)));
    });
}

// SAFETY: every call is passed on to the system allocator unchanged; the counters are
// thread-local cells that allocate nothing.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: AllocLayout) -> *mut u8 {
        count(layout.size() as isize);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: AllocLayout) {
        count(-(layout.size() as isize));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: AllocLayout, new_size: usize) -> *mut u8 {
        count(new_size as isize - layout.size() as isize);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Starts measuring the calling thread's peak from what it holds now.
fn reset_peak() -> isize {
    let held = HELD.with(StdCell::get);
    PEAK.with(|peak| peak.set(held));
    held
}

/// The most the calling thread held since [`reset_peak`] returned `base`, above `base`.
fn peak_above(base: isize) -> isize {
    PEAK.with(StdCell::get) - base
}

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

/// The attribute `name` of every element of class `class`, in document order.
fn attributes(svg: &str, class: &str, name: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.attribute("class") == Some(class))
        .map(|n| n.attribute(name).unwrap_or_default().to_owned())
        .collect()
}

/// The words of the map's key: its `<text>` elements' texts.
fn key_words(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.attribute("class") == Some("key"))
        .flat_map(|k| k.descendants().filter(|t| t.has_tag_name("text")))
        .filter_map(|t| t.text().map(String::from))
        .collect()
}

/// Decodes standard base64 with padding.
fn unbase64(text: &str) -> Vec<u8> {
    let value = |c: u8| match c {
        b'A'..=b'Z' => c - b'A',
        b'a'..=b'z' => c - b'a' + 26,
        b'0'..=b'9' => c - b'0' + 52,
        b'+' => 62,
        b'/' => 63,
        _ => panic!("not base64: {c}"),
    };
    let mut out = Vec::new();
    for chunk in text.as_bytes().chunks(4) {
        let digits: Vec<u8> = chunk
            .iter()
            .filter(|&&c| c != b'=')
            .map(|&c| value(c))
            .collect();
        let n = digits
            .iter()
            .enumerate()
            .fold(0u32, |n, (i, &d)| n | u32::from(d) << (18 - 6 * i));
        out.extend((0..digits.len() - 1).map(|i| (n >> (16 - 8 * i)) as u8));
    }
    out
}

/// The pictures inside the `<svg>` of class `class` (a map's cells or a panel's expanded
/// cells): the nested `<svg>`'s x, y, width, height and viewBox, and the decoded image.
fn pictures(svg: &str, class: &str) -> Vec<([f64; 4], String, image::RgbaImage)> {
    let doc = roxmltree::Document::parse(svg).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("svg") && n.attribute("class") == Some(class))
        .map(|view| {
            let number = |name: &str| view.attribute(name).unwrap().parse::<f64>().unwrap();
            let frame = [number("x"), number("y"), number("width"), number("height")];
            let image = view.children().find(|c| c.has_tag_name("image")).unwrap();
            assert!(image.attribute("style").unwrap().contains("pixelated"));
            let uri = image.attribute("href").unwrap();
            let png = unbase64(uri.strip_prefix("data:image/png;base64,").unwrap());
            let decoded = image::load_from_memory_with_format(&png, image::ImageFormat::Png)
                .unwrap()
                .to_rgba8();
            (
                frame,
                view.attribute("viewBox").unwrap().to_owned(),
                decoded,
            )
        })
        .collect()
}

#[test]
fn large_maps_draw_their_cells_as_a_bounded_picture() {
    // 2048 x 2048, 30 % blocked: one rectangle per run was 36 MB of SVG, some 700,000
    // rectangles, and hundreds of MB to build.
    let grid = random_grid(2048, 2048, 0.3, 11);
    let path = random_walk(&grid, 5_000, 3);
    let expanded: Vec<Cell> = (0..3000)
        .map(|i| Cell::new(100 + i % 60, 7 + i / 60))
        .collect();
    let layer = Layer::new("walk", Some(&path), "n").with_expanded(&expanded);
    let (s, g) = (Cell::new(0, 0), Cell::new(2047, 2047));
    let base = reset_peak();
    let svg = draw_path(&grid, s, g, &layer, "2048", &Style::default());
    let peak = peak_above(base);
    assert!(svg.len() < 2_000_000, "{} bytes", svg.len());
    // A few bytes per pixel of 1024 x 1024 (the map's RGB, the expanded cells' RGBA, their
    // PNGs and the SVG text): 7.9 MB when written; the grid alone is 4 MB.
    assert!(peak < 16 << 20, "drawing held {peak} bytes at its peak");
    assert_eq!(obstacle_rects(&svg), 0);
    // The map: cells of (1200 - 24 - 30 - 60 - 22) / 2048 = 0.51 px (height-bound), so
    // 1044 px of map on the page, over 1024: pixels of ceil(2048 / 1024) = 2 x 2 cells.
    let [(frame, view, map)] = &pictures(&svg, "cells")[..] else {
        panic!("one picture of the cells")
    };
    assert_eq!(view, "0 0 2048 2048");
    assert_eq!(frame[2], 2048.0 * 0.51);
    assert_eq!((map.width(), map.height()), (1024, 1024));
    assert!(map.width() <= RASTER_MAX_SIDE);
    assert_eq!(
        key_words(&svg),
        ["1 pixel = 2 x 2 cells (their mean colour)"]
    );
    // Every pixel is the mean of its block's four cells: white 255, blocked 0x3b, rounded.
    for (px, py, pixel) in map.enumerate_pixels() {
        let blocked = (0..4)
            .filter(|i| !grid.is_free(Cell::new(2 * px + i % 2, 2 * py + i / 2)))
            .count() as u32;
        let mean = ((4 - blocked) * 255 + blocked * 0x3b + 2) / 4;
        assert_eq!(
            pixel.0,
            [mean as u8, mean as u8, mean as u8, 255],
            "({px}, {py})"
        );
    }
    // Expanded cells: a block is expanded when any of its cells is, in the layer colour at
    // 30 % (alpha 77); the others are transparent.
    let [(expanded_frame, _, picture)] = &pictures(&svg, "expanded-cells")[..] else {
        panic!("one picture of the expanded cells")
    };
    assert_eq!(expanded_frame, frame);
    for (px, py, pixel) in picture.enumerate_pixels() {
        // Cells 2 px and 2 px + 1 overlap columns 100 to 159; 2 py and 2 py + 1 rows 7 to 56.
        let hit = 2 * px + 1 >= 100 && 2 * px <= 159 && 2 * py + 1 >= 7 && 2 * py <= 56;
        let expect = if hit { [0x00, 0x72, 0xb2, 77] } else { [0; 4] };
        assert_eq!(pixel.0, expect, "({px}, {py})");
    }
    // The path is drawn as it is, through the centres of its own cells.
    let (ox, oy, cell) = (frame[0], frame[1], 0.51);
    let vertices = &polylines(&svg)[0];
    let mut listed = path.cells().iter();
    for &(x, y) in vertices {
        let at = Cell::new(
            ((x - ox) / cell - 0.5).round() as u32,
            ((y - oy) / cell - 0.5).round() as u32,
        );
        assert!(
            ((x - ox) / cell - 0.5 - f64::from(at.x)).abs() < 0.02,
            "{x}"
        );
        assert!(
            ((y - oy) / cell - 0.5 - f64::from(at.y)).abs() < 0.02,
            "{y}"
        );
        assert!(
            listed.any(|&c| c == at),
            "{at:?} is not the path's next vertex"
        );
    }
}

#[test]
fn maps_up_to_the_vector_limit_keep_rectangles() {
    assert_eq!(VECTOR_MAX_CELLS, 512 * 512);
    let at = random_grid(512, 512, 0.1, 5);
    let over = random_grid(513, 512, 0.1, 5);
    let (s, g) = (Cell::new(0, 0), Cell::new(511, 511));
    let at = draw_path(&at, s, g, &Layer::new("a", None, ""), "", &Style::default());
    let over = draw_path(
        &over,
        s,
        g,
        &Layer::new("a", None, ""),
        "",
        &Style::default(),
    );
    assert!(obstacle_rects(&at) > 20_000);
    assert!(pictures(&at, "cells").is_empty());
    assert_eq!(key_words(&at), Vec::<String>::new());
    assert_eq!(obstacle_rects(&over), 0);
    // (1200 - 24 - 30 - 42 - 22) / 512 = 2.11 px a cell: a pixel a cell.
    let [(_, _, map)] = &pictures(&over, "cells")[..] else {
        panic!("one picture")
    };
    assert_eq!((map.width(), map.height()), (513, 512));
    assert_eq!(key_words(&over), ["1 pixel = 1 cell"]);
    // Overlays and timelines draw the same picture.
    let path = cells(&[(0, 0), (1, 1)]);
    let over_grid = random_grid(513, 512, 0.1, 5);
    let layers = [Layer::new("a", Some(&path), ""), Layer::new("b", None, "")];
    let overlay = draw_comparison(&over_grid, s, g, &layers, "", &Style::default());
    let timeline = draw_timeline(&over_grid, &path, &[], "", &Style::default());
    for svg in [&overlay, &timeline] {
        assert_eq!(obstacle_rects(svg), 0);
        assert_eq!(pictures(svg, "cells").len(), 1);
    }
}

#[test]
fn unknown_cells_are_grey_and_keyed() {
    let grid = small_grid();
    // Unknown: the blocked (1, 1) and (0, 3), and the free (3, 0).
    let mut unknown = vec![false; 16];
    for (x, y) in [(1, 1), (0, 3), (3, 0)] {
        unknown[y * 4 + x] = true;
    }
    let path = cells(&[(0, 0), (1, 0)]);
    let layer = Layer::new("a", Some(&path), "n");
    let (s, g) = (Cell::new(0, 0), Cell::new(3, 3));
    let style = Style::default();
    let svg = draw_path(
        MapView::new(&grid).with_unknown(&unknown),
        s,
        g,
        &layer,
        "",
        &style,
    );
    // Grey cells: (3, 0), (1, 1), (0, 3), one rectangle each; dark: (2, 1) and (3, 2) only.
    assert_eq!(attributes(&svg, "unknown", "fill"), ["#cdcdcd"]);
    let rects = |class: &str| -> Vec<(String, String)> {
        let doc = roxmltree::Document::parse(&svg).unwrap();
        doc.descendants()
            .filter(|n| n.attribute("class") == Some(class))
            .flat_map(|g| g.children().filter(|c| c.has_tag_name("rect")))
            .map(|r| {
                (
                    r.attribute("x").unwrap().into(),
                    r.attribute("y").unwrap().into(),
                )
            })
            .collect()
    };
    let xy = |list: &[(u32, u32)]| -> Vec<(String, String)> {
        list.iter()
            .map(|(x, y)| (x.to_string(), y.to_string()))
            .collect()
    };
    assert_eq!(rects("unknown"), xy(&[(3, 0), (1, 1), (0, 3)]));
    assert_eq!(rects("obstacles"), xy(&[(2, 1), (3, 2)]));
    assert_eq!(key_words(&svg), ["blocked", "unknown"]);
    // No unknown cell: the figure of the grid alone, byte for byte.
    let none = vec![false; 16];
    let plain = draw_path(&grid, s, g, &layer, "", &style);
    let known = draw_path(
        MapView::new(&grid).with_unknown(&none),
        s,
        g,
        &layer,
        "",
        &style,
    );
    assert_eq!(plain, known);
    assert_eq!(counts(&plain, &["unknown", "key"]), [0, 0]);

    // A large map: a block of unknown cells is grey, a block half unknown and half free
    // the mean of the two.
    let big = Grid::from_free_cells(600, 600, vec![true; 360_000]).unwrap();
    let mut unknown = vec![false; 360_000];
    for y in 0..600 {
        for x in 300..600 {
            unknown[y * 600 + x] = true;
        }
    }
    let svg = draw_path(
        MapView::new(&big).with_unknown(&unknown),
        s,
        g,
        &layer,
        "",
        &style,
    );
    let [(_, _, map)] = &pictures(&svg, "cells")[..] else {
        panic!("one picture")
    };
    assert_eq!(map.get_pixel(0, 0).0, [255, 255, 255, 255]);
    assert_eq!(map.get_pixel(599, 599).0, [0xcd, 0xcd, 0xcd, 255]);
}

/// A 4 x 3 weighted grid: weights 1 to 9, (0, 1) blocked.
fn weighted_grid() -> Grid {
    Grid::from_ascii("....\n#...\n....")
        .unwrap()
        .with_weights(vec![1, 2, 3, 4, 5, 6, 7, 8, 9, 1, 1, 1], CostRule::Mean)
        .unwrap()
}

#[test]
fn weighted_maps_give_the_cost_a_scale_and_expanded_outlines() {
    let grid = weighted_grid();
    let path = cells(&[(0, 0), (1, 0), (2, 1), (3, 2)]);
    let cost = grid.path_cost(path.cells()).to_f64();
    let layer = Layer::new("a", Some(&path), "found: D=3");
    let (s, g) = (Cell::new(0, 0), Cell::new(3, 2));
    let style = Style::default();
    let svg = draw_path(&grid, s, g, &layer, "", &style);
    assert_eq!(texts(&svg, "note"), [format!("found: D=3 cost={cost:.2}")]);
    // A note that gives the cost already keeps it once.
    let given = Layer::new("a", Some(&path), "found cost=1.00");
    let svg_given = draw_path(&grid, s, g, &given, "", &style);
    assert_eq!(texts(&svg_given, "note"), ["found cost=1.00"]);
    // The key: the lowest weight, five steps of the shading, the highest.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let key = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("key"))
        .unwrap();
    assert_eq!(key_words(&svg), ["cell weight 1", "9"]);
    let fills: Vec<&str> = key
        .children()
        .filter(|c| c.has_tag_name("rect"))
        .filter_map(|r| r.attribute("fill"))
        .collect();
    // White to #a0522d at 0.6: 255 + (160 - 255) * 0.6 = 198, 255 + (82 - 255) * 0.6 =
    // 151.2, 255 + (45 - 255) * 0.6 = 129.
    assert_eq!(fills.len(), 5);
    assert_eq!((fills[0], fills[4]), ("#ffffff", "#c69781"));
    // A timeline gives its path's cost too.
    let timeline = draw_timeline(&grid, &path, &[], "", &style);
    assert!(timeline.contains(&format!("cost={cost:.2}")), "{timeline}");

    // Expanded cells: the outline of their region, towards free cells only. Expanded:
    // (1, 1) and (2, 1); their free neighbours (1, 0), (2, 0), (3, 1), (1, 2), (2, 2), and
    // the blocked (0, 1), which gets no edge.
    let expanded = [Cell::new(1, 1), Cell::new(2, 1), Cell::new(2, 1)];
    let layer = layer.with_expanded(&expanded);
    let svg = draw_path(&grid, s, g, &layer, "", &style);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let group = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("expanded"))
        .unwrap();
    assert_eq!(
        group.children().filter(|c| c.has_tag_name("rect")).count(),
        0
    );
    let outline = group.children().find(|c| c.has_tag_name("path")).unwrap();
    assert_eq!(
        outline.attribute("d"),
        Some("M1 1H3M1 2H3M3 1V2"),
        "top, bottom, right; not left, where (0, 1) is blocked"
    );
    assert_eq!(outline.attribute("fill"), Some("none"));
    // An unweighted grid keeps the fill.
    let plain = draw_path(&small_grid(), s, g, &layer, "", &style);
    assert_eq!(attributes(&plain, "expanded", "fill-opacity"), ["0.3"]);
    assert_eq!(texts(&plain, "note"), ["found: D=3"]);
    assert_eq!(counts(&plain, &["key"]), [0]);

    // On a large weighted map, the outline is the expanded blocks next to a free block
    // that is not expanded, opaque.
    let big = Grid::new(600, 600)
        .unwrap()
        .with_weights(
            (0..360_000).map(|i| 1 + (i % 600 / 100) as u16).collect(),
            CostRule::Mean,
        )
        .unwrap();
    let square: Vec<Cell> = (10..20)
        .flat_map(|y| (10..20).map(move |x| Cell::new(x, y)))
        .collect();
    let layer = Layer::new("a", None, "").with_expanded(&square);
    let svg = draw_path(&big, s, g, &layer, "", &style);
    let [(_, _, picture)] = &pictures(&svg, "expanded-cells")[..] else {
        panic!("one picture")
    };
    let opaque: Vec<(u32, u32)> = picture
        .enumerate_pixels()
        .filter(|p| p.2 .0[3] > 0)
        .map(|p| (p.0, p.1))
        .collect();
    assert_eq!(opaque.len(), 36, "the ring of a 10 x 10 square");
    assert!(opaque
        .iter()
        .all(|&(x, y)| picture.get_pixel(x, y).0 == [0x00, 0x72, 0xb2, 255]));
    assert!(!opaque.contains(&(15, 15)));
}

/// The numbers in `note`: each run of digits, with its decimals.
fn numbers(note: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut run = String::new();
    for c in note.chars().chain([' ']) {
        if c.is_ascii_digit() || (c == '.' && !run.is_empty()) {
            run.push(c);
        } else if !run.is_empty() {
            out.push(std::mem::take(&mut run).trim_end_matches('.').to_owned());
        }
    }
    out
}

/// Holds `svg`'s notes to `notes`: each note element's text is its note whole (wrapped
/// lines joined), every number in it among the note's text, nothing cut with an ellipsis,
/// and every line within the figure's width.
fn notes_whole(svg: &str, class: &str, notes: &[String]) {
    assert_eq!(texts(svg, class), notes, "{svg}");
    let text = texts(svg, class).concat();
    assert!(!text.contains('…'), "{svg}");
    for note in notes {
        for number in numbers(note) {
            assert!(text.contains(&number), "{number} of {note} in {svg}");
        }
    }
    let doc = roxmltree::Document::parse(svg).unwrap();
    let width: f64 = doc
        .root_element()
        .attribute("width")
        .unwrap()
        .parse()
        .unwrap();
    for n in doc
        .descendants()
        .filter(|n| n.attribute("class") == Some(class))
    {
        // Every line starts inside the figure, and its estimated width (0.62 em a
        // character at 12 px) ends inside it.
        let lines: Vec<roxmltree::Node> = match n.children().any(|c| c.is_element()) {
            true => n.children().filter(|c| c.is_element()).collect(),
            false => vec![n],
        };
        for line in lines {
            let own = line.text().unwrap_or("").trim_end();
            if let Some(x) = line.attribute("x").and_then(|x| x.parse::<f64>().ok()) {
                let end = x + own.chars().count() as f64 * 12.0 * 0.62;
                assert!(
                    end <= width + 0.5,
                    "{own:?} ends at {end} of {width}: {svg}"
                );
            }
        }
    }
}

/// Notes are wrapped, never cut: on a 3 x 3 map, a 3 x 100000 map (a picture), and in a
/// comparison of a weighted map's panels (where each note gains its path's cost), every
/// number of each note reaches the SVG's text, with the words in order.
#[test]
fn notes_keep_every_number_on_narrow_maps_and_weighted_comparisons() {
    let style = Style::default();
    // 3 x 3: the per-run figure read `found: D=4 T=1 Score=5 leng…`.
    let grid = Grid::new(3, 3).unwrap();
    let path = cells(&[(0, 0), (1, 0), (2, 0), (2, 1), (2, 2)]);
    let note = "found: D=4 T=1 Score=5 length=4.00 time_ms=0.0123";
    let layer = Layer::new("astar", Some(&path), note);
    let svg = draw_path(&grid, Cell::new(0, 0), Cell::new(2, 2), &layer, "m", &style);
    notes_whole(&svg, "note", &[note.to_owned()]);
    // With expanded cells, their line too.
    let expanded: Vec<Cell> = path.cells().to_vec();
    let with = layer.clone().with_expanded(&expanded);
    let svg = draw_path(&grid, Cell::new(0, 0), Cell::new(2, 2), &with, "m", &style);
    notes_whole(&svg, "note", &[note.to_owned()]);
    notes_whole(&svg, "expanded-note", &["expanded: 5 cells".to_owned()]);

    // 3 x 100000: `plan --svg` read `found: D=100001 T=2 Score=100003 …`.
    let tall = Grid::new(3, 100_000).unwrap();
    let path = cells(&[(0, 0), (0, 99_999), (2, 99_999)]);
    let note = "found: D=100001 T=2 Score=100003 length=100001.00 cost=100001.00";
    let layer = Layer::new("astar", Some(&path), note);
    let svg = draw_path(
        &tall,
        Cell::new(0, 0),
        Cell::new(2, 99_999),
        &layer,
        "",
        &style,
    );
    notes_whole(&svg, "note", &[note.to_owned()]);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let height: f64 = doc
        .root_element()
        .attribute("height")
        .unwrap()
        .parse()
        .unwrap();
    assert!(height <= 1200.0, "{height}");

    // A weighted 8 x 6 map compared in panels: `found: D=7 T=4 Score=11 length=7.83 c…`.
    let weighted = Grid::new(8, 6)
        .unwrap()
        .with_weights(
            (0..48).map(|i| 1 + (i % 7) as u16 * 40).collect(),
            CostRule::Mean,
        )
        .unwrap();
    let a = cells(&[
        (0, 0),
        (1, 1),
        (2, 2),
        (3, 3),
        (4, 3),
        (5, 4),
        (6, 5),
        (7, 5),
    ]);
    let b = cells(&[
        (0, 0),
        (1, 0),
        (2, 1),
        (3, 2),
        (4, 3),
        (5, 4),
        (6, 5),
        (7, 5),
    ]);
    let notes = [
        "found: D=7 T=4 Score=11 length=7.83",
        "found: D=7 T=3 Score=10 length=8.24",
    ];
    let layers: Vec<Layer> = [(&a, notes[0]), (&b, notes[1])]
        .iter()
        .enumerate()
        .map(|(i, (p, n))| Layer::new(["astar", "bfs"][i], Some(p), *n))
        .collect();
    let expected: Vec<String> = [(&a, notes[0]), (&b, notes[1])]
        .iter()
        .map(|(p, n)| {
            let cost = weighted.path_cost(p.cells()).to_f64();
            format!("{n} cost={cost:.2}")
        })
        .collect();
    let (s, g) = (Cell::new(0, 0), Cell::new(7, 5));
    for layout in [Layout::Panels, Layout::Overlay] {
        let style = Style {
            layout,
            ..Style::default()
        };
        let svg = draw_comparison(&weighted, s, g, &layers, "weighted", &style);
        notes_whole(&svg, "note", &expected);
    }
    // Six panels of a narrow map in rows and columns, a long label in an overlay.
    let six: Vec<Layer> = (0..6).map(|i| layers[i % 2].clone()).collect();
    let svg = draw_comparison(&weighted, s, g, &six, "six", &style);
    let six_expected: Vec<String> = (0..6).map(|i| expected[i % 2].clone()).collect();
    notes_whole(&svg, "note", &six_expected);
    let long = "a label long enough to take the whole legend line of the overlay ".repeat(3);
    let overlay = Style {
        layout: Layout::Overlay,
        ..Style::default()
    };
    let labelled = [Layer::new(&long, Some(&a), notes[0])];
    let svg = draw_comparison(&weighted, s, g, &labelled, "", &overlay);
    notes_whole(&svg, "note", &expected[..1]);
}
