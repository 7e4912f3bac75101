//! Bounded reading (issue 18): non-regular files are refused, declared sizes are checked
//! against [`ReadOptions::max_cells`] before anything is allocated, files against
//! [`ReadOptions::max_file_bytes`]; and the `.csv` convention with its inversion hint.

use std::path::{Path, PathBuf};

use crate::common;

use planner_api::Cell;
use planner_maps::{
    csv_inversion_hint, read_map, read_map_with, read_scenarios, CsvConvention, MapErrorKind,
    MapFormat, ReadOptions,
};

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("planner-maps-limits");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Reads `path` with `options` and compares the error's display with `expect`.
fn check(path: &Path, options: &ReadOptions, expect: &str) {
    match read_map_with(path, options) {
        Ok(_) => panic!("{}: read, expected {expect:?}", path.display()),
        Err(err) => assert_eq!(err.to_string(), expect),
    }
}

#[test]
#[cfg(unix)]
fn devices_fifos_and_directories_are_refused() {
    let options = ReadOptions::default();
    // /dev/zero never ends: it used to be read until memory ran out. Through a symbolic
    // link with a map extension, as a user could make it.
    let link = tmp("zero.map");
    let _ = std::fs::remove_file(&link);
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    check(
        &link,
        &options,
        &format!(
            "{}: not a regular file (a character device): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only",
            link.display()
        ),
    );
    let png = tmp("zero.png");
    let _ = std::fs::remove_file(&png);
    std::os::unix::fs::symlink("/dev/zero", &png).unwrap();
    let err = read_map(&png).unwrap_err();
    assert!(
        matches!(
            err.kind,
            MapErrorKind::NotRegularFile {
                what: "a character device"
            }
        ),
        "{err}"
    );
    let scen = tmp("zero.scen");
    let _ = std::fs::remove_file(&scen);
    std::os::unix::fs::symlink("/dev/zero", &scen).unwrap();
    let err = read_scenarios(&scen).unwrap_err();
    assert!(
        matches!(err.kind, MapErrorKind::NotRegularFile { .. }),
        "{err}"
    );

    // A directory named like a map.
    let dir = tmp("dir.map");
    std::fs::create_dir_all(&dir).unwrap();
    check(
        &dir,
        &options,
        &format!(
            "{}: not a regular file (a directory): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only",
            dir.display()
        ),
    );

    // A FIFO would block the open until a writer came: it is refused before opening.
    let fifo = tmp("fifo.txt");
    let _ = std::fs::remove_file(&fifo);
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let err = read_map(&fifo).unwrap_err();
        assert!(
            matches!(err.kind, MapErrorKind::NotRegularFile { what: "a FIFO" }),
            "{err}"
        );
    }

    // A ROS YAML naming /dev/zero as its image.
    let yaml = tmp("zero-image.yaml");
    std::fs::write(
        &yaml,
        "image: /dev/zero\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
    // The error is at the YAML's `image` value (line 1, column 8).
    check(
        &yaml,
        &options,
        &format!("{}:1:8: image '/dev/zero': not a regular file (a character device): gridplan reads its inputs (maps, images, scenarios, configs, weights) from regular files only", yaml.display()),
    );
}

#[test]
fn files_larger_than_the_limit_are_refused() {
    let path = tmp("big.map");
    std::fs::write(&path, "type octile\nheight 1\nwidth 4\nmap\n....\n").unwrap();
    let small = ReadOptions {
        max_file_bytes: 10,
        ..ReadOptions::default()
    };
    check(
        &path,
        &small,
        &format!(
            "{}: the file has 38 bytes, more than the limit of 10 bytes",
            path.display()
        ),
    );
    assert_eq!(read_map(&path).unwrap().grid.len(), 4);
}

