//! `cargo xtask new-planner <name>`: a new planner crate, registered and runnable at once.
//!
//! Writes `crates/<name>/` (Cargo.toml, src/lib.rs with a config struct and a working
//! greedy best-first search to replace, tests/smoke.rs), adds the dependency to
//! `crates/registry/Cargo.toml` and the entry to `crates/registry/src/lib.rs` between
//! their markers, a config that runs it (`configs/<name>.toml`, on seed 000's maps) and
//! its paragraph in ARCHITECTURE.md's code map (before planner-figures'). The result
//! passes tidy, clippy, the docs and the conformance test as generated; its snapshot is
//! written once accepted (`INSTA_UPDATE=new cargo test -p xtask --test experiments`, README.md).
//! Nothing is written unless every step can be done: the name is checked (its length, and
//! its CamelCase type against every name the generated code uses) and the markers are
//! found first, and a write that fails even so (a full disk) undoes the ones before it.

use std::fs;
use std::path::{Path, PathBuf};

const DEPS_MARKER: &str = "# (planners end)";
const REGISTRY_MARKER: &str = "    // (registry end)";

/// The paragraph of ARCHITECTURE.md's code map a new planner's paragraph goes before.
const ARCHITECTURE_MARKER: &str = "**`crates/figures` (`planner-figures`).**";

/// What was written.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scaffolded {
    /// Files created or edited, relative to the workspace root.
    pub files: Vec<String>,
    /// Whether `rustfmt` formatted the Rust files among them (else `cargo fmt` would
    /// change some lines).
    pub formatted: bool,
}

