//! The JSON outputs' schemas (`softgrip_lab::schema`): `docs/schema/NAME.json` is each output
//! type's schema, `docs/formats.md` names each output's keys as its type has them, and an
//! output that does not fit its type is refused.
//!
//! After changing an output's type: `SOFTGRIP_WRITE_SCHEMA=1 cargo test -p softgrip-lab --test
//! it schema` writes the schema files anew (then commit them).

use std::collections::BTreeSet;
use std::path::PathBuf;

use serde_json::{Value, json};
use softgrip_lab::schema;

/// `docs/schema/` of the repository.
fn schema_dir() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/schema"))
}

const REGENERATE: &str = "SOFTGRIP_WRITE_SCHEMA=1 cargo test -p softgrip-lab --test it schema";

/// Each committed `docs/schema/NAME.json` is its output type's schema, and there is no other
/// (with `SOFTGRIP_WRITE_SCHEMA=1` they are written instead).
#[test]
fn the_schema_files_are_the_output_types() {
    let dir = schema_dir();
    let write = std::env::var_os("SOFTGRIP_WRITE_SCHEMA").is_some_and(|v| v == "1");
    let all = schema::all();
    let mut stale = Vec::new();
    for (name, s) in &all {
        let path = dir.join(format!("{name}.json"));
        let text = schema::file_text(s);
        if write {
            std::fs::create_dir_all(&dir).expect("docs/schema");
            std::fs::write(&path, &text).expect("a schema file");
        } else if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            stale.push(format!("docs/schema/{name}.json"));
        }
    }
    let names: BTreeSet<String> = all.iter().map(|(n, _)| format!("{n}.json")).collect();
    for entry in std::fs::read_dir(&dir).expect("docs/schema") {
        let file = entry
            .expect("an entry")
            .file_name()
            .to_string_lossy()
            .into_owned();
        if file.ends_with(".json") && !names.contains(&file) {
            if write {
                std::fs::remove_file(dir.join(&file)).expect("an old schema removed");
            } else {
                stale.push(format!("docs/schema/{file} (no output of that name)"));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "the committed schemas are not the output types': {}. After changing an output type, \
         regenerate them with `{REGENERATE}` and commit docs/schema/",
        stale.join(", ")
    );
}

/// Every key name under a `properties` anywhere in `schema` (its definitions included).
fn property_names(schema: &Value, names: &mut BTreeSet<String>) {
    match schema {
        Value::Object(map) => {
            if let Some(Value::Object(props)) = map.get("properties") {
                names.extend(props.keys().cloned());
            }
            map.values().for_each(|v| property_names(v, names));
        }
        Value::Array(items) => items.iter().for_each(|v| property_names(v, names)),
        _ => {}
    }
}

/// The top-level keys of `schema`: its own properties, or every variant's (`anyOf`).
fn top_level_keys(schema: &Value) -> BTreeSet<String> {
    let defs = &schema["$defs"];
    let resolve = |s: &Value| match s["$ref"].as_str() {
        Some(r) => defs[r.trim_start_matches("#/$defs/")].clone(),
        None => s.clone(),
    };
    let variants = match schema["anyOf"].as_array() {
        Some(vs) => vs.iter().map(resolve).collect(),
        None => vec![schema.clone()],
    };
    variants
        .iter()
        .flat_map(|v| v["properties"].as_object().into_iter().flatten())
        .map(|(k, _)| k.clone())
        .collect()
}

/// `docs/formats.md`'s table of JSON outputs: each output's row links its schema file and names
/// (in backticks) every top-level key of its type, and no key the type does not have.
#[test]
fn the_formats_table_names_each_outputs_keys() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../docs/formats.md"
    ))
    .expect("docs/formats.md");
    for (name, s) in schema::all() {
        let link = format!("(schema/{name}.json)");
        let row = text
            .lines()
            .find(|l| l.starts_with('|') && l.contains(&link))
            .unwrap_or_else(|| panic!("docs/formats.md: no table row links {link}"));
        let keys_cell = row.split('|').nth(3).unwrap_or("");
        let named: BTreeSet<String> = keys_cell
            .split('`')
            .skip(1)
            .step_by(2)
            .filter(|k| !k.starts_with('-'))
            .map(String::from)
            .collect();
        let mut known = BTreeSet::new();
        property_names(s.as_value(), &mut known);
        let unknown: Vec<_> = named.difference(&known).collect();
        assert!(
            unknown.is_empty(),
            "docs/formats.md, {name}: {unknown:?} are no keys of the output"
        );
        let missing: Vec<_> = top_level_keys(s.as_value())
            .into_iter()
            .filter(|k| !named.contains(k))
            .collect();
        assert!(
            missing.is_empty(),
            "docs/formats.md, {name}: the row does not name the keys {missing:?}"
        );
    }
}

/// An output with a key its type does not have, without one it has, or with a value of
/// another kind, is refused, and so is an output name that does not exist.
#[test]
fn an_output_that_does_not_fit_its_schema_is_refused() {
    let modulus = json!({
        "recording": "r.toml", "young_modulus": 6e4, "young_modulus_range": [5e4, 7e4],
        "r_squared": 0.99, "strain_range": [0.0, 0.1], "points": 4, "intercept_pa": 10.0,
    });
    schema::round_trip("modulus", &modulus).expect("a modulus output");
    let mut extra = modulus.clone();
    extra["extra"] = json!(1);
    let e = schema::round_trip("modulus", &extra).expect_err("an unknown key");
    assert!(e.contains("unknown field `extra`"), "{e}");
    let mut missing = modulus.clone();
    missing.as_object_mut().unwrap().remove("points");
    let e = schema::round_trip("modulus", &missing).expect_err("a key missing");
    assert!(e.contains("missing field `points`"), "{e}");
    let mut wrong = modulus.clone();
    wrong["points"] = json!("four");
    assert!(schema::round_trip("modulus", &wrong).is_err());
    assert!(schema::round_trip("no such output", &modulus).is_err());
}
