//! The constant model, built once from a scene (MuJoCo's `mjModel`): particle
//! masses, springs, elements, boundary facets, fingers and solver settings, as
//! flat arrays. Nothing here changes while the simulation steps; a GUI slider
//! rebuilds the affected arrays instead.

mod build;
pub mod fem;
mod finger;
pub mod self_collision;
pub mod table;

pub use finger::{AxisDrive, FingerModel, HUNT_CROSSLEY_MIN_APPROACH_SPEED, PartModel};

use glam::DVec3;

use crate::error::SimError;
use crate::mesh::TetMesh;
use crate::scene::{Scene, Shape};
use table::TableModel;

/// Below this speed (m/s) a finger's guide friction holds it (static
/// friction, as a stiff damper): [`Model::guide_rest_speed`] in a run.
pub const GUIDE_REST_SPEED: f64 = 1e-6;

/// A spring and its parallel damper between particles `i < j` (thesis Fig. 4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// First particle, the lower index.
    pub i: u32,
    /// Second particle, the higher index.
    pub j: u32,
    /// Rest length l0, m: the particles' distance at rest.
    pub rest_length: f64,
    /// Stiffness k, N/m: Lloyd's formula summed over the elements sharing the edge (eq. 7-8).
    pub stiffness: f64,
    /// Damping d, N s/m: `damping_ratio * 2 sqrt(k mu)` with the reduced mass mu
    /// (see [`spring_damping`]).
    pub damping: f64,
}

/// CG's tolerance is relative to the right-hand side `dt (f - dt Kp v)`, or
/// to this fraction of `dt` times the load norm when that is larger. When an
/// object comes truly to rest the right-hand side is rounding noise, and a
/// tolerance relative to it alone took ~80 iterations a step to solve the
/// noise to five digits (measured on the built-in scene with a stiffer limit
/// spring that let it settle to 1e-9 m/s).
///
/// With the default `cg_tolerance` (1e-5) the floor asks for a force
/// balance to 1e-7 of the loads. 1e-2 (it was 1e-3) takes the built-in
/// scene's first second from 22.1 to 18.5 CG iterations a step, and leaves
/// the rest as quiet (3e-8 m/s against 2e-8, and the light-guide scenes'
/// 4.5e-6 m/s, which is not the solver's, unchanged); at 1e-1 the built-in
/// scene's rest rose to 2-3e-6 m/s (docs/results/benchmarks-history.md).
pub const REST_REFERENCE: f64 = 1e-2;

/// How the step's linear system `A dv = b` is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LinearSolver {
    /// Block-Jacobi preconditioned conjugate gradients to [`Model::cg_tolerance`]: a time step,
    /// whose matrix changes little from the last and whose solve need not be exact.
    #[default]
    Cg,
    /// A sparse Cholesky factorisation (`crate::solver::direct`): an exact solve, for Newton's
    /// steps on an exact tangent.
    Direct,
}

