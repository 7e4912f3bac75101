//! The declared parameters and the config schema against what the code accepts: every
//! registered planner's listed parameters are its `Config`'s serialized keys with their
//! defaults, every config in configs/ validates against `gridplan schema` (checked by the
//! independent `boon` validator) and wrong types fail it, the schema's top-level and
//! map-set keys are the parser's, and sweeps expand as configs/README.md says.

use std::path::{Path, PathBuf};

use planner_registry as registry;
use planner_runner::{config, schema};
use serde_json::Value;

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The experiment schema compiled by `boon`, a JSON Schema validator independent of the code
/// that writes the schema (draft 2020-12, the schema's own `$schema`).
struct Validator {
    schemas: boon::Schemas,
    index: boon::SchemaIndex,
}

impl Validator {
    /// Every validation error of `instance`, with the place in the config it is about.
    fn errors(&self, instance: &Value) -> Vec<String> {
        match self.schemas.validate(instance, self.index) {
            Ok(()) => Vec::new(),
            Err(error) => vec![format!("{error:#}")],
        }
    }
}

fn validator() -> Validator {
    let schema = schema::experiment_schema(&planner_paper::renderer().section_schemas())
        .expect("the schema builds");
    let mut schemas = boon::Schemas::new();
    let mut compiler = boon::Compiler::new();
    compiler.set_default_draft(boon::Draft::V2020_12);
    let url = "urn:gridplan:experiment-schema";
    compiler
        .add_resource(url, schema)
        .expect("the schema is a JSON document");
    let index = compiler
        .compile(url, &mut schemas)
        .expect("the schema is a valid draft 2020-12 schema");
    Validator { schemas, index }
}

/// A TOML config text as the JSON value the schema describes.
fn as_json(text: &str) -> Value {
    let table: toml::Table = toml::from_str(text).expect("TOML");
    serde_json::to_value(table).expect("JSON")
}

#[test]
fn listed_parameters_are_each_configs_serialized_keys_and_defaults() {
    for entry in registry::PLANNERS {
        let factory = (entry.factory)(&toml::Table::new()).expect("default config");
        let resolved = factory.resolved().as_object().expect("a table").clone();
        let declared = planner_registry::schema::declared(entry.name).expect("declared");
        let keys: Vec<&str> = declared.iter().map(|p| p.key.as_str()).collect();
        let serialized: Vec<&str> = resolved.keys().map(String::as_str).collect();
        // Options left unset serialize as null: still keys of the config.
        assert_eq!(keys, serialized, "{}", entry.name);
        for param in &declared {
            assert!(
                !param.doc.is_empty(),
                "{}.{} has no doc",
                entry.name,
                param.key
            );
            assert!(!param.kind.is_empty(), "{}.{}", entry.name, param.key);
            let default = param.default.clone().unwrap_or(Value::Null);
            assert_eq!(
                default, resolved[&param.key],
                "{}.{}: declared default",
                entry.name, param.key
            );
            if !param.allowed.is_empty() && !default.is_null() {
                assert!(
                    param.allowed.contains(&default),
                    "{}.{}: default {default} not among {:?}",
                    entry.name,
                    param.key,
                    param.allowed
                );
            }
        }
    }
}

