//! What is drawn, as lit triangles: the object's boundary surface with
//! smooth normals, the fingers, the contact points (stick or slip) and the
//! force arrows. Built on the CPU from a model and a state every frame.

use glam::{DVec3, Vec3};

use softgrip_core::fields::Field;
use softgrip_core::mesh::TET_FACES;
use softgrip_core::model::Model;
use softgrip_core::scene::FingerShape;
use softgrip_core::state::{State, TableMode};

/// One vertex as the GPU reads it (`shaders/lit.wgsl`'s `VertexIn`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Position in the world, m.
    pub position: [f32; 3],
    /// Normal for the lighting (normalised by the shader; zero for lines, drawn unlit).
    pub normal: [f32; 3],
    /// Colour, linear RGBA 0..1; alpha below 1 is see-through in the blended layers.
    pub color: [f32; 4],
}

/// What a frame draws: opaque triangles, then lines (the wireframe), then
/// translucent triangles (fingers drawn see-through, so the contacts under
/// them show), then the x-ray layer; and the colour map's legend, if the
/// object is coloured.
#[derive(Debug, Clone, Default)]
pub struct Drawing {
    /// Opaque lit triangles: the object, opaque fingers, contacts, arrows, the table.
    pub opaque: Mesh,
    /// Pairs of indices (a line list), drawn unlit.
    pub lines: Mesh,
    /// Alpha-blended triangles, not writing depth: see-through fingers.
    pub translucent: Mesh,
    /// Triangles drawn only where something else is in front of them, by
    /// their alpha: a recording's markers inside or behind the object
    /// show faintly through it.
    pub xray: Mesh,
    /// The colour map's legend; `None` unless the object is coloured by a field.
    pub legend: Option<Legend>,
}

/// What the colours of a coloured object mean: `field` from `min` (the
/// map's first colour) to `max` (its last), SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Legend {
    /// The field the object is coloured by.
    pub field: Field,
    /// The value drawn in the map's first colour, in the field's SI unit.
    pub min: f64,
    /// The value drawn in the map's last colour, in the field's SI unit.
    pub max: f64,
}

impl Legend {
    /// The colour of `value`.
    pub fn color(&self, value: f64) -> [f32; 4] {
        let t = (value - self.min) / (self.max - self.min);
        let [r, g, b] = softgrip_core::fields::colormap(t, self.field.signed());
        [r, g, b, 1.0]
    }
}

/// A cut-away: elements whose centroid lies below `fraction` of the
/// object's rest extent along `axis` (0 = x, 1 = y, 2 = z) are hidden, so
/// the interior shows; `flip` hides the other side instead.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cut {
    /// The axis cut across: 0 = x, 1 = y, 2 = z (larger is taken as z).
    pub axis: usize,
    /// Where the cutting plane lies, as a fraction 0..1 of the rest extent along `axis`.
    pub fraction: f32,
    /// Hide the elements above the plane instead of those below.
    pub flip: bool,
}

/// An indexed triangle list.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// The vertices.
    pub vertices: Vec<Vertex>,
    /// Indices into `vertices`, three per triangle (two per line in `Drawing::lines`).
    pub indices: Vec<u32>,
}

