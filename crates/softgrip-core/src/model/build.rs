//! The stages of [`Model::from_mesh`](super::Model::from_mesh), in the order it runs them: the
//! body (each element's material from the `[[region]]`s, the lumped masses, the supports, the
//! constant forces), the spring network on the mesh's edges, the contact models (fingers, table,
//! self-collision), and the elements' elasticity (neo-Hookean elements, the nodal volume term).
//! `Model::assemble` then lays them out as the model's flat arrays.

use glam::DVec3;

use super::table::{TABLE_STIFFNESS_FACTOR, TableModel};
use super::{
    FingerModel, GUIDE_REST_SPEED, LinearSolver, Model, NodalBulk, REST_REFERENCE, Spring,
    SpringLaw, fem, lloyd_stiffness, self_collision, spring_damping,
};
use crate::error::SimError;
use crate::mesh::{TET_EDGES, TetMesh};
use crate::scene::{BulkPressure, Elasticity, Scene, Shape, SupportKind};

/// The body: each element's material and rest volume, each particle's mass, support and
/// constant force.
pub(super) struct Body {
    /// Young's modulus of each element, Pa (length: tets).
    pub element_modulus: Vec<f64>,
    /// Rest volume of each element, m^3 (length: tets).
    pub rest_volume: Vec<f64>,
    /// Lumped mass of each particle with its share of the loads' masses, kg (length: particles).
    pub mass: Vec<f64>,
    /// Whether each particle is held in place (length: particles).
    pub fixed: Vec<bool>,
    /// Gravity and loads on each particle, N (length: particles).
    pub constant_force: Vec<DVec3>,
    /// Largest extent of the undeformed mesh, m.
    pub extent: f64,
}

impl Body {
    /// Runs the body's stages in order: materials, masses, supports, constant forces.
    pub fn build(scene: &Scene, mesh: &TetMesh, file: &str) -> Result<Body, SimError> {
        let (element_modulus, element_density) = element_materials(scene, mesh, file)?;
        // Masses (eq. 6) and rest volumes.
        let rest_volume: Vec<f64> = (0..mesh.tets.len()).map(|t| mesh.tet_volume(t)).collect();
        let mut mass = lumped_masses(mesh, &rest_volume, &element_density);
        let (lo, hi) = mesh.bounds();
        let extent = (hi - lo).max_element();
        let fixed = fixed_particles(scene, mesh, file, (lo, hi), extent)?;
        let constant_force = constant_forces(scene, mesh, file, (lo, hi), &mut mass)?;
        Ok(Body {
            element_modulus,
            rest_volume,
            mass,
            fixed,
            constant_force,
            extent,
        })
    }
}

/// Each element's Young's modulus and density (Pa, kg/m^3): the object's, or that of the last
/// `[[region]]` holding the element's centroid. Refuses a region that holds no centroid.
fn element_materials(
    scene: &Scene,
    mesh: &TetMesh,
    file: &str,
) -> Result<(Vec<f64>, Vec<f64>), SimError> {
    let obj = &scene.object;
    let mut element_modulus = vec![obj.young_modulus; mesh.tets.len()];
    let mut element_density = vec![obj.density; mesh.tets.len()];
    for (b, region) in scene.regions.iter().enumerate() {
        let mut any = false;
        for (t, tet) in mesh.tets.iter().enumerate() {
            let centroid = tet.iter().map(|&p| mesh.nodes[p as usize]).sum::<DVec3>() * 0.25;
            if region.region.contains(centroid) {
                element_modulus[t] = region.young_modulus;
                element_density[t] = region.density;
                any = true;
            }
        }
        if !any {
            let (lo, hi) = mesh.bounds();
            return Err(SimError::EmptyRegion {
                file: file.to_string(),
                table: "region".into(),
                index: b + 1,
                min: region.region.min.to_array(),
                max: region.region.max.to_array(),
                bounds_min: lo.to_array(),
                bounds_max: hi.to_array(),
            });
        }
    }
    Ok((element_modulus, element_density))
}

