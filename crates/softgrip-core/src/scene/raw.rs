//! The raw layer: the file as written. Every key is optional and unknown keys are rejected
//! (`deny_unknown_fields`), so a typo is an error that names the key. The field order is the one
//! serde's unknown-key message lists. `to_toml` serializes these same structs.

use serde::{Deserialize, Deserializer, Serialize};

/// A point or vector, `[x, y, z]`: exactly three numbers (serde's own `[f64; 3]` reads the first
/// three of a longer list and drops the rest without a word).
fn three<'de, D: Deserializer<'de>>(d: D) -> Result<[f64; 3], D::Error> {
    let v = Vec::<f64>::deserialize(d)?;
    <[f64; 3]>::try_from(v.as_slice())
        .map_err(|_| serde::de::Error::invalid_length(v.len(), &"three numbers, [x, y, z]"))
}

/// [`three`], for a key that may be left out.
fn maybe_three<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 3]>, D::Error> {
    three(d).map(Some)
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawScene {
    pub(super) simulation: Option<RawSimulation>,
    pub(super) object: Option<RawObject>,
    pub(super) model: Option<RawModel>,
    pub(super) support: Option<RawSupport>,
    #[serde(default)]
    pub(super) fixed: Vec<RawBox>,
    #[serde(default)]
    pub(super) load: Vec<RawLoad>,
    #[serde(default)]
    pub(super) finger: Vec<RawFinger>,
    #[serde(default)]
    pub(super) region: Vec<RawRegion>,
    pub(super) grasp: Option<RawGrasp>,
    /// Free-form by contract: kept so it parses, never written back.
    pub(super) extra: Option<toml::Table>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSimulation {
    pub(super) dt: Option<f64>,
    pub(super) duration: Option<f64>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) gravity: Option<[f64; 3]>,
    pub(super) cg_tolerance: Option<f64>,
    pub(super) cg_max_iterations: Option<i64>,
    pub(super) settle: Option<String>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObject {
    pub(super) shape: Option<String>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) size: Option<[f64; 3]>,
    pub(super) radius: Option<f64>,
    pub(super) height: Option<f64>,
    pub(super) path: Option<String>,
    pub(super) scale: Option<f64>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) position: Option<[f64; 3]>,
    pub(super) edge_length: Option<f64>,
    pub(super) density: Option<f64>,
    pub(super) young_modulus: Option<f64>,
    pub(super) poisson_ratio: Option<f64>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawModel {
    pub(super) damping_ratio: Option<f64>,
    pub(super) rayleigh_mass: Option<f64>,
    pub(super) rayleigh_stiffness: Option<f64>,
    pub(super) alpha: Option<f64>,
    pub(super) bulk_modulus: Option<f64>,
    pub(super) bulk_pressure: Option<String>,
    pub(super) limit_stiffness: Option<f64>,
    pub(super) tau_s: Option<f64>,
    pub(super) tau_c: Option<f64>,
    pub(super) constraint_iterations: Option<i64>,
    pub(super) constraint_tolerance: Option<f64>,
    pub(super) stiffening: Option<f64>,
    pub(super) stiffening_cubic: Option<f64>,
    pub(super) softening: Option<f64>,
    pub(super) gent_limit: Option<f64>,
    pub(super) compression_ratio: Option<f64>,
    pub(super) prony_g: Option<f64>,
    pub(super) prony_tau: Option<f64>,
    pub(super) elasticity: Option<String>,
    pub(super) self_collision: Option<bool>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSupport {
    pub(super) kind: Option<String>,
    pub(super) friction: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBox {
    #[serde(deserialize_with = "three")]
    pub(super) min: [f64; 3],
    #[serde(deserialize_with = "three")]
    pub(super) max: [f64; 3],
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLoad {
    #[serde(deserialize_with = "three")]
    pub(super) min: [f64; 3],
    #[serde(deserialize_with = "three")]
    pub(super) max: [f64; 3],
    pub(super) mass: Option<f64>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) force: Option<[f64; 3]>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawFinger {
    pub(super) shape: Option<String>,
    pub(super) radius: Option<f64>,
    /// `[x, y]` for a plate, `[x, y, z]` for a box.
    pub(super) size: Option<Vec<f64>>,
    /// `[[finger.part]]`: more rigid shapes moving with the finger.
    pub(super) part: Option<Vec<RawPart>>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) position: Option<[f64; 3]>,
    pub(super) free_axes: Option<String>,
    pub(super) control: Option<String>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) force: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) velocity: Option<[f64; 3]>,
    pub(super) mass: Option<f64>,
    pub(super) young_modulus: Option<f64>,
    pub(super) poisson_ratio: Option<f64>,
    pub(super) restitution: Option<f64>,
    pub(super) friction: Option<f64>,
    pub(super) stick_velocity: Option<f64>,
    pub(super) stick_stiffness: Option<f64>,
    pub(super) stick_damping: Option<f64>,
    pub(super) travel: Option<f64>,
    pub(super) start_time: Option<f64>,
    pub(super) ramp_time: Option<f64>,
    pub(super) guide_speed: Option<f64>,
    pub(super) guide_friction: Option<f64>,
    pub(super) contact_stiffness_scale: Option<f64>,
}

#[derive(Debug, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRegion {
    #[serde(deserialize_with = "three")]
    pub(super) min: [f64; 3],
    #[serde(deserialize_with = "three")]
    pub(super) max: [f64; 3],
    pub(super) young_modulus: Option<f64>,
    pub(super) density: Option<f64>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPart {
    pub(super) shape: Option<String>,
    pub(super) radius: Option<f64>,
    pub(super) size: Option<Vec<f64>>,
    #[serde(default, deserialize_with = "maybe_three")]
    pub(super) offset: Option<[f64; 3]>,
}

#[derive(Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGrasp {
    pub(super) acceleration: Option<f64>,
    pub(super) shake: Option<f64>,
    pub(super) slip_tolerance: Option<f64>,
    pub(super) hold: Option<f64>,
    pub(super) damage: Option<String>,
    pub(super) limit: Option<f64>,
    pub(super) material: Option<String>,
}
