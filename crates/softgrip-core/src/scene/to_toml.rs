//! A resolved scene back to its file: the raw structs built from it, written by `toml_text`.
//! Every value is explicit, except keys whose absence means the default (`bulk_pressure`
//! where it is the elasticity's, no `tau_s`, zero `softening` or `rayleigh_mass`, no `travel` ...).

use super::raw::{
    RawBox, RawFinger, RawGrasp, RawLoad, RawModel, RawObject, RawPart, RawRegion, RawScene,
    RawSimulation, RawSupport,
};
use super::toml_text::{self, Table, Value};
use super::{
    BulkPressure, Control, Elasticity, Finger, FingerShape, ModelParams, Object, Scene, Shape,
    Simulation, SupportKind,
};

impl Scene {
    /// Writes the scene back as TOML, with every value explicit.
    pub fn to_toml(&self) -> String {
        let mut root = toml_text::to_table(&raw_scene(self));
        written_order(&mut root);
        toml_text::document(&root)
    }
}

impl Scene {
    /// As [`Scene::to_toml`], for the file `file`: a mesh's path written relative to the file's
    /// directory, where the reader resolves it (the scene holds it relative to the directory the
    /// program runs in). Left as it is where either cannot be found.
    pub fn to_toml_for(&self, file: &std::path::Path) -> String {
        let mut scene = self.clone();
        if let Shape::Mesh { path, .. } = &mut scene.object.shape {
            let dir = file.parent().filter(|d| !d.as_os_str().is_empty());
            let dir = dir.unwrap_or(std::path::Path::new("."));
            if let (Ok(mesh), Ok(dir)) = (path.canonicalize(), dir.canonicalize()) {
                *path = relative(&mesh, &dir);
            }
        }
        scene.to_toml()
    }
}

/// `target` relative to the directory `base` (both absolute, canonical).
fn relative(target: &std::path::Path, base: &std::path::Path) -> std::path::PathBuf {
    let (t, b): (Vec<_>, Vec<_>) = (target.components().collect(), base.components().collect());
    let common = t.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return target.to_path_buf();
    }
    let mut out = std::path::PathBuf::new();
    for _ in common..b.len() {
        out.push("..");
    }
    for c in &t[common..] {
        out.push(c);
    }
    out
}

impl FingerShape {
    /// Its `shape` and `radius` or `size` keys, as a scene file writes them
    /// (for a `[[finger]]` and a `[[finger.part]]` alike).
    pub fn to_toml(&self) -> String {
        toml_text::key_lines(&toml_text::to_table(&raw_part(self, None)))
    }
}

