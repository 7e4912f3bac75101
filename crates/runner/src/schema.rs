//! The JSON Schema of experiment configs, for `gridplan schema` and editors.
//!
//! The planner tables come from each planner's declared parameters
//! ([`planner_registry::schema::declared`]), so they cannot drift from what the planner
//! accepts. The schema's top level (the runner's own keys) is written here by hand; the
//! runner's tests compare its key lists with the ones the config parser accepts. The
//! summary.md section names are the report's, passed in by the caller.

use planner_registry as registry;
use planner_registry::schema::{declared, Param, RegistryError};
use serde_json::{json, Map, Value};

/// The schema of a `budget` table (planner-api's `Budget`).
fn budget_schema() -> Value {
    json!({
        "type": "object",
        "description": "Limits per run; a planner table's own `budget` replaces the experiment's.",
        "additionalProperties": false,
        "properties": {
            "max_expansions": {
                "type": "integer", "minimum": 0,
                "description": "Stop after this many expansions (each planner says what one expansion is)."
            },
            "max_time_ms": {
                "type": "integer", "minimum": 0,
                "description": "Stop after this much wall-clock time (not deterministic)."
            },
            "max_memory_mb": {
                "type": "integer", "minimum": 0,
                "description": "Refuse to plan when the planner's per-cell state for the grid would take more than this many MiB."
            }
        }
    })
}

/// A parameter's schema in a planner table: its own, or (for a parameter whose values
/// are not lists) also a non-empty list of them, a sweep (configs/README.md).
fn sweepable(param: &Param) -> Value {
    let mut own = param.schema.clone();
    if let Some(object) = own.as_object_mut() {
        object.remove("default");
    }
    if param.is_list {
        return param.schema.clone();
    }
    let mut wrapper = Map::new();
    if !param.doc.is_empty() {
        wrapper.insert("description".into(), param.doc.clone().into());
    }
    if let Some(default) = &param.default {
        wrapper.insert("default".into(), default.clone());
    }
    wrapper.insert(
        "anyOf".into(),
        json!([own, { "type": "array", "items": own, "minItems": 1,
                      "description": "A sweep: one label per value." }]),
    );
    Value::Object(wrapper)
}

/// The schema of one planner table for registry planner `name`.
fn planner_table_schema(name: &str, summary: &str) -> Result<Value, RegistryError> {
    let mut properties = Map::new();
    properties.insert(
        "planner".into(),
        json!({ "const": name, "description": summary }),
    );
    properties.insert("budget".into(), budget_schema());
    properties.insert(
        "costs".into(),
        json!({ "const": "ignore",
                "description": "Run on weighted maps with their weights left out (planners that do not honour cell costs are refused otherwise)." }),
    );
    properties.insert(
        "compare".into(),
        json!({
            "type": "object",
            "description": "Mark these metrics against another planner's published values.",
            "additionalProperties": false,
            "required": ["with", "metrics"],
            "properties": {
                "with": { "type": "string" },
                "metrics": { "type": "array", "items": { "type": "string" } }
            }
        }),
    );
    for param in declared(name)? {
        properties.insert(param.key.clone(), sweepable(&param));
    }
    Ok(json!({
        "type": "object",
        "title": name,
        "additionalProperties": false,
        "required": ["planner"],
        "properties": properties,
    }))
}

/// The top-level keys of an experiment config that this schema declares (the runner's
/// tests compare them with the parser's).
pub const TOP_LEVEL_KEYS: &[&str] = &[
    "name",
    "description",
    "output",
    "threads",
    "repeats",
    "seed",
    "budget",
    "figures",
    "figures_per_map",
    "figures_pick",
    "figures_expanded",
    "charts",
    "ompl",
    "paths",
    "outputs",
    "published",
    "test",
    "sections",
    "maps",
    "planners",
];

/// The schema of a map set's `costs` table (configs/README.md).
fn costs_schema() -> Value {
    json!({
        "type": "object", "additionalProperties": false,
        "description": "Cell costs (weights): graded ROS maps by nav2's cost bands, a weight file, or Moving AI terrain letters.",
        "properties": {
            "rule": { "enum": ["mean", "entered"] },
            "lethal": { "type": "integer", "minimum": 1, "maximum": 255 },
            "unknown": { "type": "integer", "minimum": 0, "maximum": 254 },
            "weights": { "type": "string" },
            "swamp": { "type": "integer", "minimum": 1, "maximum": 65535 },
            "water": { "type": "integer", "minimum": 1, "maximum": 65535 }
        }
    })
}

