//! The results directory: when gridplan may replace it, the lock that keeps two runs apart,
//! and the atomic swap of old results for new ones.
//!
//! [`write_results`] writes a sweep's files as the whole new contents of an output directory
//! `dir` under these rules:
//!
//! - **Only gridplan's own directories are replaced.** Every results directory carries a
//!   marker file, [`MARKER`] (`.gridplan-results`, a small TOML [`Marker`]: format version,
//!   experiment name, gridplan version, and since 2026-12-07 every file written beside it).
//!   `dir` is replaced only if it is absent, empty, or carries the marker (a regular file of
//!   that name). Anything else is [`OutdirError::NotResults`], which names the directory and
//!   what it holds, and nothing is touched. A results directory written before the marker
//!   existed is refused the same way: remove it by hand once.
//! - **Nothing added to the results is lost.** A marker that lists its files lets `dir` be
//!   replaced only when every entry in it (links not followed) is a listed file, a directory
//!   holding one, or the marker: anything else, such as notes the user saved beside
//!   `runs.csv` or a figure of their own in `figures/`, is [`OutdirError::UnlistedFiles`],
//!   naming the first of them, and nothing is touched. A file an earlier run wrote is
//!   listed by that run's marker, so results of a changed config are replaced as before; a
//!   marker written before the listing (or unreadable) lets the directory be replaced whole.
//! - **Not a directory.** A file (or anything else that is not a directory) at `dir` is
//!   [`OutdirError::NotADirectory`]; it is left as it is.
//! - **Symbolic links are written through.** If `dir` is a symbolic link to a directory, the
//!   link stays and its target directory is replaced under the same rules (it must be absent,
//!   empty or marked; the lock and the temporary siblings live beside the target). A link to
//!   a file is [`OutdirError::NotADirectory`], a dangling link
//!   [`OutdirError::DanglingSymlink`].
//! - **Read-only directories are refused.** If `dir`, or any directory inside it, has no
//!   write permission bit (for anyone), the run is [`OutdirError::ReadOnly`] and nothing is
//!   touched. The rule reads the permission bits, so it holds for root too, whom the bits
//!   would not stop.
//! - **Mount points are refused.** A `dir` that is a mount point (a bind mount, a
//!   container's volume `--output /results`) cannot be renamed, so it can never be swapped:
//!   it is [`OutdirError::MountPoint`], before anything runs or is written, with the hint
//!   to write to a directory inside it. A mount point is a directory the kernel calls a
//!   mount's root (statx's `STATX_ATTR_MOUNT_ROOT`), or where the kernel does not say,
//!   one whose device differs from its parent's.
//! - **Missing parents are created**, as `mkdir -p` would (creating a directory destroys
//!   nothing). A file among the parents is an [`OutdirError::Io`] naming the output ("Not a
//!   directory"), and nothing is created.
//! - **One writer at a time.** The write holds an exclusive OS file lock (flock) on
//!   `.<name>.lock` beside the directory, taken before anything is written and released (and
//!   the file removed) when the write ends. Lock files are opened without following
//!   symbolic links (`O_NOFOLLOW`): a link planted at a lock's name (in a shared parent
//!   directory, say) is [`OutdirError::LinkedLock`], and the file it points to is never
//!   opened, truncated or written. The kernel drops the lock of a process that dies,
//!   so a crashed run never leaves a lock that blocks the next one; a leftover lock file is
//!   simply locked again. A second run on the same directory waits for the lock, saying so
//!   on the log (`tracing::warn!`), for at most the `lock_wait` it is given
//!   ([`DEFAULT_LOCK_WAIT`] from `cargo xtask experiment`), then fails with
//!   [`OutdirError::Locked`] naming the holder's pid (the lock file holds the pid its
//!   binary gave [`set_lock_holder`]: the runner reads no process state). Two runs therefore both succeed, one
//!   after the other, and the directory ends holding the later one's complete results.
//!   A sweep waiting for the stream area's lock ([`stream_area_stoppable`]) stops waiting
//!   as soon as its stop flag is raised (Ctrl-C, SIGTERM): [`OutdirError::Stopped`], and
//!   nothing is created or left beside the output.
//! - **The swap is atomic.** The files are written into a fresh sibling `.<name>.partial`
//!   (its marker first), which then takes the place of `dir`. On Linux the two directories
//!   are exchanged by one `renameat2(RENAME_EXCHANGE)` system call, so at every moment `dir`
//!   holds either the old results or the new ones, whatever kills the process; the old
//!   results, now under `.<name>.partial`, are then removed. Where the exchange is not
//!   supported, the old directory is renamed to `.<name>.previous` and the new one into
//!   place: a kill between the two renames leaves the old results under `.<name>.previous`,
//!   and the next run puts them back before doing anything else.
//! - **Leftovers are cleaned, never foreign files.** Under the lock, a `.<name>.partial` or
//!   `.<name>.previous` left by a killed run is recognised by its marker (or by being empty,
//!   as it is for an instant after creation; gridplan writes the marker first and removes it
//!   last, so a kill while writing or removing leaves it in place) and removed (or, for `.<name>.previous` with no
//!   `dir`, restored). One that is not gridplan's is [`OutdirError::ForeignLeftover`] and
//!   stays. If removing the old results after a successful swap fails, the run still
//!   succeeds (the new results are in place) and warns; the next run removes them.
//! - **Side files fit a file name.** The locks, the stream area and the temporary siblings
//!   are named `.<name>.<suffix>`; where that would pass 255 bytes (a directory name of
//!   about 240 bytes or more), `<name>` is cut to fit and followed by `-` and 16 hex digits
//!   of its SHA-256, so an output with a long name keeps side files of its own, the same
//!   ones for every run on it (`--resume` included).
//!
//! [`check`] applies the same rules without writing anything (a lock file planted as a link
//! included), so a sweep can refuse a bad output directory before it spends time computing.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, Read as _, Write as _};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

/// The marker file's name inside every results directory gridplan writes.
pub const MARKER: &str = ".gridplan-results";

/// The marker file's name inside every stream area (`.<name>.stream/`) gridplan creates;
/// only a stream area carrying it is written into or removed.
pub const STREAM_MARKER: &str = ".gridplan-stream";

/// The version of the results layout the marker records.
pub const FORMAT_VERSION: u32 = 1;

/// How long `cargo xtask experiment` waits for another run's lock on the same output.
pub const DEFAULT_LOCK_WAIT: Duration = Duration::from_secs(120);

/// How often a waiting run tries the lock again.
const LOCK_POLL: Duration = Duration::from_millis(50);

pub use crate::output::{OutputFile, StreamedFile};

