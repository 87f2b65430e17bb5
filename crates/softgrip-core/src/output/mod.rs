//! Writing results: ParaView files (a `.vtu` per frame for the object and
//! one per finger, and a `.pvd` series), the deformed surface (`.stl` or
//! `.obj`, optional), the fingers' track and the per-step solver record as CSV.

pub mod finger;
pub mod surface;
pub mod vtu;

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use crate::model::Model;
use crate::state::State;

/// A result file that could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}: {source}. Check that the folder exists and is writable.")]
pub struct OutputError {
    /// The file (or folder) being written.
    pub path: PathBuf,
    /// The operating system's error.
    pub source: std::io::Error,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError {
        path: path.to_path_buf(),
        source,
    }
}

/// Writes a trajectory as it is produced.
pub struct TrajectoryWriter {
    dir: PathBuf,
    /// Each frame's time and files: the object's, then each finger's.
    frames: Vec<(f64, Vec<String>)>,
    /// Also write the deformed surface of every frame in this format.
    pub surface: Option<surface::SurfaceFormat>,
    /// How the `.vtu` files' arrays are written (compressed binary unless
    /// ASCII is asked for).
    pub encoding: vtu::Encoding,
    fingers_csv: String,
    steps_csv: String,
}

/// Header of `steps.csv`: one row per step.
pub const STEPS_HEADER: &str = "time,step,cg_iterations,cg_residual,energy,kinetic_energy,volume_error,limit_violation,projection_sweeps,contacts,max_speed";

impl TrajectoryWriter {
    /// A writer into `dir`, created if missing; no file is written yet.
    pub fn new(dir: &Path) -> Result<TrajectoryWriter, OutputError> {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
        Ok(TrajectoryWriter {
            dir: dir.to_path_buf(),
            frames: Vec::new(),
            surface: None,
            encoding: vtu::Encoding::default(),
            fingers_csv: String::from("time,finger,x,y,z,fx,fy,fz\n"),
            steps_csv: format!("{STEPS_HEADER}\n"),
        })
    }

    /// Appends the step's solver record (call after every step).
    pub fn step(&mut self, state: &State) {
        let s = &state.stats;
        let _ = writeln!(
            self.steps_csv,
            "{},{},{},{:e},{:e},{:e},{:e},{:e},{},{},{:e}",
            time_text(state.time),
            state.step,
            s.cg_iterations,
            s.cg_residual,
            s.energy,
            s.kinetic_energy,
            s.volume_error,
            s.limit_violation,
            s.projection_sweeps,
            s.contacts,
            s.max_speed
        );
    }

    /// Writes `frame_NNNNN.vtu`, each finger's `fingerK_NNNNN.vtu` (K from
    /// 1) and appends the fingers' rows.
    pub fn frame(&mut self, model: &Model, state: &State) -> Result<(), OutputError> {
        let index = self.frames.len();
        let mut files = Vec::with_capacity(1 + state.fingers.len());
        let name = format!("frame_{index:05}.vtu");
        let path = self.dir.join(&name);
        std::fs::write(&path, vtu::to_vtu(model, state, self.encoding)).map_err(io_err(&path))?;
        files.push(name);
        for k in 0..state.fingers.len() {
            let name = format!("finger{}_{index:05}.vtu", k + 1);
            let path = self.dir.join(&name);
            std::fs::write(&path, vtu::finger_to_vtu(model, state, k, self.encoding))
                .map_err(io_err(&path))?;
            files.push(name);
        }
        if let Some(format) = self.surface {
            let path = self.dir.join(format!(
                "surface_{:05}.{}",
                self.frames.len(),
                format.extension()
            ));
            std::fs::write(&path, format.write(model, state)).map_err(io_err(&path))?;
        }
        self.frames.push((state.time, files));
        for (k, f) in state.fingers.iter().enumerate() {
            let p = f.position;
            let c = f.contact_force;
            let _ = writeln!(
                self.fingers_csv,
                "{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
                time_text(state.time),
                k + 1,
                p.x,
                p.y,
                p.z,
                c.x,
                c.y,
                c.z
            );
        }
        Ok(())
    }

    /// Writes `trajectory.pvd` (each frame's object as part 0, finger K as
    /// part K: ParaView makes each part a block), `fingers.csv` and `steps.csv`.
    pub fn finish(self) -> Result<PathBuf, OutputError> {
        let pvd = self.dir.join("trajectory.pvd");
        let mut text = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for (t, files) in &self.frames {
            for (part, name) in files.iter().enumerate() {
                let _ = writeln!(
                    text,
                    "    <DataSet timestep=\"{}\" group=\"\" part=\"{part}\" file=\"{name}\"/>",
                    time_text(*t)
                );
            }
        }
        text.push_str("  </Collection>\n</VTKFile>\n");
        std::fs::write(&pvd, text).map_err(io_err(&pvd))?;
        let csv = self.dir.join("fingers.csv");
        let mut file = std::fs::File::create(&csv).map_err(io_err(&csv))?;
        file.write_all(self.fingers_csv.as_bytes())
            .map_err(io_err(&csv))?;
        let steps = self.dir.join("steps.csv");
        std::fs::write(&steps, &self.steps_csv).map_err(io_err(&steps))?;
        Ok(pvd)
    }
}

/// A simulated time as a person writes it: the sum of steps rounded to 12 significant digits
/// (0.05, not 0.05000000000000004).
pub fn time_text(t: f64) -> String {
    let rounded: f64 = format!("{t:.11e}").parse().unwrap_or(t);
    format!("{rounded}")
}
