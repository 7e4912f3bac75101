//! The workspace's invariants (ARCHITECTURE.md), checked from `cargo metadata` and the
//! source tree, as rust-analyzer's tidy test does. Each check names what to fix.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use common::root;
use planner_registry::PLANNERS;

/// The crates under `crates/` that are not planners.
const SUPPORT_CRATES: &[&str] = &[
    "api", "bench", "cli", "figures", "maps", "paper", "registry", "replan", "report", "runner",
    "search", "serve", "stats", "testkit", "text",
];

/// The package of `crates/<dir>`: `planner-<dir>`, but for the command line, `gridplan`.
fn package_name(dir: &str) -> String {
    match dir {
        "cli" => "gridplan".to_string(),
        _ => format!("planner-{dir}"),
    }
}

/// What planner-api may depend on (normal dependencies).
const API_DEPENDENCIES: &[&str] = &["serde", "thiserror"];

/// What no planner crate may depend on (normal dependencies): planners do no I/O and
/// know nothing of the runner.
const PLANNER_FORBIDDEN: &[&str] = &[
    "planner-maps",
    "planner-registry",
    "planner-runner",
    "planner-report",
    "planner-paper",
    "xtask",
    "tracing",
    "gridplan",
];

struct Package {
    name: String,
    dir: PathBuf,
    /// Normal (not dev, not build) dependencies.
    dependencies: Vec<String>,
    /// Its targets: [`targets`].
    targets: Vec<(String, String, PathBuf, bool)>,
}

/// What `cargo ARGS` prints on stdout, run in the workspace root; it must succeed.
fn cargo(args: &[&str]) -> Vec<u8> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args(args)
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| panic!("cargo {args:?}: {e}"));
    assert!(
        output.status.success(),
        "cargo {args:?}: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
}

/// `cargo metadata --format-version 1 --offline` with `args`, parsed.
fn cargo_metadata(args: &[&str]) -> serde_json::Value {
    let mut all = vec!["metadata", "--format-version", "1", "--offline"];
    all.extend_from_slice(args);
    serde_json::from_slice(&cargo(&all)).unwrap()
}

fn packages() -> Vec<Package> {
    let metadata = cargo_metadata(&["--no-deps"]);
    metadata["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| Package {
            name: p["name"].as_str().unwrap().to_string(),
            dir: PathBuf::from(p["manifest_path"].as_str().unwrap())
                .parent()
                .unwrap()
                .to_path_buf(),
            dependencies: p["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["kind"].is_null())
                .map(|d| d["name"].as_str().unwrap().to_string())
                .collect(),
            targets: targets(p),
        })
        .collect()
}

fn crate_dirs() -> BTreeSet<String> {
    std::fs::read_dir(root().join("crates"))
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().join("Cargo.toml").is_file())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .collect()
}

#[test]
fn planner_api_depends_only_on_its_listed_dependencies() {
    let api = packages()
        .into_iter()
        .find(|p| p.name == "planner-api")
        .unwrap();
    for dep in &api.dependencies {
        assert!(
            API_DEPENDENCIES.contains(&dep.as_str()),
            "planner-api depends on {dep}; it may depend only on {API_DEPENDENCIES:?} (it is the vocabulary every planner shares)"
        );
    }
}

#[test]
fn planner_crates_do_no_io_and_know_no_runner() {
    let packages = packages();
    for entry in PLANNERS {
        let package = format!("planner-{}", entry.name);
        let p = packages
            .iter()
            .find(|p| p.name == package)
            .unwrap_or_else(|| panic!("registry name `{}` has no package {package}", entry.name));
        for dep in &p.dependencies {
            assert!(
                !PLANNER_FORBIDDEN.contains(&dep.as_str()),
                "{package} depends on {dep}: planner crates may not depend on {PLANNER_FORBIDDEN:?} (dev-dependencies are fine)"
            );
        }
    }
}

