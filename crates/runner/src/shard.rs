//! Deterministic, cost-balanced slices of a run list, for sweeps spread over machines.
//!
//! Shard `K/N` (1-based `K`) holds some runs of every (map, problem) block of the
//! [`RunList`]. A block's runs (its planners x repeats) are dealt round-robin over the N
//! shards, starting at the shard that has the least expected cost so far, so each shard
//! gets the same number of a block's runs, give or take one, and a block's leftover runs go
//! where there is the least work. A run's expected cost is its problem's stated optimal
//! length (a scenario file's bucket is that length divided by four), else the octile
//! distance from start to goal, plus one; invalid problems cost one. The slicing is a pure
//! function of the run list and N: every machine computes the same slices, every run is in
//! exactly one shard, and a shard iterates its runs in increasing run index, lazily (its
//! memory is a few numbers per block, whatever the repeats), and tells a run's position
//! among them ([`ShardRuns::position`]).

use crate::config::Experiment;
use crate::run::RunList;

/// Which slice of a sweep to run: shard `index` (1-based) of `count`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shard {
    /// 1-based shard number, at most `count`.
    pub index: u64,
    /// Number of shards, at least 1.
    pub count: u64,
}

impl Shard {
    /// The whole sweep as one shard.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// The most shards a sweep may be cut into: 2^20 = 1048576. [`ShardRuns::new`] keeps
    /// one load figure per shard (8 MiB at this count), and a merge opens every shard's
    /// stream, so a count is checked against this before anything is allocated. Slurm's
    /// own array limit (`MaxArraySize`) defaults to 1001.
    pub const MAX_COUNT: u64 = 1 << 20;

    /// Shard `index` of `count`, checked (1 <= index <= count <= [`Shard::MAX_COUNT`]).
    pub fn new(index: u64, count: u64) -> Result<Shard, ShardError> {
        if count == 0 || index == 0 || index > count {
            return Err(ShardError::OutOfRange { index, count });
        }
        if count > Self::MAX_COUNT {
            return Err(ShardError::TooMany { index, count });
        }
        Ok(Shard { index, count })
    }

    /// Parses `K/N`, e.g. `2/3`.
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| ShardError::NotKn(text.to_string()))?;
        let number = |s: &str| {
            s.trim()
                .parse::<u64>()
                .map_err(|source| ShardError::NotANumber {
                    text: text.to_string(),
                    part: s.to_string(),
                    source,
                })
        };
        Shard::new(number(k)?, number(n)?)
    }

    /// The shard that the environment of a job array names, if any: Slurm's
    /// `SLURM_ARRAY_TASK_ID` with `SLURM_ARRAY_TASK_COUNT` (shard
    /// `ID - SLURM_ARRAY_TASK_MIN + 1`, the minimum taken as 0 when unset, so `--array=1-N`
    /// and `--array=0-(N-1)` both give shards 1..N), or Kubernetes' 0-based
    /// `JOB_COMPLETION_INDEX` with `GRIDPLAN_SHARD_COUNT`. `get` reads one variable
    /// (`std::env::var` in the binary; a map in tests).
    pub fn from_env(get: impl Fn(&str) -> Option<String>) -> Result<Option<Shard>, ShardError> {
        let number = |key: &'static str| -> Result<Option<u64>, ShardError> {
            match get(key) {
                None => Ok(None),
                Some(value) => value
                    .trim()
                    .parse::<u64>()
                    .map(Some)
                    .map_err(|source| ShardError::Variable { key, value, source }),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let count = number("SLURM_ARRAY_TASK_COUNT")?.ok_or(ShardError::NoSlurmCount)?;
            let min = number("SLURM_ARRAY_TASK_MIN")?.unwrap_or(0);
            let named = |e: ShardError| ShardError::Slurm {
                id,
                min,
                count,
                problem: Box::new(e),
            };
            let offset = id
                .checked_sub(min)
                .ok_or_else(|| named(ShardError::BelowMin { id, min }))?;
            let index = offset
                .checked_add(1)
                .ok_or_else(|| named(ShardError::TaskPastCount { offset, count }))?;
            return Shard::new(index, count).map(Some).map_err(named);
        }
        if let Some(index) = number("JOB_COMPLETION_INDEX")? {
            let count = number("GRIDPLAN_SHARD_COUNT")?.ok_or(ShardError::NoIndexedCount)?;
            let named = |e: ShardError| ShardError::Indexed {
                index,
                count,
                problem: Box::new(e),
            };
            let shard = index
                .checked_add(1)
                .ok_or_else(|| named(ShardError::IndexPastCount { index, count }))?;
            return Shard::new(shard, count).map(Some).map_err(named);
        }
        Ok(None)
    }
}

