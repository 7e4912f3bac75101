//! ROS map_server maps: small PGM and PNG images written here, read back through the YAML.

use std::path::{Path, PathBuf};

use crate::common;

use planner_api::Cell;
use planner_maps::{
    parse_ros_yaml, read_map, read_ros_map, MapErrorKind, MapFormat, MapFrame, RosMode, RosOptions,
};

/// A fresh directory for one test's files.
fn dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ros")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const YAML: &str = "\
# written by map_saver
image: map.pgm
resolution: 0.050000
origin: [-1.000000, -2.000000, 0.000000]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
";

/// A 4 x 3 binary PGM (P5): white (254) free, black (0) occupied, grey (205) unknown.
///   254 254   0 254
///   254 205 254 254
///     0 254 254 254
fn write_pgm(dir: &Path) {
    let mut bytes = b"P5\n# gridplan test\n4 3\n255\n".to_vec();
    bytes.extend([254, 254, 0, 254, 254, 205, 254, 254, 0, 254, 254, 254]);
    std::fs::write(dir.join("map.pgm"), bytes).unwrap();
}

#[test]
fn pgm_trinary_by_hand() {
    let dir = dir("trinary");
    write_pgm(&dir);
    std::fs::write(dir.join("map.yaml"), YAML).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.yaml.mode, RosMode::Trinary);
    assert_eq!(map.occupancy, [0, 0, 100, 0, 0, -1, 0, 0, 100, 0, 0, 0]);
    // Unknown is blocked: 12 cells - 2 occupied - 1 unknown.
    assert_eq!(
        map.grid.to_ascii(),
        "\
..#.
.#..
#...
"
    );
    // Cell (0, 2) is the image's bottom-left pixel: the origin cell, centre at +0.025 m.
    let (x, y) = map.world(Cell::new(0, 2));
    assert!((x - -0.975).abs() < 1e-12 && (y - -1.975).abs() < 1e-12);
    let (x, y) = map.world(Cell::new(3, 0));
    assert!((x - -0.825).abs() < 1e-12 && (y - -1.875).abs() < 1e-12);

    // read_map dispatches on the extension, with default options.
    let file = read_map(&dir.join("map.yaml")).unwrap();
    assert_eq!(file.format, MapFormat::Ros);
    assert_eq!(file.grid, map.grid);
    assert!(file.problems.is_empty());
    // The YAML's frame, and back from a point to its cell: the origin corner's cell.
    assert_eq!(file.frame, Some(map.frame()));
    let frame = map.frame();
    assert_eq!(frame.cell_at(-1.0, -2.0), Some(Cell::new(0, 2)));
    assert_eq!(frame.cell_at(-0.826, -1.851), Some(Cell::new(3, 0)));
    for (got, expect) in frame.bounds().into_iter().zip([-1.0, -2.0, -0.8, -1.85]) {
        assert!((got - expect).abs() < 1e-12, "{got} {expect}");
    }

    // Inflation by one cell blocks the 4-neighbours of the two occupied cells only.
    let inflated = read_ros_map(
        &dir.join("map.yaml"),
        &RosOptions {
            inflation_radius: 1,
            inflate_unknown: false,
        },
    )
    .unwrap();
    assert_eq!(
        inflated.grid.to_ascii(),
        "\
.###
###.
##..
"
    );
}

#[test]
fn ascii_pgm_negated() {
    let dir = dir("negated");
    // P2 (ASCII) with maxval 255; negated, so black (0) is free and white occupied.
    std::fs::write(dir.join("map.pgm"), "P2\n3 2\n255\n0 0 255\n0 255 0\n").unwrap();
    let yaml = YAML.replace("negate: 0", "negate: 1");
    std::fs::write(dir.join("map.yaml"), yaml).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.grid.to_ascii(), "..#\n.#.\n");
}

#[test]
fn png_scale_with_alpha() {
    let dir = dir("png");
    // Grey + alpha: free white, occupied black, mid grey 170 (p = 1/3 -> value 30, a partly
    // occupied cell, blocked), and a transparent mid grey (unknown in scale mode).
    let img =
        image::GrayAlphaImage::from_raw(4, 1, vec![255, 255, 0, 255, 170, 255, 170, 0]).unwrap();
    img.save(dir.join("map.png")).unwrap();
    let yaml = YAML.replace("map.pgm", "\"map.png\"") + "mode: scale  # partly occupied\n";
    std::fs::write(dir.join("map.yaml"), yaml).unwrap();
    let map = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap();
    assert_eq!(map.yaml.mode, RosMode::Scale);
    assert_eq!(map.occupancy, [0, 100, 30, -1]);
    assert_eq!(map.grid.to_ascii(), ".###\n");
}