/// The contents of [`MARKER`]: which gridplan wrote the directory, and for which experiment.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Marker {
    /// The results layout version, [`FORMAT_VERSION`] when written.
    pub format: u32,
    /// The experiment's `name`.
    pub experiment: String,
    /// The gridplan version that wrote the directory.
    pub gridplan: String,
    /// Every file gridplan wrote there, relative to it (`/`-separated), but the marker;
    /// absent in markers written before 2026-12-07, whose directories are replaced without
    /// this check.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub files: Option<Vec<String>>,
}

impl Marker {
    /// The marker this gridplan writes for `experiment`.
    pub fn new(experiment: &str) -> Self {
        Self {
            format: FORMAT_VERSION,
            experiment: experiment.to_string(),
            gridplan: env!("CARGO_PKG_VERSION").to_string(),
            files: None,
        }
    }

    /// [`Marker::new`] listing `files`, the paths written beside the marker.
    pub fn listing(experiment: &str, files: &[&Path]) -> Self {
        let mut names: Vec<String> = files.iter().map(|path| relative_name(path)).collect();
        names.sort();
        Self {
            files: Some(names),
            ..Self::new(experiment)
        }
    }

    /// Reads the marker of results directory `dir`.
    pub fn read(dir: &Path) -> Result<Self, OutdirError> {
        let path = dir.join(MARKER);
        let text = fs::read_to_string(&path).map_err(io_error("read", &path))?;
        toml::from_str(&text).map_err(|e| OutdirError::BadMarker {
            path,
            message: e.message().to_string(),
        })
    }

    fn to_text(&self) -> String {
        let quoted = |text: &str| toml::Value::String(text.to_string()).to_string();
        let mut text = format!(
            "# Written by gridplan: this directory holds an experiment's results, and the next\n\
             # run writing here replaces it whole, unless it holds files gridplan did not write\n\
             # (those `files` does not list). Remove this file and gridplan leaves it alone.\n\
             format = {}\nexperiment = {}\ngridplan = {}\n",
            self.format,
            quoted(&self.experiment),
            quoted(&self.gridplan)
        );
        if let Some(files) = &self.files {
            text.push_str("files = [\n");
            for file in files {
                text.push_str("    ");
                text.push_str(&quoted(file));
                text.push_str(",\n");
            }
            text.push_str("]\n");
        }
        text
    }
}

/// `path`'s components joined by `/` (lossily for a name that is not UTF-8), as a marker
/// lists the files.
fn relative_name(path: &Path) -> String {
    path.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

/// The entries of results directory `dir` that its marker does not list (at most `limit`,
/// the outermost of a foreign tree only, sorted), or none when the marker lists no files
/// (an older one) or cannot be read. A directory is listed when a listed file lies in it.
fn unlisted_entries(dir: &Path, limit: usize) -> Result<Vec<String>, OutdirError> {
    let Some(files) = Marker::read(dir).ok().and_then(|marker| marker.files) else {
        return Ok(Vec::new());
    };
    let files: std::collections::BTreeSet<String> = files.into_iter().collect();
    let mut found = Vec::new();
    let mut pending = vec![PathBuf::new()];
    'walk: while let Some(relative) = pending.pop() {
        let here = dir.join(&relative);
        let mut entries: Vec<_> = fs::read_dir(&here)
            .map_err(io_error("list", &here))?
            .collect::<Result<_, _>>()
            .map_err(io_error("list", &here))?;
        entries.sort_by_key(fs::DirEntry::file_name);
        for entry in entries {
            let path = relative.join(entry.file_name());
            let name = relative_name(&path);
            if name == MARKER {
                continue;
            }
            let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
            let prefix = format!("{name}/");
            let listed = if is_dir {
                files
                    .range(prefix.clone()..)
                    .next()
                    .is_some_and(|f| f.starts_with(&prefix))
            } else {
                files.contains(&name)
            };
            if !listed {
                found.push(if is_dir { prefix } else { name });
                if found.len() == limit {
                    break 'walk;
                }
            } else if is_dir {
                pending.push(path);
            }
        }
    }
    found.sort();
    Ok(found)
}

