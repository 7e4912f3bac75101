//! `slurm`'s working directory: `DIR-slurm` beside the results directory however the
//! results directory is spelt, and a results directory without a name of its own refused
//! before anything is written.

use std::path::{Path, PathBuf};

use planner_runner::provenance::Machine;
use planner_runner::shard::Shard;
use planner_runner::slurm::{slurm, SlurmArgs, SlurmError};
use planner_runner::sweep::{experiment, merge, SweepArgs};

use crate::common::{root, scratch, NoReport};

/// tiny.toml in `dir`: arena.map's first 3 scenarios, one A*.
fn tiny(dir: &Path) -> PathBuf {
    let map = root().join("maps/movingai/arena.map");
    let text = format!(
        "name = \"tiny\"\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\nscen = {:?}\nlimit = 3\n\
         [planners.a]\nplanner = \"astar\"\n",
        map.display().to_string(),
        format!("{}.scen", map.display())
    );
    let path = dir.join("tiny.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// `slurm --shards 2 tiny.toml --output OUTPUT` from `current_dir`.
fn write_jobs(config: &Path, current_dir: &Path, output: &str) -> Result<PathBuf, SlurmError> {
    let jobs = slurm(&SlurmArgs {
        config: config.to_path_buf(),
        shards: 2,
        output: Some(PathBuf::from(output)),
        binary: PathBuf::from("/usr/bin/gridplan"),
        current_dir: current_dir.to_path_buf(),
        ..SlurmArgs::default()
    })?;
    Ok(jobs.array_script.parent().unwrap().to_path_buf())
}

/// Every file and directory under `dir`, relative to it.
fn listing(dir: &Path) -> Vec<PathBuf> {
    let mut all = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(next) = todo.pop() {
        for entry in std::fs::read_dir(&next).unwrap() {
            let path = entry.unwrap().path();
            all.push(path.strip_prefix(dir).unwrap().to_path_buf());
            if path.is_dir() {
                todo.push(path);
            }
        }
    }
    all.sort();
    all
}

/// `--output o2/` (or `o2/.`, `./o2`) put the working directory at `o2/-slurm`, inside
/// the results directory, and after the array ran the merge job failed: "output
/// '.../o2/' is not a gridplan results directory: it holds 1 entry (-slurm)" (exit 5).
/// The working directory is `o2-slurm` beside `o2` now, the scripts name `o2` without
/// the slash, and the shards run where the array script puts them merge into `o2`.
#[test]
fn a_trailing_slash_or_dot_keeps_the_work_dir_beside_the_output() {
    let dir = scratch("slurm-slash");
    let config = tiny(&dir);
    for output in ["o2/", "o2/.", "./o2", "o2//"] {
        let work = write_jobs(&config, &dir, output).unwrap();
        assert_eq!(work, dir.join("o2-slurm"), "{output}");
        assert!(!dir.join("o2").exists(), "{output}: the output was made");
        let merge_script = std::fs::read_to_string(work.join("merge.sbatch")).unwrap();
        let named = format!("--output '{}'", dir.join("o2").display());
        assert!(merge_script.contains(&named), "{output}: {merge_script}");
        // What the array's tasks and the merge job then do.
        let shards: Vec<PathBuf> = (1..=2).map(|k| work.join(format!("shard-{k}"))).collect();
        for (k, shard) in shards.iter().enumerate() {
            experiment(&SweepArgs {
                output: Some(shard),
                shard: Some(Shard::new(k as u64 + 1, 2).unwrap()),
                ..SweepArgs::new(&config, &NoReport)
            })
            .unwrap();
        }
        let machine = |_: &Path| Machine::default();
        let report = merge(&shards, Some(&dir.join("o2")), None, &NoReport, &machine);
        assert_eq!(report.unwrap().n_runs, 3, "{output}");
        std::fs::remove_dir_all(dir.join("o2")).unwrap();
        std::fs::remove_dir_all(&work).unwrap();
    }
    // `.` is the current directory, and its working directory is beside it.
    let current = dir.join("here");
    std::fs::create_dir(&current).unwrap();
    assert_eq!(
        write_jobs(&config, &current, ".").unwrap(),
        dir.join("here-slurm")
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The root and a path ending in `..` name no results directory of their own: refused,
/// naming `--output`, before anything is written.
#[test]
fn an_output_without_a_name_is_refused_before_anything_is_written() {
    let dir = scratch("slurm-nameless");
    let config = tiny(&dir);
    let current = dir.join("a/b");
    std::fs::create_dir_all(&current).unwrap();
    let before = listing(&dir);
    for output in ["..", "../..", "x/..", "/", "./.."] {
        let error = write_jobs(&config, &current, output).unwrap_err();
        assert!(
            matches!(error, SlurmError::OutputName { .. }),
            "{output}: {error}"
        );
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("--output: {output} does not name")),
            "{message}"
        );
        assert_eq!(listing(&dir), before, "{output}: something was written");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `slurm CONFIG --shards N` with `options`, from `dir`, into `dir/out-slurm`.
fn write_with(
    config: &Path,
    dir: &Path,
    shards: u64,
    options: SlurmArgs,
) -> Result<PathBuf, SlurmError> {
    let jobs = slurm(&SlurmArgs {
        config: config.to_path_buf(),
        shards,
        output: Some(PathBuf::from("out")),
        binary: PathBuf::from("/usr/bin/gridplan"),
        current_dir: dir.to_path_buf(),
        ..options
    })?;
    Ok(jobs.array_script.parent().unwrap().to_path_buf())
}

/// `--cpus-per-task 300` wrote scripts whose every task failed ("error: 300 worker
/// threads asked for; at most 256": the tasks run `--threads 300`), while
/// `--cpus-per-task 0` was refused when they were written. Above the sweep's thread limit
/// it is refused too now, naming --cpus-per-task, before anything is written.
#[test]
fn cpus_per_task_above_the_thread_limit_is_refused() {
    let dir = scratch("slurm-cpus");
    let config = tiny(&dir);
    let before = listing(&dir);
    for cpus in [257, 300, u32::MAX] {
        let options = SlurmArgs {
            cpus_per_task: Some(cpus),
            ..SlurmArgs::default()
        };
        let error = write_with(&config, &dir, 2, options).unwrap_err();
        assert!(matches!(error, SlurmError::Value { .. }), "{error}");
        assert_eq!(
            error.to_string(),
            format!(
                "--cpus-per-task \"{cpus}\": at most 256 (it is also the tasks' worker threads, at most 256 in a sweep)"
            )
        );
        assert_eq!(listing(&dir), before, "{cpus}: something was written");
    }
    let options = SlurmArgs {
        cpus_per_task: Some(256),
        ..SlurmArgs::default()
    };
    let work = write_with(&config, &dir, 2, options).unwrap();
    let array = std::fs::read_to_string(work.join("array.sbatch")).unwrap();
    assert!(array.contains("#SBATCH --cpus-per-task=256\n") && array.contains(" --threads 256 "));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--mem 18446744073709551616M` was written into the scripts, and sbatch refused them
/// at submission ("Invalid --mem specification"). A size that does not fit Slurm's signed
/// 64-bit count of megabytes (the number itself, or once its unit is applied, which sbatch
/// would wrap) is refused now, naming --mem, before anything is written.
#[test]
fn a_mem_beyond_what_sbatch_reads_is_refused() {
    let dir = scratch("slurm-mem");
    let config = tiny(&dir);
    let before = listing(&dir);
    let with = |mem: &str| SlurmArgs {
        mem: Some(mem.to_string()),
        ..SlurmArgs::default()
    };
    for mem in [
        "18446744073709551616M",
        "18446744073709551616",
        "9223372036854775808",
        "9007199254740992G",
        "8796093022208T",
        "99999999999999999999999K",
    ] {
        let error = write_with(&config, &dir, 2, with(mem)).unwrap_err();
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("--mem {mem:?}: a whole number of megabytes"))
                && message.contains("at most 8 EiB"),
            "{message}"
        );
        assert_eq!(listing(&dir), before, "{mem}: something was written");
    }
    for mem in [
        "9223372036854775807",
        "9223372036854775807K",
        "9007199254740991G",
        "4G",
        "0",
    ] {
        write_with(&config, &dir, 2, with(mem)).unwrap();
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// merge.log was overwritten by each merge (no `--open-mode=append` in merge.sbatch)
/// while the tasks' logs were appended to, and no log line said which job or start it
/// came from. Both scripts append now, and each start writes its date, SLURM_JOB_ID,
/// SLURM_ARRAY_TASK_ID and SLURM_RESTART_COUNT first (run here with bash).
#[test]
fn both_logs_are_appended_to_and_say_each_start() {
    let dir = scratch("slurm-logs");
    let config = tiny(&dir);
    let work = write_with(&config, &dir, 2, SlurmArgs::default()).unwrap();
    for script in ["array.sbatch", "merge.sbatch"] {
        let text = std::fs::read_to_string(work.join(script)).unwrap();
        assert!(text.contains("\n#SBATCH --open-mode=append\n"), "{text}");
        let echo = text
            .lines()
            .find(|l| l.starts_with("echo "))
            .unwrap_or_else(|| panic!("{script}: no start line: {text}"));
        // Only the `exec` of gridplan, which the test does not run, follows it.
        let mut bash = String::from("set -euo pipefail\n");
        bash.push_str(echo);
        let out = std::process::Command::new("bash")
            .args(["-c", &bash])
            .env("SLURM_JOB_ID", "55")
            .env("SLURM_ARRAY_TASK_ID", "2")
            .env("SLURM_RESTART_COUNT", "1")
            .output()
            .unwrap();
        let line = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "{script}: {line}");
        assert!(line.starts_with("== 20"), "{line}");
        assert!(
            line.ends_with(" start: job 55, array task 2, restart 1\n"),
            "{script}: {line}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The array's tasks always resume now, so the records an earlier `slurm` of the same
/// output left that a task would refuse (another config's, another shard count's) would
/// fail every such task. `slurm` refuses them before writing anything, naming the shard's
/// directory to move away, and removes nothing.
#[test]
fn shards_their_tasks_would_not_resume_are_refused() {
    let dir = scratch("slurm-other-sweep");
    let config = tiny(&dir);
    let work = write_with(&config, &dir, 2, SlurmArgs::default()).unwrap();
    let shard = work.join("shard-2");
    experiment(&SweepArgs {
        output: Some(&shard),
        shard: Some(Shard::new(2, 2).unwrap()),
        ..SweepArgs::new(&config, &NoReport)
    })
    .unwrap();
    // The same config and shard count: written again.
    write_with(&config, &dir, 2, SlurmArgs::default()).unwrap();
    let before = listing(&dir);
    // Another shard count.
    let error = write_with(&config, &dir, 3, SlurmArgs::default()).unwrap_err();
    assert!(
        matches!(error, SlurmError::OtherSweep { shard: 2, .. }),
        "{error}"
    );
    let message = error.to_string();
    for needle in [
        "shard-2/shard.stream: it holds the records of shard 2 of 2 (an earlier `slurm` of this output with --shards 2), not of shard 2 of 3",
        "give another --output, or, once no task of an earlier array runs, move ",
        "shard-2 away to start shard 2 over",
    ] {
        assert!(message.contains(needle), "{needle}: {message}");
    }
    assert_eq!(listing(&dir), before);
    // Another config.
    let edited = std::fs::read_to_string(&config)
        .unwrap()
        .replace("limit = 3", "limit = 2");
    std::fs::write(&config, edited).unwrap();
    let error = write_with(&config, &dir, 2, SlurmArgs::default()).unwrap_err();
    assert!(
        matches!(error, SlurmError::OtherSweep { shard: 2, .. }),
        "{error}"
    );
    assert!(
        error
            .to_string()
            .contains("it holds records of another config (experiment \"tiny\""),
        "{error}"
    );
    assert!(shard.join("shard.stream").is_file());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The jobs file `--submit` reads back is read only as a regular file, and at most a
/// bounded part of it: a link planted at its name (to `/dev/zero`, which never ends) is an
/// error naming it, not followed; the ids of a file gridplan wrote are read.
#[test]
fn the_jobs_file_is_read_only_as_a_regular_file() {
    let work = scratch("slurm-jobs-file");
    std::fs::create_dir_all(&work).unwrap();
    let jobs = work.join(planner_runner::slurm::JOBS_FILE);
    assert!(planner_runner::slurm::submitted(&work).unwrap().is_empty());
    planner_runner::slurm::record_submitted(&work, &["55".into(), "56".into()]).unwrap();
    assert_eq!(
        planner_runner::slurm::submitted(&work).unwrap(),
        ["55", "56"]
    );
    std::fs::remove_file(&jobs).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &jobs).unwrap();
    let error = planner_runner::slurm::submitted(&work)
        .unwrap_err()
        .to_string();
    assert!(
        error.contains("jobs") && error.contains("not a regular file (a symbolic link)"),
        "{error}"
    );
    std::fs::remove_dir_all(&work).unwrap();
}
