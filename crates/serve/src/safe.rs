//! The server's one way to turn a user's relative path into a file: only files under the
//! served directory are ever opened.
//!
//! A request names a file by a path relative to the served directory `DIR`. It is refused
//! ([`Refusal::Forbidden`], HTTP 403) when it is absolute, has a `..` or a root or prefix
//! component, or contains a NUL; otherwise it is joined to `DIR` and canonicalized (every
//! symlink resolved), and refused again when the result is not inside `DIR`'s own
//! canonical form (a symlink leading out). A path that does not exist is
//! [`Refusal::NotFound`] (404), and a directory where a file is asked for
//! [`Refusal::Directory`] (400). Nothing is opened before these checks pass.

use std::path::{Component, Path, PathBuf};

/// Why a path was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    /// The path leaves the served directory (absolute, `..`, or a link out of it): 403.
    #[error("{0:?}: outside the served directory")]
    Forbidden(String),
    /// No such file under the served directory: 404.
    #[error("{0:?}: no such file")]
    NotFound(String),
    /// A directory where a file is asked for: 400.
    #[error("{0:?}: is a directory, not a file")]
    Directory(String),
}

impl Refusal {
    /// The HTTP status of the refusal.
    pub fn status(&self) -> u16 {
        match self {
            Refusal::Forbidden(_) => 403,
            Refusal::NotFound(_) => 404,
            Refusal::Directory(_) => 400,
        }
    }
}

/// The served directory, canonicalized once.
#[derive(Debug, Clone)]
pub struct Root {
    canonical: PathBuf,
}

impl Root {
    /// The root at `dir` (which must exist and be a directory).
    pub fn new(dir: &Path) -> std::io::Result<Root> {
        let canonical = dir.canonicalize()?;
        if !canonical.is_dir() {
            return Err(std::io::Error::new(
                std::io::ErrorKind::NotADirectory,
                format!("{} is not a directory", dir.display()),
            ));
        }
        Ok(Root { canonical })
    }

    /// The canonical directory.
    pub fn path(&self) -> &Path {
        &self.canonical
    }

    /// The file `relative` names under the root, canonical, or why not (module docs).
    ///
    /// ```
    /// use planner_serve::safe::{Refusal, Root};
    /// let root = Root::new(std::path::Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    /// assert!(root.file("Cargo.toml").is_ok());
    /// assert!(matches!(root.file("../../Cargo.toml"), Err(Refusal::Forbidden(_))));
    /// assert!(matches!(root.file("/etc/passwd"), Err(Refusal::Forbidden(_))));
    /// assert!(matches!(root.file("nothing.map"), Err(Refusal::NotFound(_))));
    /// assert!(matches!(root.file("src"), Err(Refusal::Directory(_))));
    /// ```
    pub fn file(&self, relative: &str) -> Result<PathBuf, Refusal> {
        let path = self.inside(relative)?;
        if path.is_file() {
            Ok(path)
        } else if path.is_dir() {
            Err(Refusal::Directory(relative.to_string()))
        } else {
            Err(Refusal::NotFound(relative.to_string()))
        }
    }

    /// The directory `relative` names under the root ("" is the root itself), canonical.
    pub fn dir(&self, relative: &str) -> Result<PathBuf, Refusal> {
        if relative.is_empty() {
            return Ok(self.canonical.clone());
        }
        let path = self.inside(relative)?;
        if path.is_dir() {
            Ok(path)
        } else {
            Err(Refusal::NotFound(relative.to_string()))
        }
    }

    /// Whether an already resolved `path` lies inside the root (after canonicalizing it).
    pub fn contains(&self, path: &Path) -> bool {
        path.canonicalize()
            .is_ok_and(|p| p.starts_with(&self.canonical))
    }

    /// `path` (canonical, inside the root) relative to the root, with `/` separators;
    /// `None` outside the root or when a name on the way is not UTF-8 (the page could not
    /// ask for it: its replacement-character form names no file).
    pub fn relative(&self, path: &Path) -> Option<String> {
        let rest = path.strip_prefix(&self.canonical).ok()?;
        let parts: Option<Vec<&str>> = rest.components().map(|c| c.as_os_str().to_str()).collect();
        Some(parts?.join("/"))
    }

    fn inside(&self, relative: &str) -> Result<PathBuf, Refusal> {
        let forbidden = || Refusal::Forbidden(relative.to_string());
        if relative.is_empty() || relative.contains('\0') || relative.starts_with(['/', '\\']) {
            return Err(forbidden());
        }
        let given = Path::new(relative);
        if given.is_absolute()
            || given
                .components()
                .any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
        {
            return Err(forbidden());
        }
        let joined = self.canonical.join(given);
        let canonical = joined
            .canonicalize()
            .map_err(|_| Refusal::NotFound(relative.to_string()))?;
        if !canonical.starts_with(&self.canonical) {
            return Err(forbidden());
        }
        Ok(canonical)
    }
}