/// Colours (linear RGBA, 0..1) and what to show.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    /// The object's free particles.
    pub object: [f32; 4],
    /// The fingers (alpha replaced by `finger_opacity`).
    pub finger: [f32; 4],
    /// The object's fixed particles.
    pub fixed: [f32; 4],
    /// The table (`[support] kind = "table"`).
    pub table: [f32; 4],
    /// A particle pressed against the object's own surface.
    pub self_contact: [f32; 4],
    /// A contact point that sticks (finger contacts with stick >= 0.5, table contacts sticking).
    pub stick: [f32; 4],
    /// A contact point that slides.
    pub slip: [f32; 4],
    /// Contact normal-force arrows.
    pub normal_force: [f32; 4],
    /// Contact friction (tangential force) arrows.
    pub tangential_force: [f32; 4],
    /// The arrow of the contact force on each finger.
    pub finger_force: [f32; 4],
    /// The mouse spring, and where a held finger is held.
    pub drag: [f32; 4],
    /// Arrow length per newton (m/N).
    pub force_scale: f32,
    /// 1 = opaque fingers; below, they are drawn see-through.
    pub finger_opacity: f32,
    /// Draw the fingers.
    pub fingers: bool,
    /// Draw the contact points (finger, table and self-contact dots).
    pub contacts: bool,
    /// Draw the force arrows.
    pub arrows: bool,
    /// Colour the object by this field (with a legend) instead of `object`.
    pub color_by: Option<Field>,
    /// Draw the object's surface (off with `wireframe` shows every spring
    /// inside).
    pub surface: bool,
    /// Draw every spring as a line.
    pub wireframe: bool,
    /// The wireframe's lines, unless the surface is off and the object is coloured by a field.
    pub wire: [f32; 4],
    /// The cut-away, if any.
    pub cut: Option<Cut>,
}

impl Default for Style {
    fn default() -> Style {
        Style {
            object: [0.93, 0.62, 0.45, 1.0],
            finger: [0.25, 0.45, 0.85, 1.0],
            fixed: [0.35, 0.35, 0.38, 1.0],
            table: [0.62, 0.63, 0.66, 1.0],
            self_contact: [0.75, 0.20, 0.85, 1.0],
            stick: [0.15, 0.80, 0.25, 1.0],
            slip: [0.95, 0.55, 0.05, 1.0],
            normal_force: [0.85, 0.10, 0.10, 1.0],
            tangential_force: [0.95, 0.85, 0.10, 1.0],
            finger_force: [0.60, 0.10, 0.75, 1.0],
            drag: [0.10, 0.60, 0.70, 1.0],
            force_scale: 0.002,
            finger_opacity: 1.0,
            fingers: true,
            contacts: true,
            arrows: true,
            color_by: None,
            surface: true,
            wireframe: false,
            wire: [0.12, 0.12, 0.14, 1.0],
            cut: None,
        }
    }
}

fn f32v(v: DVec3) -> Vec3 {
    v.as_vec3()
}

impl Mesh {
    fn push(&mut self, position: Vec3, normal: Vec3, color: [f32; 4]) -> u32 {
        self.vertices.push(Vertex {
            position: position.to_array(),
            normal: normal.to_array(),
            color,
        });
        (self.vertices.len() - 1) as u32
    }

    /// A UV sphere.
    pub fn add_sphere(&mut self, centre: Vec3, radius: f32, color: [f32; 4]) {
        const RINGS: u32 = 16;
        const SEGMENTS: u32 = 24;
        let base = self.vertices.len() as u32;
        for r in 0..=RINGS {
            let theta = std::f32::consts::PI * r as f32 / RINGS as f32;
            for s in 0..=SEGMENTS {
                let phi = std::f32::consts::TAU * s as f32 / SEGMENTS as f32;
                let n = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                self.push(centre + radius * n, n, color);
            }
        }
        let row = SEGMENTS + 1;
        for r in 0..RINGS {
            for s in 0..SEGMENTS {
                let a = base + r * row + s;
                let b = a + row;
                self.indices
                    .extend_from_slice(&[a, b, a + 1, a + 1, b, b + 1]);
            }
        }
    }

