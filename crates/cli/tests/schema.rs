//! `gridplan schema` covers every config `experiment` runs: each config in configs/ (the
//! runner's and the replanning kinds', `configs/replan/*.toml`) validates against it
//! (checked by the independent `boon` validator), and an unknown key fails it in either
//! kind.

use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The composed schema compiled by `boon`.
struct Validator {
    schemas: boon::Schemas,
    index: boon::SchemaIndex,
}

impl Validator {
    fn new() -> Validator {
        let schema = gridplan::schema().expect("the schema builds");
        let mut schemas = boon::Schemas::new();
        let mut compiler = boon::Compiler::new();
        compiler.set_default_draft(boon::Draft::V2020_12);
        let url = "urn:gridplan:schema";
        compiler.add_resource(url, schema).expect("JSON");
        let index = compiler
            .compile(url, &mut schemas)
            .expect("a valid draft 2020-12 schema");
        Validator { schemas, index }
    }

    fn valid(&self, text: &str) -> Result<(), String> {
        let table: toml::Table = toml::from_str(text).expect("TOML");
        let json = serde_json::to_value(table).expect("JSON");
        self.schemas
            .validate(&json, self.index)
            .map_err(|e| format!("{e:#}"))
    }
}

/// Every `.toml` under `dir`, recursively.
fn tomls(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a directory") {
        let path = entry.expect("entry").path();
        if path.is_dir() {
            tomls(&path, out);
        } else if path.extension().and_then(|e| e.to_str()) == Some("toml") {
            out.push(path);
        }
    }
}

#[test]
fn every_runner_and_replanning_config_validates() {
    let validator = Validator::new();
    let mut files = Vec::new();
    tomls(&repo().join("configs"), &mut files);
    files.sort();
    let (mut runner, mut replan) = (0, 0);
    for path in files {
        let text = std::fs::read_to_string(&path).expect("read");
        let table: toml::Table = toml::from_str(&text).expect("TOML");
        // Only configs `experiment` runs (configs/bench and the like may hold others).
        if table.contains_key("kind") {
            replan += 1;
        } else if table.contains_key("planners") {
            runner += 1;
        } else {
            continue;
        }
        if let Err(e) = validator.valid(&text) {
            panic!("{}: {e}", path.display());
        }
    }
    assert!(runner >= 10, "only {runner} runner configs checked");
    assert!(replan >= 2, "only {replan} replanning configs checked");
}

#[test]
fn unknown_keys_and_wrong_kinds_fail() {
    let validator = Validator::new();
    let navigate = std::fs::read_to_string(repo().join("configs/replan/navigate.toml"))
        .expect("configs/replan/navigate.toml");
    assert_eq!(validator.valid(&navigate), Ok(()));
    // The replanning config's keys are its parser's: a misspelt one fails, and so does a
    // kind that is neither.
    let misspelt = format!("radius = [1]\n{navigate}");
    assert!(validator.valid(&misspelt).is_err());
    let other = navigate.replacen("kind = \"navigate\"", "kind = \"sideways\"", 1);
    assert_ne!(other, navigate, "the config names its kind");
    assert!(validator.valid(&other).is_err());
    // A runner config with a replanning key fails (no config is both).
    let runner = std::fs::read_to_string(repo().join("configs/paper.toml")).expect("paper");
    assert_eq!(validator.valid(&runner), Ok(()));
    assert!(validator
        .valid(&format!("kind = \"navigate\"\n{runner}"))
        .is_err());
    assert!(validator.valid(&format!("threds = 2\n{runner}")).is_err());
}

/// The schema accepted configs the parser refuses: a section's options (a seed 002 table
/// without `proposed`, an option a section does not take), a `u32` beyond its range, a
/// name longer than 100 characters, line 0 of a scenario file, `limit = 0`, and the
/// replanning configs' empty or repeated lists, unknown planners and bad names. Each
/// of these is refused by both.
#[test]
fn configs_the_parser_refuses_fail_the_schema() {
    let validator = Validator::new();
    let runner = "name = \"x\"\n[[maps]]\nfiles = [\"tiny.map\"]\nproblems = \"corners\"\n[planners.p]\nplanner = \"astar\"\n";
    let scen = runner.replace("problems = \"corners\"", "scen = \"t.scen\"");
    assert_eq!(validator.valid(runner), Ok(()));
    assert_eq!(validator.valid(&scen), Ok(()));
    let with = |top: &str| format!("{top}\n{runner}");
    let long_name = runner.replace("\"x\"", &format!("\"{}\"", "x".repeat(101)));
    let refused_runner = [
        with("sections = [\"seed002\"]"),
        with("sections = [{ name = \"seed002\" }]"),
        with("sections = [{ name = \"seed002\", proposed = 5 }]"),
        with("sections = [{ name = \"seed002\", planner = \"pastar\" }]"),
        with("sections = [{ name = \"seed002_capso\", proposed = \"capso\" }]"),
        with("sections = [{ name = \"paired\", baseline = \"p\", proposed = \"astar\" }]"),
        with("sections = [{ name = \"aggregate\", baseline = \"p\" }]"),
        with("sections = [{ name = \"nosuch\" }]"),
        with("repeats = 4294967296"),
        long_name,
        runner.replace(
            "problems = \"corners\"",
            "pairs = [{ start = [4294967296, 0], goal = [1, 1] }]",
        ),
        runner.replace(
            "problems = \"corners\"",
            "problems = \"start\"\nstart = [0, 4294967296]",
        ),
        scen.replace("scen = \"t.scen\"", "scen = \"t.scen\"\nlines = [0, 2]"),
        scen.replace("scen = \"t.scen\"", "scen = \"t.scen\"\nlimit = 0"),
        scen.replace("scen = \"t.scen\"", "scen = \"t.scen\"\nevery = 0"),
    ];
    let accepted_runner = [
        with("sections = [\"paired\", { name = \"seed002\", proposed = \"astar\" }]"),
        with("sections = [{ name = \"paired\", baseline = \"p\" }, { name = \"seed002_capso\", planner = \"astar\" }]"),
        with("repeats = 4294967295"),
    ];
    let navigate = "kind = \"navigate\"\nname = \"x\"\nradii = [1]\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n";
    let dynamic = "kind = \"dynamic\"\nname = \"x\"\n[[maps]]\nmap = \"a.map\"\nscen = \"a.scen\"\n[toggles]\nevents = 2\nk = 1\nradius = 3\nseeds = [1]\n";
    assert_eq!(validator.valid(navigate), Ok(()));
    assert_eq!(validator.valid(dynamic), Ok(()));
    let refused_replan = [
        navigate.replace("name = \"x\"", "name = \"a b\""),
        navigate.replace("radii = [1]", "radii = []"),
        navigate.replace("radii = [1]", "radii = [1, 1]"),
        navigate.replace("radii = [1]", "radii = [0]"),
        format!("compare = []\n{navigate}"),
        format!("compare = [\"dstar\"]\n{navigate}"),
        format!("compare = [\"lpastar\", \"lpastar\"]\n{navigate}"),
        dynamic.replace("seeds = [1]", "seeds = []"),
        dynamic.replace("seeds = [1]", "seeds = [1, 1]"),
        dynamic.replace("k = 1", "k = 4294967296"),
    ];
    for text in refused_runner.iter().chain(&refused_replan) {
        assert!(validator.valid(text).is_err(), "accepted:\n{text}");
    }
    for text in accepted_runner {
        assert_eq!(validator.valid(&text), Ok(()), "{text}");
    }
}
