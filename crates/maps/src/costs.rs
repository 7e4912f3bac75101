//! Cell costs from map files, all opt-in ([`CostOptions`]): graded ROS maps read the way
//! ROS 2 navigation's costmap reads them, weight files (`.csv` of integers), and Moving AI
//! terrain letters. Without them every reader gives an unweighted grid, as before.
//!
//! # ROS maps: nav2's cost bands
//! A `map_server` map's occupancy values (`-1` unknown, `0` free, `1..=99` graded, `100`
//! occupied; graded values come from `mode: scale` or `mode: raw`, see the `ros` module)
//! become costmap costs as nav2's static layer makes them (`nav2_costmap_2d`,
//! `StaticLayer::interpretValue`, with `lethal_cost_threshold = 100`,
//! `inscribed_obstacle_cost_value = 99`, `track_unknown_space = true` and
//! `trinary_costmap = false`, the setting that keeps the grades) ([`costmap_cost`]):
//! - unknown `-1` is `NO_INFORMATION`, 255;
//! - `99` is `INSCRIBED_INFLATED_OBSTACLE`, 253; `100` is `LETHAL_OBSTACLE`, 254;
//! - any other `v` is `floor(v / 100 * 254)` (0 for free).
//!
//! [`CostBands`] then says which costs are passable: a cost at or above `lethal` (default
//! 254) is blocked, unknown (255) is blocked unless `unknown` gives it a cost (NavFn's and
//! Smac's `allow_unknown` plan through it at a high cost), and every passable cost `c`
//! becomes the cell weight `1 + c` (free space weight 1, neutral). Inflation
//! ([`crate::RosOptions`]) still blocks what it reaches.
//!
//! nav2's two highest costs below unknown: 254, `LETHAL_OBSTACLE`, is an obstacle in the
//! cell itself; 253, `INSCRIBED_INFLATED_OBSTACLE`, a cell within the robot's inscribed
//! radius of one, where the centre of a circular robot already touches it. nav2's
//! planners block both for the robot's centre: Smac's `GridCollisionChecker::inCollision`
//! calls a centre cost of 253 or more a collision (for a circular footprint that is the
//! whole check), and NavFn makes every cost from `COST_OBS_ROS`, 253, up an obstacle
//! (both let unknown through with `allow_unknown`). The default `lethal` of 254 blocks
//! only lethal cells, as for a point robot (253 is passable at weight 254), which the
//! recorded results keep; `lethal = 253` (`plan --lethal 253`) blocks as nav2's planners
//! do for a circular robot.
//!
//! # Weight files
//! A `.csv` of positive integers, one row per grid row, values separated by a comma and/or
//! whitespace, exactly as many rows and columns as the map; lines whose first non-blank
//! character is `#` are comments ([`parse_weights`]). A value that is 0, negative, not an
//! integer, or above 65,535 is an error naming the file, line and column.
//!
//! # Moving AI terrain
//! The Moving AI benchmark reads `S` (swamp) as passable and `W` (water) as blocked, both
//! at the cost of ground (crate docs). With [`TerrainWeights`] (opt-in) ground (`.`, `G`)
//! has weight 1, swamp the given weight, and water, when given a weight, is passable at it.
//!
//! ```
//! use planner_maps::costs::INSCRIBED_INFLATED_OBSTACLE;
//! use planner_maps::{costmap_cost, CostBands};
//!
//! assert_eq!(costmap_cost(0), 0);
//! assert_eq!(costmap_cost(22), 55); // floor(0.22 * 254) = floor(55.88)
//! assert_eq!(costmap_cost(99), 253);
//! assert_eq!(costmap_cost(100), 254);
//! assert_eq!(costmap_cost(-1), 255);
//! let bands = CostBands::default();
//! assert_eq!(bands.weight(55), Some(56));
//! assert_eq!(bands.weight(253), Some(254)); // inscribed: passable by default
//! assert_eq!(bands.weight(254), None);
//! assert_eq!(bands.weight(255), None);
//! // nav2's planners, for a circular robot: inscribed cells blocked too.
//! let nav2 = CostBands { lethal: INSCRIBED_INFLATED_OBSTACLE, ..CostBands::default() };
//! assert_eq!((nav2.weight(252), nav2.weight(253)), (Some(253), None));
//! let allow_unknown = CostBands { lethal: 253, unknown: Some(200) };
//! assert_eq!(allow_unknown.weight(255), Some(201));
//! assert_eq!(allow_unknown.weight(253), None);
//! ```

