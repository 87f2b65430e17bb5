//! The fingers' rigid shapes as closed triangle surfaces (a plate: its
//! face), for drawing them beside the object in ParaView.

use glam::DVec3;

use crate::mesh::surface::Surface;
use crate::model::Model;
use crate::scene::FingerShape;

/// A sphere's facets around its axis and from pole to pole (18 degrees
/// each): round enough on screen at 360 triangles, a ~5 KB file a frame.
const SPHERE_SEGMENTS: u32 = 20;
const SPHERE_RINGS: u32 = 10;

/// Appends `other` to `to`, its indices shifted past `to`'s vertices.
fn append(to: &mut Surface, other: Surface) {
    let base = to.vertices.len() as u32;
    to.vertices.extend(other.vertices);
    to.triangles
        .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
}

/// Finger `k`'s surface with its centre at `centre`: every part, at its offset.
pub fn finger_surface(model: &Model, k: usize, centre: DVec3) -> Surface {
    let mut out = Surface {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    if let Some(finger) = model.fingers.get(k) {
        for part in &finger.parts {
            append(&mut out, shape_surface(part.shape, centre + part.offset));
        }
    }
    out
}

/// One shape centred at `centre`: the sphere, the box, or the plate's face
/// (the contact model's plate is its face, normal -z, at the centre).
pub fn shape_surface(shape: FingerShape, centre: DVec3) -> Surface {
    match shape {
        FingerShape::Sphere { radius } => sphere(centre, radius),
        FingerShape::Box { half_size } => cuboid(centre, DVec3::from_array(half_size)),
        FingerShape::Plate {
            half_size: [hx, hy],
        } => Surface {
            // Clockwise seen from +z: the face looks down, as it presses.
            vertices: [(-hx, -hy), (-hx, hy), (hx, hy), (hx, -hy)]
                .map(|(x, y)| centre + DVec3::new(x, y, 0.0))
                .to_vec(),
            triangles: vec![[0, 1, 2], [0, 2, 3]],
        },
    }
}

/// A UV sphere: a point at each pole, `SPHERE_RINGS - 1` rings between.
fn sphere(centre: DVec3, radius: f64) -> Surface {
    use std::f64::consts::PI;
    let (n, rings) = (SPHERE_SEGMENTS, SPHERE_RINGS);
    let mut points = vec![centre + DVec3::new(0.0, 0.0, radius)];
    for i in 1..rings {
        let theta = PI * f64::from(i) / f64::from(rings);
        for j in 0..n {
            let phi = 2.0 * PI * f64::from(j) / f64::from(n);
            points.push(
                centre
                    + radius
                        * DVec3::new(
                            theta.sin() * phi.cos(),
                            theta.sin() * phi.sin(),
                            theta.cos(),
                        ),
            );
        }
    }
    let south = points.len() as u32;
    points.push(centre - DVec3::new(0.0, 0.0, radius));
    // Point j of ring i (1-based rings, as above).
    let at = |i: u32, j: u32| 1 + (i - 1) * n + j % n;
    let mut triangles = Vec::with_capacity((2 * n * (rings - 1)) as usize);
    for j in 0..n {
        triangles.push([0, at(1, j), at(1, j + 1)]);
        for i in 1..rings - 1 {
            triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
        triangles.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    Surface {
        vertices: points,
        triangles,
    }
}

/// An axis-aligned box of half extents `h`: corner `c` has bit 0 for +x,
/// bit 1 for +y, bit 2 for +z; two triangles a face.
fn cuboid(centre: DVec3, h: DVec3) -> Surface {
    let points = (0..8)
        .map(|c| {
            let sign = |bit: u32| if c & (1 << bit) != 0 { 1.0 } else { -1.0 };
            centre + h * DVec3::new(sign(0), sign(1), sign(2))
        })
        .collect();
    // Each face's corners counter-clockwise seen from outside.
    let faces = [
        [0, 4, 6, 2],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 2, 3, 1],
        [4, 5, 7, 6],
    ];
    let triangles = faces
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    Surface {
        vertices: points,
        triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shapes_are_closed_and_face_outward() {
        let centre = DVec3::new(0.01, -0.02, 0.03);
        let r = 0.01;
        let s = shape_surface(FingerShape::Sphere { radius: r }, centre);
        assert_eq!(
            s.vertices.len() as u32,
            2 + SPHERE_SEGMENTS * (SPHERE_RINGS - 1)
        );
        for p in &s.vertices {
            assert!(((*p - centre).length() - r).abs() < 1e-15);
        }
        // Inscribed polyhedron: a little under the sphere's volume.
        let ball = 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
        let v = s.volume();
        assert!(v < ball && v > 0.95 * ball, "{v:e} vs {ball:e}");
        // Closed: every edge is used once each way.
        let mut edges = std::collections::HashMap::new();
        for t in &s.triangles {
            for e in 0..3 {
                *edges.entry((t[e], t[(e + 1) % 3])).or_insert(0) += 1;
            }
        }
        for (&(a, b), &count) in &edges {
            assert_eq!(count, 1);
            assert_eq!(edges.get(&(b, a)), Some(&1));
        }

        let h = [0.01, 0.02, 0.005];
        let b = shape_surface(FingerShape::Box { half_size: h }, centre);
        let exact = 8.0 * h[0] * h[1] * h[2];
        assert!((b.volume() - exact).abs() < 1e-12 * exact);

        let p = shape_surface(
            FingerShape::Plate {
                half_size: [0.02, 0.01],
            },
            centre,
        );
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.vertices[i as usize]);
            let n = (b - a).cross(c - a);
            assert!(n.z < 0.0 && n.x == 0.0 && n.y == 0.0);
        }
    }
}
