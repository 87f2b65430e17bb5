//! `[model]`: damping (the springs' dampers, Rayleigh's), volume preservation, the spring limits, the elastic law (springs or
//! neo-Hookean elements) and its nonlinear and viscous terms, self-collision.

use super::resolver::{At, Resolver};
use crate::scene::defaults::DEFAULT_LIMIT_STIFFNESS;
use crate::scene::error::SceneError;
use crate::scene::raw::RawModel;
use crate::scene::{BulkPressure, Elasticity, ModelParams};

/// Where `key` of `[model]` is reported.
fn at(key: &str) -> At<'_> {
    At {
        table: "model",
        index: None,
        key,
    }
}

/// The spring limits of `[model]` (see [`ModelParams`]'s fields of the same names).
struct SpringLimits {
    limit_stiffness: f64,
    tau_s: Option<f64>,
    tau_c: Option<f64>,
    constraint_iterations: usize,
    constraint_tolerance: Option<f64>,
}

/// The nonlinear terms of the elastic law (see [`ModelParams`]'s fields of the same names).
struct NonlinearTerms {
    stiffening: f64,
    stiffening_cubic: f64,
    softening: f64,
    gent_limit: f64,
    compression_ratio: f64,
}

impl Resolver<'_> {
    /// `[model]`, stage by stage in file order (the order of the defaults recorded and of the
    /// errors reported).
    pub(super) fn model(&mut self, m: RawModel) -> Result<ModelParams, SceneError> {
        let (damping_ratio, rayleigh_mass, rayleigh_stiffness) = self.model_damping(&m)?;
        let (alpha, bulk_modulus) = self.model_volume(&m)?;
        let elasticity = self.model_elasticity(&m)?;
        let bulk_pressure = self.model_bulk_pressure(&m, elasticity)?;
        let limits = self.model_spring_limits(&m)?;
        let terms = self.model_nonlinear_terms(&m)?;
        let (prony_g, prony_tau) = self.model_prony(&m)?;
        self.check_terms_fit_elasticity(elasticity, &terms)?;
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
            limit_stiffness: limits.limit_stiffness,
            tau_s: limits.tau_s,
            tau_c: limits.tau_c,
            constraint_iterations: limits.constraint_iterations,
            constraint_tolerance: limits.constraint_tolerance,
            stiffening: terms.stiffening,
            stiffening_cubic: terms.stiffening_cubic,
            softening: terms.softening,
            gent_limit: terms.gent_limit,
            compression_ratio: terms.compression_ratio,
            prony_g,
            prony_tau,
        })
    }

    /// The dampers: `(damping_ratio, rayleigh_mass, rayleigh_stiffness)`.
    fn model_damping(&mut self, m: &RawModel) -> Result<(f64, f64, f64), SceneError> {
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
        Ok((damping_ratio, rayleigh_mass, rayleigh_stiffness))
    }

    /// Volume preservation: `(alpha, bulk_modulus)`.
    fn model_volume(&mut self, m: &RawModel) -> Result<(f64, f64), SceneError> {
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
        Ok((alpha, bulk_modulus))
    }

    /// The elastic law: springs or neo-Hookean elements.
    fn model_elasticity(&mut self, m: &RawModel) -> Result<Elasticity, SceneError> {
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
        Ok(elasticity)
    }

    /// Where the bulk term measures the volume change; its default depends on `elasticity`.
    fn model_bulk_pressure(
        &mut self,
        m: &RawModel,
        elasticity: Elasticity,
    ) -> Result<BulkPressure, SceneError> {
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
        Ok(bulk_pressure)
    }

    /// The limit springs, the over-stretch and over-compression limits and their projection.
    fn model_spring_limits(&mut self, m: &RawModel) -> Result<SpringLimits, SceneError> {
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
        Ok(SpringLimits {
            limit_stiffness,
            tau_s,
            tau_c,
            constraint_iterations: iters as usize,
            constraint_tolerance,
        })
    }

    /// The elastic law's nonlinear terms: stiffening, Yeoh's and Gent's terms, the
    /// compression ratio.
    fn model_nonlinear_terms(&mut self, m: &RawModel) -> Result<NonlinearTerms, SceneError> {
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
        Ok(NonlinearTerms {
            stiffening,
            stiffening_cubic,
            softening,
            gent_limit,
            compression_ratio,
        })
    }

    /// Viscoelasticity, one Prony term: `(prony_g, prony_tau)`.
    fn model_prony(&mut self, m: &RawModel) -> Result<(f64, f64), SceneError> {
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
        Ok((prony_g, prony_tau))
    }

    /// Rejects a nonlinear term that the chosen elastic law does not have.
    fn check_terms_fit_elasticity(
        &self,
        elasticity: Elasticity,
        terms: &NonlinearTerms,
    ) -> Result<(), SceneError> {
        let NonlinearTerms {
            stiffening_cubic,
            softening,
            gent_limit,
            compression_ratio,
            ..
        } = *terms;
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
        Ok(())
    }
}