    /// An axis-aligned box.
    pub fn add_box(&mut self, min: Vec3, max: Vec3, color: [f32; 4]) {
        let c = |x: bool, y: bool, z: bool| {
            Vec3::new(
                if x { max.x } else { min.x },
                if y { max.y } else { min.y },
                if z { max.z } else { min.z },
            )
        };
        // (normal, four corners counter-clockwise seen from outside)
        let faces = [
            (
                Vec3::X,
                [
                    c(true, false, false),
                    c(true, true, false),
                    c(true, true, true),
                    c(true, false, true),
                ],
            ),
            (
                -Vec3::X,
                [
                    c(false, true, false),
                    c(false, false, false),
                    c(false, false, true),
                    c(false, true, true),
                ],
            ),
            (
                Vec3::Y,
                [
                    c(true, true, false),
                    c(false, true, false),
                    c(false, true, true),
                    c(true, true, true),
                ],
            ),
            (
                -Vec3::Y,
                [
                    c(false, false, false),
                    c(true, false, false),
                    c(true, false, true),
                    c(false, false, true),
                ],
            ),
            (
                Vec3::Z,
                [
                    c(false, false, true),
                    c(true, false, true),
                    c(true, true, true),
                    c(false, true, true),
                ],
            ),
            (
                -Vec3::Z,
                [
                    c(false, true, false),
                    c(true, true, false),
                    c(true, false, false),
                    c(false, false, false),
                ],
            ),
        ];
        for (n, corners) in faces {
            let i: Vec<u32> = corners.iter().map(|&p| self.push(p, n, color)).collect();
            self.indices
                .extend_from_slice(&[i[0], i[1], i[2], i[0], i[2], i[3]]);
        }
    }

    /// An arrow from `from` along `vector` (its full length), a shaft and a
    /// head; nothing for a vector shorter than a micrometre.
    pub fn add_arrow(&mut self, from: Vec3, vector: Vec3, radius: f32, color: [f32; 4]) {
        let length = vector.length();
        if length < 1e-6 {
            return;
        }
        let axis = vector / length;
        let helper = if axis.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
        let u = axis.cross(helper).normalize();
        let v = axis.cross(u);
        let head = (4.0 * radius).min(0.4 * length);
        let shaft_end = from + axis * (length - head);
        const SEGMENTS: u32 = 10;
        let ring = |k: u32| {
            let a = std::f32::consts::TAU * k as f32 / SEGMENTS as f32;
            u * a.cos() + v * a.sin()
        };
        // Shaft.
        let base = self.vertices.len() as u32;
        for k in 0..=SEGMENTS {
            let d = ring(k);
            self.push(from + radius * d, d, color);
            self.push(shaft_end + radius * d, d, color);
        }
        for k in 0..SEGMENTS {
            let a = base + 2 * k;
            self.indices
                .extend_from_slice(&[a, a + 2, a + 1, a + 1, a + 2, a + 3]);
        }
        // Head: a cone from a ring of twice the shaft's radius to the tip.
        let tip = from + vector;
        let base = self.vertices.len() as u32;
        for k in 0..=SEGMENTS {
            let d = ring(k);
            let n = (d * head + axis * 2.0 * radius).normalize();
            self.push(shaft_end + 2.0 * radius * d, n, color);
            self.push(tip, n, color);
        }
        for k in 0..SEGMENTS {
            let a = base + 2 * k;
            self.indices.extend_from_slice(&[a, a + 2, a + 1]);
        }
    }
}

/// The scene drawn for `state` of `model`.
pub fn build(model: &Model, state: &State, style: &Style) -> Drawing {
    let mut drawing = Drawing::default();
    add_object(&mut drawing, model, state, style);
    let scale = bounds_size(model).max(1e-3);
    add_fingers(&mut drawing, model, state, style, scale);
    let mesh = &mut drawing.opaque;
    add_drag(mesh, model, state, style, scale);
    if let Some(table) = &model.table {
        add_table(mesh, state, table, style, scale);
    }
    add_contacts(mesh, state, style, scale);
    drawing
}