/// Where a key goes.
enum Place {
    After(&'static str),
    Before(&'static str),
}

/// `softgrip scene` writes these keys elsewhere than the raw structs declare them. Both orders
/// stay as they were: the raw one is the list serde's unknown-key message gives.
fn written_order(root: &mut Table) {
    move_key(root, "region", Place::Before("finger"));
    for (key, value) in root.iter_mut() {
        match (*key, value) {
            ("model", Value::Table(model)) => {
                move_key(model, "bulk_pressure", Place::After("limit_stiffness"));
                move_key(model, "stiffening", Place::Before("compression_ratio"));
            }
            ("finger", Value::Array(fingers)) => {
                for finger in fingers {
                    if let Value::Table(finger) = finger {
                        move_key(finger, "guide_speed", Place::After("stick_damping"));
                        move_key(
                            finger,
                            "contact_stiffness_scale",
                            Place::After("guide_speed"),
                        );
                    }
                }
            }
            _ => {}
        }
    }
}

/// Moves `key` (when present) to `place` (when its key is present).
fn move_key(table: &mut Table, key: &str, place: Place) {
    let Some(from) = table.iter().position(|(k, _)| *k == key) else {
        return;
    };
    let entry = table.remove(from);
    let (anchor, offset) = match place {
        Place::After(anchor) => (anchor, 1),
        Place::Before(anchor) => (anchor, 0),
    };
    match table.iter().position(|(k, _)| *k == anchor) {
        Some(to) => table.insert(to + offset, entry),
        None => table.insert(from, entry),
    }
}

fn raw_scene(scene: &Scene) -> RawScene {
    let aabox = |b: &super::AaBox| (b.min.to_array(), b.max.to_array());
    RawScene {
        simulation: Some(raw_simulation(&scene.simulation)),
        object: Some(raw_object(&scene.object)),
        model: Some(raw_model(&scene.model)),
        support: Some(RawSupport {
            kind: Some(
                match scene.support.kind {
                    SupportKind::FixedBottom => "fixed-bottom",
                    SupportKind::Table => "table",
                    SupportKind::None => "none",
                }
                .to_string(),
            ),
            friction: Some(scene.support.friction),
        }),
        fixed: (scene.fixed.iter())
            .map(|b| {
                let (min, max) = aabox(b);
                RawBox { min, max }
            })
            .collect(),
        load: (scene.loads.iter())
            .map(|l| {
                let (min, max) = aabox(&l.region);
                RawLoad {
                    min,
                    max,
                    mass: Some(l.mass),
                    force: Some(l.force.to_array()),
                }
            })
            .collect(),
        finger: scene.fingers.iter().map(raw_finger).collect(),
        region: (scene.regions.iter())
            .map(|r| {
                let (min, max) = aabox(&r.region);
                RawRegion {
                    min,
                    max,
                    young_modulus: Some(r.young_modulus),
                    density: Some(r.density),
                }
            })
            .collect(),
        grasp: raw_grasp(&scene.grasp),
        extra: None,
    }
}

/// `[grasp]`, where the scene has any of its keys.
fn raw_grasp(g: &super::Grasp) -> Option<RawGrasp> {
    (*g != super::Grasp::default()).then(|| RawGrasp {
        acceleration: g.acceleration,
        shake: g.shake,
        slip_tolerance: g.slip_tolerance,
        hold: g.hold,
        damage: g.damage.map(|d| d.name().to_string()),
        limit: g.limit,
        material: g.material.map(|m| m.name.to_string()),
    })
}

fn raw_simulation(s: &Simulation) -> RawSimulation {
    RawSimulation {
        dt: Some(s.dt),
        duration: Some(s.duration),
        gravity: Some(s.gravity.to_array()),
        cg_tolerance: Some(s.cg_tolerance),
        cg_max_iterations: Some(s.cg_max_iterations as i64),
        settle: Some(s.settle.as_str().to_string()),
    }
}

fn raw_object(o: &Object) -> RawObject {
    let mut raw = RawObject {
        edge_length: Some(o.edge_length),
        density: Some(o.density),
        young_modulus: Some(o.young_modulus),
        poisson_ratio: Some(o.poisson_ratio),
        ..RawObject::default()
    };
    let shape = match &o.shape {
        Shape::Cuboid { size } => {
            raw.size = Some(size.to_array());
            "cuboid"
        }
        Shape::Cylinder { radius, height } => {
            raw.radius = Some(*radius);
            raw.height = Some(*height);
            "cylinder"
        }
        Shape::Mesh {
            path,
            scale,
            position,
        } => {
            raw.path = Some(path.display().to_string());
            raw.scale = Some(*scale);
            raw.position = Some(position.to_array());
            "mesh"
        }
    };
    raw.shape = Some(shape.to_string());
    raw
}

fn raw_model(m: &ModelParams) -> RawModel {
    let nonzero = |x: f64| (x != 0.0).then_some(x);
    RawModel {
        damping_ratio: Some(m.damping_ratio),
        rayleigh_mass: nonzero(m.rayleigh_mass),
        rayleigh_stiffness: nonzero(m.rayleigh_stiffness),
        alpha: Some(m.alpha),
        bulk_modulus: Some(m.bulk_modulus),
        // Written only where it is not the elasticity's default.
        bulk_pressure: match (m.elasticity, m.bulk_pressure) {
            (Elasticity::Springs, BulkPressure::Nodal) => Some("nodal".to_string()),
            (Elasticity::NeoHookean, BulkPressure::Element) => Some("element".to_string()),
            _ => None,
        },
        limit_stiffness: Some(m.limit_stiffness),
        tau_s: m.tau_s,
        tau_c: m.tau_c,
        constraint_iterations: Some(m.constraint_iterations as i64),
        constraint_tolerance: m.constraint_tolerance,
        stiffening: Some(m.stiffening),
        stiffening_cubic: nonzero(m.stiffening_cubic),
        softening: nonzero(m.softening),
        gent_limit: nonzero(m.gent_limit),
        compression_ratio: Some(m.compression_ratio),
        prony_g: Some(m.prony_g),
        prony_tau: Some(m.prony_tau),
        elasticity: Some(
            match m.elasticity {
                Elasticity::Springs => "springs",
                Elasticity::NeoHookean => "neo-hookean",
            }
            .to_string(),
        ),
        self_collision: Some(m.self_collision),
    }
}

fn raw_finger(f: &Finger) -> RawFinger {
    let shape = raw_part(&f.shape, None);
    let free_axes: String = ['x', 'y', 'z']
        .iter()
        .zip(f.free_axes)
        .filter(|(_, free)| *free)
        .map(|(c, _)| *c)
        .collect();
    let control = match f.control {
        Control::Force => "force",
        Control::Velocity => "velocity",
    };
    RawFinger {
        shape: shape.shape,
        radius: shape.radius,
        size: shape.size,
        part: Some(
            (f.parts.iter())
                .map(|part| raw_part(&part.shape, Some(part.offset.to_array())))
                .collect(),
        ),
        position: Some(f.position.to_array()),
        free_axes: Some(free_axes),
        control: Some(control.to_string()),
        force: Some(f.force.to_array()),
        velocity: Some(f.velocity.to_array()),
        mass: Some(f.mass),
        young_modulus: Some(f.young_modulus),
        poisson_ratio: Some(f.poisson_ratio),
        restitution: Some(f.restitution),
        friction: Some(f.friction),
        stick_velocity: Some(f.stick_velocity),
        stick_stiffness: Some(f.stick_stiffness),
        stick_damping: Some(f.stick_damping),
        travel: f.travel,
        start_time: Some(f.start_time),
        ramp_time: Some(f.ramp_time),
        guide_speed: Some(f.guide_speed),
        guide_friction: Some(f.guide_friction),
        contact_stiffness_scale: Some(f.contact_stiffness_scale),
    }
}

/// A finger's (or a part's) shape keys: `size` holds whole extents, the shape half ones.
fn raw_part(shape: &FingerShape, offset: Option<[f64; 3]>) -> RawPart {
    let (name, radius, size) = match *shape {
        FingerShape::Sphere { radius } => ("sphere", Some(radius), None),
        FingerShape::Plate { half_size: [x, y] } => ("plate", None, Some(vec![2.0 * x, 2.0 * y])),
        FingerShape::Box {
            half_size: [x, y, z],
        } => ("box", None, Some(vec![2.0 * x, 2.0 * y, 2.0 * z])),
    };
    RawPart {
        shape: Some(name.to_string()),
        radius,
        size,
        offset,
    }
}
