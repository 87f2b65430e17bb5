//! `softgrip._softgrip`: the Rust half of the Python package (`python/softgrip` is the other).
//! Scenes, simulations and recordings are classes; compare, fit, sweep and diagnose return the
//! CLI's JSON as text, which the Python half turns into result objects, so both say the same
//! (`softgrip_lab::json`). Long work runs with the GIL released and stops on Ctrl-C
//! (`softgrip_core::cancel`). Errors are `SoftgripError`s with the CLI's messages.

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use softgrip_core::Simulation as CoreSimulation;
use softgrip_core::scene::Scene as CoreScene;
use softgrip_lab::recording::Recording as CoreRecording;

pyo3::create_exception!(
    softgrip,
    SoftgripError,
    PyException,
    "A softgrip error: bad input (a scene, recording or parameter; the message names it and says what to write) or a simulation that failed."
);

/// Any softgrip error as a Python exception with the CLI's message.
fn err(e: impl std::fmt::Display) -> PyErr {
    SoftgripError::new_err(e.to_string())
}

/// Runs `work` on its own thread with the GIL released, under a cancel token that Ctrl-C
/// sets (the interpreter's signal check runs on the calling thread every 50 ms while it
/// waits): long simulations stop with `KeyboardInterrupt`, as Python code would.
fn cancellable<R: Send>(py: Python<'_>, work: impl FnOnce() -> R + Send) -> PyResult<R> {
    use std::sync::Condvar;
    let token = softgrip_core::cancel::Cancel::new();
    let finished = (Mutex::new(false), Condvar::new());
    let mut interrupted: Option<PyErr> = None;
    let result = std::thread::scope(|s| {
        let (t, finished) = (token.clone(), &finished);
        let handle = s.spawn(move || {
            let r = softgrip_core::cancel::scope(Some(t), work);
            if let Ok(mut done) = finished.0.lock() {
                *done = true;
            }
            finished.1.notify_all();
            r
        });
        loop {
            let done = py.detach(|| {
                let Ok(guard) = finished.0.lock() else {
                    return true;
                };
                finished
                    .1
                    .wait_timeout_while(guard, std::time::Duration::from_millis(50), |d| !*d)
                    .map_or(true, |(d, _)| *d)
            });
            if done {
                break;
            }
            if interrupted.is_none()
                && let Err(e) = py.check_signals()
            {
                token.cancel();
                interrupted = Some(e);
            }
        }
        handle.join()
    });
    match (interrupted, result) {
        (Some(e), _) => Err(e),
        (None, Ok(r)) => Ok(r),
        (None, Err(_)) => Err(SoftgripError::new_err(
            "softgrip panicked: this is a bug, please report it with the input",
        )),
    }
}

/// An (n, 3) float64 array of points.
fn points<'py>(py: Python<'py>, v: &[glam::DVec3]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = v.iter().flat_map(|p| p.to_array()).collect();
    Array2::from_shape_vec((v.len(), 3), flat)
        .expect("n x 3")
        .into_pyarray(py)
}

/// An (n, k) uint32 array of indices.
fn indices<'py, const K: usize>(py: Python<'py>, v: &[[u32; K]]) -> Bound<'py, PyArray2<u32>> {
    let flat: Vec<u32> = v.iter().flatten().copied().collect();
    Array2::from_shape_vec((v.len(), K), flat)
        .expect("n x k")
        .into_pyarray(py)
}

/// A scene: the object, its model, the fingers and the support, as a scene file says them.
#[pyclass(module = "softgrip._softgrip", from_py_object)]
#[derive(Clone)]
pub struct Scene {
    inner: CoreScene,
}

#[pymethods]
impl Scene {
    /// The scene in a TOML file (relative mesh paths are relative to it).
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Scene> {
        CoreScene::load(&path)
            .map(|inner| Scene { inner })
            .map_err(err)
    }

    /// A scene from TOML text; `name` stands for the file in error messages.
    #[staticmethod]
    #[pyo3(signature = (text, name = "<string>"))]
    fn from_toml(text: &str, name: &str) -> PyResult<Scene> {
        CoreScene::from_toml_str(text, name)
            .map(|inner| Scene { inner })
            .map_err(err)
    }

