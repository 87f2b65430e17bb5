//! Force stages of a step (thesis Sec. III-B and III-D.1). Each adds its
//! forces to the force vector and its negative Jacobians to the system.

pub mod external;
pub mod fem;
pub mod pull;
pub mod springs;
pub mod viscosity;
pub mod volume;

use glam::DVec3;

use crate::state::State;

/// Velocity of unknown `dof` (particles first, then fingers).
#[inline]
pub fn velocity_of(state: &State, dof: usize) -> DVec3 {
    let n = state.velocities.len();
    if dof < n {
        state.velocities[dof]
    } else {
        state.fingers[dof - n].velocity
    }
}
