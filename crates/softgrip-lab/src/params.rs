//! Scene parameters by name, for sweeps and fits (`--param tau_c=...`):
//! reading one, setting one with the scene file's own range checks (a bad
//! value is an error naming the parameter and the allowed range), and the
//! grids of `softgrip sweep`.

use crate::error::LabError;
use softgrip_core::scene::Scene;

/// A parameter that sweeps and fits may vary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Param {
    /// The name sweeps and fits give (`--params young_modulus`).
    pub name: &'static str,
    /// Its SI unit (`Pa`, `kg/m^3`; empty for a dimensionless one).
    pub unit: &'static str,
    /// Natural on a log scale (moduli, alpha, the spring limits: their
    /// plausible values span decades, and a search needs as many trials
    /// at 0.02 to 0.05, where a limit acts, as at 0.2 to 0.5, where it
    /// often does not).
    pub log: bool,
    /// The scene file's key it sets (e.g. `[object] young_modulus`).
    pub about: &'static str,
}

/// Every parameter sweeps and fits may vary.
pub const PARAMS: &[Param] = &[
    Param {
        name: "young_modulus",
        unit: "Pa",
        log: true,
        about: "[object] young_modulus",
    },
    Param {
        name: "poisson_ratio",
        unit: "",
        log: false,
        about: "[object] poisson_ratio",
    },
    Param {
        name: "density",
        unit: "kg/m^3",
        log: false,
        about: "[object] density",
    },
    Param {
        name: "alpha",
        unit: "",
        log: true,
        about: "[model] alpha, the volume-preservation force scale",
    },
    Param {
        name: "tau_s",
        unit: "",
        log: true,
        about: "[model] tau_s, the over-stretch limit",
    },
    Param {
        name: "tau_c",
        unit: "",
        log: true,
        about: "[model] tau_c, the over-compression limit",
    },
    Param {
        name: "damping_ratio",
        unit: "",
        log: false,
        about: "[model] damping_ratio",
    },
    Param {
        name: "rayleigh_mass",
        unit: "1/s",
        log: true,
        about: "[model] rayleigh_mass, Rayleigh damping's mass-proportional a (softgrip)",
    },
    Param {
        name: "rayleigh_stiffness",
        unit: "s",
        log: true,
        about: "[model] rayleigh_stiffness, Rayleigh damping's stiffness-proportional b (softgrip)",
    },
    Param {
        name: "bulk_modulus",
        unit: "Pa",
        log: true,
        about: "[model] bulk_modulus (softgrip)",
    },
    Param {
        name: "limit_stiffness",
        unit: "",
        log: true,
        about: "[model] limit_stiffness (softgrip)",
    },
    Param {
        name: "stiffening",
        unit: "",
        log: false,
        about: "[model] stiffening, strain stiffening of the springs or the neo-Hookean elements (softgrip)",
    },
    Param {
        name: "stiffening_cubic",
        unit: "",
        log: false,
        about: "[model] stiffening_cubic, the third-order strain stiffening of the neo-Hookean elements (softgrip)",
    },
    Param {
        name: "softening",
        unit: "",
        log: false,
        about: "[model] softening, the early softening of the neo-Hookean elements before stiffening_cubic (softgrip)",
    },
    Param {
        name: "gent_limit",
        unit: "",
        log: true,
        about: "[model] gent_limit, Gent's J_m: the I1 - 3 where the neo-Hookean elements lock (softgrip)",
    },
    Param {
        name: "gent_stiffening",
        unit: "",
        log: false,
        about: "1 / [model] gent_limit, Gent's locking as a stiffening: 0 = none (the neo-Hookean solid), 1 = locking at I1 - 3 = 1 (softgrip)",
    },
    Param {
        name: "compression_ratio",
        unit: "",
        log: true,
        about: "[model] compression_ratio, spring stiffness in compression over tension (softgrip)",
    },
    Param {
        name: "prony_g",
        unit: "",
        log: false,
        about: "[model] prony_g, the share of the stiffness that relaxes (softgrip)",
    },
    Param {
        name: "prony_tau",
        unit: "s",
        log: true,
        about: "[model] prony_tau, the relaxation time constant (softgrip)",
    },
    Param {
        name: "region_young_modulus",
        unit: "Pa",
        log: true,
        about: "every [[region]] young_modulus (softgrip)",
    },
    Param {
        name: "friction",
        unit: "",
        log: false,
        about: "every [[finger]] friction",
    },
    Param {
        name: "table_friction",
        unit: "",
        log: false,
        about: "[support] friction, object-table (with kind = \"table\")",
    },
    Param {
        name: "guide_friction",
        unit: "N",
        log: false,
        about: "every [[finger]] guide_friction, Coulomb friction in the finger's guide (softgrip)",
    },
    Param {
        name: "restitution",
        unit: "",
        log: false,
        about: "every [[finger]] restitution",
    },
    Param {
        name: "contact_stiffness_scale",
        unit: "",
        log: true,
        about: "every [[finger]] contact_stiffness_scale (softgrip)",
    },
    Param {
        name: "dt",
        unit: "s",
        log: true,
        about: "[simulation] dt",
    },
];