#[test]
fn declared_sizes_are_checked_before_allocating() {
    let small = ReadOptions {
        max_cells: 6,
        ..ReadOptions::default()
    };
    let parse = |format: MapFormat, text: &str| {
        format
            .parse_with(text, "t", &small)
            .map(|read| read.file.grid.len())
            .map_err(|e| e.to_string())
    };
    // The header is enough: no row is there.
    assert_eq!(
        parse(MapFormat::MovingAi, "type octile\nheight 3\nwidth 3\nmap\n"),
        Err("t:4:1: a 3x3 map has 9 cells, more than the limit of 6 cells".to_owned())
    );
    assert_eq!(
        parse(
            MapFormat::MovingAi,
            "type octile\nheight 2\nwidth 3\nmap\n...\n...\n"
        ),
        Ok(6)
    );
    // Row formats stop at the row that passes the limit.
    assert_eq!(
        parse(MapFormat::Seed003, "...\n...\n...\n...\n"),
        Err("t:3:1: a 3x3 map has 9 cells, more than the limit of 6 cells".to_owned())
    );
    assert_eq!(
        parse(MapFormat::Matrix, "1,1,1,1,1,1,1\n"),
        Err("t:1:1: a 7x1 map has 7 cells, more than the limit of 6 cells".to_owned())
    );
    // Issue 27: the default limit is the largest grid (2^31 cells), no longer 2^28; a
    // header declaring 2 * 10^9 cells over a few bytes is still refused at once, without
    // reserving more than the file's size.
    let err = MapFormat::MovingAi
        .parse_with(
            "type octile\nheight 40000\nwidth 50000\nmap\n..\n",
            "t.map",
            &ReadOptions::default(),
        )
        .unwrap_err();
    assert!(err.to_string().starts_with("t.map:5:"), "{err}");
    // Image headers: a PGM claiming 100000 x 100000 pixels with no data, and a PNG
    // header claiming 2^31 - 1 squared; neither is decoded.
    let default = ReadOptions::default();
    let err = MapFormat::Image
        .parse_bytes(b"P5\n100000 100000\n255\n", "huge.pgm", &default)
        .unwrap_err();
    assert_eq!(
        err.to_string(),
        "huge.pgm: a 100000x100000 map has 10000000000 cells, more than the limit of 2147483648 cells"
    );
    let mut png = b"\x89PNG\r\n\x1a\n\x00\x00\x00\x0dIHDR".to_vec();
    png.extend(0x7fff_ffffu32.to_be_bytes());
    png.extend(0x7fff_ffffu32.to_be_bytes());
    png.extend([8, 0, 0, 0, 0]);
    png.extend(common::crc32(&png[12..]).to_be_bytes());
    // An empty IDAT chunk: the decoder reads the header up to the first data.
    png.extend(b"\x00\x00\x00\x00IDAT");
    png.extend(common::crc32(b"IDAT").to_be_bytes());
    let err = MapFormat::Image
        .parse_bytes(&png, "huge.png", &default)
        .unwrap_err();
    assert!(
        matches!(
            err.kind,
            MapErrorKind::TooManyCells {
                width: 0x7fff_ffff,
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn csv_convention_and_inversion_hint() {
    let text = "0,0,1\n1,0,0\n";
    let read = |csv| {
        MapFormat::Matrix
            .parse_with(
                text,
                "m.csv",
                &ReadOptions {
                    csv,
                    ..ReadOptions::default()
                },
            )
            .unwrap()
            .file
            .grid
    };
    let zero = read(CsvConvention::ZeroIsObstacle);
    let one = read(CsvConvention::OneIsObstacle);
    assert_eq!(zero.to_ascii(), "##.\n.##\n");
    assert_eq!(one.to_ascii(), "..#\n#..\n");
    assert_eq!(
        CsvConvention::from_obstacle_value(1),
        Some(CsvConvention::OneIsObstacle)
    );
    assert_eq!(CsvConvention::from_obstacle_value(2), None);
    assert_eq!(CsvConvention::default().obstacle_value(), 0);

    let (start, goal) = (Cell::new(0, 0), Cell::new(2, 1));
    let hint = csv_inversion_hint(&zero, CsvConvention::ZeroIsObstacle, start, goal).unwrap();
    assert_eq!(
        hint.to_string(),
        "start (0, 0) and goal (2, 1) are blocked with obstacle = 0 but free with obstacle = 1: the map looks written with 1 = obstacle"
    );
    // Read the right way, there is nothing to say.
    assert_eq!(
        csv_inversion_hint(&one, CsvConvention::OneIsObstacle, start, goal),
        None
    );
    // Blocked in both conventions' sense (one blocked, one free) or outside: no hint.
    assert_eq!(
        csv_inversion_hint(&zero, CsvConvention::ZeroIsObstacle, start, Cell::new(2, 0)),
        None
    );
    assert_eq!(
        csv_inversion_hint(&zero, CsvConvention::ZeroIsObstacle, start, Cell::new(9, 9)),
        None
    );
    // The other way round.
    let hint = csv_inversion_hint(
        &one,
        CsvConvention::OneIsObstacle,
        Cell::new(2, 0),
        Cell::new(0, 1),
    )
    .unwrap();
    assert!(
        hint.to_string().ends_with(
            "with obstacle = 1 but free with obstacle = 0: the map looks written with 0 = obstacle"
        ),
        "{hint}"
    );
}

#[test]
fn images_read_directly() {
    // An ASCII PGM: white free, black occupied, grey 205 unknown (map_server's defaults).
    let path = tmp("direct.pgm");
    std::fs::write(&path, "P2\n3 2\n255\n255 0 205\n254 255 90\n").unwrap();
    let file = read_map(&path).unwrap();
    assert_eq!(file.format, MapFormat::Image);
    assert_eq!(file.grid.to_ascii(), ".##\n..#\n");
    // Not an image: the decoder's message, naming the file, no internal function.
    let bad = tmp("bad.png");
    std::fs::write(&bad, "not an image").unwrap();
    let err = read_map(&bad).unwrap_err();
    assert_eq!(
        err.to_string(),
        format!(
            "{}: cannot decode the image: The image format could not be determined",
            bad.display()
        )
    );
}

/// Reads `bytes` as an image map with the default limits: the error's message (the map's
/// size when it reads) and the most heap the read held.
fn read_image_bounded(name: &str, bytes: &[u8]) -> (String, u64) {
    let baseline = common::reset_peak();
    let read = MapFormat::Image.parse_bytes(bytes, name, &ReadOptions::default());
    let peak = common::peak_since(baseline);
    let said = match read {
        Ok(read) => format!("read {}", read.file.grid.len()),
        Err(err) => err.to_string(),
    };
    (said, peak)
}

/// The probe's PNG: an `IHDR` declaring `width` x `height` pixels of `depth` bits and
/// colour type `colour` (interlaced when `interlace` is 1), and one `IDAT` of the zlib
/// stream of 1000 zero bytes (17 bytes), then `IEND`: 74 bytes in all.
fn tiny_idat_png(size: (u32, u32), depth: u8, colour: u8, interlace: u8) -> Vec<u8> {
    let zeros = b"\x78\x9c\x63\x60\x18\x05\xa3\x60\x14\x0c\x77\x00\x00\x03\xe8\x00\x01";
    common::png_file(size, (depth, colour, interlace), &[], zeros)
}

/// An image whose header declares far more pixels than its data holds allocates about
/// what the data holds (here under 8 MiB) and is an error naming the file, never an abort:
/// the probe's 74-byte PNG declaring 40000 x 40000 16-bit RGBA pixels made the reader
/// allocate the 12.8 GB decode buffer first (SIGABRT where that failed); PBM bitmaps
/// likewise allocated their whole decoded size before finding the raster short. A PNG
/// whose compressed data cannot inflate to its pixels is refused before decoding; one that
/// could is decoded a row at a time, so data that ends after a few rows says so.
#[test]
fn images_declaring_more_than_their_data_allocate_what_they_hold() {
    let repro = tiny_idat_png((40000, 40000), 16, 6, 0);
    assert_eq!(repro.len(), 74);
    // Three white rows of a grey 4000 x 40 PNG: a whole zlib stream, and one cut short
    // (a stored block that is not the last, no checksum).
    let three_rows = common::unfiltered(&vec![vec![255u8; 4000]; 3]);
    let whole = common::zlib_stored(&three_rows);
    let mut cut = whole[..whole.len() - 4].to_vec();
    cut[2] = 0;
    let grey = |height: u32, idat: &[u8]| common::png_file((4000, height), (8, 0, 0), &[], idat);
    // 40 rows of 40000 bytes that do not compress, stored: 1.6 MB of data, which could
    // inflate to the 1.6 GB of the 40000 x 40000 pixels declared.
    let mut state = 1u32;
    let noise: Vec<Vec<u8>> = (0..40)
        .map(|_| {
            (0..40000)
                .map(|_| {
                    state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                    (state >> 24) as u8
                })
                .collect()
        })
        .collect();
    let forty_rows = common::zlib_stored(&common::unfiltered(&noise));
    let too_small = |name: &str, needed: u64| {
        format!("{name}: the header declares 40000x40000 pixels, {needed} bytes, but the file's 17 bytes of compressed pixel data inflate to at most 17544 bytes: the file is cut short or damaged")
    };
    let ends = |name: &str, pixels: u64, size: &str, reason: &str| {
        format!("{name}: the pixel data ends after {pixels} of the {size} pixels the header declares ({reason}): the file is cut short or damaged")
    };
    let no_data = "IDAT or fDAT chunk does not have enough data for image";
    let pbm = |name: &str, found: u32| {
        format!("{name}: cannot decode the image: expected 1600000000 samples (40000x40000 pixels of 1), found {found}")
    };
    let cases = [
        ("big.png", repro, too_small("big.png", 12_800_000_000)),
        (
            "interlaced.png",
            tiny_idat_png((40000, 40000), 8, 0, 1),
            too_small("interlaced.png", 1_600_000_000),
        ),
        (
            "rows.png",
            common::png_file((40000, 40000), (8, 0, 0), &[], &forty_rows),
            ends("rows.png", 1_600_000, "40000x40000", no_data),
        ),
        (
            "grey.png",
            grey(40, &whole),
            ends("grey.png", 12000, "4000x40", no_data),
        ),
        (
            "cut.png",
            grey(40, &cut),
            ends(
                "cut.png",
                0,
                "4000x40",
                "Corrupt deflate stream. InsufficientInput",
            ),
        ),
        (
            "bits.pbm",
            b"P4\n40000 40000\n\x00\xff\x00".to_vec(),
            pbm("bits.pbm", 0),
        ),
        (
            "digits.pbm",
            b"P1\n40000 40000\n0 1 0\n".to_vec(),
            pbm("digits.pbm", 3),
        ),
    ];
    for (name, bytes, expect) in cases {
        let (said, peak) = read_image_bounded(name, &bytes);
        assert_eq!(said, expect);
        assert!(peak < 8 << 20, "{name}: held {peak} bytes at the peak");
    }
}
