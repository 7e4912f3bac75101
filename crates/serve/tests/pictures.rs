//! `plan --trace` and `plan --gif` on den520d: the trace follows Posthoc's documented
//! layout (version 1.4.0: `version`, `views`, `pivot`, `events` of known types with `id`,
//! `x`, `y`) with one `expanding` event per expansion, and the GIF decodes, fits 5 MB and
//! ends on a frame with the path drawn on the path's cells.

use std::path::Path;

use planner_runner::plan::{PlanArgs, PlanOptions, PlanResult};

fn den520d(problem: usize) -> PlanResult {
    den520d_recording(problem, false)
}

/// `plan` of A* on den520d's scenario `problem`, with its expansions recorded, and with
/// `events` its steps too.
fn den520d_recording(problem: usize, events: bool) -> PlanResult {
    let args = PlanArgs {
        map: Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai/den520d.map"),
        planner: "astar".into(),
        problem: Some(problem),
        ..PlanArgs::default()
    };
    let options = PlanOptions {
        record_expanded: true,
        record_events: events,
        ..PlanOptions::default()
    };
    planner_runner::plan::run_with(&args, &options).unwrap()
}

/// With A*'s steps recorded, the trace has Posthoc's `generating`, `updating` and
/// `expanding` events with `pId`, `g` and `f`: one `generating` per OPEN insertion, one
/// `expanding` per expansion (the expanded cells in order), each parent an expanded node,
/// and `f` at least `g`.
#[test]
fn a_den520d_trace_with_steps_has_parents_g_and_f() {
    let result = den520d_recording(600, true);
    let text = planner_serve::trace::plan_trace_json(&result).unwrap();
    let trace: serde_json::Value = serde_json::from_str(&text).unwrap();
    let events = trace["events"].as_array().unwrap();
    let width = u64::from(result.grid.width());
    let mut expanded: Vec<u64> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    let mut generating = 0u64;
    for event in &events[2..events.len() - 1] {
        let kind = event["type"].as_str().unwrap();
        assert!(
            ["generating", "updating", "expanding"].contains(&kind),
            "{event}"
        );
        let (g, f) = (event["g"].as_f64().unwrap(), event["f"].as_f64().unwrap());
        assert!(g >= 0.0 && f >= g, "{event}");
        if let Some(parent) = event.get("pId") {
            assert!(
                seen.contains(&parent.as_u64().unwrap()),
                "{event}: parent not expanded"
            );
        }
        let id = event["id"].as_u64().unwrap();
        generating += u64::from(kind == "generating");
        if kind == "expanding" {
            expanded.push(id);
            seen.insert(id);
        }
    }
    let r = &result.record;
    assert_eq!(Some(generating), r.counters.get("n_open_insertions"));
    let recorded: Vec<u64> = result
        .expanded
        .iter()
        .map(|c| u64::from(c.y) * width + u64::from(c.x))
        .collect();
    assert_eq!(expanded, recorded);
    assert_eq!(Some(expanded.len() as u64), r.counters.get("n_expanded"));
    assert_eq!(events.last().unwrap()["type"], "end");
}

#[test]
fn a_den520d_trace_follows_posthocs_schema() {
    let result = den520d(600);
    let text = planner_serve::trace::plan_trace_json(&result).unwrap();
    let trace: serde_json::Value = serde_json::from_str(&text).unwrap();
    let top: Vec<&str> = trace
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(top, ["version", "views", "pivot", "events"]);
    assert_eq!(trace["version"], "1.4.0");
    // A view is a list of primitives, each naming its component with `$`.
    let main = trace["views"]["main"].as_array().unwrap();
    assert!(!main.is_empty());
    for primitive in main {
        assert!(primitive["$"].is_string(), "{primitive}");
    }
    assert!(trace["pivot"]["x"].is_string() && trace["pivot"]["y"].is_string());
    let (width, height) = (
        u64::from(result.grid.width()),
        u64::from(result.grid.height()),
    );
    let events = trace["events"].as_array().unwrap();
    let mut expanding = 0u64;
    for event in events {
        let kind = event["type"].as_str().unwrap();
        assert!(
            ["source", "destination", "expanding", "end"].contains(&kind),
            "{event}"
        );
        let (id, x, y) = (
            event["id"].as_u64().unwrap(),
            event["x"].as_u64().unwrap(),
            event["y"].as_u64().unwrap(),
        );
        assert!(x < width && y < height, "{event}");
        assert_eq!(id, y * width + x, "{event}");
        assert!(
            result
                .grid
                .is_free(planner_api::Cell::new(x as u32, y as u32)),
            "{event}"
        );
        expanding += u64::from(kind == "expanding");
    }
    let r = &result.record;
    assert_eq!(Some(expanding), r.counters.get("n_expanded"));
    assert!(expanding > 100, "a real search: {expanding}");
    let first = &events[0];
    assert_eq!(first["type"], "source");
    assert_eq!(
        (first["x"].as_u64(), first["y"].as_u64()),
        (Some(u64::from(r.start.x)), Some(u64::from(r.start.y)))
    );
    assert_eq!(events[1]["type"], "destination");
    let last = events.last().unwrap();
    assert_eq!(last["type"], "end");
    assert_eq!(
        (last["x"].as_u64(), last["y"].as_u64()),
        (Some(u64::from(r.goal.x)), Some(u64::from(r.goal.y)))
    );
    // The expanding events are the recorded expansions, in order.
    let ids: Vec<u64> = events[2..events.len() - 1]
        .iter()
        .map(|e| e["id"].as_u64().unwrap())
        .collect();
    let recorded: Vec<u64> = result
        .expanded
        .iter()
        .map(|c| u64::from(c.y) * width + u64::from(c.x))
        .collect();
    assert_eq!(ids, recorded);
}