/// The parameter called `name`, or an error listing the known ones.
pub fn find(name: &str) -> Result<&'static Param, LabError> {
    PARAMS.iter().find(|p| p.name == name).ok_or_else(|| {
        LabError::Input(format!(
            "unknown parameter {name:?}; known: {}",
            PARAMS.iter().map(|p| p.name).collect::<Vec<_>>().join(", ")
        ))
    })
}

/// The parameter's value in `scene` (`None`: a limit that is off, or a
/// finger parameter in a scene without fingers).
pub fn get(scene: &Scene, name: &str) -> Result<Option<f64>, LabError> {
    find(name)?;
    let first = scene.fingers.first();
    Ok(match name {
        "young_modulus" => Some(scene.object.young_modulus),
        "poisson_ratio" => Some(scene.object.poisson_ratio),
        "density" => Some(scene.object.density),
        "alpha" => Some(scene.model.alpha),
        "tau_s" => scene.model.tau_s,
        "tau_c" => scene.model.tau_c,
        "damping_ratio" => Some(scene.model.damping_ratio),
        "rayleigh_mass" => Some(scene.model.rayleigh_mass),
        "rayleigh_stiffness" => Some(scene.model.rayleigh_stiffness),
        "bulk_modulus" => Some(scene.model.bulk_modulus),
        "limit_stiffness" => Some(scene.model.limit_stiffness),
        "stiffening" => Some(scene.model.stiffening),
        "stiffening_cubic" => Some(scene.model.stiffening_cubic),
        "softening" => Some(scene.model.softening),
        "gent_limit" => Some(scene.model.gent_limit),
        "gent_stiffening" => Some(if scene.model.gent_limit > 0.0 {
            1.0 / scene.model.gent_limit
        } else {
            0.0
        }),
        "compression_ratio" => Some(scene.model.compression_ratio),
        "prony_g" => Some(scene.model.prony_g),
        "prony_tau" => Some(scene.model.prony_tau),
        "region_young_modulus" => scene.regions.first().map(|r| r.young_modulus),
        "friction" => first.map(|f| f.friction),
        "table_friction" => (scene.support.kind == softgrip_core::scene::SupportKind::Table)
            .then_some(scene.support.friction),
        "restitution" => first.map(|f| f.restitution),
        "guide_friction" => first.map(|f| f.guide_friction),
        "contact_stiffness_scale" => first.map(|f| f.contact_stiffness_scale),
        "dt" => Some(scene.simulation.dt),
        _ => None,
    })
}

/// `scene` with `name` set to `value`, checked as a scene file is: a value
/// the file would reject is an error naming the parameter and the rule.
pub fn set(scene: &Scene, name: &str, value: f64) -> Result<Scene, LabError> {
    find(name)?;
    let mut s = scene.clone();
    assign(&mut s, name, value)?;
    checked(scene, &s, name, value)
}

