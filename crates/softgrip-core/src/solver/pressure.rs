//! The preconditioner for a nearly incompressible body: block Jacobi on the rest of the
//! system plus the nodal volume term whole, inverted by Woodbury's identity.
//!
//! The system is `A = B + G C G^T`, with `G` the nodal volume gradients (one column a node) and
//! `C` their weights (`dt^2 K_i / V0_i`, `solver::system::NodalOperator`). Near nu = 0.5, `C`
//! is hundreds of times the shear stiffness, and block Jacobi, which sees only the diagonal of
//! `G C G^T`, needs five times the CG iterations it needs at nu = 0.45. Here
//! `P = D + G C G^T` (`D`: the block diagonal of `B`), whose inverse is
//! `D^-1 - D^-1 G S^-1 G^T D^-1` with `S = C^-1 + G^T D^-1 G`: one value a node, coupling nodes
//! two edges apart, factored once by envelope Cholesky in reverse Cuthill-McKee order.
//!
//! A factorization is kept over steps while it stays good (`Pressure::serves`): `P` is then
//! that of an earlier step, still symmetric positive definite (its `G`, `C` and `D` are kept
//! with it), so CG stays CG and only its iteration count tells the age. An iteration with it
//! costs two to three products (`S` couples nodes two edges apart), so it is used only while
//! it saves more iterations than that ([`Choice`]): below nu = 0.49 block Jacobi is cheaper.

use glam::{DMat3, DVec3};

/// Envelope entries the factor may hold per element: beyond (a large or badly ordered mesh),
/// block Jacobi alone, so memory stays within a few hundred bytes an element.
const ENVELOPE_PER_ELEMENT: usize = 40;

/// A factorization of `P` at one step.
#[derive(Debug, Default, Clone)]
pub struct Pressure {
    tets: Vec<[u32; 4]>,
    quarter_gradients: Vec<[DVec3; 4]>,
    /// `D^-1` on the particles, masked.
    inv_d: Vec<DMat3>,
    /// Node at each position of the ordering, and the position of each node.
    order: Vec<u32>,
    position: Vec<u32>,
    /// Row `p` of the factor holds columns `first[p]..=p` from `start[p]` in `l`.
    first: Vec<u32>,
    start: Vec<usize>,
    l: Vec<f64>,
    /// The mask it was built under: another asks for another factorization.
    mask: Vec<DVec3>,
    /// CG iterations of the first solve with this factorization (0: not solved yet).
    pub fresh_iterations: usize,
    /// The element count the ordering was made for.
    ordered_for: usize,
}

/// Why there is no factorization: the system is preconditioned by block Jacobi.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoFactor {
    /// The factor would hold more than `ENVELOPE_PER_ELEMENT` values an element.
    TooLarge,
    /// A node without volume weight, or a pivot not positive (`S` not positive definite).
    NotDefinite,
}

impl Pressure {
    /// Whether this factorization serves a system with `particles` and `mask`, after a solve
    /// of `last_iterations` with it: not when the last solve took so many more iterations
    /// than the first that a new one pays.
    pub fn serves(&mut self, particles: usize, mask: &[DVec3], last_iterations: usize) -> bool {
        if self.inv_d.len() != particles || self.mask[..] != mask[..particles] {
            return false;
        }
        if self.fresh_iterations == 0 {
            self.fresh_iterations = last_iterations.max(1);
        }
        last_iterations <= 2 * self.fresh_iterations + 5
    }