/// A shard that cannot be: `K/N` malformed or out of range, or a job array's environment
/// that names none (a usage error).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ShardError {
    /// `K/N` with `K` or `N` 0, or `K > N`.
    #[error("shard {index}/{count}: expected K/N with 1 <= K <= N")]
    OutOfRange {
        /// `K`.
        index: u64,
        /// `N`.
        count: u64,
    },
    /// More shards than [`Shard::MAX_COUNT`].
    #[error("shard {index}/{count}: at most {max} shards", max = Shard::MAX_COUNT)]
    TooMany {
        /// `K`.
        index: u64,
        /// `N`.
        count: u64,
    },
    /// Text without a `/`.
    #[error("shard {0:?}: expected K/N, e.g. 2/3")]
    NotKn(String),
    /// A side of `K/N` that is not a number.
    #[error("shard {text:?}: {part:?} is not a number: {source}")]
    NotANumber {
        /// The text given.
        text: String,
        /// The side that is not a number.
        part: String,
        /// Why.
        source: std::num::ParseIntError,
    },
    /// An environment variable that is not a number.
    #[error("environment variable {key}={value:?}: {source}")]
    Variable {
        /// The variable.
        key: &'static str,
        /// Its value.
        value: String,
        /// Why.
        source: std::num::ParseIntError,
    },
    /// `SLURM_ARRAY_TASK_ID` without `SLURM_ARRAY_TASK_COUNT`.
    #[error("SLURM_ARRAY_TASK_ID is set but SLURM_ARRAY_TASK_COUNT is not; pass --shard K/N")]
    NoSlurmCount,
    /// A Slurm task whose variables name no shard.
    #[error(
        "environment variables SLURM_ARRAY_TASK_ID={id}, SLURM_ARRAY_TASK_MIN={min}, \
         SLURM_ARRAY_TASK_COUNT={count}: {problem}"
    )]
    Slurm {
        /// `SLURM_ARRAY_TASK_ID`.
        id: u64,
        /// `SLURM_ARRAY_TASK_MIN` (0 when unset).
        min: u64,
        /// `SLURM_ARRAY_TASK_COUNT`.
        count: u64,
        /// What is wrong with them.
        problem: Box<ShardError>,
    },
    /// A task id below the array's minimum.
    #[error("SLURM_ARRAY_TASK_ID {id} is below SLURM_ARRAY_TASK_MIN {min}")]
    BelowMin {
        /// The task id.
        id: u64,
        /// The array's minimum.
        min: u64,
    },
    /// A task offset with no shard after it.
    #[error("task {offset} is not below the count {count}")]
    TaskPastCount {
        /// The task's offset from the minimum.
        offset: u64,
        /// The task count.
        count: u64,
    },
    /// `JOB_COMPLETION_INDEX` without `GRIDPLAN_SHARD_COUNT`.
    #[error("JOB_COMPLETION_INDEX is set but GRIDPLAN_SHARD_COUNT is not; pass --shard K/N")]
    NoIndexedCount,
    /// An indexed job whose variables name no shard.
    #[error(
        "environment variables JOB_COMPLETION_INDEX={index} (0-based), \
         GRIDPLAN_SHARD_COUNT={count}: {problem}"
    )]
    Indexed {
        /// `JOB_COMPLETION_INDEX`.
        index: u64,
        /// `GRIDPLAN_SHARD_COUNT`.
        count: u64,
        /// What is wrong with them.
        problem: Box<ShardError>,
    },
    /// An index with no shard after it.
    #[error("index {index} is not below the count {count}")]
    IndexPastCount {
        /// The index.
        index: u64,
        /// The shard count.
        count: u64,
    },
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// The runs of one shard: for each block of the run list, where its round-robin starts.
#[derive(Debug, Clone)]
pub struct ShardRuns {
    /// Per block: (first run index, runs in the block, shard offset of the block's first
    /// run, the shard's runs in earlier blocks).
    blocks: Vec<(u64, u64, u64, u64)>,
    shard: Shard,
    n_runs: u64,
}