#[test]
fn a_den520d_gif_fits_and_ends_on_the_path() {
    let result = den520d(600);
    let bytes = planner_serve::anim::plan_gif(&result).unwrap();
    assert!(
        bytes.len() <= planner_serve::anim::MAX_GIF_BYTES,
        "{}",
        bytes.len()
    );
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options.read_info(bytes.as_slice()).unwrap();
    let (w, h) = (decoder.width() as usize, decoder.height() as usize);
    let grid = &result.grid;
    let scale = w / grid.width() as usize;
    assert_eq!(
        (w, h),
        (
            grid.width() as usize * scale,
            grid.height() as usize * scale
        )
    );
    let mut frames = 0;
    let mut last = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        frames += 1;
        last = frame.buffer.to_vec();
    }
    assert!(frames >= 2, "{frames}");
    // In the last frame, palette index 3 (the path) lies exactly on the path's cells
    // (minus start and goal, drawn over it).
    let path = result.record.path.as_ref().unwrap().cells();
    let on_path = |x: usize, y: usize| path.iter().any(|c| c.x as usize == x && c.y as usize == y);
    let mut path_pixels = 0;
    for (i, &value) in last.iter().enumerate() {
        let (x, y) = ((i % w) / scale, (i / w) / scale);
        if value == 3 {
            path_pixels += 1;
            assert!(on_path(x, y), "path colour at cell ({x}, {y})");
        }
    }
    assert_eq!(path_pixels, (path.len() - 2) * scale * scale);
}

/// The frames of a GIF, as palette indices, and its width and height.
fn decode_indexed(bytes: &[u8]) -> (usize, usize, Vec<Vec<u8>>) {
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::Indexed);
    let mut decoder = options.read_info(bytes).unwrap();
    let (w, h) = (decoder.width() as usize, decoder.height() as usize);
    let mut frames = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        assert_eq!((frame.width as usize, frame.height as usize), (w, h));
        frames.push(frame.buffer.to_vec());
    }
    (w, h, frames)
}

