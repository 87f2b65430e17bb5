//! The implicit-Euler system matrix `A = M - dt df/dv - dt^2 df/dx` (thesis
//! eq. 43), stored as 3x3 blocks: one diagonal block per particle and finger,
//! one off-diagonal block per spring (every pair of particles that a force
//! couples is an edge of the mesh: springs, volume terms of an element and
//! contact terms of a facet all act on edges), and a list of particle-finger
//! blocks from contacts.
//!
//! Force terms are added as their negative Jacobians `Kp = -df/dx` and
//! `Dp = -df/dv`, which every term keeps symmetric positive semi-definite, so
//! A stays SPD and CG applies. The product `Kp v` that the right-hand side of
//! eq. 43 needs is accumulated at the same time.

use glam::{DMat3, DVec3};

use crate::model::Model;
use crate::solver::pressure::{Choice, NoFactor, Pressure};

/// Unknown index: particles first, then fingers.
pub type Dof = usize;

/// The implicit-Euler system `A` (blocks in kg) and the `Kp v` its right-hand side needs.
#[derive(Debug, Default, Clone)]
pub struct System {
    dt: f64,
    /// Number of particles (the dofs after them are the fingers).
    pub particles: usize,
    /// Diagonal blocks, particles then fingers.
    pub diag: Vec<DMat3>,
    /// Block (`springs[s].i`, `springs[s].j`); its transpose is block (j, i).
    pub off: Vec<DMat3>,
    /// Block (particle, finger dof); its transpose is block (finger, particle).
    pub coupling: Vec<(u32, u32, DMat3)>,
    /// `Kp v`, for the right-hand side.
    pub kv: Vec<DVec3>,
    /// What an exact tangent adds to the blocks above, weighted as A's blocks: the
    /// non-symmetric part of friction in a static solve (a sliding contact's force follows the
    /// normal force, not the other way). The blocks hold a symmetric matrix, which a direct
    /// solve factorises and preconditions GMRES with; only a direct solve reads these
    /// (`solver::direct`).
    pub asym: Vec<Asym>,
    /// 1 on a free component, 0 on a fixed one (Baraff-Witkin filter).
    pub mask: Vec<DVec3>,
    /// Inverses of the masked diagonal blocks (block-Jacobi preconditioner).
    inv_diag: Vec<DMat3>,
    /// Springs with no pinned end: the only off-diagonal blocks the product
    /// needs (a pinned particle's row is masked out and its entry in every
    /// vector CG multiplies is zero).
    free_springs: Vec<u32>,
    /// The particle pairs of `free_springs`, in the same order: the product
    /// reads these 8 bytes instead of the whole spring.
    free_pairs: Vec<[u32; 2]>,
    /// The spring count `free_springs` was built for.
    built_for: usize,
    /// The volume term averaged per node (`forces::volume::nodal`): it couples
    /// nodes two edges apart, so it is applied matrix-free.
    pub nodal: NodalOperator,
    /// The nodal term's own preconditioner, kept over steps (`None`: block Jacobi).
    pressure: Option<Pressure>,
    /// A factorization refused for its size is not tried again for this mesh.
    pressure_refused: bool,
    /// Whether the next solve uses `pressure`.
    choice: Choice,
    /// The system is solved by a factorisation: CG's preconditioners are not made.
    direct: bool,
}

/// `sum_i c_i g_i g_i^T` with `g_i = dV_i/dx`, `V_i` a quarter of the volume of
/// each element around node i: the Gauss-Newton Jacobian of an energy
/// `sum_i V0_i K_i / 2 (V_i / V0_i - 1)^2`, weighted by dt^2 as it enters A.
#[derive(Debug, Default, Clone)]
pub struct NodalOperator {
    /// Each element's volume gradients `G_a = dV/dx_a` at this step's
    /// positions, a quarter of each (empty: no nodal term).
    pub quarter_gradients: Vec<[DVec3; 4]>,
    /// `c_i = dt^2 K_i / V0_i` per node.
    pub weight: Vec<f64>,
    /// Its diagonal blocks, for the preconditioner only.
    pub diag: Vec<DMat3>,
}

/// A small dense non-symmetric term over up to four dofs (unused ones [`Asym::NONE`]):
/// `A[dofs[a], dofs[b]] += blocks[a][b]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Asym {
    /// The dofs the term couples ([`Asym::NONE`] where unused).
    pub dofs: [u32; 4],
    /// Block `[a][b]` adds to `A[dofs[a], dofs[b]]`, weighted by dt^2 as A's blocks (kg).
    pub blocks: [[DMat3; 4]; 4],
}