/// Reads `image` (written as `name` in a fresh directory) through a YAML with `mode` and
/// gives the occupancy values, or the error's text.
fn occupancy_of(test: &str, name: &str, image: &[u8], mode: &str) -> Result<Vec<i8>, String> {
    let dir = dir(test);
    std::fs::write(dir.join(name), image).unwrap();
    let yaml = YAML.replace("map.pgm", name) + &format!("mode: {mode}\n");
    std::fs::write(dir.join("map.yaml"), yaml).unwrap();
    read_ros_map(&dir.join("map.yaml"), &RosOptions::default())
        .map(|map| map.occupancy)
        .map_err(|e| e.to_string().replace(&format!("{}/", dir.display()), ""))
}

/// A PNG of `pixels` (`width` x 1) written with the image crate.
fn png<P: image::Pixel + image::PixelWithColorType>(width: u32, pixels: Vec<P::Subpixel>) -> Vec<u8>
where
    [P::Subpixel]: image::EncodableLayout,
{
    let img = image::ImageBuffer::<P, _>::from_raw(width, 1, pixels).unwrap();
    let mut bytes = std::io::Cursor::new(Vec::new());
    img.write_to(&mut bytes, image::ImageFormat::Png).unwrap();
    bytes.into_inner()
}

/// 16-bit samples and a maxval other than 255 or 65535 are read at full precision, as
/// nav2 reads them (`v / maxval`): cutting them to 8 bits first moved cells across a
/// threshold. Each case's first value is one the 8-bit cut got wrong.
#[test]
fn samples_are_read_at_full_precision() {
    // 805 / 1000: p = 0.195 < 0.196, free (205 / 255 gave p = 0.19608, unknown).
    let ascii = b"P2\n2 1\n1000\n805 1000\n";
    assert_eq!(
        occupancy_of("p2-1000", "q.pgm", ascii, "trinary"),
        Ok(vec![0, 0])
    );
    // 161 / 200: p = 0.195, free (the decoder's 8-bit 205 gave unknown).
    let small = b"P5\n2 1\n200\n\xa1\xc8";
    assert_eq!(
        occupancy_of("p5-200", "q.pgm", small, "trinary"),
        Ok(vec![0, 0])
    );
    // 52000 / 65535: p = 0.20653 -> rint(2.32) = 2 in scale mode (202 / 255 gave 3).
    let wide = b"P5\n2 1\n65535\n\xcb\x20\xff\xff";
    assert_eq!(
        occupancy_of("p5-16", "s.pgm", wide, "scale"),
        Ok(vec![2, 0])
    );
    // A PPM and a PAM (grey and alpha, opaque) the same way.
    let ppm = b"P3\n1 1\n1000\n805 805 805\n";
    assert_eq!(
        occupancy_of("p3-1000", "c.ppm", ppm, "trinary"),
        Ok(vec![0])
    );
    let pam = b"P7\nWIDTH 1\nHEIGHT 1\nDEPTH 2\nMAXVAL 65535\nTUPLTYPE GRAYSCALE_ALPHA\nENDHDR\n\xcb\x20\xff\xff";
    assert_eq!(occupancy_of("p7-16", "a.pam", pam, "scale"), Ok(vec![2]));
    // 16-bit PNGs: grey 52691 is p = 0.19599, free, 52690 unknown (both 205 in 8 bits);
    // RGB the same; grey and alpha in scale mode, opaque only at 65535.
    let grey = png::<image::Luma<u16>>(2, vec![52691, 52690]);
    assert_eq!(
        occupancy_of("png-16", "g.png", &grey, "trinary"),
        Ok(vec![0, -1])
    );
    let rgb = png::<image::Rgb<u16>>(1, vec![52691, 52691, 52691]);
    assert_eq!(
        occupancy_of("png-rgb-16", "c.png", &rgb, "trinary"),
        Ok(vec![0])
    );
    let alpha = png::<image::LumaA<u16>>(2, vec![52000, 65535, 52000, 65534]);
    assert_eq!(
        occupancy_of("png-la-16", "a.png", &alpha, "scale"),
        Ok(vec![2, -1])
    );

    // A sample above the maxval is an error naming the pixel, as GraphicsMagick refuses it
    // (the decoder scaled it to white); so is a raster cut short.
    let check = |test: &str, image: &[u8], expect: &str| {
        assert_eq!(
            occupancy_of(test, "m.pgm", image, "trinary"),
            Err(format!("m.pgm: cannot decode the image: {expect}"))
        )
    };
    check(
        "above-ascii",
        b"P2\n2 1\n100\n50 200\n",
        "pixel (1, 0) has sample '200', not a whole number from 0 to the maxval 100",
    );
    check(
        "not-a-number",
        b"P2\n2 1\n100\n50 5x\n",
        "pixel (1, 0) has sample '5x', not a whole number from 0 to the maxval 100",
    );
    check(
        "above-binary",
        b"P5\n1 2\n100\n\x32\xc8",
        "pixel (0, 1) has sample 200, above the maxval 100",
    );
    check(
        "short-16",
        b"P5\n2 2\n1000\n\x03\x25\x03\x25\x03",
        "expected 4 samples (2x2 pixels of 1), found 2",
    );
}

