//! The files a config's `files` pattern names: the `glob` crate's patterns (`*`, `?`,
//! `[...]`, `**`), with one difference. `**` descends into directories only, never through a
//! link to a directory (as bash's `globstar` does since bash 4.3): the `glob` crate follows
//! such links, so one link back to a parent (`maps/sub/loop -> ..`) made a `maps/**/*.map`
//! walk endless. A link under a `**` is still matched as a file, and a link named by the
//! pattern's other components (`maps/linked/*.map`) is followed as before.
//!
//! A directory that cannot be read is an error naming it, where it used to be skipped
//! silently: an experiment over fewer maps than its config names would say nothing of it.
//! So is a name that is not UTF-8 where a wildcard would match it read as UTF-8 with
//! replacement characters (`bad\xff.map` under `maps/*.map`): the `glob` crate skipped such
//! names, and a map's name, written into every record, must be text.

use std::fs;
use std::io;
use std::path::{Component, Path, PathBuf};

use glob::{MatchOptions, Pattern};

/// Why a pattern names no list of files.
#[derive(Debug, thiserror::Error)]
pub enum PatternError {
    /// The pattern is malformed (`a**`, an unclosed `[`).
    #[error("bad pattern: {0}")]
    Pattern(#[from] glob::PatternError),
    /// A file or directory the pattern would match has a name that is not UTF-8 (shown with
    /// replacement characters).
    #[error("{} matches but its name is not UTF-8; rename it", path.display())]
    NotUnicode {
        /// The path.
        path: PathBuf,
    },
    /// A directory the pattern reaches could not be listed.
    #[error("cannot read directory {}: {source}", path.display())]
    Directory {
        /// The directory.
        path: PathBuf,
        /// Why it could not be listed.
        source: io::Error,
    },
}

/// The paths matching `pattern`, sorted. A component `**` matches any number of directories
/// below it, links to directories excepted (module docs).
pub fn expand(pattern: &Path) -> Result<Vec<PathBuf>, PatternError> {
    // Components, so that `a/./b` and `a//b` are matched as the walk writes paths: `a/b`.
    let components: Vec<Component<'_>> = pattern.components().collect();
    let recursive = components.iter().position(|c| c.as_os_str() == "**");
    let mut matches = Vec::new();
    match recursive {
        None => matches = expand_components(&components)?,
        Some(at) => {
            let head: PathBuf = match at {
                0 => PathBuf::from("."),
                _ => components[..at].iter().collect(),
            };
            // What precedes the first `**` names finitely many directories; each is walked,
            // its paths matched from the `**` on.
            let tail: PathBuf = components[at..].iter().collect();
            let tail = Pattern::new(&tail.to_string_lossy())?;
            for root in expand(&head)? {
                if root.is_dir() {
                    walk(&root, at == 0, &tail, &mut matches)?;
                }
            }
        }
    }
    matches.sort();
    Ok(matches)
}

/// The existing paths matching `components` (no `**` among them), one component at a time
/// as the `glob` crate matches them: a component without wildcards is joined as it is, one
/// with wildcards is matched against the names in each directory reached so far (links to
/// directories followed, as by the shell).
fn expand_components(components: &[Component<'_>]) -> Result<Vec<PathBuf>, PatternError> {
    let mut reached = vec![PathBuf::new()];
    for (i, component) in components.iter().enumerate() {
        // Above the last component only directories can lead anywhere.
        let last = i + 1 == components.len();
        let text = component.as_os_str().to_string_lossy();
        let literal = !matches!(component, Component::Normal(_)) || !text.contains(['*', '?', '[']);
        if literal {
            for path in &mut reached {
                path.push(component);
            }
            continue;
        }
        let pattern = Pattern::new(&text)?;
        let mut next = Vec::new();
        for dir in &reached {
            let listed = match dir.as_os_str().is_empty() {
                true => Path::new("."),
                false => dir.as_path(),
            };
            if !listed.is_dir() {
                continue;
            }
            let unreadable = |source| PatternError::Directory {
                path: listed.to_path_buf(),
                source,
            };
            for entry in fs::read_dir(listed).map_err(unreadable)? {
                let name = entry.map_err(unreadable)?.file_name();
                if !last && !dir.join(&name).is_dir() {
                    continue;
                }
                if matches_name(&pattern, &name, &dir.join(&name), MatchOptions::new())? {
                    next.push(dir.join(&name));
                }
            }
        }
        reached = next;
    }
    // A literal last component (or a pattern without wildcards) names what may not exist.
    reached.retain(|path| fs::symlink_metadata(path).is_ok());
    Ok(reached)
}

/// Whether `pattern` matches `text` (the part of `path` it is matched against); an error
/// when `text` is not UTF-8 and its replacement-character form matches (module docs).
fn matches_name(
    pattern: &Pattern,
    text: &std::ffi::OsStr,
    path: &Path,
    options: MatchOptions,
) -> Result<bool, PatternError> {
    match text.to_str() {
        Some(text) => Ok(pattern.matches_with(text, options)),
        None if pattern.matches_with(&text.to_string_lossy(), options) => {
            Err(PatternError::NotUnicode {
                path: path.to_path_buf(),
            })
        }
        None => Ok(false),
    }
}

/// Adds to `out` every path below `root` whose part below `root` `pattern` matches,
/// descending into directories but not through links (module docs). `strip_dot`: `root` is
/// the `.` a relative pattern starting with `**` begins at, left out of the paths.
fn walk(
    root: &Path,
    strip_dot: bool,
    pattern: &Pattern,
    out: &mut Vec<PathBuf>,
) -> Result<(), PatternError> {
    // `*` stops at a separator, as it does in the `glob` crate's component-wise walk.
    let options = MatchOptions {
        require_literal_separator: true,
        ..MatchOptions::new()
    };
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let unreadable = |source| PatternError::Directory {
            path: dir.clone(),
            source,
        };
        for entry in fs::read_dir(&dir).map_err(unreadable)? {
            let entry = entry.map_err(unreadable)?;
            // The entry's own type: a link is not a directory here.
            let is_dir = entry.file_type().map_err(unreadable)?.is_dir();
            let path = entry.path();
            let below = path.strip_prefix(root).unwrap_or(&path);
            let path = match strip_dot {
                true => below.to_path_buf(),
                false => path.clone(),
            };
            if matches_name(pattern, below.as_os_str(), &path, options)? {
                out.push(path.clone());
            }
            if is_dir {
                stack.push(path);
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch directory for one test, emptied first.
    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("gridplan-pattern-{name}-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn names(root: &Path, found: &[PathBuf]) -> Vec<String> {
        found
            .iter()
            .map(|p| p.strip_prefix(root).unwrap().to_string_lossy().into_owned())
            .collect()
    }

    #[test]
    #[cfg(unix)]
    fn double_star_walks_directories_but_not_links_to_them() {
        let root = scratch("loop");
        fs::create_dir_all(root.join("maps/sub/deeper")).unwrap();
        for file in [
            "maps/a.map",
            "maps/sub/b.map",
            "maps/sub/deeper/c.map",
            "maps/x.txt",
        ] {
            fs::write(root.join(file), "").unwrap();
        }
        // Two links back up the tree: the `glob` crate's walk never ended here.
        std::os::unix::fs::symlink("..", root.join("maps/sub/loop")).unwrap();
        std::os::unix::fs::symlink("../..", root.join("maps/sub/deeper/up")).unwrap();
        // A link to a file is matched like the file.
        std::os::unix::fs::symlink("../a.map", root.join("maps/sub/alias.map")).unwrap();
        let found = expand(&root.join("maps/**/*.map")).unwrap();
        assert_eq!(
            names(&root, &found),
            [
                "maps/a.map",
                "maps/sub/alias.map",
                "maps/sub/b.map",
                "maps/sub/deeper/c.map"
            ]
        );
        // `*` does not cross a separator; the part before `**` may have wildcards; `.`
        // components are matched as the walk writes paths.
        let found = expand(&root.join("m*/./sub/**/*.map")).unwrap();
        assert_eq!(
            names(&root, &found),
            [
                "maps/sub/alias.map",
                "maps/sub/b.map",
                "maps/sub/deeper/c.map"
            ]
        );
        let found = expand(&root.join("maps/*.map")).unwrap();
        assert_eq!(names(&root, &found), ["maps/a.map"]);
        // A link named by a literal component is followed, as by the shell.
        let found = expand(&root.join("maps/sub/loop/*.map")).unwrap();
        assert_eq!(names(&root, &found), ["maps/sub/loop/a.map"]);
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    #[cfg(unix)]
    fn a_name_that_is_not_utf8_is_an_error_where_it_would_match() {
        use std::ffi::OsStr;
        use std::os::unix::ffi::OsStrExt;
        let root = scratch("unicode");
        // The directory's own name is not UTF-8 either: only matched names are checked.
        let dir = root.join(OsStr::from_bytes(b"latin\xe9"));
        fs::create_dir_all(dir.join("sub")).unwrap();
        for name in [&b"bad\xff.map"[..], b"ok.map", b"sub/deep.map"] {
            fs::write(dir.join(OsStr::from_bytes(name)), "").unwrap();
        }
        let bad = dir.join(OsStr::from_bytes(b"bad\xff.map"));
        for pattern in ["*.map", "b*", "**/*.map", "s*/../*.map"] {
            match expand(&dir.join(pattern)) {
                Err(PatternError::NotUnicode { path }) => {
                    assert_eq!(path.file_name(), bad.file_name(), "{pattern}")
                }
                other => panic!("{pattern}: {other:?}"),
            }
        }
        // Patterns that would not match it either way name the other files.
        assert_eq!(expand(&dir.join("o*.map")).unwrap(), [dir.join("ok.map")]);
        assert_eq!(
            expand(&dir.join("**/d*.map")).unwrap(),
            [dir.join("sub/deep.map")]
        );
        assert_eq!(expand(&dir.join("ok.map")).unwrap(), [dir.join("ok.map")]);
        // Above the last component, only directories are matched.
        assert_eq!(
            expand(&dir.join("*/deep.map")).unwrap(),
            [dir.join("sub/deep.map")]
        );
        assert_eq!(
            expand(&dir.join("none.map")).unwrap(),
            Vec::<PathBuf>::new()
        );
        let message = expand(&dir.join("*.map")).unwrap_err().to_string();
        assert!(message.ends_with("bad\u{fffd}.map matches but its name is not UTF-8; rename it"));
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn bad_patterns_are_errors() {
        assert!(matches!(
            expand(Path::new("maps/a**/*.map")),
            Err(PatternError::Pattern(_))
        ));
        assert!(matches!(
            expand(Path::new("maps/[ab.map")),
            Err(PatternError::Pattern(_))
        ));
    }
}
