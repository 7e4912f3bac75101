//! Where and from what a sweep's results came: gridplan's version and git commit, the
//! date, the host, its CPU and thread count, and the config file's hash.
//!
//! The sweep collects it ([`Provenance::collect`]) and passes it to the report and to
//! runs.json; it is never part of a [`crate::RunRecord`], so snapshots of records stay a
//! pure function of the config. What needs the environment or another process (the host
//! name's fallback `$HOSTNAME`, `git`) the caller learns and passes in as a [`Machine`]:
//! the runner reads no environment variable and starts no process. [`Machine::from_facts`]
//! turns the raw answers into it, so every front end reads them alike.

use std::fmt::Write as _;
use std::path::Path;

use planner_text::md_cell;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// The provenance of one sweep.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Provenance {
    /// gridplan's version (the runner crate's version).
    pub version: String,
    /// The git commit gridplan was built from, as `gridplan --version` says it (the
    /// caller's build script learns it: [`crate::sweep::SweepArgs::build`]); `None` when
    /// the caller did not tell it (a library caller, or a results directory of an earlier
    /// version).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub build: Option<String>,
    /// The git commit of the config's working tree at run time (`git rev-parse HEAD`), with
    /// `-dirty` when it has uncommitted changes; `None` outside a git repository or when
    /// the caller did not ask git ([`Machine`]).
    pub commit: Option<String>,
    /// The date and time the sweep was run, UTC, RFC 3339 (seconds).
    pub date: String,
    /// The host name (`/proc/sys/kernel/hostname`, else `$HOSTNAME`; [`Machine`]), if known.
    pub host: Option<String>,
    /// The CPU model (`model name` in `/proc/cpuinfo`), if known.
    pub cpu: Option<String>,
    /// Worker threads the sweep ran with (of a sweep merged from shards: the most any
    /// shard ran with).
    pub threads: usize,
    /// Of a sweep merged from shards whose thread counts differ: each shard's, in shard
    /// order (absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard_threads: Option<Vec<usize>>,
    /// SHA-256 of the config file's bytes, hex; `None` if it could not be read.
    pub config_sha256: Option<String>,
}

/// The provenance facts only the caller can learn: the git commit of the config's working
/// tree and the host name. [`Machine::default`] leaves both unknown.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Machine {
    /// [`Provenance::commit`].
    pub commit: Option<String>,
    /// [`Provenance::host`].
    pub host: Option<String>,
}

/// The raw answers a front end gathers for a [`Machine`] (each `None` when unavailable).
#[derive(Debug, Clone, Default)]
pub struct Facts {
    /// The contents of `/proc/sys/kernel/hostname`.
    pub hostname_file: Option<String>,
    /// `$HOSTNAME`.
    pub hostname_env: Option<String>,
    /// The output of `git -C <config's directory> rev-parse HEAD` (when it succeeded).
    pub git_head: Option<String>,
    /// The output of `git -C <config's directory> status --porcelain --untracked-files=no`
    /// (when it succeeded).
    pub git_status: Option<String>,
}

impl Machine {
    /// The [`Machine`] of `facts`: the host from the kernel's file, else `$HOSTNAME`; the
    /// commit from `git rev-parse HEAD`, with `-dirty` when `git status` lists a change.
    ///
    /// ```
    /// use planner_runner::provenance::{Facts, Machine};
    /// let machine = Machine::from_facts(Facts {
    ///     hostname_file: Some(" \n".into()),
    ///     hostname_env: Some("node7".into()),
    ///     git_head: Some("abc123\n".into()),
    ///     git_status: Some(" M README.md\n".into()),
    /// });
    /// assert_eq!(machine.host.as_deref(), Some("node7"));
    /// assert_eq!(machine.commit.as_deref(), Some("abc123-dirty"));
    /// ```
    pub fn from_facts(facts: Facts) -> Machine {
        let host = facts
            .hostname_file
            .map(|h| h.trim().to_string())
            .filter(|h| !h.is_empty())
            .or(facts.hostname_env);
        let commit = facts
            .git_head
            .map(|c| c.trim().to_string())
            .filter(|c| !c.is_empty())
            .map(|commit| {
                let dirty = facts.git_status.is_some_and(|s| !s.trim().is_empty());
                if dirty {
                    format!("{commit}-dirty")
                } else {
                    commit
                }
            });
        Machine { commit, host }
    }
}

