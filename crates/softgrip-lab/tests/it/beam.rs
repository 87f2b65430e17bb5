//! The real Dragon Skin beam (`assets/recordings/beam_ds10`) with one material: neo-Hookean
//! elements (nodal pressures), one E and one Rayleigh damping shared by the recordings, fitted
//! to the three at once (`softgrip fit`, docs/results/accuracy.md). Each recording's first
//! frequency and decay rate, both measured by `ringing` from the recording and from the
//! simulation on the same marker axis, agree within 5 % and 25 %. The slow tier checks the
//! unloaded beam (the shortest recording); docs/results/accuracy.md gives all three.

use softgrip_core::scene::Elasticity;
use softgrip_lab::recording::Recording;
use softgrip_lab::replay::{ReplayOptions, replay};
use softgrip_lab::ringing;

use crate::support::asset;

/// The shared material (docs/results/accuracy.md, "The real beam").
const YOUNG_MODULUS: f64 = 264e3;
const RAYLEIGH_MASS: f64 = 2.3;
const RAYLEIGH_STIFFNESS: f64 = 2.8e-4;

fn rings_as_recorded(name: &str) {
    let path = asset(&format!(
        "assets/recordings/beam_ds10/{name}/recording.toml"
    ));
    let recording = Recording::load(&path).expect("the shipped recording loads");
    let mut scene = recording.scene.clone();
    scene.object.young_modulus = YOUNG_MODULUS;
    scene.model.elasticity = Elasticity::NeoHookean;
    scene.model.bulk_pressure = softgrip_core::scene::BulkPressure::Nodal;
    // The springs' dampers are the lattice's; the continuum's damping is Rayleigh's.
    scene.model.damping_ratio = 0.0;
    scene.model.rayleigh_mass = RAYLEIGH_MASS;
    scene.model.rayleigh_stiffness = RAYLEIGH_STIFFNESS;
    let replay = replay(&recording, &scene, ReplayOptions::default(), |_| {}).expect("replay");
    let compared = ringing::compare(&recording, &replay.residuals).expect("a time series");
    let recorded = compared.recorded.expect("the recording rings");
    let simulated = compared.simulated.expect("the simulation rings");
    let (f, s) = (
        simulated.frequency_hz / recorded.frequency_hz - 1.0,
        simulated.decay_rate / recorded.decay_rate - 1.0,
    );
    eprintln!(
        "{name}: f {:.3} Hz recorded, {:.3} simulated ({:+.1} %); decay {:.3} 1/s recorded, {:.3} simulated ({:+.1} %); NRMSE {:.4}",
        recorded.frequency_hz,
        simulated.frequency_hz,
        100.0 * f,
        recorded.decay_rate,
        simulated.decay_rate,
        100.0 * s,
        replay.errors.nrmse
    );
    assert!(
        f.abs() < 0.05,
        "{name}: frequency off by {:.1} %",
        100.0 * f
    );
    assert!(
        s.abs() < 0.25,
        "{name}: decay rate off by {:.1} %",
        100.0 * s
    );
}

#[test]
#[ignore = "slow: a 1.6 s beam simulation"]
fn the_unloaded_beam_rings_as_recorded() {
    rings_as_recorded("gravity_a");
}
