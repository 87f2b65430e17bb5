//! A simulation that runs on its own thread while something else (the viewer) watches it and
//! changes it: rerun's and MuJoCo's viewer split.
//!
//! The solver thread owns the [`Simulation`]; others send it [`Command`]s without ever blocking
//! ([`LiveSimulation::send`] fails with [`SendError::Busy`] rather than wait) and read the
//! latest published [`Frame`] ([`LiveSimulation::latest`]). A parameter change is an edited
//! [`Scene`] ([`Command::SetScene`]), checked as a scene file is and applied on the mesh the
//! run has when it can. No GUI dependency (tested with `--no-default-features`). More:
//! `docs/design/live-simulation.md`.

use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::{self, JoinHandle};
use std::time::{Duration, Instant};

use crate::error::SimError;
use crate::mesh::TetMesh;
use crate::model::Model;
use crate::scene::Scene;
use crate::state::{Pull, State};
use crate::step::Simulation;
use glam::DVec3;

/// Commands the channel holds before [`LiveSimulation::send`] reports
/// [`SendError::Busy`].
pub const CHANNEL_CAPACITY: usize = 64;

/// How often a running simulation publishes a frame (wall time).
pub const PUBLISH_INTERVAL: Duration = Duration::from_millis(15);

/// How far (wall seconds) a paced run may fall behind before the lag is
/// forgiven instead of made up.
pub const MAX_LAG: f64 = 0.05;

/// Samples of finger history kept for plots; past this, every other one
/// is dropped.
pub const HISTORY_LENGTH: usize = 2000;

/// What the solver thread is told to do.
#[derive(Debug, Clone)]
pub enum Command {
    /// Run (paced by the speed; see [`Command::SetSpeed`]).
    Play,
    /// Stop stepping; the state stays.
    Pause,
    /// Pause and take this many steps.
    Step(u32),
    /// Back to the scene's start state (the current scene, re-meshed only
    /// if it has to be).
    Reset,
    /// Simulated seconds per wall second; `None` = as fast as it goes.
    SetSpeed(Option<f64>),
    /// Use this scene from now on (a parameter moved, a finger added or
    /// switched to velocity control, a file opened): checked, then only
    /// what changed is rebuilt.
    SetScene(Box<Scene>),
    /// Hold finger `finger` at a point (position-driven along its free
    /// axes: the viewer drags it), or let it go (`None`) back to its
    /// control mode. Not part of the scene; a reset lets go.
    Hold {
        /// The finger (index into the scene's fingers).
        finger: usize,
        /// The point to hold it at, m; `None` lets it go.
        at: Option<DVec3>,
    },
    /// Pull a point of the object with the mouse spring, or stop (`None`).
    Pull(Option<Pull>),
}

/// Why a command was not taken.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SendError {
    /// The channel is full ([`CHANNEL_CAPACITY`] commands waiting).
    #[error("the solver has {CHANNEL_CAPACITY} commands waiting; try again next frame")]
    Busy,
    /// The solver thread has ended.
    #[error("the solver thread has stopped")]
    Stopped,
}

/// Run state of the solver thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    /// Stepping.
    Running,
    /// Not stepping (or taking the steps of a [`Command::Step`]).
    Paused,
    /// Building a new mesh and model; no state to show yet.
    Meshing,
}

/// One finger's history sample, for plots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FingerSample {
    /// Simulated time of the sample, s.
    pub time: f64,
    /// Indentation depth (m), as `Simulation::indentation`.
    pub depth: f64,
    /// Normal contact force on the finger (N).
    pub normal_force: f64,
    /// Magnitude of the tangential force (N).
    pub tangential_force: f64,
}