/// Why an output directory was not written. Each names the path concerned.
#[derive(Debug, thiserror::Error)]
pub enum OutdirError {
    /// The path names no directory (empty, `/`, or ending in `..`).
    #[error("output directory `{}` has no name: give one such as results/mine", path.display())]
    NoName {
        /// The path given.
        path: PathBuf,
    },
    /// Something other than a directory is at the path.
    #[error(
        "output `{}` is {what}, not a directory; gridplan writes results only into a directory \
         and leaves this one alone (choose another output directory)",
        path.display()
    )]
    NotADirectory {
        /// The path given.
        path: PathBuf,
        /// What is there, e.g. "a file".
        what: &'static str,
    },
    /// A symbolic link whose target does not exist.
    #[error(
        "output `{}` is a symbolic link to `{}`, which does not exist; create that directory \
         or choose another output directory",
        path.display(), target.display()
    )]
    DanglingSymlink {
        /// The path given.
        path: PathBuf,
        /// The link's target.
        target: PathBuf,
    },
    /// A directory that holds something and no marker.
    #[error(
        "output `{}` is not a gridplan results directory: it holds {entries} and no `{MARKER}` \
         marker, so gridplan will not replace it (choose another output directory, or empty or remove \
         it yourself)",
        path.display()
    )]
    NotResults {
        /// The directory.
        path: PathBuf,
        /// What it holds, e.g. "2 entries (chapters, thesis.tex)".
        entries: String,
    },
    /// A results directory holding files that gridplan did not write there.
    #[error(
        "output `{}` holds what gridplan did not write there ({names}), so gridplan will not \
         replace it and lose them: move them out first, or write elsewhere",
        path.display()
    )]
    UnlistedFiles {
        /// The directory.
        path: PathBuf,
        /// The first of them, e.g. "notes.txt, mine/".
        names: String,
    },
    /// The results directory, or a directory inside it, has no write permission.
    #[error(
        "output `{}` is read-only: directory `{}` has no write permission, so gridplan will not \
         replace it; make it writable or choose another output directory",
        path.display(), dir.display()
    )]
    ReadOnly {
        /// The output directory.
        path: PathBuf,
        /// The read-only directory (the output or one inside it).
        dir: PathBuf,
    },
    /// A `.<name>.partial` or `.<name>.previous` that gridplan did not make.
    #[error(
        "`{}` is in the way of writing `{}` but is not gridplan's (not a directory with a \
         `{MARKER}` marker), so gridplan leaves it alone; move or remove it yourself",
        path.display(), output.display()
    )]
    ForeignLeftover {
        /// The sibling in the way.
        path: PathBuf,
        /// The output directory.
        output: PathBuf,
    },
    /// Another run kept the lock longer than the wait allowed.
    #[error(
        "output `{}` is being written by another gridplan run{holder} (it holds `{}`); gave up \
         after waiting {seconds} s",
        path.display(), lock.display()
    )]
    Locked {
        /// The output directory.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// " (pid N)" when the lock file names its holder, else empty.
        holder: String,
        /// Seconds waited.
        seconds: u64,
    },
    /// A lock file that is a symbolic link (never followed).
    #[error(
        "lock file `{}` of output `{}` is a symbolic link; gridplan does not follow links \
         to its lock files (the file it points to is left untouched): remove the link",
        lock.display(), path.display()
    )]
    LinkedLock {
        /// The output directory.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
    },
    /// The output directory is a mount point (a bind mount, a container's volume): the
    /// atomic swap renames the directory, which the system refuses for a mount point.
    #[error(
        "output `{}` is a mount point, which cannot be swapped atomically (gridplan replaces \
         its output directory by renaming a new one into its place); write to a directory \
         inside it, e.g. {}",
        path.display(), path.join("results").display()
    )]
    MountPoint {
        /// The output directory.
        path: PathBuf,
    },
    /// The stop flag (Ctrl-C, SIGTERM) was raised while waiting for another run's lock.
    #[error(
        "stopped while waiting for another gridplan run's lock `{}` on output `{}`; nothing \
         was written",
        lock.display(), path.display()
    )]
    Stopped {
        /// The output directory.
        path: PathBuf,
        /// The lock file.
        lock: PathBuf,
    },
    /// A file of the stream area that is a symbolic link (never followed).
    #[error(
        "`{}` is a symbolic link; gridplan does not follow links in its stream directory \
         (the file it points to is left untouched): remove the link",
        path.display()
    )]
    LinkedStream {
        /// The link.
        path: PathBuf,
    },
    /// A `.<name>.stream` that gridplan did not make.
    #[error(
        "`{}` is in the way of the sweep's stream area for `{}` but is not gridplan's (not a \
         directory with a `{STREAM_MARKER}` marker), so gridplan neither writes into it nor \
         removes it; move or remove it yourself",
        path.display(), output.display()
    )]
    ForeignStream {
        /// The stream directory in the way.
        path: PathBuf,
        /// The output directory.
        output: PathBuf,
    },
    /// A `DIR-slurm` working directory that gridplan did not make.
    #[error(
        "`{}` is in the way of the Slurm scripts for `{}` but is not gridplan's (not an empty \
         directory or one with a `{marker}` marker), so gridplan neither writes into it nor \
         removes it; move or remove it yourself, or choose another output directory",
        path.display(), output.display()
    )]
    ForeignWorkDir {
        /// The directory in the way.
        path: PathBuf,
        /// The output directory.
        output: PathBuf,
        /// The marker it lacks.
        marker: &'static str,
    },
    /// A merge's output that is one of its input shards (or holds one): writing it would
    /// replace the shard, so the shard set could never be merged again.
    #[error(
        "output `{}` {relation} the shard directory `{}` given to merge (resolved: `{}`); \
         writing the merged results there would replace that shard: choose another output \
         directory",
        path.display(), shard.display(), resolved.display()
    )]
    InputShard {
        /// The output directory.
        path: PathBuf,
        /// The input shard's directory.
        shard: PathBuf,
        /// "is", or "holds" when the shard is inside the output.
        relation: &'static str,
        /// The directory both name, resolved (links followed).
        resolved: PathBuf,
    },
    /// A result file path that is not a plain relative path, or is the marker's.
    #[error(
        "result file `{}` must be a relative path of plain names other than `{MARKER}`",
        path.display()
    )]
    BadFile {
        /// The file's path.
        path: PathBuf,
    },
    /// A marker file that is not a marker.
    #[error("marker `{}` is not a gridplan marker: {message}", path.display())]
    BadMarker {
        /// The marker file.
        path: PathBuf,
        /// The parse error.
        message: String,
    },
    /// A file system operation failed.
    #[error("cannot {action} `{}`: {source}", path.display())]
    Io {
        /// What was being done, e.g. "create".
        action: &'static str,
        /// The path it was done to.
        path: PathBuf,
        /// The error.
        #[source]
        source: io::Error,
    },
}

fn io_error(action: &'static str, path: &Path) -> impl FnOnce(io::Error) -> OutdirError {
    let path = path.to_path_buf();
    move |source| OutdirError::Io {
        action,
        path,
        source,
    }
}

/// Checks that `output` is none of the directories `inputs` (a merge's shards) and holds
/// none of them, by canonical path (links followed), so that writing it replaces no input.
/// An output that does not exist yet is none of them.
pub fn check_not_input(output: &Path, inputs: &[PathBuf]) -> Result<(), OutdirError> {
    let Ok(resolved) = fs::canonicalize(output) else {
        return Ok(());
    };
    for input in inputs {
        let Ok(shard) = fs::canonicalize(input) else {
            continue;
        };
        let relation = match shard == resolved {
            true => "is",
            false if shard.starts_with(&resolved) => "holds",
            false => continue,
        };
        return Err(OutdirError::InputShard {
            path: output.to_path_buf(),
            shard: input.clone(),
            relation,
            resolved: shard,
        });
    }
    Ok(())
}

/// Checks that `output` may be written by [`write_results`], without writing anything:
/// the directory rules of the module docs, and the leftovers beside it.
pub fn check(output: &Path) -> Result<(), OutdirError> {
    let location = locate(output, false)?;
    inspect(&location)?;
    for suffix in ["lock", "stream.lock"] {
        let lock = location.sibling(suffix);
        if fs::symlink_metadata(&lock).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(OutdirError::LinkedLock {
                path: location.output.clone(),
                lock,
            });
        }
    }
    for leftover in [location.sibling("partial"), location.sibling("previous")] {
        if exists(&leftover) {
            ensure_ours(&leftover, &location)?;
        }
    }
    Ok(())
}

/// Writes `files` as the whole new contents of `output`, marked as results of `experiment`,
/// under the rules of the module docs; waits at most `lock_wait` for another run's lock.
/// Returns the directory written: `output` itself, or a symbolic link's target.
pub fn write_results(
    output: &Path,
    experiment: &str,
    files: &[OutputFile],
    lock_wait: Duration,
) -> Result<PathBuf, OutdirError> {
    write_results_streamed(output, experiment, files, &[], lock_wait)
}

