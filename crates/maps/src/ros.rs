//! ROS `map_server` maps: a YAML file naming an image (PGM or PNG), read into a grid.
//!
//! # The YAML file
//! The flat `key: value` file `map_server` and `map_saver` use
//! (<https://wiki.ros.org/map_server#YAML_format>):
//!
//! | key | value | required |
//! |---|---|---|
//! | `image` | image path, relative to the YAML file's directory unless absolute | yes |
//! | `resolution` | metres per cell, > 0 | yes |
//! | `origin` | `[x, y, yaw]`: the pose of the lower-left cell in metres and radians | yes |
//! | `occupied_thresh` | in [0, 1] | yes |
//! | `free_thresh` | in [0, 1], at most `occupied_thresh` | yes |
//! | `negate` | `0`/`1` or `true`/`false` | yes |
//! | `mode` | `trinary` (default), `scale` or `raw` | no |
//!
//! Comments (`#`), blank lines, `---`, quoted scalars and flow sequences (`[a, b, c]`) are
//! read; anything else (indented or nested values, block sequences, unknown or repeated
//! keys) is an error naming the file, line and column. The parser is written here rather
//! than taken from a YAML crate: the format is flat, a hand parser gives exact positions
//! for every key and value, and the serde YAML crates are in flux (`serde_yaml` is archived
//! and `serde_yml` deprecated).
//!
//! # The threshold rule
//! That of ROS 1 `map_server` (`image_loader.cpp`), which ROS 2's `nav2_map_server`
//! shares for grey images. For each pixel, `v` is the mean of its channels (8-bit; a grey
//! image has one; with `mode: trinary` an alpha channel is averaged in, as `map_server`
//! does, otherwise it is left out), `v = 255 - v` when `negate`, and `p = (255 - v) / 255`
//! is the occupancy probability: white is free, black occupied. Then, as ROS values:
//! - `p > occupied_thresh`: occupied, `100`;
//! - `p < free_thresh`: free, `0`;
//! - otherwise unknown, `-1`, in `trinary` mode (and in `scale` mode for a fully
//!   transparent pixel); in `scale` mode `1 + 98 (p - free_thresh) / (occupied_thresh -
//!   free_thresh)` truncated, a partly occupied cell;
//! - `raw` mode skips the thresholds: the value is `v` itself, as a signed byte (so 255
//!   reads as `-1`, unknown).
//!
//! A cell of the [`Grid`] is free exactly when its value is `0`; occupied, partly occupied
//! and **unknown cells are blocked**, since seed 004 plans "on grid cells that are entirely
//! vacant" (section 3). [`RosOptions::inflation_radius`] then blocks every cell whose
//! centre lies within that many cells (Euclidean, centre to centre) of an occupied cell
//! (value >= 100; and of an unknown one with [`RosOptions::inflate_unknown`]), like the
//! inflation layer of the ROS cost map (seed 004, Fig. 10b).
//!
//! Grid row `y` is image row `y`, the top row first, so the grid looks like the image;
//! ROS's `OccupancyGrid` stores the bottom row first instead. [`RosMap::world`] gives a
//! cell centre's position in the map frame (the yaw of `origin` is ignored, as
//! `map_server` does).

use std::io::Cursor;
use std::path::{Path, PathBuf};

use planner_api::{Cell, Grid};

use crate::error::{MapError, MapErrorKind};
use crate::text::{lines, show_token, unexpected, Origin};

/// How the image's values become occupancy, the YAML's `mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum RosMode {
    /// Occupied, free or unknown (the default).
    #[default]
    Trinary,
    /// Occupied, free, or a value in 1..=99 between the thresholds.
    Scale,
    /// The pixel value is the occupancy value.
    Raw,
}

/// The contents of a `map_server` YAML file (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct RosYaml {
    /// The image path as written.
    pub image: String,
    /// Metres per cell.
    pub resolution: f64,
    /// `[x, y, yaw]` of the lower-left cell.
    pub origin: [f64; 3],
    /// Occupancy probability above which a cell is occupied.
    pub occupied_thresh: f64,
    /// Occupancy probability below which a cell is free.
    pub free_thresh: f64,
    /// Whether dark pixels are free.
    pub negate: bool,
    /// Trinary, scale or raw.
    pub mode: RosMode,
}