#[test]
fn allowed_values_are_what_the_planner_accepts() {
    // Every listed value of every fixed-set parameter builds the planner alone, and a
    // value outside the set fails, for each planner.
    for entry in registry::PLANNERS {
        for param in planner_registry::schema::declared(entry.name).expect("declared") {
            for value in &param.allowed {
                let mut table = toml::Table::new();
                let value: toml::Value =
                    serde_json::from_value(value.clone()).expect("a TOML value");
                table.insert(param.key.clone(), value.clone());
                // Some values need others (a zigzag-only key needs the zigzag): then the
                // error is about that, not an unknown value.
                if let Err(e) = (entry.factory)(&table) {
                    assert!(
                        !e.message.contains("unknown variant")
                            && !e.message.contains("unsupported"),
                        "{}.{} = {value}: {e}",
                        entry.name,
                        param.key
                    );
                }
            }
            if !param.allowed.is_empty() && param.allowed.iter().all(Value::is_u64) {
                // A fixed set of integers: exactly those build the planner (as far as 64).
                for n in 0..=64_u64 {
                    let mut table = toml::Table::new();
                    table.insert(param.key.clone(), toml::Value::Integer(n as i64));
                    assert_eq!(
                        (entry.factory)(&table).is_ok(),
                        param.allowed.contains(&Value::from(n)),
                        "{}.{} = {n}",
                        entry.name,
                        param.key
                    );
                }
            }
            if !param.allowed.is_empty() && param.allowed.iter().all(Value::is_string) {
                let mut table = toml::Table::new();
                table.insert(param.key.clone(), "no_such_value".into());
                assert!(
                    (entry.factory)(&table).is_err(),
                    "{}.{}: an unlisted value",
                    entry.name,
                    param.key
                );
            }
        }
    }
}

#[test]
fn every_config_validates_against_the_schema() {
    let validator = validator();
    let mut n_checked = 0;
    let mut files: Vec<PathBuf> = std::fs::read_dir(repo().join("configs"))
        .expect("configs/")
        .map(|e| e.expect("entry").path())
        .collect();
    for dir in files.clone() {
        if dir.is_dir() {
            files.extend(
                std::fs::read_dir(&dir)
                    .expect("a configs/ subdirectory")
                    .map(|e| e.expect("entry").path()),
            );
        }
    }
    files.sort();
    for path in files {
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        // Only experiment configs (those with [planners]); configs/bench may hold others.
        let text = std::fs::read_to_string(&path).expect("read");
        let json = as_json(&text);
        if json.get("planners").is_none() {
            continue;
        }
        let errors = validator.errors(&json);
        assert!(errors.is_empty(), "{}: {errors:#?}", path.display());
        n_checked += 1;
    }
    assert!(n_checked >= 10, "only {n_checked} configs checked");
}

const GOOD: &str = r#"
name = "mine"
[[maps]]
files = ["m.map"]
problems = "corners"
[planners.a]
planner = "astar"
moves = 8
heuristic = "octile"
"#;

fn check(text: &str, expect_valid: bool) {
    let validator = validator();
    let json = as_json(text);
    let errors = validator.errors(&json);
    assert_eq!(errors.is_empty(), expect_valid, "{text}\n{errors:#?}");
}

#[test]
fn wrong_types_and_unknown_keys_fail_validation() {
    check(GOOD, true);
    // A sweep is a list of the parameter's values.
    check(&GOOD.replace("moves = 8", "moves = [4, 8]"), true);
    check(&GOOD.replace("moves = 8", "moves = \"eight\""), false);
    check(&GOOD.replace("moves = 8", "moves = 6"), false);
    check(&GOOD.replace("moves = 8", "moves = [4, 6]"), false);
    check(&GOOD.replace("moves = 8", "moves = []"), false);
    check(&GOOD.replace("\"octile\"", "\"octil\""), false);
    check(&GOOD.replace("heuristic", "heuristics"), false);
    // A parameter of another planner.
    check(&GOOD.replace("moves = 8", "r_threshold = 3.0"), false);
    check(&GOOD.replace("\"astar\"", "\"no_such_planner\""), false);
    check(&GOOD.replace("name = \"mine\"", "name = 7"), false);
    check(
        &GOOD.replace("name = \"mine\"", "name = \"mine\"\nthreds = 2"),
        false,
    );
    check(
        &GOOD.replace("problems = \"corners\"", "problems = 3"),
        false,
    );
}

/// The keys serde lists in "unknown field `x`, expected one of `a`, `b`".
fn expected_keys(message: &str) -> Vec<String> {
    let list = message
        .split("expected one of ")
        .nth(1)
        .or_else(|| message.split("expected ").nth(1))
        .expect("a list of keys");
    list.lines()
        .next()
        .unwrap_or_default()
        .split(", ")
        .flat_map(|k| k.split(" or "))
        .map(|k| k.trim().trim_matches('`').to_string())
        .collect()
}

