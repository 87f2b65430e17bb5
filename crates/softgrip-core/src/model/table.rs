//! The table's constant data (`[support] kind = "table"`): which particles can touch it, its
//! stiffness and friction. Its forces are `crate::contact::table`'s.

/// The table's penalty stiffness per particle, in units of `E h` (Young's
/// modulus times the mean edge length): a spring's Lloyd stiffness is about
/// `E h / 2`, so this is ~200 of the object's own springs side by side. The
/// 9.73 N thesis load on the built-in cuboid sinks the bottom by ~3 um.
pub const TABLE_STIFFNESS_FACTOR: f64 = 100.0;

/// The table of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct TableModel {
    /// Coulomb coefficient object-table (dimensionless).
    pub friction: f64,
    /// Normal and stick stiffness per particle, N/m.
    pub stiffness: f64,
    /// The particles that can touch it: the boundary's, ascending.
    pub particles: Vec<u32>,
}

impl TableModel {
    /// On the boundary facets' particles, with the Coulomb coefficient and the stiffness
    /// per particle (N/m).
    pub fn new(model_facets: &[[u32; 3]], friction: f64, stiffness: f64) -> TableModel {
        let mut particles: Vec<u32> = model_facets.iter().flatten().copied().collect();
        particles.sort_unstable();
        particles.dedup();
        TableModel {
            friction,
            stiffness,
            particles,
        }
    }

    /// The dashpot of particle mass `m` (N s/m): critical damping.
    pub fn damping(&self, m: f64) -> f64 {
        2.0 * (self.stiffness * m).sqrt()
    }
}