/// A PNG holding grey 8-bit pixels `grey` (`width` x 1), with a `tRNS` chunk making grey
/// `transparent` transparent when given: written by hand (stored deflate), since the image
/// crate writes no `tRNS`.
fn grey_png_with_trns(grey: &[u8], transparent: Option<u8>) -> Vec<u8> {
    let trns = transparent.map(|t| [0, t]);
    let extra: Vec<(&[u8; 4], &[u8])> = trns.iter().map(|t| (b"tRNS", &t[..])).collect();
    let idat = common::zlib_stored(&common::unfiltered(&[grey.to_vec()]));
    common::png_file((grey.len() as u32, 1), (8, 0, 0), &extra, &idat)
}

/// A PNG is decoded a row at a time, at its own depth: an interlaced one (Adam7's seven
/// passes, put back in row order), a palette of 2-bit indices and 16-bit RGBA give each
/// pixel its value where it lies. In raw mode a grey 0-100 is its own value, so a pixel
/// read into the wrong cell shows.
#[test]
fn pngs_of_every_layout_give_each_pixel_its_value() {
    let (w, h) = (11usize, 9usize);
    let grey = |x: usize, y: usize| ((x * 7 + y * 13) % 101) as u8;
    let expect: Vec<i8> = (0..h * w).map(|i| grey(i % w, i / w) as i8).collect();
    let rows = |pixel: &dyn Fn(usize, usize) -> Vec<u8>| -> Vec<Vec<u8>> {
        (0..h)
            .map(|y| (0..w).flat_map(|x| pixel(x, y)).collect())
            .collect()
    };
    let idat = |rows: &[Vec<u8>]| common::zlib_stored(&common::unfiltered(rows));
    let size = (w as u32, h as u32);
    let grey8 = |x, y| vec![grey(x, y)];
    let plain = common::png_file(size, (8, 0, 0), &[], &idat(&rows(&grey8)));
    assert_eq!(
        occupancy_of("png-plain", "p.png", &plain, "raw"),
        Ok(expect.clone())
    );
    // Interlaced: each pass's rows (first column, first row, steps), empty ones left out.
    let adam7 = [
        (0, 0, 8, 8),
        (4, 0, 8, 8),
        (0, 4, 4, 8),
        (2, 0, 4, 4),
        (0, 2, 2, 4),
        (1, 0, 2, 2),
        (0, 1, 1, 2),
    ];
    let passes = |pixel: &dyn Fn(usize, usize) -> Vec<u8>| -> Vec<Vec<u8>> {
        let mut out = Vec::new();
        for (x0, y0, dx, dy) in adam7 {
            for y in (y0..h).step_by(dy) {
                let row: Vec<u8> = (x0..w).step_by(dx).flat_map(|x| pixel(x, y)).collect();
                if !row.is_empty() {
                    out.push(row);
                }
            }
        }
        out
    };
    let interlaced = common::png_file(size, (8, 0, 1), &[], &idat(&passes(&grey8)));
    assert_eq!(
        occupancy_of("png-adam7", "i.png", &interlaced, "raw"),
        Ok(expect.clone())
    );
    // 16-bit RGBA, opaque, interlaced: grey g is 257 g in 16 bits.
    let rgba16 = |x, y| {
        let [high, low] = (u16::from(grey(x, y)) * 257).to_be_bytes();
        [high, low, high, low, high, low, 0xff, 0xff].to_vec()
    };
    let wide = common::png_file(size, (16, 6, 1), &[], &idat(&passes(&rgba16)));
    assert_eq!(
        occupancy_of("png-rgba16", "w.png", &wide, "raw"),
        Ok(expect)
    );
    // A palette of four greys, 2-bit indices packed four to a byte, the first pixel in the
    // high bits.
    let palette = [0u8, 40, 80, 100];
    let index = |x: usize, y: usize| (x + 2 * y) % 4;
    let packed: Vec<Vec<u8>> = (0..h)
        .map(|y| {
            let mut row = vec![0u8; w.div_ceil(4)];
            for x in 0..w {
                row[x / 4] |= (index(x, y) as u8) << (6 - 2 * (x % 4));
            }
            row
        })
        .collect();
    let plte: Vec<u8> = palette.iter().flat_map(|&g| [g, g, g]).collect();
    let indexed = common::png_file(size, (2, 3, 0), &[(b"PLTE", &plte)], &idat(&packed));
    let expect: Vec<i8> = (0..h * w)
        .map(|i| palette[index(i % w, i / w)] as i8)
        .collect();
    assert_eq!(
        occupancy_of("png-palette", "c.png", &indexed, "raw"),
        Ok(expect)
    );
}

