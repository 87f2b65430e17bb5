//! A space-filling design of the unit box.

/// Point `k` (from 1) of the Halton sequence in `dims` dimensions: a
/// deterministic, evenly spread design in the unit box.
pub fn halton(k: usize, dims: usize) -> Vec<f64> {
    const PRIMES: [usize; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];
    (0..dims)
        .map(|d| {
            let base = PRIMES[d % PRIMES.len()];
            let (mut f, mut r, mut i) = (1.0, 0.0, k);
            while i > 0 {
                f /= base as f64;
                r += f * (i % base) as f64;
                i /= base;
            }
            r
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_design_is_spread_over_the_box() {
        let points: Vec<Vec<f64>> = (1..=32).map(|k| halton(k, 4)).collect();
        for p in &points {
            assert!(p.iter().all(|x| *x > 0.0 && *x < 1.0), "{p:?}");
        }
        // Every half of every axis holds between a third and two thirds.
        for d in 0..4 {
            let low = points.iter().filter(|p| p[d] < 0.5).count();
            assert!((11..=21).contains(&low), "axis {d}: {low}");
        }
        assert_eq!(halton(1, 2), [0.5, 1.0 / 3.0]);
    }
}
