//! The step's system solved by a sparse Cholesky factorisation (faer's supernodal `LL^T` with an
//! AMD ordering), for the static solver's Newton steps and the sensitivities: there the tangent
//! is exact and CG's inexact solves would cost Newton its quadratic convergence.
//!
//! The matrix is [`System`]'s blocks (diagonal, edge, coupling) plus the nodal volume term's
//! rank-one blocks `c_i g_i g_i^T`, which couple nodes two edges apart; restricted to the free
//! components (the Baraff-Witkin mask), its lower triangle in compressed columns. The pattern and
//! its symbolic analysis (ordering, elimination tree, supernodes) are made once per mesh, mask
//! and set of couplings; each solve refactors the values. A coupling outside the pattern (a new
//! contact) widens it: the pattern only grows, so a replay analyses it a few times at most.
//! Everything runs on the calling thread (`Par::Seq`), so results are the same bit for bit on any
//! thread count.

use std::collections::BTreeMap;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
    factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use glam::{DMat3, DVec3};

use super::System;
use super::gmres::{GmresParams, flexible_gmres};
use super::system::Asym;
use crate::model::Model;

/// A component that is not an unknown (masked out).
/// Free unknowns up to which a static solve may factorise its tangent
/// ([`crate::equilibrium::StaticSolver::Auto`], the static tangent's solver): the 4 mm cuboid's
/// 2,536 take 8.5 ms a factorisation, the 4 mm cylinder's 12,910 460 ms (its CG replay is 8
/// times faster than its direct one).
pub const DIRECT_UNKNOWNS: usize = 8000;

/// The factorisation a simulation keeps between its states held fixed (the sensitivities of
/// each load of a replay): a clone starts without one, so that what a solve reuses never
/// depends on another simulation's history.
#[derive(Debug, Default)]
pub struct KeptSolver(std::sync::Mutex<Option<DirectSolver>>);

impl Clone for KeptSolver {
    fn clone(&self) -> Self {
        KeptSolver::default()
    }
}

impl KeptSolver {
    /// The kept factorisation, if any, leaving none behind.
    pub fn take(&self) -> Option<DirectSolver> {
        self.0.lock().ok().and_then(|mut s| s.take())
    }

    /// Keeps `solver` for the next [`KeptSolver::take`].
    pub fn keep(&self, solver: DirectSolver) {
        if let Ok(mut kept) = self.0.lock() {
            *kept = Some(solver);
        }
    }
}

const NONE: u32 = u32::MAX;

/// GMRES's relative residual on a system with a non-symmetric remainder: Newton's step to
/// about the rounding of the force it is computed from.
const ASYM_TOLERANCE: f64 = 1e-10;

/// Why a direct solve did not happen.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum DirectError {
    /// The matrix is not positive definite (a pivot not positive): the tangent is indefinite.
    #[error("the system matrix is not positive definite (a Cholesky pivot is not positive)")]
    NotPositiveDefinite,
    /// The factor would not fit in memory, or the symbolic analysis failed.
    #[error("the sparse factorisation could not be made: {0}")]
    Factorisation(&'static str),
}

/// What a pattern was made for: another mesh, mask or set of couplings needs another.
#[derive(Debug, Clone, PartialEq)]
struct Key {
    dofs: usize,
    springs: usize,
    elements: usize,
    nodal: bool,
    mask: Vec<DVec3>,
}

/// The nodal volume term's pattern: per node, its patch (the nodes of its elements) and where
/// each pair of patch nodes' block goes.
#[derive(Debug, Clone, Default)]
struct NodalPattern {
    /// Node `i`'s patch nodes are `patch[patch_start[i]..patch_start[i + 1]]`, ascending.
    patch_start: Vec<u32>,
    patch: Vec<u32>,
    /// Node `i`'s elements are `elements[element_start[i]..element_start[i + 1]]`, each with the
    /// patch slots of its four nodes.
    element_start: Vec<u32>,
    elements: Vec<(u32, [u16; 4])>,
    /// For node `i`, the pairs `(k, l)`, `k >= l` of its patch slots, row-major, each with the
    /// positions of the block (patch[k], patch[l]) in the lower triangle: `pair_start[i]` is the
    /// first.
    pair_start: Vec<u32>,
    pair_positions: Vec<[u32; 9]>,
}