/// PBM bitmaps (`P1` digits, `P4` bits packed from the high bit, each row on a byte): 1 is
/// black, occupied; 0 white, free; as the image crate decodes them (its grey 0 and 255).
#[test]
fn pbm_bitmaps_read_black_as_occupied() {
    let cases: [&[u8]; 4] = [
        b"P1\n3 2\n0 1 0\n110\n",
        b"P1 1 1 1",
        b"P4\n10 2\n\xa5\x40\x0f\xc0",
        b"P4 9 1\n\x01\x80",
    ];
    for (i, bytes) in cases.into_iter().enumerate() {
        let decoded = image::load_from_memory(bytes).unwrap().into_luma8();
        let expect: Vec<i8> = decoded
            .pixels()
            .map(|p| if p.0[0] == 0 { 100 } else { 0 })
            .collect();
        assert_eq!(
            occupancy_of(&format!("pbm-{i}"), "b.pbm", bytes, "trinary"),
            Ok(expect)
        );
    }
    assert_eq!(
        occupancy_of("pbm-2", "b.pbm", b"P1 3 1 0 2 1", "trinary"),
        Err("b.pbm: cannot decode the image: pixel (1, 0) has sample '2', not 0 or 1".to_owned())
    );
}

/// In trinary mode nav2 averages red, green, blue and alpha: a grey and alpha pixel counts
/// its grey three times, `(3 grey + alpha) / 4`, not `(grey + alpha) / 2`; a grey PNG
/// with `tRNS` has an alpha channel too. Other modes leave alpha out of the mean.
#[test]
fn alpha_is_averaged_with_three_colour_channels() {
    // Opaque grey 179: (537 + 255) / 4 = 198 -> p = 0.2235, unknown (the mean of grey and
    // alpha, 217, made it free); opaque 230: 236.25 -> p = 0.0735, free; transparent
    // 170: 127.5 -> p = 0.5, unknown (85 made it occupied).
    let grey_alpha = png::<image::LumaA<u8>>(3, vec![179, 255, 230, 255, 170, 0]);
    assert_eq!(
        occupancy_of("grey-alpha", "a.png", &grey_alpha, "trinary"),
        Ok(vec![-1, 0, -1])
    );
    // Grey 200 with tRNS (marking grey 0 transparent): the image has alpha, so opaque 200
    // is (600 + 255) / 4 = 213.75 -> p = 0.162, free, and the transparent 0 occupied;
    // without tRNS grey 200 is p = 0.2157, unknown.
    let with = grey_png_with_trns(&[200, 179, 0], Some(0));
    assert_eq!(
        occupancy_of("trns", "t.png", &with, "trinary"),
        Ok(vec![0, -1, 100])
    );
    let without = grey_png_with_trns(&[200, 179, 0], None);
    assert_eq!(
        occupancy_of("no-trns", "t.png", &without, "trinary"),
        Ok(vec![-1, -1, 100])
    );
    // Scale mode: the grey alone (200 -> p = 0.2157 -> 4, 179 -> 22), a transparent
    // pixel unknown.
    assert_eq!(
        occupancy_of("trns-scale", "t.png", &with, "scale"),
        Ok(vec![4, 22, -1])
    );
}

/// What reading `text` gives: `error: <message>`, or `ok` followed by one
/// `warning: <message>` line per warning.
fn outcome(text: &str) -> String {
    match parse_ros_yaml(text, "m.yaml") {
        Err(err) => format!("error: {err}"),
        Ok(yaml) => {
            let mut out = "ok".to_owned();
            for w in &yaml.warnings {
                out.push_str(&format!("\nwarning: {w}"));
            }
            out
        }
    }
}