/// Options of [`read_ros_map`] beyond what the YAML says.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct RosOptions {
    /// Block every cell within this many cells of an occupied cell (0, the default: none).
    pub inflation_radius: u32,
    /// Inflate around unknown cells as well (default false, like ROS's cost map).
    pub inflate_unknown: bool,
}

/// A `map_server` map read into a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct RosMap {
    /// Free where the value is 0 and no inflation reaches (module docs).
    pub grid: Grid,
    /// The ROS occupancy value of each cell (-1 unknown, 0 free, 1..=99 partly occupied,
    /// 100 occupied; raw mode may give others), row-major in grid order (top row first),
    /// before inflation.
    pub occupancy: Vec<i8>,
    /// The YAML file's contents.
    pub yaml: RosYaml,
    /// The image file, resolved against the YAML file's directory.
    pub image_path: PathBuf,
}

impl RosMap {
    /// The map-frame position in metres of `cell`'s centre:
    /// `origin + resolution * (x + 0.5, height - 1 - y + 0.5)`.
    pub fn world(&self, cell: Cell) -> (f64, f64) {
        let r = self.yaml.resolution;
        let [ox, oy, _] = self.yaml.origin;
        let rows_below = f64::from(self.grid.height()) - 1.0 - f64::from(cell.y);
        (
            ox + r * (f64::from(cell.x) + 0.5),
            oy + r * (rows_below + 0.5),
        )
    }
}

/// The keys of the YAML file, as listed in messages.
const KEYS: &str = "image, resolution, origin, occupied_thresh, free_thresh, negate, mode";

/// A value as written: a scalar (quotes removed) or a flow sequence of scalars, each with
/// its 1-based column.
enum Raw {
    Scalar(String),
    Sequence(Vec<(usize, String)>),
}