/// Each particle's lumped mass (thesis eq. 6), kg: a quarter of each of its elements' masses.
fn lumped_masses(mesh: &TetMesh, rest_volume: &[f64], element_density: &[f64]) -> Vec<f64> {
    let mut mass = vec![0.0; mesh.nodes.len()];
    for ((tet, &v), &density) in mesh.tets.iter().zip(rest_volume).zip(element_density) {
        for &p in tet {
            mass[p as usize] += 0.25 * density * v;
        }
    }
    mass
}

/// The particles held in place: the bottom's with `[support] kind = "fixed_bottom"`, and those
/// in each `[[fixed]]` box. Refuses a box that holds no particle.
fn fixed_particles(
    scene: &Scene,
    mesh: &TetMesh,
    file: &str,
    (lo, hi): (DVec3, DVec3),
    extent: f64,
) -> Result<Vec<bool>, SimError> {
    let mut fixed = vec![false; mesh.nodes.len()];
    if scene.support.kind == SupportKind::FixedBottom {
        let tol = 1e-9 * extent;
        for (f, p) in fixed.iter_mut().zip(&mesh.nodes) {
            *f |= p.z <= lo.z + tol;
        }
    }
    for (b, region) in scene.fixed.iter().enumerate() {
        let mut any = false;
        for (f, p) in fixed.iter_mut().zip(&mesh.nodes) {
            if region.contains(*p) {
                *f = true;
                any = true;
            }
        }
        if !any {
            return Err(SimError::EmptyRegion {
                file: file.to_string(),
                table: "fixed".into(),
                index: b + 1,
                min: region.min.to_array(),
                max: region.max.to_array(),
                bounds_min: lo.to_array(),
                bounds_max: hi.to_array(),
            });
        }
    }
    Ok(fixed)
}

/// Each particle's constant force (N): gravity on its mass (eq. 5), and each `[[load]]`'s mass
/// and force shared equally by the particles in its box, whose masses gain their share.
/// Refuses a load whose box holds no particle.
fn constant_forces(
    scene: &Scene,
    mesh: &TetMesh,
    file: &str,
    (lo, hi): (DVec3, DVec3),
    mass: &mut [f64],
) -> Result<Vec<DVec3>, SimError> {
    let gravity = scene.simulation.gravity;
    let mut constant_force: Vec<DVec3> = mass.iter().map(|&m| m * gravity).collect();
    for (b, load) in scene.loads.iter().enumerate() {
        let inside: Vec<usize> = (0..mesh.nodes.len())
            .filter(|&i| load.region.contains(mesh.nodes[i]))
            .collect();
        if inside.is_empty() {
            return Err(SimError::EmptyRegion {
                file: file.to_string(),
                table: "load".into(),
                index: b + 1,
                min: load.region.min.to_array(),
                max: load.region.max.to_array(),
                bounds_min: lo.to_array(),
                bounds_max: hi.to_array(),
            });
        }
        let share = 1.0 / inside.len() as f64;
        for i in inside {
            mass[i] += load.mass * share;
            constant_force[i] += load.mass * share * gravity + load.force * share;
        }
    }
    Ok(constant_force)
}

/// The spring network: a spring on every edge, and the boundary facets with their springs.
pub(super) struct SpringNetwork {
    /// One spring per mesh edge, in the edges' sorted order (length: springs).
    pub springs: Vec<Spring>,
    /// The spring of each element edge, in [`TET_EDGES`] order (length: tets).
    pub tet_springs: Vec<[u32; 6]>,
    /// Boundary facets, wound outward (length: facets).
    pub facets: Vec<[u32; 3]>,
    /// The springs along each facet's edges `(0,1), (1,2), (2,0)` (length: facets).
    pub facet_springs: Vec<[u32; 3]>,
    /// The mesh's edge length, m: a mesh file's mean spring rest length, else the meshing target.
    pub edge_length: f64,
}

