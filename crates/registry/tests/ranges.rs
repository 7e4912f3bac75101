//! Declared ranges against the planners' own validation.

use planner_registry::PLANNERS;
use serde_json::Value;

/// A declared numeric bound of a parameter.
#[derive(Debug, Clone, Copy)]
enum Bound {
    /// `minimum`: the value is allowed, anything below is not.
    Min(f64),
    /// `maximum`: the value is allowed, anything above is not.
    Max(f64),
    /// `exclusiveMinimum`: the value is not allowed, anything just above is.
    AboveMin(f64),
    /// `exclusiveMaximum`: the value is not allowed, anything just below is.
    BelowMax(f64),
    /// No declared lower bound: the type's least value (a config's) is allowed.
    TypeMin(f64),
    /// No declared upper bound: the type's greatest value (a config's) is allowed.
    TypeMax(f64),
}

/// The numeric alternatives of a parameter's schema (itself, or its `anyOf`/`oneOf`
/// members), each with whether it is an integer and its bounds.
fn numeric_bounds(schema: &Value) -> Vec<(bool, Vec<Bound>)> {
    let mut out = Vec::new();
    for alternative in ["anyOf", "oneOf"]
        .iter()
        .filter_map(|key| schema.get(*key).and_then(Value::as_array))
        .flatten()
    {
        out.extend(numeric_bounds(alternative));
    }
    let types: Vec<&str> = match schema.get("type") {
        Some(Value::String(t)) => vec![t.as_str()],
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    };
    let integer = types.contains(&"integer");
    if !integer && !types.contains(&"number") {
        return out;
    }
    let read = |key: &str| schema.get(key).and_then(Value::as_f64);
    let mut bounds: Vec<Bound> = [
        read("minimum").map(Bound::Min),
        read("maximum").map(Bound::Max),
        read("exclusiveMinimum").map(Bound::AboveMin),
        read("exclusiveMaximum").map(Bound::BelowMax),
    ]
    .into_iter()
    .flatten()
    .collect();
    // A config's integers are TOML's (64-bit signed), narrowed by the field's type.
    let (least, most) = match schema.get("format").and_then(Value::as_str) {
        Some("uint8") => (0.0, f64::from(u8::MAX)),
        Some("uint16") => (0.0, f64::from(u16::MAX)),
        Some("uint32") => (0.0, f64::from(u32::MAX)),
        Some("uint64") => (0.0, i64::MAX as f64),
        _ if integer => (i64::MIN as f64, i64::MAX as f64),
        _ => (-f64::MAX, f64::MAX),
    };
    if read("minimum").or(read("exclusiveMinimum")).is_none() {
        bounds.push(Bound::TypeMin(least));
    }
    if read("maximum").or(read("exclusiveMaximum")).is_none() {
        bounds.push(Bound::TypeMax(most));
    }
    out.push((integer, bounds));
    out
}

/// The value at `x` as the TOML a config writes: an integer for integer parameters.
fn toml_value(integer: bool, x: f64) -> toml::Value {
    if integer {
        toml::Value::Integer(x as i64)
    } else {
        toml::Value::Float(x)
    }
}

/// The next representable float above (`up`) or below `x`, for finite `x` (`f64::next_up`
/// is newer than the workspace's minimum Rust).
fn next_float(x: f64, up: bool) -> f64 {
    if x == 0.0 {
        let tiny = f64::from_bits(1);
        return if up { tiny } else { -tiny };
    }
    let bits = x.to_bits();
    // Away from zero the bits grow; towards zero they shrink.
    if (x > 0.0) == up {
        f64::from_bits(bits + 1)
    } else {
        f64::from_bits(bits - 1)
    }
}

/// The value just inside and just outside a bound (integers step by 1, floats to the
/// next representable number); nothing is outside a type's own bound.
fn inside_and_outside(integer: bool, bound: Bound) -> (f64, Option<f64>) {
    let step = |x: f64, up: bool| match (integer, up) {
        (true, true) => x + 1.0,
        (true, false) => x - 1.0,
        (false, up) => next_float(x, up),
    };
    let (down, up) = (|x| step(x, false), |x| step(x, true));
    match bound {
        Bound::Min(m) => (m, Some(down(m))),
        Bound::Max(m) => (m, Some(up(m))),
        Bound::AboveMin(m) => (up(m), Some(m)),
        Bound::BelowMax(m) => (down(m), Some(m)),
        Bound::TypeMin(m) | Bound::TypeMax(m) => (m, None),
    }
}

