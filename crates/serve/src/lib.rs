//! `gridplan serve` and the search's pictures: a local web page that plans on real maps
//! with the real planners and plays each search back ([`server`]), Posthoc search traces
//! ([`trace`]) and GIF animations ([`anim`]) of one run.
//!
//! Everything planned here goes through planner-runner, as `gridplan plan` does
//! ([`query`]), so the page's counters are `plan --json`'s for the same query. The page
//! (HTML, JavaScript, CSS under `assets/`) is embedded in the binary: no CDN, no build
//! step, works offline. A results directory's runs are drawn only on the map [`located`]
//! finds for them under the served directory (the one the config that ran read, else
//! the one map file of their map's name), and not at all when it is ambiguous.
//!
//! The server answers each connection on a thread of its own, so an idle or slow client
//! delays no other; its limits ([`server`]'s docs) bound the threads and memory: at most
//! 128 connections open (503 beyond), 10 s for a request head and 30 s for its body
//! (idle connections are closed, slow ones answered 408), 16 KiB heads, 8 MiB bodies, two
//! plans running at once.
#![deny(missing_docs)]
#![cfg_attr(not(test), warn(clippy::unwrap_used))]

pub mod anim;
pub mod located;
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
    /// A picture would replace one of the run's input files.
    #[error("{}: names {}, which the run reads; a picture there would replace it", path.display(), input.display())]
    Input {
        /// The picture's file as given.
        path: PathBuf,
        /// The input it names.
        input: PathBuf,
    },
    /// The path is a device, a named pipe or a socket (or a link to one): a picture replaces
    /// its file whole, and would put a regular file in its place.
    #[error("{}: is {what}, not a file; a picture is written to a regular file, new or replaced whole", path.display())]
    NotAFile {
        /// The picture's file as given.
        path: PathBuf,
        /// What it is, e.g. `a character device`.
        what: &'static str,
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

/// The pictures `plan` writes: the figure's SVG text with its file, the Posthoc trace's
/// file and the GIF's.
#[derive(Debug, Clone, Copy, Default)]
pub struct Pictures<'a> {
    /// `--svg FILE` and the figure drawn for it.
    pub svg: Option<(&'a Path, &'a str)>,
    /// `--trace FILE`.
    pub trace: Option<&'a Path>,
    /// `--gif FILE`.
    pub gif: Option<&'a Path>,
}

impl Pictures<'_> {
    fn files(&self) -> Vec<&Path> {
        [self.svg.map(|(file, _)| file), self.trace, self.gif]
            .into_iter()
            .flatten()
            .collect()
    }
}

/// Refuses, before anything is run or written, two of `files` that name one directory
/// entry (`x.svg` and `./x.svg` too), a file that names one of `inputs` (its entry, or
/// the file a link there leads to): writing the picture would replace the user's map or
/// configuration; and a device, named pipe or socket, or a link to one (`/dev/null`,
/// `/dev/stdout`): the picture would replace it with a regular file.
pub fn check_picture_files(files: &[&Path], inputs: &[PathBuf]) -> Result<(), PictureError> {
    for file in files {
        // The entry itself, then what a link there leads to.
        for metadata in [std::fs::symlink_metadata(file), std::fs::metadata(file)] {
            if let Some(what) = metadata.ok().and_then(|m| special(&m.file_type())) {
                return Err(PictureError::NotAFile {
                    path: file.to_path_buf(),
                    what,
                });
            }
        }
    }
    let entries: Vec<PathBuf> = files.iter().map(|f| entry(f)).collect();
    for (i, a) in entries.iter().enumerate() {
        if entries[i + 1..].contains(a) {
            return Err(PictureError::SameFile {
                path: files[i].to_path_buf(),
            });
        }
        for input in inputs {
            let resolved = input.canonicalize().ok();
            if *a == entry(input) || resolved.as_ref() == Some(a) {
                return Err(PictureError::Input {
                    path: files[i].to_path_buf(),
                    input: input.clone(),
                });
            }
        }
    }
    Ok(())
}

/// What a file of type `kind` is when it is neither a regular file, a directory nor a link.
fn special(kind: &std::fs::FileType) -> Option<&'static str> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt as _;
        let what = [
            (kind.is_char_device(), "a character device"),
            (kind.is_block_device(), "a block device"),
            (kind.is_fifo(), "a named pipe"),
            (kind.is_socket(), "a socket"),
        ];
        what.into_iter().find(|(is, _)| *is).map(|(_, what)| what)
    }
    #[cfg(not(unix))]
    {
        (!kind.is_file() && !kind.is_dir() && !kind.is_symlink()).then_some("not a regular file")
    }
}

/// The directory entry `path` names: its directory with the links in it resolved, and its
/// own name (a link there is not followed: a picture replaces the link, not what it leads
/// to). The path as given when its directory cannot be resolved.
fn entry(path: &Path) -> PathBuf {
    let (Some(name), dir) = (path.file_name(), path.parent()) else {
        return path.to_path_buf();
    };
    let dir = match dir {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    dir.canonicalize()
        .map_or_else(|_| path.to_path_buf(), |dir| dir.join(name))
}

/// [`planner_maps::write_whole`] with the picture's error.
fn write_whole(file: &Path, bytes: &[u8]) -> Result<(), PictureError> {
    planner_maps::write_whole(file, bytes).map_err(|source| PictureError::Write {
        path: file.to_path_buf(),
        source,
    })
}

/// `plan --svg FILE`, `--trace FILE` and `--gif FILE`: writes the run's figure, Posthoc
/// trace and GIF animation where asked (the run must have recorded its expanded cells for
/// the last two), each whole or not at all. Refuses, before writing anything, what
/// [`check_picture_files`] refuses.
pub fn write_pictures(
    result: &planner_runner::plan::PlanResult,
    pictures: &Pictures<'_>,
    inputs: &[PathBuf],
) -> Result<(), PictureError> {
    check_picture_files(&pictures.files(), inputs)?;
    if let Some((file, svg)) = pictures.svg {
        write_whole(file, svg.as_bytes())?;
    }
    if let Some(file) = pictures.trace {
        let text = trace::plan_trace_json(result)?;
        write_whole(file, text.as_bytes())?;
    }
    if let Some(file) = pictures.gif {
        let bytes = anim::plan_gif(result).map_err(|source| PictureError::Gif {
            path: file.to_path_buf(),
            source,
        })?;
        write_whole(file, &bytes)?;
    }
    Ok(())
}
