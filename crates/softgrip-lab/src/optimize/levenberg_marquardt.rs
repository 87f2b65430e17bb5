//! Bounded Levenberg-Marquardt on the unit box for a least-squares cost,
//! with a forward-difference Jacobian and two damping factors tried at once.

use super::linalg::invert;
use super::types::{Minimum, Tolerances};

/// A batch of points in, their residual vectors out (`None`: failed).
pub type ResidualBatch<'a> = dyn FnMut(&[Vec<f64>]) -> Vec<Option<Vec<f64>>> + 'a;

/// Bounded Levenberg-Marquardt on the unit box for a least-squares cost:
/// `f` maps a batch of points to their residual vectors (`None` where the
/// simulation failed); the cost is the sum of squares. The Jacobian comes
/// from forward differences of `jacobian_step` (stepped inward at a
/// bound), and each iteration tries two damping factors at once (a batch
/// of two runs on two cores costs one). Stops when a step gains less than
/// `f_tolerance` of the cost, moves less than `x_tolerance`, or the
/// `budget` of new evaluations is spent.
pub fn levenberg_marquardt(
    f: &mut ResidualBatch,
    x0: &[f64],
    r0: Vec<f64>,
    budget: usize,
    options: impl Into<Tolerances>,
    jacobian_step: f64,
) -> Minimum {
    levenberg_marquardt_with(f, &mut |_| None, x0, r0, budget, options, jacobian_step)
}

/// The Jacobian's columns `dr/dx_i` at a point, each as long as the residual, from one run
/// (`None`: not to be had there; finite differences instead).
pub type JacobianAt<'a> = dyn FnMut(&[f64]) -> Option<Vec<Vec<f64>>> + 'a;

/// [`levenberg_marquardt`] with the Jacobian from `jacobian` where it gives one (one evaluation,
/// however many parameters), from forward differences elsewhere.
pub fn levenberg_marquardt_with(
    f: &mut ResidualBatch,
    jacobian: &mut JacobianAt,
    x0: &[f64],
    r0: Vec<f64>,
    budget: usize,
    options: impl Into<Tolerances>,
    jacobian_step: f64,
) -> Minimum {
    let options = options.into();
    let n = x0.len();
    let fx = cost(&r0);
    let mut s = State {
        x: x0.to_vec(),
        r: r0,
        fx,
        evaluations: 0,
        lambda: 1e-2,
        converged: false,
    };
    while s.evaluations + n + 2 <= budget {
        let jac = jacobian_at(f, jacobian, &s, jacobian_step);
        s.evaluations += jac.evaluations;
        let system = NormalEquations::new(&jac.columns, &s.r, n);
        let improved = damped_steps(f, &system, &mut s, budget, &options);
        if !improved || s.converged {
            s.converged = s.converged || !improved;
            break;
        }
    }
    Minimum {
        x: s.x,
        f: s.fx,
        evaluations: s.evaluations,
        converged: s.converged,
        stalled: false,
    }
}

/// The least-squares cost: the residuals' sum of squares.
fn cost(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum::<f64>()
}

/// Where the search stands.
struct State {
    /// The point, in the unit box.
    x: Vec<f64>,
    /// Its residuals.
    r: Vec<f64>,
    /// Its cost.
    fx: f64,
    /// New evaluations spent.
    evaluations: usize,
    /// The damping factor tried first.
    lambda: f64,
    /// Whether the search has converged.
    converged: bool,
}

/// The Jacobian at a point, and the evaluations it took.
struct Jacobian {
    /// Its columns `dr/dx_i`, each as long as the residual.
    columns: Vec<Vec<f64>>,
    /// Evaluations spent on it.
    evaluations: usize,
}

/// The Jacobian at `s.x`: from `jacobian` where it gives one of the right shape, else by forward
/// differences of `jacobian_step` (stepped inward at a bound).
fn jacobian_at(
    f: &mut ResidualBatch,
    jacobian: &mut JacobianAt,
    s: &State,
    jacobian_step: f64,
) -> Jacobian {
    let (x, r) = (&s.x, &s.r);
    let n = x.len();
    let analytic = jacobian(x).filter(|c| c.len() == n && c.iter().all(|c| c.len() == r.len()));
    if let Some(columns) = analytic {
        return Jacobian {
            columns,
            evaluations: 1,
        };
    }
    // Jacobian, column by column.
    let steps: Vec<f64> = x
        .iter()
        .map(|&v| {
            if v + jacobian_step <= 1.0 {
                jacobian_step
            } else {
                -jacobian_step
            }
        })
        .collect();
    let probes: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            let mut p = x.clone();
            p[i] += steps[i];
            p
        })
        .collect();
    let columns = f(&probes);
    let mut jac: Vec<Vec<f64>> = Vec::with_capacity(n);
    for (i, c) in columns.into_iter().enumerate() {
        match c {
            Some(c) if c.len() == r.len() => {
                jac.push(c.iter().zip(r).map(|(a, b)| (a - b) / steps[i]).collect())
            }
            _ => jac.push(vec![0.0; r.len()]),
        }
    }
    Jacobian {
        columns: jac,
        evaluations: n,
    }
}

