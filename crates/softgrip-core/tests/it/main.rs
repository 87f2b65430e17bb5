//! The integration tests, one binary: one module per subject.

mod bad_scenes;
mod bulk_modulus;
mod contact_regressions;
mod contact_stiffness;
mod dragging;
mod fem;
mod fields;
mod finger_shapes;
mod guide_friction;
mod hanging_cuboid;
mod hertz_indentation;
mod invariants;
mod live;
mod mesh_import;
mod mesh_scenes;
mod pinch;
mod rest;
mod self_collision;
mod shipped_scenes;
mod solver_tolerance;
mod spring_laws;
mod spring_limits;
mod spring_oscillator;
mod support;
mod surface_meshes;
mod volume_alpha;