/// Reads `text` and compares the outcome (see [`outcome`]) with `expect`.
fn check(text: &str, expect: &str) {
    assert_eq!(outcome(text), expect, "input:\n{text}");
}

#[test]
fn yaml_errors_name_line_and_column() {
    check(
        &YAML.replace("resolution: 0.050000", "resolution: fast"),
        "error: m.yaml:3:13: expected a number for 'resolution', found 'fast'",
    );
    check(
        &YAML.replace("negate: 0", "negate: maybe"),
        "error: m.yaml:5:9: expected an integer or a boolean (0, 1, true, false) for 'negate', found 'maybe'",
    );
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "[-1.0, x, 0.0]"),
        "error: m.yaml:4:16: expected a number for 'origin', found 'x'",
    );
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "[-1.0, 2.0]"),
        "error: m.yaml:4:9: expected three numbers [x, y, yaw] for 'origin', found 2 items",
    );
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "-1.0"),
        "error: m.yaml:4:9: expected a sequence [x, y, yaw] for 'origin', found '-1.0'",
    );
    check(
        &YAML.replace("free_thresh: 0.196\n", ""),
        "error: m.yaml:2:1: missing key 'free_thresh'",
    );
    check(
        &(YAML.to_owned() + "image: other.pgm\n"),
        "error: m.yaml:8:1: duplicate header key 'image', already given on line 2",
    );
    check(
        &YAML.replace("negate: 0", "negate:"),
        "error: m.yaml:5:7: expected an integer or a boolean (0, 1, true, false) for 'negate', found null",
    );
    check(
        &YAML.replace("image: map.pgm", "image: ''"),
        "error: m.yaml:2:8: expected an image file name for 'image', found an empty string",
    );
    check(
        &YAML.replace("image: map.pgm", "image: [a.pgm]"),
        "error: m.yaml:2:8: expected an image file name for 'image', found a sequence",
    );
    check(
        &YAML.replace("resolution: 0.050000", "resolution: .nan"),
        "error: m.yaml:3:13: expected a finite number for 'resolution', found '.nan'",
    );
    check(
        &(YAML.to_owned() + "mode: ternary\n"),
        "error: m.yaml:8:7: expected trinary, scale or raw for 'mode', found 'ternary'",
    );
    check(
        "- image: a.pgm\n",
        "error: m.yaml:1:1: expected a mapping of map_server keys (image, resolution, ...), found a sequence",
    );
    check(
        "# nothing\n",
        "error: m.yaml:2:1: expected a mapping of map_server keys (image, resolution, ...), found end of file",
    );
    // Invalid YAML: the parser's message at its position.
    check(
        &YAML.replace("[-1.000000, -2.000000, 0.000000]", "[-1.0, 2.0, 0.0"),
        "error: m.yaml:5:7: invalid YAML: illegal placement of ':' indicator",
    );
    check(
        "image: a.pgm\n  resolution: 1\n",
        "error: m.yaml:2:13: invalid YAML: mapping values are not allowed in this context",
    );
    check(
        &format!("a: {}1{}\n", "[".repeat(70), "]".repeat(70)),
        "error: m.yaml:1:67: expected at most 64 nested sequences and mappings, found more",
    );
}