#[test]
fn registry_crate_directories_and_runner_dependencies_match() {
    let names: BTreeSet<String> = PLANNERS.iter().map(|e| e.name.to_string()).collect();
    assert_eq!(names.len(), PLANNERS.len(), "a registry name appears twice");
    let dirs = crate_dirs();
    let planner_dirs: BTreeSet<String> = dirs
        .iter()
        .filter(|d| !SUPPORT_CRATES.contains(&d.as_str()))
        .cloned()
        .collect();
    assert_eq!(
        names, planner_dirs,
        "registry names (crates/registry/src/lib.rs) and the planner directories under crates/ differ"
    );
    let packages = packages();
    for dir in &dirs {
        let p = packages
            .iter()
            .find(|p| p.dir.file_name().is_some_and(|n| n == dir.as_str()))
            .unwrap_or_else(|| panic!("crates/{dir} is not a workspace member"));
        assert_eq!(p.name, package_name(dir), "crates/{dir}'s package name");
    }
    let registry = packages
        .iter()
        .find(|p| p.name == "planner-registry")
        .unwrap();
    let registry_planners: BTreeSet<String> = registry
        .dependencies
        .iter()
        .filter_map(|d| d.strip_prefix("planner-"))
        .filter(|d| !SUPPORT_CRATES.contains(d))
        .map(String::from)
        .collect();
    assert_eq!(
        names, registry_planners,
        "planner-registry's planner dependencies and its list differ"
    );
}

/// The packages that are planners (a registry name's `planner-<name>`).
fn planner_packages() -> BTreeSet<String> {
    PLANNERS
        .iter()
        .map(|e| format!("planner-{}", e.name))
        .collect()
}

/// What the layered crates may not depend on (normal dependencies), beside any planner
/// crate: dependencies point down (ARCHITECTURE.md, "Layers").
const LAYER_FORBIDDEN: &[(&str, &[&str])] = &[
    (
        "planner-registry",
        &[
            "planner-maps",
            "planner-runner",
            "planner-report",
            "planner-paper",
            "rayon",
        ],
    ),
    (
        "planner-runner",
        &[
            "plotters",
            "pulldown-cmark",
            "planner-figures",
            "planner-stats",
            "planner-report",
            "planner-paper",
        ],
    ),
    ("planner-report", &["planner-registry", "planner-paper"]),
    ("planner-paper", &["planner-registry"]),
    // Above the runner, whose results directories (`outdir`) it writes.
    ("planner-replan", &["planner-report", "planner-paper"]),
    ("planner-serve", &["planner-report", "planner-paper"]),
    // At the bottom: every writer of user text uses it, so it uses none of them.
    (
        "planner-text",
        &[
            "planner-api",
            "planner-maps",
            "planner-registry",
            "planner-runner",
            "planner-report",
            "planner-paper",
            "planner-replan",
        ],
    ),
];

/// Packages that may depend on planner crates directly: the registry (the one list),
/// planner crates themselves (one planner may build on another), xtask (which runs
/// PA-star's map generator), and planner-replan, which takes the incremental planners
/// from the registry but builds its baseline of its own from A* (restarted at every
/// replan behind the incremental interface, which the registry's factories do not offer)
/// and checks every replan against an exact A* oracle that must not be a user's
/// configuration.
const MAY_NAME_PLANNERS: &[&str] = &["planner-registry", "xtask", "planner-replan"];

#[test]
fn dependencies_point_down_and_only_the_registry_names_planners() {
    let packages = packages();
    let planners = planner_packages();
    for p in &packages {
        if planners.contains(&p.name) || MAY_NAME_PLANNERS.contains(&p.name.as_str()) {
            continue;
        }
        for dep in &p.dependencies {
            assert!(
                !planners.contains(dep),
                "{} depends on the planner crate {dep}: only planner-registry names planners (add the planner to crates/registry instead)",
                p.name
            );
        }
    }
    for (package, forbidden) in LAYER_FORBIDDEN {
        let p = packages
            .iter()
            .find(|p| p.name == *package)
            .unwrap_or_else(|| panic!("no package {package}"));
        for dep in &p.dependencies {
            assert!(
                !forbidden.contains(&dep.as_str()),
                "{package} depends on {dep}; it may not depend on {forbidden:?} (dependencies point down: ARCHITECTURE.md)"
            );
        }
    }
}

