//! The tables of boxes: `[[fixed]]` (particles held still), `[[load]]` (mass and force on the
//! particles inside) and `[[region]]` (elements of other material).

use glam::DVec3;

use super::resolver::{At, Resolver};
use crate::scene::error::SceneError;
use crate::scene::raw::{RawBox, RawLoad, RawRegion};
use crate::scene::{AaBox, Load, Object, Region};

impl Resolver<'_> {
    pub(super) fn fixed(&mut self, raw: &[RawBox]) -> Result<Vec<AaBox>, SceneError> {
        let mut fixed = Vec::new();
        for (i, b) in raw.iter().enumerate() {
            let at = At {
                table: "fixed",
                index: Some(i),
                key: "max",
            };
            fixed.push(self.aabox(at, b.min, b.max)?);
        }
        Ok(fixed)
    }

    pub(super) fn loads(&mut self, raw: &[RawLoad]) -> Result<Vec<Load>, SceneError> {
        let mut loads = Vec::new();
        for (i, l) in raw.iter().enumerate() {
            let at = |key| At {
                table: "load",
                index: Some(i),
                key,
            };
            let region = self.aabox(at("max"), l.min, l.max)?;
            let mass = self.number(at("mass"), l.mass, 0.0, |x| x >= 0.0, "must be >= 0 kg")?;
            let force = self.vec3(at("force"), l.force, [0.0; 3])?;
            loads.push(Load {
                region,
                mass,
                force,
            });
        }
        Ok(loads)
    }

    /// The regions, whose material defaults to the object's.
    pub(super) fn regions(
        &mut self,
        raw: &[RawRegion],
        object: &Object,
    ) -> Result<Vec<Region>, SceneError> {
        let mut regions = Vec::new();
        for (i, r) in raw.iter().enumerate() {
            let at = |key| At {
                table: "region",
                index: Some(i),
                key,
            };
            let region = self.aabox(at("max"), r.min, r.max)?;
            let young_modulus = self.number(
                at("young_modulus"),
                r.young_modulus,
                object.young_modulus,
                |x| (1.0..=1e12).contains(&x),
                "must be a modulus from 1 Pa to 1e12 Pa (Ecoflex 00-20 is 57.6e3 Pa, steel 2e11)",
            )?;
            let density = self.number(
                at("density"),
                r.density,
                object.density,
                |x| (1.0..=1e5).contains(&x),
                "must be a density from 1 to 1e5 kg/m^3",
            )?;
            regions.push(Region {
                region,
                young_modulus,
                density,
            });
        }
        Ok(regions)
    }

    fn aabox(&self, at: At<'_>, min: [f64; 3], max: [f64; 3]) -> Result<AaBox, SceneError> {
        let (min, max) = (DVec3::from_array(min), DVec3::from_array(max));
        if !min.is_finite() || !max.is_finite() || !min.cmple(max).all() {
            return Err(self.err(
                at,
                format!("{:?} (min = {:?})", max.to_array(), min.to_array()),
                "min must be <= max on every axis, all finite (m)",
            ));
        }
        Ok(AaBox { min, max })
    }
}