/// A sparse Cholesky factorisation of the step's matrix, its pattern analysed once.
#[derive(Debug, Default)]
pub struct DirectSolver {
    key: Option<Key>,
    /// Each component's unknown (`3 dof + axis`), or [`NONE`]; ascending.
    index: Vec<u32>,
    unknowns: usize,
    col_ptr: Vec<u32>,
    row_idx: Vec<u32>,
    values: Vec<f64>,
    /// Positions of each dof's diagonal block, `[3 a + b]` for `a >= b` (row a, column b).
    diag_pos: Vec<[u32; 9]>,
    /// Positions of each spring's block (row `j`, column `i`): `[3 b + a]` holds the entry of
    /// `off[s]`'s row a, column b (block (i, j)), which sits at row `3 j + b`, column `3 i + a`.
    off_pos: Vec<[u32; 9]>,
    /// Block pairs of the couplings in the pattern (larger dof, smaller dof).
    couplings: BTreeMap<(u32, u32), [u32; 9]>,
    nodal: Option<NodalPattern>,
    symbolic: Option<SymbolicCholesky<u32>>,
    factor: Vec<f64>,
    stack: Stack,
    /// Whether `factor` holds the factorisation of the last assembled values.
    factored: bool,
    /// Symbolic analyses made (one per new pattern).
    pub analyses: usize,
    /// Numeric factorisations made.
    pub factorisations: usize,
    /// Patch-sized scratch for the nodal term.
    gradient: Vec<DVec3>,
}

impl Clone for DirectSolver {
    /// A clone analyses its pattern anew when first used.
    fn clone(&self) -> DirectSolver {
        DirectSolver::default()
    }
}

impl DirectSolver {
    /// The unknowns of the last system: the free components.
    pub fn unknowns(&self) -> usize {
        self.unknowns
    }

    /// Values of the factor (a measure of its cost).
    pub fn factor_len(&self) -> usize {
        self.factor.len()
    }