/// Why no planner was scaffolded.
#[derive(Debug, thiserror::Error)]
pub enum ScaffoldError {
    /// A name that cannot be a planner's.
    #[error("planner name {name:?}: {reason}")]
    Name {
        /// The name given.
        name: String,
        /// Why not.
        reason: &'static str,
    },
    /// The crate directory or config exists already.
    #[error("{} already exists", path.display())]
    Exists {
        /// The path.
        path: PathBuf,
    },
    /// The registry has a planner of that name.
    #[error("planner `{0}` is already registered")]
    Registered(String),
    /// A file to edit lacks the marker the new lines go before.
    #[error("{}: marker {marker:?} not found", path.display())]
    Marker {
        /// The file.
        path: PathBuf,
        /// The marker.
        marker: &'static str,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// An I/O error about `path`.
fn io(path: &Path) -> impl FnOnce(std::io::Error) -> ScaffoldError + '_ {
    move |source| ScaffoldError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Creates planner `name` in the workspace at `root`.
pub fn new_planner(root: &Path, name: &str) -> Result<Scaffolded, ScaffoldError> {
    check_name(name)?;
    let crate_dir = root.join("crates").join(name);
    if crate_dir.exists() {
        return Err(ScaffoldError::Exists { path: crate_dir });
    }
    if planner_registry::find(name).is_some() {
        return Err(ScaffoldError::Registered(name.to_string()));
    }
    let cargo_path = root.join("crates/registry/Cargo.toml");
    let registry_path = root.join("crates/registry/src/lib.rs");
    let cargo = fs::read_to_string(&cargo_path).map_err(io(&cargo_path))?;
    let registry = fs::read_to_string(&registry_path).map_err(io(&registry_path))?;
    let config_rel = format!("configs/{name}.toml");
    if root.join(&config_rel).exists() {
        return Err(ScaffoldError::Exists {
            path: root.join(&config_rel),
        });
    }
    let architecture_path = root.join("ARCHITECTURE.md");
    let architecture = fs::read_to_string(&architecture_path).map_err(io(&architecture_path))?;
    for (path, text, marker) in [
        (&cargo_path, &cargo, DEPS_MARKER),
        (&registry_path, &registry, REGISTRY_MARKER),
        (&architecture_path, &architecture, ARCHITECTURE_MARKER),
    ] {
        if !text.contains(marker) {
            return Err(ScaffoldError::Marker {
                path: path.clone(),
                marker,
            });
        }
    }
    let package = format!("planner-{name}");
    let ident = format!("planner_{name}");
    let type_name = type_name(name);
    let cargo = cargo.replacen(
        DEPS_MARKER,
        &format!("{package} = {{ path = \"../{name}\" }}\n{DEPS_MARKER}"),
        1,
    );
    let entry = format!(
        "    Entry {{\n        name: {ident}::NAME,\n        summary: \"{name}: greedy best-first search (the scaffold's; describe yours here)\",\n        task: Task::StartGoal,\n        factory: |params| Factory::path({ident}::NAME, params, {ident}::{type_name}::new),\n    }},\n"
    );
    let registry = registry.replacen(REGISTRY_MARKER, &format!("{entry}{REGISTRY_MARKER}"), 1);
    let architecture = architecture.replacen(
        ARCHITECTURE_MARKER,
        &format!(
            "**`crates/{name}` (`{package}`).** Scaffolded by `cargo xtask new-planner {name}`: a greedy\nbest-first search to replace; `configs/{name}.toml` runs it.\n\n{ARCHITECTURE_MARKER}"
        ),
        1,
    );

    let files = [
        (
            format!("crates/{name}/Cargo.toml"),
            manifest(name, &package),
        ),
        (
            format!("crates/{name}/src/lib.rs"),
            library(name, &ident, &type_name),
        ),
        (
            format!("crates/{name}/tests/smoke.rs"),
            smoke_test(&ident, &type_name),
        ),
        (config_rel.clone(), config(name)),
    ];
    let edits = [
        (&cargo_path, cargo),
        (&registry_path, registry),
        (&architecture_path, architecture),
    ];
    let mut undo = Undo::default();
    if let Err(error) = write_all(root, &files, &edits, &mut undo) {
        undo.roll_back();
        return Err(error);
    }
    let mut written: Vec<String> = files.into_iter().map(|(p, _)| p).collect();
    written.push("crates/registry/Cargo.toml".into());
    written.push("crates/registry/src/lib.rs".into());
    written.push("ARCHITECTURE.md".into());
    let rust: Vec<PathBuf> = written
        .iter()
        .filter(|path| path.ends_with(".rs"))
        .map(|path| root.join(path))
        .collect();
    let formatted = rustfmt(&rust);
    Ok(Scaffolded {
        files: written,
        formatted,
    })
}

/// Formats the generated Rust files as `cargo fmt` would (a long name makes some generated
/// lines longer than rustfmt's width): whether `rustfmt` ran and succeeded. The files are
/// written either way; without rustfmt they compile and only `cargo fmt` changes them.
fn rustfmt(files: &[PathBuf]) -> bool {
    std::process::Command::new("rustfmt")
        .args(["--edition", "2021"])
        .args(files)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|status| status.success())
}

/// What [`write_all`] has done so far, to be undone when a later step fails: the files it
/// created, the directories it created (deepest last), and the edited files' old text.
#[derive(Default)]
struct Undo {
    created_files: Vec<PathBuf>,
    created_dirs: Vec<PathBuf>,
    edited: Vec<(PathBuf, String)>,
}

impl Undo {
    /// Restores the edited files, removes the created files, then the created directories
    /// if they are empty (`remove_dir` leaves a directory someone else wrote into).
    fn roll_back(self) {
        for (path, old) in self.edited.iter().rev() {
            let _ = fs::write(path, old);
        }
        for path in self.created_files.iter().rev() {
            let _ = fs::remove_file(path);
        }
        for dir in self.created_dirs.iter().rev() {
            let _ = fs::remove_dir(dir);
        }
    }
}

/// Writes the new files (creating their directories) and then the edited ones, noting in
/// `undo` each step done.
fn write_all(
    root: &Path,
    files: &[(String, String)],
    edits: &[(&PathBuf, String)],
    undo: &mut Undo,
) -> Result<(), ScaffoldError> {
    for (path, contents) in files {
        let full = root.join(path);
        if let Some(dir) = full.parent() {
            let mut missing: Vec<PathBuf> = dir
                .ancestors()
                .take_while(|d| !d.exists())
                .map(Path::to_path_buf)
                .collect();
            missing.reverse();
            fs::create_dir_all(dir).map_err(io(dir))?;
            undo.created_dirs.extend(missing);
        }
        // `create_new`: a file that appeared since the checks is never overwritten.
        fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&full)
            .and_then(|mut file| std::io::Write::write_all(&mut file, contents.as_bytes()))
            .map_err(io(&full))?;
        undo.created_files.push(full);
    }
    for (path, text) in edits {
        let old = fs::read_to_string(path).map_err(io(path))?;
        undo.edited.push(((*path).clone(), old));
        fs::write(path, text).map_err(io(path))?;
    }
    Ok(())
}