#[test]
fn yaml_accepts_what_map_server_accepts() {
    // Issue 18: these valid files were rejected by the hand-written reader.
    // A block-sequence origin, nav2's test file style.
    let block = YAML.replace(
        "[-1.000000, -2.000000, 0.000000]",
        "\n  - -1.0\n  - -2.0\n  - 0.0",
    );
    check(&block, "ok");
    assert_eq!(
        parse_ros_yaml(&block, "m.yaml").unwrap().origin,
        [-1.0, -2.0, 0.0]
    );
    // A flow mapping, quoted numbers, an explicit document start, tags.
    let flow = "--- {image: \"map.pgm\", resolution: '0.05', origin: [0, 0, 0], negate: false, \
                occupied_thresh: !!float 0.65, free_thresh: 0.196, mode: \"scale\"}\n";
    check(
        flow,
        "ok\nwarning: m.yaml:1:71: 'negate' false is a boolean: ROS 2's nav2_map_server reads it as false (and so does gridplan), ROS 1's map_server refuses the file; write 0",
    );
    let yaml = parse_ros_yaml(flow, "m.yaml").unwrap();
    assert_eq!(
        (yaml.resolution, yaml.mode, yaml.negate),
        (0.05, RosMode::Scale, false)
    );
    // Anchors and aliases.
    let alias = YAML.replace("occupied_thresh: 0.65", "occupied_thresh: &t 0.65\nx: *t");
    check(
        &alias,
        "ok\nwarning: m.yaml:7:1: key 'x' is not one map_server reads (image, resolution, origin, occupied_thresh, free_thresh, negate, mode): ignored",
    );
    // Extra keys are read with a warning naming them: map_type (nav2's map_circular),
    // map_name, a misspelt key, a non-scalar key.
    check(
        &(YAML.to_owned() + "map_type: occupancy\nmap_name: depot\nfree_tresh: 0.2\n? [a]\n: 1\n"),
        "ok\n\
         warning: m.yaml:8:1: key 'map_type' is not one map_server reads (image, resolution, origin, occupied_thresh, free_thresh, negate, mode): ignored\n\
         warning: m.yaml:9:1: key 'map_name' is not one map_server reads (image, resolution, origin, occupied_thresh, free_thresh, negate, mode): ignored\n\
         warning: m.yaml:10:1: key 'free_tresh' is not one map_server reads (image, resolution, origin, occupied_thresh, free_thresh, negate, mode): ignored\n\
         warning: m.yaml:11:3: a sequence as a key is not one map_server reads: ignored",
    );
    // Values map_server reads as written, with a warning each.
    check(
        &YAML
            .replace("negate: 0", "negate: 2")
            .replace("occupied_thresh: 0.65", "occupied_thresh: 1.5")
            .replace("free_thresh: 0.196", "free_thresh: 1.6")
            .replace("resolution: 0.050000", "resolution: 0")
            .replace("0.000000]", "0.0, 7]"),
        "ok\n\
         warning: m.yaml:3:13: resolution 0 is not positive: map positions are meaningless\n\
         warning: m.yaml:4:9: 'origin' has 4 items: the first three are read, as ROS 1 map_server does\n\
         warning: m.yaml:5:9: 'negate' 2 is neither 0 nor 1: non-zero negates, as map_server reads it\n\
         warning: m.yaml:6:18: 'occupied_thresh' 1.5 is outside [0, 1]: read as written\n\
         warning: m.yaml:7:14: 'free_thresh' 1.6 is outside [0, 1]: read as written\n\
         warning: m.yaml:7:14: 'free_thresh' 1.6 is above 'occupied_thresh' 1.5: read as written",
    );
    let negated = parse_ros_yaml(&YAML.replace("negate: 0", "negate: 2"), "m.yaml").unwrap();
    assert!(negated.negate);
    for (text, negate) in [
        ("true", true),
        ("yes", true),
        ("On", true),
        ("0", false),
        ("off", false),
        ("-1", true),
    ] {
        let yaml = parse_ros_yaml(
            &YAML.replace("negate: 0", &format!("negate: {text}")),
            "m.yaml",
        )
        .unwrap();
        assert_eq!(yaml.negate, negate, "{text}");
        // Issue 27: a boolean was read silently, though ROS 1's map_server refuses it.
        let warned = yaml.warnings.iter().any(|w| {
            w.to_string().contains(&format!(
                "m.yaml:5:9: 'negate' {text} is a boolean: ROS 2's nav2_map_server reads it as {negate} (and so does gridplan), ROS 1's map_server refuses the file; write {}",
                u8::from(negate)
            ))
        });
        let is_integer = text.parse::<i64>().is_ok();
        assert_eq!(warned, !is_integer, "{text}: {:?}", yaml.warnings);
    }
    // A second document is ignored, as yaml-cpp's LoadFile does.
    check(
        &(YAML.to_owned() + "---\nimage: other.pgm\n"),
        "ok\nwarning: m.yaml:8:1: a second YAML document is ignored, as map_server does",
    );
    // Comments after values and quoted '#' are fine.
    let ok = parse_ros_yaml(
        &YAML.replace("image: map.pgm", "image: 'a #1.pgm'  # the map"),
        "m.yaml",
    )
    .unwrap();
    assert_eq!(ok.image, "a #1.pgm");
    assert_eq!(ok.origin, [-1.0, -2.0, 0.0]);
}

