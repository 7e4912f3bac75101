//! Helpers shared by the CLI's test files: scratch directories, running the real
//! `gridplan` binary with a timeout, and running the Slurm scripts it writes with bash.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// How long one command may take before a test calls it a hang.
pub const TIMEOUT: Duration = Duration::from_secs(120);

/// A 3x3 Moving AI map with a wall cell in the middle.
pub const SMALL: &[u8] = b"type octile\nheight 3\nwidth 3\nmap\n...\n.@.\n...\n";

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh, empty directory `gridplan-KIND-PID-NAME` under the system's temp dir
/// (canonical, so paths built from it are the ones the binary prints).
pub fn scratch(kind: &str, name: impl std::fmt::Display) -> PathBuf {
    // Under the target directory, one per process (two runs of the tests at once, as two
    // engineers' or agents' builds, must not share one), and the ones of finished
    // processes removed first, so that they do not pile up.
    let root = Path::new(env!("CARGO_TARGET_TMPDIR"));
    let (prefix, suffix) = (format!("gridplan-{kind}-"), format!("-{name}"));
    for entry in std::fs::read_dir(root).into_iter().flatten().flatten() {
        let file_name = entry.file_name();
        let Some(pid) = file_name
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix)?.strip_suffix(&suffix))
        else {
            continue;
        };
        let alive = Path::new("/proc").join(pid).exists();
        if pid.bytes().all(|b| b.is_ascii_digit()) && !alive {
            let _ = std::fs::remove_dir_all(entry.path());
        }
    }
    let dir = root.join(format!("{prefix}{}{suffix}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir.canonicalize().unwrap()
}

/// How a command ended: its exit code (`None`: killed by a signal) and what it printed.
pub struct Run {
    /// The exit code.
    pub code: Option<i32>,
    /// Standard output (empty when it was not a pipe).
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

impl Run {
    /// Everything about the run, for a failed assertion's message.
    pub fn describe(&self) -> String {
        format!(
            "exit {:?}\nstdout: {}\nstderr: {}",
            self.code, self.stdout, self.stderr
        )
    }
}

/// Asserts exit status 0.
pub fn succeeded(out: &Run) {
    assert_eq!(out.code, Some(0), "{}", out.describe());
}

/// Asserts exit code `code` (README, "exit status") with `needle` in stderr.
pub fn refused(out: &Run, code: i32, needle: &str) {
    assert!(
        out.code == Some(code) && out.stderr.contains(needle),
        "expected exit {code} naming {needle:?}: {}",
        out.describe()
    );
}

/// Waits for `child` (its stdout and stderr read on threads, so a chatty child cannot
/// block on a full pipe) at most [`TIMEOUT`]; `what` names it in the panic of a hang.
pub fn finish(mut child: Child, what: &str) -> Run {
    let reader = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            String::from_utf8_lossy(&bytes).into_owned()
        })
    };
    let stdout = reader(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = reader(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > TIMEOUT {
            child.kill().unwrap();
            let _ = child.wait();
            panic!("{what} did not end within {TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Run {
        code: status.code(),
        stdout: stdout.join().unwrap(),
        stderr: stderr.join().unwrap(),
    }
}

/// Runs `gridplan args` in `dir`, `env` added and stdout as given (its stderr piped);
/// waits at most [`TIMEOUT`].
pub fn gridplan_with(dir: &Path, args: &[&str], env: &[(&str, &str)], stdout: Stdio) -> Run {
    let child = Command::new(env!("CARGO_BIN_EXE_gridplan"))
        .args(args)
        .current_dir(dir)
        .env_remove("RUST_LOG")
        .envs(env.iter().copied())
        .stdin(Stdio::null())
        .stdout(stdout)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    finish(child, &format!("gridplan {args:?}"))
}

/// Runs `gridplan args` in `dir`; waits at most [`TIMEOUT`].
pub fn gridplan(dir: &Path, args: &[&str]) -> Run {
    gridplan_with(dir, args, &[], Stdio::piped())
}

/// Runs the Slurm scripts `slurm` wrote into `work` with bash in `dir`, as Slurm would:
/// `array.sbatch` for each of the tasks 1 to `tasks` (each must succeed), then
/// `merge.sbatch`, whose run is returned.
pub fn run_slurm_scripts(work: &Path, dir: &Path, tasks: u32) -> Run {
    let bash = |script: &str, task: Option<u32>| {
        let mut command = Command::new("bash");
        command
            .arg(work.join(script))
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        if let Some(task) = task {
            command.env("SLURM_ARRAY_TASK_ID", task.to_string());
        }
        finish(command.spawn().unwrap(), script)
    };
    for task in 1..=tasks {
        succeeded(&bash("array.sbatch", Some(task)));
    }
    bash("merge.sbatch", None)
}

/// Runs `experiment CONFIG --quiet --shard SHARD --output OUTPUT` in `dir`, which must
/// succeed (the shard's results and `shard.jsonl` in `dir/OUTPUT`).
pub fn shard(dir: &Path, config: &str, shard: &str, output: &str) {
    let args = [
        "experiment",
        config,
        "--quiet",
        "--shard",
        shard,
        "--output",
        output,
    ];
    succeeded(&gridplan(dir, &args));
}

/// Writes `dir/nav.toml`, a navigate experiment on the repository's Moving AI map `map`
/// (`arena`, `den520d`) with its first `scenarios` scenarios at the sensor `radii`
/// (`"1, 5"`).
pub fn write_navigate_config(dir: &Path, map: &str, radii: &str, scenarios: usize) {
    let maps = root().join("maps/movingai");
    std::fs::write(
        dir.join("nav.toml"),
        format!(
            "kind = \"navigate\"\nname = \"nav\"\nradii = [{radii}]\n[[maps]]\nmap = {:?}\n\
             scen = {:?}\nscenarios = {scenarios}\n",
            maps.join(format!("{map}.map")).display().to_string(),
            maps.join(format!("{map}.map.scen")).display().to_string(),
        ),
    )
    .unwrap();
}