/// [`write_results`] with, besides `files`, the `streamed` files, each written by its
/// function straight into the new directory through a buffered writer (so a large
/// table is never held whole); a function's error fails the write like an I/O error.
pub fn write_results_streamed(
    output: &Path,
    experiment: &str,
    files: &[OutputFile],
    streamed: &[StreamedFile<'_>],
    lock_wait: Duration,
) -> Result<PathBuf, OutdirError> {
    for path in files
        .iter()
        .map(|f| &f.path)
        .chain(streamed.iter().map(|f| &f.path))
    {
        let plain = path.components().all(|c| matches!(c, Component::Normal(_)));
        if !plain || path.as_os_str().is_empty() || path == Path::new(MARKER) {
            return Err(OutdirError::BadFile { path: path.clone() });
        }
    }
    let location = locate(output, true)?;
    inspect(&location)?;
    let _lock = OutputLock::acquire(&location, lock_wait)?;
    recover_leftovers(&location)?;
    // Looked at again under the lock: another run may have written it meanwhile.
    inspect(&location)?;
    let partial = location.sibling("partial");
    // On failure the partial results go, but only if they are still recognisably ours.
    let discard = |_: &OutdirError| {
        if exists(&partial) && ensure_ours(&partial, &location).is_ok() {
            let _ = remove_results(&partial);
        }
    };
    write_partial(&partial, experiment, files, streamed).inspect_err(discard)?;
    swap(&location, cfg!(target_os = "linux")).inspect_err(discard)?;
    Ok(location.dir)
}

/// Where the results go, once links are followed.
struct Location {
    /// The path as given, for messages.
    output: PathBuf,
    /// The directory to replace (a link's target; absolute when it or its parent exists).
    dir: PathBuf,
    /// Its parent, where the lock and the temporary siblings live.
    parent: PathBuf,
    /// Its file name.
    name: OsString,
}

/// The longest file name gridplan gives its side files, in bytes: Linux's `NAME_MAX`, the
/// limit of most file systems.
const MAX_FILE_NAME: usize = 255;

impl Location {
    /// `.<name>.<suffix>` beside the directory. When that is longer than
    /// [`MAX_FILE_NAME`] bytes (a directory name of about 240 bytes or more), `<name>` is
    /// cut to fit and followed by `-` and 16 hex digits of its SHA-256, so the file is
    /// still the output's own and the same one for every run on it.
    fn sibling(&self, suffix: &str) -> PathBuf {
        let mut name = OsString::from(".");
        name.push(&self.name);
        name.push(".");
        name.push(suffix);
        if name.len() > MAX_FILE_NAME {
            let hash = crate::provenance::sha256_hex(self.name.as_encoded_bytes());
            let hash = hash.get(..16).unwrap_or(&hash);
            let mut kept = self.name.to_string_lossy().into_owned();
            let room = MAX_FILE_NAME - ".-.".len() - hash.len() - suffix.len();
            while kept.len() > room {
                kept.pop();
            }
            name = OsString::from(format!(".{kept}-{hash}.{suffix}"));
        }
        self.parent.join(name)
    }
}

/// Whether anything, even a dangling link, is at `path`.
fn exists(path: &Path) -> bool {
    fs::symlink_metadata(path).is_ok()
}

/// Follows `output` to the directory to replace; creates missing parents if `create`.
fn locate(output: &Path, create: bool) -> Result<Location, OutdirError> {
    let no_name = || OutdirError::NoName {
        path: output.to_path_buf(),
    };
    if output.as_os_str().is_empty() {
        return Err(no_name());
    }
    let metadata = match fs::symlink_metadata(output) {
        Ok(metadata) => metadata,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            let name = output.file_name().ok_or_else(no_name)?.to_os_string();
            let parent = match output.parent() {
                Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
                _ => PathBuf::from("."),
            };
            if create {
                fs::create_dir_all(&parent).map_err(io_error("create the parent of", output))?;
            }
            // A parent still missing (when checking only) is created by the write.
            let parent = fs::canonicalize(&parent).unwrap_or(parent);
            return Ok(Location {
                output: output.to_path_buf(),
                dir: parent.join(&name),
                parent,
                name,
            });
        }
        Err(e) => return Err(io_error("read", output)(e)),
    };
    let what_else = |metadata: &fs::Metadata| {
        if metadata.is_file() {
            "a file"
        } else {
            "a special file"
        }
    };
    if metadata.file_type().is_symlink() {
        match fs::metadata(output) {
            Ok(target) if target.is_dir() => {}
            Ok(target) => {
                return Err(OutdirError::NotADirectory {
                    path: output.to_path_buf(),
                    what: if target.is_file() {
                        "a symbolic link to a file"
                    } else {
                        "a symbolic link to a special file"
                    },
                })
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                return Err(OutdirError::DanglingSymlink {
                    path: output.to_path_buf(),
                    target: fs::read_link(output).map_err(io_error("read the link", output))?,
                })
            }
            Err(e) => return Err(io_error("follow the link", output)(e)),
        }
    } else if !metadata.is_dir() {
        return Err(OutdirError::NotADirectory {
            path: output.to_path_buf(),
            what: what_else(&metadata),
        });
    }
    let dir = fs::canonicalize(output).map_err(io_error("resolve", output))?;
    let (Some(parent), Some(name)) = (dir.parent(), dir.file_name()) else {
        return Err(no_name());
    };
    Ok(Location {
        output: output.to_path_buf(),
        parent: parent.to_path_buf(),
        name: name.to_os_string(),
        dir,
    })
}

/// Whether the directory `dir` carries the marker or is empty.
fn marked_or_empty(dir: &Path) -> Result<bool, OutdirError> {
    if fs::symlink_metadata(dir.join(MARKER)).is_ok_and(|m| m.is_file()) {
        return Ok(true);
    }
    let mut entries = fs::read_dir(dir).map_err(io_error("list", dir))?;
    Ok(entries.next().is_none())
}

/// Checks that the directory to replace is absent, or empty or marked, and writable.
fn inspect(location: &Location) -> Result<(), OutdirError> {
    let dir = &location.dir;
    if !fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir()) {
        // Absent (`locate` refused anything else; a race is caught by the renames).
        return Ok(());
    }
    if mount_point(dir, &location.parent)? {
        return Err(OutdirError::MountPoint {
            path: location.output.clone(),
        });
    }
    if !marked_or_empty(dir)? {
        let mut names: Vec<String> = fs::read_dir(dir)
            .map_err(io_error("list", dir))?
            .filter_map(Result::ok)
            .map(|entry| entry.file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        let shown: Vec<&str> = names.iter().take(3).map(String::as_str).collect();
        let more = if names.len() > shown.len() {
            ", ..."
        } else {
            ""
        };
        let count = match names.len() {
            1 => "1 entry".to_string(),
            n => format!("{n} entries"),
        };
        return Err(OutdirError::NotResults {
            path: location.output.clone(),
            entries: format!("{count} ({}{more})", shown.join(", ")),
        });
    }
    let unlisted = unlisted_entries(dir, 4)?;
    if !unlisted.is_empty() {
        let mut names = unlisted
            .iter()
            .take(3)
            .cloned()
            .collect::<Vec<_>>()
            .join(", ");
        if unlisted.len() > 3 {
            names.push_str(", ...");
        }
        return Err(OutdirError::UnlistedFiles {
            path: location.output.clone(),
            names,
        });
    }
    if let Some(read_only) = read_only_dir(dir)? {
        return Err(OutdirError::ReadOnly {
            path: location.output.clone(),
            dir: read_only,
        });
    }
    Ok(())
}