    /// Factors `P` for the particles' diagonal blocks `diag` (the nodal term not included)
    /// under `mask`, the elements `tets` and the nodal term's `quarter_gradients` and
    /// `weight` (one a particle).
    pub fn build(
        &mut self,
        tets: &[[u32; 4]],
        quarter_gradients: &[[DVec3; 4]],
        weight: &[f64],
        diag: &[DMat3],
        mask: &[DVec3],
    ) -> Result<(), NoFactor> {
        let n = weight.len();
        // Every weight positive and finite (NaN fails too): C^-1 must exist.
        if !weight.iter().all(|&w| w > 0.0 && w.is_finite()) {
            return Err(NoFactor::NotDefinite);
        }
        let mut elements_of = vec![Vec::new(); n];
        for (e, tet) in tets.iter().enumerate() {
            for &i in tet {
                elements_of[i as usize].push(e as u32);
            }
        }
        if self.ordered_for != tets.len() || self.order.len() != n {
            self.order_and_envelope(tets, &elements_of)?;
            self.ordered_for = tets.len();
        }
        self.tets.clear();
        self.tets.extend_from_slice(tets);
        self.quarter_gradients.clear();
        self.quarter_gradients.extend_from_slice(quarter_gradients);
        self.inv_d.clear();
        self.inv_d
            .extend(diag[..n].iter().zip(&mask[..n]).map(|(d, m)| {
                let keep = DMat3::from_diagonal(*m);
                let block = keep * *d * keep + DMat3::from_diagonal(DVec3::ONE - *m);
                let det = block.determinant();
                let inv = if det.is_finite() && det.abs() > 0.0 {
                    block.inverse()
                } else {
                    DMat3::IDENTITY
                };
                keep * inv * keep
            }));
        self.mask.clear();
        self.mask.extend_from_slice(&mask[..n]);
        self.fresh_iterations = 0;

        // S = C^-1 + G^T D^-1 G, summed node k by node k: g_i[k] = dV_i/dx_k.
        self.l.iter_mut().for_each(|v| *v = 0.0);
        let mut local: Vec<(u32, DVec3)> = Vec::new();
        for (k, elements) in elements_of.iter().enumerate() {
            local.clear();
            for &e in elements {
                let tet = tets[e as usize];
                let a = tet.iter().position(|&i| i as usize == k).unwrap_or(0);
                let g = quarter_gradients[e as usize][a];
                for &i in &tet {
                    match local.iter_mut().find(|(j, _)| *j == i) {
                        Some((_, sum)) => *sum += g,
                        None => local.push((i, g)),
                    }
                }
            }
            let inv = self.inv_d[k];
            for &(i, gi) in &local {
                let hi = inv * gi;
                let pi = self.position[i as usize];
                for &(j, gj) in &local {
                    let pj = self.position[j as usize];
                    if pj <= pi {
                        let slot =
                            self.start[pi as usize] + (pj - self.first[pi as usize]) as usize;
                        self.l[slot] += hi.dot(gj);
                    }
                }
            }
        }
        for (i, w) in weight.iter().enumerate() {
            let p = self.position[i] as usize;
            self.l[self.start[p] + p - self.first[p] as usize] += 1.0 / w;
        }
        self.factor()
    }

    /// Multiply-adds of an application: the two triangular solves and the two passes over
    /// the elements.
    pub fn work(&self) -> f64 {
        (2 * self.l.len() + 48 * self.tets.len() + 18 * self.inv_d.len()) as f64
    }

    /// Reverse Cuthill-McKee on the graph of `S` (nodes sharing an element's node), and the
    /// envelope it gives.
    fn order_and_envelope(
        &mut self,
        tets: &[[u32; 4]],
        elements_of: &[Vec<u32>],
    ) -> Result<(), NoFactor> {
        let n = elements_of.len();
        let neighbours = node_graph(tets, elements_of);
        let order = reverse_cuthill_mckee(&neighbours);
        let mut position = vec![0u32; n];
        for (p, &i) in order.iter().enumerate() {
            position[i as usize] = p as u32;
        }
        let mut first = vec![0u32; n];
        let mut start = Vec::with_capacity(n + 1);
        let mut size = 0usize;
        for p in 0..n {
            let i = order[p] as usize;
            let low = neighbours[i]
                .iter()
                .map(|&j| position[j as usize])
                .filter(|&q| (q as usize) < p)
                .min()
                .unwrap_or(p as u32);
            first[p] = low;
            start.push(size);
            size += p + 1 - low as usize;
        }
        if size > ENVELOPE_PER_ELEMENT * tets.len().max(1) {
            return Err(NoFactor::TooLarge);
        }
        self.order = order;
        self.position = position;
        self.first = first;
        self.start = start;
        self.l = vec![0.0; size];
        Ok(())
    }