/// The object: its surface (cut away where `style.cut` says) and its wireframe, in its colours
/// or a field's (whose legend goes into `drawing`).
fn add_object(drawing: &mut Drawing, model: &Model, state: &State, style: &Style) {
    let colors = object_colors(model, state, style, &mut drawing.legend);
    let kept = style.cut.map(|cut| kept_elements(model, state, cut));
    match &kept {
        _ if !style.surface => {}
        Some(kept) => add_cut_surface(&mut drawing.opaque, model, state, kept, &colors),
        None => add_surface(&mut drawing.opaque, model, state, &colors),
    }
    if style.wireframe {
        // Over the surface, dark; alone, in the field's colours if any.
        let wire = (!style.surface && style.color_by.is_some()).then_some(colors.as_slice());
        add_wireframe(
            &mut drawing.lines,
            model,
            state,
            kept.as_deref(),
            style.wire,
            wire,
        );
    }
}

/// Each finger's parts (see-through below full opacity) and the arrow of the contact force on
/// it; `scale` is the object's extent (m).
fn add_fingers(drawing: &mut Drawing, model: &Model, state: &State, style: &Style, scale: f32) {
    let mut finger_color = style.finger;
    finger_color[3] = style.finger_opacity.clamp(0.0, 1.0);
    for (k, f) in model.fingers.iter().enumerate() {
        let Some(fs) = state.fingers.get(k) else {
            continue;
        };
        let centre = f32v(fs.position);
        if !style.fingers {
            continue;
        }
        let body = if finger_color[3] < 1.0 {
            &mut drawing.translucent
        } else {
            &mut drawing.opaque
        };
        for part in &f.parts {
            let at = centre + f32v(part.offset);
            match part.shape {
                FingerShape::Sphere { radius } => body.add_sphere(at, radius as f32, finger_color),
                FingerShape::Plate { half_size } => {
                    let h = Vec3::new(half_size[0] as f32, half_size[1] as f32, 0.0);
                    let thickness = plate_thickness(model) as f32;
                    body.add_box(at - h, at + h + Vec3::Z * thickness, finger_color);
                }
                FingerShape::Box { half_size } => {
                    let h = f32v(DVec3::from_array(half_size));
                    body.add_box(at - h, at + h, finger_color);
                }
            }
        }
        let mesh = &mut drawing.opaque;
        if style.arrows {
            // From the finger's surface, along the force on it.
            let force = f32v(fs.contact_force) * style.force_scale;
            let from = centre
                + force.normalize_or_zero()
                    * f.shape.reach_along(fs.contact_force.normalize_or_zero()) as f32;
            mesh.add_arrow(from, force, 0.006 * scale, style.finger_force);
        }
    }
}

/// Dragging: the mouse spring as a thin rod to its target, a held finger's hold point as a dot.
fn add_drag(mesh: &mut Mesh, model: &Model, state: &State, style: &Style, scale: f32) {
    if let Some(pull) = &state.pull
        && let Some(tri) = model.facets.get(pull.facet as usize)
    {
        let point: DVec3 = (0..3)
            .map(|a| pull.weights[a] * state.positions[tri[a] as usize])
            .sum();
        let from = f32v(point);
        let to = f32v(pull.target);
        mesh.add_sphere(from, 0.01 * scale, style.drag);
        mesh.add_sphere(to, 0.01 * scale, style.drag);
        mesh.add_arrow(from, to - from, 0.004 * scale, style.drag);
    }
    for fs in &state.fingers {
        if let Some(at) = fs.held {
            mesh.add_sphere(f32v(at), 0.01 * scale, style.drag);
        }
    }
}

/// The contacts: a dot on each particle pressed against the object's own surface and on each
/// finger contact (stick or slip colours), with their force arrows.
fn add_contacts(mesh: &mut Mesh, state: &State, style: &Style, scale: f32) {
    // Self-collision: a dot on each particle pressed against the surface,
    // and its force.
    for c in &state.self_contacts {
        let at = f32v(state.positions[c.particle as usize]);
        if style.contacts {
            mesh.add_sphere(at, 0.006 * scale, style.self_contact);
        }
        if style.arrows {
            let force = f32v(c.normal * c.force) * style.force_scale;
            mesh.add_arrow(at, force, 0.002 * scale, style.normal_force);
        }
    }
    for c in &state.contacts {
        let at = f32v(c.point);
        if style.contacts {
            let color = if c.stick >= 0.5 {
                style.stick
            } else {
                style.slip
            };
            mesh.add_sphere(at, 0.008 * scale, color);
        }
        if style.arrows {
            let force = f32v(c.normal * c.normal_force) * style.force_scale;
            mesh.add_arrow(at, force, 0.0025 * scale, style.normal_force);
            let tangential = f32v(c.tangential_force) * style.force_scale;
            mesh.add_arrow(at, tangential, 0.0025 * scale, style.tangential_force);
        }
    }
}