/// What the report and paper crates' sources may not name: they render a results
/// directory and never run a planner or read the planner list.
const RENDER_FORBIDDEN: &[&str] = &[
    "run_one",
    "run_all",
    "run_stream",
    "record_expanded",
    "record_all",
    "planner_registry",
    "PLANNERS",
    ".build()",
];

#[test]
fn report_and_paper_never_run_a_planner() {
    for dir in ["crates/report/src", "crates/paper/src"] {
        let mut files = Vec::new();
        rust_files(&root().join(dir), &mut files);
        assert!(!files.is_empty(), "{dir} has no Rust files");
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or_default();
                for word in RENDER_FORBIDDEN {
                    assert!(
                        !code.contains(word),
                        "{}:{}: `{word}`: the report renders a results directory and never runs a planner or reads the planner list",
                        file.display(),
                        n + 1
                    );
                }
            }
        }
    }
}

#[test]
fn every_registered_planner_is_in_some_config() {
    let texts: Vec<String> = common::configs()
        .iter()
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    for entry in PLANNERS {
        let key = format!("planner = \"{}\"", entry.name);
        assert!(
            texts.iter().any(|t| t.contains(&key)),
            "no config under configs/ runs `{}`: add a label with {key}",
            entry.name
        );
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if path.is_dir() {
            if name != "target" && !name.starts_with('.') {
                rust_files(&path, out);
            }
        } else if name.ends_with(".rs") {
            out.push(path);
        }
    }
}

/// Every Rust file under the directories `dirs` (relative to the root): its path relative
/// to the root and its text.
fn sources(dirs: &[&str]) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for dir in dirs {
        let mut files = Vec::new();
        rust_files(&root().join(dir), &mut files);
        for file in files {
            let relative = file.strip_prefix(root()).unwrap().display().to_string();
            out.push((relative, std::fs::read_to_string(&file).unwrap()));
        }
    }
    out
}

#[test]
fn every_rust_file_opens_with_a_module_doc() {
    let mut files = Vec::new();
    for dir in ["crates", "xtask"] {
        rust_files(&root().join(dir), &mut files);
    }
    assert!(files.len() > 50);
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(
            text.starts_with("//!"),
            "{} does not open with a `//!` doc comment saying what it is",
            file.display()
        );
    }
}

#[test]
fn architecture_names_every_crate() {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    for dir in crate_dirs() {
        let package = package_name(&dir);
        assert!(
            text.contains(&format!("crates/{dir}")) && text.contains(&package),
            "ARCHITECTURE.md's code map does not name crates/{dir} ({package})"
        );
    }
}

/// The workspace's `rust-version` (its MSRV).
fn workspace_msrv() -> (u32, u32, u32) {
    let text = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    let manifest: toml::Value = toml::from_str(&text).unwrap();
    let msrv = manifest["workspace"]["package"]["rust-version"]
        .as_str()
        .expect("workspace.package.rust-version is set");
    parse_version(msrv)
}

/// `1.85` or `1.85.0` as (1, 85, 0).
fn parse_version(text: &str) -> (u32, u32, u32) {
    let mut parts = text.split('.').map(|p| p.parse::<u32>().unwrap_or(0));
    (
        parts.next().unwrap_or(0),
        parts.next().unwrap_or(0),
        parts.next().unwrap_or(0),
    )
}