    /// The built-in thesis scene (what `softgrip run` runs without a file).
    #[staticmethod]
    fn thesis() -> Scene {
        Scene {
            inner: CoreScene::thesis(),
        }
    }

    /// The scene as a TOML file writes it.
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// The parameters a scene has by name (`young_modulus`, `alpha`, `friction`, ...): the names
    /// `fit`, `sweep` and `scene[name]` take.
    #[staticmethod]
    fn parameters() -> Vec<&'static str> {
        softgrip_lab::params::PARAMS
            .iter()
            .map(|p| p.name)
            .collect()
    }

    /// A parameter's value; `None` for a limit that is off or a finger parameter without fingers.
    fn __getitem__(&self, name: &str) -> PyResult<Option<f64>> {
        softgrip_lab::params::get(&self.inner, name).map_err(err)
    }

    /// Sets a parameter, with the scene file's checks.
    fn __setitem__(&mut self, name: &str, value: f64) -> PyResult<()> {
        self.inner = softgrip_lab::params::set(&self.inner, name, value).map_err(err)?;
        Ok(())
    }

    fn copy(&self) -> Scene {
        self.clone()
    }

    fn __repr__(&self) -> String {
        let o = &self.inner.object;
        format!(
            "Scene(E={} Pa, edge_length={} m, {} finger(s))",
            o.young_modulus,
            o.edge_length,
            self.inner.fingers.len(),
        )
    }
}

/// A running simulation of a scene: step it, run it, bring it to rest or to equilibrium, and
/// read its state as numpy arrays (copies: the state moves on under them).
#[pyclass(module = "softgrip._softgrip")]
pub struct Simulation {
    inner: Mutex<CoreSimulation>,
}

impl Simulation {
    /// The simulation, for one call (a panic in softgrip, a bug, would leave it poisoned).
    fn lock(&self) -> PyResult<std::sync::MutexGuard<'_, CoreSimulation>> {
        self.inner
            .lock()
            .map_err(|_| err("the simulation was left broken by an earlier error"))
    }

    fn with<R>(&self, f: impl FnOnce(&mut CoreSimulation) -> R) -> PyResult<R> {
        Ok(f(&mut *self.lock()?))
    }
}

#[pymethods]
impl Simulation {
    /// The scene's simulation; `threads` as `softgrip run` (0: as many as help).
    #[new]
    #[pyo3(signature = (scene, threads = 0))]
    fn new(py: Python<'_>, scene: &Scene, threads: usize) -> PyResult<Simulation> {
        let (mesh, warnings) = softgrip_core::Model::load_mesh(&scene.inner).map_err(err)?;
        let warn = py.import("warnings")?;
        for w in &warnings {
            warn.call_method1("warn", (w.to_string(),))?;
        }
        let mut sim = CoreSimulation::on_mesh(&scene.inner, mesh).map_err(err)?;
        if threads > 0 {
            sim.set_threads(threads);
        }
        Ok(Simulation {
            inner: Mutex::new(sim),
        })
    }

    /// `n` time steps of the scene's `dt`.
    #[pyo3(signature = (n = 1))]
    fn step(&self, py: Python<'_>, n: u64) -> PyResult<()> {
        let mut s = self.lock()?;
        let sim: &mut CoreSimulation = &mut s;
        cancellable(py, || {
            for _ in 0..n {
                // Ctrl-C (`cancellable`) ends the steps between two of them.
                if softgrip_core::cancel::requested() {
                    break;
                }
                sim.step().map_err(|e| e.to_string())?;
            }
            Ok::<_, String>(())
        })?
        .map_err(err)
    }