/// Parses the text of a `map_server` YAML file. `origin` names it in error messages.
///
/// Errors, with line and column: a line that is not `key: value` at the top level, an
/// unknown or repeated key, a missing required key, or a value of the wrong type or out of
/// range (module docs). Never panics.
pub fn parse_ros_yaml(text: &str, origin: &str) -> Result<RosYaml, MapError> {
    let o = Origin(origin);
    let mut image = None;
    let mut resolution = None;
    let mut origin_pose = None;
    let mut occupied = None;
    let mut free = None;
    let mut negate = None;
    let mut mode = None;
    // (key, line) of the keys seen, for duplicate errors.
    let mut seen: Vec<(&'static str, usize)> = Vec::new();
    for (line_no, line) in lines(text) {
        let line = strip_comment(line);
        let trimmed = line.trim_end();
        if trimmed.trim_start().is_empty() || trimmed == "---" || trimmed == "..." {
            continue;
        }
        if trimmed.starts_with(char::is_whitespace) {
            return Err(o.at(
                line_no,
                1,
                unexpected(
                    "a top-level 'key: value' (a map_server YAML file is flat)",
                    "an indented line",
                ),
            ));
        }
        let Some(colon) = trimmed.find(':') else {
            return Err(o.at(line_no, 1, unexpected("'key: value'", show_token(trimmed))));
        };
        let key_text = &trimmed[..colon];
        let after = &trimmed[colon + 1..];
        if !after.is_empty() && !after.starts_with(char::is_whitespace) {
            return Err(o.at(
                line_no,
                colon + 2,
                unexpected("a space after ':'", show_token(after)),
            ));
        }
        let key: &'static str = match key_text {
            "image" => "image",
            "resolution" => "resolution",
            "origin" => "origin",
            "occupied_thresh" => "occupied_thresh",
            "free_thresh" => "free_thresh",
            "negate" => "negate",
            "mode" => "mode",
            other => {
                return Err(o.at(
                    line_no,
                    1,
                    unexpected(format!("one of the keys {KEYS}"), show_token(other)),
                ))
            }
        };
        if let Some(&(_, first_line)) = seen.iter().find(|(k, _)| *k == key) {
            return Err(o.at(line_no, 1, MapErrorKind::DuplicateKey { key, first_line }));
        }
        seen.push((key, line_no));
        let value_column = colon + 2 + (after.len() - after.trim_start().len());
        let value_text = after.trim();
        let at = |column: usize, kind: MapErrorKind| o.at(line_no, column, kind);
        if value_text.is_empty() {
            return Err(at(
                value_column,
                unexpected(format!("a value for '{key}'"), "end of line"),
            ));
        }
        let raw = parse_value(value_text, value_column).map_err(|(c, k)| at(c, k))?;
        let number = |raw: &Raw, what: &str| -> Result<f64, MapError> {
            match raw {
                Raw::Scalar(s) => parse_number(s).ok_or_else(|| {
                    at(
                        value_column,
                        unexpected(format!("a number for '{what}'"), show_token(s)),
                    )
                }),
                Raw::Sequence(_) => Err(at(
                    value_column,
                    unexpected(format!("a number for '{what}'"), "a sequence"),
                )),
            }
        };
        let probability = |raw: &Raw| -> Result<f64, MapError> {
            let p = number(raw, key)?;
            if (0.0..=1.0).contains(&p) {
                Ok(p)
            } else {
                Err(at(
                    value_column,
                    unexpected(
                        format!("a number in [0, 1] for '{key}'"),
                        show_token(value_text),
                    ),
                ))
            }
        };
        match key {
            "image" => match raw {
                Raw::Scalar(s) => image = Some(s),
                Raw::Sequence(_) => {
                    return Err(at(
                        value_column,
                        unexpected("an image file name", "a sequence"),
                    ))
                }
            },
            "resolution" => {
                let r = number(&raw, key)?;
                if r <= 0.0 {
                    return Err(at(
                        value_column,
                        unexpected("a positive number for 'resolution'", show_token(value_text)),
                    ));
                }
                resolution = Some(r);
            }
            "origin" => {
                let Raw::Sequence(items) = &raw else {
                    return Err(at(
                        value_column,
                        unexpected(
                            "a sequence [x, y, yaw] for 'origin'",
                            show_token(value_text),
                        ),
                    ));
                };
                if items.len() != 3 {
                    return Err(at(
                        value_column,
                        unexpected(
                            "three numbers [x, y, yaw] for 'origin'",
                            format!("{} items", items.len()),
                        ),
                    ));
                }
                let mut pose = [0.0; 3];
                for (slot, (column, item)) in pose.iter_mut().zip(items) {
                    *slot = parse_number(item).ok_or_else(|| {
                        at(
                            *column,
                            unexpected("a number in 'origin'", show_token(item)),
                        )
                    })?;
                }
                origin_pose = Some(pose);
            }
            "occupied_thresh" => occupied = Some((probability(&raw)?, line_no, value_column)),
            "free_thresh" => free = Some((probability(&raw)?, line_no, value_column)),
            "negate" => {
                let flag = match &raw {
                    Raw::Scalar(s) => match s.as_str() {
                        "0" | "false" | "False" | "FALSE" => Some(false),
                        "1" | "true" | "True" | "TRUE" => Some(true),
                        _ => None,
                    },
                    Raw::Sequence(_) => None,
                };
                negate = Some(flag.ok_or_else(|| {
                    at(
                        value_column,
                        unexpected("0, 1, true or false for 'negate'", show_token(value_text)),
                    )
                })?);
            }
            _ => {
                let m = match &raw {
                    Raw::Scalar(s) => match s.as_str() {
                        "trinary" => Some(RosMode::Trinary),
                        "scale" => Some(RosMode::Scale),
                        "raw" => Some(RosMode::Raw),
                        _ => None,
                    },
                    Raw::Sequence(_) => None,
                };
                mode = Some(m.ok_or_else(|| {
                    at(
                        value_column,
                        unexpected("trinary, scale or raw for 'mode'", show_token(value_text)),
                    )
                })?);
            }
        }
    }
    let missing = |key: &'static str| o.at(0, 0, MapErrorKind::MissingField { key });
    let (occupied_thresh, _, _) = occupied.ok_or_else(|| missing("occupied_thresh"))?;
    let (free_thresh, free_line, free_column) = free.ok_or_else(|| missing("free_thresh"))?;
    if free_thresh > occupied_thresh {
        return Err(o.at(
            free_line,
            free_column,
            unexpected(
                format!("'free_thresh' at most 'occupied_thresh' ({occupied_thresh})"),
                free_thresh.to_string(),
            ),
        ));
    }
    Ok(RosYaml {
        image: image.ok_or_else(|| missing("image"))?,
        resolution: resolution.ok_or_else(|| missing("resolution"))?,
        origin: origin_pose.ok_or_else(|| missing("origin"))?,
        occupied_thresh,
        free_thresh,
        negate: negate.ok_or_else(|| missing("negate"))?,
        mode: mode.unwrap_or_default(),
    })
}

