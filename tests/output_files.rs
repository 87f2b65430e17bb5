//! `run --out`: the ParaView files and fingers.csv are written and consistent.

use softgrip::Simulation;
use softgrip::output::TrajectoryWriter;

#[test]
fn trajectory_files_are_complete() {
    let mut scene = softgrip::Scene::thesis();
    scene.object.edge_length = 0.005;
    let mut sim = Simulation::new(&scene).expect("sim");
    let dir = std::env::temp_dir().join(format!("softgrip-out-{}", std::process::id()));
    let mut w = TrajectoryWriter::new(&dir).expect("writer");
    w.frame(&sim.model, &sim.state).expect("frame");
    for _ in 0..3 {
        for _ in 0..10 {
            sim.step().expect("step");
        }
        w.frame(&sim.model, &sim.state).expect("frame");
    }
    let pvd = w.finish().expect("finish");
    let text = std::fs::read_to_string(&pvd).expect("pvd");
    assert_eq!(text.matches("<DataSet").count(), 4);
    let vtu = std::fs::read_to_string(dir.join("frame_00003.vtu")).expect("vtu");
    let header = format!(
        "NumberOfPoints=\"{}\" NumberOfCells=\"{}\"",
        sim.model.particle_count(),
        sim.model.tets.len()
    );
    assert!(vtu.contains(&header));
    for field in [
        "displacement",
        "velocity",
        "fixed",
        "volume_ratio",
        "connectivity",
        "offsets",
        "types",
    ] {
        assert!(
            vtu.contains(&format!("Name=\"{field}\"")),
            "missing {field}"
        );
    }
    let csv = std::fs::read_to_string(dir.join("fingers.csv")).expect("csv");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("time,finger,x,y,z,fx,fy,fz"));
    let last: Vec<f64> = lines
        .last()
        .expect("rows")
        .split(',')
        .map(|v| v.parse().expect("number"))
        .collect();
    assert_eq!(last.len(), 8);
    assert!((last[4] - sim.state.fingers[0].position.z).abs() < 1e-12);
    std::fs::remove_dir_all(&dir).ok();
}