    /// Steps for `seconds` of simulated time; `callback(sim)` every `every` simulated seconds
    /// (default 0.01) if given. The GIL is released between callbacks.
    #[pyo3(signature = (seconds, callback = None, every = 0.01))]
    fn run(
        slf: &Bound<'_, Self>,
        py: Python<'_>,
        seconds: f64,
        callback: Option<Py<PyAny>>,
        every: f64,
    ) -> PyResult<()> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(err(format!(
                "run({seconds}): give a number of simulated seconds, 0 or more"
            )));
        }
        let this = slf.borrow();
        let dt = this.with(|s| s.model.dt)?;
        let steps = (seconds / dt).round() as u64;
        let chunk = match &callback {
            Some(_) if every > 0.0 => ((every / dt).round() as u64).max(1),
            Some(_) => {
                return Err(err(format!(
                    "every={every}: give the simulated seconds between callbacks, above 0"
                )));
            }
            None => steps.max(1),
        };
        let mut done = 0;
        while done < steps {
            let n = chunk.min(steps - done);
            this.step(py, n)?;
            done += n;
            if let Some(cb) = &callback {
                cb.call1(py, (slf,))?;
            }
        }
        Ok(())
    }

    /// Steps until at rest (every particle and finger slower than `speed` m/s for 20 steps),
    /// at most `max_seconds`; returns {"steps", "seconds", "max_speed"}.
    #[pyo3(signature = (speed = 1e-5, max_seconds = 20.0))]
    fn settle<'py>(
        &self,
        py: Python<'py>,
        speed: f64,
        max_seconds: f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let tol = softgrip_core::quasi_static::RestTolerance {
            speed,
            consecutive_steps: 20,
            max_seconds,
            give_up_after: None,
        };
        let mut s = self.lock()?;
        let sim: &mut CoreSimulation = &mut s;
        let r =
            cancellable(py, || sim.settle(tol, |_| {}).map_err(|e| e.to_string()))?.map_err(err)?;
        let d = PyDict::new(py);
        d.set_item("steps", r.steps)?;
        d.set_item("seconds", r.seconds)?;
        d.set_item("max_speed", r.max_speed)?;
        Ok(d)
    }

    /// The static equilibrium (Newton) with the first force-controlled finger's load set to
    /// `load` N along the scene's force direction (None: the present load), reached from the
    /// present one in load steps; returns {"iterations", "residual"}.
    #[pyo3(signature = (load = None))]
    fn equilibrium<'py>(&self, py: Python<'py>, load: Option<f64>) -> PyResult<Bound<'py, PyDict>> {
        let mut s = self.lock()?;
        let from: Vec<glam::DVec3> = s.state.fingers.iter().map(|f| f.applied_force).collect();
        if let Some(load) = load {
            if !load.is_finite() {
                return Err(err(format!("equilibrium(load={load}): give a load in N")));
            }
            let Some(k) = s.load_finger() else {
                return Err(err(
                    "the scene has no force-controlled finger to load; add a [[finger]] with control = \"force\"",
                ));
            };
            if s.model.fingers[k].load_direction == glam::DVec3::ZERO {
                return Err(err(format!(
                    "finger {} has force = [0, 0, 0], so the load has no direction; give it a force (e.g. [0, 0, -1]) and, for a pure load, mass = 0",
                    k + 1
                )));
            }
            s.set_load(k, load);
        }
        let sim: &mut CoreSimulation = &mut s;
        let r = cancellable(py, || {
            sim.equilibrium_from(&from, Default::default())
                .map_err(|e| e.to_string())
        })?
        .map_err(err)?;
        let d = PyDict::new(py);
        d.set_item("iterations", r.iterations)?;
        d.set_item("residual", r.residual)?;
        Ok(d)
    }

    /// Simulated time, s.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        self.with(|s| s.state.time)
    }

    /// Steps taken.
    #[getter]
    fn steps(&self) -> PyResult<u64> {
        self.with(|s| s.state.step)
    }

    /// The time step, s.
    #[getter]
    fn dt(&self) -> PyResult<f64> {
        self.with(|s| s.model.dt)
    }

    /// Particle positions, (n, 3) m.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.with(|s| points(py, &s.state.positions))
    }

    /// Particle velocities, (n, 3) m/s.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.with(|s| points(py, &s.state.velocities))
    }

    /// Rest positions, (n, 3) m.
    #[getter]
    fn rest_positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.with(|s| points(py, &s.model.rest_positions))
    }

    /// Particle masses, (n,) kg.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.with(|s| PyArray1::from_vec(py, s.model.mass.clone()))
    }

    /// Tetrahedra, (m, 4) particle indices.
    #[getter]
    fn tetrahedra<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        self.with(|s| indices(py, &s.model.tets))
    }

    /// Surface triangles, (k, 3) particle indices, outward.
    #[getter]
    fn surface<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u32>>> {
        self.with(|s| indices(py, &s.model.facets))
    }

    /// The fingers: {"position", "velocity", "applied_force", "contact_force"} as (f, 3)
    /// arrays (m, m/s, N, N) and "normal_force", "max_penetration" as (f,) arrays.
    #[getter]
    fn fingers<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        self.with(|s| -> PyResult<()> {
            let f = &s.state.fingers;
            let col = |g: &dyn Fn(&softgrip_core::state::FingerState) -> glam::DVec3| {
                points(py, &f.iter().map(g).collect::<Vec<_>>())
            };
            d.set_item("position", col(&|x| x.position))?;
            d.set_item("velocity", col(&|x| x.velocity))?;
            d.set_item("applied_force", col(&|x| x.applied_force))?;
            d.set_item("contact_force", col(&|x| x.contact_force))?;
            d.set_item(
                "normal_force",
                PyArray1::from_vec(py, f.iter().map(|x| x.normal_force).collect()),
            )?;
            d.set_item(
                "max_penetration",
                PyArray1::from_vec(py, f.iter().map(|x| x.max_penetration).collect()),
            )?;
            Ok(())
        })??;
        Ok(d)
    }

    /// The finger contacts of the last step: {"finger", "facet"} (c,) indices, "point" and
    /// "normal" (c, 3), "penetration" and "normal_force" (c,), "tangential_force" (c, 3).
    #[getter]
    fn contacts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        self.with(|s| -> PyResult<()> {
            let c = &s.state.contacts;
            d.set_item(
                "finger",
                PyArray1::from_vec(py, c.iter().map(|x| x.finger).collect()),
            )?;
            d.set_item(
                "facet",
                PyArray1::from_vec(py, c.iter().map(|x| x.facet).collect()),
            )?;
            d.set_item(
                "point",
                points(py, &c.iter().map(|x| x.point).collect::<Vec<_>>()),
            )?;
            d.set_item(
                "normal",
                points(py, &c.iter().map(|x| x.normal).collect::<Vec<_>>()),
            )?;
            d.set_item(
                "penetration",
                PyArray1::from_vec(py, c.iter().map(|x| x.penetration).collect()),
            )?;
            d.set_item(
                "normal_force",
                PyArray1::from_vec(py, c.iter().map(|x| x.normal_force).collect()),
            )?;
            d.set_item(
                "tangential_force",
                points(
                    py,
                    &c.iter().map(|x| x.tangential_force).collect::<Vec<_>>(),
                ),
            )?;
            Ok(())
        })??;
        Ok(d)
    }

    /// The last step's figures: CG iterations and residual, energies (J), volume error,
    /// spring-limit violation, contacts, largest speed (m/s).
    #[getter]
    fn stats<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let st = self.with(|s| s.state.stats)?;
        let d = PyDict::new(py);
        d.set_item("cg_iterations", st.cg_iterations)?;
        d.set_item("cg_residual", st.cg_residual)?;
        d.set_item("energy", st.energy)?;
        d.set_item("kinetic_energy", st.kinetic_energy)?;
        d.set_item("volume_error", st.volume_error)?;
        d.set_item("limit_violation", st.limit_violation)?;
        d.set_item("projection_sweeps", st.projection_sweeps)?;
        d.set_item("contacts", st.contacts)?;
        d.set_item("max_speed", st.max_speed)?;
        Ok(d)
    }

    fn __repr__(&self) -> PyResult<String> {
        self.with(|s| {
            format!(
                "Simulation({} particles, {} tetrahedra, t={} s, dt={} s)",
                s.model.particle_count(),
                s.model.tets.len(),
                s.state.time,
                s.model.dt
            )
        })
    }
}