/// What the solver thread publishes: everything a viewer draws.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The scene in use (edits that failed are not in it).
    pub scene: Arc<Scene>,
    /// The model in use; `None` while the first one is being built, or if
    /// no scene could be built at all.
    pub model: Option<Arc<Model>>,
    /// The state at the frame's time.
    pub state: State,
    /// Whether the solver thread is running, paused or meshing.
    pub run: RunState,
    /// The last error (a bad edit, a failed step), cleared by the next
    /// command that succeeds.
    pub error: Option<String>,
    /// Steps per wall second and simulated seconds per wall second, over
    /// the last publishing interval while running (0 when paused).
    pub steps_per_second: f64,
    /// Simulated seconds per wall second (see `steps_per_second`).
    pub realtime_factor: f64,
    /// Per finger, its recent history (time-ordered).
    pub history: Arc<Vec<Vec<FingerSample>>>,
    /// Counts the commands the solver has taken: a viewer that sent its
    /// n-th command can wait for a frame with `commands >= n`.
    pub commands: u64,
    /// What loading the mesh in use changed or noticed (skipped cells,
    /// reordered tetrahedra...).
    pub mesh_warnings: Arc<Vec<String>>,
    /// What the run's physical checks found since its start (`crate::watch`): a finger through
    /// the object, energy gained... as `softgrip run` warns.
    pub physics_warnings: Arc<Vec<String>>,
}

/// The viewer's side: send commands, read frames.
#[derive(Debug)]
pub struct LiveSimulation {
    sender: Option<SyncSender<Command>>,
    latest: Arc<Mutex<Option<Arc<Frame>>>>,
    thread: Option<JoinHandle<()>>,
}

fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl LiveSimulation {
    /// Starts the solver thread on `scene`, paused. The model is built on
    /// that thread; the first frame says whether it worked.
    pub fn start(scene: Scene) -> Result<LiveSimulation, std::io::Error> {
        let (sender, receiver) = sync_channel(CHANNEL_CAPACITY);
        let latest = Arc::new(Mutex::new(None));
        let published = Arc::clone(&latest);
        let thread = thread::Builder::new()
            .name("softgrip-solver".into())
            .spawn(move || Solver::new(scene, published).run(&receiver))?;
        Ok(LiveSimulation {
            sender: Some(sender),
            latest,
            thread: Some(thread),
        })
    }

    /// Queues a command; never blocks.
    pub fn send(&self, command: Command) -> Result<(), SendError> {
        let Some(sender) = &self.sender else {
            return Err(SendError::Stopped);
        };
        sender.try_send(command).map_err(|e| match e {
            TrySendError::Full(_) => SendError::Busy,
            TrySendError::Disconnected(_) => SendError::Stopped,
        })
    }

    /// The latest frame published, if any.
    pub fn latest(&self) -> Option<Arc<Frame>> {
        lock(&self.latest).clone()
    }

    /// Waits (polling) until a published frame satisfies `ready`, for at
    /// most `timeout`; for tests and headless use, never for a UI.
    pub fn wait_for(
        &self,
        timeout: Duration,
        ready: impl Fn(&Frame) -> bool,
    ) -> Option<Arc<Frame>> {
        let start = Instant::now();
        loop {
            if let Some(frame) = self.latest()
                && ready(&frame)
            {
                return Some(frame);
            }
            if start.elapsed() > timeout {
                return None;
            }
            thread::sleep(Duration::from_millis(2));
        }
    }

    /// Whether the solver thread is still there.
    pub fn is_alive(&self) -> bool {
        self.thread.as_ref().is_some_and(|t| !t.is_finished())
    }
}

