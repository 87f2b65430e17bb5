//! Bounded Nelder-Mead on the unit box, and [`minimize`], which restarts it
//! until a restart gains nothing. The coefficients are the dimension-adapted
//! ones of Gao and Han (2012).

use super::types::{Minimum, Tolerances};

/// Nelder-Mead from `x0`, restarted from its best point with a fresh
/// simplex until a restart gains nothing: a simplex that collapsed (onto
/// a bound, or along a plateau) gets its dimensions back. `converged`:
/// the last run converged or stalled rather than running out of budget.
pub fn minimize(
    f: &mut dyn FnMut(&[Vec<f64>]) -> Vec<f64>,
    x0: &[f64],
    f0: f64,
    budget: usize,
    options: impl Into<Tolerances>,
) -> Minimum {
    let options = options.into();
    let mut best = Minimum {
        x: x0.to_vec(),
        f: f0,
        evaluations: 0,
        converged: false,
        stalled: false,
    };
    let mut step = 0.1;
    loop {
        let left = budget.saturating_sub(best.evaluations);
        if left == 0 {
            best.converged = false;
            break;
        }
        let r = nelder_mead(f, &best.x, best.f, step, left, options);
        best.evaluations += r.evaluations;
        let gained = best.f - r.f;
        if r.f <= best.f {
            (best.x, best.f) = (r.x, r.f);
        }
        best.converged = r.converged || r.stalled;
        best.stalled = r.stalled;
        if !best.converged || gained <= options.f_tolerance * best.f.abs() {
            break;
        }
        step = 0.05;
    }
    best
}

/// Bounded Nelder-Mead on the unit box: minimises `f` (given batches of
/// points, evaluated together) from `x0` (where `f0` is known), with a
/// first simplex of edge `step`, at most `budget` new evaluations.
pub fn nelder_mead(
    f: &mut dyn FnMut(&[Vec<f64>]) -> Vec<f64>,
    x0: &[f64],
    f0: f64,
    step: f64,
    budget: usize,
    options: impl Into<Tolerances>,
) -> Minimum {
    let options = options.into();
    let n = x0.len();
    let c = Coefficients::new(n);
    let mut simplex = first_simplex(x0, step);
    let mut values = vec![f0];
    values.extend(f(&simplex[1..]));
    let mut evaluations = n;
    let (mut converged, mut stalled) = (false, false);
    // The best value and the evaluation count when it last improved.
    let mut progress_at = (f64::INFINITY, 0);
    loop {
        sort_simplex(&mut simplex, &mut values);
        let size = simplex[1..]
            .iter()
            .flat_map(|x| x.iter().zip(&simplex[0]).map(|(a, b)| (a - b).abs()))
            .fold(0.0, f64::max);
        let spread = values[n] - values[0];
        let tolerance = options.f_tolerance * values[0].abs();
        if size <= options.x_tolerance && spread <= tolerance {
            converged = true;
            break;
        }
        if values[0] < progress_at.0 - tolerance {
            progress_at = (values[0], evaluations);
        }
        if evaluations - progress_at.1 >= options.stall * (n + 1) {
            stalled = true;
            break;
        }
        if evaluations >= budget {
            break;
        }
        evaluations += simplex_step(f, &mut simplex, &mut values, &c);
    }
    Minimum {
        x: simplex[0].clone(),
        f: values[0],
        evaluations,
        converged,
        stalled,
    }
}

/// The dimension-adapted coefficients of Gao and Han (2012).
struct Coefficients {
    /// The dimension, as a float.
    nf: f64,
    /// Reflection.
    reflect: f64,
    /// Expansion.
    expand: f64,
    /// Contraction.
    contract: f64,
    /// Shrinking.
    shrink: f64,
}

impl Coefficients {
    /// The coefficients in `n` dimensions.
    fn new(n: usize) -> Self {
        let nf = n as f64;
        let (reflect, expand) = (1.0, 1.0 + 2.0 / nf);
        let (contract, shrink) = (0.75 - 1.0 / (2.0 * nf), 1.0 - 1.0 / nf);
        Coefficients {
            nf,
            reflect,
            expand,
            contract,
            shrink,
        }
    }
}

/// `x` clamped to the unit box.
fn clamp(x: Vec<f64>) -> Vec<f64> {
    x.into_iter().map(|v| v.clamp(0.0, 1.0)).collect()
}

/// The point `a + t (b - a)`.
fn combine(a: &[f64], b: &[f64], t: f64) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x + t * (y - x)).collect()
}

/// The first simplex: `x0`, and `x0` moved by `step` along each axis (backwards where that
/// would leave the box).
fn first_simplex(x0: &[f64], step: f64) -> Vec<Vec<f64>> {
    let n = x0.len();
    let mut simplex: Vec<Vec<f64>> = vec![x0.to_vec()];
    for i in 0..n {
        let mut x = x0.to_vec();
        x[i] = if x[i] + step <= 1.0 {
            x[i] + step
        } else {
            x[i] - step
        };
        simplex.push(x);
    }
    simplex
}

/// The simplex's points and values sorted by value, best first (stable: ties keep their order).
fn sort_simplex(simplex: &mut Vec<Vec<f64>>, values: &mut Vec<f64>) {
    let n = simplex.len() - 1;
    let mut order: Vec<usize> = (0..=n).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    *simplex = order.iter().map(|&i| simplex[i].clone()).collect();
    *values = order.iter().map(|&i| values[i]).collect();
}