/// Whether the directory `dir` (no link) is a mount point, `parent` being its parent.
#[cfg(unix)]
fn mount_point(dir: &Path, parent: &Path) -> Result<bool, OutdirError> {
    use std::os::unix::fs::MetadataExt as _;
    let dev = fs::symlink_metadata(dir)
        .map_err(io_error("read", dir))?
        .dev();
    let parent_dev = fs::metadata(parent)
        .map_err(io_error("read", parent))?
        .dev();
    Ok(is_mount_root(dev, parent_dev, statx_mount_root(dir)))
}

/// Whether the directory `dir` is a mount point (not known here: no).
#[cfg(not(unix))]
fn mount_point(_dir: &Path, _parent: &Path) -> Result<bool, OutdirError> {
    Ok(false)
}

/// Whether a directory is the root of a mount: what the kernel says where it says it
/// (`mount_root`, statx's `STATX_ATTR_MOUNT_ROOT`, Linux 5.8 and later: also a bind mount
/// of a directory of the same file system, whose device is its parent's; a btrfs
/// subvolume, whose device differs, is no mount), else whether its device (`dev`) differs
/// from its parent's (`parent_dev`: another file system is mounted there).
fn is_mount_root(dev: u64, parent_dev: u64, mount_root: Option<bool>) -> bool {
    mount_root.unwrap_or(dev != parent_dev)
}

/// `STATX_ATTR_MOUNT_ROOT` of `dir` (links not followed), if the kernel reports it.
#[cfg(target_os = "linux")]
fn statx_mount_root(dir: &Path) -> Option<bool> {
    use rustix::fs::{statx, AtFlags, StatxAttributes, StatxFlags, CWD};
    let flags = AtFlags::NO_AUTOMOUNT | AtFlags::SYMLINK_NOFOLLOW;
    let found = statx(CWD, dir, flags, StatxFlags::empty()).ok()?;
    let known = found
        .stx_attributes_mask
        .contains(StatxAttributes::MOUNT_ROOT);
    known.then(|| found.stx_attributes.contains(StatxAttributes::MOUNT_ROOT))
}

/// Not known outside Linux.
#[cfg(not(target_os = "linux"))]
fn statx_mount_root(_dir: &Path) -> Option<bool> {
    None
}

/// The first directory in the tree at `dir` (links not followed) with no write permission.
fn read_only_dir(dir: &Path) -> Result<Option<PathBuf>, OutdirError> {
    let metadata = fs::symlink_metadata(dir).map_err(io_error("read", dir))?;
    if metadata.permissions().readonly() {
        return Ok(Some(dir.to_path_buf()));
    }
    for entry in fs::read_dir(dir).map_err(io_error("list", dir))? {
        let entry = entry.map_err(io_error("list", dir))?;
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            if let Some(found) = read_only_dir(&entry.path())? {
                return Ok(Some(found));
            }
        }
    }
    Ok(None)
}

/// Refuses a leftover sibling that is not a real directory carrying the marker or empty.
fn ensure_ours(leftover: &Path, location: &Location) -> Result<(), OutdirError> {
    let is_dir = fs::symlink_metadata(leftover).is_ok_and(|m| m.is_dir());
    if is_dir && marked_or_empty(leftover)? {
        Ok(())
    } else {
        Err(OutdirError::ForeignLeftover {
            path: leftover.to_path_buf(),
            output: location.output.clone(),
        })
    }
}

/// Puts back or removes what a killed run left; called under the lock.
fn recover_leftovers(location: &Location) -> Result<(), OutdirError> {
    let previous = location.sibling("previous");
    if exists(&previous) {
        ensure_ours(&previous, location)?;
        if exists(&location.dir) {
            remove_results(&previous).map_err(io_error("remove the leftover", &previous))?;
        } else {
            tracing::warn!(
                "restoring the results that a killed run left in {}",
                previous.display()
            );
            fs::rename(&previous, &location.dir)
                .map_err(io_error("restore the previous results from", &previous))?;
        }
    }
    let partial = location.sibling("partial");
    if exists(&partial) {
        ensure_ours(&partial, location)?;
        remove_results(&partial).map_err(io_error("remove the leftover", &partial))?;
    }
    Ok(())
}