/// No package in the resolved dependency graph (dev and build dependencies included, on
/// Linux x86-64) declares a `rust-version` above the workspace's. This machine has one
/// toolchain, so the MSRV cannot be built here; what the dependencies declare is the check
/// that can run. A failure names the package: pin an older version in Cargo.lock
/// (`cargo update -p NAME --precise VERSION`). Packages that declare nothing cannot be
/// checked this way (plotters is one).
#[test]
fn no_dependency_declares_a_rust_version_above_the_msrv() {
    let metadata = cargo_metadata(&["--filter-platform", "x86_64-unknown-linux-gnu"]);
    let resolved: BTreeSet<&str> = metadata["resolve"]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|n| n["id"].as_str())
        .collect();
    let msrv = workspace_msrv();
    let above: Vec<String> = metadata["packages"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["id"].as_str().is_some_and(|id| resolved.contains(id)))
        .filter_map(|p| {
            let declared = p["rust_version"].as_str()?;
            (parse_version(declared) > msrv).then(|| {
                format!(
                    "{} {} (rust-version {declared})",
                    p["name"].as_str().unwrap_or("?"),
                    p["version"].as_str().unwrap_or("?")
                )
            })
        })
        .collect();
    assert!(
        above.is_empty(),
        "dependencies above the workspace's rust-version {msrv:?}: {above:?}"
    );
    assert!(
        resolved.len() > 50,
        "the graph was read ({} packages)",
        resolved.len()
    );
}

/// The crates whose functions stay short and whose public errors are typed.
const LAYERED_SOURCES: &[&str] = &["crates/runner/src", "crates/report/src", "crates/paper/src"];

/// Every function with a body in the Rust source `text`: (name, line of its `fn`,
/// lines from there to its closing brace, both counted). A scan that matches braces,
/// passing over comments, string, byte, raw string and char literals (a lifetime is not
/// a char), so any layout counts, not only rustfmt's; every `fn` counts, nested ones too
/// (their lines count in the outer one as well), whatever its qualifiers (`pub(super)`,
/// `const`, `async`, `unsafe`, `extern`). A `fn` without a name (a function pointer type)
/// or without a body (a trait's declaration) is none.
fn functions(text: &str) -> Vec<(String, usize, usize)> {
    let chars: Vec<char> = text.chars().collect();
    // Each char's line (1-based), and a mask of the chars that are code (not comments or
    // literals): what the brace matching reads.
    let mut line_of = Vec::with_capacity(chars.len());
    let mut code = vec![true; chars.len()];
    let mut line = 1;
    let mut i = 0;
    while i < chars.len() {
        let skip_to = literal_or_comment_end(&chars, i);
        let end = skip_to.unwrap_or(i + 1);
        for (j, &c) in chars.iter().enumerate().take(end).skip(i) {
            line_of.push(line);
            if skip_to.is_some() {
                code[j] = false;
            }
            if c == '\n' {
                line += 1;
            }
        }
        i = end;
    }
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    for i in 0..chars.len() {
        let word_start = code[i] && (i == 0 || !is_ident(chars[i - 1]));
        if !(word_start && chars[i] == 'f' && chars.get(i + 1) == Some(&'n')) {
            continue;
        }
        let mut j = i + 2;
        if chars.get(j).is_none_or(|c| !c.is_whitespace()) {
            continue;
        }
        while chars.get(j).is_some_and(|c| c.is_whitespace()) {
            j += 1;
        }
        let name: String = chars[j..].iter().take_while(|&&c| is_ident(c)).collect();
        if name.is_empty() || name.starts_with(|c: char| c.is_ascii_digit()) {
            continue;
        }
        // The body: the first `{` outside parentheses and brackets, unless a `;` comes first.
        let mut depth = 0i32;
        let mut open = None;
        for k in j + name.len()..chars.len() {
            if !code[k] {
                continue;
            }
            match chars[k] {
                '(' | '[' => depth += 1,
                ')' | ']' => depth -= 1,
                ';' if depth == 0 => break,
                '{' if depth == 0 => {
                    open = Some(k);
                    break;
                }
                _ => {}
            }
        }
        let Some(open) = open else { continue };
        let mut braces = 0i32;
        for k in open..chars.len() {
            if !code[k] {
                continue;
            }
            match chars[k] {
                '{' => braces += 1,
                '}' => braces -= 1,
                _ => {}
            }
            if braces == 0 {
                out.push((name, line_of[i], line_of[k] - line_of[i] + 1));
                break;
            }
        }
    }
    out
}