/// The line without a comment: `#` at its start or after whitespace, outside quotes.
fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut previous_blank = true;
    for (byte, ch) in line.char_indices() {
        match quote {
            Some(q) if ch == q => quote = None,
            Some(_) => {}
            None if ch == '"' || ch == '\'' => quote = Some(ch),
            None if ch == '#' && previous_blank => return &line[..byte],
            None => {}
        }
        previous_blank = ch.is_whitespace();
    }
    line
}

/// Parses a value starting at 1-based `column`: a flow sequence, a quoted or a plain
/// scalar. Errors carry the column.
fn parse_value(text: &str, column: usize) -> Result<Raw, (usize, MapErrorKind)> {
    if let Some(inner) = text.strip_prefix('[') {
        let Some(inner) = inner.strip_suffix(']') else {
            return Err((
                column,
                unexpected("a flow sequence closed by ']'", show_token(text)),
            ));
        };
        let mut items = Vec::new();
        if inner.trim().is_empty() {
            return Ok(Raw::Sequence(items));
        }
        let mut offset = column + 1;
        for part in inner.split(',') {
            let lead = part.chars().take_while(|c| c.is_whitespace()).count();
            let item = part.trim();
            if item.is_empty() {
                return Err((offset + lead, unexpected("a sequence item", "nothing")));
            }
            match parse_value(item, offset + lead)? {
                Raw::Scalar(s) => items.push((offset + lead, s)),
                Raw::Sequence(_) => {
                    return Err((
                        offset + lead,
                        unexpected("a scalar item", "a nested sequence"),
                    ))
                }
            }
            offset += part.chars().count() + 1;
        }
        return Ok(Raw::Sequence(items));
    }
    for quote in ['"', '\''] {
        if let Some(inner) = text.strip_prefix(quote) {
            return match inner.strip_suffix(quote) {
                Some(body) if !body.contains(quote) => Ok(Raw::Scalar(body.to_owned())),
                _ => Err((
                    column,
                    unexpected(
                        format!("a string closed by {quote} at the end of the line (escapes are not supported)"),
                        show_token(text),
                    ),
                )),
            };
        }
    }
    if text.starts_with(['{', '|', '>', '&', '*', '!']) {
        return Err((
            column,
            unexpected(
                "a plain scalar, a quoted string or [a, b, c]",
                show_token(text),
            ),
        ));
    }
    Ok(Raw::Scalar(text.to_owned()))
}