fn schema_keys(schema: &Value) -> Vec<String> {
    schema["properties"]
        .as_object()
        .expect("properties")
        .keys()
        .cloned()
        .collect()
}

#[test]
fn the_schemas_runner_keys_are_the_parsers() {
    let schema =
        schema::experiment_schema(&planner_paper::renderer().section_schemas()).expect("schema");
    let top = config::parse(
        Path::new("t.toml"),
        &GOOD.replace("name = \"mine\"", "name = \"mine\"\nzz_unknown = 1"),
    )
    .expect_err("an unknown key");
    // A key added to the parser needs its line in src/schema.rs (and configs/README.md).
    assert_eq!(schema_keys(&schema), expected_keys(&top.message));
    let maps = config::parse(
        Path::new("t.toml"),
        &GOOD.replace(
            "problems = \"corners\"",
            "problems = \"corners\"\nzz_unknown = 1",
        ),
    )
    .expect_err("an unknown key");
    let map_set = &schema["properties"]["maps"]["items"];
    assert_eq!(schema_keys(map_set), expected_keys(&maps.message));
    let budget = config::parse(
        Path::new("t.toml"),
        &GOOD.replace(
            "name = \"mine\"",
            "name = \"mine\"\n[budget]\nzz_unknown = 1\n",
        ),
    )
    .expect_err("an unknown key");
    assert_eq!(
        schema_keys(&schema["properties"]["budget"]),
        expected_keys(&budget.message)
    );
}

fn labels(text: &str) -> Result<Vec<String>, String> {
    config::parse(&repo().join("configs/t.toml"), text)
        .map(|e| e.planners.into_iter().map(|p| p.label).collect())
        .map_err(|e| e.to_string())
}

const SWEEP: &str = r#"
name = "sweep"
[[maps]]
files = ["../maps/paper/map01.map"]
problems = "corners"
[planners.a]
planner = "astar"
moves = [4, 8]
weight = 1.5
heuristic = ["manhattan", "octile"]
[planners.b]
planner = "bfs"
"#;

#[test]
fn sweeps_expand_to_one_label_per_combination_in_table_order() {
    assert_eq!(
        labels(SWEEP).expect("valid"),
        [
            "a[moves=4,heuristic=manhattan]",
            "a[moves=4,heuristic=octile]",
            "a[moves=8,heuristic=manhattan]",
            "a[moves=8,heuristic=octile]",
            "b",
        ]
    );
    // Each label runs its combination, the other parameters as written.
    let experiment = config::parse(&repo().join("configs/t.toml"), SWEEP).expect("valid");
    let resolved = experiment.planners[2].factory.resolved();
    assert_eq!(resolved["moves"], 8);
    assert_eq!(resolved["heuristic"], "manhattan");
    assert_eq!(resolved["weight"], 1.5);
    // Floats keep their decimal point, strings lose their quotes.
    let radius = SWEEP.replace(
        "planner = \"bfs\"",
        "planner = \"pastar\"\nradius = [1.0, \"size\"]",
    );
    assert_eq!(
        labels(&radius).expect("valid")[4..],
        ["b[radius=1.0]", "b[radius=size]"]
    );
}

#[test]
fn bad_sweeps_are_errors_that_name_the_key() {
    let empty = labels(&SWEEP.replace("moves = [4, 8]", "moves = []")).expect_err("empty");
    assert!(
        empty.contains("t.toml:8:9") && empty.contains("key `moves`: an empty list"),
        "{empty}"
    );
    let clash = SWEEP.replace("[planners.b]", "[planners.\"a[moves=4,heuristic=octile]\"]");
    let clash = labels(&clash).expect_err("a label twice");
    assert!(clash.contains("appears twice"), "{clash}");
    // A wrong value inside a sweep is reported at its key, with the combination's label.
    let bad = labels(&SWEEP.replace("moves = [4, 8]", "moves = [4, 6]")).expect_err("bad");
    assert!(
        bad.contains("t.toml:8:1: planner `a[moves=6,heuristic=manhattan]`")
            && bad.contains("parameter `moves`"),
        "{bad}"
    );
}