/// A lab recording: its scene, markers and samples (`docs/recordings.md`).
#[pyclass(module = "softgrip._softgrip", frozen)]
pub struct Recording {
    inner: CoreRecording,
}

#[pymethods]
impl Recording {
    /// The recording file (recording.toml) with its scene and samples.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Recording> {
        CoreRecording::load(&path)
            .map(|inner| Recording { inner })
            .map_err(err)
    }

    /// The recording file's path.
    #[getter]
    fn path(&self) -> String {
        self.inner.source.display().to_string()
    }

    /// "quasi-static" or "time-series".
    #[getter]
    fn mode(&self) -> &'static str {
        self.inner.mode.name()
    }

    #[getter]
    fn description(&self) -> &str {
        &self.inner.description
    }

    /// A copy of the recording's scene.
    #[getter]
    fn scene(&self) -> Scene {
        Scene {
            inner: self.inner.scene.clone(),
        }
    }

    /// The object markers: name to reference point (m).
    #[getter]
    fn markers(&self) -> Vec<(String, (f64, f64, f64))> {
        self.inner
            .markers
            .iter()
            .map(|m| {
                let r = m.reference;
                (m.name.clone(), (r.x, r.y, r.z))
            })
            .collect()
    }

    /// The samples in the spec's long format, as columns: time (NaN in quasi-static mode),
    /// load, marker, x, y, z (NaN where not observed).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let r = &self.inner;
        let (mut time, mut load, mut marker) = (Vec::new(), Vec::new(), Vec::new());
        let mut xyz: [Vec<f64>; 3] = Default::default();
        for s in &r.samples {
            for o in &s.observations {
                time.push(s.time.unwrap_or(f64::NAN));
                load.push(s.load);
                marker.push(r.marker_name(o.marker));
                for (column, x) in xyz.iter_mut().zip(o.position) {
                    column.push(x.unwrap_or(f64::NAN));
                }
            }
        }
        let d = PyDict::new(py);
        d.set_item("time", PyArray1::from_vec(py, time))?;
        d.set_item("load", PyArray1::from_vec(py, load))?;
        d.set_item("marker", marker)?;
        let [x, y, z] = xyz;
        d.set_item("x", PyArray1::from_vec(py, x))?;
        d.set_item("y", PyArray1::from_vec(py, y))?;
        d.set_item("z", PyArray1::from_vec(py, z))?;
        Ok(d)
    }

    fn __len__(&self) -> usize {
        self.inner.samples.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "Recording({:?}, {}, {} samples, {} markers)",
            self.path(),
            self.mode(),
            self.inner.samples.len(),
            self.inner.markers.len()
        )
    }
}