/// Where the comment or literal starting at `chars[i]` ends (one past it), or `None` when
/// none starts there.
fn literal_or_comment_end(chars: &[char], i: usize) -> Option<usize> {
    let at = |k: usize| chars.get(k).copied();
    let find = |from: usize, pat: &[char]| {
        (from..chars.len())
            .find(|&k| chars[k..].starts_with(pat))
            .map_or(chars.len(), |k| k + pat.len())
    };
    let prev_ident = i > 0 && (chars[i - 1].is_alphanumeric() || chars[i - 1] == '_');
    match (at(i)?, at(i + 1)) {
        ('/', Some('/')) => Some(find(i, &['\n'])),
        ('/', Some('*')) => {
            // Block comments nest.
            let (mut depth, mut k) = (0, i);
            while k < chars.len() {
                if chars[k..].starts_with(&['/', '*']) {
                    depth += 1;
                    k += 2;
                } else if chars[k..].starts_with(&['*', '/']) {
                    depth -= 1;
                    k += 2;
                    if depth == 0 {
                        return Some(k);
                    }
                } else {
                    k += 1;
                }
            }
            Some(chars.len())
        }
        ('r' | 'b', _) if !prev_ident => {
            // r"..", r#".."#, b"..", br#".."#, b'.'.
            let mut k = i + 1;
            if chars[i] == 'b' && at(k) == Some('r') {
                k += 1;
            }
            let raw = chars[i] == 'r' || k == i + 2;
            if raw {
                let hashes = chars[k..].iter().take_while(|&&c| c == '#').count();
                if at(k + hashes) != Some('"') {
                    return None;
                }
                let mut close = vec!['"'];
                close.extend(std::iter::repeat_n('#', hashes));
                Some(find(k + hashes + 1, &close))
            } else {
                match at(k) {
                    Some('"') => Some(quoted_end(chars, k, '"')),
                    Some('\'') => Some(quoted_end(chars, k, '\'')),
                    _ => None,
                }
            }
        }
        ('"', _) => Some(quoted_end(chars, i, '"')),
        // A char literal ('x', '\n', '\u{7f}'), not a lifetime ('a).
        ('\'', Some('\\')) => Some(quoted_end(chars, i, '\'')),
        ('\'', Some(_)) if at(i + 2) == Some('\'') => Some(i + 3),
        _ => None,
    }
}

/// One past the closing `quote` of the literal opened at `chars[open]`, escapes skipped.
fn quoted_end(chars: &[char], open: usize, quote: char) -> usize {
    let mut k = open + 1;
    while k < chars.len() {
        match chars[k] {
            '\\' => k += 2,
            c if c == quote => return k + 1,
            _ => k += 1,
        }
    }
    chars.len()
}

/// The scan on a fixture with every trap it passes over: braces in strings, raw strings,
/// chars, comments; lifetimes; a nested fn; a bodiless trait fn with `[u8; 4]`; a
/// function pointer type; qualifiers; a layout rustfmt would not write.
#[test]
fn the_function_scan_matches_braces_past_literals_and_comments() {
    let fixture = r####"//! Fixture.
pub(super) const fn a<'x>(s: &'x str) -> &'x str {
    let _ = "}}}"; let _ = '}'; let _ = '\'';
    // }
    /* { /* nested } */ } */
    let _ = r#"}"#; let _ = b'{'; let _ = br"}";
    s
}
trait T { fn declared(&self, b: [u8; 4]) -> u8; }
fn takes(f: fn(u8) -> u8) -> u8 { f(1) }
unsafe extern "C" fn outer() {
    fn inner() -> char { '{' }
    inner();
  }
async fn last() {}
"####;
    assert_eq!(
        functions(fixture),
        vec![
            ("a".to_string(), 2, 7),
            ("takes".to_string(), 10, 1),
            ("outer".to_string(), 11, 4),
            ("inner".to_string(), 12, 1),
            ("last".to_string(), 15, 1),
        ]
    );
}