impl SpringNetwork {
    /// Springs on every edge with their stiffness and damping, then the boundary facets.
    pub fn build(scene: &Scene, mesh: &TetMesh, body: &Body) -> SpringNetwork {
        let edges = mesh.edges();
        let (springs, tet_springs) = edge_springs(scene, mesh, &edges, body);
        let facets = mesh.boundary_facets();
        // A mesh file's own edges, not the meshing target it ignores.
        let edge_length = if matches!(scene.object.shape, Shape::Mesh { .. }) && !springs.is_empty()
        {
            springs.iter().map(|s| s.rest_length).sum::<f64>() / springs.len() as f64
        } else {
            scene.object.edge_length
        };
        let facet_springs = facets
            .iter()
            .map(|f| {
                [
                    spring_of(&edges, f[0], f[1]),
                    spring_of(&edges, f[1], f[2]),
                    spring_of(&edges, f[2], f[0]),
                ]
            })
            .collect();
        SpringNetwork {
            springs,
            tet_springs,
            facets,
            facet_springs,
            edge_length,
        }
    }
}

/// Springs on every edge, Lloyd stiffness summed over the elements (eq. 7), damped after
/// eq. 9 ([`spring_damping`]) on the final masses; and each element's six springs.
fn edge_springs(
    scene: &Scene,
    mesh: &TetMesh,
    edges: &[[u32; 2]],
    body: &Body,
) -> (Vec<Spring>, Vec<[u32; 6]>) {
    let mut springs: Vec<Spring> = edges
        .iter()
        .map(|&[i, j]| Spring {
            i,
            j,
            rest_length: mesh.nodes[i as usize].distance(mesh.nodes[j as usize]),
            stiffness: 0.0,
            damping: 0.0,
        })
        .collect();
    let mut tet_springs = Vec::with_capacity(mesh.tets.len());
    let tets = mesh.tets.iter().zip(&body.rest_volume);
    for ((tet, &v), &modulus) in tets.zip(&body.element_modulus) {
        let k_e = lloyd_stiffness(v, modulus);
        let slots = TET_EDGES.map(|[a, b]| spring_of(edges, tet[a], tet[b]));
        for &s in &slots {
            springs[s as usize].stiffness += k_e;
        }
        tet_springs.push(slots);
    }
    let mass = &body.mass;
    for s in &mut springs {
        s.damping = spring_damping(
            scene.model.damping_ratio,
            s.stiffness,
            mass[s.i as usize],
            mass[s.j as usize],
        );
    }
    (springs, tet_springs)
}

/// The spring on the edge `a`-`b`, found in the sorted `edges` (`u32::MAX` if none).
fn spring_of(edges: &[[u32; 2]], a: u32, b: u32) -> u32 {
    let key = if a < b { [a, b] } else { [b, a] };
    // Edges are sorted and every queried pair is an edge of the mesh.
    edges
        .binary_search(&key)
        .map(|s| s as u32)
        .unwrap_or(u32::MAX)
}

/// The contact models: the fingers, the table and the surface's self-collision.
pub(super) struct Contacts {
    /// One per `[[finger]]` (length: fingers).
    pub fingers: Vec<FingerModel>,
    /// The table, with `[support] kind = "table"`.
    pub table: Option<TableModel>,
    /// Self-collision, with `[model] self_collision`.
    pub self_collision: Option<self_collision::SelfCollisionModel>,
}

impl Contacts {
    /// Fingers, table and self-collision, each on the object's material and edge length.
    pub fn build(scene: &Scene, mesh: &TetMesh, network: &SpringNetwork) -> Contacts {
        let obj = &scene.object;
        let gravity = scene.simulation.gravity;
        let fingers = scene
            .fingers
            .iter()
            .map(|f| FingerModel::new(f, obj.young_modulus, obj.poisson_ratio, gravity))
            .collect();
        let table = (scene.support.kind == SupportKind::Table).then(|| {
            TableModel::new(
                &network.facets,
                scene.support.friction,
                TABLE_STIFFNESS_FACTOR * obj.young_modulus * network.edge_length,
            )
        });
        let self_collision = scene.model.self_collision.then(|| {
            self_collision::SelfCollisionModel::new(
                &mesh.nodes,
                &network.facets,
                network.edge_length,
                obj.young_modulus,
            )
        });
        Contacts {
            fingers,
            table,
            self_collision,
        }
    }
}