    /// In place: `S = L L^T` row by row within the envelope.
    fn factor(&mut self) -> Result<(), NoFactor> {
        let n = self.order.len();
        for p in 0..n {
            let (fp, sp) = (self.first[p] as usize, self.start[p]);
            for q in fp..=p {
                let (fq, sq) = (self.first[q] as usize, self.start[q]);
                let from = fp.max(fq);
                let mut sum = self.l[sp + q - fp];
                for m in from..q {
                    sum -= self.l[sp + m - fp] * self.l[sq + m - fq];
                }
                if q < p {
                    self.l[sp + q - fp] = sum / self.l[sq + q - fq];
                } else if sum > 0.0 && sum.is_finite() {
                    self.l[sp + p - fp] = sum.sqrt();
                } else {
                    return Err(NoFactor::NotDefinite);
                }
            }
        }
        Ok(())
    }

    /// `v = S^-1 v`, `v` in node order: the hot spot of a nearly incompressible step, so row
    /// slices (no bounds checks) and a dot product in four sums (a single sum waits on each add).
    fn solve(&self, v: &mut [f64], y: &mut Vec<f64>) {
        let n = self.order.len();
        y.clear();
        y.extend(self.order.iter().map(|&i| v[i as usize]));
        for p in 0..n {
            let (fp, sp) = (self.first[p] as usize, self.start[p]);
            let row = &self.l[sp..=sp + p - fp];
            let (below, done) = y.split_at_mut(p);
            done[0] = (done[0] - dot(&row[..p - fp], &below[fp..])) / row[p - fp];
        }
        for p in (0..n).rev() {
            let (fp, sp) = (self.first[p] as usize, self.start[p]);
            let row = &self.l[sp..=sp + p - fp];
            let (below, done) = y.split_at_mut(p);
            done[0] /= row[p - fp];
            let yp = done[0];
            for (y, l) in below[fp..].iter_mut().zip(&row[..p - fp]) {
                *y -= l * yp;
            }
        }
        for (p, &i) in self.order.iter().enumerate() {
            v[i as usize] = y[p];
        }
    }

    /// `z = P^-1 r` on the particles (the first `inv_d.len()` entries), masked by `mask`.
    pub fn apply(&self, r: &[DVec3], z: &mut [DVec3], mask: &[DVec3]) {
        SCRATCH.with_borrow_mut(|(u, y, gv)| {
            let n = self.inv_d.len();
            for ((z, inv), r) in z[..n].iter_mut().zip(&self.inv_d).zip(r) {
                *z = *inv * *r;
            }
            u.clear();
            u.resize(n, 0.0);
            for (tet, g) in self.tets.iter().zip(&self.quarter_gradients) {
                let t = tet.map(|i| i as usize);
                let w = (0..4).map(|a| g[a].dot(z[t[a]])).sum::<f64>();
                for i in t {
                    u[i] += w;
                }
            }
            self.solve(u, y);
            // z -= D^-1 G v, G v gathered element by element into y's room.
            gv.clear();
            gv.resize(n, DVec3::ZERO);
            for (tet, g) in self.tets.iter().zip(&self.quarter_gradients) {
                let t = tet.map(|i| i as usize);
                let q = t.iter().map(|&i| u[i]).sum::<f64>();
                for a in 0..4 {
                    gv[t[a]] += g[a] * q;
                }
            }
            for (((z, inv), g), m) in z[..n].iter_mut().zip(&self.inv_d).zip(gv.iter()).zip(mask) {
                *z = (*z - *inv * *g) * *m;
            }
        });
    }
}

/// `a . b` over the shorter, in four interleaved sums added at the end: the loop is bound by
/// the add's latency otherwise. Deterministic (a fixed order), not the sequential sum's bits.
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = [0.0f64; 4];
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let (ra, rb) = (a4.remainder(), b4.remainder());
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            s[k] += x[k] * y[k];
        }
    }
    let tail: f64 = ra.iter().zip(rb).map(|(x, y)| x * y).sum();
    (s[0] + s[1]) + (s[2] + s[3]) + tail
}