/// The table as a slab three times the object's extent around where the
/// object is now, its top a hair under z = 0 (the object sinks micrometres
/// into it), and its contacts: a dot per particle on it (stick or slip
/// colours) with its normal and friction arrows.
fn add_table(
    mesh: &mut Mesh,
    state: &State,
    table: &softgrip_core::model::table::TableModel,
    style: &Style,
    scale: f32,
) {
    let (lo, hi) = softgrip_core::mesh::bounds_of(&state.positions);
    let centre = f32v(0.5 * (lo + hi));
    let half = 1.5 * scale;
    let top = -0.002 * scale;
    mesh.add_box(
        Vec3::new(centre.x - half, centre.y - half, top - 0.03 * scale),
        Vec3::new(centre.x + half, centre.y + half, top),
        style.table,
    );
    for (c, &p) in state.table.iter().zip(&table.particles) {
        if c.mode == TableMode::Free {
            continue;
        }
        let at = f32v(state.positions[p as usize]);
        if style.contacts {
            let color = if c.mode == TableMode::Stick {
                style.stick
            } else {
                style.slip
            };
            mesh.add_sphere(at, 0.006 * scale, color);
        }
        if style.arrows {
            let normal = Vec3::Z * (c.normal_force as f32 * style.force_scale);
            mesh.add_arrow(at, normal, 0.002 * scale, style.normal_force);
            let friction = f32v(c.tangential_force) * style.force_scale;
            mesh.add_arrow(at, friction, 0.002 * scale, style.tangential_force);
        }
    }
}

/// How thick a plate finger is drawn (m): 2 % of the object's extent.
pub fn plate_thickness(model: &Model) -> f64 {
    0.02 * f64::from(bounds_size(model).max(1e-3))
}

/// The object's extent (m), for marker sizes.
pub(crate) fn bounds_size(model: &Model) -> f32 {
    let (lo, hi) = softgrip_core::mesh::bounds_of(&model.rest_positions);
    (hi - lo).max_element() as f32
}

/// Facets meeting at a sharper angle than this keep their own normals at
/// the shared vertex (the cuboid's edges stay sharp); smoother ones share
/// the area-weighted mean.
const CREASE_COS: f32 = 0.766; // cos 40 degrees

/// Each particle's colour: by the style's field (and the legend it sets),
/// else the object's colour with pinned particles grey.
fn object_colors(
    model: &Model,
    state: &State,
    style: &Style,
    legend: &mut Option<Legend>,
) -> Vec<[f32; 4]> {
    if let Some(field) = style.color_by {
        let values = field.particle_values(model, state);
        let (min, max) = softgrip_core::fields::range(&values, field.signed());
        let l = Legend { field, min, max };
        *legend = Some(l);
        return values.iter().map(|v| l.color(*v)).collect();
    }
    model
        .fixed
        .iter()
        .map(|&fixed| if fixed { style.fixed } else { style.object })
        .collect()
}

/// Which elements a cut-away keeps.
fn kept_elements(model: &Model, state: &State, cut: Cut) -> Vec<bool> {
    let axis = cut.axis.min(2);
    let (lo, hi) = softgrip_core::mesh::bounds_of(&model.rest_positions);
    let plane = lo[axis] + f64::from(cut.fraction.clamp(0.0, 1.0)) * (hi[axis] - lo[axis]);
    model
        .tets
        .iter()
        .map(|t| {
            let c: f64 = t
                .iter()
                .map(|&i| state.positions[i as usize][axis])
                .sum::<f64>()
                / 4.0;
            (c >= plane) != cut.flip
        })
        .collect()
}

