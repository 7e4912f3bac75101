//! The files a config's `files` pattern names: the `glob` crate's patterns (`*`, `?`,
//! `[...]`, `**`), with one difference. `**` descends into directories only, never through a
//! link to a directory (as bash's `globstar` does since bash 4.3): the `glob` crate follows
//! such links, so one link back to a parent (`maps/sub/loop -> ..`) made a `maps/**/*.map`
//! walk endless. A link under a `**` is still matched as a file, and a link named by the
//! pattern's other components (`maps/linked/*.map`) is followed as before.
//!
//! A directory that cannot be read is an error naming it, where it used to be skipped
//! silently: an experiment over fewer maps than its config names would say nothing of it.

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
    let normalised: PathBuf = components.iter().collect();
    let text = normalised.to_string_lossy().into_owned();
    let whole = Pattern::new(&text)?;
    let mut matches = Vec::new();
    match recursive {
        None => {
            for entry in glob::glob(&text)? {
                matches.push(entry.map_err(|e| PatternError::Directory {
                    path: e.path().to_path_buf(),
                    source: e.into(),
                })?);
            }
        }
        Some(at) => {
            let head: PathBuf = match at {
                0 => PathBuf::from("."),
                _ => components[..at].iter().collect(),
            };
            // What precedes the first `**` names finitely many directories; each is walked.
            for root in expand(&head)? {
                if root.is_dir() {
                    walk(&root, at == 0, &whole, &mut matches)?;
                }
            }
        }
    }
    matches.sort();
    Ok(matches)
}

/// Adds to `out` every path below `root` that `pattern` matches, descending into
/// directories but not through links (module docs). `strip_dot`: `root` is the `.` a
/// relative pattern starting with `**` begins at, left out of the paths.
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
            let path = match strip_dot {
                true => entry
                    .path()
                    .strip_prefix(".")
                    .map_or_else(|_| entry.path(), Path::to_path_buf),
                false => entry.path(),
            };
            if pattern.matches_path_with(&path, options) {
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