/// A map of more than 512 cells a side is drawn in blocks of k x k cells, k = ceil(longer
/// side / 512): A* on a 1500 x 1100 map (a fifth of its cells blocked) gives a 500 x 367
/// GIF (k = 3) whose last frame draws the path on exactly the blocks of the path's cells
/// (but the start's and the goal's), and whose first frame draws a block blocked when most
/// of its cells are.
#[test]
fn a_large_map_gif_is_drawn_in_blocks_of_at_most_512_pixels_a_side() {
    let (width, height) = (1500usize, 1100usize);
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut free = vec![true; width * height];
    for cell in free.iter_mut() {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        *cell = state % 5 != 0;
    }
    let (start, goal) = ((3, 2), (width - 4, height - 3));
    free[start.1 * width + start.0] = true;
    free[goal.1 * width + goal.0] = true;
    let mut text = format!("type octile\nheight {height}\nwidth {width}\nmap\n");
    for row in free.chunks(width) {
        text.extend(row.iter().map(|&f| if f { '.' } else { '@' }));
        text.push('\n');
    }
    let map = crate::common::scratch("large-gif").join("large.map");
    std::fs::write(&map, text).unwrap();
    let args = PlanArgs {
        map,
        planner: "astar".into(),
        start: Some(planner_api::Cell::new(start.0 as u32, start.1 as u32)),
        goal: Some(planner_api::Cell::new(goal.0 as u32, goal.1 as u32)),
        ..PlanArgs::default()
    };
    let options = PlanOptions {
        record_expanded: true,
        ..PlanOptions::default()
    };
    let result = planner_runner::plan::run_with(&args, &options).unwrap();
    let bytes = planner_serve::anim::plan_gif(&result).unwrap();
    let (w, h, frames) = decode_indexed(&bytes);
    let k = 3;
    assert_eq!((w, h), (500, 367));
    assert!(w <= 512 && h <= 512);
    assert!(frames.len() >= 2, "{}", frames.len());

    // The last frame: palette index 3 (the path) on the path's blocks, the start (4) and
    // goal (5) over it.
    let path = result.record.path.as_ref().unwrap().cells();
    let pixel = |x: usize, y: usize| (y / k) * w + x / k;
    let ends = [pixel(start.0, start.1), pixel(goal.0, goal.1)];
    let mut expected: Vec<usize> = path
        .iter()
        .map(|c| pixel(c.x as usize, c.y as usize))
        .filter(|p| !ends.contains(p))
        .collect();
    expected.sort_unstable();
    expected.dedup();
    let last = frames.last().unwrap();
    let drawn: Vec<usize> = (0..w * h).filter(|&i| last[i] == 3).collect();
    assert!(drawn.len() > 400, "{}", drawn.len());
    assert_eq!(drawn, expected);
    assert_eq!((last[ends[0]], last[ends[1]]), (4, 5));

    // The first frame: the blocks with no expanded cell among its first expansions are
    // shaded by their share of blocked cells (free, a grey, blocked).
    let first = &frames[0];
    for py in 0..h {
        for px in 0..w {
            let i = py * w + px;
            if (2..=5).contains(&first[i]) {
                continue;
            }
            let (mut cells, mut blocked) = (0, 0);
            for y in py * k..((py + 1) * k).min(height) {
                for x in px * k..((px + 1) * k).min(width) {
                    cells += 1;
                    blocked += usize::from(!free[y * width + x]);
                }
            }
            assert_eq!(
                first[i],
                planner_serve::anim::block_index(blocked, cells),
                "pixel ({px}, {py})"
            );
        }
    }
}

/// 512 cells a side is still drawn cell by cell (one pixel a cell); 513 is drawn in blocks
/// of 2 x 2 cells, the last column and row of blocks half a block.
#[test]
fn gifs_are_drawn_in_blocks_from_513_cells_a_side() {
    for (width, height, pixels) in [
        (512, 40, (512, 40)),
        (40, 513, (20, 257)),
        (513, 513, (257, 257)),
    ] {
        let grid = planner_api::Grid::new(width, height).unwrap();
        let start = planner_api::Cell::new(0, 0);
        let goal = planner_api::Cell::new(width - 1, height - 1);
        let search = planner_serve::anim::Search {
            grid: &grid,
            start,
            goal,
            expanded: &[start, goal],
            path: &[start, goal],
            unknown: None,
        };
        let bytes = planner_serve::anim::gif(&search, usize::MAX).unwrap();
        let (w, h, frames) = decode_indexed(&bytes);
        assert_eq!((w, h), pixels, "{width}x{height}");
        let last = frames.last().unwrap();
        assert_eq!((last[0], last[w * h - 1]), (4, 5), "{width}x{height}");
    }
}