/// The longest planner name: with `configs/<name>.toml`, snapshot names and the package
/// `planner-<name>`, every file name stays far below the usual 255-byte limit.
const MAX_NAME_LEN: usize = 64;

/// Names the generated crate's code uses besides its own type (the prelude's and the
/// derive macros'); the template's and smoke test's own imports are found in their text.
const PRELUDE_TYPES: &[&str] = &[
    "Option",
    "Some",
    "None",
    "Result",
    "Ok",
    "Err",
    "Vec",
    "String",
    "Box",
    "Default",
    "Clone",
    "Copy",
    "Send",
    "Sync",
    "Sized",
    "Drop",
    "Fn",
    "FnMut",
    "FnOnce",
    "Iterator",
    "IntoIterator",
    "DoubleEndedIterator",
    "ExactSizeIterator",
    "Extend",
    "ToString",
    "ToOwned",
    "PartialEq",
    "Eq",
    "PartialOrd",
    "Ord",
    "AsRef",
    "AsMut",
    "Into",
    "From",
    "TryFrom",
    "TryInto",
    "FromIterator",
    "Debug",
    "Hash",
    "Self",
    "JsonSchema",
];

/// Whether the CamelCase type `type_name` would clash with a name the generated code uses:
/// an identifier of the template or smoke test, or the prelude's.
fn clashes_with_template(type_name: &str) -> bool {
    let used = |text: &str| {
        text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .any(|word| word == type_name)
    };
    PRELUDE_TYPES.contains(&type_name)
        || used(&TEMPLATE.replace("__TYPE__", ""))
        || used(&smoke_test("planner_x", ""))
}

/// Rust keywords and names a crate or type cannot take.
const RESERVED: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "static", "struct", "super", "trait", "true", "type", "unsafe", "use",
    "where", "while", "abstract", "become", "box", "do", "final", "macro", "override", "priv",
    "typeof", "unsized", "virtual", "yield", "try", "gen", "api", "maps", "runner", "testkit",
    "registry", "report", "paper", "search", "figures", "stats", "cli", "bench", "test", "core",
    "std", "alloc",
];

/// A planner name is snake case (lowercase words of letters and digits joined by single
/// underscores, starting with a letter, at least 2 characters) and not reserved: it becomes
/// the directory `crates/<name>`, the package `planner-<name>`, the registry name and, in
/// CamelCase, a Rust type.
fn check_name(name: &str) -> Result<(), ScaffoldError> {
    let shape = name.len() >= 2
        && name.starts_with(|c: char| c.is_ascii_lowercase())
        && !name.ends_with('_')
        && !name.contains("__")
        && name
            .chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_');
    if !shape {
        return Err(ScaffoldError::Name {
            name: name.to_string(),
            reason: "use 2 or more lowercase letters, digits and single underscores, starting with a letter (it is the directory crates/<name> and the registry name)",
        });
    }
    if name.len() > MAX_NAME_LEN {
        return Err(ScaffoldError::Name {
            name: name.to_string(),
            reason: "too long (at most 64 characters)",
        });
    }
    if RESERVED.contains(&name) {
        return Err(ScaffoldError::Name {
            name: name.to_string(),
            reason: "reserved (a Rust keyword or a workspace crate's directory); choose another",
        });
    }
    if clashes_with_template(&type_name(name)) {
        return Err(ScaffoldError::Name {
            name: name.to_string(),
            reason: "its type name (the name in CamelCase) is one the generated code already uses (Planner, Config, Path, Outcome, ...); choose another",
        });
    }
    Ok(())
}

/// The planner's type: `name` in CamelCase (`greedy_best` is `GreedyBest`).
fn type_name(name: &str) -> String {
    name.split('_')
        .map(|word| {
            let mut chars = word.chars();
            chars
                .next()
                .map(|c| c.to_ascii_uppercase().to_string() + chars.as_str())
                .unwrap_or_default()
        })
        .collect()
}

fn manifest(name: &str, package: &str) -> String {
    format!(
        r#"[package]
name = "{package}"
description = "The {name} planner for gridplan."
version.workspace = true
edition.workspace = true
rust-version.workspace = true
license.workspace = true

[dependencies]
planner-api.workspace = true
serde.workspace = true
schemars.workspace = true
thiserror.workspace = true

[lints]
workspace = true
"#
    )
}