/// Creates `partial` holding the marker, then `files`.
fn write_partial(
    partial: &Path,
    experiment: &str,
    files: &[OutputFile],
    streamed: &[StreamedFile<'_>],
) -> Result<(), OutdirError> {
    fs::create_dir(partial).map_err(io_error("create", partial))?;
    let marker = partial.join(MARKER);
    let written: Vec<&Path> = files
        .iter()
        .map(|f| f.path.as_path())
        .chain(streamed.iter().map(|f| f.path.as_path()))
        .collect();
    fs::write(&marker, Marker::listing(experiment, &written).to_text())
        .map_err(io_error("write", &marker))?;
    for file in files {
        let target = partial.join(&file.path);
        if let Some(dir) = target.parent() {
            fs::create_dir_all(dir).map_err(io_error("create", dir))?;
        }
        fs::write(&target, &file.contents).map_err(io_error("write", &target))?;
    }
    for file in streamed {
        let target = partial.join(&file.path);
        if let Some(dir) = target.parent() {
            fs::create_dir_all(dir).map_err(io_error("create", dir))?;
        }
        let mut out =
            io::BufWriter::new(File::create(&target).map_err(io_error("create", &target))?);
        (file.write)(&mut out).map_err(|e| {
            // The kind kept (a full disk is told from a refusal by it).
            let kind = match e.innermost() {
                crate::RunnerError::Io { source, .. } => source.kind(),
                _ => io::ErrorKind::Other,
            };
            io_error("write", &target)(io::Error::new(kind, e.to_string()))
        })?;
        out.flush().map_err(io_error("write", &target))?;
    }
    Ok(())
}

/// Puts `.<name>.partial` in the place of the directory; by one exchange if `exchange` and
/// the system supports it, else by two renames.
fn swap(location: &Location, exchange: bool) -> Result<(), OutdirError> {
    let dir = &location.dir;
    let partial = location.sibling("partial");
    if !exists(dir) {
        return fs::rename(&partial, dir).map_err(io_error("move the results into", dir));
    }
    if exchange && exchange_dirs(&partial, dir)? {
        // The old results are now under `partial`.
        remove_old(&partial);
        return Ok(());
    }
    let previous = location.sibling("previous");
    fs::rename(dir, &previous).map_err(io_error("move aside the old results in", dir))?;
    if let Err(e) = fs::rename(&partial, dir) {
        let _ = fs::rename(&previous, dir);
        return Err(io_error("move the results into", dir)(e));
    }
    remove_old(&previous);
    Ok(())
}

/// Removes a results directory of gridplan's, its marker last, so a kill midway leaves a
/// directory still recognised as gridplan's (and cleaned by the next run).
fn remove_results(dir: &Path) -> io::Result<()> {
    for entry in fs::read_dir(dir)? {
        let entry = entry?;
        if entry.file_name() == MARKER {
            continue;
        }
        if entry.file_type()?.is_dir() {
            fs::remove_dir_all(entry.path())?;
        } else {
            fs::remove_file(entry.path())?;
        }
    }
    match fs::remove_file(dir.join(MARKER)) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    fs::remove_dir(dir)
}

/// Removes the replaced results; a failure only warns, as the new results are in place and
/// the next run removes the leftover.
fn remove_old(old: &Path) {
    if let Err(e) = remove_results(old) {
        tracing::warn!(
            "the new results are written, but the old ones in {} could not be removed: {e}",
            old.display()
        );
    }
}

/// Exchanges two directories atomically. `Ok(false)` if the file system cannot.
#[cfg(target_os = "linux")]
fn exchange_dirs(a: &Path, b: &Path) -> Result<bool, OutdirError> {
    use rustix::fs::{renameat_with, RenameFlags, CWD};
    use rustix::io::Errno;
    match renameat_with(CWD, a, CWD, b, RenameFlags::EXCHANGE) {
        Ok(()) => Ok(true),
        Err(Errno::INVAL | Errno::NOSYS | Errno::OPNOTSUPP) => Ok(false),
        Err(e) => Err(io_error("exchange the new results with", b)(e.into())),
    }
}

/// Exchanges two directories atomically. `Ok(false)` if the file system cannot.
#[cfg(not(target_os = "linux"))]
fn exchange_dirs(_a: &Path, _b: &Path) -> Result<bool, OutdirError> {
    Ok(false)
}

/// The working area of a streamed sweep that writes to an output directory: the directory
/// `.<name>.stream` beside it (where the sweep appends its records, so a killed sweep can be
/// resumed), held under its own exclusive lock `.<name>.stream.lock` (the same flock rules
/// as the output's lock) while this value lives. The area is not a results directory and
/// the swap never touches it; the sweep removes it once its results are in place.
///
/// gridplan writes the marker [`STREAM_MARKER`] into the area when it creates it, and uses
/// or removes an existing `.<name>.stream` only if it carries that marker (or is empty):
/// anything else there, a symbolic link included, is [`OutdirError::ForeignStream`] and is
/// left as it is. Files in the area are opened without following links: a link planted
/// at a stream file's name is [`OutdirError::LinkedStream`], and what it points to is never
/// opened, read or written.
pub struct StreamArea {
    /// The stream directory (created, with its marker, by [`stream_area`]).
    pub dir: PathBuf,
    _lock: OutputLock,
}

impl StreamArea {
    /// Opens file `name` of the area for writing, without following a link: created
    /// empty (`truncate`) or the existing file as it is.
    pub fn open_write(&self, name: &str, truncate: bool) -> Result<File, OutdirError> {
        let path = self.dir.join(name);
        let mut options = OpenOptions::new();
        options.write(true).create(truncate).truncate(truncate);
        no_follow(&mut options);
        #[cfg(not(unix))]
        if fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
            return Err(OutdirError::LinkedStream { path });
        }
        match options.open(&path) {
            Ok(file) => Ok(file),
            Err(e) if is_link_error(&e, &path) => Err(OutdirError::LinkedStream { path }),
            Err(e) => Err(io_error("open", &path)(e)),
        }
    }

    /// Refuses a file `name` of the area that is a symbolic link
    /// ([`OutdirError::LinkedStream`]), before anything reads it (a resume).
    pub fn check_not_link(&self, name: &str) -> Result<(), OutdirError> {
        let path = self.dir.join(name);
        match fs::symlink_metadata(&path) {
            Ok(m) if m.file_type().is_symlink() => Err(OutdirError::LinkedStream { path }),
            _ => Ok(()),
        }
    }

    /// Removes the area, if it still carries gridplan's marker (its contents first, the
    /// marker last).
    pub fn remove(&self) -> io::Result<()> {
        if !fs::symlink_metadata(&self.dir).is_ok_and(|m| m.is_dir())
            || !fs::symlink_metadata(self.dir.join(STREAM_MARKER)).is_ok_and(|m| m.is_file())
        {
            return Ok(());
        }
        for entry in fs::read_dir(&self.dir)? {
            let entry = entry?;
            if entry.file_name() == STREAM_MARKER {
                continue;
            }
            if entry.file_type()?.is_dir() {
                fs::remove_dir_all(entry.path())?;
            } else {
                fs::remove_file(entry.path())?;
            }
        }
        fs::remove_file(self.dir.join(STREAM_MARKER))?;
        fs::remove_dir(&self.dir)
    }
}

/// Where the stream area of `output` is ([`stream_area`] locks and creates it); nothing is
/// created.
pub fn stream_area_path(output: &Path) -> Result<PathBuf, OutdirError> {
    Ok(locate(output, false)?.sibling("stream"))
}

/// Locks the stream area of `output` (creating missing parents, as [`write_results`]
/// would), waiting at most `wait` for another sweep on the same output, and creates it
/// with its marker, or checks that an existing one is gridplan's.
pub fn stream_area(output: &Path, wait: Duration) -> Result<StreamArea, OutdirError> {
    stream_area_stoppable(output, wait, None)
}

/// [`stream_area`] that stops waiting for another sweep's lock as soon as `stop` (a
/// sweep's stop flag: Ctrl-C, SIGTERM) is raised, with [`OutdirError::Stopped`]: nothing is
/// created then (missing parents aside), and whatever is beside the output stays as it was.
pub fn stream_area_stoppable(
    output: &Path,
    wait: Duration,
    stop: Option<&AtomicBool>,
) -> Result<StreamArea, OutdirError> {
    let location = locate(output, true)?;
    let lock = OutputLock::acquire_named(&location, "stream.lock", wait, stop)?;
    let dir = location.sibling("stream");
    claim_dir(
        &dir,
        STREAM_MARKER,
        "# Written by gridplan: a sweep's records, kept for --resume; gridplan removes\n\
         # this directory when the sweep's results are written.\n",
        || OutdirError::ForeignStream {
            path: dir.clone(),
            output: location.output.clone(),
        },
    )?;
    Ok(StreamArea { dir, _lock: lock })
}