/// The model: constant for a run.
#[derive(Debug, Clone)]
pub struct Model {
    /// Rest position of each particle, m (length: particles).
    pub rest_positions: Vec<DVec3>,
    /// Lumped mass of each particle (eq. 6) plus its share of any `[[load]]` mass, kg
    /// (length: particles).
    pub mass: Vec<f64>,
    /// Whether each particle is held in place (fixed bottom, `[[fixed]]`) (length: particles).
    pub fixed: Vec<bool>,
    /// Constant external force on each particle: gravity (eq. 5) and loads, N
    /// (length: particles).
    pub constant_force: Vec<DVec3>,
    /// The springs, one per mesh edge in the edges' sorted order (length: springs).
    pub springs: Vec<Spring>,
    /// The four particles of each tetrahedron (length: tets).
    pub tets: Vec<[u32; 4]>,
    /// The spring of each tetrahedron edge, in [`crate::mesh::TET_EDGES`] order (length: tets).
    pub tet_springs: Vec<[u32; 6]>,
    /// Rest volume of each tetrahedron, m^3 (length: tets).
    pub rest_volume: Vec<f64>,
    /// Sum of the tetrahedra's rest volumes, m^3.
    pub rest_total_volume: f64,
    /// Boundary facets' three particles, wound outward (length: facets).
    pub facets: Vec<[u32; 3]>,
    /// The springs along each facet's edges `(0,1), (1,2), (2,0)` (length: facets).
    pub facet_springs: Vec<[u32; 3]>,
    /// The fingers, one per `[[finger]]` (length: fingers).
    pub fingers: Vec<FingerModel>,
    /// Gravitational acceleration, m/s^2.
    pub gravity: DVec3,
    /// Time step, s: the scene's in time; a static solve's pseudo time step in its Newton
    /// steps (`crate::equilibrium`).
    pub dt: f64,
    /// Below this speed (m/s) a finger's guide friction holds it:
    /// [`GUIDE_REST_SPEED`] in time, scaled to the
    /// pseudo time step in a static solve (`crate::equilibrium`).
    pub guide_rest_speed: f64,
    /// Springs' Jacobians with their negative transverse terms (the static solver's Newton
    /// tangent); false in time steps, whose matrix must stay positive definite.
    pub exact_tangent: bool,
    /// Newton's whole tangent (with `exact_tangent`): the elements' and the nodal pressures'
    /// geometric terms, the finger contacts' full derivative and the table friction's coupling
    /// to the penetration, some of it not symmetric ([`crate::solver::System::asym`]). Only a
    /// factorised solve takes it (`crate::equilibrium`, `crate::sensitivity`).
    pub full_tangent: bool,
    /// The steps are a static solver's Newton iterations, not time: the table's friction is a
    /// return mapping to anchors held over the load increment (`crate::contact::table`).
    pub quasi_static: bool,
    /// How the step's linear system is solved: CG in time steps, a sparse factorisation in the
    /// static solver's Newton steps where it pays (`crate::equilibrium`).
    pub linear_solver: LinearSolver,
    /// CG's relative tolerance on the step's linear system (`[simulation] cg_tolerance`).
    pub cg_tolerance: f64,
    /// CG's tolerance is relative to the right-hand side or to this share of `dt` times the
    /// loads, whichever is larger ([`REST_REFERENCE`] in time steps;
    /// the static solver's own tolerance in its Newton steps).
    pub cg_reference: f64,
    /// CG iterations at most per linear solve.
    pub cg_max_iterations: usize,
    /// Volume-preservation scale alpha (thesis eq. 10-11), N/m^3: each element's force
    /// `alpha (V0 - V) (u_i - mean(u))`; 0 = off, and 0 with neo-Hookean elements.
    pub alpha: f64,
    /// Element volumetric stiffness K, Pa: the energy `K V0 / 2 (V / V0 - 1)^2`
    /// (`crate::forces::volume`); 0 = off, and 0 with neo-Hookean elements.
    pub bulk_modulus: f64,
    /// Rayleigh damping `a M + b K` (`crate::forces::viscosity`): a (1/s) ...
    pub rayleigh_mass: f64,
    /// ... and b (s); 0 = off.
    pub rayleigh_stiffness: f64,
    /// Limit springs' stiffness over each spring's own (`crate::forces::springs`); 0 = the
    /// projection alone (thesis Alg. 3), and 0 with neo-Hookean elements.
    pub limit_stiffness: f64,
    /// Over-stretch limit, a fraction of the rest length: a spring may reach `(1 + tau_s) l0`
    /// (thesis eq. 13-17); `None` = no limit, and `None` with neo-Hookean elements.
    pub tau_s: Option<f64>,
    /// Over-compression limit, a fraction of the rest length: a spring may shrink to
    /// `(1 - tau_c) l0` (thesis eq. 13-17); `None` = no limit, and `None` with neo-Hookean
    /// elements.
    pub tau_c: Option<f64>,
    /// Jacobi sweeps of the spring-limit projection (thesis Alg. 3) at most; with
    /// `constraint_tolerance`, `step::constraints::MAX_SWEEPS_FACTOR` times as many.
    pub constraint_iterations: usize,
    /// Project until no spring is outside its limits by more than this fraction of its rest
    /// length; `None` = `constraint_iterations` sweeps (see
    /// [`crate::scene::ModelParams::constraint_tolerance`]).
    pub constraint_tolerance: Option<f64>,
    /// Largest extent of the undeformed object (m): the NRMSE normaliser.
    pub extent: f64,
    /// Edge length, m: the meshing target, or a mesh file's mean spring rest length; for
    /// broad-phase cells and messages.
    pub edge_length: f64,
    /// The object's Young's modulus, Pa (a `[[region]]`'s own: `element_stiffness_scale`).
    pub young_modulus: f64,
    /// The object's Poisson ratio: the elements' (a continuum) or the continuum the springs
    /// stand for (its stresses, `crate::fields::element_von_mises`).
    pub poisson_ratio: f64,
    /// The object's density, kg/m^3 (a `[[region]]`'s own is in `mass`).
    pub density: f64,
    /// The table under the object (`[support] kind = "table"`).
    pub table: Option<TableModel>,
    /// How a spring's force follows its length (`forces::springs`).
    pub spring_law: SpringLaw,
    /// Self-collision of the surface (`[model] self_collision`).
    pub self_collision: Option<self_collision::SelfCollisionModel>,
    /// The neo-Hookean elements (`[model] elasticity = "neo-hookean"`),
    /// which replace the springs' elastic forces; `None` for the springs.
    pub fem: Option<fem::FemModel>,
    /// Each element's Young's modulus over the object's (`[[region]]`s):
    /// scales its bulk term as it scales its springs. Empty without
    /// regions (every element 1) (length: tets, or 0).
    pub element_stiffness_scale: Vec<f64>,
    /// The volume term per node (`[model] bulk_pressure = "nodal"`): the bulk
    /// term's, or the neo-Hookean elements' `lambda`; `None` for each
    /// element's own (`forces::volume`, `forces::fem`).
    pub nodal_bulk: Option<NodalBulk>,
}