/// The JSON Schema (draft 2020-12) of experiment configs, for `gridplan schema` and
/// editors: the top-level keys, the `[[maps]]` sets, and the planner tables as a `oneOf`
/// over `planner = "<name>"`, each with that planner's declared parameters. `sections` are
/// the names `sections = [...]` may use (the report's catalogue).
pub fn experiment_schema(sections: &[&str]) -> Result<Value, RegistryError> {
    let mut planners = Vec::new();
    for entry in registry::PLANNERS {
        planners.push(planner_table_schema(entry.name, entry.summary)?);
    }
    let cell = json!({ "type": "array", "items": { "type": "integer", "minimum": 0 },
                       "minItems": 2, "maxItems": 2 });
    let count = json!({ "type": "integer", "minimum": 0 });
    let map_set = json!({
        "type": "object", "additionalProperties": false, "required": ["files"],
        "properties": {
            "files": { "type": "array", "items": { "type": "string" },
                       "description": "Map files or globs, relative to the config." },
            "problems": { "enum": ["corners", "file", "start"] },
            "start": cell,
            "pairs": { "type": "array", "items": {
                "type": "object", "additionalProperties": false,
                "required": ["start", "goal"],
                "properties": { "start": cell, "goal": cell }
            }},
            "scen": { "type": "string" },
            "buckets": { "type": "array", "items": count },
            "lines": { "type": "array", "items": count, "minItems": 2, "maxItems": 2 },
            "every": { "type": "integer", "minimum": 1 },
            "limit": count,
            "inflation": count,
            "inflate_unknown": { "type": "boolean" },
            "obstacle": { "enum": [0, 1],
                          "description": ".csv maps only: the value of a cell that is an obstacle (default 0)." },
            "costs": costs_schema()
        }
    });
    let schema = json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "gridplan experiment config",
        "description": "An experiment: every map x problem x planner x repeat (configs/README.md).",
        "type": "object",
        "additionalProperties": false,
        "required": ["name", "maps", "planners"],
        "properties": {
            "name": { "type": "string", "pattern": "^[A-Za-z0-9_-]+$",
                      "description": "The experiment's name; names the output directory." },
            "description": { "type": "string" },
            "output": { "type": "string",
                        "description": "Output directory (default results/<name>)." },
            "threads": { "type": "integer", "minimum": 0, "maximum": crate::config::MAX_THREADS,
                         "description": "Worker threads; 0 = one per core." },
            "repeats": { "type": "integer", "minimum": 1,
                         "description": "Runs per (map, problem, planner)." },
            "seed": { "type": "integer", "minimum": 0,
                      "description": "Base seed; seeded planners get seed + repeat." },
            "budget": budget_schema(),
            "figures": { "enum": ["all", "comparisons", "none"] },
            "figures_per_map": count,
            "figures_pick": { "enum": ["first", "hardest", "buckets"] },
            "figures_expanded": { "type": "boolean",
                                  "description": "Also draw each drawn run's expanded cells." },
            "charts": { "type": "array", "items": {
                "type": "object", "additionalProperties": false, "required": ["x", "y"],
                "properties": {
                    "x": { "type": "string" }, "y": { "type": "string" },
                    "group": { "type": "string" }, "title": { "type": "string" }
                }
            }},
            "ompl": { "type": "boolean", "description": "Write OMPL benchmark logs." },
            "paths": { "enum": ["all", "figures", "none"] },
            "outputs": { "type": "array", "minItems": 1, "items": { "enum": ["csv", "json", "parquet"] },
                         "description": "The result tables to write (default all three)." },
            "published": { "type": "string",
                           "description": "A TOML file of published values to compare with." },
            "test": { "type": "object", "additionalProperties": false, "properties": {
                "problems_per_map": count, "repeats": count
            }},
            "sections": { "type": "array",
                          "description": "The summary.md sections to write (configs/README.md).",
                          "items": { "anyOf": [
                              { "enum": sections },
                              { "type": "object", "required": ["name"],
                                "description": "A section with its options, e.g. { name = \"seed002\", proposed = \"pastar\" }.",
                                "properties": { "name": { "enum": sections } } }
                          ] } },
            "maps": { "type": "array", "minItems": 1, "items": map_set },
            "planners": {
                "type": "object",
                "minProperties": 1,
                "description": "Planner labels; each table runs one registered planner.",
                "additionalProperties": { "oneOf": planners }
            }
        }
    });
    Ok(schema)
}
