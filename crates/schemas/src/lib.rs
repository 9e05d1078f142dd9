//! The JSON Schema documents of the scenario file and of every report (`docs/schemas/`, written
//! by `cargo xtask schemas` from the types: [`schemas`], [`schema_files`], [`stale_schema_files`]),
//! and a validator of JSON documents against them ([`check`]): the keywords schemars emits, each
//! checked; any other keyword is an error, so a document cannot pass by a keyword being ignored.
//! For tests, `cargo xtask schemas` and `cargo xtask journeys`, which check every report a
//! command prints against its schema; the facade (`rappel`) derives the schemas, this crate
//! writes and checks the documents.

use schemars::SchemaGenerator;
use serde_json::Value;

use rappel::input_kind::ValidateReport;
use rappel::report::{Envelope, GenMapReport, HomotopicReport, Report};
use schemars::Schema;

/// Checks `v` against the schema document `root` ([`conforms`] from its top).
///
/// ```
/// use serde_json::json;
/// let schema = json!({"type": "object", "required": ["a"], "properties": {"a": {"type": "integer"}}});
/// assert!(rappel_schemas::check(&json!({"a": 1}), &schema).is_ok());
/// assert!(rappel_schemas::check(&json!({"a": "x"}), &schema).is_err());
/// assert!(rappel_schemas::check(&json!({}), &schema).is_err());
/// ```
pub fn check(v: &Value, root: &Value) -> Result<(), String> {
    conforms(v, root, root, "$")
}

/// `Ok` when `v` conforms to the schema `s` (resolving `$ref` against `root`), else the first
/// violation found with its path `at`; the keywords handled are the
/// ones schemars writes; any other keyword is an error, so the check cannot pass by ignoring one.
pub fn conforms(v: &Value, s: &Value, root: &Value, at: &str) -> Result<(), String> {
    let s = match s {
        Value::Bool(true) => return Ok(()),
        Value::Bool(false) => return Err(format!("{at}: schema `false`")),
        Value::Object(m) => m,
        _ => return Err(format!("{at}: schema is not an object")),
    };
    for (k, x) in s {
        match k.as_str() {
            "$schema" | "title" | "description" | "$defs" | "format" | "default" => {}
            "$ref" => {
                let name = x
                    .as_str()
                    .and_then(|r| r.strip_prefix("#/$defs/"))
                    .ok_or_else(|| format!("{at}: unsupported $ref {x}"))?;
                conforms(v, &root["$defs"][name], root, at)?;
            }
            "type" => {
                let types: Vec<&str> = match x {
                    Value::String(t) => vec![t.as_str()],
                    Value::Array(a) => a.iter().filter_map(Value::as_str).collect(),
                    _ => return Err(format!("{at}: bad type {x}")),
                };
                let ok = types.iter().any(|t| match *t {
                    "object" => v.is_object(),
                    "array" => v.is_array(),
                    "string" => v.is_string(),
                    "boolean" => v.is_boolean(),
                    "null" => v.is_null(),
                    "number" => v.is_number(),
                    "integer" => v.is_i64() || v.is_u64(),
                    _ => false,
                });
                if !ok {
                    return Err(format!("{at}: {v} is not of type {x}"));
                }
            }
            "properties" => {
                if let (Some(o), Some(props)) = (v.as_object(), x.as_object()) {
                    for (name, sub) in props {
                        if let Some(val) = o.get(name) {
                            conforms(val, sub, root, &format!("{at}.{name}"))?;
                        }
                    }
                }
            }
            "required" => {
                if let Some(o) = v.as_object() {
                    for name in x.as_array().into_iter().flatten().filter_map(Value::as_str) {
                        if !o.contains_key(name) {
                            return Err(format!("{at}: required field {name} missing"));
                        }
                    }
                }
            }
            "additionalProperties" => {
                if let (Some(o), Some(props)) = (v.as_object(), s.get("properties")) {
                    for (name, val) in o {
                        if props.get(name).is_none() {
                            conforms(val, x, root, &format!("{at}.{name}"))?;
                        }
                    }
                }
            }
            "items" => {
                if let Some(a) = v.as_array() {
                    let skip = s
                        .get("prefixItems")
                        .and_then(Value::as_array)
                        .map_or(0, Vec::len);
                    for (i, val) in a.iter().enumerate().skip(skip) {
                        conforms(val, x, root, &format!("{at}[{i}]"))?;
                    }
                }
            }
            "prefixItems" => {
                if let (Some(a), Some(subs)) = (v.as_array(), x.as_array()) {
                    for (i, (val, sub)) in a.iter().zip(subs).enumerate() {
                        conforms(val, sub, root, &format!("{at}[{i}]"))?;
                    }
                }
            }
            "minItems" | "maxItems" => {
                if let (Some(a), Some(n)) = (v.as_array(), x.as_u64()) {
                    let len = a.len() as u64;
                    if (k == "minItems" && len < n) || (k == "maxItems" && len > n) {
                        return Err(format!("{at}: {len} items, {k} {n}"));
                    }
                }
            }
            "minimum" => {
                if let (Some(n), Some(m)) = (v.as_f64(), x.as_f64())
                    && n < m
                {
                    return Err(format!("{at}: {n} below the minimum {m}"));
                }
            }
            "const" => {
                if v != x {
                    return Err(format!("{at}: {v} is not the constant {x}"));
                }
            }
            "enum" => {
                if !x.as_array().is_some_and(|a| a.contains(v)) {
                    return Err(format!("{at}: {v} not among {x}"));
                }
            }
            "oneOf" | "anyOf" => {
                let subs = x.as_array().ok_or_else(|| format!("{at}: bad {k}"))?;
                let passing = subs
                    .iter()
                    .filter(|sub| conforms(v, sub, root, at).is_ok())
                    .count();
                if passing == 0 || (k == "oneOf" && passing > 1) {
                    return Err(format!("{at}: {passing} of the {k} branches match {v}"));
                }
            }
            "allOf" => {
                for sub in x.as_array().into_iter().flatten() {
                    conforms(v, sub, root, at)?;
                }
            }
            other => {
                return Err(format!(
                    "{at}: schema keyword {other} not handled by this validator"
                ));
            }
        }
    }
    Ok(())
}