/// The normal equations `JᵀJ d = -Jᵀr` of one iteration, scaled to their largest diagonal.
struct NormalEquations {
    /// `JᵀJ`.
    jtj: Vec<Vec<f64>>,
    /// `Jᵀr`.
    jtr: Vec<f64>,
    /// The largest diagonal of `JᵀJ`.
    scale: f64,
    /// The parameters held for this step (a zero column).
    inert: Vec<bool>,
}

impl NormalEquations {
    /// The normal equations of the Jacobian's `n` columns `jac` at residuals `r`.
    fn new(jac: &[Vec<f64>], r: &[f64], n: usize) -> Self {
        let jtj: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| jac[i].iter().zip(&jac[j]).map(|(a, b)| a * b).sum())
                    .collect()
            })
            .collect();
        let jtr: Vec<f64> = (0..n)
            .map(|i| jac[i].iter().zip(r).map(|(a, b)| a * b).sum())
            .collect();
        // A parameter that does nothing where it stands (a relaxation
        // time while the relaxing share is 0) has a zero column: it is
        // held for this step instead of making the system singular, and
        // the others move. The system is scaled to its largest diagonal.
        let scale = (0..n).map(|i| jtj[i][i]).fold(0.0, f64::max);
        let inert: Vec<bool> = (0..n).map(|i| jtj[i][i] <= 1e-12 * scale).collect();
        NormalEquations {
            jtj,
            jtr,
            scale,
            inert,
        }
    }

    /// The point the step from `x` with damping `lambda` reaches, clamped to the unit box;
    /// `None` where the system is empty or singular.
    fn step_for(&self, x: &[f64], lambda: f64) -> Option<Vec<f64>> {
        let (jtj, jtr, scale, inert) = (&self.jtj, &self.jtr, self.scale, &self.inert);
        let n = jtr.len();
        if scale <= 0.0 || !scale.is_finite() {
            return None;
        }
        let a: Vec<Vec<f64>> = (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| match (inert[i] || inert[j], i == j) {
                        (true, true) => 1.0,
                        (true, false) => 0.0,
                        (false, true) => jtj[i][i] / scale * (1.0 + lambda),
                        (false, false) => jtj[i][j] / scale,
                    })
                    .collect()
            })
            .collect();
        let inv = invert(a)?;
        Some(
            (0..n)
                .map(|i| {
                    let d: f64 = (0..n)
                        .filter(|&j| !inert[j])
                        .map(|j| -inv[i][j] * jtr[j] / scale)
                        .sum();
                    (x[i] + d).clamp(0.0, 1.0)
                })
                .collect(),
        )
    }
}