#[test]
fn no_function_of_the_runner_report_or_paper_is_over_100_lines() {
    let mut long = Vec::new();
    for (relative, text) in sources(LAYERED_SOURCES) {
        for (name, line, n) in functions(&text) {
            if n > 100 {
                long.push((relative.clone(), name, line, n));
            }
        }
    }
    if let Some((file, name, line, n)) = long.first() {
        panic!("{file}:{line}: fn {name} has {n} lines; split it (at most 100)");
    }
}

/// What the layered crates' sources may not name outside their tests: the process's
/// environment, current directory, executable, id, exit and child processes belong to
/// the command line, xtask and the Python package, which pass what the library needs as
/// arguments (ARCHITECTURE.md, "Layers").
const PROCESS_FORBIDDEN: &[&str] = &["std::env", "std::process"];

/// Nor may they print: the command line, xtask and the Python package print; the library
/// reports through its return values, its progress callback and `tracing` (which the
/// caller sends where it wants).
const PRINT_FORBIDDEN: &[&str] = &["println!", "eprintln!", "print!(", "eprint!(", "dbg!("];

#[test]
fn the_runner_report_and_paper_read_no_process_state_and_print_nothing() {
    for dir in LAYERED_SOURCES {
        assert!(!sources(&[dir]).is_empty(), "{dir} has no Rust files");
    }
    for (relative, text) in sources(LAYERED_SOURCES) {
        // A file's unit tests (its `#[cfg(test)]` module, last by convention) may.
        for (n, line) in text
            .lines()
            .enumerate()
            .take_while(|(_, l)| l.trim() != "#[cfg(test)]")
        {
            let code = line.split("//").next().unwrap_or_default();
            for word in PROCESS_FORBIDDEN {
                assert!(
                    !code.contains(word),
                    "{relative}:{}: `{word}`: the runner, report and paper read no process state; take it as an argument from the caller (cli, xtask, python)",
                    n + 1
                );
            }
            for word in PRINT_FORBIDDEN {
                assert!(
                    !code.contains(word),
                    "{relative}:{}: `{word}`: the runner, report and paper do not print; return it, or say it with `tracing` (cli, xtask and python print)",
                    n + 1
                );
            }
        }
    }
}

/// The command line writes its lines to stderr through `to_stderr!`, which loses a line
/// when stderr is closed (`2>&1 | head -1`), where `eprintln!` panics (status 101, and a
/// sweep's results lost to a warning). xtask prints through the command line's functions.
#[test]
fn the_command_line_writes_stderr_without_panicking() {
    for (relative, text) in sources(&["crates/cli/src", "xtask/src"]) {
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or_default();
            for word in ["eprintln!(", "eprint!("] {
                assert!(
                    !code.contains(word),
                    "{relative}:{}: `{word}` panics when stderr is a closed pipe; use `to_stderr!` (crates/cli)",
                    n + 1
                );
            }
        }
    }
}

/// The libraries' error types carry what went wrong as fields, never as one preformatted
/// message (a caller, the Python package among them, can then tell the cases apart): no
/// `#[error("{0}")]` variant or struct whose payload is a `String` in any crate but the
/// command line's, which composes messages to print. (A `String` the message quotes, such
/// as the text a user gave, is a field like any other.)
#[test]
fn library_errors_are_not_strings() {
    let mut dirs: Vec<String> = std::fs::read_dir(root().join("crates"))
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().to_string())
        .filter(|name| name != "cli")
        .map(|name| format!("crates/{name}/src"))
        .filter(|dir| root().join(dir).is_dir())
        .collect();
    dirs.sort();
    assert!(dirs.len() > 20, "{dirs:?}");
    let dirs: Vec<&str> = dirs.iter().map(String::as_str).collect();
    for (relative, text) in sources(&dirs) {
        let lines: Vec<&str> = text.lines().collect();
        for (i, line) in lines.iter().enumerate() {
            if line.trim() != "#[error(\"{0}\")]" {
                continue;
            }
            // The item the attribute is on: the first line after it that is neither an
            // attribute nor a doc comment.
            let item = lines[i + 1..]
                .iter()
                .map(|l| l.trim())
                .find(|l| !(l.starts_with("#[") || l.starts_with("///") || l.is_empty()));
            if let Some(item) = item {
                assert!(
                    !(item.contains("(String)") || item.contains("(pub String)")),
                    "{relative}:{}: `{item}`: an error that is a preformatted String; give it fields (ARCHITECTURE.md, Invariants)",
                    i + 1
                );
            }
        }
    }
}