/// A finite number in YAML's usual spellings (`0.05`, `-10`, `1e-3`, `+2`).
fn parse_number(text: &str) -> Option<f64> {
    let ok = !text.is_empty()
        && text
            .chars()
            .all(|c| c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E'));
    text.parse::<f64>().ok().filter(|v| ok && v.is_finite())
}

/// The ROS occupancy value of one pixel given as 8-bit channels (1 grey, 2 grey and
/// alpha, 3 RGB, 4 RGBA), by the module's threshold rule.
pub fn ros_occupancy_value(yaml: &RosYaml, pixel: &[u8]) -> i8 {
    let n = pixel.len();
    let has_alpha = n == 2 || n == 4;
    let averaged = if yaml.mode == RosMode::Trinary || !has_alpha {
        n
    } else {
        n - 1
    };
    if averaged == 0 {
        return -1;
    }
    let sum: f64 = pixel[..averaged].iter().map(|&c| f64::from(c)).sum();
    let mut v = sum / averaged as f64;
    let alpha = if has_alpha { pixel[n - 1] } else { 255 };
    if yaml.negate {
        v = 255.0 - v;
    }
    if yaml.mode == RosMode::Raw {
        // map_server stores the double in a signed byte: 255 becomes -1.
        return (v as u8) as i8;
    }
    let p = (255.0 - v) / 255.0;
    if p > yaml.occupied_thresh {
        100
    } else if p < yaml.free_thresh {
        0
    } else if yaml.mode == RosMode::Trinary || alpha == 0 {
        -1
    } else {
        let ratio = (p - yaml.free_thresh) / (yaml.occupied_thresh - yaml.free_thresh);
        (1.0 + 98.0 * ratio) as i8
    }
}

/// The grid of `occupancy` values (row-major, `width` x `height`): free exactly where the
/// value is 0, then inflated by `options` (module docs).
///
/// Precondition: `occupancy.len() == width * height`; errors as [`Grid::from_free_cells`]
/// otherwise.
pub fn ros_grid(
    width: u32,
    height: u32,
    occupancy: &[i8],
    options: &RosOptions,
) -> Result<Grid, planner_api::GridError> {
    let mut free: Vec<bool> = occupancy.iter().map(|&v| v == 0).collect();
    let r = i64::from(options.inflation_radius);
    if r > 0 {
        let (w, h) = (i64::from(width), i64::from(height));
        for (index, &v) in occupancy.iter().enumerate() {
            let source = v >= 100 || (options.inflate_unknown && v < 0);
            if !source {
                continue;
            }
            let (x, y) = (index as i64 % w, index as i64 / w);
            for dy in -r..=r {
                for dx in -r..=r {
                    let (nx, ny) = (x + dx, y + dy);
                    if dx * dx + dy * dy <= r * r && nx >= 0 && ny >= 0 && nx < w && ny < h {
                        free[(ny * w + nx) as usize] = false;
                    }
                }
            }
        }
    }
    Grid::from_free_cells(width, height, free)
}

/// Reads a `map_server` map: the YAML at `path`, then its image (PGM or PNG, found by
/// content) relative to the YAML's directory, into a grid with `options`.
///
/// Errors name the YAML file (line and column for its contents) or the image file.
pub fn read_ros_map(path: &Path, options: &RosOptions) -> Result<RosMap, MapError> {
    let origin = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| {
        MapError::new(
            &origin,
            0,
            0,
            MapErrorKind::Io {
                message: e.to_string(),
            },
        )
    })?;
    ros_map_from_yaml_text(&text, path, options)
}