/// The elements' elasticity beside the springs': the neo-Hookean elements, each element's
/// stiffness scale and the nodal volume term.
pub(super) struct Elements {
    /// The neo-Hookean elements, with `[model] elasticity = "neo-hookean"`.
    pub fem: Option<fem::FemModel>,
    /// Each element's Young's modulus over the object's; empty without regions (length: tets).
    pub element_stiffness_scale: Vec<f64>,
    /// The volume term per node, with `[model] bulk_pressure = "nodal"`.
    pub nodal_bulk: Option<NodalBulk>,
}

impl Elements {
    /// Neo-Hookean elements, stiffness scales, then the nodal volume term, which takes both.
    pub fn build(scene: &Scene, mesh: &TetMesh, body: &Body) -> Elements {
        let fem = neo_hookean_elements(scene, mesh, &body.element_modulus);
        let element_stiffness_scale: Vec<f64> = if scene.regions.is_empty() {
            Vec::new()
        } else {
            body.element_modulus
                .iter()
                .map(|e| e / scene.object.young_modulus)
                .collect()
        };
        let nodal_bulk = nodal_volume_term(
            scene,
            mesh,
            &body.rest_volume,
            fem.as_ref(),
            &element_stiffness_scale,
        );
        Elements {
            fem,
            element_stiffness_scale,
            nodal_bulk,
        }
    }
}

/// The neo-Hookean elements on each element's modulus, with the scene's stiffening terms and
/// the share of mu a Prony term takes away; `None` for the springs.
fn neo_hookean_elements(
    scene: &Scene,
    mesh: &TetMesh,
    element_modulus: &[f64],
) -> Option<fem::FemModel> {
    let fem_mode = scene.model.elasticity == Elasticity::NeoHookean;
    fem_mode.then(|| {
        let mut fem = fem::FemModel::new(
            &mesh.nodes,
            &mesh.tets,
            element_modulus,
            scene.object.poisson_ratio,
        );
        fem.yeoh = fem::Yeoh::new(
            scene.model.stiffening,
            scene.model.stiffening_cubic,
            scene.model.softening,
        )
        .with_gent_limit(scene.model.gent_limit);
        // A Prony term: the share g of the shear modulus is the Maxwell arms'
        // (`forces::viscosity::accumulate_arms`); lambda does not relax.
        for mu in &mut fem.mu {
            *mu *= 1.0 - scene.model.prony_g;
        }
        fem
    })
}

/// The nodal volume term (`[model] bulk_pressure = "nodal"`): on the neo-Hookean elements'
/// `lambda` less the share each keeps, or on the springs' bulk modulus when it is on.
fn nodal_volume_term(
    scene: &Scene,
    mesh: &TetMesh,
    rest_volume: &[f64],
    fem: Option<&fem::FemModel>,
    element_stiffness_scale: &[f64],
) -> Option<NodalBulk> {
    let nodal = scene.model.bulk_pressure == BulkPressure::Nodal;
    let bulk = scene.model.bulk_modulus;
    match fem {
        Some(fem) if nodal => Some(NodalBulk::new(
            mesh.nodes.len(),
            &mesh.tets,
            rest_volume,
            |e| fem.lambda[e] - fem::STABILISATION * fem.mu[e],
        )),
        None if nodal && bulk > 0.0 => Some(NodalBulk::new(
            mesh.nodes.len(),
            &mesh.tets,
            rest_volume,
            |e| bulk * element_stiffness_scale.get(e).copied().unwrap_or(1.0),
        )),
        _ => None,
    }
}

/// The spring model's own terms, which neo-Hookean elements replace: zero (or no limit) with
/// them, the scene's otherwise.
pub(super) struct SpringTerms {
    /// Volume-preservation scale (eq. 11), N/m^3.
    pub alpha: f64,
    /// Element volumetric stiffness, Pa.
    pub bulk_modulus: f64,
    /// Limit springs' stiffness over each spring's own.
    pub limit_stiffness: f64,
    /// Over-stretch limit, a fraction of the rest length.
    pub tau_s: Option<f64>,
    /// Over-compression limit, a fraction of the rest length.
    pub tau_c: Option<f64>,
}

