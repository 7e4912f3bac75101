//! Where the maps a results directory's runs were planned on lie under the served
//! directory, so that the page draws a recorded run on its own map and on no other.
//!
//! A run names its map by file name only (`arena.map`), and two maps under the served
//! directory may share that name. The results record the config that ran (runs.json's
//! `config`, the path as given to `experiment`, relative to the directory it ran in) and
//! its SHA-256 (`provenance.config_sha256`). The config is looked for under the served
//! directory: at that path, or a shorter tail of it, from the results directory or one
//! of the directories above it up to the served one; a file counts only if it has the
//! recorded SHA-256. Its `[[maps]]` sets' `files` are then resolved as the runner
//! resolves them (relative to the config, expanded by [`planner_runner::pattern`]), so
//! each map name has the file it was read from. When no such config is found, a map is
//! looked for by its file name, and used only if exactly one map file under the served
//! directory has it (said in a note).
//!
//! Either way the map found is checked against the runs: every start, goal and kept
//! path cell of its runs must lie inside its grid. A map that cannot be found, is
//! ambiguous (two files by one name, or two copies of the config resolving it to
//! different files), lies outside the served directory or fails the check is not
//! located; [`Located::unlocated`] says why.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Component, Path, PathBuf};

use crate::safe::Root;
use crate::server::MapReadError;

/// The largest config file read when looking for the results' config.
const MAX_CONFIG_BYTES: u64 = 16 << 20;

/// The most configs with the recorded SHA-256 considered.
const MAX_CONFIGS: usize = 16;

/// What the results say of the config that ran.
#[derive(Debug, Clone, Copy)]
pub struct Recorded<'a> {
    /// The canonical results directory (inside the root).
    pub results: &'a Path,
    /// runs.json's `config`: the config's path as given to `experiment`.
    pub config: Option<&'a str>,
    /// The config's SHA-256 (runs.json's `provenance.config_sha256`).
    pub config_sha256: Option<&'a str>,
}

/// The largest column and row the runs of one map use (starts, goals, kept paths).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Extent {
    /// The largest x.
    pub x: u64,
    /// The largest y.
    pub y: u64,
}

impl Extent {
    /// Widens the extent to hold `(x, y)`.
    pub fn add(&mut self, x: u64, y: u64) {
        self.x = self.x.max(x);
        self.y = self.y.max(y);
    }
}

/// Why the results' config did not locate a map (and a file name alone was looked for).
#[derive(Debug, Clone, thiserror::Error)]
pub enum NoConfig {
    /// No file under the served directory has the recorded path (or a tail of it) and
    /// SHA-256.
    #[error("its config ({config}) is not under the served directory with the SHA-256 the results recorded")]
    NotFound {
        /// The config's path as recorded.
        config: String,
    },
    /// The results record no SHA-256 to check a config by.
    #[error("the results record no SHA-256 to check its config ({config}) by")]
    NoHash {
        /// The config's path as recorded.
        config: String,
    },
    /// The results name no config.
    #[error("the results name no config")]
    Unnamed,
}

/// Why a map of the runs is not located: the page says it instead of drawing the runs on
/// a map that may not be theirs.
#[derive(Debug, thiserror::Error)]
pub enum Unlocated {
    /// The config reads the map from outside the served directory.
    #[error("map {name}: its config ({configs}) reads it from outside the served directory")]
    Outside {
        /// The map's name in the runs.
        name: String,
        /// The configs found, root-relative, comma-separated.
        configs: String,
    },
    /// Copies of the config resolve the name to different files.
    #[error("map {name}: copies of its config ({configs}) name different files, {files}; which one the runs used is unknown")]
    Ambiguous {
        /// The map's name in the runs.
        name: String,
        /// The configs found, root-relative, comma-separated.
        configs: String,
        /// The files, root-relative.
        files: String,
    },
    /// The config names no file of that name any more.
    #[error("map {name}: its config ({configs}) names no map file of that name now")]
    NotInConfig {
        /// The map's name in the runs.
        name: String,
        /// The configs found, root-relative, comma-separated.
        configs: String,
    },
    /// No config, and no map file of that name.
    #[error("map {name}: {why}, and no map file under the served directory has that name")]
    NoFile {
        /// The map's name in the runs.
        name: String,
        /// Why the config did not locate it.
        why: NoConfig,
    },
    /// No config, and several map files of that name.
    #[error("map {name}: {why}, and {count} map files under the served directory have that name ({files}); which one the runs used is unknown")]
    SameName {
        /// The map's name in the runs.
        name: String,
        /// Why the config did not locate it.
        why: NoConfig,
        /// How many files have the name.
        count: usize,
        /// The files, root-relative, comma-separated.
        files: String,
    },
    /// The file found cannot be read.
    #[error("map {name}: {path} cannot be read: {source}")]
    Unreadable {
        /// The map's name in the runs.
        name: String,
        /// The file, root-relative.
        path: String,
        /// Why.
        source: Box<MapReadError>,
    },
    /// The file found does not hold the cells the runs use.
    #[error("map {name}: {path} is {width} x {height}, and its runs use cells up to ({x}, {y}): not the map they were planned on")]
    TooSmall {
        /// The map's name in the runs.
        name: String,
        /// The file, root-relative.
        path: String,
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
        /// The largest column the runs use.
        x: u64,
        /// The largest row the runs use.
        y: u64,
    },
}

