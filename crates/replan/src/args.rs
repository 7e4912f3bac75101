//! The command-line options of this crate's examples and bench, in one place: `--key
//! value` pairs, comma-separated lists, the Moving AI maps they name, and the scenarios
//! they pick.
//!
//! ```
//! use planner_replan::args::Args;
//! let args = Args::new(["--radius", "1,5", "--scenarios", "20"].map(String::from).to_vec());
//! assert_eq!(args.parsed_list::<u32>("--radius", "1")?, vec![1, 5]);
//! assert_eq!(args.parsed::<usize>("--scenarios", "100")?, 20);
//! assert_eq!(args.value("--maps", "den520d"), "den520d");
//! assert!(args.parsed::<u32>("--maps", "x").is_err());
//! # Ok::<(), planner_replan::args::ArgError>(())
//! ```

use std::path::{Path, PathBuf};
use std::str::FromStr;

use planner_api::Grid;
use planner_maps::{MapError, Scenario};
use thiserror::Error;

/// A bad option value or map name.
#[derive(Debug, Error)]
pub enum ArgError {
    /// An option's value does not parse.
    #[error("option {key}: cannot read {value:?}")]
    Value {
        /// The option.
        key: String,
        /// Its value.
        value: String,
    },
    /// A map name with characters other than letters, digits, `-`, `_` and `.`.
    #[error("map name {0:?}: letters, digits, '-', '_' and '.' only")]
    MapName(String),
    /// A map or scenario file could not be read.
    #[error(transparent)]
    Map(#[from] MapError),
}

/// The options after the program name.
#[derive(Debug, Clone, Default)]
pub struct Args(Vec<String>);

impl Args {
    /// The given arguments.
    pub fn new(args: Vec<String>) -> Args {
        Args(args)
    }

    /// The process's arguments after the program name.
    pub fn from_env() -> Args {
        Args(std::env::args().skip(1).collect())
    }

    /// The value after `key`, else `default`.
    pub fn value<'a>(&'a self, key: &str, default: &'a str) -> &'a str {
        self.0
            .iter()
            .position(|a| a == key)
            .and_then(|i| self.0.get(i + 1))
            .map_or(default, String::as_str)
    }

    /// Whether the flag `key` is given.
    pub fn flag(&self, key: &str) -> bool {
        self.0.iter().any(|a| a == key)
    }

    /// The value after `key` (else `default`) split at commas.
    pub fn list(&self, key: &str, default: &str) -> Vec<String> {
        self.value(key, default)
            .split(',')
            .map(str::to_owned)
            .collect()
    }

    /// The value after `key` (else `default`), parsed.
    pub fn parsed<T: FromStr>(&self, key: &str, default: &str) -> Result<T, ArgError> {
        let value = self.value(key, default);
        value.parse().map_err(|_| ArgError::Value {
            key: key.to_owned(),
            value: value.to_owned(),
        })
    }

    /// The value after `key` (else `default`) split at commas, each parsed.
    pub fn parsed_list<T: FromStr>(&self, key: &str, default: &str) -> Result<Vec<T>, ArgError> {
        self.list(key, default)
            .iter()
            .map(|v| {
                v.parse().map_err(|_| ArgError::Value {
                    key: key.to_owned(),
                    value: v.clone(),
                })
            })
            .collect()
    }
}

/// The repository's Moving AI maps (`maps/movingai`).
pub fn movingai_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../maps/movingai")
}

/// The Moving AI map `name` (`maps/movingai/<name>.map`) and its scenarios; the name is
/// checked to be a plain file name first.
pub fn movingai_map(name: &str) -> Result<(Grid, Vec<Scenario>), ArgError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        || name.starts_with('.')
    {
        return Err(ArgError::MapName(name.to_owned()));
    }
    let root = movingai_dir();
    let grid = planner_maps::read_map(&root.join(format!("{name}.map")))?.grid;
    let scenarios = planner_maps::read_scenarios(&root.join(format!("{name}.map.scen")))?;
    Ok((grid, scenarios))
}

/// `n` of `items` spread evenly (all of them when there are fewer): item `i * len / n`.
///
/// ```
/// let picked = planner_replan::args::spread(&[0, 1, 2, 3, 4, 5], 3);
/// assert_eq!(picked, [&0, &2, &4]);
/// ```
pub fn spread<T>(items: &[T], n: usize) -> Vec<&T> {
    let n = n.min(items.len());
    (0..n).map(|i| &items[i * items.len() / n]).collect()
}

/// The system's load averages (`/proc/loadavg`; empty where there is none), printed with
/// timing figures.
pub fn loadavg() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .unwrap_or_default()
        .trim()
        .to_owned()
}
