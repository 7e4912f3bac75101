//! Bounded reading (issue 18): non-regular files are refused, declared sizes are checked
//! against [`ReadOptions::max_cells`] before anything is allocated, files against
//! [`ReadOptions::max_file_bytes`]; and the `.csv` convention with its inversion hint.

use std::path::{Path, PathBuf};

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
    png.extend(crc32(&png[12..]).to_be_bytes());
    // An empty IDAT chunk: the decoder reads the header up to the first data.
    png.extend(b"\x00\x00\x00\x00IDAT");
    png.extend(crc32(b"IDAT").to_be_bytes());
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

/// CRC-32 (ISO-HDLC, PNG's), bit by bit.
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &byte in bytes {
        crc ^= u32::from(byte);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xedb8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
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