use std::path::Path;

use planner_api::{CostRule, Grid, GridError};

use crate::error::{MapError, MapErrorKind};
use crate::text::{end_of_file, lines, show_token, unexpected, Origin};
use crate::ReadOptions;

/// nav2's `NO_INFORMATION` cost: a cell the map does not know.
pub const NO_INFORMATION: u8 = 255;
/// nav2's `LETHAL_OBSTACLE` cost: an obstacle in the cell.
pub const LETHAL_OBSTACLE: u8 = 254;
/// nav2's `INSCRIBED_INFLATED_OBSTACLE` cost: a cell within the robot's inscribed radius
/// of an obstacle, where a circular robot's centre collides; nav2's planners block it
/// (module docs), the default [`CostBands`] does not.
pub const INSCRIBED_INFLATED_OBSTACLE: u8 = 253;

/// Which costmap costs are passable and at what weight (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct CostBands {
    /// Costs at or above this are blocked. Default 254 ([`LETHAL_OBSTACLE`]: obstacles
    /// only); 253 ([`INSCRIBED_INFLATED_OBSTACLE`]) blocks as nav2's planners do for a
    /// circular robot (module docs).
    pub lethal: u8,
    /// The cost of an unknown cell, or `None` (the default) to block it.
    pub unknown: Option<u8>,
}

impl Default for CostBands {
    fn default() -> CostBands {
        CostBands {
            lethal: LETHAL_OBSTACLE,
            unknown: None,
        }
    }
}

impl CostBands {
    /// The weight of a cell of costmap cost `cost`: `1 + cost` when passable, `None` when
    /// blocked (module docs).
    pub fn weight(&self, cost: u8) -> Option<u16> {
        let cost = if cost == NO_INFORMATION {
            self.unknown?
        } else {
            cost
        };
        (cost < self.lethal).then_some(1 + u16::from(cost))
    }
}

/// The weights of Moving AI terrain letters (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct TerrainWeights {
    /// The weight of a swamp cell `S` (ground is 1).
    pub swamp: u16,
    /// The weight of a water cell `W`, or `None` to keep it blocked (the benchmark's rule).
    pub water: Option<u16>,
}

/// What the readers make of costs; the default reads no costs at all.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct CostOptions {
    /// ROS maps: read the graded values into weights by [`CostOptions::bands`].
    pub graded: bool,
    /// The bands for graded ROS maps.
    pub bands: CostBands,
    /// Moving AI maps: terrain weights, when given.
    pub terrain: Option<TerrainWeights>,
    /// The move cost rule of the weighted grids read.
    pub rule: CostRule,
}

/// nav2's static layer cost of a ROS occupancy value (module docs).
pub fn costmap_cost(occupancy: i8) -> u8 {
    match occupancy {
        -1 => NO_INFORMATION,
        99 => INSCRIBED_INFLATED_OBSTACLE,
        v if v >= 100 => LETHAL_OBSTACLE,
        // Other negative values are read as unsigned bytes by nav2: at least 128, lethal.
        v if v < 0 => LETHAL_OBSTACLE,
        // value / 100 * 254, truncated as nav2's conversion to unsigned char does.
        v => (f64::from(v) / 100.0 * f64::from(LETHAL_OBSTACLE)) as u8,
    }
}