    /// Assembles `system` (finished, for `model`'s mesh) and factorises it.
    pub fn factorise(&mut self, model: &Model, system: &System) -> Result<(), DirectError> {
        self.factored = false;
        self.ensure_pattern(model, system)?;
        self.assemble(model, system);
        let Some(symbolic) = self.symbolic.as_ref() else {
            unreachable!("ensure_pattern analyses the pattern")
        };
        let n = self.unknowns;
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx),
            &self.values,
        );
        self.factor.clear();
        self.factor.resize(symbolic.len_val(), 0.0);
        let need = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        let stack = self.stack.at_least(need)?;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut self.factor,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| DirectError::NotPositiveDefinite)?;
        self.factorisations += 1;
        self.factored = true;
        Ok(())
    }

    /// `x = A^-1 b` on the free components (zero on the fixed ones), with the last
    /// factorisation. `b` and `x` are per dof (particles then fingers).
    pub fn solve(&mut self, b: &[DVec3], x: &mut [DVec3]) {
        let Some(symbolic) = self.symbolic.as_ref().filter(|_| self.factored) else {
            unreachable!("solve after a successful factorise")
        };
        let mut rhs = vec![0.0; self.unknowns];
        for (c, &k) in self.index.iter().enumerate() {
            if k != NONE {
                rhs[k as usize] = b[c / 3][c % 3];
            }
        }
        let n = self.unknowns;
        let Ok(stack) = self
            .stack
            .at_least(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq))
        else {
            unreachable!("factorise reserved the solve's scratch")
        };
        LltRef::new(symbolic, &self.factor).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut rhs, n, 1),
            Par::Seq,
            stack,
        );
        for (c, &k) in self.index.iter().enumerate() {
            x[c / 3][c % 3] = if k == NONE { 0.0 } else { rhs[k as usize] };
        }
    }

    /// `x = A^-1 b` for the whole system `A = P + R`: `P` the factorised symmetric blocks, `R`
    /// the remainder `system.asym` (friction in a static solve). GMRES on `(I + R P^-1) u = b`,
    /// `x = P^-1 u` (right-preconditioned by the factor, so a product is one solve with the
    /// factor and the small `R`); without a remainder, a plain [`DirectSolver::solve`]. Returns
    /// GMRES's iterations (0: none needed), or `None` where it did not reach its tolerance, `x`
    /// then the factor's answer for `P` alone: an approximate Newton step.
    pub fn solve_system(&mut self, system: &System, b: &[DVec3], x: &mut [DVec3]) -> Option<usize> {
        self.solve(b, x);
        if system.asym.is_empty() {
            return Some(0);
        }
        let params = GmresParams {
            tolerance: ASYM_TOLERANCE,
            max_iterations: 60,
            restart: 60,
        };
        // Started from the factor's answer x: u = P x = b - R x.
        let mut u = b.to_vec();
        let mut rx = vec![DVec3::ZERO; b.len()];
        remainder_product(system, x, &mut rx);
        for (u, r) in u.iter_mut().zip(&rx) {
            *u -= *r;
        }
        let report = {
            let this = std::cell::RefCell::new(&mut *self);
            let apply = |v: &[DVec3], out: &mut Vec<DVec3>| -> Result<(), ()> {
                let mut z = vec![DVec3::ZERO; v.len()];
                this.borrow_mut().solve(v, &mut z);
                out.clear();
                out.extend_from_slice(v);
                remainder_product(system, &z, out);
                Ok(())
            };
            let identity = |r: &[DVec3], z: &mut Vec<DVec3>| -> Result<(), ()> {
                z.clear();
                z.extend_from_slice(r);
                Ok(())
            };
            flexible_gmres(apply, identity, b, &mut u, params)
        };
        let Ok(report) = report else {
            return None;
        };
        self.solve(&u, x);
        Some(report.iterations)
    }

    /// `out = A v` on the free components (zero on the fixed ones), `A` the last factorised
    /// system's assembled matrix (its symmetric blocks, lower triangle) plus its non-symmetric
    /// remainder: what [`DirectSolver::solve_system`] inverts.
    pub fn apply(&self, system: &System, v: &[DVec3], out: &mut [DVec3]) {
        let n = self.unknowns;
        let mut xv = vec![0.0; n];
        for (c, &k) in self.index.iter().enumerate() {
            if k != NONE {
                xv[k as usize] = v[c / 3][c % 3];
            }
        }
        let mut yv = vec![0.0; n];
        for col in 0..n {
            let (start, end) = (self.col_ptr[col] as usize, self.col_ptr[col + 1] as usize);
            for p in start..end {
                let row = self.row_idx[p] as usize;
                let a = self.values[p];
                yv[row] += a * xv[col];
                if row != col {
                    yv[col] += a * xv[row];
                }
            }
        }
        for (c, &k) in self.index.iter().enumerate() {
            out[c / 3][c % 3] = if k == NONE { 0.0 } else { yv[k as usize] };
        }
        remainder_product(system, v, out);
    }

    /// Analyses the pattern anew where the mesh, the mask or the couplings changed.
    fn ensure_pattern(&mut self, model: &Model, system: &System) -> Result<(), DirectError> {
        let key = Key {
            dofs: system.diag.len(),
            springs: system.off.len(),
            elements: model.tets.len(),
            nodal: system.nodal.is_active(),
            mask: system.mask.clone(),
        };
        let fits = self.key.as_ref() == Some(&key)
            && system
                .coupling
                .iter()
                .all(|&(p, f, _)| p == f || self.couplings.contains_key(&ordered(p, f)));
        if fits {
            return Ok(());
        }
        // Couplings already in the pattern stay (a contact that ended may come back).
        let mut pairs: Vec<(u32, u32)> = if self.key.as_ref() == Some(&key) {
            self.couplings.keys().copied().collect()
        } else {
            Vec::new()
        };
        pairs.extend(
            system
                .coupling
                .iter()
                .filter(|(p, f, _)| p != f)
                .map(|&(p, f, _)| ordered(p, f)),
        );
        // A finger's contacts move over the boundary: every boundary particle it may touch
        // joins the pattern with the first, so that a contact moving on does not need another
        // analysis.
        let fingers: Vec<u32> = pairs
            .iter()
            .filter(|(hi, _)| *hi as usize >= model.particle_count())
            .map(|(hi, _)| *hi)
            .collect();
        for f in fingers {
            for tri in &model.facets {
                for &p in tri {
                    pairs.push((f, p));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        self.build_pattern(model, system, key, &pairs)
    }

    /// Analyses the pattern of `key` with `pairs` (contact couplings, `(hi, lo)`) from scratch:
    /// numbers the unknowns, lays out the lower triangle, finds each block's entries and runs
    /// the symbolic factorisation.
    fn build_pattern(
        &mut self,
        model: &Model,
        system: &System,
        key: Key,
        pairs: &[(u32, u32)],
    ) -> Result<(), DirectError> {
        let dofs = key.dofs;
        self.number_unknowns(&key.mask);
        let (blocks, nodal) = block_pattern(model, &key, pairs);
        self.lay_out(&blocks);
        self.locate_blocks(model, dofs, pairs, nodal);
        self.analyse()?;
        let _ = system;
        self.key = Some(key);
        Ok(())
    }

    /// The unknowns: free components (`mask` nonzero), in order; [`NONE`] for fixed ones.
    fn number_unknowns(&mut self, mask: &[DVec3]) {
        self.index.clear();
        let mut next = 0u32;
        for m in mask {
            for axis in 0..3 {
                if m[axis] != 0.0 {
                    self.index.push(next);
                    next += 1;
                } else {
                    self.index.push(NONE);
                }
            }
        }
        self.unknowns = next as usize;
    }

    /// The scalar pattern of `blocks`: lower triangle, rows ascending in each column; the
    /// values zeroed.
    fn lay_out(&mut self, blocks: &[Vec<u32>]) {
        self.col_ptr.clear();
        self.row_idx.clear();
        self.col_ptr.push(0);
        for (bj, rows) in blocks.iter().enumerate() {
            for b in 0..3 {
                let col = self.index[3 * bj + b];
                if col == NONE {
                    continue;
                }
                for &bi in rows {
                    for a in 0..3 {
                        let row = self.index[3 * bi as usize + a];
                        if row != NONE && row >= col {
                            self.row_idx.push(row);
                        }
                    }
                }
                self.col_ptr.push(self.row_idx.len() as u32);
            }
        }
        self.values.clear();
        self.values.resize(self.row_idx.len(), 0.0);
    }

    /// Where each block's entries go: the diagonal (`dofs` blocks), the springs, the
    /// couplings `pairs` and, with the nodal pattern, each patch's pairs.
    fn locate_blocks(
        &mut self,
        model: &Model,
        dofs: usize,
        pairs: &[(u32, u32)],
        nodal: Option<NodalPattern>,
    ) {
        self.diag_pos = (0..dofs).map(|d| self.block_positions(d, d)).collect();
        self.off_pos = model
            .springs
            .iter()
            .map(|s| self.block_positions(s.j as usize, s.i as usize))
            .collect();
        self.couplings = pairs
            .iter()
            .map(|&(hi, lo)| ((hi, lo), self.block_positions(hi as usize, lo as usize)))
            .collect();
        self.nodal = nodal.map(|mut p| {
            p.pair_start.clear();
            p.pair_positions.clear();
            for i in 0..p.patch_start.len() - 1 {
                p.pair_start.push(p.pair_positions.len() as u32);
                let patch = &p.patch[p.patch_start[i] as usize..p.patch_start[i + 1] as usize];
                for (k, &a) in patch.iter().enumerate() {
                    for &b in &patch[..=k] {
                        let pos = self.block_positions(a as usize, b as usize);
                        p.pair_positions.push(pos);
                    }
                }
            }
            p.pair_start.push(p.pair_positions.len() as u32);
            p
        });
    }

    /// The symbolic Cholesky analysis (AMD ordering) of the laid-out pattern.
    fn analyse(&mut self) -> Result<(), DirectError> {
        let n = self.unknowns;
        let symbolic =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        let analysed = factorize_symbolic_cholesky(
            symbolic,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .map_err(|_| DirectError::Factorisation("the symbolic analysis failed"))?;
        self.symbolic = Some(analysed);
        self.analyses += 1;
        Ok(())
    }

    /// The positions of block (`bi`, `bj`), `bi >= bj`, in the lower triangle: `[3 a + b]` for
    /// row `3 bi + a`, column `3 bj + b` ([`NONE`] where masked or above the diagonal).
    fn block_positions(&self, bi: usize, bj: usize) -> [u32; 9] {
        let mut out = [NONE; 9];
        for b in 0..3 {
            let col = self.index[3 * bj + b];
            if col == NONE {
                continue;
            }
            let rows = &self.row_idx
                [self.col_ptr[col as usize] as usize..self.col_ptr[col as usize + 1] as usize];
            for a in 0..3 {
                let row = self.index[3 * bi + a];
                if row == NONE || row < col {
                    continue;
                }
                if let Ok(k) = rows.binary_search(&row) {
                    out[3 * a + b] = self.col_ptr[col as usize] + k as u32;
                }
            }
        }
        out
    }

    /// The matrix's values from the system's blocks.
    fn assemble(&mut self, model: &Model, system: &System) {
        let values = &mut self.values;
        values.fill(0.0);
        for (block, pos) in system.diag.iter().zip(&self.diag_pos) {
            // Symmetrised: a return mapping's diagonal block may not be.
            add_block(values, pos, (*block + block.transpose()) * 0.5);
        }
        for (block, pos) in system.off.iter().zip(&self.off_pos) {
            // off[s] is block (i, j); the lower triangle holds block (j, i) = off[s]^T.
            add_block(values, pos, block.transpose());
        }
        for &(p, f, block) in &system.coupling {
            if p == f {
                let pos = self.diag_pos[p as usize];
                add_block(values, &pos, (block + block.transpose()) * 0.5);
                continue;
            }
            let Some(pos) = self.couplings.get(&ordered(p, f)) else {
                unreachable!("ensure_pattern holds every coupling")
            };
            // block is (p, f); the lower triangle holds (max, min).
            add_block(values, pos, if p > f { block } else { block.transpose() });
        }
        if let Some(nodal) = &self.nodal {
            let op = &system.nodal;
            for i in 0..nodal.patch_start.len() - 1 {
                let weight = op.weight[i];
                if weight == 0.0 {
                    continue;
                }
                let (p0, p1) = (
                    nodal.patch_start[i] as usize,
                    nodal.patch_start[i + 1] as usize,
                );
                let g = &mut self.gradient;
                g.clear();
                g.resize(p1 - p0, DVec3::ZERO);
                let (e0, e1) = (
                    nodal.element_start[i] as usize,
                    nodal.element_start[i + 1] as usize,
                );
                for &(e, slots) in &nodal.elements[e0..e1] {
                    let q = &op.quarter_gradients[e as usize];
                    for (a, &slot) in slots.iter().enumerate() {
                        g[slot as usize] += q[a];
                    }
                }
                let mut pair = nodal.pair_start[i] as usize;
                for k in 0..g.len() {
                    let gk = g[k] * weight;
                    for l in 0..=k {
                        add_block(values, &nodal.pair_positions[pair], outer(gk, g[l]));
                        pair += 1;
                    }
                }
            }
        }
        let _ = model;
    }
}

/// faer's scratch memory, grown to the largest need seen.
#[derive(Default)]
struct Stack {
    buffer: Option<MemBuffer>,
    bytes: usize,
}

impl std::fmt::Debug for Stack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Stack({} bytes)", self.bytes)
    }
}

impl Stack {
    /// At least `need` of scratch.
    fn at_least(&mut self, need: StackReq) -> Result<&mut MemStack, DirectError> {
        let bytes = need.size_bytes();
        if self.buffer.is_none() || self.bytes < bytes {
            let buffer = MemBuffer::try_new(need)
                .map_err(|_| DirectError::Factorisation("out of memory"))?;
            self.buffer = Some(buffer);
            self.bytes = bytes;
        }
        match self.buffer.as_mut() {
            Some(b) => Ok(MemStack::new(b)),
            None => unreachable!("set above"),
        }
    }
}

/// `out += R v` on the free components, `R` the system's non-symmetric remainder.
fn remainder_product(system: &System, v: &[DVec3], out: &mut [DVec3]) {
    for term in &system.asym {
        for (a, &da) in term.dofs.iter().enumerate() {
            if da == Asym::NONE {
                continue;
            }
            let mut sum = DVec3::ZERO;
            for (bb, &db) in term.dofs.iter().enumerate() {
                if db != Asym::NONE {
                    sum += term.blocks[a][bb] * v[db as usize];
                }
            }
            out[da as usize] += sum * system.mask[da as usize];
        }
    }
}

/// A coupling's block pair as the pattern keys it: (larger dof, smaller dof).
fn ordered(p: u32, f: u32) -> (u32, u32) {
    (p.max(f), p.min(f))
}

/// `a b^T`.
#[inline]
fn outer(a: DVec3, b: DVec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// Adds `block` (row a, column b at `[3 a + b]` of `pos`) where it has a place.
#[inline]
fn add_block(values: &mut [f64], pos: &[u32; 9], block: DMat3) {
    for b in 0..3 {
        let col = block.col(b);
        for a in 0..3 {
            let p = pos[3 * a + b];
            if p != NONE {
                values[p as usize] += col[a];
            }
        }
    }
}

/// The block pattern: for each block column, the block rows at or below it (sorted, once
/// each): the diagonal, the springs, the couplings `pairs` and, if `key.nodal`, every pair in
/// a nodal patch (the nodal pattern returned with it).
fn block_pattern(
    model: &Model,
    key: &Key,
    pairs: &[(u32, u32)],
) -> (Vec<Vec<u32>>, Option<NodalPattern>) {
    let mut blocks: Vec<Vec<u32>> = vec![Vec::new(); key.dofs];
    for (d, rows) in blocks.iter_mut().enumerate() {
        rows.push(d as u32);
    }
    for s in &model.springs {
        blocks[s.i.min(s.j) as usize].push(s.i.max(s.j));
    }
    for &(hi, lo) in pairs {
        blocks[lo as usize].push(hi);
    }
    let nodal = if key.nodal {
        let pattern = nodal_pattern(model);
        for i in 0..pattern.patch_start.len() - 1 {
            let patch = &pattern.patch
                [pattern.patch_start[i] as usize..pattern.patch_start[i + 1] as usize];
            for (k, &a) in patch.iter().enumerate() {
                for &b in &patch[..k] {
                    blocks[b as usize].push(a);
                }
            }
        }
        Some(pattern)
    } else {
        None
    };
    for rows in &mut blocks {
        rows.sort_unstable();
        rows.dedup();
    }
    (blocks, nodal)
}

/// Each node's patch and elements (the nodal volume term's coupling).
fn nodal_pattern(model: &Model) -> NodalPattern {
    let nodes = model.particle_count();
    let mut around: Vec<Vec<u32>> = vec![Vec::new(); nodes];
    for (e, tet) in model.tets.iter().enumerate() {
        for &i in tet {
            around[i as usize].push(e as u32);
        }
    }
    let mut p = NodalPattern::default();
    p.patch_start.push(0);
    p.element_start.push(0);
    for elements in &around {
        let mut patch: Vec<u32> = elements
            .iter()
            .flat_map(|&e| model.tets[e as usize])
            .collect();
        patch.sort_unstable();
        patch.dedup();
        for &e in elements {
            let slots =
                model.tets[e as usize].map(|n| patch.binary_search(&n).map_or(0, |k| k as u16));
            p.elements.push((e, slots));
        }
        p.patch.extend_from_slice(&patch);
        p.patch_start.push(p.patch.len() as u32);
        p.element_start.push(p.elements.len() as u32);
    }
    p
}