fn library(name: &str, ident: &str, type_name: &str) -> String {
    TEMPLATE
        .replace("__NAME__", name)
        .replace("__IDENT__", ident)
        .replace("__TYPE__", type_name)
}

/// A config that runs the new planner on seed 000's maps (tidy wants every planner in
/// some config; the snapshot test then pins its counters).
fn config(name: &str) -> String {
    format!(
        r#"# The {name} planner on seed 000's maps, corner to corner (written by
# `cargo xtask new-planner {name}`; its snapshot pins the counters).
name = "{name}"
figures = "none"

[[maps]]
files = ["../maps/paper/map0*.map"]
problems = "corners"

[planners.{name}]
planner = "{name}"
"#
    )
}

fn smoke_test(ident: &str, type_name: &str) -> String {
    format!(
        r#"//! The scaffolded planner finds a path around a wall.

use planner_api::{{Budget, Cell, Grid, Planner, Problem, Status}};
use {ident}::{{Config, {type_name}}};

#[test]
fn finds_a_path_around_a_wall() {{
    let grid = Grid::from_ascii(
        "
        ....
        .##.
        ....
        ",
    )
    .unwrap();
    let problem = Problem::new(&grid, Cell::new(0, 1), Cell::new(3, 1)).unwrap();
    let mut planner = {type_name}::new(Config::default()).unwrap();
    let outcome = planner.plan(&problem, &Budget::unlimited());
    assert_eq!(outcome.status, Status::Found);
    let path = outcome.path.unwrap();
    assert_eq!(path.start(), Some(Cell::new(0, 1)));
    assert_eq!(path.goal(), Some(Cell::new(3, 1)));
    assert_eq!(path.metrics().steps, 5);
}}
"#
    )
}

const TEMPLATE: &str = r#"//! The `__NAME__` planner.
//!
//! Scaffolded by `cargo xtask new-planner __NAME__` as a greedy best-first search (pop the
//! OPEN cell closest to the goal by Manhattan distance; FIFO among ties). Replace the body
//! of `plan` with your algorithm; keep the counters honest (see `planner_api::counters`
//! for what each name means) and document every choice the source paper leaves open.
//!
//! With `Budget::record_expanded` on, it lists the cells it expands in expansion order
//! (`Outcome::expanded`); keep that list, or say in these docs that the planner has none.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use planner_api::{
    Budget, Cell, Connectivity, Counter, IndexedMoves, MoveOrderError, MoveSet, NeighborOrder,
    Outcome, ParamKey, Path, PathSpec, Planner, PlannerSpecs, Problem, SearchStats,
};
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// The registry name.
pub const NAME: &str = "__NAME__";

/// Parameters; every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct Config {
    /// Neighbourhood: 4, 8, 16, 32 or 48 directions. Default 4.
    #[schemars(with = "u32", extend("enum" = [4, 8, 16, 32, 48]))]
    pub moves: Connectivity,
    /// Neighbour order, e.g. `"R L D U"`. Default `"R L D U"`.
    #[schemars(with = "String")]
    pub order: NeighborOrder,
}

impl Default for Config {
    fn default() -> Config {
        Config {
            moves: Connectivity::Four,
            order: NeighborOrder::default(),
        }
    }
}

/// A parameter the planner cannot run with.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ConfigError {
    /// `moves` and `order` do not fit together.
    #[error("parameter `order`: {0}")]
    Moves(#[from] MoveOrderError),
}

impl ParamKey for ConfigError {
    fn param_key(&self) -> &str {
        match self {
            ConfigError::Moves(e) => e.param_key(),
        }
    }
}

/// The planner.
#[derive(Debug, Clone)]
pub struct __TYPE__ {
    moves: MoveSet,
}

impl __TYPE__ {
    /// A planner with `config`, validated.
    pub fn new(config: Config) -> Result<__TYPE__, ConfigError> {
        Ok(__TYPE__ {
            moves: MoveSet::new(config.moves, false, &config.order)?,
        })
    }
}

impl Planner for __TYPE__ {
    fn name(&self) -> &str {
        NAME
    }

    /// Unseeded; every step is one of the configured moves.
    fn specs(&self) -> PlannerSpecs {
        PlannerSpecs::deterministic(PathSpec::Moves(self.moves.clone()))
    }