impl SpringTerms {
    /// The scene's terms, switched off with neo-Hookean elements.
    pub fn of(scene: &Scene) -> SpringTerms {
        let fem_mode = scene.model.elasticity == Elasticity::NeoHookean;
        SpringTerms {
            alpha: if fem_mode { 0.0 } else { scene.model.alpha },
            bulk_modulus: if fem_mode {
                0.0
            } else {
                scene.model.bulk_modulus
            },
            limit_stiffness: if fem_mode {
                0.0
            } else {
                scene.model.limit_stiffness
            },
            tau_s: scene.model.tau_s.filter(|_| !fem_mode),
            tau_c: scene.model.tau_c.filter(|_| !fem_mode),
        }
    }
}

impl Model {
    /// Builds the model of a scene on a given mesh, stage by stage (`model::build`): the body
    /// (materials, masses, supports, constant forces), the springs, the contact models, the
    /// elements' elasticity, then the flat arrays with the solver settings.
    pub fn from_mesh(scene: &Scene, mesh: TetMesh) -> Result<Model, SimError> {
        let file = scene
            .source
            .as_ref()
            .map(|p| p.display().to_string())
            .unwrap_or_else(|| "scene".to_string());
        mesh.validate().map_err(|source| SimError::Mesh {
            file: file.clone(),
            source,
        })?;
        let body = Body::build(scene, &mesh, &file)?;
        let network = SpringNetwork::build(scene, &mesh, &body);
        let contacts = Contacts::build(scene, &mesh, &network);
        let elements = Elements::build(scene, &mesh, &body);
        Ok(Model::assemble(
            scene, mesh, body, network, contacts, elements,
        ))
    }

    /// Lays the stages' results out as the model, with the scene's solver settings and the
    /// spring model's own terms ([`SpringTerms`], off with neo-Hookean elements).
    fn assemble(
        scene: &Scene,
        mesh: TetMesh,
        body: Body,
        network: SpringNetwork,
        contacts: Contacts,
        elements: Elements,
    ) -> Model {
        let obj = &scene.object;
        let spring_terms = SpringTerms::of(scene);
        Model {
            rest_total_volume: body.rest_volume.iter().sum(),
            rest_positions: mesh.nodes,
            mass: body.mass,
            fixed: body.fixed,
            constant_force: body.constant_force,
            springs: network.springs,
            tets: mesh.tets,
            tet_springs: network.tet_springs,
            rest_volume: body.rest_volume,
            facets: network.facets,
            facet_springs: network.facet_springs,
            fingers: contacts.fingers,
            gravity: scene.simulation.gravity,
            dt: scene.simulation.dt,
            guide_rest_speed: GUIDE_REST_SPEED,
            exact_tangent: false,
            full_tangent: false,
            quasi_static: false,
            linear_solver: LinearSolver::Cg,
            cg_tolerance: scene.simulation.cg_tolerance,
            cg_reference: REST_REFERENCE,
            cg_max_iterations: scene.simulation.cg_max_iterations,
            alpha: spring_terms.alpha,
            rayleigh_mass: scene.model.rayleigh_mass,
            rayleigh_stiffness: scene.model.rayleigh_stiffness,
            bulk_modulus: spring_terms.bulk_modulus,
            limit_stiffness: spring_terms.limit_stiffness,
            tau_s: spring_terms.tau_s,
            tau_c: spring_terms.tau_c,
            constraint_iterations: scene.model.constraint_iterations,
            constraint_tolerance: scene.model.constraint_tolerance,
            extent: body.extent,
            // A mesh file's own edges, not the meshing target it ignores.
            edge_length: network.edge_length,
            young_modulus: obj.young_modulus,
            poisson_ratio: obj.poisson_ratio,
            density: obj.density,
            table: contacts.table,
            fem: elements.fem,
            self_collision: contacts.self_collision,
            nodal_bulk: elements.nodal_bulk,
            element_stiffness_scale: elements.element_stiffness_scale,
            spring_law: SpringLaw {
                stiffening: scene.model.stiffening,
                compression_ratio: scene.model.compression_ratio,
                prony_g: scene.model.prony_g,
                prony_tau: scene.model.prony_tau,
            },
        }
    }
}