/// The rest volume and modulus of each node's share of its elements (the
/// nodal volume term, `forces::volume::nodal`): a quarter of each element's
/// volume, and the elements' moduli averaged by those volumes.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalBulk {
    /// Each node's share of its elements' rest volumes, m^3 (length: particles).
    pub rest_volume: Vec<f64>,
    /// Each node's modulus, its elements' averaged by volume, Pa (length: particles).
    pub modulus: Vec<f64>,
}

impl NodalBulk {
    /// From each element's modulus (Pa): the bulk term's `K` for the
    /// springs, `lambda` for neo-Hookean elements.
    pub fn new(
        nodes: usize,
        tets: &[[u32; 4]],
        rest_volume: &[f64],
        element_modulus: impl Fn(usize) -> f64,
    ) -> NodalBulk {
        let mut volume = vec![0.0; nodes];
        let mut weighted = vec![0.0; nodes];
        for (e, (tet, &v0)) in tets.iter().zip(rest_volume).enumerate() {
            let k = element_modulus(e);
            for &i in tet {
                volume[i as usize] += 0.25 * v0;
                weighted[i as usize] += 0.25 * v0 * k;
            }
        }
        let modulus = volume
            .iter()
            .zip(&weighted)
            .map(|(v, w)| if *v > 0.0 { w / v } else { 0.0 })
            .collect();
        NodalBulk {
            rest_volume: volume,
            modulus,
        }
    }
}

/// The springs' force law beyond the thesis's linear spring (softgrip
/// extensions; the default is the thesis's, and takes its code path).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpringLaw {
    /// Strain stiffening beta (dimensionless): `F = k dl (1 + beta (dl / l0)^2)`.
    pub stiffening: f64,
    /// Stiffness in compression over stiffness in tension (1 = the thesis's).
    pub compression_ratio: f64,
    /// Prony term's relative modulus g, the share that relaxes (0 = elastic).
    pub prony_g: f64,
    /// Prony term's relaxation time tau, s.
    pub prony_tau: f64,
}

impl Default for SpringLaw {
    fn default() -> Self {
        SpringLaw {
            stiffening: 0.0,
            compression_ratio: 1.0,
            prony_g: 0.0,
            prony_tau: 1.0,
        }
    }
}

impl SpringLaw {
    /// The thesis's linear elastic spring.
    pub fn is_linear(&self) -> bool {
        self.stiffening == 0.0 && self.compression_ratio == 1.0 && self.prony_g == 0.0
    }

    /// Whether the springs relax (a Prony term, `prony_g > 0`).
    pub fn is_viscoelastic(&self) -> bool {
        self.prony_g > 0.0
    }
}

