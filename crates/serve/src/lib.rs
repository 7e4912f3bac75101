//! `gridplan serve` and the search's pictures: a local web page that plans on real maps
//! with the real planners and plays each search back ([`server`]), Posthoc search traces
//! ([`trace`]) and GIF animations ([`anim`]) of one run.
//!
//! Everything planned here goes through planner-runner, as `gridplan plan` does
//! ([`query`]), so the page's counters are `plan --json`'s for the same query. The page
//! (HTML, JavaScript, CSS under `assets/`) is embedded in the binary: no CDN, no build
//! step, works offline.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod anim;
pub mod query;
pub mod safe;
pub mod server;
pub mod trace;

pub use server::{ServeError, ServeOptions, Server};

use std::net::SocketAddr;
use std::path::{Path, PathBuf};

/// `gridplan serve`: binds, hands the address it listens on (with the chosen port when 0
/// was asked for) to `ready`, where the command line prints it, and answers until the
/// process ends. This crate prints nothing.
pub fn serve(options: &ServeOptions, ready: impl FnOnce(SocketAddr)) -> Result<(), ServeError> {
    let server = Server::bind(options)?;
    ready(server.addr().ok_or(ServeError::NoAddress)?);
    server.run();
    Ok(())
}

/// Why `plan --svg/--trace/--gif` wrote no picture.
#[derive(Debug, thiserror::Error)]
pub enum PictureError {
    /// One file named by two of the options.
    #[error("{}: given for two of --svg, --trace and --gif", path.display())]
    SameFile {
        /// The file.
        path: PathBuf,
    },
    /// The trace could not be encoded.
    #[error("search trace: {0}")]
    Trace(#[from] serde_json::Error),
    /// The animation could not be made.
    #[error("{}: {source}", path.display())]
    Gif {
        /// The file asked for.
        path: PathBuf,
        /// Why.
        source: anim::AnimError,
    },
    /// A file could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// `plan --trace FILE` and `plan --gif FILE`: writes the run's Posthoc trace and GIF
/// animation where asked (the run must have recorded its expanded cells). Refuses, before
/// writing anything, two of `svg` (which the caller writes), `trace` and `gif` naming one
/// file.
pub fn write_pictures(
    result: &planner_runner::plan::PlanResult,
    svg: Option<&Path>,
    trace: Option<&Path>,
    gif: Option<&Path>,
) -> Result<(), PictureError> {
    let outputs: Vec<&Path> = [svg, trace, gif].into_iter().flatten().collect();
    for (i, a) in outputs.iter().enumerate() {
        if outputs[i + 1..].iter().any(|b| b == a) {
            return Err(PictureError::SameFile {
                path: a.to_path_buf(),
            });
        }
    }
    let write = |file: &Path, bytes: &[u8]| {
        std::fs::write(file, bytes).map_err(|source| PictureError::Write {
            path: file.to_path_buf(),
            source,
        })
    };
    if let Some(file) = trace {
        let text = trace::plan_trace_json(result)?;
        write(file, text.as_bytes())?;
    }
    if let Some(file) = gif {
        let bytes = anim::plan_gif(result).map_err(|source| PictureError::Gif {
            path: file.to_path_buf(),
            source,
        })?;
        write(file, &bytes)?;
    }
    Ok(())
}
