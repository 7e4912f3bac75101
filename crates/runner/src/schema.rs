//! Every planner's declared parameters, and the JSON Schema of experiment configs.
//!
//! A planner declares its parameters once, in its crate's `Config` struct: the
//! `schemars::JsonSchema` derive reads the field types, the serde attributes
//! (`rename_all`, `default`, `deny_unknown_fields`) and the doc comments, so the parameter
//! list that `gridplan planners <name>` prints ([`declared`]) and the config schema that
//! `gridplan schema` prints ([`experiment_schema`]) cannot drift from what the planner
//! accepts. The schema's top level (the runner's own keys) is written here by hand; the
//! runner's tests compare its key lists with the ones the config parser accepts.

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema};
use serde_json::{json, Map, Value};

use crate::registry;

/// The JSON Schema of a planner config type `C`, subschemas inlined (no `$ref`s).
pub fn parameters_of<C: JsonSchema>() -> Schema {
    SchemaSettings::draft2020_12()
        .with(|s| s.inline_subschemas = true)
        .into_generator()
        .into_root_schema_for::<C>()
}

/// One declared parameter of a planner.
#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    /// The key in a planner table.
    pub key: String,
    /// The type, e.g. `integer`, `number`, `string`, `boolean`, `number or "size"`.
    pub kind: String,
    /// The default value (as the planner's default `Config` serializes it), if declared.
    pub default: Option<Value>,
    /// The values it allows, when it allows only a fixed set (else empty).
    pub allowed: Vec<Value>,
    /// The first paragraph of its doc comment.
    pub doc: String,
    /// Whether a value of it is itself a list (a list there is then no sweep).
    pub is_list: bool,
    /// The parameter's own JSON Schema.
    pub schema: Value,
}

/// The parameters registry planner `name` declares, in declaration order.
pub fn declared(name: &str) -> Result<Vec<Param>, String> {
    let schema = planner_schema(name)?;
    let properties = schema
        .get("properties")
        .and_then(Value::as_object)
        .cloned()
        .unwrap_or_default();
    Ok(properties
        .iter()
        .map(|(key, schema)| describe(key, schema))
        .collect())
}

/// The JSON Schema of registry planner `name`'s `Config`.
fn planner_schema(name: &str) -> Result<Value, String> {
    let entry = registry::find(name).ok_or_else(|| {
        format!(
            "unknown planner `{name}`, expected one of {}",
            registry::names().join(", ")
        )
    })?;
    let factory = (entry.factory)(&toml::Table::new())
        .map_err(|e| format!("planner `{name}`: its default config fails: {e}"))?;
    Ok(factory.parameters().to_value())
}

/// Reads one property schema into a [`Param`].
fn describe(key: &str, schema: &Value) -> Param {
    let doc = first_paragraph(
        schema
            .get("description")
            .and_then(Value::as_str)
            .unwrap_or_default(),
    );
    let (kind, allowed) = kind_of(schema);
    Param {
        key: key.to_string(),
        is_list: types_of(schema).iter().any(|t| t == "array"),
        kind,
        default: schema.get("default").cloned(),
        allowed: allowed.unwrap_or_default(),
        doc,
        schema: schema.clone(),
    }
}

/// The JSON types a schema names (`type`, or the types of its alternatives), `null` left out.
fn types_of(schema: &Value) -> Vec<String> {
    let mut types = match schema.get("type") {
        Some(Value::String(t)) => vec![t.clone()],
        Some(Value::Array(ts)) => ts
            .iter()
            .filter_map(Value::as_str)
            .map(str::to_string)
            .collect(),
        _ => Vec::new(),
    };
    for key in ["anyOf", "oneOf"] {
        for alternative in schema
            .get(key)
            .and_then(Value::as_array)
            .into_iter()
            .flatten()
        {
            types.extend(types_of(alternative));
        }
    }
    types.retain(|t| t != "null");
    types.dedup();
    types
}

/// A readable type of `schema`, and the values it allows when it allows only a fixed set.
fn kind_of(schema: &Value) -> (String, Option<Vec<Value>>) {
    if let Some(value) = schema.get("const") {
        return (value.to_string(), Some(vec![value.clone()]));
    }
    let alternatives = ["anyOf", "oneOf"]
        .iter()
        .find_map(|key| schema.get(*key).and_then(Value::as_array));
    if let Some(alternatives) = alternatives {
        let mut kinds: Vec<String> = Vec::new();
        let mut allowed = Some(Vec::new());
        for alternative in alternatives {
            if alternative.get("type").and_then(Value::as_str) == Some("null") {
                continue;
            }
            let (kind, values) = kind_of(alternative);
            if !kinds.contains(&kind) {
                kinds.push(kind);
            }
            allowed = match (allowed, values) {
                (Some(mut all), Some(values)) => {
                    all.extend(values);
                    Some(all)
                }
                _ => None,
            };
        }
        // An enum written as one `const` per value reads as its type.
        if alternatives.iter().all(|a| a.get("const").is_some()) {
            return (types_of(schema).join(" or "), allowed);
        }
        return (kinds.join(" or "), allowed);
    }
    let allowed = schema
        .get("enum")
        .and_then(Value::as_array)
        .map(|values| values.iter().filter(|v| !v.is_null()).cloned().collect());
    let mut kind = types_of(schema).join(" or ");
    if kind.is_empty() {
        kind = "any".to_string();
    }
    match schema.get("format").and_then(Value::as_str) {
        Some("double") | None => {}
        Some(format) => kind = format!("{kind} ({format})"),
    }
    (kind, allowed)
}

/// A doc comment's first paragraph on one line, rustdoc links as plain code.
fn first_paragraph(description: &str) -> String {
    description
        .split("\n\n")
        .next()
        .unwrap_or_default()
        .replace('\n', " ")
        .replace("[`", "`")
        .replace("`]", "`")
}

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
fn planner_table_schema(name: &str, summary: &str) -> Result<Value, String> {
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
    "published",
    "test",
    "sections",
    "maps",
    "planners",
];

/// The JSON Schema (draft 2020-12) of experiment configs, for `gridplan schema` and
/// editors: the top-level keys, the `[[maps]]` sets, and the planner tables as a `oneOf`
/// over `planner = "<name>"`, each with that planner's declared parameters.
pub fn experiment_schema() -> Result<Value, String> {
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
            "costs": {
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
            }
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
            "published": { "type": "string",
                           "description": "A TOML file of published values to compare with." },
            "test": { "type": "object", "additionalProperties": false, "properties": {
                "problems_per_map": count, "repeats": count
            }},
            "sections": { "type": "array",
                          "items": { "enum": crate::report::section_names() } },
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
