//! The JSON Schema of experiment configs, for `gridplan schema` and editors.
//!
//! Derived, not written: the experiment's keys, the `[[maps]]` sets, `[[charts]]`, `test`
//! and `budget` come from the `schemars::JsonSchema` derive on the config parser's own
//! types (`config::RawConfig` and what it holds: field types, serde's `default` and
//! `deny_unknown_fields`, doc comments), so a key added to the parser is in the schema.
//! The planner tables come from each planner's declared parameters
//! ([`planner_registry::schema::declared`]), so they cannot drift from what the planner
//! accepts. The summary.md section names are the report's, passed in by the caller.

use planner_registry as registry;
use planner_registry::schema::{declared, parameters_of, Param, RegistryError};
use schemars::JsonSchema;
use serde_json::{json, Map, Value};

use crate::config::{Compare, RawConfig};

/// The keys of a `budget` table, as the schema declares them: planner-api's `Budget`
/// (which declares no schema, planner-api depending on serde alone) read by the config
/// parser; planner-paper's schema test compares them with the keys the parser accepts.
#[derive(JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(
    description = "Limits per run, for every planner; a planner table's own `budget` sets some of them for that planner, key by key (a key it leaves out keeps the experiment's)."
)]
pub struct BudgetKeys {
    /// Stop after this many expansions (each planner says what one expansion is).
    pub max_expansions: Option<u64>,
    /// Stop after this much wall-clock time (not deterministic).
    pub max_time_ms: Option<u64>,
    /// Refuse to plan when the planner's per-cell state for the grid would take more than
    /// this many MiB.
    pub max_memory_mb: Option<u64>,
}

/// The values of a map set's `costs.rule` (planner-api's `CostRule`, as it deserializes).
#[derive(JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CostRuleKeys {
    /// Length times the mean of the two cells' weights.
    Mean,
    /// Length times the weight of the cell entered.
    Entered,
}

/// The schema of type `T`, inlined, without the root's `$schema` and `title`.
fn inline_schema<T: JsonSchema>() -> Value {
    let mut value = parameters_of::<T>().to_value();
    if let Some(object) = value.as_object_mut() {
        object.remove("$schema");
        object.remove("title");
    }
    value
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
    properties.insert("budget".into(), inline_schema::<BudgetKeys>());
    properties.insert(
        "costs".into(),
        json!({ "const": "ignore",
                "description": "Run on weighted maps with their weights left out (planners that do not honour cell costs are refused otherwise)." }),
    );
    properties.insert("compare".into(), inline_schema::<Compare>());
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

/// The JSON Schema (draft 2020-12) of experiment configs, for `gridplan schema` and
/// editors: derived from the config parser's types, with the planner tables as a `oneOf`
/// over `planner = "<name>"`, each with that planner's declared parameters. `sections` are
/// the names `sections = [...]` may use (the report's catalogue), each with the schema of
/// its options (`{ "properties": {...}, "required": [...] }`, without `name`).
pub fn experiment_schema(sections: &[(&str, Value)]) -> Result<Value, RegistryError> {
    let mut planners = Vec::new();
    for entry in registry::PLANNERS {
        planners.push(planner_table_schema(entry.name, entry.summary)?);
    }
    let mut schema = parameters_of::<RawConfig>().to_value();
    // The derive of a struct always gives `properties` (planner-paper's schema test reads
    // them); the two filled in here replace the derive's placeholders.
    let mut properties = Map::new();
    if let Some(derived) = schema.get_mut("properties").and_then(Value::as_object_mut) {
        properties = std::mem::take(derived);
    }
    properties.insert("sections".into(), sections_schema(sections));
    properties.insert(
        "planners".into(),
        json!({
            "type": "object",
            "minProperties": 1,
            "description": "Planner labels; each table runs one registered planner.",
            "additionalProperties": { "oneOf": planners }
        }),
    );
    if let Some(object) = schema.as_object_mut() {
        object.insert("properties".into(), Value::Object(properties));
    }
    bound_unsigned(&mut schema);
    Ok(schema)
}

/// The schema of `sections = [...]`: a bare name for a section that needs no option, or
/// a table per section (`name` and exactly that section's options, `oneOf` by name).
fn sections_schema(sections: &[(&str, Value)]) -> Value {
    let bare: Vec<&str> = sections
        .iter()
        .filter(|(_, options)| {
            options
                .get("required")
                .and_then(Value::as_array)
                .is_none_or(Vec::is_empty)
        })
        .map(|(name, _)| *name)
        .collect();
    let mut tables = Vec::new();
    for (name, options) in sections {
        let mut properties = Map::new();
        properties.insert("name".into(), json!({ "const": name }));
        if let Some(own) = options.get("properties").and_then(Value::as_object) {
            properties.extend(own.clone());
        }
        let mut required = vec![Value::from("name")];
        if let Some(own) = options.get("required").and_then(Value::as_array) {
            required.extend(own.iter().cloned());
        }
        tables.push(json!({
            "type": "object",
            "title": name,
            "required": required,
            "additionalProperties": false,
            "properties": properties,
        }));
    }
    json!({ "type": "array",
            "description": "The summary.md sections to write (configs/README.md): a name, or a table with its `name` and its options, e.g. { name = \"seed002\", proposed = \"pastar\" }.",
            "items": { "anyOf": [ { "enum": bare }, { "oneOf": tables } ] } })
}

/// Adds the largest value of an unsigned integer of 8, 16 or 32 bits (`format` `uint8`,
/// `uint16`, `uint32`) as its `maximum` wherever the derive gave none, so that the schema
/// refuses what the parser refuses (`repeats = 4294967296`, a cell's coordinate).
pub fn bound_unsigned(value: &mut Value) {
    match value {
        Value::Object(object) => {
            let most = match object.get("format").and_then(Value::as_str) {
                Some("uint8") => Some(u64::from(u8::MAX)),
                Some("uint16") => Some(u64::from(u16::MAX)),
                Some("uint32") => Some(u64::from(u32::MAX)),
                _ => None,
            };
            if let Some(most) = most {
                object.entry("maximum").or_insert_with(|| most.into());
            }
            object.values_mut().for_each(bound_unsigned);
        }
        Value::Array(items) => items.iter_mut().for_each(bound_unsigned),
        _ => {}
    }
}