impl Asym {
    /// An unused slot of [`Asym::dofs`].
    pub const NONE: u32 = u32::MAX;
}

thread_local! {
    /// Each node's `c_i (g_i . x)` during a product: one buffer per thread.
    static NODAL_RATE: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

impl NodalOperator {
    /// Whether there is a nodal term (its gradients were set this step).
    pub fn is_active(&self) -> bool {
        !self.quarter_gradients.is_empty()
    }

    /// `y += sum_i c_i g_i (g_i . x)`: two passes over the elements.
    fn add_product(&self, tets: &[[u32; 4]], x: &[DVec3], y: &mut [DVec3]) {
        NODAL_RATE.with_borrow_mut(|rate| {
            rate.clear();
            rate.resize(self.weight.len(), 0.0);
            for (tet, g) in tets.iter().zip(&self.quarter_gradients) {
                let [a, b, c, d] = tet.map(|i| i as usize);
                let t = g[0].dot(x[a]) + g[1].dot(x[b]) + g[2].dot(x[c]) + g[3].dot(x[d]);
                for i in [a, b, c, d] {
                    rate[i] += t;
                }
            }
            for (r, w) in rate.iter_mut().zip(&self.weight) {
                *r *= *w;
            }
            for (tet, g) in tets.iter().zip(&self.quarter_gradients) {
                let [a, b, c, d] = tet.map(|i| i as usize);
                let q = rate[a] + rate[b] + rate[c] + rate[d];
                y[a] += g[0] * q;
                y[b] += g[1] * q;
                y[c] += g[2] * q;
                y[d] += g[3] * q;
            }
        });
    }
}

impl System {
    /// Starts a step: `A = M`, `Kp v = 0`; the mask is set by the caller.
    pub fn begin(&mut self, model: &Model, dt: f64) {
        self.begin_with(model, dt, true);
    }

    /// Starts a partial system for a share of the force passes (see
    /// `crate::step::parallel`): every block zero, no mass, to be added to a full
    /// one with [`System::add`].
    pub fn begin_partial(&mut self, model: &Model, dt: f64) {
        self.begin_with(model, dt, false);
    }

    fn begin_with(&mut self, model: &Model, dt: f64, with_mass: bool) {
        let n = model.particle_count();
        let nf = model.fingers.len();
        let mass = if with_mass { 1.0 } else { 0.0 };
        self.dt = dt;
        self.direct = model.linear_solver == crate::model::LinearSolver::Direct;
        self.particles = n;
        self.diag.clear();
        self.diag.extend(
            model
                .mass
                .iter()
                .map(|&m| DMat3::from_diagonal(DVec3::splat(mass * m))),
        );
        self.diag.extend(
            model
                .fingers
                .iter()
                .map(|f| DMat3::from_diagonal(DVec3::splat(mass * f.mass))),
        );
        self.off.clear();
        self.off.resize(model.springs.len(), DMat3::ZERO);
        self.coupling.clear();
        self.asym.clear();
        self.nodal.quarter_gradients.clear();
        self.nodal.weight.clear();
        self.nodal.diag.clear();
        self.kv.clear();
        self.kv.resize(n + nf, DVec3::ZERO);
        self.mask.clear();
        self.mask.resize(n + nf, DVec3::ONE);
        if self.built_for != model.springs.len() {
            self.built_for = model.springs.len();
            self.free_springs = (0..model.springs.len() as u32)
                .filter(|&s| {
                    let sp = &model.springs[s as usize];
                    !model.fixed[sp.i as usize] && !model.fixed[sp.j as usize]
                })
                .collect();
            self.free_pairs = self
                .free_springs
                .iter()
                .map(|&s| [model.springs[s as usize].i, model.springs[s as usize].j])
                .collect();
        }
    }

    /// Adds the blocks and `Kp v` of a partial system (same model).
    pub fn add(&mut self, part: &System) {
        for (a, b) in self.diag.iter_mut().zip(&part.diag) {
            *a += *b;
        }
        for (a, b) in self.off.iter_mut().zip(&part.off) {
            *a += *b;
        }
        for (a, b) in self.kv.iter_mut().zip(&part.kv) {
            *a += *b;
        }
        self.coupling.extend_from_slice(&part.coupling);
        self.asym.extend_from_slice(&part.asym);
    }

    /// Adds a non-symmetric stiffness remainder `kp` (unweighted, `-df/dx`) over `dofs`.
    pub fn add_asym(&mut self, dofs: [u32; 4], mut kp: [[DMat3; 4]; 4]) {
        let w = self.dt * self.dt;
        for row in &mut kp {
            for b in row.iter_mut() {
                *b *= w;
            }
        }
        self.asym.push(Asym { dofs, blocks: kp });
    }

    #[inline]
    fn weight(&self, kp: DMat3, dp: DMat3) -> DMat3 {
        kp * (self.dt * self.dt) + dp * self.dt
    }

    /// Adds `(Kp, Dp)` to the diagonal block of `a`.
    #[inline]
    pub fn add_diag(&mut self, a: Dof, kp: DMat3, dp: DMat3, v: &impl Fn(Dof) -> DVec3) {
        let w = self.weight(kp, dp);
        self.diag[a] += w;
        self.kv[a] += kp * v(a);
    }

    /// The time step the blocks are weighted with.
    #[inline]
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Adds block `(a, b)` (and its transpose at `(b, a)`) for particles `a != b`
    /// joined by spring `slot` of `springs`.
    #[inline]
    pub fn add_off(
        &mut self,
        springs: &[crate::model::Spring],
        slot: u32,
        a: Dof,
        b: Dof,
        kp: DMat3,
        dp: DMat3,
        v: &impl Fn(Dof) -> DVec3,
    ) {
        let w = self.weight(kp, dp);
        let s = slot as usize;
        if springs[s].i as usize == a {
            self.off[s] += w;
        } else {
            self.off[s] += w.transpose();
        }
        self.kv[a] += kp * v(b);
        self.kv[b] += kp.transpose() * v(a);
    }

    /// Adds block `(particle, finger)` and its transpose.
    #[inline]
    pub fn add_coupling(
        &mut self,
        particle: Dof,
        finger: Dof,
        kp: DMat3,
        dp: DMat3,
        v: &impl Fn(Dof) -> DVec3,
    ) {
        let w = self.weight(kp, dp);
        self.coupling.push((particle as u32, finger as u32, w));
        self.kv[particle] += kp * v(finger);
        self.kv[finger] += kp.transpose() * v(particle);
    }

    /// Prepares the preconditioner after assembly (`tets`: the model's elements;
    /// `last_iterations`: CG's iterations in the last solve, which tell when the nodal term's
    /// factorization has aged).
    pub fn finish(&mut self, tets: &[[u32; 4]], last_iterations: usize) {
        if self.direct {
            return;
        }
        self.finish_block_jacobi();
        if !self.nodal.is_active() || self.pressure_refused {
            self.pressure = None;
            self.choice = Choice::default();
            return;
        }
        let n = self.particles;
        let cost = self.pressure.as_ref().map_or(f64::INFINITY, |p| {
            // The product's two halves run side by side (`crate::step::parallel`): the
            // factor's application, on one thread, weighs against the longer half.
            let half = (36 * self.free_springs.len()).max(48 * tets.len() + 9 * n) as f64;
            1.0 + p.work() / half
        });
        // Untried yet: tried where block Jacobi's iterations leave room (cost unknown: 3).
        let cost = if cost.is_finite() { cost } else { 3.0 };
        let factored = self.choice.factored;
        let serving = factored
            && self
                .pressure
                .as_mut()
                .is_some_and(|p| p.serves(n, &self.mask, last_iterations));
        if !factored {
            // Block Jacobi last: is the factorization worth a try?
            if !self.choice.next(last_iterations, cost) {
                return;
            }
        } else if serving {
            // Judged against block Jacobi's count: kept, or block Jacobi again.
            self.choice.next(last_iterations, cost);
            return;
        }
        // Here a new factorization: tried, or an aged one built anew before it is judged (its
        // count tells its age).
        let mut p = self.pressure.take().unwrap_or_default();
        let built = p.build(
            tets,
            &self.nodal.quarter_gradients,
            &self.nodal.weight,
            &self.diag[..n],
            &self.mask[..n],
        );
        match built {
            Ok(()) => self.pressure = Some(p),
            Err(NoFactor::TooLarge) => self.pressure_refused = true,
            Err(NoFactor::NotDefinite) => {}
        }
        if self.pressure.is_none() {
            self.choice.failed();
        }
    }

    fn finish_block_jacobi(&mut self) {
        self.inv_diag.clear();
        for (i, (d, m)) in self.diag.iter().zip(&self.mask).enumerate() {
            // Replace fixed rows and columns by the identity, then invert.
            let keep = DMat3::from_diagonal(*m);
            let fixed = DMat3::from_diagonal(DVec3::ONE - *m);
            let d = match self.nodal.diag.get(i) {
                Some(nodal) => *d + *nodal,
                None => *d,
            };
            let block = keep * d * keep + fixed;
            let det = block.determinant();
            let inv = if det.is_finite() && det.abs() > 0.0 {
                block.inverse()
            } else {
                // A zero block (a mass-less, undamped free axis) preconditions as identity.
                DMat3::IDENTITY
            };
            self.inv_diag.push(keep * inv * keep);
        }
    }

    /// `y = A x` restricted to the free components, for `x` zero on the
    /// fixed components (as every vector CG multiplies is). `second` is
    /// scratch: the product is always summed as [`System::multiply_first`]
    /// plus [`System::multiply_second`], whether one thread computes both
    /// halves or two do (`crate::step::parallel`), so results do not depend on it.
    pub fn multiply(
        &self,
        tets: &[[u32; 4]],
        x: &[DVec3],
        y: &mut [DVec3],
        second: &mut Vec<DVec3>,
    ) {
        self.multiply_first(tets, x, y);
        self.multiply_second(x, second);
        self.multiply_finish(x, y, second);
    }

    /// Where the spring blocks split between the halves: the first half
    /// is smaller, since its thread also does the diagonal and the rest;
    /// with the nodal volume term, which the first half does, it has none.
    fn split(&self) -> usize {
        if self.nodal.is_active() {
            0
        } else {
            self.free_springs.len() / 2
        }
    }

    /// `y = D x` plus the first half of the spring blocks and the nodal
    /// volume term (`tets`: the model's elements).
    pub fn multiply_first(&self, tets: &[[u32; 4]], x: &[DVec3], y: &mut [DVec3]) {
        for ((y, d), x) in y.iter_mut().zip(&self.diag).zip(x) {
            *y = *d * *x;
        }
        debug_assert!(x.iter().zip(&self.mask).all(|(x, m)| *x == *x * *m));
        self.add_spring_blocks(0..self.split(), x, y);
        if self.nodal.is_active() {
            self.nodal.add_product(tets, x, y);
        }
    }

    /// `y` = the second half of the spring blocks times `x`.
    pub fn multiply_second(&self, x: &[DVec3], y: &mut Vec<DVec3>) {
        y.clear();
        y.resize(x.len(), DVec3::ZERO);
        self.add_spring_blocks(self.split()..self.free_springs.len(), x, y);
    }

    /// Adds the second half, the contact blocks, and masks.
    pub fn multiply_finish(&self, x: &[DVec3], y: &mut [DVec3], second: &[DVec3]) {
        for (y, s) in y.iter_mut().zip(second) {
            *y += *s;
        }
        for &(p, f, block) in &self.coupling {
            let (p, f) = (p as usize, f as usize);
            y[p] += block * x[f];
            y[f] += block.transpose() * x[p];
        }
        for (y, m) in y.iter_mut().zip(&self.mask) {
            *y *= *m;
        }
    }

    /// `z = M^-1 r` with the preconditioner `M`: block Jacobi, with the nodal volume term
    /// whole where there is one (`solver::pressure`).
    pub fn precondition(&self, r: &[DVec3], z: &mut [DVec3]) {
        let from = match self.pressure.as_ref().filter(|_| self.choice.factored) {
            Some(p) => {
                p.apply(r, z, &self.mask);
                self.particles
            }
            None => 0,
        };
        for ((z, inv), r) in z[from..]
            .iter_mut()
            .zip(&self.inv_diag[from..])
            .zip(&r[from..])
        {
            *z = *inv * *r;
        }
    }

    /// [`System::precondition`], returning `r . z`.
    pub fn precondition_dot(&self, r: &[DVec3], z: &mut [DVec3]) -> f64 {
        if self.choice.factored && self.pressure.is_some() {
            self.precondition(r, z);
            return r.iter().zip(z.iter()).map(|(r, z)| r.dot(*z)).sum();
        }
        // Block Jacobi alone, in CG's inner loop: one pass.
        let mut rz = 0.0;
        for ((z, inv), r) in z.iter_mut().zip(&self.inv_diag).zip(r) {
            *z = *inv * *r;
            rz += r.dot(*z);
        }
        rz
    }

    fn add_spring_blocks(&self, range: std::ops::Range<usize>, x: &[DVec3], y: &mut [DVec3]) {
        let (slots, pairs) = (&self.free_springs[range.clone()], &self.free_pairs[range]);
        for (&slot, &[i, j]) in slots.iter().zip(pairs) {
            let block = &self.off[slot as usize];
            let (i, j) = (i as usize, j as usize);
            y[i] += *block * x[j];
            y[j] += block.transpose() * x[i];
        }
    }
}

/// `a b^T`.
#[inline]
pub fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}
