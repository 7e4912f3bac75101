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

use std::path::Path;

/// Writes seed 002's generated maps ([`planner_pastar::generate::specs`]) to `dir` as
/// Moving AI `.map` files; returns the paths.
pub fn write_pastar_maps(dir: &Path) -> Result<Vec<String>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut written = Vec::new();
    for map in planner_pastar::generate::specs() {
        let path = dir.join(map.name);
        std::fs::write(&path, planner_maps::to_movingai(&map.grid))
            .map_err(|e| format!("{}: {e}", path.display()))?;
        written.push(path.display().to_string());
    }
    Ok(written)
}