/// Which preconditioner the next solve uses, from the iterations the last ones took. The
/// factorization is tried when block Jacobi takes more iterations than the factor's own
/// application costs ten times over (it leaves ten or more), and kept while its iterations,
/// weighted by their `cost` against block Jacobi's, are fewer than block Jacobi's last count.
/// Deterministic: iteration counts, not clocks, decide.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct Choice {
    /// The last solve used the factorization.
    pub factored: bool,
    /// Iterations of the last solve with block Jacobi.
    jacobi: usize,
    /// After the factorization lost: block Jacobi's count must pass this for another try.
    retry_above: usize,
}

impl Choice {
    /// After a solve of `iterations` with the current choice (0: none yet), whether the next
    /// uses the factorization, whose iteration costs `cost` block-Jacobi iterations.
    pub fn next(&mut self, iterations: usize, cost: f64) -> bool {
        if iterations == 0 {
            return self.factored;
        }
        if self.factored {
            if iterations as f64 * cost > self.jacobi as f64 {
                self.factored = false;
                self.retry_above = 2 * self.jacobi;
            }
        } else {
            self.jacobi = iterations;
            self.factored = iterations as f64 > 10.0 * cost && iterations > self.retry_above;
        }
        self.factored
    }

    /// The factorization could not be made (`S` not positive definite here): block Jacobi,
    /// and no other try until its count doubles.
    pub fn failed(&mut self) {
        self.factored = false;
        self.retry_above = 2 * self.jacobi;
    }
}

thread_local! {
    /// `G^T D^-1 r` (then `S^-1` of it), the ordering's copy, and `G v`: one set a thread.
    #[allow(clippy::type_complexity)]
    static SCRATCH: std::cell::RefCell<(Vec<f64>, Vec<f64>, Vec<DVec3>)> =
        const { std::cell::RefCell::new((Vec::new(), Vec::new(), Vec::new())) };
}

/// The graph of `S`: for each node, the nodes sharing an element's node with it (ascending,
/// once each; `elements_of[k]`: the elements holding node `k`).
fn node_graph(tets: &[[u32; 4]], elements_of: &[Vec<u32>]) -> Vec<Vec<u32>> {
    let n = elements_of.len();
    let ring = |k: usize| {
        let mut r: Vec<u32> = elements_of[k]
            .iter()
            .flat_map(|&e| tets[e as usize])
            .collect();
        r.sort_unstable();
        r.dedup();
        r
    };
    let rings: Vec<Vec<u32>> = (0..n).map(ring).collect();
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); n];
    for r in &rings {
        for &i in r {
            neighbours[i as usize].extend(r.iter().copied().filter(|&j| j != i));
        }
    }
    for list in &mut neighbours {
        list.sort_unstable();
        list.dedup();
    }
    neighbours
}

