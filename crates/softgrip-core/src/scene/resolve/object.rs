//! `[object]`: the shape (a cuboid, a cylinder or a mesh file), its meshing and its material.

use std::path::PathBuf;

use glam::DVec3;

use super::resolver::{At, Resolver};
use crate::scene::error::SceneError;
use crate::scene::raw::RawObject;
use crate::scene::{Object, Shape};

fn at(key: &str) -> At<'_> {
    At {
        table: "object",
        index: None,
        key,
    }
}

impl Resolver<'_> {
    pub(super) fn object(&mut self, o: Option<RawObject>) -> Result<Object, SceneError> {
        let Some(o) = o else {
            return Err(self.invalid("the [object] table is missing: a scene needs at least [object] shape = \"cuboid\" with size = [x, y, z]"));
        };
        let shape = self.object_shape(&o)?;
        if !matches!(shape, Shape::Mesh { .. }) {
            for (key, given) in [
                ("scale", o.scale.is_some()),
                ("position", o.position.is_some()),
            ] {
                if given {
                    return Err(self.invalid(format!(
                        "[object] {key} applies to shape = \"mesh\" only; remove it (built-in shapes are centred at x = y = 0 with their bottom at z = 0)"
                    )));
                }
            }
        }
        let smallest = match &shape {
            Shape::Cuboid { size } => size.min_element(),
            Shape::Cylinder { radius, height } => height.min(2.0 * radius),
            Shape::Mesh { .. } => f64::INFINITY,
        };
        let edge_length = self.number(
            at("edge_length"),
            o.edge_length,
            0.004,
            |x| x > 0.0 && x <= smallest,
            "must be > 0 and no larger than the object's smallest extent (m)",
        )?;
        let density = self.number(
            at("density"),
            o.density,
            1070.0,
            |x| (1.0..=1e5).contains(&x),
            "must be a density from 1 to 1e5 kg/m^3 (silicone rubbers are about 1070)",
        )?;
        let young_modulus = self.number(
            at("young_modulus"),
            o.young_modulus,
            57.6e3,
            |x| (1.0..=1e12).contains(&x),
            "must be a modulus from 1 Pa to 1e12 Pa (Ecoflex 00-20 is 57.6e3 Pa, steel 2e11)",
        )?;
        let poisson_ratio = self.number(
            at("poisson_ratio"),
            o.poisson_ratio,
            0.49,
            |x| x > -1.0 && x < 0.5,
            "must be in (-1, 0.5); 0.5 is perfectly incompressible and not allowed (use 0.49)",
        )?;
        Ok(Object {
            shape,
            edge_length,
            density,
            young_modulus,
            poisson_ratio,
        })
    }

    /// `shape` with the keys it requires: `size`; `radius` and `height`; `path` (with `scale`
    /// and `position`).
    fn object_shape(&mut self, o: &RawObject) -> Result<Shape, SceneError> {
        Ok(match o.shape.as_deref() {
            Some("cuboid") => {
                let Some(size) = o.size else {
                    return Err(self.invalid(
                        "[object] size = [x, y, z] (m) is required for shape = \"cuboid\"",
                    ));
                };
                if !size.iter().all(|c| c.is_finite() && *c > 0.0) {
                    return Err(self.err(
                        at("size"),
                        format!("{size:?}"),
                        "every extent must be > 0 m",
                    ));
                }
                Shape::Cuboid {
                    size: DVec3::from_array(size),
                }
            }
            Some("cylinder") => {
                let radius = self.required(at("radius"), o.radius, |x| x > 0.0, "radius > 0 m")?;
                let height = self.required(at("height"), o.height, |x| x > 0.0, "height > 0 m")?;
                Shape::Cylinder { radius, height }
            }
            Some("mesh") => match o.path.clone() {
                Some(p) if !p.trim().is_empty() => Shape::Mesh {
                    path: PathBuf::from(p),
                    scale: self.number(
                        at("scale"),
                        o.scale,
                        1.0,
                        |x| x > 0.0,
                        "must be > 0 (0.001 for a file in millimetres)",
                    )?,
                    position: self.vec3(at("position"), o.position, [0.0; 3])?,
                },
                _ => {
                    return Err(self
                        .invalid("[object] path = \"file.msh\" is required for shape = \"mesh\""));
                }
            },
            Some(other) => {
                return Err(self.err(
                    at("shape"),
                    format!("{other:?}"),
                    "must be \"cuboid\", \"cylinder\" or \"mesh\"",
                ));
            }
            None => {
                return Err(self
                    .invalid("[object] shape is required: \"cuboid\", \"cylinder\" or \"mesh\""));
            }
        })
    }
}