/// Lloyd's stiffness contribution of one element (thesis eq. 7-8):
/// `k_e = 2 sqrt(2) / 25 * l_e * E`, `l_e = (12 V / sqrt(2))^(1/3)`.
pub fn lloyd_stiffness(volume: f64, young_modulus: f64) -> f64 {
    let equivalent_edge = (volume * 12.0 / std::f64::consts::SQRT_2).cbrt();
    2.0 * std::f64::consts::SQRT_2 / 25.0 * equivalent_edge * young_modulus
}

/// Damping of one spring (thesis eq. 9, made dimensionally consistent).
///
/// The thesis writes `d = 2 sqrt(k (m_i + m_j)) / l0`, which is not a force per
/// velocity. We use the critical damping of the two-body oscillator the spring
/// forms, `d = zeta * 2 sqrt(k mu)` with the reduced mass
/// `mu = m_i m_j / (m_i + m_j)`: `zeta = 1` makes each spring's own mode
/// critically damped whatever the mesh resolution, which is what the thesis's
/// division by `l0` was meant to keep (see ARCHITECTURE.md, choice 2).
pub fn spring_damping(damping_ratio: f64, stiffness: f64, m_i: f64, m_j: f64) -> f64 {
    let reduced = m_i * m_j / (m_i + m_j);
    damping_ratio * 2.0 * (stiffness * reduced).sqrt()
}

impl Model {
    /// Whether an equilibrium depends only on the loads, not on the path to them: no friction
    /// (fingers, guides, table), whose stick anchors remember the path, no spring limits, whose
    /// projection does too, and no viscoelastic branch. Only then may a static solve start from
    /// another solve's answer: on the light-guide thesis cuboid at 4.17 N, a start from E's
    /// answers at E + 5 % ends 25 um from the usual path's answer with friction and limits,
    /// 0.016 um without (`docs/design/equilibrium.md`).
    pub fn path_independent(&self) -> bool {
        self.tau_s.is_none()
            && self.tau_c.is_none()
            && !self.spring_law.is_viscoelastic()
            && self
                .fingers
                .iter()
                .all(|f| f.friction == 0.0 && f.guide_friction == 0.0)
            && self.table.as_ref().is_none_or(|t| t.friction == 0.0)
    }

    /// Builds the model of a scene (meshes the object first).
    pub fn from_scene(scene: &Scene) -> Result<Model, SimError> {
        Model::from_mesh(scene, Model::mesh_of(scene)?)
    }

    /// Refuses a scene whose edge length would make more tetrahedra than the limit
    /// ([`crate::mesh::budget`]), counted before anything is built. A volume mesh file is as
    /// large as it is; a surface is counted by the fewest tetrahedra TetGen could fill it with.
    pub fn check_budget(scene: &Scene) -> Result<(), SimError> {
        use crate::mesh::budget;
        let h = scene.object.edge_length;
        let (shape, count, refusal) = match &scene.object.shape {
            Shape::Cuboid { size } => {
                let at = |h: f64| budget::cuboid_tetrahedra(*size, h);
                let what = format!(
                    "{} x {} x {} mm cuboid",
                    1e3 * size.x,
                    1e3 * size.y,
                    1e3 * size.z
                );
                (what, at(h), budget::refusal(at(h), h, at))
            }
            Shape::Cylinder { radius, height } => {
                let at = |h: f64| budget::cylinder_tetrahedra(*radius, *height, h);
                let what = format!(
                    "cylinder of radius {} mm, {} mm tall",
                    1e3 * radius,
                    1e3 * height
                );
                (what, at(h), budget::refusal(at(h), h, at))
            }
            Shape::Mesh { path, scale, .. } if crate::mesh::io::is_surface(path) => {
                let volume = crate::mesh::io::read_surface(path)?.volume() * scale.powi(3);
                let at = |h: f64| budget::tetgen_tetrahedra_at_least(volume, h);
                let what = format!("surface ({})", path.display());
                (what, at(h), budget::refusal(at(h), h, at))
            }
            Shape::Mesh { .. } => return Ok(()),
        };
        let Some(r) = refusal else { return Ok(()) };
        let count = match &scene.object.shape {
            Shape::Mesh { .. } => format!("at least {count:.2e}"),
            _ if count < 1e15 => thousands(count as u64),
            _ => format!("{count:.2e}"),
        };
        let advice = match r.edge {
            Some(e) if r.by_memory => format!("set edge_length = {e:e} or larger in [object]"),
            Some(e) => format!(
                "set edge_length = {e:e} or larger in [object], or raise the limit with `softgrip --max-tetrahedra N`"
            ),
            None => format!(
                "even the coarsest mesh of this {shape} has {} tetrahedra: raise the limit to this edge length's count with `softgrip --max-tetrahedra {}`",
                thousands(r.coarsest as u64),
                r.count.ceil() as u64
            ),
        };
        Err(SimError::TooManyTetrahedra {
            file: scene
                .source
                .as_ref()
                .map_or("the scene".into(), |p| p.display().to_string()),
            shape,
            edge_length: h,
            count,
            gib: match r.gib {
                g if g < 100.0 => format!("{g:.1}"),
                g if g < 1e15 => thousands(g.round() as u64),
                g => format!("{g:.1e}"),
            },
            limit: if r.by_memory {
                format!(
                    "the {} tetrahedra this machine's {:.1} GiB of memory holds",
                    thousands(r.limit),
                    r.memory_gib.unwrap_or(0.0)
                )
            } else {
                format!("the limit of {}", thousands(r.limit))
            },
            advice,
        })
    }