/// An image that cannot be read is an error at the YAML's `image` value, naming the path
/// it resolves to; one that cannot be decoded names the image.
#[test]
fn image_errors_name_the_image() {
    let dir = dir("bad-image");
    let yaml = dir.join("map.yaml");
    std::fs::write(&yaml, YAML).unwrap();
    let err = read_ros_map(&yaml, &RosOptions::default()).unwrap_err();
    assert_eq!(
        (err.file.as_str(), err.line, err.column),
        (yaml.to_str().unwrap(), 2, 8)
    );
    let MapErrorKind::NamedFile {
        what,
        name,
        path,
        reason,
    } = &err.kind
    else {
        panic!("{err}");
    };
    assert_eq!((*what, name.as_str()), ("image", "map.pgm"));
    assert_eq!(path, dir.join("map.pgm").to_str().unwrap());
    assert!(matches!(**reason, MapErrorKind::Io { .. }), "{err}");
    assert!(
        err.to_string().starts_with(&format!(
            "{}:2:8: image 'map.pgm' ({}): cannot read the file: ",
            yaml.display(),
            dir.join("map.pgm").display()
        )),
        "{err}"
    );
    // Through read_map too, and the same in a flow mapping: the value's own column.
    let err = read_map(&yaml).unwrap_err();
    assert_eq!((err.line, err.column), (2, 8), "{err}");
    std::fs::write(&yaml, "{resolution: 1, origin: [0, 0, 0], negate: 0, occupied_thresh: 0.65,\n free_thresh: 0.196, image: \"gone.png\"}\n").unwrap();
    let err = read_map(&yaml).unwrap_err();
    assert_eq!((err.line, err.column), (2, 29), "{err}");
    assert!(err.to_string().contains(": image 'gone.png' ("), "{err}");
    std::fs::write(&yaml, YAML).unwrap();
    std::fs::write(dir.join("map.pgm"), "P5\n4 3\n255\n\x01").unwrap();
    let err = read_ros_map(&dir.join("map.yaml"), &RosOptions::default()).unwrap_err();
    assert!(err.file.ends_with("map.pgm"), "{err}");
    assert!(matches!(err.kind, MapErrorKind::Image { .. }), "{err}");
    assert!(err.to_string().contains("cannot decode the image"), "{err}");
}

/// A map frame's points and cells, against the definition worked out independently of
/// `MapFrame`: every cell's centre maps back to the cell; points just inside each corner
/// map to the corner cells; the upper and right edges, points below or left of the
/// origin and non-finite points are outside (nav2's `worldToMap`; a point exactly on the
/// computed upper edge may round either way, as there).
#[test]
fn map_frame_points_and_cells() {
    for (resolution, origin, width, height) in [
        (0.05, [-10.0, -10.0, 0.0], 384u32, 384u32),
        (0.025, [-51.224998, -51.224998, 0.0], 411, 137),
        (1.0, [0.0, 0.0, 0.0], 10, 10),
        (0.1, [3.3, -7.7, 1.57], 1, 1),
        (0.3, [-1e6, 2e6, 0.0], 1000, 3),
    ] {
        let frame = MapFrame {
            resolution,
            origin,
            width,
            height,
        };
        for y in 0..height {
            for x in 0..width {
                let cell = Cell::new(x, y);
                let (wx, wy) = frame.world(cell);
                // The centre, written out: half a cell in from the corner, rows from the bottom.
                let expect_x = origin[0] + resolution * (x as f64 + 0.5);
                let expect_y = origin[1] + resolution * ((height - 1 - y) as f64 + 0.5);
                assert!((wx - expect_x).abs() < 1e-9 && (wy - expect_y).abs() < 1e-9);
                assert_eq!(frame.cell_at(wx, wy), Some(cell), "{frame:?} {cell}");
            }
        }
        let [x0, y0, x1, y1] = frame.bounds();
        let inset = resolution * 1e-3;
        assert_eq!(frame.cell_at(x0, y0), Some(Cell::new(0, height - 1)));
        assert_eq!(
            frame.cell_at(x1 - inset, y1 - inset),
            Some(Cell::new(width - 1, 0))
        );
        assert_eq!(frame.cell_at(x0 + inset, y1 - inset), Some(Cell::new(0, 0)));
        for (px, py) in [
            (x1 + inset, y0),
            (x0, y1 + inset),
            (x0 - inset, y0),
            (x0, y0 - inset),
            (f64::NAN, y0),
            (x0, f64::INFINITY),
            (f64::NEG_INFINITY, y0),
        ] {
            assert_eq!(frame.cell_at(px, py), None, "{frame:?} ({px}, {py})");
        }
    }
}

