//! `[model]`: damping (the springs' dampers, Rayleigh's), volume preservation, the spring limits, the elastic law (springs or
//! neo-Hookean elements) and its nonlinear and viscous terms, self-collision.

use super::resolver::{At, Resolver};
use crate::scene::defaults::DEFAULT_LIMIT_STIFFNESS;
use crate::scene::error::SceneError;
use crate::scene::raw::RawModel;
use crate::scene::{BulkPressure, Elasticity, ModelParams};

impl Resolver<'_> {
    pub(super) fn model(&mut self, m: RawModel) -> Result<ModelParams, SceneError> {
        let at = |key| At {
            table: "model",
            index: None,
            key,
        };
        let damping_ratio = self.number(
            at("damping_ratio"),
            m.damping_ratio,
            1.0,
            |x| x >= 0.0,
            "must be >= 0 (1 = critical damping of each spring)",
        )?;
        let rayleigh_mass = self.number(
            at("rayleigh_mass"),
            m.rayleigh_mass,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 (1/s; Rayleigh damping's mass-proportional a: each particle's force -a m v, which damps rigid motion too; 0 = off)",
        )?;
        let rayleigh_stiffness = self.number(
            at("rayleigh_stiffness"),
            m.rayleigh_stiffness,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 (s; Rayleigh damping's stiffness-proportional b: a mode of angular frequency w is damped at ratio b w / 2; 0 = off)",
        )?;
        let alpha = self.number(
            at("alpha"),
            m.alpha,
            6e6,
            |x| x >= 0.0,
            "must be >= 0 (0 = no volume preservation; the thesis fits 6e6)",
        )?;
        let bulk_modulus = self.number(
            at("bulk_modulus"),
            m.bulk_modulus,
            0.0,
            |x| x >= 0.0,
            "must be >= 0 Pa (0 = off; E / (3 (1 - 2 nu)) is the material's own bulk modulus)",
        )?;
        let elasticity_at = at("elasticity");
        let elasticity = match self
            .default(elasticity_at, m.elasticity.clone(), "springs".to_string())
            .as_str()
        {
            "springs" => Elasticity::Springs,
            "neo-hookean" => Elasticity::NeoHookean,
            other => {
                return Err(self.err(
                    elasticity_at,
                    format!("{other:?}"),
                    "must be \"springs\" (the thesis's lattice) or \"neo-hookean\" (finite elements; with bulk_pressure = \"element\" the plain linear tetrahedron)",
                ));
            }
        };
        let bulk_pressure_at = at("bulk_pressure");
        let bulk_pressure = match self
            .default(
                bulk_pressure_at,
                m.bulk_pressure.clone(),
                // Linear tetrahedra lock as nu nears 1/2; the lattice's bulk
                // term keeps the thesis scenes' figures.
                match elasticity {
                    Elasticity::NeoHookean => "nodal",
                    Elasticity::Springs => "element",
                }
                .to_string(),
            )
            .as_str()
        {
            "element" => BulkPressure::Element,
            "nodal" => BulkPressure::Nodal,
            other => {
                return Err(self.err(
                    bulk_pressure_at,
                    format!("{other:?}"),
                    "must be \"element\" (each element's own volume) or \"nodal\" (averaged over each node's elements: less locking)",
                ));
            }
        };
        let limit_stiffness = self.number(
            at("limit_stiffness"),
            m.limit_stiffness,
            DEFAULT_LIMIT_STIFFNESS,
            |x| (0.0..=1e6).contains(&x),
            "must be in [0, 1e6] (a multiple of each spring's stiffness; 0 = the thesis's projection alone)",
        )?;
        let tau_s = self.optional(
            at("tau_s"),
            m.tau_s,
            |x| x > 0.0,
            "must be > 0 (omit the key for no limit; the thesis fits 0.16)",
        )?;
        let tau_c = self.optional(
            at("tau_c"),
            m.tau_c,
            |x| x > 0.0 && x < 1.0,
            "must be in (0, 1) (omit the key for no limit; the thesis fits 0.155)",
        )?;
        let iters = self.default(at("constraint_iterations"), m.constraint_iterations, 10);
        if !(0..=10_000).contains(&iters) {
            return Err(self.err(at("constraint_iterations"), iters, "must be in 0..=10000"));
        }
        let constraint_tolerance = self.optional(
            at("constraint_tolerance"),
            m.constraint_tolerance,
            |x| x > 0.0 && x <= 0.1,
            "must be in (0, 0.1] (a fraction of the rest length; omit the key for exactly constraint_iterations sweeps)",
        )?;
        let stiffening = self.number(
            at("stiffening"),
            m.stiffening,
            0.0,
            |x| (0.0..=1e5).contains(&x),
            "must be in [0, 1e5] (a spring's F = k dl (1 + stiffening (dl / l0)^2), an element's energy mu stiffening / 12 max(I1 - 3, 0)^2 more; 0 = none)",
        )?;
        let stiffening_cubic = self.number(
            at("stiffening_cubic"),
            m.stiffening_cubic,
            0.0,
            |x| (0.0..=1e5).contains(&x),
            "must be in [0, 1e5] (an element's energy mu stiffening_cubic / 54 max(I1 - 3, 0)^3 more; 0 = none)",
        )?;
        let softening = self.number(
            at("softening"),
            m.softening,
            0.0,
            |x| (0.0..1.0).contains(&x),
            "must be in [0, 1) (the early softening of a two-term Yeoh solid: the shear modulus dips to 1 - softening^2 of mu before stiffening_cubic lifts it; 0 = none)",
        )?;
        let gent_limit = self.number(
            at("gent_limit"),
            m.gent_limit,
            0.0,
            |x| x == 0.0 || (0.1..=1e12).contains(&x),
            "must be 0 (none) or in [0.1, 1e12] (Gent's J_m, the I1 - 3 where the material locks: the shear modulus is mu J_m / (J_m - (I1 - 3)); rubbers about 30 to 100)",
        )?;
        let compression_ratio = self.number(
            at("compression_ratio"),
            m.compression_ratio,
            1.0,
            |x| x > 0.0 && x <= 100.0,
            "must be in (0, 100] (compression stiffness over tension stiffness; 1 = symmetric)",
        )?;
        let prony_g = self.number(
            at("prony_g"),
            m.prony_g,
            0.0,
            |x| (0.0..1.0).contains(&x),
            "must be in [0, 1) (the share of the stiffness that relaxes; 0 = elastic)",
        )?;
        let prony_tau = self.number(
            at("prony_tau"),
            m.prony_tau,
            1.0,
            |x| x > 0.0,
            "must be > 0 s (the relaxation time constant)",
        )?;
        if elasticity == Elasticity::Springs {
            for (key, value) in [
                ("stiffening_cubic", stiffening_cubic),
                ("softening", softening),
                ("gent_limit", gent_limit),
            ] {
                if value != 0.0 {
                    return Err(self.err(
                        at(key),
                        value,
                        "applies to neo-Hookean elements only: set [model] elasticity = \"neo-hookean\", or remove the key (the springs' law is stiffening alone)",
                    ));
                }
            }
        }
        if elasticity == Elasticity::NeoHookean {
            for (key, value, plain) in [("compression_ratio", compression_ratio, 1.0)] {
                if value != plain {
                    return Err(self.err(
                        at(key),
                        value,
                        "applies to the springs only (the neo-Hookean elements have no such term): remove the key, or set [model] elasticity = \"springs\"",
                    ));
                }
            }
        }
        let self_collision = self.default(at("self_collision"), m.self_collision, false);
        Ok(ModelParams {
            self_collision,
            elasticity,
            damping_ratio,
            rayleigh_mass,
            rayleigh_stiffness,
            alpha,
            bulk_modulus,
            bulk_pressure,
            limit_stiffness,
            tau_s,
            tau_c,
            constraint_iterations: iters as usize,
            constraint_tolerance,
            stiffening,
            stiffening_cubic,
            softening,
            gent_limit,
            compression_ratio,
            prony_g,
            prony_tau,
        })
    }
}