/// Sets `name` to `value` in `s`, unchecked; an error where the scene has nothing it applies to.
fn assign(s: &mut Scene, name: &str, value: f64) -> Result<(), LabError> {
    match name {
        "young_modulus" => s.object.young_modulus = value,
        "poisson_ratio" => s.object.poisson_ratio = value,
        "density" => s.object.density = value,
        "alpha" => s.model.alpha = value,
        "tau_s" => s.model.tau_s = Some(value),
        "tau_c" => s.model.tau_c = Some(value),
        "damping_ratio" => s.model.damping_ratio = value,
        "rayleigh_mass" => s.model.rayleigh_mass = value,
        "rayleigh_stiffness" => s.model.rayleigh_stiffness = value,
        "bulk_modulus" => s.model.bulk_modulus = value,
        "limit_stiffness" => s.model.limit_stiffness = value,
        "stiffening" => s.model.stiffening = value,
        "stiffening_cubic" => s.model.stiffening_cubic = value,
        "softening" => s.model.softening = value,
        "gent_limit" => s.model.gent_limit = value,
        "gent_stiffening" => {
            // 0 is the neo-Hookean solid; a negative one is no Gent solid (the file's rule
            // refuses the limit it would give).
            // Below 1e-12 it is the neo-Hookean solid to every digit: off.
            s.model.gent_limit = if value.abs() < 1e-12 {
                0.0
            } else {
                1.0 / value
            };
        }
        "compression_ratio" => s.model.compression_ratio = value,
        "prony_g" => s.model.prony_g = value,
        "prony_tau" => s.model.prony_tau = value,
        "region_young_modulus" => {
            if s.regions.is_empty() {
                return Err(LabError::input(
                    "region_young_modulus needs a [[region]] in the scene",
                ));
            }
            for r in &mut s.regions {
                r.young_modulus = value;
            }
        }
        "table_friction" => {
            if s.support.kind != softgrip_core::scene::SupportKind::Table {
                return Err(LabError::input(
                    "table_friction needs a table: the scene's [support] kind is not \"table\"",
                ));
            }
            s.support.friction = value;
        }
        "friction" | "restitution" | "contact_stiffness_scale" | "guide_friction" => {
            if s.fingers.is_empty() {
                return Err(LabError::Input(format!(
                    "{name} is a finger parameter and the scene has no finger"
                )));
            }
            for f in &mut s.fingers {
                match name {
                    "friction" => f.friction = value,
                    "restitution" => f.restitution = value,
                    "guide_friction" => f.guide_friction = value,
                    _ => f.contact_stiffness_scale = value,
                }
            }
        }
        "dt" => s.simulation.dt = value,
        _ => {}
    }
    Ok(())
}

/// `s` (`scene` with `name` set to `value`) read back as a scene file is, keeping `scene`'s
/// source and mesh path; a value the file would reject is an error naming the rule.
fn checked(scene: &Scene, s: &Scene, name: &str, value: f64) -> Result<Scene, LabError> {
    let mut checked = Scene::from_toml_str(&s.to_toml(), "parameter").map_err(|e| {
        let message = e.to_string();
        let rule = message
            .split_once("is not allowed: ")
            .map_or(message.as_str(), |(_, r)| r);
        LabError::Input(format!("{name} = {value}: not allowed: {rule}"))
    })?;
    checked.source.clone_from(&scene.source);
    if let (
        softgrip_core::scene::Shape::Mesh { path: a, .. },
        softgrip_core::scene::Shape::Mesh { path: b, .. },
    ) = (&mut checked.object.shape, &scene.object.shape)
    {
        a.clone_from(b);
    }
    Ok(checked)
}

/// One axis of a sweep: a parameter and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct Axis {
    /// The parameter.
    pub param: &'static Param,
    /// Its values, in its unit, in the sweep's order.
    pub values: Vec<f64>,
}

/// Parses `name=start:end:count`, with `:log` for log spacing (e.g.
/// `tau_c=0.01:0.25:25`, `alpha=1e5:1e8:7:log`), or `name=v1,v2,...`.
pub fn parse_axis(text: &str) -> Result<Axis, LabError> {
    let bad = |why: &str| {
        LabError::Input(format!(
            "--param {text:?}: {why}; write name=start:end:count (add :log for log spacing) or name=v1,v2,..."
        ))
    };
    let (name, spec) = text.split_once('=').ok_or_else(|| bad("no '='"))?;
    let param = find(name.trim())?;
    let number = |t: &str| -> Result<f64, LabError> {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| bad(&format!("{t:?} is not a number")))
    };
    let values = if spec.contains(':') {
        let parts: Vec<&str> = spec.split(':').collect();
        let log = match parts.len() {
            3 => false,
            4 if parts[3].trim() == "log" => true,
            _ => return Err(bad("a range has start:end:count")),
        };
        let (a, b) = (number(parts[0])?, number(parts[1])?);
        let n: usize = parts[2]
            .trim()
            .parse()
            .ok()
            .filter(|n| (1..=10_000).contains(n))
            .ok_or_else(|| bad("the count must be a whole number from 1 to 10000"))?;
        if log && (a <= 0.0 || b <= 0.0) {
            return Err(bad("a log range needs positive ends"));
        }
        (0..n)
            .map(|k| {
                let t = if n == 1 {
                    0.0
                } else {
                    k as f64 / (n - 1) as f64
                };
                if k == 0 {
                    a
                } else if k + 1 == n {
                    b
                } else if log {
                    (a.ln() + t * (b.ln() - a.ln())).exp()
                } else {
                    a + t * (b - a)
                }
            })
            .collect()
    } else {
        spec.split(',').map(number).collect::<Result<Vec<_>, _>>()?
    };
    if values.is_empty() {
        return Err(bad("no values"));
    }
    Ok(Axis { param, values })
}