/// How a located map was found, when not by its config.
#[derive(Debug, Clone, thiserror::Error)]
#[error("map {name}: found by its file name alone ({path}), since {why}")]
pub struct ByName {
    /// The map's name in the runs.
    pub name: String,
    /// The file, root-relative.
    pub path: String,
    /// Why the config did not locate it.
    pub why: NoConfig,
}

/// The maps located, and why the others were not (or that one was found by name only).
#[derive(Debug, Default)]
pub struct Located {
    /// Map name -> its path relative to the root, `None` when not located.
    pub maps: BTreeMap<String, Option<String>>,
    /// Map name -> why it was not located.
    pub unlocated: BTreeMap<String, Unlocated>,
    /// Map name -> how it was found, for the maps located by file name alone.
    pub by_name: BTreeMap<String, ByName>,
}

/// Where a map name leads by the config.
#[derive(Debug, Default)]
struct ByConfig {
    /// The configs found (root-relative), with the recorded SHA-256.
    configs: Vec<String>,
    /// Map name -> the root-relative files the configs resolve it to.
    files: BTreeMap<String, BTreeSet<String>>,
    /// Map names some config resolves to a file outside the root.
    outside: BTreeSet<String>,
}

/// Locates each map of `extents` (map name -> the cells its runs use) for the results
/// `recorded` describes (module docs); `listed` is every map file under the root
/// (root-relative), and `size` reads a root-relative map's width and height.
pub fn locate(
    root: &Root,
    recorded: &Recorded<'_>,
    extents: &BTreeMap<String, Extent>,
    listed: &[String],
    size: impl Fn(&str) -> Result<(u32, u32), MapReadError>,
) -> Located {
    let by_config = by_config(root, recorded);
    let configs = by_config.configs.join(", ");
    let mut located = Located::default();
    for (name, extent) in extents {
        let name = name.clone();
        let files: Vec<&String> = by_config
            .files
            .get(&name)
            .map(|files| files.iter().collect())
            .unwrap_or_default();
        let found = match files.as_slice() {
            _ if by_config.outside.contains(&name) => Err(Unlocated::Outside {
                name: name.clone(),
                configs: configs.clone(),
            }),
            [one] => Ok(((*one).clone(), None)),
            [] if !by_config.configs.is_empty() => Err(Unlocated::NotInConfig {
                name: name.clone(),
                configs: configs.clone(),
            }),
            [] => by_name(&name, recorded, listed).map(|found| (found.path.clone(), Some(found))),
            many => Err(Unlocated::Ambiguous {
                name: name.clone(),
                configs: configs.clone(),
                files: many
                    .iter()
                    .map(|s| s.as_str())
                    .collect::<Vec<_>>()
                    .join(" and "),
            }),
        };
        let checked = found
            .and_then(|(path, note)| check(&path, &name, *extent, &size).map(|()| (path, note)));
        match checked {
            Ok((path, note)) => {
                located.maps.insert(name.clone(), Some(path));
                if let Some(note) = note {
                    located.by_name.insert(name, note);
                }
            }
            Err(why) => {
                located.maps.insert(name.clone(), None);
                located.unlocated.insert(name, why);
            }
        }
    }
    located
}

/// Why the config did not locate a map, from what the results record.
fn no_config(recorded: &Recorded<'_>) -> NoConfig {
    match (recorded.config, recorded.config_sha256) {
        (Some(config), Some(_)) => NoConfig::NotFound {
            config: config.to_string(),
        },
        (Some(config), None) => NoConfig::NoHash {
            config: config.to_string(),
        },
        (None, _) => NoConfig::Unnamed,
    }
}