    /// The mesh a scene's object is made of.
    pub fn mesh_of(scene: &Scene) -> Result<TetMesh, SimError> {
        Model::load_mesh(scene).map(|(mesh, _)| mesh)
    }

    /// Refuses a mesh whose size at its `scale` is thousands of times its fingers' (or, without
    /// fingers, outside 0.1 mm .. 100 m): a file in millimetres read as metres, or the reverse.
    /// Suggests the scale (a power of ten, or inches) that brings it to its fingers' size.
    fn check_units(scene: &Scene, extent_at_scale: f64) -> Result<(), SimError> {
        let Shape::Mesh { path, scale, .. } = &scene.object.shape else {
            return Ok(());
        };
        let finger = scene
            .fingers
            .iter()
            .enumerate()
            .map(|(k, f)| (k, f.shape.size()))
            .filter(|(_, size)| *size > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let (target, too_far, against) = match finger {
            Some((k, size)) => {
                let r = extent_at_scale / size;
                (
                    3.0 * size,
                    !(1.0 / 500.0..=500.0).contains(&r),
                    format!("finger {}'s size ({size:.3e} m)", k + 1),
                )
            }
            None => (
                0.05,
                !(1e-4..=100.0).contains(&extent_at_scale),
                "plausible size (0.1 mm to 100 m)".to_string(),
            ),
        };
        if !too_far || extent_at_scale.is_nan() || extent_at_scale <= 0.0 {
            return Ok(());
        }
        // The unit that brings it nearest the target, as a factor on the present scale.
        let suggest = [1e-3, 1e-2, 0.0254, 1e3, 1e2, 1.0 / 0.0254]
            .iter()
            .map(|f| scale * f)
            .min_by(|a, b| {
                let d = |s: f64| (extent_at_scale / scale * s / target).ln().abs();
                d(*a).total_cmp(&d(*b))
            })
            .unwrap_or(*scale);
        let ratio = match finger {
            Some((_, size)) if extent_at_scale > size => {
                format!("{:.0} times", extent_at_scale / size)
            }
            Some((_, size)) => format!("1/{:.0} of", size / extent_at_scale),
            None => "outside the".to_string(),
        };
        Err(SimError::MeshUnits {
            file: path.display().to_string(),
            extent: extent_at_scale,
            scale: *scale,
            ratio,
            against,
            suggest,
            scaled: extent_at_scale / scale * suggest,
        })
    }

    /// The mesh of `scene` and what loading it changed or noticed (a mesh
    /// file's skipped cells, reordered tetrahedra, merged nodes...).
    pub fn load_mesh(scene: &Scene) -> Result<(TetMesh, Vec<String>), SimError> {
        if let Shape::Mesh { path, scale, .. } = &scene.object.shape
            && crate::mesh::io::is_surface(path)
        {
            let s = crate::mesh::io::read_surface(path)?;
            let (lo, hi) = crate::mesh::bounds_of(&s.vertices);
            Model::check_units(scene, (hi - lo).max_element() * scale)?;
        }
        Model::check_budget(scene)?;
        Ok(match &scene.object.shape {
            Shape::Cuboid { size } => (TetMesh::cuboid(*size, scene.object.edge_length), vec![]),
            Shape::Cylinder { radius, height } => (
                TetMesh::cylinder(*radius, *height, scene.object.edge_length),
                vec![],
            ),
            Shape::Mesh {
                path,
                scale,
                position,
            } => {
                let file = path.display().to_string();
                let (mut mesh, mut warnings) = if crate::mesh::io::is_surface(path) {
                    // Scaled first: the edge length is in metres.
                    let mut surface = crate::mesh::io::read_surface(path)?;
                    for v in &mut surface.vertices {
                        *v *= *scale;
                    }
                    let mut mesh = crate::mesh::tetrahedralize::tetrahedralize(
                        &surface,
                        scene.object.edge_length,
                    )
                    .map_err(|m| crate::mesh::io::ImportError::at(&file, None, m))?;
                    for p in &mut mesh.nodes {
                        *p /= *scale;
                    }
                    let note = format!(
                        "tetrahedralized by TetGen: {} triangles to {} tetrahedra (edge length {} m)",
                        surface.triangles.len(),
                        mesh.tets.len(),
                        scene.object.edge_length
                    );
                    (mesh, vec![note])
                } else {
                    let imported = crate::mesh::io::read(path)?;
                    (imported.mesh, imported.warnings)
                };
                let report =
                    crate::mesh::checks::repair(&mut mesh).map_err(|source| SimError::Mesh {
                        file: file.clone(),
                        source,
                    })?;
                warnings.extend(report.warnings);
                mesh.place(*scale, *position);
                let (lo, hi) = mesh.bounds();
                Model::check_units(scene, (hi - lo).max_element())?;
                (
                    mesh,
                    warnings
                        .into_iter()
                        .map(|w| format!("{file}: {w}"))
                        .collect(),
                )
            }
        })
    }

    /// A bare particle-spring model without elements or facets (a chain, a
    /// single spring): for verification against analytic results.
    /// `springs` are `(i, j, stiffness, damping)`, rest lengths taken from
    /// `positions`.
    pub fn from_particles(
        positions: Vec<DVec3>,
        mass: Vec<f64>,
        fixed: Vec<bool>,
        springs: &[(u32, u32, f64, f64)],
        gravity: DVec3,
        dt: f64,
    ) -> Model {
        let springs: Vec<Spring> = springs
            .iter()
            .map(|&(i, j, k, d)| {
                let (i, j) = if i < j { (i, j) } else { (j, i) };
                Spring {
                    i,
                    j,
                    rest_length: positions[i as usize].distance(positions[j as usize]),
                    stiffness: k,
                    damping: d,
                }
            })
            .collect();
        let (lo, hi) = crate::mesh::bounds_of(&positions);
        Model {
            constant_force: mass.iter().map(|&m| m * gravity).collect(),
            rest_positions: positions,
            mass,
            fixed,
            springs,
            tets: Vec::new(),
            tet_springs: Vec::new(),
            rest_volume: Vec::new(),
            rest_total_volume: 0.0,
            facets: Vec::new(),
            facet_springs: Vec::new(),
            fingers: Vec::new(),
            gravity,
            dt,
            guide_rest_speed: GUIDE_REST_SPEED,
            exact_tangent: false,
            full_tangent: false,
            quasi_static: false,
            linear_solver: LinearSolver::Cg,
            cg_tolerance: 1e-12,
            cg_reference: REST_REFERENCE,
            cg_max_iterations: 1000,
            alpha: 0.0,
            bulk_modulus: 0.0,
            rayleigh_mass: 0.0,
            rayleigh_stiffness: 0.0,
            limit_stiffness: 0.0,
            tau_s: None,
            tau_c: None,
            constraint_iterations: 0,
            constraint_tolerance: None,
            extent: (hi - lo).max_element(),
            edge_length: (hi - lo).max_element(),
            young_modulus: 1.0,
            poisson_ratio: 0.0,
            density: 1.0,
            table: None,
            element_stiffness_scale: Vec::new(),
            nodal_bulk: None,
            fem: None,
            self_collision: None,
            spring_law: SpringLaw::default(),
        }
    }

    /// Number of particles.
    pub fn particle_count(&self) -> usize {
        self.rest_positions.len()
    }

    /// Total mass of the object (with loads), kg.
    pub fn total_mass(&self) -> f64 {
        self.mass.iter().sum()
    }
}

/// `n` with thousands separated by commas.
fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}