/// [`read_ros_map`] for YAML text already read from `path` (the image is resolved against
/// `path`'s directory).
pub(crate) fn ros_map_from_yaml_text(
    text: &str,
    path: &Path,
    options: &RosOptions,
) -> Result<RosMap, MapError> {
    let yaml = parse_ros_yaml(text, &path.display().to_string())?;
    let image_path = path.parent().unwrap_or(Path::new("")).join(&yaml.image);
    let image_origin = image_path.display().to_string();
    let image_error =
        |message: String| MapError::new(&image_origin, 0, 0, MapErrorKind::Image { message });
    let bytes = std::fs::read(&image_path).map_err(|e| {
        MapError::new(
            &image_origin,
            0,
            0,
            MapErrorKind::Io {
                message: e.to_string(),
            },
        )
    })?;
    let decoded = image::ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| image_error(e.to_string()))?
        .decode()
        .map_err(|e| image_error(e.to_string()))?;
    let (width, height) = (decoded.width(), decoded.height());
    let (channels, pixels): (usize, Vec<u8>) = match decoded {
        image::DynamicImage::ImageLuma8(img) => (1, img.into_raw()),
        image::DynamicImage::ImageLumaA8(img) => (2, img.into_raw()),
        image::DynamicImage::ImageRgb8(img) => (3, img.into_raw()),
        image::DynamicImage::ImageRgba8(img) => (4, img.into_raw()),
        other if other.color().has_color() => {
            if other.color().has_alpha() {
                (4, other.to_rgba8().into_raw())
            } else {
                (3, other.to_rgb8().into_raw())
            }
        }
        other if other.color().has_alpha() => (2, other.to_luma_alpha8().into_raw()),
        other => (1, other.to_luma8().into_raw()),
    };
    let occupancy: Vec<i8> = pixels
        .chunks_exact(channels)
        .map(|pixel| ros_occupancy_value(&yaml, pixel))
        .collect();
    let grid = ros_grid(width, height, &occupancy, options)
        .map_err(|e| MapError::new(&image_origin, 0, 0, MapErrorKind::Grid(e)))?;
    Ok(RosMap {
        grid,
        occupancy,
        yaml,
        image_path,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn yaml(mode: RosMode, negate: bool) -> RosYaml {
        RosYaml {
            image: "m.pgm".into(),
            resolution: 0.05,
            origin: [0.0; 3],
            occupied_thresh: 0.65,
            free_thresh: 0.196,
            negate,
            mode,
        }
    }

    #[test]
    fn threshold_rule_by_hand() {
        let t = yaml(RosMode::Trinary, false);
        // p = (255 - v) / 255: v = 254 -> 0.0039 < 0.196 free; v = 0 -> 1 > 0.65 occupied;
        // v = 205 (map_saver's unknown grey) -> 50 / 255 = 0.19608, not < 0.196: unknown;
        // v = 206 -> 0.1922 free; v = 89 -> 0.651 occupied; v = 90 -> 0.647 unknown.
        let check = |y: &RosYaml, px: &[u8], expect: i8| {
            assert_eq!(ros_occupancy_value(y, px), expect, "{px:?} {:?}", y.mode)
        };
        check(&t, &[254], 0);
        check(&t, &[0], 100);
        check(&t, &[205], -1);
        check(&t, &[206], 0);
        check(&t, &[89], 100);
        check(&t, &[90], -1);
        // Negated: black is free.
        check(&yaml(RosMode::Trinary, true), &[0], 0);
        // RGB: the mean (0 + 255 + 255) / 3 = 170 -> p = 1/3, unknown.
        check(&t, &[0, 255, 255], -1);
        // Scale: p = 1/3 -> 1 + 98 (0.3333 - 0.196) / 0.454 = 30.6 -> 30; transparent -> -1.
        let s = yaml(RosMode::Scale, false);
        check(&s, &[170, 255], 30);
        check(&s, &[170, 0], -1);
        // Trinary averages alpha in: (170 + 0) / 2 = 85 -> p = 0.667 occupied.
        check(&t, &[170, 0], 100);
        // Raw: the value itself; 255 reads -1.
        let r = yaml(RosMode::Raw, false);
        check(&r, &[0], 0);
        check(&r, &[100], 100);
        check(&r, &[255], -1);
    }

    #[test]
    fn inflation_by_hand() {
        // One occupied cell in the middle of 5 x 5; radius 1 blocks its 4-neighbours
        // (distance 1) but not the diagonals (sqrt 2); radius 2 blocks 13 cells.
        let mut occ = vec![0i8; 25];
        occ[12] = 100;
        let options = |r| RosOptions {
            inflation_radius: r,
            inflate_unknown: false,
        };
        assert_eq!(ros_grid(5, 5, &occ, &options(0)).unwrap().n_free(), 24);
        assert_eq!(ros_grid(5, 5, &occ, &options(1)).unwrap().n_free(), 20);
        assert_eq!(ros_grid(5, 5, &occ, &options(2)).unwrap().n_free(), 12);
        // Unknown cells are blocked but inflate only when asked.
        occ[12] = -1;
        assert_eq!(ros_grid(5, 5, &occ, &options(1)).unwrap().n_free(), 24);
        let both = RosOptions {
            inflation_radius: 1,
            inflate_unknown: true,
        };
        assert_eq!(ros_grid(5, 5, &occ, &both).unwrap().n_free(), 20);
    }
}