/// The JSON Schema documents `docs/schemas/NAME.json` shipped with the code: the scenario file,
/// then every report by [`rappel::report::Report::KIND`]. `cargo xtask schemas` writes them and a test checks the
/// committed files against these.
pub fn schemas() -> Vec<(&'static str, schemars::Schema)> {
    let mut scenario = SchemaGenerator::default().root_schema_for::<rappel::scenario::Scenario>();
    scenario.insert("title".into(), "rappel scenario file".into());
    #[allow(unused_mut)] // without `mesh` nothing is added
    let mut all = vec![
        ("scenario", scenario),
        ("validate", schema_of::<ValidateReport>()),
        ("btm", schema_of::<rappel::btm_summary::BtmSummary>()),
        ("dem", schema_of::<rappel::dem::DemReport>()),
        (
            "stability",
            schema_of::<rappel::stability::StabilityReport>(),
        ),
        ("shp", schema_of::<rappel::tether::ShpReport>()),
        ("homotopic", schema_of::<HomotopicReport>()),
        ("gen_map", schema_of::<GenMapReport>()),
        ("plan", schema_of::<rappel::plan::PlanReport>()),
        (
            "plan_stream",
            schema_of::<rappel::plan_stream::PlanStreamLine>(),
        ),
        ("query", schema_of::<rappel::query::QueryReport>()),
        ("online", schema_of::<rappel::online::OnlineReport>()),
        ("track", schema_of::<rappel::track::TrackReport>()),
    ];
    #[cfg(feature = "mesh")]
    all.extend([
        ("settle", schema_of::<rappel::settle::SettleReport>()),
        (
            "settle_not_settled",
            schema_of::<rappel::settle::NotSettledReport>(),
        ),
        (
            "settle_map",
            schema_of::<rappel::settle_map::StabilityMap>(),
        ),
        ("navigate", schema_of::<rappel::navigate::NavigateReport>()),
    ]);
    all
}

/// The files of `docs/schemas/`: `(file name, pretty JSON text ending in a newline)` for each of
/// [`schemas`].
pub fn schema_files() -> Vec<(String, String)> {
    schemas()
        .into_iter()
        .map(|(name, schema)| {
            let text = serde_json::to_string_pretty(&schema).unwrap_or_default() + "\n";
            (format!("{name}.json"), text)
        })
        .collect()
}

/// The files of `dir` (the committed `docs/schemas/`) that differ from [`schema_files`], are
/// missing, or are not generated: one line each; empty when the directory is up to date.
pub fn stale_schema_files(dir: &std::path::Path) -> Vec<String> {
    let mut stale = Vec::new();
    let files = schema_files();
    for (name, text) in &files {
        match std::fs::read_to_string(dir.join(name)) {
            Ok(committed) if committed == *text => {}
            Ok(_) => stale.push(format!("{name}: differs from the code")),
            Err(_) => stale.push(format!("{name}: missing")),
        }
    }
    if let Ok(entries) = std::fs::read_dir(dir) {
        for e in entries.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if name.ends_with(".json") && !files.iter().any(|(n, _)| *n == name) {
                stale.push(format!("{name}: not generated by any report type"));
            }
        }
    }
    stale.sort();
    stale
}

/// The JSON Schema document of `T` in its [`Envelope`].
pub fn schema_of<T: Report>() -> Schema {
    let mut g = SchemaGenerator::default();
    let mut s = g.root_schema_for::<Envelope<T>>();
    s.insert("title".into(), format!("rappel {} report", T::KIND).into());
    s
}
