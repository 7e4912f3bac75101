//! Where and how a sweep ran, as its results record it: a merge carries its shards'.

use planner_runner::provenance::Machine;
use planner_runner::shard::Shard;
use planner_runner::sweep::{self, SweepArgs};

use crate::common::{root, scratch, NoReport};

/// `merge` recorded its own thread count and wall time (milliseconds of merging) in
/// provenance.json and summary.md; now each shard records its provenance and seconds,
/// and the merge carries them: the most threads (each shard's when they differ) and the
/// sum of the shards' seconds.
#[test]
fn a_merge_records_its_shards_threads_and_seconds() {
    let dir = scratch("merge-provenance");
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        format!(
            "name = \"m\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n[planners.b]\nplanner = \"bfs\"\n",
            root().join("maps/paper/map0*.map").display().to_string()
        ),
    )
    .unwrap();
    let mut shards = Vec::new();
    for (k, threads) in [(1, 1), (2, 3)] {
        let out = dir.join(format!("shard-{k}"));
        let mut args = SweepArgs::new(&config, &NoReport);
        args.output = Some(&out);
        args.threads = threads;
        args.shard = Some(Shard::new(k, 2).unwrap());
        sweep::experiment(&args).unwrap();
        shards.push(out);
    }
    let info = |dir: &std::path::Path| -> serde_json::Value {
        serde_json::from_slice(&std::fs::read(dir.join("provenance.json")).unwrap()).unwrap()
    };
    let seconds: Vec<f64> = shards
        .iter()
        .map(|s| info(s)["seconds"].as_f64().unwrap())
        .collect();
    assert_eq!(info(&shards[0])["provenance"]["threads"], 1);
    assert_eq!(info(&shards[1])["provenance"]["threads"], 3);
    let merged = dir.join("merged");
    sweep::merge(&shards, Some(&merged), None, &NoReport, &|_| {
        Machine::default()
    })
    .unwrap();
    let merged_info = info(&merged);
    assert_eq!(merged_info["provenance"]["threads"], 3, "{merged_info}");
    assert_eq!(
        merged_info["provenance"]["shard_threads"],
        serde_json::json!([1, 3]),
        "{merged_info}"
    );
    let sum = seconds.iter().sum::<f64>();
    let recorded = merged_info["seconds"].as_f64().unwrap();
    assert!((recorded - sum).abs() < 1e-9, "{recorded} vs {sum}");
    let provenance = sweep::read_provenance(&merged).unwrap();
    assert!(
        provenance
            .markdown()
            .contains("- threads: 3 (shards: 1, 3)\n"),
        "{}",
        provenance.markdown()
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The provenance said `commit: unknown` for a config outside a git tree, though the
/// binary knew the commit it was built from (`gridplan --version`). The caller's build
/// commit ([`SweepArgs::build`]) is recorded beside the version, in provenance.json and
/// in summary.md's list, a shard's too; a caller that tells none records none.
#[test]
fn the_provenance_records_the_build_commit() {
    let dir = scratch("build-provenance");
    let config = dir.join("c.toml");
    std::fs::write(
        &config,
        format!(
            "name = \"b\"\n[[maps]]\nfiles = [{:?}]\nproblems = \"corners\"\n[planners.a]\nplanner = \"astar\"\n",
            root().join("maps/paper/map01.map").display().to_string()
        ),
    )
    .unwrap();
    for (build, shard) in [
        (Some("0123456789ab"), None),
        (Some("0123456789ab"), Some(1)),
        (None, Some(1)),
    ] {
        let out = dir.join(format!("out-{build:?}-{shard:?}"));
        let mut args = SweepArgs::new(&config, &NoReport);
        args.output = Some(&out);
        args.build = build;
        args.shard = shard.map(|k| Shard::new(k, 1).unwrap());
        sweep::experiment(&args).unwrap();
        let provenance = sweep::read_provenance(&out).unwrap();
        assert_eq!(provenance.build.as_deref(), build);
        let line = "- gridplan built from commit: 0123456789ab\n";
        assert_eq!(
            provenance.markdown().contains(line),
            build.is_some(),
            "{}",
            provenance.markdown()
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