fn pretty(value: &serde_json::Value) -> PyResult<String> {
    serde_json::to_string_pretty(value).map_err(err)
}

/// `softgrip compare`'s JSON: the recording replayed on its own scene (or `scene`).
#[pyfunction]
#[pyo3(signature = (recording, scene = None))]
fn compare(py: Python<'_>, recording: &Recording, scene: Option<&Scene>) -> PyResult<String> {
    let mut rec = recording.inner.clone();
    if let Some(s) = scene {
        rec.scene = s.inner.clone();
    }
    let run = cancellable(py, || {
        softgrip_lab::replay::replay(&rec, &rec.scene, Default::default(), |_| {})
            .map_err(|e| e.to_string())
    })?
    .map_err(err)?;
    pretty(&softgrip_lab::json::compare(&rec.source, &rec, &run, None))
}

/// `softgrip grasp window --json`: the least squeeze that holds and the most before damage of
/// `scene`, the options over its `[grasp]`; `fit` a `fit --json` file whose material is set in
/// and its uncertainty carried to both bounds; `confirm` lifts each bound dynamically.
#[pyfunction]
#[pyo3(signature = (scene, acceleration = None, shake = None, slip_tolerance = None, hold = None, damage = None, limit = None, fit = None, confirm = true))]
#[allow(clippy::too_many_arguments)]
fn grasp_window(
    py: Python<'_>,
    scene: &Scene,
    acceleration: Option<f64>,
    shake: Option<f64>,
    slip_tolerance: Option<f64>,
    hold: Option<f64>,
    damage: Option<String>,
    limit: Option<f64>,
    fit: Option<std::path::PathBuf>,
    confirm: bool,
) -> PyResult<String> {
    use softgrip_lab::grasp::plan::Asked;
    use softgrip_lab::grasp::window::Measure;
    let damage = match damage.as_deref() {
        None => None,
        Some(name) => Some(Measure::from_name(name).ok_or_else(|| {
            err(format!(
                "damage {name:?}: must be \"strain\", \"stress\" or \"pressure\""
            ))
        })?),
    };
    let asked = Asked {
        acceleration,
        shake,
        slip_tolerance,
        hold,
        damage,
        limit,
    };
    let inner = &scene.inner;
    let computed = cancellable(py, || {
        softgrip_lab::grasp::compute::compute(inner, asked, fit.as_deref(), confirm, |_| {})
            .map_err(|e| e.to_string())
    })?
    .map_err(err)?;
    pretty(&computed.to_json())
}