/// The surface of the kept elements: every face of a kept element that no
/// other kept element shares, flat-shaded.
fn add_cut_surface(
    mesh: &mut Mesh,
    model: &Model,
    state: &State,
    kept: &[bool],
    colors: &[[f32; 4]],
) {
    let mut count: std::collections::HashMap<[u32; 3], u32> = std::collections::HashMap::new();
    let sorted = |mut f: [u32; 3]| {
        f.sort_unstable();
        f
    };
    let faces = |t: &[u32; 4]| TET_FACES.map(|f| [t[f[0]], t[f[1]], t[f[2]]]);
    for (t, _) in model.tets.iter().zip(kept).filter(|(_, k)| **k) {
        for f in faces(t) {
            *count.entry(sorted(f)).or_insert(0) += 1;
        }
    }
    for (t, _) in model.tets.iter().zip(kept).filter(|(_, k)| **k) {
        for f in faces(t) {
            if count.get(&sorted(f)) != Some(&1) {
                continue;
            }
            let p = f.map(|i| f32v(state.positions[i as usize]));
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            for (k, &i) in f.iter().enumerate() {
                let at = mesh.push(p[k], n, colors[i as usize]);
                mesh.indices.push(at);
            }
        }
    }
}

/// Every spring as a line (with a cut-away, those of kept elements).
fn add_wireframe(
    lines: &mut Mesh,
    model: &Model,
    state: &State,
    kept: Option<&[bool]>,
    color: [f32; 4],
    colors: Option<&[[f32; 4]]>,
) {
    let mut shown = vec![kept.is_none(); model.springs.len()];
    if let Some(kept) = kept {
        for (springs, _) in model.tet_springs.iter().zip(kept).filter(|(_, k)| **k) {
            for &s in springs {
                shown[s as usize] = true;
            }
        }
    }
    for (s, _) in model.springs.iter().zip(&shown).filter(|(_, v)| **v) {
        for i in [s.i, s.j] {
            let c = colors.map_or(color, |c| c[i as usize]);
            let at = lines.push(f32v(state.positions[i as usize]), Vec3::ZERO, c);
            lines.indices.push(at);
        }
    }
}

/// The boundary facets, three vertices each, with normals smoothed over the
/// facets around each corner that meet it at less than the crease angle.
/// Pinned particles are grey.
fn add_surface(mesh: &mut Mesh, model: &Model, state: &State, colors: &[[f32; 4]]) {
    let n = model.particle_count();
    // Facet normals (length = twice the area) and the facets at each particle.
    let normals: Vec<Vec3> = model
        .facets
        .iter()
        .map(|tri| {
            let p = tri.map(|i| f32v(state.positions[i as usize]));
            (p[1] - p[0]).cross(p[2] - p[0])
        })
        .collect();
    let mut start = vec![0u32; n + 1];
    for tri in &model.facets {
        for &i in tri {
            start[i as usize + 1] += 1;
        }
    }
    for i in 0..n {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![0u32; start[n] as usize];
    for (f, tri) in model.facets.iter().enumerate() {
        for &i in tri {
            around[fill[i as usize] as usize] = f as u32;
            fill[i as usize] += 1;
        }
    }
    for (f, tri) in model.facets.iter().enumerate() {
        let own = normals[f].normalize_or_zero();
        for &i in tri {
            let i = i as usize;
            let mut sum = Vec3::ZERO;
            for &g in &around[start[i] as usize..start[i + 1] as usize] {
                let other = normals[g as usize];
                if other.normalize_or_zero().dot(own) >= CREASE_COS {
                    sum += other;
                }
            }
            let at = mesh.push(f32v(state.positions[i]), sum.normalize_or_zero(), colors[i]);
            mesh.indices.push(at);
        }
    }
}