/// The weighted grid of ROS occupancy values: free where [`CostBands::weight`] of the
/// costmap cost is passable, weighted `1 + cost`, then blocked where `blocked_by_inflation`
/// says. Precondition: `occupancy.len() == width * height` (else an error, as
/// [`Grid::from_free_cells`]).
pub(crate) fn graded_grid(
    width: u32,
    height: u32,
    occupancy: &[i8],
    inflated: Option<Vec<bool>>,
    costs: &CostOptions,
) -> Result<Grid, GridError> {
    let mut free = Vec::with_capacity(occupancy.len());
    let mut weights = Vec::with_capacity(occupancy.len());
    for &value in occupancy {
        let weight = costs.bands.weight(costmap_cost(value));
        free.push(weight.is_some());
        weights.push(weight.unwrap_or(1));
    }
    if let Some(near) = inflated {
        for (cell, near) in free.iter_mut().zip(near) {
            *cell &= !near;
        }
    }
    Grid::from_free_cells(width, height, free)?.with_weights(weights, costs.rule)
}

/// The expected value of a weight file, as messages say it.
const WEIGHT: &str = "a weight (an integer from 1 to 65535)";

/// Parses a weight file (module docs) for a `width` x `height` map; `origin` names it in
/// errors, which give the line and column of the first bad value, row or line.
///
/// ```
/// use planner_maps::parse_weights;
///
/// assert_eq!(parse_weights("1, 2\n3 4\n", "w.csv", 2, 2).unwrap(), [1, 2, 3, 4]);
/// let err = |text| parse_weights(text, "w.csv", 2, 2).unwrap_err().to_string();
/// assert_eq!(err("1,0\n1,1\n"), "w.csv:1:3: expected a weight (an integer from 1 to 65535), found 0");
/// assert_eq!(err("1,1\n-3,1\n"), "w.csv:2:1: expected a weight (an integer from 1 to 65535), found '-3', a negative number");
/// assert_eq!(err("1,1.5\n1,1\n"), "w.csv:1:3: expected a weight (an integer from 1 to 65535), found '1.5', not an integer");
/// assert_eq!(err("1,1\n1,65536\n"), "w.csv:2:3: expected a weight (an integer from 1 to 65535), found '65536', above 65535");
/// assert_eq!(err("1,1\n1\n"), "w.csv:2:2: expected 2 weights in the row, as the map's width, found 1");
/// assert_eq!(err("1,1\n"), "w.csv:2:1: expected 2 rows of weights, as the map's height, found 1");
/// ```
pub fn parse_weights(
    text: &str,
    origin: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u16>, MapError> {
    let o = Origin(origin);
    let (w, h) = (width as usize, height as usize);
    let mut weights = Vec::new();
    let mut rows = 0usize;
    for (number, line) in lines(text) {
        let body = line.trim();
        if body.is_empty() || body.starts_with('#') {
            continue;
        }
        if rows == h {
            return Err(o.at(
                number,
                1,
                unexpected(
                    format!("end of file after {h} rows of weights, the map's height"),
                    show_token(body),
                ),
            ));
        }
        let mut count = 0usize;
        let mut end_column = 1;
        for (column, value) in values(line) {
            if count == w {
                return Err(o.at(
                    number,
                    column,
                    unexpected(
                        format!("end of line after {w} weights, the map's width"),
                        show_token(value),
                    ),
                ));
            }
            weights.push(
                parse_weight(value)
                    .map_err(|found| o.at(number, column, unexpected(WEIGHT, found)))?,
            );
            count += 1;
            end_column = column + value.chars().count();
        }
        if count < w {
            return Err(o.at(
                number,
                end_column,
                unexpected(
                    format!("{w} weights in the row, as the map's width"),
                    count.to_string(),
                ),
            ));
        }
        rows += 1;
    }
    if rows < h {
        let (line, column) = end_of_file(text);
        return Err(o.at(
            line,
            column,
            unexpected(
                format!("{h} rows of weights, as the map's height"),
                rows.to_string(),
            ),
        ));
    }
    Ok(weights)
}

/// The values of a row with their 1-based columns: separated by commas and/or whitespace;
/// an empty value (`1,,2`) is returned as `""` at the second comma.
fn values(line: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    let mut start: Option<(usize, usize)> = None;
    let mut after_comma = false;
    let mut column = 0;
    for (byte, ch) in line.char_indices() {
        column += 1;
        let separator = ch == ',' || ch.is_whitespace();
        match (separator, start) {
            (false, None) => start = Some((byte, column)),
            (true, Some((from, at))) => {
                out.push((at, &line[from..byte]));
                start = None;
                after_comma = false;
            }
            _ => {}
        }
        if ch == ',' {
            if after_comma {
                out.push((column, ""));
            }
            after_comma = true;
        }
    }
    if let Some((from, at)) = start {
        out.push((at, &line[from..]));
    } else if after_comma {
        out.push((column + 1, ""));
    }
    out
}

/// One weight, or what was found instead, as a message fragment.
fn parse_weight(value: &str) -> Result<u16, String> {
    if value.is_empty() {
        return Err("an empty value".to_owned());
    }
    let digits = value.strip_prefix('+').unwrap_or(value);
    if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) {
        let trimmed = digits.trim_start_matches('0');
        return match trimmed.parse::<u16>() {
            Ok(0) | Err(_) if trimmed.is_empty() => Err("0".to_owned()),
            Ok(weight) => Ok(weight),
            Err(_) => Err(format!("{}, above 65535", show_token(value))),
        };
    }
    let shown = show_token(value);
    if value.starts_with('-') && value[1..].parse::<f64>().is_ok() {
        return Err(format!("{shown}, a negative number"));
    }
    if value.parse::<f64>().is_ok() {
        return Err(format!("{shown}, not an integer"));
    }
    Err(shown)
}