/// A wall one cell thick across a 5000 x 5000 map, with one gap, is drawn (blocks of 10 x
/// 10 cells) as a row of grey pixels in every frame: each of its blocks has a tenth of its
/// cells blocked (the gap's block a little less), which is shaded, lighter than a block
/// all blocked and darker than a free one (it was drawn free: a block was blocked only
/// when most of its cells were, so the wall vanished).
#[test]
fn a_thin_wall_on_a_big_map_shows_in_every_gif_frame() {
    let (width, height) = (5000u32, 5000u32);
    let mut grid = planner_api::Grid::new(width, height).unwrap();
    let wall = 2503;
    for x in 0..width {
        if x != 1234 {
            grid.set_free(planner_api::Cell::new(x, wall), false);
        }
    }
    let start = planner_api::Cell::new(0, 0);
    let goal = planner_api::Cell::new(width - 1, height - 1);
    let expanded = [start, planner_api::Cell::new(1, 0)];
    let search = planner_serve::anim::Search {
        grid: &grid,
        start,
        goal,
        expanded: &expanded,
        path: &[start, goal],
        unknown: None,
    };
    let bytes = planner_serve::anim::gif(&search, usize::MAX).unwrap();
    let (w, h, frames) = decode_indexed(&bytes);
    assert_eq!((w, h), (500, 500));
    let row = (wall / 10) as usize;
    let [free, blocked] = [0, 1].map(planner_serve::anim::palette_rgb);
    for (f, frame) in frames.iter().enumerate() {
        for px in 0..w {
            let index = frame[row * w + px];
            // The path's diagonal crosses the wall's row of blocks.
            if (2..=5).contains(&index) {
                continue;
            }
            let rgb = planner_serve::anim::palette_rgb(index);
            assert!(
                rgb[0] < free[0] && rgb[0] > blocked[0],
                "frame {f}, pixel ({px}, {row}): index {index}, {rgb:?}"
            );
        }
        // The rows of blocks beside it are free.
        assert!(frame[(row + 1) * w + 250] == 0 && frame[(row - 1) * w + 250] == 0);
    }
}

/// A ROS map's unknown cells are drawn in their own colour in every frame of `plan --gif`
/// (they were drawn as walls: the mask never reached the animation), as the SVG figures
/// draw them; cell by cell on a small map, and in blocks (a block all unknown is unknown,
/// another's share counts its known cells only) on a large one.
#[test]
fn unknown_cells_of_a_ros_map_have_their_own_colour_in_gifs() {
    // A 6 x 4 trinary map: `#` occupied (0), `?` unknown (205), `.` free (254).
    let rows = ["..?...", "..#??.", "......", "?....."];
    let dir =
        Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("gif-unknown-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    planner_testkit::write_ros_map(&dir, "m", &rows);
    let args = PlanArgs {
        map: dir.join("m.yaml"),
        planner: "astar".into(),
        start: Some(planner_api::Cell::new(0, 0)),
        goal: Some(planner_api::Cell::new(5, 2)),
        ..PlanArgs::default()
    };
    let options = PlanOptions {
        record_expanded: true,
        ..PlanOptions::default()
    };
    let result = planner_runner::plan::run_with(&args, &options).unwrap();
    let bytes = planner_serve::anim::plan_gif(&result).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let (w, _, frames) = decode_indexed(&bytes);
    // Eight pixels a cell (512 / 6, at most 8); the colour of a cell at its centre.
    assert_eq!(w, 48);
    let unknown = planner_serve::anim::palette_rgb(21);
    assert_eq!(unknown, [160, 180, 200]);
    for frame in &frames {
        for (y, row) in rows.iter().enumerate() {
            for (x, c) in row.bytes().enumerate() {
                let index = frame[(y * 8 + 4) * w + x * 8 + 4];
                match c {
                    b'?' => assert_eq!(index, 21, "unknown ({x}, {y})"),
                    b'#' => assert_eq!(index, 1, "wall ({x}, {y})"),
                    _ => assert!(index != 21 && index != 1, "free ({x}, {y}): {index}"),
                }
            }
        }
    }

    // Blocks of 2 x 2 cells: the first all unknown, the second half unknown with one of
    // its two known cells blocked (half: the grey of level 8), the third free.
    let mut grid = planner_api::Grid::new(1024, 2).unwrap();
    grid.set_free(planner_api::Cell::new(3, 0), false);
    let mut mask = vec![false; 2048];
    for (x, y) in [(0, 0), (1, 0), (0, 1), (1, 1), (2, 0), (2, 1)] {
        mask[y * 1024 + x] = true;
    }
    let (start, goal) = (
        planner_api::Cell::new(1023, 0),
        planner_api::Cell::new(1023, 1),
    );
    let search = planner_serve::anim::Search {
        grid: &grid,
        start,
        goal,
        expanded: &[start],
        path: &[start, goal],
        unknown: Some(&mask),
    };
    let bytes = planner_serve::anim::gif(&search, usize::MAX).unwrap();
    let (w, h, frames) = decode_indexed(&bytes);
    assert_eq!((w, h), (512, 1));
    let half = planner_serve::anim::block_index(1, 2);
    assert_eq!(half, 6 + 8 - 1);
    for frame in &frames {
        assert_eq!(&frame[..3], &[21, half, 0]);
    }
}