/// One step of a sorted simplex: its worst point reflected, expanded or contracted through the
/// centroid of the others, or else the whole simplex shrunk towards its best. The evaluations
/// it took.
fn simplex_step(
    f: &mut dyn FnMut(&[Vec<f64>]) -> Vec<f64>,
    simplex: &mut [Vec<f64>],
    values: &mut [f64],
    c: &Coefficients,
) -> usize {
    let n = simplex.len() - 1;
    let centroid: Vec<f64> = (0..n)
        .map(|k| simplex[..n].iter().map(|x| x[k]).sum::<f64>() / c.nf)
        .collect();
    let worst = simplex[n].clone();
    let xr = clamp(combine(&centroid, &worst, -c.reflect));
    let fr = f(std::slice::from_ref(&xr))[0];
    if fr < values[0] {
        let xe = clamp(combine(&centroid, &worst, -c.reflect * c.expand));
        let fe = f(std::slice::from_ref(&xe))[0];
        if fe < fr {
            (simplex[n], values[n]) = (xe, fe);
        } else {
            (simplex[n], values[n]) = (xr, fr);
        }
        return 2;
    }
    if fr < values[n - 1] {
        (simplex[n], values[n]) = (xr, fr);
        return 1;
    }
    let (xc, limit) = if fr < values[n] {
        (clamp(combine(&centroid, &xr, c.contract)), fr)
    } else {
        (clamp(combine(&centroid, &worst, c.contract)), values[n])
    };
    let fc = f(std::slice::from_ref(&xc))[0];
    if fc < limit {
        (simplex[n], values[n]) = (xc, fc);
        return 2;
    }
    let best = simplex[0].clone();
    for x in &mut simplex[1..] {
        *x = combine(&best, x, c.shrink);
    }
    let shrunk = f(&simplex[1..]);
    values[1..].copy_from_slice(&shrunk);
    2 + n
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options() -> Tolerances {
        Tolerances {
            x_tolerance: 1e-6,
            f_tolerance: 1e-12,
            stall: 20,
        }
    }

    #[test]
    fn nelder_mead_finds_the_rosenbrock_minimum_and_a_minimum_on_a_bound() {
        // Rosenbrock's valley on x, y in -2..2: minimum at (1, 1), u = 0.75.
        let rosenbrock = |u: &[f64]| {
            let (x, y) = (4.0 * u[0] - 2.0, 4.0 * u[1] - 2.0);
            (1.0 - x).powi(2) + 100.0 * (y - x * x).powi(2)
        };
        let mut calls = 0;
        let mut f = |points: &[Vec<f64>]| -> Vec<f64> {
            calls += points.len();
            points.iter().map(|u| rosenbrock(u)).collect()
        };
        let x0 = [0.2, 0.6];
        let f0 = rosenbrock(&x0);
        let m = nelder_mead(&mut f, &x0, f0, 0.1, 2000, options());
        assert!(m.converged, "{m:?}");
        assert!(
            (m.x[0] - 0.75).abs() < 1e-4 && (m.x[1] - 0.75).abs() < 1e-4,
            "{m:?}"
        );
        assert_eq!(m.evaluations, calls, "every evaluation counted");
        // A minimum outside the box in u0: the search stops on the bound.
        let bowl = |u: &[f64]| (u[0] + 0.5).powi(2) + (u[1] - 0.3).powi(2) + (u[2] - 0.9).powi(2);
        let mut g = |points: &[Vec<f64>]| -> Vec<f64> { points.iter().map(|u| bowl(u)).collect() };
        let x0 = [0.5, 0.5, 0.5];
        // (A simplex can collapse onto a bound face; the restarts of
        // `minimize` give it its dimensions back.)
        let m = minimize(&mut g, &x0, bowl(&x0), 2000, options());
        assert!(m.converged);
        assert!(m.x[0] == 0.0, "{m:?}");
        assert!(
            (m.x[1] - 0.3).abs() < 1e-4 && (m.x[2] - 0.9).abs() < 1e-4,
            "{m:?}"
        );
        // The budget is a hard limit.
        let m = minimize(&mut g, &x0, bowl(&x0), 10, options());
        assert!(!m.converged && m.evaluations <= 10 + 3, "{m:?}");
    }

    /// A quadratic bowl with its minimum inside the box, in four
    /// dimensions: found to the tolerance.
    #[test]
    fn minimize_finds_the_centre_of_a_quadratic_bowl() {
        let centre = [0.2, 0.4, 0.6, 0.8];
        let bowl = |u: &[f64]| -> f64 {
            u.iter()
                .zip(centre)
                .enumerate()
                .map(|(k, (x, c))| (k + 1) as f64 * (x - c).powi(2))
                .sum()
        };
        let mut f = |points: &[Vec<f64>]| -> Vec<f64> { points.iter().map(|u| bowl(u)).collect() };
        let x0 = [0.5; 4];
        let m = minimize(&mut f, &x0, bowl(&x0), 4000, options());
        assert!(m.converged, "{m:?}");
        for (x, c) in m.x.iter().zip(centre) {
            assert!((x - c).abs() < 1e-4, "{m:?}");
        }
    }
}