impl Provenance {
    /// Collects the provenance of a sweep of `config` run with `threads` workers on
    /// `machine` (what the caller learnt of the commit and host).
    pub fn collect(config: &Path, threads: usize, machine: &Machine) -> Provenance {
        Provenance {
            version: env!("CARGO_PKG_VERSION").to_string(),
            build: None,
            commit: machine.commit.clone(),
            date: rfc3339_utc(
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_secs()),
            ),
            host: machine.host.clone(),
            cpu: std::fs::read_to_string("/proc/cpuinfo")
                .ok()
                .and_then(|text| cpu_model(&text)),
            threads,
            shard_threads: None,
            config_sha256: std::fs::read(config).ok().map(|bytes| sha256_hex(&bytes)),
        }
    }

    /// The provenance as a markdown list (the top of summary.md). Every value is data
    /// ([`md_cell`]): a host name or an edited provenance.json cannot add a line, a heading
    /// or HTML.
    pub fn markdown(&self) -> String {
        let unknown = |v: &Option<String>| md_cell(v.as_deref().unwrap_or("unknown"));
        let mut out = String::from("## Provenance\n\n");
        let _ = writeln!(out, "- gridplan {}", md_cell(&self.version));
        if let Some(build) = &self.build {
            let _ = writeln!(out, "- gridplan built from commit: {}", md_cell(build));
        }
        let _ = writeln!(out, "- commit: {}", unknown(&self.commit));
        let _ = writeln!(out, "- date: {}", md_cell(&self.date));
        let _ = writeln!(out, "- host: {}", unknown(&self.host));
        let _ = writeln!(out, "- CPU: {}", unknown(&self.cpu));
        match &self.shard_threads {
            Some(each) => {
                let each: Vec<String> = each.iter().map(usize::to_string).collect();
                let _ = writeln!(
                    out,
                    "- threads: {} (shards: {})",
                    self.threads,
                    each.join(", ")
                );
            }
            None => {
                let _ = writeln!(out, "- threads: {}", self.threads);
            }
        }
        let _ = writeln!(out, "- config SHA-256: {}", unknown(&self.config_sha256));
        out.push('\n');
        out
    }
}

/// SHA-256 of `bytes` as lowercase hex.
pub fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .fold(String::with_capacity(64), |mut hex, b| {
            let _ = write!(hex, "{b:02x}");
            hex
        })
}

/// The first `model name` of a `/proc/cpuinfo` text.
fn cpu_model(cpuinfo: &str) -> Option<String> {
    cpuinfo
        .lines()
        .filter_map(|line| line.split_once(':'))
        .find(|(key, _)| key.trim() == "model name")
        .map(|(_, value)| value.trim().to_string())
}

/// `seconds` since the Unix epoch as `YYYY-MM-DDThh:mm:ssZ` (Howard Hinnant's
/// days-to-civil algorithm, proleptic Gregorian calendar).
fn rfc3339_utc(seconds: u64) -> String {
    let days = (seconds / 86_400) as i64;
    let rest = seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3600,
        rest % 3600 / 60,
        rest % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_utc_civil_dates() {
        assert_eq!(rfc3339_utc(0), "1970-01-01T00:00:00Z");
        // `date -u -d @951782400` = 2000-02-29 00:00:00 (a leap day of a century year).
        assert_eq!(rfc3339_utc(951_782_400), "2000-02-29T00:00:00Z");
        // `date -u -d @1735689599` = 2024-12-31 23:59:59.
        assert_eq!(rfc3339_utc(1_735_689_599), "2024-12-31T23:59:59Z");
    }

    #[test]
    fn sha256_of_abc_is_the_fips_vector() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }

    #[test]
    fn cpu_model_is_the_first_model_name() {
        let text = "processor\t: 0\nmodel name\t: Example CPU @ 2.0GHz\nprocessor\t: 1\nmodel name\t: Other\n";
        assert_eq!(cpu_model(text).as_deref(), Some("Example CPU @ 2.0GHz"));
        assert_eq!(cpu_model("processor: 0\n"), None);
    }

    #[test]
    fn markdown_values_cannot_add_lines_or_html() {
        let provenance = Provenance {
            version: "0.1.0".into(),
            build: Some("b\nuild".into()),
            commit: Some("abc\r\ndef".into()),
            date: "2026-12-07T00:00:00Z".into(),
            host: Some("a\n## Fake section\n<script>x</script>|y".into()),
            cpu: None,
            threads: 2,
            shard_threads: None,
            config_sha256: None,
        };
        let markdown = provenance.markdown();
        // A heading line, the list's items and the blank line after them: nothing more.
        assert_eq!(markdown.lines().count(), 11, "{markdown}");
        assert!(
            markdown.contains("- gridplan built from commit: b uild\n"),
            "{markdown}"
        );
        assert!(markdown.contains("- commit: abc  def\n"), "{markdown}");
        assert!(
            markdown.contains("- host: a ## Fake section &lt;script&gt;x&lt;/script&gt;\\|y\n"),
            "{markdown}"
        );
    }
}