/// Up to six tries of two damping factors at once from `s`, until one gains (then `s` moves
/// there): whether one did. Sets `s.converged` where the step is too small to be worth a run or
/// the gain or move under the tolerances.
fn damped_steps(
    f: &mut ResidualBatch,
    system: &NormalEquations,
    s: &mut State,
    budget: usize,
    options: &Tolerances,
) -> bool {
    let mut improved = false;
    for _ in 0..6 {
        if s.evaluations + 2 > budget {
            break;
        }
        let lambdas = [s.lambda, s.lambda * 10.0];
        let trials: Vec<Vec<f64>> = lambdas
            .iter()
            .filter_map(|&l| system.step_for(&s.x, l))
            .collect();
        if trials.is_empty() {
            break;
        }
        // Steps within the tolerance are not worth a run: where the
        // model says to move less than `x_tolerance`, this is the
        // minimum (a step that small would end the search anyway).
        let moves = |t: &Vec<f64>| {
            t.iter()
                .zip(&s.x)
                .any(|(a, b)| (a - b).abs() > options.x_tolerance)
        };
        if !trials.iter().any(moves) {
            s.converged = true;
            break;
        }
        let results = f(&trials);
        s.evaluations += trials.len();
        let best = trials
            .iter()
            .zip(results)
            .enumerate()
            .filter_map(|(k, (t, res))| res.map(|res| (k, t.clone(), cost(&res), res)))
            .min_by(|a, b| a.2.total_cmp(&b.2));
        match best {
            Some((k, t, c, res)) if c < s.fx => {
                let moved = t
                    .iter()
                    .zip(&s.x)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                let gained = s.fx - c;
                (s.x, s.r, s.fx) = (t, res, c);
                s.lambda = if k == 0 {
                    s.lambda / 5.0
                } else {
                    s.lambda * 2.0
                };
                s.lambda = s.lambda.max(1e-7);
                improved = true;
                if gained <= options.f_tolerance * s.fx || moved <= options.x_tolerance {
                    s.converged = true;
                }
                break;
            }
            _ => s.lambda *= 100.0,
        }
    }
    improved
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tolerances(x_tolerance: f64, f_tolerance: f64) -> Tolerances {
        Tolerances {
            x_tolerance,
            f_tolerance,
            stall: 20,
        }
    }

    /// Noise-free data from `model` at `truth`, fitted back from `x0` with
    /// tight tolerances and a fine Jacobian step.
    fn fit_back(
        model: &dyn Fn(&[f64]) -> Vec<f64>,
        truth: &[f64],
        x0: &[f64],
        budget: usize,
    ) -> Minimum {
        let data = model(truth);
        let mut f = |points: &[Vec<f64>]| -> Vec<Option<Vec<f64>>> {
            points
                .iter()
                .map(|u| Some(model(u).iter().zip(&data).map(|(m, d)| m - d).collect()))
                .collect()
        };
        let r0 = f(&[x0.to_vec()]).remove(0).unwrap_or_default();
        levenberg_marquardt(&mut f, x0, r0, budget, tolerances(1e-9, 1e-12), 1e-6)
    }

    /// A model curve y = a (1 - exp(-b t)) with a, b mapped from the unit
    /// box; noise-free data from known values are fitted back to them.
    #[test]
    fn levenberg_marquardt_recovers_an_exponential_rise() {
        let ts: Vec<f64> = (0..20).map(|k| 0.1 * k as f64).collect();
        let model = |u: &[f64]| -> Vec<f64> {
            let (a, b) = (1.0 + 4.0 * u[0], 0.5 + 5.0 * u[1]);
            ts.iter().map(|t| a * (1.0 - (-b * t).exp())).collect()
        };
        let m = fit_back(&model, &[0.3, 0.6], &[0.8, 0.1], 200);
        assert!((m.x[0] - 0.3).abs() < 1e-4, "{:?}", m.x);
        assert!((m.x[1] - 0.6).abs() < 1e-4, "{:?}", m.x);
        assert!(m.evaluations <= 200);
    }

    /// With the exact Jacobian given (one evaluation for both columns), the exponential rise is
    /// fitted back as with differences, in fewer evaluations; a Jacobian that is not to be had
    /// falls back to differences.
    #[test]
    fn an_analytic_jacobian_fits_back_in_fewer_evaluations() {
        let ts: Vec<f64> = (0..20).map(|k| 0.1 * k as f64).collect();
        let ab = |u: &[f64]| (1.0 + 4.0 * u[0], 0.5 + 5.0 * u[1]);
        let model = |u: &[f64]| -> Vec<f64> {
            let (a, b) = ab(u);
            ts.iter().map(|t| a * (1.0 - (-b * t).exp())).collect()
        };
        let data = model(&[0.3, 0.6]);
        let mut f = |points: &[Vec<f64>]| -> Vec<Option<Vec<f64>>> {
            points
                .iter()
                .map(|u| Some(model(u).iter().zip(&data).map(|(m, d)| m - d).collect()))
                .collect()
        };
        let mut exact = |u: &[f64]| -> Option<Vec<Vec<f64>>> {
            let (a, b) = ab(u);
            let da: Vec<f64> = ts.iter().map(|t| 4.0 * (1.0 - (-b * t).exp())).collect();
            let db: Vec<f64> = ts.iter().map(|t| 5.0 * a * t * (-b * t).exp()).collect();
            Some(vec![da, db])
        };
        let x0 = [0.8, 0.1];
        let r0 = f(&[x0.to_vec()]).remove(0).unwrap_or_default();
        let o = tolerances(1e-9, 1e-12);
        let with = levenberg_marquardt_with(&mut f, &mut exact, &x0, r0.clone(), 200, o, 1e-6);
        let without = levenberg_marquardt(&mut f, &x0, r0.clone(), 200, o, 1e-6);
        for m in [&with, &without] {
            assert!(
                (m.x[0] - 0.3).abs() < 1e-4 && (m.x[1] - 0.6).abs() < 1e-4,
                "{:?}",
                m.x
            );
        }
        assert!(
            with.evaluations < without.evaluations,
            "{} {}",
            with.evaluations,
            without.evaluations
        );
        let mut none = |_: &[f64]| -> Option<Vec<Vec<f64>>> { None };
        let fallback = levenberg_marquardt_with(&mut f, &mut none, &x0, r0, 200, o, 1e-6);
        assert_eq!(fallback.x, without.x);
        assert_eq!(fallback.evaluations, without.evaluations);
    }

    /// Started at the minimum of a noisy fit (the residual does not
    /// vanish), the search spends the Jacobian and stops: the steps it
    /// would try are within the tolerance, and are not run. Started away
    /// from it, it gets there.
    #[test]
    fn levenberg_marquardt_does_not_run_steps_within_the_tolerance() {
        let ts: Vec<f64> = (0..20).map(|k| 0.1 * k as f64).collect();
        // A straight line fitted to a sine: a minimum with a residual.
        let data: Vec<f64> = ts.iter().map(|t| (3.0 * t).sin()).collect();
        let model = |u: &[f64]| -> Vec<f64> {
            let (a, b) = (-2.0 + 4.0 * u[0], -2.0 + 4.0 * u[1]);
            ts.iter().map(|t| a + b * t).collect()
        };
        // The least-squares line, in closed form.
        let n = ts.len() as f64;
        let (st, sy) = (ts.iter().sum::<f64>(), data.iter().sum::<f64>());
        let stt = ts.iter().map(|t| t * t).sum::<f64>();
        let sty = ts.iter().zip(&data).map(|(t, y)| t * y).sum::<f64>();
        let b = (n * sty - st * sy) / (n * stt - st * st);
        let a = (sy - b * st) / n;
        let best = [(a + 2.0) / 4.0, (b + 2.0) / 4.0];
        let runs = std::cell::Cell::new(0usize);
        let mut f = |points: &[Vec<f64>]| -> Vec<Option<Vec<f64>>> {
            runs.set(runs.get() + points.len());
            points
                .iter()
                .map(|u| Some(model(u).iter().zip(&data).map(|(m, d)| m - d).collect()))
                .collect()
        };
        let options = tolerances(2e-3, 1e-4);
        let r0 = f(&[best.to_vec()]).remove(0).unwrap_or_default();
        runs.set(0);
        let m = levenberg_marquardt(&mut f, &best, r0, 100, options, 1e-2);
        assert!(m.converged);
        assert_eq!(m.evaluations, 2, "the Jacobian's two columns only");
        assert_eq!(runs.get(), 2);
        assert_eq!(m.x, best.to_vec());
        let start = [0.9, 0.1];
        let r0 = f(&[start.to_vec()]).remove(0).unwrap_or_default();
        let m = levenberg_marquardt(&mut f, &start, r0, 100, options, 1e-2);
        assert!(m.converged);
        for (x, b) in m.x.iter().zip(best) {
            assert!((x - b).abs() < 2e-3, "{:?} against {best:?}", m.x);
        }
    }

    /// A parameter with no effect at the start (the time constant of an
    /// amplitude that starts at 0) neither stalls the search nor stops
    /// the other: the amplitude moves first, then the time constant.
    #[test]
    fn levenberg_marquardt_moves_past_a_parameter_that_starts_inert() {
        let ts: Vec<f64> = (1..30).map(|k| 0.1 * k as f64).collect();
        let model = |u: &[f64]| -> Vec<f64> {
            let (a, tau) = (2.0 * u[0], 0.2 + 2.0 * u[1]);
            ts.iter().map(|t| a * (-t / tau).exp()).collect()
        };
        let m = fit_back(&model, &[0.6, 0.3], &[0.0, 0.5], 300);
        assert!((m.x[0] - 0.6).abs() < 1e-3, "{:?}", m.x);
        assert!((m.x[1] - 0.3).abs() < 1e-3, "{:?}", m.x);
    }

    /// The optimum outside the box: the search ends on the bound.
    #[test]
    fn levenberg_marquardt_stops_on_a_bound() {
        let mut f = |points: &[Vec<f64>]| -> Vec<Option<Vec<f64>>> {
            points
                .iter()
                .map(|u| Some(vec![u[0] - 1.5, 2.0 * (u[1] - 0.25)]))
                .collect()
        };
        let r0 = f(&[vec![0.5, 0.5]]).remove(0).unwrap_or_default();
        let m = levenberg_marquardt(&mut f, &[0.5, 0.5], r0, 100, tolerances(1e-3, 1e-5), 1e-4);
        assert!((m.x[0] - 1.0).abs() < 1e-9, "{:?}", m.x);
        assert!((m.x[1] - 0.25).abs() < 1e-3, "{:?}", m.x);
    }

    /// A quadratic least-squares cost (a linear model) with its minimum
    /// inside the box: one damped Gauss-Newton step lands next to it.
    #[test]
    fn levenberg_marquardt_solves_a_linear_least_squares_problem() {
        let m = fit_back(
            &|u: &[f64]| vec![u[0] + u[1], u[0] - u[1], 2.0 * u[1]],
            &[0.7, 0.2],
            &[0.1, 0.9],
            100,
        );
        assert!((m.x[0] - 0.7).abs() < 1e-6, "{:?}", m.x);
        assert!((m.x[1] - 0.2).abs() < 1e-6, "{:?}", m.x);
    }
}