/// The map `name` by its file name alone: found when exactly one listed map has it.
fn by_name(name: &str, recorded: &Recorded<'_>, listed: &[String]) -> Result<ByName, Unlocated> {
    let why = no_config(recorded);
    let same: Vec<&String> = listed
        .iter()
        .filter(|f| f.rsplit('/').next() == Some(name))
        .collect();
    match same.as_slice() {
        [] => Err(Unlocated::NoFile {
            name: name.to_string(),
            why,
        }),
        [one] => Ok(ByName {
            name: name.to_string(),
            path: (*one).clone(),
            why,
        }),
        many => Err(Unlocated::SameName {
            name: name.to_string(),
            why,
            count: many.len(),
            files: many
                .iter()
                .map(|s| s.as_str())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// Refuses a map whose grid does not hold every cell its runs use.
fn check(
    path: &str,
    name: &str,
    extent: Extent,
    size: &impl Fn(&str) -> Result<(u32, u32), MapReadError>,
) -> Result<(), Unlocated> {
    let (width, height) = size(path).map_err(|source| Unlocated::Unreadable {
        name: name.to_string(),
        path: path.to_string(),
        source: Box::new(source),
    })?;
    if extent.x >= u64::from(width) || extent.y >= u64::from(height) {
        return Err(Unlocated::TooSmall {
            name: name.to_string(),
            path: path.to_string(),
            width,
            height,
            x: extent.x,
            y: extent.y,
        });
    }
    Ok(())
}

/// The configs under the root with the recorded SHA-256, and the map files they name.
fn by_config(root: &Root, recorded: &Recorded<'_>) -> ByConfig {
    let mut found = ByConfig::default();
    let (Some(config), Some(sha)) = (recorded.config, recorded.config_sha256) else {
        return found;
    };
    let mut seen = BTreeSet::new();
    for path in config_candidates(root, recorded.results, Path::new(config)) {
        if found.configs.len() >= MAX_CONFIGS {
            break;
        }
        let Some(relative) = root.relative(&path) else {
            continue;
        };
        if !seen.insert(path.clone()) {
            continue;
        }
        let Ok(text) = planner_maps::read_text_file(&path, MAX_CONFIG_BYTES) else {
            continue;
        };
        if planner_runner::provenance::sha256_hex(text.as_bytes()) != sha {
            continue;
        }
        found.configs.push(relative);
        let base = path.parent().unwrap_or(Path::new("")).to_path_buf();
        for pattern in map_patterns(&text) {
            let full = base.join(&pattern);
            if !prefix_inside(root, &full) {
                // The names it would give are unknown without listing outside the root:
                // the literal file name, if the pattern ends in one, is marked.
                if let Some(name) = Path::new(&pattern).file_name().and_then(|n| n.to_str()) {
                    if !name.contains(['*', '?', '[']) {
                        found.outside.insert(name.to_string());
                    }
                }
                continue;
            }
            let Ok(matches) = planner_runner::pattern::expand(&full) else {
                continue;
            };
            for file in matches {
                let Some(name) = file.file_name().and_then(|n| n.to_str()) else {
                    continue;
                };
                let inside = file
                    .canonicalize()
                    .ok()
                    .and_then(|canonical| root.relative(&canonical));
                match inside {
                    Some(relative) => {
                        found
                            .files
                            .entry(name.to_string())
                            .or_default()
                            .insert(relative);
                    }
                    None => {
                        found.outside.insert(name.to_string());
                    }
                }
            }
        }
    }
    found
}

/// Where the config recorded as `config` may lie: that path, and each shorter tail of it,
/// from the results directory and each directory above it up to the root (the directory
/// `experiment` ran in is unknown); an absolute path as it is, too. Canonical files under
/// the root only.
fn config_candidates(root: &Root, results: &Path, config: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    if config.is_absolute() {
        if let Ok(canonical) = config.canonicalize() {
            if canonical.starts_with(root.path()) && canonical.is_file() {
                out.push(canonical);
            }
        }
    }
    let parts: Vec<&std::ffi::OsStr> = config
        .components()
        .filter_map(|c| match c {
            Component::Normal(part) => Some(part),
            _ => None,
        })
        .collect();
    let mut bases = Vec::new();
    let mut base = Some(results);
    while let Some(dir) = base {
        if !dir.starts_with(root.path()) {
            break;
        }
        bases.push(dir);
        base = dir.parent();
    }
    for skip in 0..parts.len() {
        let tail: PathBuf = parts[skip..].iter().collect();
        for dir in &bases {
            let Ok(canonical) = dir.join(&tail).canonicalize() else {
                continue;
            };
            if canonical.starts_with(root.path()) && canonical.is_file() {
                out.push(canonical);
            }
        }
    }
    out
}

/// The `files` patterns of a config's `[[maps]]` sets (none when it is not TOML).
fn map_patterns(text: &str) -> Vec<String> {
    let Ok(table) = toml::from_str::<toml::Table>(text) else {
        return Vec::new();
    };
    table
        .get("maps")
        .and_then(|maps| maps.as_array())
        .into_iter()
        .flatten()
        .filter_map(|set| set.get("files").and_then(|files| files.as_array()))
        .flatten()
        .filter_map(|file| file.as_str().map(str::to_string))
        .collect()
}

/// Whether the part of `pattern` before its first wildcard lies inside the root (so that
/// expanding it lists no directory outside); a prefix that does not exist matches nothing
/// and counts as inside.
fn prefix_inside(root: &Root, pattern: &Path) -> bool {
    let mut prefix = PathBuf::new();
    for component in pattern.components() {
        let text = component.as_os_str().to_string_lossy();
        if text.contains(['*', '?', '[']) {
            break;
        }
        prefix.push(component);
    }
    match prefix.canonicalize() {
        Ok(canonical) => canonical.starts_with(root.path()),
        Err(_) => true,
    }
}