/// The sources whose public functions must return typed errors: the layered crates, the
/// server, the command line, xtask and the replanning experiments.
const TYPED_ERROR_SOURCES: &[&str] = &[
    "crates/runner/src",
    "crates/report/src",
    "crates/paper/src",
    "crates/serve/src",
    "crates/cli/src",
    "crates/replan/src",
    "xtask/src",
];

#[test]
fn public_functions_of_the_libraries_cli_and_xtask_return_typed_errors() {
    for dir in TYPED_ERROR_SOURCES {
        let mut files = Vec::new();
        rust_files(&root().join(dir), &mut files);
        for file in files {
            let relative = file.strip_prefix(root()).unwrap().display().to_string();
            let text = std::fs::read_to_string(&file).unwrap();
            let lines: Vec<&str> = text.lines().collect();
            for (i, line) in lines.iter().enumerate() {
                let Some(after) = line.trim_start().strip_prefix("pub fn ") else {
                    continue;
                };
                let name: String = after
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                // The signature: up to the line that opens the body.
                let signature: String = lines[i..]
                    .iter()
                    .take_while(|l| !l.trim_end().ends_with('{') && !l.trim_end().ends_with(';'))
                    .chain(
                        lines[i..]
                            .iter()
                            .find(|l| l.trim_end().ends_with('{') || l.trim_end().ends_with(';')),
                    )
                    .copied()
                    .collect::<Vec<_>>()
                    .join(" ");
                let stringly = signature.contains(", String>") && signature.contains("Result<");
                if stringly {
                    panic!(
                        "{relative}:{}: pub fn {name} returns Result<_, String>; give it a thiserror type",
                        i + 1
                    );
                }
            }
        }
    }
}

/// A package's targets from `cargo metadata`: (kind, name, source path, built for tests).
fn targets(package: &serde_json::Value) -> Vec<(String, String, PathBuf, bool)> {
    package["targets"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| {
            (
                t["kind"][0].as_str().unwrap().to_string(),
                t["name"].as_str().unwrap().to_string(),
                PathBuf::from(t["src_path"].as_str().unwrap()),
                t["test"].as_bool().unwrap_or(true),
            )
        })
        .collect()
}

/// xtask's test binaries: `tidy` and `experiments` keep their names (the docs, CI and the
/// snapshot workflow run `--test tidy` and `--test experiments`), the rest is `it`.
const XTASK_TESTS: &[&str] = &["experiments", "it", "tidy"];

/// One integration-test binary per package (xtask: [`XTASK_TESTS`]), and every file
/// directly under a package's `tests/` is compiled: the root of a test target or a module
/// (`mod NAME;`) that a root declares. Each test binary links the package's whole
/// dependency graph, so a new test file is a module of `tests/it.rs`, not a binary of its
/// own; and with `autotests = false` an undeclared file would silently never run
/// (ARCHITECTURE.md, "Tests").
#[test]
fn one_test_binary_per_package_and_every_test_file_compiled() {
    for Package {
        name, dir, targets, ..
    } in packages()
    {
        let tests: Vec<(String, PathBuf)> = targets
            .into_iter()
            .filter(|(kind, ..)| kind == "test")
            .map(|(_, target, path, _)| (target, path))
            .collect();
        let names: BTreeSet<&str> = tests.iter().map(|(t, _)| t.as_str()).collect();
        if name == "xtask" {
            assert_eq!(
                names,
                XTASK_TESTS.iter().copied().collect(),
                "xtask's test binaries: new test files are modules of xtask/tests/it.rs"
            );
        } else {
            assert!(
                names.len() <= 1,
                "{name} has the test binaries {names:?}: one per package; make each file a module of tests/it.rs (`mod NAME;`), with `autotests = false` and one [[test]] in its Cargo.toml (ARCHITECTURE.md, \"Tests\")"
            );
        }
        let mut declared: BTreeSet<PathBuf> = tests.iter().map(|(_, p)| p.clone()).collect();
        for (_, root_file) in &tests {
            let text = std::fs::read_to_string(root_file).unwrap();
            for line in text.lines() {
                if let Some(module) = line
                    .trim()
                    .strip_prefix("mod ")
                    .and_then(|m| m.strip_suffix(';'))
                {
                    let base = root_file.parent().unwrap();
                    declared.insert(base.join(format!("{module}.rs")));
                }
            }
        }
        let Ok(entries) = std::fs::read_dir(dir.join("tests")) else {
            continue;
        };
        for entry in entries {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "rs") {
                assert!(
                    declared.contains(&path),
                    "{} is compiled by no test binary of {name}: declare it in tests/it.rs (`mod NAME;`)",
                    path.display()
                );
            }
        }
    }
}