/// Reverse Cuthill-McKee order of the graph `neighbours`: breadth first from the least
/// connected unseen node, neighbours by ascending degree, then reversed.
fn reverse_cuthill_mckee(neighbours: &[Vec<u32>]) -> Vec<u32> {
    let n = neighbours.len();
    let mut seen = vec![false; n];
    let mut order = Vec::with_capacity(n);
    let mut by_degree: Vec<u32> = (0..n as u32).collect();
    by_degree.sort_by_key(|&i| (neighbours[i as usize].len(), i));
    for &root in &by_degree {
        if seen[root as usize] {
            continue;
        }
        seen[root as usize] = true;
        let mut head = order.len();
        order.push(root);
        while head < order.len() {
            let mut next: Vec<u32> = neighbours[order[head] as usize]
                .iter()
                .copied()
                .filter(|&j| !seen[j as usize])
                .collect();
            next.sort_by_key(|&j| (neighbours[j as usize].len(), j));
            for j in next {
                seen[j as usize] = true;
                order.push(j);
            }
            head += 1;
        }
    }
    order.reverse();
    order
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factorization_is_tried_where_jacobi_is_slow_and_kept_while_it_pays() {
        let mut c = Choice::default();
        assert!(!c.next(0, 3.0), "no solve yet: block Jacobi");
        assert!(
            !c.next(25, 3.0),
            "25 iterations: no room to save three times over"
        );
        assert!(c.next(170, 3.0), "170: tried");
        assert!(c.next(36, 3.0), "36 x 3 < 170: kept");
        assert!(!c.next(60, 3.0), "60 x 3 > 170: block Jacobi again");
        assert!(
            !c.next(200, 3.0),
            "not tried again below twice the count it lost to"
        );
        assert!(c.next(400, 3.0), "past it: tried again");
    }

    /// The four-sum dot product is the dot product at every length, the tail included
    /// (small integers: every sum exact, whatever the order).
    #[test]
    fn the_dot_product_in_four_sums_is_the_dot_product() {
        for n in 0..11usize {
            let a: Vec<f64> = (0..n).map(|i| (i as f64) - 3.0).collect();
            let b: Vec<f64> = (0..n).map(|i| (2 * i + 1) as f64).collect();
            let plain: f64 = a.iter().zip(&b).map(|(x, y)| x * y).sum();
            assert_eq!(dot(&a, &b), plain, "n = {n}");
            assert_eq!(
                dot(&a, &b[..n.saturating_sub(1)]),
                dot(&a[..n.saturating_sub(1)], &b)
            );
        }
    }

    /// A dense check: P^-1 from Woodbury times P is the identity on the free components.
    #[test]
    fn woodbury_inverts_the_block_diagonal_plus_the_nodal_term() {
        // Two elements sharing a face, nodes 0..5, node 4 with its x fixed.
        let p = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
        ];
        let tets = [[0u32, 1, 2, 3], [1, 2, 3, 4]];
        let grads = |t: [u32; 4]| {
            let x = t.map(|i| p[i as usize]);
            // dV/dx_a for V = (x1-x0).((x2-x0)x(x3-x0))/6, a quarter of each.
            let g1 = (x[2] - x[0]).cross(x[3] - x[0]) / 6.0;
            let g2 = (x[3] - x[0]).cross(x[1] - x[0]) / 6.0;
            let g3 = (x[1] - x[0]).cross(x[2] - x[0]) / 6.0;
            [-(g1 + g2 + g3), g1, g2, g3].map(|g| g * 0.25)
        };
        let qg: Vec<[DVec3; 4]> = tets.iter().map(|&t| grads(t)).collect();
        let weight = [3.0, 50.0, 7.0, 11.0, 400.0];
        let diag: Vec<DMat3> = (0..5)
            .map(|i| {
                let a = DVec3::new(1.0 + i as f64, 0.3, -0.2);
                DMat3::from_diagonal(DVec3::splat(2.0 + i as f64))
                    + DMat3::from_cols(a * 0.1, a * 0.05, a * 0.1).transpose()
                        * DMat3::from_cols(a * 0.1, a * 0.05, a * 0.1)
            })
            .collect();
        let mut mask = vec![DVec3::ONE; 5];
        mask[4] = DVec3::new(0.0, 1.0, 1.0);
        let mut pre = Pressure::default();
        pre.build(&tets, &qg, &weight, &diag, &mask).unwrap();

        // P x, dense: D x + sum_i c_i g_i (g_i . x), masked.
        let product = |x: &[DVec3]| {
            let mut y: Vec<DVec3> = (0..5).map(|k| diag[k] * x[k]).collect();
            for i in 0..5 {
                let mut g = [DVec3::ZERO; 5];
                for (t, q) in tets.iter().zip(&qg) {
                    if t.contains(&(i as u32)) {
                        for a in 0..4 {
                            g[t[a] as usize] += q[a];
                        }
                    }
                }
                let dot: f64 = g.iter().zip(x).map(|(g, x)| g.dot(*x)).sum();
                for k in 0..5 {
                    y[k] += g[k] * (weight[i] * dot);
                }
            }
            y.iter()
                .zip(&mask)
                .map(|(y, m)| *y * *m)
                .collect::<Vec<_>>()
        };
        for k in 0..5 {
            for c in 0..3 {
                if mask[k][c] == 0.0 {
                    continue;
                }
                let mut e = vec![DVec3::ZERO; 5];
                e[k][c] = 1.0;
                let mut z = vec![DVec3::ZERO; 5];
                pre.apply(&product(&e), &mut z, &mask);
                for (j, z) in z.iter().enumerate() {
                    let err = (*z - e[j]).abs().max_element();
                    assert!(err < 1e-9, "P^-1 P e_({k},{c}) off by {err} at node {j}");
                }
            }
        }
    }
}
