//! Hostile inputs for every reader, through the same entry points as the fuzz targets
//! (`fuzz/`): each must give a clear error or a map, never a panic, a hang or an
//! allocation the input does not pay for. Inputs a fuzzer finds crashing belong here too.

use planner_maps::{parse_ros_yaml, parse_scenarios, MapFormat, ReadOptions};

/// Reads `bytes` as `format` and compares the outcome (`ok WxH` or the error) with
/// `expect`.
fn check(format: MapFormat, bytes: &[u8], expect: &str) {
    let got = match format.parse_bytes(bytes, "f", &ReadOptions::default()) {
        Ok(read) => format!("ok {}x{}", read.file.grid.width(), read.file.grid.height()),
        Err(err) => err.to_string(),
    };
    assert_eq!(
        got,
        expect,
        "{format:?} {:?}",
        String::from_utf8_lossy(bytes)
    );
}

#[test]
fn yaml_alias_bomb_stays_small() {
    // Nine levels of nine aliases each would be 9^9 = 387 million scalars if expanded;
    // aliases share the anchored node, so this reads at once.
    let mut text = String::from("l0: &l0 [x, x, x, x, x, x, x, x, x]\n");
    for level in 1..=9 {
        let previous = format!("*l{}", level - 1);
        let items = [previous.as_str(); 9].join(", ");
        text.push_str(&format!("l{level}: &l{level} [{items}]\n"));
    }
    text.push_str("image: m.pgm\nresolution: 1\norigin: [0, 0, 0]\nnegate: 0\n");
    text.push_str("occupied_thresh: 0.65\nfree_thresh: 0.196\n");
    let yaml = parse_ros_yaml(&text, "bomb.yaml").unwrap();
    assert_eq!(yaml.warnings.len(), 10);
    // An alias used as the origin is read through.
    let text = "o: &o [1, 2, 3]\nimage: m.pgm\nresolution: 1\norigin: *o\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
    assert_eq!(
        parse_ros_yaml(text, "a.yaml").unwrap().origin,
        [1.0, 2.0, 3.0]
    );
}

#[test]
fn yaml_deep_nesting_is_refused_early() {
    // 100000 open brackets: the YAML scanner, which reads ahead of the events, stops at
    // its own limit of 256 flow levels, without recursion; block nesting reaches ours.
    let text = "[".repeat(100_000);
    let err = parse_ros_yaml(&text, "deep.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "deep.yaml:1:256: invalid YAML: recursion limit exceeded"
    );
    let text: String = (0..100)
        .map(|depth| format!("{}- \n", "  ".repeat(depth)))
        .collect();
    let err = parse_ros_yaml(&text, "deep.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "deep.yaml:65:129: expected at most 64 nested sequences and mappings, found more"
    );
    let text = "{a: ".repeat(100_000);
    assert!(parse_ros_yaml(&text, "deep.yaml").is_err());
}

#[test]
fn yaml_odd_bytes() {
    let cases: [(&str, &str); 6] = [
        // The byte-order mark is not a column, as in the other readers.
        ("\u{feff}image: a", "b.yaml:1:1: missing key 'resolution'"),
        // NUL is not a YAML character: the scanner takes it for the end of the stream.
        ("image: \"a\0b\"", "b.yaml:1:8: invalid YAML: while scanning a quoted scalar, found unexpected end of stream"),
        ("'unclosed", "b.yaml:1:1: invalid YAML: while scanning a quoted scalar, found unexpected end of stream"),
        ("\t", "b.yaml:1:2: expected a mapping of map_server keys (image, resolution, ...), found end of file"),
        ("*nothing", "b.yaml:1:1: invalid YAML: while parsing node, found unknown anchor"),
        ("---\n...\n", "b.yaml:2:1: expected a mapping of map_server keys (image, resolution, ...), found null"),
    ];
    for (text, expect) in cases {
        let got = match parse_ros_yaml(text, "b.yaml") {
            Ok(_) => "ok".to_owned(),
            Err(e) => e.to_string(),
        };
        assert_eq!(got, expect, "{text:?}");
    }
}

#[test]
fn yaml_errors_stay_inside_the_text() {
    // Found by `fuzz/run.sh ros_yaml` (crash-4fdd356c...): the scanner put this error on
    // line 3 of a 2-line text; it now points at the end of the text.
    let text = "image: \"testmap/png\"\nresolmua :geit";
    let err = parse_ros_yaml(text, "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:2:15: invalid YAML: simple key expected"
    );
    // The same with a final newline: the end is line 3, column 1.
    let err = parse_ros_yaml(&format!("{text}\n"), "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:3:1: invalid YAML: simple key expect ':'"
    );
    // The second input `fuzz/run.sh ros_yaml` flagged, "\rJ*": a lone carriage return is
    // a YAML line break, which the target's line count missed. Positions and the end of
    // the text count it (the reader was right; the target now counts as YAML does).
    let err = parse_ros_yaml("\rJ*", "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:2:1: expected a mapping of map_server keys (image, resolution, ...), found 'J*'"
    );
    let err = parse_ros_yaml("# a\r# b\r\n", "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:3:1: expected a mapping of map_server keys (image, resolution, ...), found end of file"
    );
    // The third: "---" alone, an empty document the parser placed on line 2.
    let err = parse_ros_yaml("---", "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:1:4: expected a mapping of map_server keys (image, resolution, ...), found null"
    );
    let err = parse_ros_yaml("image: \"a\rb", "f.yaml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "f.yaml:1:8: invalid YAML: invalid indentation in quoted scalar"
    );
}

#[test]
fn text_formats_hostile_input() {
    check(
        MapFormat::MovingAi,
        b"\xff",
        "f:1:1: expected UTF-8 text, found byte 0xff",
    );
    check(
        MapFormat::MovingAi,
        b"type octile\nheight 4294967295\nwidth 4294967295\nmap\n",
        "f:4:1: a 4294967295x4294967295 map has 18446744065119617025 cells, more than the limit of 2147483648 cells",
    );
    check(
        MapFormat::Seed003,
        b"\0",
        "f:1:1: expected '.' or 'X', found '\\0'",
    );
    check(MapFormat::Matrix, b"1,0\r\n0,1\r\n", "ok 2x2");
    check(MapFormat::Matrix, "1\u{a0}0\n".as_bytes(), "ok 2x1");
    assert!(parse_scenarios("version 1\n0\tm\t1\t1\t0\t0\t0\t0\tNaN\n", "s").is_err());
    assert!(parse_scenarios("version 1\n0\tm\t1\t1\t0\t0\t0\t0\tinf\n", "s").is_err());
}

#[test]
fn images_truncated_or_garbled() {
    check(
        MapFormat::Image,
        b"",
        "f: cannot decode the image: The image format could not be determined",
    );
    check(
        MapFormat::Image,
        b"P5\n0 0\n255\n",
        "f: invalid grid: a grid needs at least one row and one column",
    );
    check(
        MapFormat::Image,
        b"P2 2 1 255 0",
        "f: cannot decode the image: expected 2 samples (2x1 pixels of 1), found 1",
    );
    check(MapFormat::Image, b"P2 2 1 255 0 255", "ok 2x1");
    // A real map cut short.
    let pgm = std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../maps/ros-nav2/tb3_sandbox.pgm"
    ))
    .unwrap();
    let err = MapFormat::Image
        .parse_bytes(&pgm[..1000], "cut.pgm", &ReadOptions::default())
        .unwrap_err();
    assert!(
        err.to_string()
            .starts_with("cut.pgm: cannot decode the image: "),
        "{err}"
    );
}