impl ShardRuns {
    /// The runs of `shard` in `experiment`'s run list.
    pub fn new(experiment: &Experiment, shard: Shard) -> ShardRuns {
        let n = shard.count;
        let mut load = vec![0.0f64; n as usize];
        let mut blocks = Vec::new();
        let mut next = 0u64;
        let n_planners = experiment.planners.len() as u64;
        let mut n_runs = 0u64;
        for map in &experiment.maps {
            for problem in &map.problems {
                let repeats = experiment.repeats_of(problem);
                let size = repeats * n_planners;
                let cost = if problem.invalid.is_some() {
                    1.0
                } else {
                    1.0 + problem
                        .optimal_length
                        .unwrap_or_else(|| problem.start.octile(problem.goal))
                };
                let offset = (0..n)
                    .min_by(|&a, &b| load[a as usize].total_cmp(&load[b as usize]))
                    .unwrap_or(0);
                let before = n_runs;
                for s in 0..n {
                    let share = count_in(size, offset, s, n);
                    load[s as usize] += share as f64 * cost;
                    if s == shard.index - 1 {
                        n_runs += share;
                    }
                }
                blocks.push((next, size, offset, before));
                next += size;
            }
        }
        debug_assert_eq!(next, RunList::new(experiment).len());
        ShardRuns {
            blocks,
            shard,
            n_runs,
        }
    }

    /// How many runs the shard holds.
    pub fn len(&self) -> u64 {
        self.n_runs
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.n_runs == 0
    }

    /// The shard.
    pub fn shard(&self) -> Shard {
        self.shard
    }

    /// The shard's run indices, increasing.
    pub fn iter(&self) -> impl Iterator<Item = u64> + '_ {
        let n = self.shard.count;
        let s = self.shard.index - 1;
        self.blocks
            .iter()
            .flat_map(move |&(first, size, offset, _)| {
                // Run r of the block goes to shard (offset + r) mod n.
                let r0 = (s + n - offset) % n;
                (r0..size).step_by(n as usize).map(move |r| first + r)
            })
    }

    /// The position of run `index` among the shard's runs ([`ShardRuns::iter`]'s), or
    /// `None` when the shard does not hold it.
    pub fn position(&self, index: u64) -> Option<u64> {
        let block = self
            .blocks
            .partition_point(|b| b.0 <= index)
            .checked_sub(1)?;
        let (first, size, offset, before) = self.blocks[block];
        let r = index - first;
        let n = self.shard.count;
        let r0 = (self.shard.index - 1 + n - offset) % n;
        (r < size && r >= r0 && (r - r0) % n == 0).then(|| before + (r - r0) / n)
    }
}

