//! Acceptance 1: a single spring and mass against the analytic oscillator and
//! against implicit Euler's known amplification factor (thesis eq. 41-43).

use glam::DVec3;
use softgrip_core::Model;
use softgrip_core::Simulation;

const MASS: f64 = 0.02;
const STIFFNESS: f64 = 50.0;
const LENGTH: f64 = 0.01;

/// Particle 0 pinned at the origin, particle 1 on the x axis, stretched by `amplitude`.
fn oscillator(dt: f64, amplitude: f64) -> Simulation {
    let model = Model::from_particles(
        vec![DVec3::ZERO, DVec3::new(LENGTH, 0.0, 0.0)],
        vec![MASS, MASS],
        vec![true, false],
        &[(0, 1, STIFFNESS, 0.0)],
        DVec3::ZERO,
        dt,
    );
    let mut sim = Simulation::from_model(model);
    sim.state.positions[1].x += amplitude;
    sim
}

#[test]
fn undamped_period_matches_two_pi_sqrt_m_over_k() {
    let period = 2.0 * std::f64::consts::PI * (MASS / STIFFNESS).sqrt();
    let dt = period / 2000.0;
    let mut sim = oscillator(dt, 1e-4);
    // Times of downward zero crossings of the displacement, interpolated.
    let mut crossings = Vec::new();
    let mut prev = sim.state.positions[1].x - LENGTH;
    while crossings.len() < 4 {
        sim.step().expect("step");
        let now = sim.state.positions[1].x - LENGTH;
        if prev > 0.0 && now <= 0.0 {
            let frac = prev / (prev - now);
            crossings.push(sim.state.time - dt + frac * dt);
        }
        prev = now;
    }
    let measured = (crossings[3] - crossings[0]) / 3.0;
    let rel = (measured - period).abs() / period;
    assert!(
        rel < 0.01,
        "period {measured} vs {period} (relative error {rel})"
    );
}

#[test]
fn implicit_euler_decays_by_its_known_factor() {
    // For x'' = -w^2 x, one implicit Euler step maps E = w^2 x^2 + v^2 to
    // E / (1 + (w dt)^2) exactly. Alg. 5's `v += dv * dt` would not.
    let omega = (STIFFNESS / MASS).sqrt();
    let dt = 2.0 * std::f64::consts::PI / omega / 20.0;
    let mut sim = oscillator(dt, 1e-4);
    let energy = |s: &Simulation| {
        let x = s.state.positions[1].x - LENGTH;
        let v = s.state.velocities[1].x;
        omega * omega * x * x + v * v
    };
    let e0 = energy(&sim);
    let steps = 40;
    for _ in 0..steps {
        sim.step().expect("step");
    }
    let expected = e0 / (1.0 + (omega * dt).powi(2)).powi(steps);
    let measured = energy(&sim);
    assert!(
        (measured - expected).abs() < 1e-9 * e0,
        "energy ratio {} vs implicit Euler's {}",
        measured / e0,
        expected / e0
    );
    // And it did decay: the numerical damping is real, not zero.
    assert!(measured < 0.5 * e0);
}
