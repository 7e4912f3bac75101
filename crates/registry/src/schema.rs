//! Every planner's declared parameters.
//!
//! A planner declares its parameters once, in its crate's `Config` struct: the
//! `schemars::JsonSchema` derive reads the field types, the serde attributes
//! (`rename_all`, `default`, `deny_unknown_fields`), the doc comments and the numeric
//! ranges a field declares (`#[schemars(range(min = 1, max = 20))]`, `exclusiveMinimum`
//! by `extend`; the registry's tests hold each planner's validation to them), so the parameter
//! list that `gridplan planners <name>` prints ([`declared`]) and the config schema that
//! `gridplan schema` prints (planner-runner's `schema::experiment_schema`) cannot drift
//! from what the planner accepts.

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema};
use serde_json::Value;

use crate as registry;

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
    /// The type and its declared range, e.g. `integer (1 to 20)`, `number (>= 0)`,
    /// `string`, `boolean`, `number (> 0) or "size"`.
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

/// Why a planner's declared parameters could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RegistryError {
    /// No planner has this registry name.
    #[error("unknown planner `{name}`, expected one of {}", registry::names().join(", "))]
    UnknownPlanner {
        /// The name given.
        name: String,
    },
    /// The planner refuses its own default config (a bug in the planner crate).
    #[error("planner `{name}`: its default config fails: {error}")]
    DefaultConfig {
        /// The registry name.
        name: String,
        /// The planner's error.
        error: planner_api::ParamError,
    },
}

/// The parameters registry planner `name` declares, in declaration order.
pub fn declared(name: &str) -> Result<Vec<Param>, RegistryError> {
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
fn planner_schema(name: &str) -> Result<Value, RegistryError> {
    let entry = registry::find(name).ok_or_else(|| RegistryError::UnknownPlanner {
        name: name.to_string(),
    })?;
    let factory =
        (entry.factory)(&toml::Table::new()).map_err(|error| RegistryError::DefaultConfig {
            name: name.to_string(),
            error,
        })?;
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
    let format = schema.get("format").and_then(Value::as_str);
    match (range_of(schema, format), format) {
        (Some(range), _) => kind = format!("{kind} ({range})"),
        (None, Some("double") | None) => {}
        // A config's integers are TOML's, 64-bit signed.
        (None, Some("uint64")) => kind = format!("{kind} (0 to 2^63 - 1)"),
        (None, Some(format)) => kind = format!("{kind} ({format})"),
    }
    (kind, allowed)
}

/// The values a numeric schema declares beyond its type's own (`minimum`, `maximum`,
/// `exclusiveMinimum`, `exclusiveMaximum`), in words: `1 to 20`, `>= 0`, `> 0 to 1`.
/// An unsigned integer's own bounds (0, and the largest value of its width) fill in
/// what is not declared; `None` when nothing beyond the type is declared.
fn range_of(schema: &Value, format: Option<&str>) -> Option<String> {
    let read = |key: &str| {
        schema
            .get(key)
            .filter(|v| v.is_number())
            .map(Value::to_string)
    };
    let (min, max) = (read("minimum"), read("maximum"));
    let (above, below) = (read("exclusiveMinimum"), read("exclusiveMaximum"));
    let most = match format {
        Some("uint8") => Some(u8::MAX.to_string()),
        Some("uint16") => Some(u16::MAX.to_string()),
        Some("uint32") => Some(u32::MAX.to_string()),
        Some("uint64") => Some("2^63 - 1".to_string()),
        _ => None,
    };
    let unsigned = most.is_some();
    // The derive declares `minimum = 0` for every unsigned integer: that alone is the type.
    let declared_min = min.as_ref().filter(|m| !(unsigned && m.as_str() == "0"));
    if declared_min.is_none() && above.is_none() && max.is_none() && below.is_none() {
        return None;
    }
    let low = match (&min, &above) {
        (_, Some(above)) => Some(format!("> {above}")),
        (Some(min), None) => Some(min.clone()),
        (None, None) => None,
    };
    let high = max.or(most).map(|max| format!("to {max}"));
    let high = below.map(|below| format!("< {below}")).or(high);
    Some(match (low, high) {
        (Some(low), Some(high)) if high.starts_with('<') => format!("{low}, {high}"),
        (Some(low), Some(high)) => format!("{low} {high}"),
        (Some(low), None) if low.starts_with('>') => low,
        (Some(low), None) => format!(">= {low}"),
        (None, Some(high)) if high.starts_with('<') => high,
        (None, Some(high)) => format!("<= {}", high.trim_start_matches("to ")),
        (None, None) => return None,
    })
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