    fn plan(&mut self, problem: &Problem<'_>, budget: &Budget) -> Outcome {
        let grid = problem.grid();
        let goal = problem.goal();
        let mut stats = SearchStats::default();
        // The per-cell arrays below (a parent and a flag a cell) must fit the memory budget,
        // checked before they are allocated.
        let per_cell = std::mem::size_of::<Option<usize>>() + std::mem::size_of::<bool>();
        if let Err(shortfall) = budget.check_memory(grid.len() as u64 * per_cell as u64, grid) {
            return Outcome::over_memory(shortfall, stats.report(Counter::ASTAR));
        }
        let moves = IndexedMoves::new(&self.moves, grid);
        let mut parent: Vec<Option<usize>> = vec![None; grid.len()];
        let mut seen = vec![false; grid.len()];
        let mut open = BinaryHeap::new();
        let mut clock = budget.start();
        let mut expanded = Vec::new();
        let start = grid.index(problem.start());
        seen[start] = true;
        open.push(Reverse((problem.start().manhattan(goal), 0u64, start)));
        stats.n_open_insertions = 1;
        stats.peak_open = 1;
        let mut n_pushed = 1u64;
        while let Some(Reverse((_, _, node))) = open.pop() {
            if !clock.allows(stats.n_expanded) {
                let outcome = Outcome::budget_exhausted(None, stats.report(Counter::ASTAR));
                return with_expanded(outcome, expanded);
            }
            stats.n_expanded += 1;
            if budget.record_expanded {
                expanded.push(grid.cell(node));
            }
            if node == grid.index(goal) {
                let mut cells = vec![grid.cell(node)];
                let mut at = node;
                while let Some(previous) = parent[at] {
                    cells.push(grid.cell(previous));
                    at = previous;
                }
                cells.reverse();
                let outcome = Outcome::found(Path::new(cells), stats.report(Counter::ASTAR));
                return with_expanded(outcome, expanded);
            }
            let Cell { x, y } = grid.cell(node);
            for k in 0..moves.len() {
                stats.n_neighbor_checks += 1;
                let Some(next) = moves.target(grid.free_cells(), x, y, node, k) else {
                    stats.n_blocked += 1;
                    continue;
                };
                if seen[next] {
                    stats.n_skipped += 1;
                    continue;
                }
                seen[next] = true;
                parent[next] = Some(node);
                stats.n_relaxations += 1;
                stats.n_open_insertions += 1;
                open.push(Reverse((grid.cell(next).manhattan(goal), n_pushed, next)));
                n_pushed += 1;
                stats.peak_open = stats.peak_open.max(open.len() as u64);
            }
        }
        with_expanded(Outcome::no_path(stats.report(Counter::ASTAR)), expanded)
    }
}

