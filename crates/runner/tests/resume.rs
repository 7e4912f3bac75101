//! `--resume` over finished results it cannot continue (another config's, another
//! shard's) is refused as over an interrupted sweep's stream, and keeps them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use planner_runner::readback::ResumeError;
use planner_runner::shard::Shard;
use planner_runner::sweep::{experiment, SweepArgs};
use planner_runner::{ErrorClass, RunnerError};

use crate::common::{root, scratch, NoReport};

/// A config of arena.map's first 20 scenarios with A* and `repeats` repeats, in `dir`
/// (`rN.toml`; its experiment is `r` whatever N).
fn config(dir: &Path, repeats: u32) -> PathBuf {
    let map = root().join("maps/movingai/arena.map");
    let text = format!(
        "name = \"r\"\nrepeats = {repeats}\nfigures = \"none\"\n[[maps]]\nfiles = [{:?}]\n\
         scen = {:?}\nlimit = 20\n[planners.a]\nplanner = \"astar\"\n",
        map.display().to_string(),
        format!("{}.scen", map.display())
    );
    let path = dir.join(format!("r{repeats}.toml"));
    std::fs::write(&path, text).unwrap();
    path
}

/// Every file under `dir` (its subdirectories' too) with its bytes.
fn files(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut all = BTreeMap::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(next) = todo.pop() {
        for entry in std::fs::read_dir(&next).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                todo.push(path);
            } else {
                all.insert(path.clone(), std::fs::read(&path).unwrap());
            }
        }
    }
    all
}

/// A sweep of `config` into `output`, resumed (`--resume`) or not.
fn sweep(
    config: &Path,
    output: &Path,
    shard: Option<Shard>,
    resume: bool,
) -> Result<planner_runner::sweep::Report, RunnerError> {
    experiment(&SweepArgs {
        output: Some(output),
        shard,
        resume,
        ..SweepArgs::new(config, &NoReport)
    })
}

/// `--resume` over the finished results of an edited config deleted them with only a
/// warning ("holds the finished results of another config ... every run runs", exit
/// 0), while the same change over an interrupted sweep was refused with exit 2. It is
/// refused now, as a usage error (exit 2) that says to run without --resume to start
/// over, and the results and the directory beside them are left as they were; without
/// --resume the edited config runs. So for a shard's finished results resumed as
/// another shard, and a whole sweep's as a shard.
#[test]
fn resuming_the_finished_results_of_another_config_or_shard_is_refused() {
    let dir = scratch("resume-finished");
    let output = dir.join("res");
    let first = config(&dir, 2);
    let edited = config(&dir, 3);
    sweep(&first, &output, None, false).unwrap();
    let before = files(&dir);
    let refused = |shard, wanted: &dyn Fn(&ResumeError) -> bool| {
        let error = sweep(&edited, &output, shard, true).unwrap_err();
        assert_eq!(error.class(), ErrorClass::Usage, "{error}");
        assert!(
            matches!(&error, RunnerError::Resume(e) if wanted(e)),
            "{error:?}"
        );
        assert!(
            error
                .to_string()
                .contains("Run without --resume to start over"),
            "{error}"
        );
        assert!(files(&dir) == before, "{shard:?}: the directory changed");
        assert!(!dir.join(".res.stream").exists());
    };
    refused(None, &|e| matches!(e, ResumeError::OtherConfig { .. }));
    let report = sweep(&edited, &output, None, false).unwrap();
    assert_eq!(report.n_runs, 60);

    // A whole sweep's finished results resumed as a shard; a shard's, resumed as another
    // shard and as the whole sweep.
    let shard = |k| Some(Shard::new(k, 3).unwrap());
    let is_other_shard = |e: &RunnerError| matches!(e, RunnerError::Resume(e) if matches!(**e, ResumeError::OtherShard { .. }));
    let before = files(&dir);
    let error = sweep(&edited, &output, shard(1), true).unwrap_err();
    assert!(is_other_shard(&error), "{error:?}");
    assert!(files(&dir) == before, "the directory changed");
    sweep(&edited, &output, shard(2), false).unwrap();
    let before = files(&dir);
    for other in [shard(1), None] {
        let error = sweep(&edited, &output, other, true).unwrap_err();
        assert!(is_other_shard(&error), "{other:?}: {error:?}");
        assert!(
            error
                .to_string()
                .contains("Run without --resume to start over"),
            "{error}"
        );
        assert!(files(&dir) == before, "{other:?}: the directory changed");
    }
    // The same shard resumes: nothing runs again.
    let report = sweep(&edited, &output, shard(2), true).unwrap();
    assert_eq!(report.interrupted, None);
    std::fs::remove_dir_all(&dir).unwrap();
}