/// Makes `dir` a working directory of gridplan's, marked by the file `marker` (written
/// with `text` when missing): created if absent; an existing `dir` is used only if it is a
/// directory (not a symbolic link) that carries `marker` or is empty, else `foreign()` is
/// returned and nothing is written.
pub fn claim_dir(
    dir: &Path,
    marker: &str,
    text: &str,
    foreign: impl FnOnce() -> OutdirError,
) -> Result<(), OutdirError> {
    match fs::symlink_metadata(dir) {
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            fs::create_dir(dir).map_err(io_error("create", dir))?;
        }
        Err(e) => return Err(io_error("read", dir)(e)),
        Ok(metadata) if !metadata.is_dir() => return Err(foreign()),
        Ok(_) => {
            let marked = fs::symlink_metadata(dir.join(marker)).is_ok_and(|m| m.is_file());
            let empty = fs::read_dir(dir)
                .map_err(io_error("list", dir))?
                .next()
                .is_none();
            if !marked && !empty {
                return Err(foreign());
            }
        }
    }
    let marker = dir.join(marker);
    if !fs::symlink_metadata(&marker).is_ok_and(|m| m.is_file()) {
        fs::write(&marker, text).map_err(io_error("write", &marker))?;
    }
    Ok(())
}

/// Makes `options` refuse to open a symbolic link (`O_NOFOLLOW`).
#[cfg(unix)]
pub(crate) fn no_follow(options: &mut OpenOptions) {
    use std::os::unix::fs::OpenOptionsExt as _;
    options.custom_flags(libc::O_NOFOLLOW);
}

/// Makes `options` refuse to open a symbolic link (checked before opening elsewhere).
#[cfg(not(unix))]
pub(crate) fn no_follow(_options: &mut OpenOptions) {}

/// Whether `error`, from opening with [`no_follow`], means the path is a symbolic link.
fn is_link_error(error: &io::Error, path: &Path) -> bool {
    #[cfg(unix)]
    let loop_error = error.raw_os_error() == Some(libc::ELOOP);
    #[cfg(not(unix))]
    let loop_error = {
        let _ = error;
        false
    };
    loop_error || fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

/// The process id this process's lock files name; 0 until [`set_lock_holder`] sets it.
static LOCK_HOLDER: AtomicU32 = AtomicU32::new(0);

/// Names `pid` (the caller's `std::process::id()`) in the lock files this process writes,
/// so that a second run waiting for one of them says whose it is ("pid N"). The command
/// line, xtask and the Python package call it once at start; the runner reads no process
/// state, so without it its lock files name no process (the locks work the same).
pub fn set_lock_holder(pid: u32) {
    LOCK_HOLDER.store(pid, Ordering::Relaxed);
}

/// The exclusive lock on an output directory: an OS file lock on `.<name>.lock` beside it,
/// whose file holds the holder's pid ([`set_lock_holder`]; empty when none was set). Dropping it removes the file, then unlocks.
struct OutputLock {
    file: File,
    path: PathBuf,
}

impl OutputLock {
    /// Takes the lock, waiting at most `wait` for another holder.
    fn acquire(location: &Location, wait: Duration) -> Result<Self, OutdirError> {
        Self::acquire_named(location, "lock", wait, None)
    }

    /// Takes the lock `.<name>.<suffix>` beside the directory; a raised `stop` ends the wait
    /// with [`OutdirError::Stopped`] (checked between tries, every [`LOCK_POLL`]).
    fn acquire_named(
        location: &Location,
        suffix: &str,
        wait: Duration,
        stop: Option<&AtomicBool>,
    ) -> Result<Self, OutdirError> {
        let path = location.sibling(suffix);
        let started = Instant::now();
        let mut told = false;
        loop {
            // Where O_NOFOLLOW is not known, a link is looked for first.
            #[cfg(not(unix))]
            if fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink()) {
                return Err(OutdirError::LinkedLock {
                    path: location.output.clone(),
                    lock: path,
                });
            }
            let mut options = OpenOptions::new();
            options.read(true).write(true).create(true).truncate(false);
            no_follow(&mut options);
            let mut file = match options.open(&path) {
                Ok(file) => file,
                Err(e) if is_link_error(&e, &path) => {
                    return Err(OutdirError::LinkedLock {
                        path: location.output.clone(),
                        lock: path,
                    })
                }
                Err(e) => return Err(io_error("open the lock file", &path)(e)),
            };
            match fs4::FileExt::try_lock(&file) {
                Ok(()) => {
                    if !still_at(&file, &path) {
                        // The previous holder removed this file after we opened it.
                        continue;
                    }
                    let pid = match LOCK_HOLDER.load(Ordering::Relaxed) {
                        0 => String::new(),
                        pid => format!("{pid}\n"),
                    };
                    file.set_len(0)
                        .and_then(|()| file.write_all(pid.as_bytes()))
                        .map_err(io_error("write the lock file", &path))?;
                    return Ok(Self { file, path });
                }
                Err(fs4::TryLockError::WouldBlock) => {
                    if stop.is_some_and(|stop| stop.load(Ordering::Relaxed)) {
                        return Err(OutdirError::Stopped {
                            path: location.output.clone(),
                            lock: path,
                        });
                    }
                    let holder = holder(&mut file);
                    if started.elapsed() >= wait {
                        return Err(OutdirError::Locked {
                            path: location.output.clone(),
                            lock: path,
                            holder,
                            seconds: started.elapsed().as_secs(),
                        });
                    }
                    if !told {
                        tracing::warn!(
                            "output {} is being written by another gridplan run{holder}; \
                             waiting up to {} s for its lock {}",
                            location.output.display(),
                            wait.as_secs(),
                            path.display()
                        );
                        told = true;
                    }
                    std::thread::sleep(LOCK_POLL);
                }
                Err(fs4::TryLockError::Error(e)) => return Err(io_error("lock", &path)(e)),
            }
        }
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still locked, so a run that opened this file meanwhile finds it gone
        // once it gets the lock, and starts over with a fresh file.
        let _ = fs::remove_file(&self.path);
        let _ = fs4::FileExt::unlock(&self.file);
    }
}

/// " (pid N)" from a lock file's contents, or "" if it names none.
fn holder(file: &mut File) -> String {
    let mut text = String::new();
    let _ = file.read_to_string(&mut text);
    match text.trim().parse::<u32>() {
        Ok(pid) => format!(" (pid {pid})"),
        Err(_) => String::new(),
    }
}