/// `softgrip fit`'s JSON: `params` (`name` or `name=low:high`) fitted to the recording.
#[pyfunction]
#[pyo3(signature = (recording, params, max_evaluations = 400, workers = 0))]
fn fit(
    py: Python<'_>,
    recording: &Recording,
    params: Vec<String>,
    max_evaluations: usize,
    workers: usize,
) -> PyResult<String> {
    use softgrip_lab::fit;
    let rec = &recording.inner;
    let params = fit::parse_params(&params, &rec.scene).map_err(err)?;
    let options = fit::FitOptions {
        max_evaluations,
        workers,
        ..fit::FitOptions::default()
    };
    let result = cancellable(py, || fit::fit(rec, &params, options, &|_, _| {}))?.map_err(err)?;
    pretty(&softgrip_lab::json::fit(&rec.source, rec, &result))
}

/// `softgrip sweep`'s CSV and JSON: every point of the grid of `params` (one or two axes,
/// `name=start:end:count[:log]` or `name=v1,v2,...`), in parallel on `workers` threads.
#[pyfunction]
#[pyo3(signature = (recording, params, workers = 0))]
fn sweep(
    py: Python<'_>,
    recording: &Recording,
    params: Vec<String>,
    workers: usize,
) -> PyResult<(String, String)> {
    let rec = &recording.inner;
    let axes = softgrip_lab::shard::parse_axes(&params).map_err(err)?;
    let points = cancellable(py, || {
        softgrip_lab::sweep::sweep(rec, &axes, workers, &|_| {})
    })?;
    let value = softgrip_lab::json::sweep(&rec.source, &axes, &points)
        .ok_or_else(|| err("no point of the sweep ran"))?;
    Ok((softgrip_lab::sweep::to_csv(&axes, &points), pretty(&value)?))
}

/// One shard's file of a sweep (`softgrip sweep --shard index/count`), as JSON text; `name`
/// is the recording as the outputs name it (default: `recording`), so that a worker reading
/// it from another directory writes what the CLI would.
#[pyfunction]
#[pyo3(signature = (recording, params, index, count, workers = 1, name = None))]
fn sweep_part(
    py: Python<'_>,
    recording: &str,
    params: Vec<String>,
    index: usize,
    count: usize,
    workers: usize,
    name: Option<&str>,
) -> PyResult<String> {
    use softgrip_lab::shard;
    let shard = shard::Shard::parse(&format!("{index}/{count}")).map_err(err)?;
    let rec = CoreRecording::load(Path::new(recording)).map_err(err)?;
    let named = Path::new(name.unwrap_or(recording));
    let value = cancellable(py, || {
        shard::run_part(named, &rec, &params, shard, workers, &|_| {})
    })?
    .map_err(err)?;
    pretty(&value)
}

