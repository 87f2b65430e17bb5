//! Every JSON output's schema, from its type: the registry that `docs/schema/NAME.json` is
//! generated from (the test `schema` of `softgrip-lab`'s `it` checks the committed files, and
//! writes them anew with `SOFTGRIP_WRITE_SCHEMA=1`), and [`round_trip`], which reads an
//! output back through its type (unknown keys refused) and writes it again.
//!
//! The schemas describe what is written (schemars' serialize contract): a key that is always
//! written is required, even where its value may be `null`.

use schemars::generate::SchemaSettings;
use schemars::{JsonSchema, Schema};
use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};

use crate::diagnose::figures::DiagnosisFigures;
use crate::grasp::compute::WindowFigures;
use crate::json::commands::{
    CheckFigures, GraspFigures, MeshFigures, ModulusFigures, RampFigures, RunFigures,
};
use crate::json::{CompareFigures, FitFigures, FitManyFigures, SweepFigures};
use crate::shard::SweepPartFigures;

/// One JSON output: its name (the schema's file is `docs/schema/NAME.json`), its schema and its
/// type's round trip.
#[derive(Clone, Copy)]
pub struct Output {
    /// The output's name: the schema file's stem.
    pub name: &'static str,
    /// The schema of the output's type.
    pub schema: fn() -> Schema,
    /// The output read into its type (unknown keys refused) and written again.
    pub round_trip: fn(&Value) -> Result<Value, serde_json::Error>,
}

/// `T`'s schema as its JSON is written: JSON Schema 2020-12, every field's `///` line its
/// description.
fn schema_of<T: JsonSchema>() -> Schema {
    let mut schema = SchemaSettings::draft2020_12()
        .for_serialize()
        .into_generator()
        .into_root_schema_for::<T>();
    if let Some(map) = schema.as_object_mut() {
        one_line_descriptions(map);
    }
    schema
}

/// Each `description` in `map` and below on one line: a doc comment's wrapped lines joined
/// by spaces.
fn one_line_descriptions(map: &mut Map<String, Value>) {
    for (key, v) in map.iter_mut() {
        match v {
            Value::String(text) if key == "description" => *text = text.replace('\n', " "),
            Value::Object(inner) => one_line_descriptions(inner),
            Value::Array(items) => items
                .iter_mut()
                .filter_map(Value::as_object_mut)
                .for_each(one_line_descriptions),
            _ => {}
        }
    }
}

/// `value` read into `T` and written again as the outputs are ([`crate::json::to_value`]).
fn through<T: Serialize + DeserializeOwned>(value: &Value) -> Result<Value, serde_json::Error> {
    serde_json::to_value(T::deserialize(value)?)
}

/// The registry entry of the output `name`, of type `T`.
fn output<T: JsonSchema + Serialize + DeserializeOwned>(name: &'static str) -> Output {
    Output {
        name,
        schema: schema_of::<T>,
        round_trip: through::<T>,
    }
}

/// Every JSON output that the CLI writes and Python returns, by name.
pub fn outputs() -> Vec<Output> {
    vec![
        // `compare --json`; Python `compare`
        output::<CompareFigures>("compare"),
        // `fit --json` of one recording; Python `fit`
        output::<FitFigures>("fit"),
        // `fit --json` of several recordings
        output::<FitManyFigures>("fit_many"),
        // `sweep --json`; Python `sweep`
        output::<SweepFigures>("sweep"),
        // `sweep --shard I/N --part FILE`, read by `merge`; Python `sweep_part`
        output::<SweepPartFigures>("sweep_part"),
        // `merge --json`: a sweep's figures; Python `sweep_merge`
        output::<SweepFigures>("merge"),
        // `modulus --json`
        output::<ModulusFigures>("modulus"),
        // `mesh info --json`
        output::<MeshFigures>("mesh"),
        // `check --json`
        output::<CheckFigures>("check"),
        // `grasp --json`
        output::<GraspFigures>("grasp"),
        // `run --json`
        output::<RunFigures>("run"),
        // `ramp --json`
        output::<RampFigures>("ramp"),
        // `diagnose --json`; Python `diagnose`
        output::<DiagnosisFigures>("diagnose"),
        // `grasp window --json`; Python `grasp_window`
        output::<WindowFigures>("grasp_window"),
    ]
}

/// Every output's name and schema: what `docs/schema/NAME.json` holds.
pub fn all() -> Vec<(&'static str, Schema)> {
    outputs()
        .into_iter()
        .map(|o| (o.name, (o.schema)()))
        .collect()
}

/// The schema as its file holds it: pretty JSON ended by a newline.
pub fn file_text(schema: &Schema) -> String {
    serde_json::to_string_pretty(schema.as_value()).unwrap_or_default() + "\n"
}

/// `value`, an output `name` wrote, read back through its type and written again: an error
/// names a key the type does not know, one it lacks, a wrong kind of value, or a value that
/// does not come back the same.
pub fn round_trip(name: &str, value: &Value) -> Result<(), String> {
    let output = outputs()
        .into_iter()
        .find(|o| o.name == name)
        .ok_or_else(|| format!("no JSON output is named {name:?}"))?;
    let back = (output.round_trip)(value)
        .map_err(|e| format!("{name}: the JSON does not fit its type: {e}"))?;
    if back == *value {
        Ok(())
    } else {
        Err(format!(
            "{name}: the JSON read through its type comes back different:\n{}\nagainst\n{}",
            serde_json::to_string_pretty(value).unwrap_or_default(),
            serde_json::to_string_pretty(&back).unwrap_or_default()
        ))
    }
}