/// A library or binary built without its test harness (`test = false`, which saves a
/// second compilation of it in `cargo test`) has no unit tests: they would never run. A
/// library's files are those under `src/` but the other targets' roots; a binary's, its root.
#[test]
fn targets_without_a_test_build_have_no_unit_tests() {
    for Package {
        name, dir, targets, ..
    } in packages()
    {
        for (kind, target, root_file, test) in &targets {
            if *test || (kind != "lib" && kind != "bin") {
                continue;
            }
            let files = if kind == "lib" {
                let mut files = Vec::new();
                rust_files(&dir.join("src"), &mut files);
                files.retain(|f| {
                    !targets
                        .iter()
                        .any(|(_, _, other, _)| other == f && f != root_file)
                });
                files
            } else {
                vec![root_file.clone()]
            };
            for file in files {
                let text = std::fs::read_to_string(&file).unwrap();
                for (n, line) in text.lines().enumerate() {
                    let code = line.split("//").next().unwrap_or_default();
                    assert!(
                        !code.contains("#[test]") && !code.contains("#[cfg(test)]"),
                        "{}:{}: a unit test in {name}'s {kind} {target}, which its Cargo.toml builds with `test = false`: move it to tests/it.rs or drop `test = false`",
                        file.display(),
                        n + 1
                    );
                }
            }
        }
    }
}

/// Each package of the dependency graph `cargo tree` prints for `selection` (and
/// `edges`), as `name version [features]`, one line per build of it.
fn feature_sets(selection: &[&str], edges: &str) -> BTreeSet<String> {
    let mut args = vec![
        "tree",
        "--offline",
        "--prefix",
        "none",
        "--format",
        "{p} [{f}]",
        "-e",
        edges,
    ];
    args.extend_from_slice(selection);
    String::from_utf8_lossy(&cargo(&args))
        .lines()
        .map(|line| line.trim_end_matches(" (*)").to_owned())
        .filter(|line| !line.is_empty())
        .collect()
}

/// Cargo turns on a dependency's features per selection of packages: a dependency that
/// only a test turns a feature on for is built once for `cargo test --workspace` and again,
/// without the feature, for `cargo xtask` (and so is everything above it, about 90 s in
/// CI). The front ends' Cargo.toml files name those dependencies with those features, so
/// that the main job, `cargo install` and the Python wheel reuse the test build.
#[test]
fn front_ends_build_with_the_workspace_test_features() {
    let workspace = feature_sets(&["--workspace"], "normal,build,dev");
    for package in ["xtask", "gridplan", "gridplan-python"] {
        let own = feature_sets(&["-p", package], "normal,build");
        let differing: Vec<&String> = own.difference(&workspace).collect();
        assert!(
            differing.is_empty(),
            "`cargo build -p {package}` builds these with other features than `cargo test --workspace`: {differing:?}; \
             name each in crates/cli/Cargo.toml (or python/Cargo.toml) with the workspace's features"
        );
    }
}