/// `grid` with the weights of the weight file at `path` (module docs) and `rule`, read
/// within `options`' file size limit.
pub fn read_weights(
    path: &Path,
    grid: Grid,
    rule: CostRule,
    options: &ReadOptions,
) -> Result<Grid, MapError> {
    let origin = path.display().to_string();
    let bytes = crate::read_file(path, &origin, options.max_file_bytes)?;
    let text = crate::utf8(&bytes, &origin)?;
    let weights = parse_weights(text, &origin, grid.width(), grid.height())?;
    grid.with_weights(weights, rule)
        .map_err(|e| MapError::new(&origin, 0, 0, MapErrorKind::Grid(e)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_have_columns() {
        assert_eq!(values("1, 22 ,3"), vec![(1, "1"), (4, "22"), (8, "3")]);
        assert_eq!(values("1,,2"), vec![(1, "1"), (3, ""), (4, "2")]);
        assert_eq!(values("1,"), vec![(1, "1"), (3, "")]);
    }

    #[test]
    fn weights_parse_or_say_why_not() {
        assert_eq!(parse_weight("65535"), Ok(65535));
        assert_eq!(parse_weight("007"), Ok(7));
        assert_eq!(parse_weight("+3"), Ok(3));
        assert_eq!(parse_weight("000"), Err("0".to_owned()));
        assert_eq!(
            parse_weight("99999999999999999999"),
            Err("'99999999999999999999', above 65535".to_owned())
        );
        assert_eq!(
            parse_weight("-0.5"),
            Err("'-0.5', a negative number".to_owned())
        );
        assert_eq!(parse_weight("1e3"), Err("'1e3', not an integer".to_owned()));
        assert_eq!(parse_weight("abc"), Err("'abc'".to_owned()));
        assert_eq!(parse_weight(""), Err("an empty value".to_owned()));
    }

    #[test]
    fn costmap_costs_by_hand() {
        // floor(v * 2.54): 1 -> 2, 50 -> 127, 98 -> 248; 99 inscribed, 100 lethal.
        assert_eq!(costmap_cost(1), 2);
        assert_eq!(costmap_cost(50), 127);
        assert_eq!(costmap_cost(98), 248);
        assert_eq!(costmap_cost(99), 253);
        assert_eq!(costmap_cost(-5), 254);
    }
}
