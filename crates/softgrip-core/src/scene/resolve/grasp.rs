//! `[grasp]` (softgrip): the lift the grasp window's grip must hold through and its damage limit.
//! No key has a default here: the command's options and defaults stand in for those left out.

use super::resolver::{At, Resolver};
use crate::scene::error::SceneError;
use crate::scene::raw::RawGrasp;
use crate::scene::{DAMAGE_MATERIALS, DamageMaterial, DamageMeasure, Grasp};

/// Where `key` of `[grasp]` is reported.
fn at(key: &str) -> At<'_> {
    At {
        table: "grasp",
        index: None,
        key,
    }
}

impl Resolver<'_> {
    /// `[grasp]`, in file order; a material without a limit for the damage asked is an error.
    pub(super) fn grasp(&mut self, raw: RawGrasp) -> Result<Grasp, SceneError> {
        let acceleration = self.optional(
            at("acceleration"),
            raw.acceleration,
            |a| a >= 0.0,
            "must be >= 0 m/s^2 (upward; 9.81 is one g)",
        )?;
        let shake = self.optional(
            at("shake"),
            raw.shake,
            |a| a >= 0.0,
            "must be >= 0 m/s^2 (sideways)",
        )?;
        let slip_tolerance = self.optional(
            at("slip_tolerance"),
            raw.slip_tolerance,
            |x| x > 0.0,
            "must be > 0 m",
        )?;
        let hold = self.optional(at("hold"), raw.hold, |t| t >= 0.0, "must be >= 0 s")?;
        let damage = self.grasp_damage(raw.damage)?;
        let limit = self.optional(
            at("limit"),
            raw.limit,
            |x| x > 0.0,
            "must be > 0, in the damage measure's unit (Pa for stress and pressure)",
        )?;
        let material = self.grasp_material(raw.material)?;
        if let (Some(m), Some(d)) = (material, damage)
            && limit.is_none()
            && m.limit(d).is_none()
        {
            return Err(self.err(
                at("damage"),
                format!("{:?}", d.name()),
                &format!(
                    "material {:?} has no {} limit in the table: give limit, or a damage it has",
                    m.name,
                    d.describe()
                ),
            ));
        }
        Ok(Grasp {
            acceleration,
            shake,
            slip_tolerance,
            hold,
            damage,
            limit,
            material,
        })
    }

    /// `damage`: the measure's name, if given.
    fn grasp_damage(&self, damage: Option<String>) -> Result<Option<DamageMeasure>, SceneError> {
        let damage = match damage {
            None => None,
            Some(name) => Some(DamageMeasure::from_name(&name).ok_or_else(|| {
                self.err(
                    at("damage"),
                    format!("{name:?}"),
                    "must be \"strain\" (largest principal Green strain), \"stress\" (von Mises, Pa) or \"pressure\" (contact, Pa)",
                )
            })?),
        };
        Ok(damage)
    }

    /// `material`: a name of [`DAMAGE_MATERIALS`], if given.
    fn grasp_material(
        &self,
        material: Option<String>,
    ) -> Result<Option<DamageMaterial>, SceneError> {
        let material = match material {
            None => None,
            Some(name) => Some(
                DAMAGE_MATERIALS
                    .iter()
                    .find(|m| m.name == name)
                    .copied()
                    .ok_or_else(|| {
                        let names: Vec<String> = DAMAGE_MATERIALS
                            .iter()
                            .map(|m| format!("{:?}", m.name))
                            .collect();
                        self.err(
                            at("material"),
                            format!("{name:?}"),
                            &format!(
                                "must be one of {}, or leave it out and give limit",
                                names.join(", ")
                            ),
                        )
                    })?,
            ),
        };
        Ok(material)
    }
}