/// Shards' files (JSON texts) merged: the sweep's CSV and JSON, as one run writes them.
#[pyfunction]
fn sweep_merge(parts: Vec<String>) -> PyResult<(String, String)> {
    let parts = parts
        .iter()
        .enumerate()
        .map(|(i, t)| {
            serde_json::from_str(t)
                .map(|v| (format!("part {i}"), v))
                .map_err(|e| err(format!("part {i}: not JSON: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let merged = softgrip_lab::shard::merge(&parts).map_err(err)?;
    let value =
        softgrip_lab::json::sweep(Path::new(&merged.recording), &merged.axes, &merged.points)
            .ok_or_else(|| err("no point of the sweep ran"))?;
    Ok((
        softgrip_lab::sweep::to_csv(&merged.axes, &merged.points),
        pretty(&value)?,
    ))
}

/// `softgrip diagnose`'s JSON. `model`: "continuum" (default), "lattice" or "scene";
/// `bounds`: "name=low:high"; `progress(done, planned, what)` as each fit starts; `checkpoint`:
/// a file each fit is saved in as it ends, from which a later call resumes; `region_scan`: the
/// region scan's shapes may name a region, not only the four halves (`--region-scan`; a region
/// the halves name is placed by the scan either way).
#[pyfunction]
#[pyo3(signature = (recording, model = "continuum", max_effects = 2, bounds = Vec::new(), lock = Vec::new(), workers = 0, progress = None, checkpoint = None, region_scan = false))]
#[allow(clippy::too_many_arguments)]
fn diagnose(
    py: Python<'_>,
    recording: &Recording,
    model: &str,
    max_effects: usize,
    bounds: Vec<String>,
    lock: Vec<String>,
    workers: usize,
    progress: Option<Py<PyAny>>,
    checkpoint: Option<PathBuf>,
    region_scan: bool,
) -> PyResult<String> {
    use softgrip_lab::diagnose::{self, BaselineModel, DiagnoseOptions};
    let model = match model {
        "scene" => None,
        m => Some(BaselineModel::from_name(m).ok_or_else(|| {
            err(format!(
                "model={m:?}: give \"continuum\", \"lattice\" or \"scene\""
            ))
        })?),
    };
    let bounds = bounds
        .iter()
        .map(|b| diagnose::parse_bound(b))
        .collect::<Result<Vec<_>, _>>()
        .map_err(err)?;
    let options = DiagnoseOptions {
        lock,
        bounds,
        workers,
        max_effects,
        model,
        region_scan,
        checkpoint: checkpoint
            .map(|path| {
                diagnose::Checkpoint::open(&path, &build(py)?)
                    .map_err(|e| err(format!("checkpoint: {e}: give a file you can write")))
            })
            .transpose()?,
        ..DiagnoseOptions::default()
    };
    let rec = &recording.inner;
    diagnose::check_bounds(&options.bounds).map_err(err)?;
    let report = |done: usize, planned: usize, what: &str| {
        if let Some(cb) = &progress {
            Python::attach(|py| {
                if let Err(e) = cb.call1(py, (done, planned, what)) {
                    e.write_unraisable(py, None);
                }
            });
        }
    };
    let d = cancellable(py, || diagnose::diagnose(rec, &options, &report))?.map_err(err)?;
    pretty(&diagnose::to_json(&d, rec))
}

/// This extension's build, for a checkpoint: a hash of its own file (another build fits again).
fn build(py: Python<'_>) -> PyResult<String> {
    let file: PathBuf = py
        .import("softgrip._softgrip")?
        .getattr("__file__")?
        .extract()?;
    softgrip_lab::diagnose::build_of("python", &file)
        .map_err(|e| err(format!("{}: {e}", file.display())))
}

/// Lets this process's simulations use at most `n` cores in all (0: the machine's), for a
/// process that is one of several on a machine (a Ray task with `num_cpus=1`).
#[pyfunction]
fn limit_cores(n: usize) {
    softgrip_core::step::parallel::limit_cores(n);
}

#[pymodule]
fn _softgrip(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_class::<Simulation>()?;
    m.add_class::<Recording>()?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_part, m)?)?;
    m.add_function(wrap_pyfunction!(sweep_merge, m)?)?;
    m.add_function(wrap_pyfunction!(diagnose, m)?)?;
    m.add_function(wrap_pyfunction!(grasp_window, m)?)?;
    m.add_function(wrap_pyfunction!(limit_cores, m)?)?;
    m.add("SoftgripError", m.py().get_type::<SoftgripError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