impl Drop for LiveSimulation {
    fn drop(&mut self) {
        // Closing the channel ends the solver's loop.
        self.sender = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The solver thread's side.
struct Solver {
    scene: Arc<Scene>,
    /// The mesh of `scene`, kept so that parameter edits need not re-mesh.
    mesh: Option<TetMesh>,
    mesh_warnings: Arc<Vec<String>>,
    sim: Option<Simulation>,
    run: RunState,
    speed: Option<f64>,
    error: Option<String>,
    published: Arc<Mutex<Option<Arc<Frame>>>>,
    history: History,
    watch: crate::watch::Watch,
    commands: u64,
    /// Pacing: wall time and simulated time when the run (re)started.
    anchor: (Instant, f64),
    /// Rates: wall time, step and simulated time at the last publication.
    last_publish: (Instant, u64, f64),
    rates: (f64, f64),
}

impl Solver {
    fn new(scene: Scene, published: Arc<Mutex<Option<Arc<Frame>>>>) -> Solver {
        Solver {
            scene: Arc::new(scene),
            mesh: None,
            mesh_warnings: Arc::new(Vec::new()),
            sim: None,
            run: RunState::Meshing,
            speed: Some(1.0),
            error: None,
            published,
            history: History::default(),
            watch: crate::watch::Watch::default(),
            commands: 0,
            anchor: (Instant::now(), 0.0),
            last_publish: (Instant::now(), 0, 0.0),
            rates: (0.0, 0.0),
        }
    }

    fn run(mut self, commands: &Receiver<Command>) {
        self.publish();
        self.rebuild_all();
        self.run = RunState::Paused;
        self.publish();
        loop {
            // Take every waiting command; wait for one only when paused.
            let next = if self.run == RunState::Running {
                match commands.try_recv() {
                    Ok(c) => Some(c),
                    Err(std::sync::mpsc::TryRecvError::Empty) => None,
                    Err(std::sync::mpsc::TryRecvError::Disconnected) => return,
                }
            } else {
                match commands.recv_timeout(Duration::from_millis(100)) {
                    Ok(c) => Some(c),
                    Err(RecvTimeoutError::Timeout) => None,
                    Err(RecvTimeoutError::Disconnected) => return,
                }
            };
            if let Some(command) = next {
                self.commands += 1;
                self.apply(command);
                self.publish();
                continue;
            }
            if self.run == RunState::Running {
                self.advance();
            }
        }
    }

    fn apply(&mut self, command: Command) {
        match command {
            Command::Play => {
                if self.sim.is_some() {
                    self.run = RunState::Running;
                    self.error = None;
                    self.reanchor();
                }
            }
            Command::Pause => self.run = RunState::Paused,
            Command::Step(n) => {
                self.run = RunState::Paused;
                if self.sim.is_some() {
                    self.error = None;
                }
                for _ in 0..n {
                    if !self.step_once() {
                        break;
                    }
                }
            }
            Command::Reset => {
                self.reset_state();
                self.reanchor();
            }
            Command::SetSpeed(speed) => {
                self.speed = speed.filter(|s| s.is_finite() && *s > 0.0);
                self.reanchor();
            }
            Command::SetScene(scene) => self.set_scene(*scene),
            Command::Hold { finger, at } => {
                if let Some(fs) = self
                    .sim
                    .as_mut()
                    .and_then(|s| s.state.fingers.get_mut(finger))
                {
                    fs.held = at.filter(|p| p.is_finite());
                }
            }
            Command::Pull(pull) => {
                if let Some(sim) = self.sim.as_mut() {
                    // A facet of another mesh (sent before a re-mesh) or a
                    // bad number is no pull.
                    sim.state.pull = pull.filter(|p| {
                        (p.facet as usize) < sim.model.facets.len()
                            && p.target.is_finite()
                            && p.stiffness.is_finite()
                            && p.stiffness >= 0.0
                            && p.weights.iter().all(|w| w.is_finite())
                    });
                }
            }
        }
    }

    fn reanchor(&mut self) {
        let time = self.sim.as_ref().map_or(0.0, |s| s.state.time);
        self.anchor = (Instant::now(), time);
    }

    /// Steps once, or waits a little if ahead of the requested speed.
    fn advance(&mut self) {
        if let (Some(speed), Some(sim)) = (self.speed, &self.sim) {
            let allowed = self.anchor.1 + speed * self.anchor.0.elapsed().as_secs_f64();
            if sim.state.time + MAX_LAG * speed < allowed {
                // Behind (slow steps in a transient): forgive it rather
                // than race to catch up, so "x1" never runs faster than 1.
                self.anchor = (Instant::now(), sim.state.time);
            } else if sim.state.time >= allowed {
                let ahead = (sim.state.time - allowed) / speed;
                thread::sleep(Duration::from_secs_f64(ahead.clamp(0.0005, 0.005)));
                self.maybe_publish();
                return;
            }
        }
        if self.step_once() {
            self.maybe_publish();
        } else {
            // Paused with an error: show it now.
            self.publish();
        }
    }

    /// One step; on failure, pauses with the error. False if it failed.
    fn step_once(&mut self) -> bool {
        let Some(sim) = self.sim.as_mut() else {
            return false;
        };
        match sim.step() {
            Ok(()) => {
                self.history.record(sim);
                self.watch.step(&sim.model, &sim.state);
                true
            }
            Err(e) => {
                self.run = RunState::Paused;
                self.error = Some(format!("{e}"));
                false
            }
        }
    }

    fn maybe_publish(&mut self) {
        if self.last_publish.0.elapsed() >= PUBLISH_INTERVAL {
            self.publish();
        }
    }

    fn publish(&mut self) {
        let now = Instant::now();
        let (step, time) = self
            .sim
            .as_ref()
            .map_or((0, 0.0), |s| (s.state.step, s.state.time));
        let wall = (now - self.last_publish.0).as_secs_f64();
        if step < self.last_publish.1 {
            // A restart (reset, new mesh): no rate across it.
            self.rates = (0.0, 0.0);
        } else if self.run == RunState::Running && wall > 0.0 {
            self.rates = (
                step.saturating_sub(self.last_publish.1) as f64 / wall,
                (time - self.last_publish.2) / wall,
            );
        } else if self.run != RunState::Running {
            self.rates = (0.0, 0.0);
        }
        self.last_publish = (now, step, time);
        let frame = Frame {
            scene: Arc::clone(&self.scene),
            model: self.sim.as_ref().map(|s| Arc::clone(&s.model)),
            state: self
                .sim
                .as_ref()
                .map(|s| s.state.clone())
                .unwrap_or_default(),
            run: self.run,
            error: self.error.clone(),
            steps_per_second: self.rates.0,
            realtime_factor: self.rates.1,
            history: Arc::new(self.history.samples.clone()),
            commands: self.commands,
            mesh_warnings: Arc::clone(&self.mesh_warnings),
            physics_warnings: Arc::new(
                self.watch
                    .findings()
                    .iter()
                    .map(|f| f.message.clone())
                    .collect(),
            ),
        };
        *lock(&self.published) = Some(Arc::new(frame));
    }

    /// Takes a freshly built mesh and simulation as the run.
    fn install(&mut self, (mesh, warnings, sim): (TetMesh, Vec<String>, Simulation)) {
        self.mesh = Some(mesh);
        self.mesh_warnings = Arc::new(warnings);
        self.history = History::default();
        self.watch = crate::watch::Watch::default();
        self.sim = Some(sim);
        self.error = None;
    }

    /// Meshes the current scene and starts it afresh.
    fn rebuild_all(&mut self) {
        self.run = RunState::Meshing;
        self.publish();
        match build(&self.scene) {
            Ok(built) => self.install(built),
            Err(e) => {
                self.mesh = None;
                self.sim = None;
                self.error = Some(format!("{e}"));
            }
        }
        self.run = RunState::Paused;
    }

    fn reset_state(&mut self) {
        let Some(mesh) = self.mesh.clone() else {
            self.rebuild_all();
            return;
        };
        match Model::from_mesh(&self.scene, mesh) {
            Ok(model) => {
                self.history = History::default();
                self.watch = crate::watch::Watch::default();
                self.sim = Some(Simulation::from_model(model));
                self.error = None;
            }
            Err(e) => self.error = Some(format!("{e}")),
        }
    }

    /// Checks `scene` as a file would be checked, then rebuilds what it
    /// changes. A scene that fails leaves everything as it was.
    fn set_scene(&mut self, scene: Scene) {
        let checked = match check(&scene) {
            Ok(s) => s,
            Err(message) => {
                self.error = Some(message);
                return;
            }
        };
        let same_mesh = self.mesh.is_some()
            && checked.object.shape == self.scene.object.shape
            && checked.object.edge_length == self.scene.object.edge_length;
        if !same_mesh {
            // Mesh the new scene while the old run waits untouched: on
            // failure it goes on where it was, with the error.
            let was = self.run;
            let previous = std::mem::replace(&mut self.scene, Arc::new(checked));
            self.run = RunState::Meshing;
            self.publish();
            match build(&self.scene) {
                Ok(built) => {
                    self.install(built);
                    self.run = if was == RunState::Running {
                        RunState::Running
                    } else {
                        RunState::Paused
                    };
                }
                Err(e) => {
                    self.scene = previous;
                    self.error = Some(format!("{e}"));
                    self.run = if self.sim.is_some() {
                        was
                    } else {
                        RunState::Paused
                    };
                }
            }
            self.reanchor();
            return;
        }
        let Some(mesh) = self.mesh.clone() else {
            return;
        };
        let model = match Model::from_mesh(&checked, mesh) {
            Ok(m) => m,
            Err(e) => {
                self.error = Some(format!("{e}"));
                return;
            }
        };
        if let Some(sim) = self.sim.as_mut() {
            carry_state(&self.scene, &checked, &model, &mut sim.state);
            sim.model = Arc::new(model);
            self.history
                .samples
                .resize(sim.model.fingers.len(), Vec::new());
        }
        self.scene = Arc::new(checked);
        self.error = None;
    }
}

/// A scene checked by the same resolver as a file: written out and read
/// back, so every range check is the file's; the message names the key and
/// the allowed range, not a line.
fn check(scene: &Scene) -> Result<Scene, String> {
    const NAME: &str = "edit";
    let mut checked = Scene::from_toml_str(&scene.to_toml(), NAME).map_err(|e| {
        // The line is one of the written-out text, which nobody sees.
        let message = e.to_string();
        let rest = message
            .strip_prefix(NAME)
            .and_then(|r| r.strip_prefix(':'))
            .map(|r| r.trim_start_matches(|c: char| c.is_ascii_digit()))
            .and_then(|r| r.strip_prefix(':'))
            .unwrap_or(&message)
            .trim();
        format!("edit rejected, the run goes on unchanged: {rest}")
    })?;
    checked.source.clone_from(&scene.source);
    Ok(checked)
}

fn build(scene: &Scene) -> Result<(TetMesh, Vec<String>, Simulation), SimError> {
    let (mesh, warnings) = Model::load_mesh(scene)?;
    // Meshed once; `on_mesh` also checks that no finger starts inside.
    let sim = Simulation::on_mesh(scene, mesh.clone())?;
    Ok((mesh, warnings, sim))
}

/// Keeps the state across a model rebuilt on the same mesh: particles as
/// they are; fingers that stay keep their motion (a finger moved in the
/// scene is put there; a new applied force replaces the old); new fingers
/// start at their scene positions; contacts of removed fingers go.
fn carry_state(old: &Scene, new: &Scene, model: &Model, state: &mut State) {
    let fresh = State::initial(model);
    let mut fingers = fresh.fingers.clone();
    for (k, f) in fingers.iter_mut().enumerate() {
        let (Some(kept), Some(was), Some(now)) =
            (state.fingers.get(k), old.fingers.get(k), new.fingers.get(k))
        else {
            continue;
        };
        let moved = was.position != now.position;
        *f = *kept;
        if moved {
            f.position = now.position;
            f.velocity = glam::DVec3::ZERO;
        }
        if was.force != now.force {
            f.applied_force = model.fingers[k].force;
        }
    }
    state.fingers = fingers;
    let count = model.fingers.len() as u32;
    state.contacts.retain(|c| c.finger < count);
    state
        .contact_memory
        .retain(|(finger, _), _| *finger < count);
}

/// Finger history for plots: one sample every `stride` steps; when a
/// series passes [`HISTORY_LENGTH`], every other sample goes (counted back
/// from the newest) and the stride doubles, so the spacing stays even.
#[derive(Debug, Default)]
struct History {
    samples: Vec<Vec<FingerSample>>,
    stride: u64,
    last: u64,
}

impl History {
    fn record(&mut self, sim: &Simulation) {
        let stride = self.stride.max(1);
        let step = sim.state.step;
        if self.last != 0 && step < self.last + stride {
            return;
        }
        self.last = step;
        self.samples.resize(sim.state.fingers.len(), Vec::new());
        let mut thinned = false;
        for (k, samples) in self.samples.iter_mut().enumerate() {
            let fs = &sim.state.fingers[k];
            samples.push(FingerSample {
                time: sim.state.time,
                depth: sim.indentation(k),
                normal_force: fs.normal_force,
                tangential_force: fs.tangential_force.length(),
            });
            if samples.len() > HISTORY_LENGTH {
                let mut kept: Vec<FingerSample> =
                    samples.iter().rev().step_by(2).copied().collect();
                kept.reverse();
                *samples = kept;
                thinned = true;
            }
        }
        if thinned {
            self.stride = 2 * stride;
        }
    }
}
