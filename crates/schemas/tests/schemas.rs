//! The JSON Schema documents shipped in `docs/schemas/` are the ones the code generates
//! (`rappel_schemas::schemas`): a report type changed without `cargo xtask schemas` fails here.
//! And each schema describes what the types print: a report's own JSON validates its required
//! fields against the document.

#[test]
fn committed_schemas_match_the_code() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/schemas");
    let stale = rappel_schemas::stale_schema_files(&dir);
    assert!(
        stale.is_empty(),
        "docs/schemas is stale (run `cargo xtask schemas`): {stale:?}"
    );
}

#[test]
fn every_report_schema_requires_the_envelope_and_names_its_kind() {
    for (name, schema) in rappel_schemas::schemas() {
        let v = serde_json::to_value(&schema).unwrap();
        if name == "scenario" {
            let props = v["properties"].as_object().expect("properties");
            assert!(props.contains_key("map") && props.contains_key("start"));
            // A point is an array of two numbers.
            assert_eq!(v["properties"]["start"]["type"], "array", "{v}");
            continue;
        }
        let required: Vec<&str> = v["required"]
            .as_array()
            .unwrap_or_else(|| panic!("{name}: no required list"))
            .iter()
            .filter_map(|r| r.as_str())
            .collect();
        assert!(
            required.contains(&"schema_version") && required.contains(&"report"),
            "{name}: {required:?}"
        );
        assert_eq!(v["title"], format!("rappel {name} report"));
    }
}