/// Only a YAML declares a frame: an image read alone has none (and nothing to say why),
/// and a YAML whose resolution is not positive or whose extent is beyond the range of
/// numbers has none either, and says why ([`MapFile::frame_error`]), so that a command
/// given points in metres can say what is wrong with the map's frame instead of asking for
/// the map_server YAML it was given.
#[test]
fn a_yaml_without_a_usable_frame_says_why() {
    let dir = dir("frames");
    write_pgm(&dir);
    let file = read_map(&dir.join("map.pgm")).unwrap();
    assert_eq!((file.frame, file.frame_error), (None, None));
    let origin = "[-1.000000, -2.000000, 0.000000]";
    for (resolution, origin, why) in [
        ("0.050000", origin, None),
        ("0", origin, Some("resolution 0 is not positive")),
        ("-1", origin, Some("resolution -1 is not positive")),
        ("-0.0", origin, Some("resolution -0 is not positive")),
        (
            "1e308",
            "[1.7e308, 0, 0]",
            Some("origin [1.7e308, 0, 0] plus resolution 1e308 times the image's 4x3 cells is beyond the range of numbers"),
        ),
        (
            "1e300",
            "[-1e300, 0, 0]",
            None,
        ),
    ] {
        let yaml = YAML
            .replace("resolution: 0.050000", &format!("resolution: {resolution}"))
            .replace("[-1.000000, -2.000000, 0.000000]", origin);
        std::fs::write(dir.join("map.yaml"), yaml).unwrap();
        let file = read_map(&dir.join("map.yaml")).unwrap();
        let said = file.frame_error.map(|e| e.to_string());
        assert_eq!(said.as_deref(), why, "resolution {resolution}");
        assert_eq!(file.frame.is_some(), why.is_none(), "resolution {resolution}");
    }
}

/// Numbers in messages are short at any magnitude: metres with at most six decimals below
/// a million kilometres and in scientific notation above (`1e300`, not its 301 digits, as
/// the overflow warning of `resolution: 1e308` and the extent of a huge map wrote them),
/// and a YAML's values in the shortest form that reads back to them.
#[test]
fn numbers_in_messages_are_short_at_any_magnitude() {
    for (value, text) in [
        (0.0, "0"),
        (-0.0, "0"),
        (0.05, "0.05"),
        (-1.4749999999999996, "-1.475"),
        (0.0000004, "0"),
        (999_999_999.25, "999999999.25"),
        (1e9, "1e9"),
        (-2.5e9, "-2.5e9"),
        (1.23456789e12, "1.234568e12"),
        (1e300, "1e300"),
        (-1.7e308, "-1.7e308"),
        (f64::MAX, "1.797693e308"),
        (f64::INFINITY, "inf"),
        (f64::NEG_INFINITY, "-inf"),
        (f64::NAN, "NaN"),
    ] {
        assert_eq!(planner_maps::metres(value), text, "{value:e}");
    }
    let frame = MapFrame {
        resolution: 1e300,
        origin: [-1e300, 2.0, 0.0],
        width: 10,
        height: 3,
    };
    assert_eq!(
        frame.extent(),
        "x from -1e300 to 9e300 and y from 2 to 3e300 (metres, the map frame; the upper ends excluded)"
    );
    // A YAML's values as written, however large or small.
    check(
        &YAML
            .replace("resolution: 0.050000", "resolution: -1e300")
            .replace("occupied_thresh: 0.65", "occupied_thresh: 1e300")
            .replace("free_thresh: 0.196", "free_thresh: 2E+300"),
        "ok\n\
         warning: m.yaml:3:13: resolution -1e300 is not positive: map positions are meaningless\n\
         warning: m.yaml:6:18: 'occupied_thresh' 1e300 is outside [0, 1]: read as written\n\
         warning: m.yaml:7:14: 'free_thresh' 2e300 is outside [0, 1]: read as written\n\
         warning: m.yaml:7:14: 'free_thresh' 2e300 is above 'occupied_thresh' 1e300: read as written",
    );
    check(
        &YAML.replace("resolution: 0.050000", "resolution: -0.0000001"),
        "ok\nwarning: m.yaml:3:13: resolution -1e-7 is not positive: map positions are meaningless",
    );
    // The frame of a resolution whose extent overflows: the warning's numbers.
    let dir = dir("huge-numbers");
    write_pgm(&dir);
    let yaml = dir.join("map.yaml");
    std::fs::write(
        &yaml,
        YAML.replace("resolution: 0.050000", "resolution: 1e308")
            .replace("[-1.000000, -2.000000, 0.000000]", "[1.7e308, 0.25, 0]"),
    )
    .unwrap();
    let read = planner_maps::read_map_with(&yaml, &planner_maps::ReadOptions::default()).unwrap();
    let warnings: Vec<String> = read.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(
        warnings,
        [format!(
            "{}: origin [1.7e308, 0.25, 0] plus resolution 1e308 times the image's 4x3 cells is beyond the range of numbers: map positions are meaningless",
            yaml.display()
        )]
    );
}