/// How many of a block's `size` runs, dealt from shard `offset` round-robin over `n`,
/// shard `s` gets.
fn count_in(size: u64, offset: u64, s: u64, n: u64) -> u64 {
    let r0 = (s + n - offset) % n;
    if r0 >= size {
        0
    } else {
        (size - r0).div_ceil(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_checks() {
        assert_eq!(Shard::parse("2/3"), Ok(Shard { index: 2, count: 3 }));
        for bad in ["0/3", "4/3", "1/0", "x/3", "3"] {
            assert!(Shard::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn reads_job_array_environments() {
        let env = |pairs: &'static [(&'static str, &'static str)]| {
            move |k: &str| {
                pairs
                    .iter()
                    .find(|(key, _)| *key == k)
                    .map(|(_, v)| v.to_string())
            }
        };
        assert_eq!(Shard::from_env(env(&[])), Ok(None));
        let slurm = env(&[
            ("SLURM_ARRAY_TASK_ID", "3"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
        ]);
        assert_eq!(
            Shard::from_env(slurm),
            Ok(Some(Shard { index: 3, count: 3 }))
        );
        let zero_based = env(&[
            ("SLURM_ARRAY_TASK_ID", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "2"),
        ]);
        assert_eq!(
            Shard::from_env(zero_based),
            Ok(Some(Shard { index: 1, count: 2 }))
        );
        let k8s = env(&[("JOB_COMPLETION_INDEX", "1"), ("GRIDPLAN_SHARD_COUNT", "4")]);
        assert_eq!(Shard::from_env(k8s), Ok(Some(Shard { index: 2, count: 4 })));
        assert!(Shard::from_env(env(&[("SLURM_ARRAY_TASK_ID", "1")])).is_err());
        // Issue 27: the largest index wrapped to shard 0/N, and the error did not name
        // the variable.
        let wrapped = env(&[
            ("JOB_COMPLETION_INDEX", "18446744073709551615"),
            ("GRIDPLAN_SHARD_COUNT", "3"),
        ]);
        let error = Shard::from_env(wrapped).unwrap_err().to_string();
        assert!(
            error.contains("JOB_COMPLETION_INDEX=18446744073709551615"),
            "{error}"
        );
        let past = env(&[("JOB_COMPLETION_INDEX", "3"), ("GRIDPLAN_SHARD_COUNT", "3")]);
        let error = Shard::from_env(past).unwrap_err().to_string();
        assert!(error.contains("JOB_COMPLETION_INDEX=3"), "{error}");
        assert!(error.contains("shard 4/3"), "{error}");
    }

    #[test]
    fn absurd_counts_are_refused_before_allocating() {
        for bad in ["1/1000000000000", "1/18446744073709551615", "1/1048577"] {
            let error = Shard::parse(bad).unwrap_err().to_string();
            assert!(error.contains("at most 1048576 shards"), "{bad}: {error}");
        }
        assert_eq!(
            Shard::parse("1048576/1048576").map(|s| s.count),
            Ok(Shard::MAX_COUNT)
        );
    }

    #[test]
    fn positions_are_those_of_the_iteration() {
        let map = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../maps/paper/map01.map")
            .display()
            .to_string();
        let text = format!(
            "name = \"t\"\nrepeats = 7\n[[maps]]\nfiles = [{map:?}]\nproblems = \"corners\"\n\
             [planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n"
        );
        let experiment = crate::config::parse(std::path::Path::new("t.toml"), &text).unwrap();
        let n_runs = RunList::new(&experiment).len();
        for count in 1..5 {
            let mut held = vec![None; n_runs as usize + 3];
            for index in 1..=count {
                let runs = ShardRuns::new(&experiment, Shard::new(index, count).unwrap());
                for (position, run) in runs.iter().enumerate() {
                    held[run as usize] = Some((index, position as u64));
                }
                for (run, holder) in held.iter().enumerate() {
                    let position = holder.filter(|(k, _)| *k == index).map(|(_, p)| p);
                    assert_eq!(
                        runs.position(run as u64),
                        position,
                        "{index}/{count} run {run}"
                    );
                }
            }
        }
    }

    #[test]
    fn dealing_counts_add_up() {
        for size in 0..20 {
            for n in 1..6 {
                for offset in 0..n {
                    let total: u64 = (0..n).map(|s| count_in(size, offset, s, n)).sum();
                    assert_eq!(total, size, "size {size} n {n} offset {offset}");
                }
            }
        }
    }
}