/// Whether the open `file` is still the one at `path`.
#[cfg(unix)]
fn still_at(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt as _;
    match (file.metadata(), fs::symlink_metadata(path)) {
        (Ok(open), Ok(named)) => open.dev() == named.dev() && open.ino() == named.ino(),
        _ => false,
    }
}

/// Whether the open `file` is still the one at `path` (assumed where inodes are not known).
#[cfg(not(unix))]
fn still_at(_file: &File, path: &Path) -> bool {
    exists(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh directory holding a marked `r` (old results) and a marked `.r.partial` (new).
    fn old_and_new(name: &str) -> Location {
        let base =
            std::env::temp_dir().join(format!("gridplan-outdir-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&base);
        let location = locate(&base.join("r"), true).unwrap();
        for (dir, text) in [
            (location.dir.clone(), "old"),
            (location.sibling("partial"), "new"),
        ] {
            fs::create_dir_all(dir.join("figures")).unwrap();
            fs::write(dir.join(MARKER), Marker::new("t").to_text()).unwrap();
            fs::write(dir.join("figures/a.svg"), text).unwrap();
        }
        location
    }

    fn names(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[test]
    fn both_swaps_put_the_new_results_in_place_and_remove_the_old() {
        for exchange in [true, false] {
            let location = old_and_new(&format!("swap-{exchange}"));
            swap(&location, exchange).unwrap();
            let figure = fs::read_to_string(location.dir.join("figures/a.svg")).unwrap();
            assert_eq!(figure, "new", "exchange: {exchange}");
            assert_eq!(names(&location.parent), ["r"], "exchange: {exchange}");
            fs::remove_dir_all(&location.parent).unwrap();
        }
    }

    #[test]
    fn side_files_of_a_long_name_fit_and_stay_apart() {
        let at = |name: &str| Location {
            output: PathBuf::from(name),
            dir: Path::new("/p").join(name),
            parent: PathBuf::from("/p"),
            name: OsString::from(name),
        };
        // A 250-byte name made `.<name>.lock` 256 bytes: "File name too long".
        let long = at(&"L".repeat(250));
        let other = at(&format!("{}M", "L".repeat(249)));
        let mut seen = Vec::new();
        for suffix in ["lock", "stream", "stream.lock", "partial", "previous"] {
            let side = long.sibling(suffix);
            let name = side.file_name().unwrap().to_string_lossy().into_owned();
            assert!(name.len() <= MAX_FILE_NAME, "{name}");
            assert!(name.starts_with(".LLLL") && name.ends_with(&format!(".{suffix}")));
            assert_eq!(side, long.sibling(suffix), "the same for every run");
            assert_ne!(side, other.sibling(suffix), "another output's own");
            seen.push(side);
        }
        seen.dedup();
        assert_eq!(seen.len(), 5);
        // Names that fit are kept whole.
        assert_eq!(
            at("res").sibling("stream.lock"),
            Path::new("/p/.res.stream.lock")
        );
        let fits = "L".repeat(MAX_FILE_NAME - ".".len() - ".lock".len());
        assert_eq!(
            at(&fits).sibling("lock"),
            Path::new("/p").join(format!(".{fits}.lock"))
        );
    }

    #[test]
    fn a_mount_root_is_told_by_the_kernel_else_by_its_device() {
        // The kernel says (statx's STATX_ATTR_MOUNT_ROOT): a bind mount on the same file
        // system (same device) is one; a btrfs subvolume (another device) is none.
        assert!(is_mount_root(7, 7, Some(true)));
        assert!(!is_mount_root(7, 9, Some(false)));
        // It does not say: another device than the parent's is a mount.
        assert!(is_mount_root(7, 9, None));
        assert!(!is_mount_root(7, 7, None));
        // A plain directory here is none.
        let location = old_and_new("mount-root");
        assert!(!mount_point(&location.dir, &location.parent).unwrap());
        fs::remove_dir_all(&location.parent).unwrap();
    }

    #[test]
    fn a_previous_without_its_directory_is_restored() {
        let location = old_and_new("restore");
        let previous = location.sibling("previous");
        fs::rename(&location.dir, &previous).unwrap();
        recover_leftovers(&location).unwrap();
        // The old results are back; the half-done partial is gone.
        let figure = fs::read_to_string(location.dir.join("figures/a.svg")).unwrap();
        assert_eq!(figure, "old");
        assert_eq!(names(&location.parent), ["r"]);
        fs::remove_dir_all(&location.parent).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_lock_planted_as_a_link_is_not_followed() {
        let location = old_and_new("linked-lock");
        let victim = location.parent.join("victim");
        fs::write(&victim, "precious").unwrap();
        std::os::unix::fs::symlink(&victim, location.sibling("lock")).unwrap();
        // Opened directly (as after a race with `check`): O_NOFOLLOW refuses it.
        let error = OutputLock::acquire(&location, Duration::ZERO)
            .err()
            .unwrap();
        assert!(matches!(error, OutdirError::LinkedLock { .. }), "{error}");
        assert_eq!(fs::read_to_string(&victim).unwrap(), "precious");
        fs::remove_dir_all(&location.parent).unwrap();
    }

    #[test]
    fn a_listing_marker_reads_back_whatever_the_names() {
        let location = old_and_new("listing");
        let files = [
            Path::new("figures/a \"quoted\" \\ name.svg"),
            Path::new("line\nbreak.csv"),
            Path::new("runs.csv"),
        ];
        let marker = Marker::listing("t", &files);
        fs::write(location.dir.join(MARKER), marker.to_text()).unwrap();
        assert_eq!(Marker::read(&location.dir).unwrap(), marker);
        assert_eq!(
            marker.files.as_deref().unwrap(),
            [
                "figures/a \"quoted\" \\ name.svg",
                "line\nbreak.csv",
                "runs.csv"
            ]
        );
        // Unlisted: the directory's own figures/a.svg and nothing else.
        assert_eq!(
            unlisted_entries(&location.dir, 4).unwrap(),
            ["figures/a.svg"]
        );
        fs::remove_dir_all(&location.parent).unwrap();
    }

    #[test]
    fn the_marker_reads_back() {
        let location = old_and_new("marker");
        assert_eq!(Marker::read(&location.dir).unwrap(), Marker::new("t"));
        fs::write(location.dir.join(MARKER), "format = \"one\"\n").unwrap();
        let error = Marker::read(&location.dir).unwrap_err();
        assert!(
            error.to_string().contains("is not a gridplan marker"),
            "{error}"
        );
        fs::remove_dir_all(&location.parent).unwrap();
    }
}