/// `outcome` with the cells its search expanded (empty unless the budget asked for them).
fn with_expanded(mut outcome: Outcome, expanded: Vec<Cell>) -> Outcome {
    outcome.expanded = expanded;
    outcome
}
"#;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_names_and_writes_nothing() {
        let root = std::env::temp_dir().join(format!("gridplan-scaffold-{}", std::process::id()));
        for bad in [
            "",
            "A",
            "x",
            "my-planner",
            "-x",
            "9lives",
            "astar",
            "self",
            "crate",
            "x_",
            "a__b",
            "_ab",
            "runner",
            // Over 64 characters (a config file name of 256 bytes failed half-way).
            &format!("a{}", "b".repeat(250)),
            // Types the generated code imports or defines (it did not compile).
            "planner",
            "config",
            "outcome",
            "path",
            "budget",
            "cell",
            "problem",
            "config_error",
            "binary_heap",
            "option",
        ] {
            let refused = new_planner(&root, bad);
            assert!(
                matches!(
                    refused,
                    Err(ScaffoldError::Name { .. } | ScaffoldError::Registered(_))
                ),
                "{bad:?}: {refused:?}"
            );
        }
        assert!(!root.exists());
    }

    /// A write that fails half-way (here `configs` is a file, so the config cannot be
    /// written after the crate's files were) leaves the tree as it was.
    #[test]
    fn a_failed_write_undoes_the_earlier_ones() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../target/tmp/gridplan-scaffold-undo");
        let _ = fs::remove_dir_all(&root);
        fs::create_dir_all(root.join("crates/registry/src")).unwrap();
        let files = [
            (
                "crates/registry/Cargo.toml",
                format!("[dependencies]\n{DEPS_MARKER}\n"),
            ),
            (
                "crates/registry/src/lib.rs",
                format!("const X: &[Entry] = &[\n{REGISTRY_MARKER}\n];\n"),
            ),
            (
                "ARCHITECTURE.md",
                format!("# Code map\n\n{ARCHITECTURE_MARKER}\n"),
            ),
            ("configs", "not a directory\n".to_string()),
        ];
        for (path, text) in &files {
            fs::write(root.join(path), text).unwrap();
        }
        let error = new_planner(&root, "greedy3").unwrap_err();
        assert!(matches!(error, ScaffoldError::Io { .. }), "{error}");
        assert!(!root.join("crates/greedy3").exists());
        for (path, text) in &files {
            assert_eq!(
                &fs::read_to_string(root.join(path)).unwrap(),
                text,
                "{path}"
            );
        }
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn registers_between_the_markers() {
        let root =
            std::env::temp_dir().join(format!("gridplan-scaffold-ok-{}", std::process::id()));
        let _ = fs::remove_dir_all(&root);
        fs::create_dir_all(root.join("crates/registry/src")).unwrap();
        fs::write(
            root.join("crates/registry/Cargo.toml"),
            format!("[dependencies]\n{DEPS_MARKER}\n"),
        )
        .unwrap();
        fs::write(
            root.join("crates/registry/src/lib.rs"),
            format!("const X: &[Entry] = &[\n{REGISTRY_MARKER}\n];\n"),
        )
        .unwrap();
        fs::write(
            root.join("ARCHITECTURE.md"),
            format!("# Code map\n\n{ARCHITECTURE_MARKER} Drawings.\n"),
        )
        .unwrap();
        let done = new_planner(&root, "greedy2").unwrap();
        assert_eq!(done.files.len(), 7);
        let architecture = fs::read_to_string(root.join("ARCHITECTURE.md")).unwrap();
        assert!(architecture.contains("**`crates/greedy2` (`planner-greedy2`).**"));
        assert!(architecture.ends_with(&format!("{ARCHITECTURE_MARKER} Drawings.\n")));
        let config = fs::read_to_string(root.join("configs/greedy2.toml")).unwrap();
        assert!(config.contains("planner = \"greedy2\""));
        let smoke = fs::read_to_string(root.join("crates/greedy2/tests/smoke.rs")).unwrap();
        assert!(smoke.starts_with("//! "));
        let cargo = fs::read_to_string(root.join("crates/registry/Cargo.toml")).unwrap();
        assert!(cargo.contains("planner-greedy2 = { path = \"../greedy2\" }\n# (planners end)"));
        let registry = fs::read_to_string(root.join("crates/registry/src/lib.rs")).unwrap();
        assert!(registry.contains("params, planner_greedy2::Greedy2::new)"));
        let lib = fs::read_to_string(root.join("crates/greedy2/src/lib.rs")).unwrap();
        assert!(
            lib.contains("pub struct Greedy2")
                && lib.contains("pub const NAME: &str = \"greedy2\";")
        );
        assert!(
            new_planner(&root, "greedy2").is_err(),
            "a second scaffold must not overwrite"
        );
        let long = format!("greedy_{}", "x".repeat(56));
        assert!(new_planner(&root, &long).unwrap().formatted);
        // As generated, every Rust file is as rustfmt writes it, a 64-character name too.
        for path in [
            "crates/greedy2/src/lib.rs".to_string(),
            "crates/greedy2/tests/smoke.rs".to_string(),
            format!("crates/{long}/src/lib.rs"),
            format!("crates/{long}/tests/smoke.rs"),
            "crates/registry/src/lib.rs".to_string(),
        ] {
            let status = std::process::Command::new("rustfmt")
                .args(["--edition", "2021", "--check"])
                .arg(root.join(&path))
                .status()
                .unwrap();
            assert!(status.success(), "{path} is not as rustfmt writes it");
        }
        new_planner(&root, "greedy_best").unwrap();
        let registry = fs::read_to_string(root.join("crates/registry/src/lib.rs")).unwrap();
        assert!(registry.contains("params, planner_greedy_best::GreedyBest::new)"));
        fs::remove_dir_all(&root).unwrap();
    }
}
