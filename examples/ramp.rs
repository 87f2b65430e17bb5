use softgrip::quasi_static::RestTolerance;
use softgrip::{Scene, Simulation};
fn main() {
    let args: Vec<String> = std::env::args().collect();
    let edge: f64 = args[1].parse().unwrap();
    let model = args[2].replace(';', "\n");
    let text = format!(
        r#"
[object]
shape = "cuboid"
size = [0.05, 0.05, 0.02]
edge_length = {edge}
[model]
{model}
[[finger]]
radius = 0.015
position = [0.0, 0.0, 0.035]
force = [0.0, 0.0, -1.0]
"#
    );
    let scene = Scene::from_toml_str(&text, "ramp").unwrap();
    let mut sim = Simulation::new(&scene).unwrap();
    for f in [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.73] {
        sim.set_load(0, f);
        let r = sim.settle(
            RestTolerance {
                speed: 1e-5,
                consecutive_steps: 20,
                max_seconds: 5.0,
            },
            |_| {},
        );
        let fs = sim.state.fingers[0];
        let inv = sim
            .model
            .tets
            .iter()
            .filter(|t| {
                let p = t.map(|i| sim.state.positions[i as usize]);
                softgrip::mesh::signed_volume(p[0], p[1], p[2], p[3]) <= 0.0
            })
            .count();
        println!(
            "F {f:5.2}: depth {:6.3} mm fz {:7.3} pen {:.3} mm vol {:.2e} inverted {inv} contacts {} {}",
            (0.035 - fs.position.z) * 1e3,
            fs.contact_force.z,
            fs.max_penetration * 1e3,
            sim.state.stats.volume_error,
            sim.state.contacts.len(),
            match r {
                Ok(r) => format!("rest in {} steps", r.steps),
                Err(e) => format!("{e}").chars().take(60).collect(),
            }
        );
    }
}
