//! `cargo xtask`: the repository's own tasks, beside the `gridplan` command line it forwards
//! (crates/cli).
//!
//! The runner (configs, registry, sweeps, results directories, reports) is the
//! `planner-runner` library and the user commands are the `gridplan` crate's; this crate
//! adds the repository's tasks: `new-planner` ([`scaffold`]) and `gen-pastar-maps`
//! ([`write_pastar_maps`]).
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod scaffold;

use std::path::{Path, PathBuf};

/// A file or directory that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct WriteError {
    /// The path.
    pub path: PathBuf,
    /// Why.
    pub source: std::io::Error,
}

/// Writes seed 002's generated maps ([`planner_pastar::generate::specs`]) to `dir` as
/// Moving AI `.map` files; returns the paths.
pub fn write_pastar_maps(dir: &Path) -> Result<Vec<String>, WriteError> {
    let failed = |path: &Path| {
        let path = path.to_path_buf();
        move |source| WriteError { path, source }
    };
    std::fs::create_dir_all(dir).map_err(failed(dir))?;
    let mut written = Vec::new();
    for map in planner_pastar::generate::specs() {
        let path = dir.join(map.name);
        planner_maps::write_whole(&path, planner_maps::to_movingai(&map.grid).as_bytes())
            .map_err(failed(&path))?;
        written.push(path.display().to_string());
    }
    Ok(written)
}