/// Every numeric bound that `gridplan planners NAME` and `gridplan schema` show, for every
/// planner, is the planner's own: the value at the bound (or just inside an exclusive
/// one) is not refused under that key, and the value just outside is refused naming the
/// key; where no bound is declared, the type's own extreme is not refused either. A value
/// may be refused at its bound only for a bound set by another key, which the message
/// names (`inertia_min` up to `inertia_max`). So declaration and validation cannot drift.
#[test]
fn declared_ranges_are_what_each_planner_accepts() {
    let (mut n_checked, mut wrong) = (0, Vec::new());
    for entry in PLANNERS {
        let declared = planner_registry::schema::declared(entry.name).expect("declared");
        let names_another_key = |key: &str, message: &str| {
            declared
                .iter()
                .any(|p| p.key != key && message.contains(p.key.as_str()))
        };
        // A fixed set of values is the set's own (planner-paper's schema tests hold them).
        for param in declared.iter().filter(|p| p.allowed.is_empty()) {
            for (integer, bounds) in numeric_bounds(&param.schema) {
                for bound in bounds {
                    let what = format!("{}.{} ({bound:?})", entry.name, param.key);
                    let build = |x: f64| {
                        let table =
                            toml::Table::from_iter([(param.key.clone(), toml_value(integer, x))]);
                        (entry.factory)(&table)
                    };
                    let (inside, outside) = inside_and_outside(integer, bound);
                    match build(inside) {
                        Err(e) if e.key == param.key && !names_another_key(&e.key, &e.message) => {
                            wrong.push(format!("{what}: {inside} refused: {e}"));
                        }
                        _ => {}
                    }
                    match outside.map(build) {
                        Some(Ok(_)) => wrong.push(format!("{what}: {outside:?} accepted")),
                        Some(Err(e)) if e.key != param.key && !e.message.contains(&param.key) => {
                            wrong.push(format!("{what}: {outside:?} refused otherwise: {e}"));
                        }
                        _ => {}
                    }
                    n_checked += 1;
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert!(n_checked > 40, "{n_checked} bounds checked");
}

/// `gridplan planners NAME` reads a parameter's range from its declared type: CAPSO's
/// control points show `1 to 20`, a finite non-negative weight `>= 0`, an exclusive bound
/// `> 0`, and an unsigned integer without a declared range only its width.
#[test]
fn listed_kinds_show_the_declared_ranges() {
    let kind = |planner: &str, key: &str| {
        planner_registry::schema::declared(planner)
            .expect("declared")
            .into_iter()
            .find(|p| p.key == key)
            .map(|p| p.kind)
            .expect("a parameter")
    };
    assert_eq!(kind("capso", "control_points"), "integer (1 to 20)");
    assert_eq!(kind("capso", "iterations"), "integer (0 to 100000)");
    assert_eq!(kind("capso", "max_speed"), "number (> 0 to 1)");
    assert_eq!(kind("capso", "beetle_step"), "number (> 0)");
    assert_eq!(kind("rrt", "goal_bias"), "number (0 to 1)");
    assert_eq!(kind("rrt", "step"), "integer (1 to 4294967295)");
    assert_eq!(kind("astar", "weight"), "number (>= 0)");
    assert_eq!(kind("pastar", "connecting_distance"), "integer (1 to 4)");
    assert_eq!(kind("pastar", "radius"), "number (> 0) or \"size\"");
    assert_eq!(kind("rrt", "seed"), "integer (0 to 2^63 - 1)");
}

/// Coverage's spiral parameters list the defaults its docs give (they listed `unset`),
/// and a config resolves to them, so runs.json says how a run ran.
#[test]
fn coverage_lists_and_resolves_its_pattern_defaults() {
    let declared = planner_registry::schema::declared("coverage").expect("declared");
    let default = |key: &str| {
        declared
            .iter()
            .find(|p| p.key == key)
            .and_then(|p| p.default.clone())
    };
    assert_eq!(default("reference_side"), Some(Value::from("left")));
    assert_eq!(default("heading"), Some(Value::from("R")));
    let entry = planner_registry::find("coverage").expect("registered");
    let resolved = |text: &str| {
        let table: toml::Table = toml::from_str(text).expect("TOML");
        (entry.factory)(&table).expect("valid").resolved().clone()
    };
    let spiral = resolved("");
    assert_eq!(
        (
            &spiral["reference_side"],
            &spiral["heading"],
            &spiral["rotation"]
        ),
        (&Value::from("left"), &Value::from("R"), &Value::Null)
    );
    let zigzag = resolved("pattern = \"zigzag\"\nrotation = \"clockwise\"");
    assert_eq!(
        (
            &zigzag["reference_side"],
            &zigzag["rotation"],
            &zigzag["first"]
        ),
        (&Value::Null, &Value::from("clockwise"), &Value::from("D"))
    );
}
