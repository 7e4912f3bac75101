//! Arguments of a command (`plan`'s flags, `merge`'s directories) that do not fit together
//! or do not fit the map: [`UsageError`], typed, each message saying what to give instead.

use std::path::PathBuf;

/// Arguments that do not fit together ([`crate::RunnerError::Usage`]).
#[derive(Debug, thiserror::Error)]
pub enum UsageError {
    /// `--weights` with another cost flag.
    #[error("--weights gives every cell's weight; it does not go with --graded, --lethal, --unknown, --swamp or --water")]
    WeightsAndBands,
    /// ROS cost bands for a map that is not a ROS map.
    #[error("--graded, --lethal and --unknown apply to ROS maps (.yaml, .pgm, .png), not {}", .0.display())]
    BandsNotRos(PathBuf),
    /// `--lethal 0`.
    #[error("--lethal 0 would block every cell; costs from --lethal up are blocked (254 is nav2's LETHAL_OBSTACLE; its planners block from 253, INSCRIBED, for the robot's centre)")]
    LethalZero,
    /// `--unknown 255`.
    #[error("--unknown: the cost of an unknown cell must be below 255 (leave it out to block unknown cells)")]
    UnknownTooHigh,
    /// Terrain weights for a map that is not a Moving AI map.
    #[error("--swamp and --water weigh Moving AI terrain (.map files), not {}", .0.display())]
    TerrainNotMovingAi(PathBuf),
    /// `--water` alone.
    #[error("--water needs --swamp (the weight of swamp `S`)")]
    WaterWithoutSwamp,
    /// A terrain weight of 0.
    #[error("--swamp and --water are weights, from 1 to 65535")]
    TerrainWeightZero,
    /// `--cost-rule` without costs.
    #[error("--cost-rule needs costs to apply to: --weights, --graded (ROS maps) or --swamp (Moving AI maps)")]
    RuleWithoutCosts,
    /// A planner that cannot honour cell costs on a map that has them.
    #[error("planner `{label}` ({planner}) {why}, and map `{map}` has them; add --ignore-costs to plan without them")]
    RefusesCosts {
        /// The planner label.
        label: String,
        /// The planner's registry name.
        planner: String,
        /// Why ([`planner_api::PlannerSpecs::cell_costs_refusal`]).
        why: String,
        /// The map.
        map: String,
    },
    /// A `--set` without `=` or without a key.
    #[error("--set {0:?}: expected key=value")]
    Assignment(String),
    /// One key given to `--set` with two values (which would win is not for gridplan to
    /// guess).
    #[error("--set {key}: given twice, as {first} and as {second}; give each parameter once")]
    SetTwice {
        /// The key.
        key: String,
        /// Its first value.
        first: String,
        /// Its other value.
        second: String,
    },
    /// A `--set` value written as a number that TOML does not read as one (`1e400`
    /// overflows, `1_000_`): said as such, rather than taken for a word.
    #[error("--set {key}={value}: not a number (numbers are written as 3, -2, 2.5 or 1e3; integers from -2^63 to 2^63 - 1)")]
    SetNumber {
        /// The key.
        key: String,
        /// The value as given.
        value: String,
    },
    /// Cost flags for a map the config lists (its map set's `costs` table decides).
    #[error("cost flags: {} lists {}; set a `costs` table on its map set instead", .config.display(), .map.display())]
    CostsOfListedMap {
        /// The config.
        config: PathBuf,
        /// The map.
        map: PathBuf,
    },
    /// `--obstacle` for a map that is not a `.csv` matrix.
    #[error("--obstacle {value} applies to .csv maps, not {}", .map.display())]
    ObstacleNotCsv {
        /// The value given.
        value: u8,
        /// The map.
        map: PathBuf,
    },
    /// `--obstacle` for a map the config lists (its map set's `obstacle` decides).
    #[error("--obstacle {value}: {} lists {}; set `obstacle` on its map set instead", .config.display(), .map.display())]
    ObstacleOfListedMap {
        /// The value given.
        value: u8,
        /// The config.
        config: PathBuf,
        /// The map.
        map: PathBuf,
    },
    /// `--problem` with `--start` or `--goal`.
    #[error("give either --problem or --start (and --goal), not both")]
    ProblemAndCells,
    /// `--goal` for a coverage planner.
    #[error("`{0}` is a coverage planner: it covers from --start and takes no --goal")]
    CoverageGoal(String),
    /// `--start` with `--start-world`, or `--goal` with `--goal-world`.
    #[error("give --{0} (a cell) or --{0}-world (a point of the map frame), not both")]
    CellAndWorld(&'static str),
    /// `--start-world` or `--goal-world` on a map_server map whose YAML places no cell in
    /// the map frame.
    #[error("--{which}-world is a point of the map frame, and the map frame of {} is unusable ({why}: its map positions are meaningless): give --{which} x,y (a cell), or correct the YAML", .map.display())]
    UnusableMapFrame {
        /// `start` or `goal`.
        which: &'static str,
        /// The map.
        map: PathBuf,
        /// Why the frame is unusable.
        why: planner_maps::FrameError,
    },
    /// `--start-world` or `--goal-world` on a map without a map frame.
    #[error("--{which}-world is a point of a ROS map's map frame, and {} has none: give --{which} x,y (a cell), or a map_server .yaml map, whose resolution and origin place its cells", .map.display())]
    NoMapFrame {
        /// `start` or `goal`.
        which: &'static str,
        /// The map.
        map: PathBuf,
    },
    /// `--start` without `--goal` or the reverse.
    #[error("--start and --goal go together")]
    StartWithoutGoal,
    /// `--problem` past the map's problems.
    #[error("--problem {number}: {} has {count} problem(s), numbered from 1", .map.display())]
    NoSuchProblem {
        /// The number given.
        number: usize,
        /// The map.
        map: PathBuf,
        /// Its problems.
        count: usize,
    },
    /// A `.scen` file beside a map, for another size of map.
    #[error("{}:{line}:{column}: the scenario is for a {}x{} map, but {} is {}x{}", .scen.display(), .scenario.0, .scenario.1, .map.display(), .grid.0, .grid.1)]
    ScenarioSize {
        /// The scenario file.
        scen: PathBuf,
        /// The scenario's line.
        line: usize,
        /// The column of the size it states (its width).
        column: usize,
        /// The size the scenario states.
        scenario: (u32, u32),
        /// The map.
        map: PathBuf,
        /// The map's size.
        grid: (u32, u32),
    },
    /// `merge` without directories.
    #[error("merge: no shard directories given")]
    NoShards,
}

/// serde's words for a value that does not fit (`invalid value: integer `300`, expected
/// u8`, `invalid type: floating point `2.5`, expected f64`, toml's `invalid type: unit
/// variant, expected string only` for a choice given as a number), said in the config's
/// words: "expected an integer from 0 to 255, got 300". `choices` are the values a choice
/// takes, when the caller knows them (a planner parameter's declared values): toml's
/// "string only" is then "one of: a, b, c". Other messages come back with only their
/// Rust type names translated ([`expected_words`]).
///
/// ```
/// use planner_runner::usage::plain_words;
/// assert_eq!(
///     plain_words("invalid value: integer `300`, expected u8", &[]),
///     "expected an integer from 0 to 255, got 300"
/// );
/// assert_eq!(
///     plain_words("invalid type: unit variant, expected string only", &["a".into(), "b".into()]),
///     "expected one of: a, b (a string)"
/// );
/// ```
pub fn plain_words(message: &str, choices: &[String]) -> String {
    let message = message.trim();
    let parsed = ["invalid value: ", "invalid type: "]
        .iter()
        .find_map(|prefix| message.strip_prefix(prefix))
        .and_then(|rest| rest.rsplit_once(", expected "));
    let Some((given, expected)) = parsed else {
        if message.starts_with("number too large to fit in target type") {
            return "a number too large: integers are from -2^63 to 2^63 - 1 \
                    (9223372036854775807)"
                .to_string();
        }
        return match message.rsplit_once("expected ") {
            Some((head, expected)) if expected_word(expected, choices).is_some() => {
                format!("{head}expected {}", expected_words(expected, choices))
            }
            _ => message.to_string(),
        };
    };
    let expected = expected_words(expected, choices);
    // toml says "unit variant" for any value given to a choice that is not a string.
    if given == "unit variant" {
        return format!("expected {expected} (a string)");
    }
    format!("expected {expected}, got {}", given_words(given))
}

/// serde's description of an expected value (`u8`, `f64`, `string only`) in words, or as
/// it is when it is words already.
pub fn expected_words(expected: &str, choices: &[String]) -> String {
    expected_word(expected, choices).unwrap_or_else(|| expected.to_string())
}

/// [`expected_words`] of the descriptions serde writes with Rust type names.
fn expected_word(expected: &str, choices: &[String]) -> Option<String> {
    let words = match expected.trim() {
        "u8" => "an integer from 0 to 255",
        "u16" => "an integer from 0 to 65535",
        "u32" => "an integer from 0 to 4294967295",
        "u64" | "usize" | "u128" => "a non-negative integer",
        "i8" => "an integer from -128 to 127",
        "i16" => "an integer from -32768 to 32767",
        "i32" => "an integer from -2147483648 to 2147483647",
        "i64" | "isize" | "i128" => "an integer",
        "f32" | "f64" => "a number",
        "char" => "a single character",
        "string only" | "a string" if !choices.is_empty() => {
            return Some(format!("one of: {}", choices.join(", ")));
        }
        "string only" => "a string",
        _ => return None,
    };
    Some(words.to_string())
}

/// serde's description of a value given (`integer `300``, `floating point `2.5``,
/// `string "a"`, `boolean `true``) as the value.
fn given_words(given: &str) -> String {
    for prefix in ["integer ", "floating point ", "boolean ", "string "] {
        if let Some(value) = given.strip_prefix(prefix) {
            let value = value.trim_matches('`');
            return match prefix {
                "string " => format!("the string {value}"),
                _ => value.to_string(),
            };
        }
    }
    given.to_string()
}
