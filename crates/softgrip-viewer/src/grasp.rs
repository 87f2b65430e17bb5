//! The Grasp panel: the grasp window of the scene the panels show, computed on a thread of its
//! own (cancellable, its squeezes counted), its plot (slip margin and damage against squeeze,
//! the window shaded, both bounds marked), and a squeeze slider whose held state the 3-D view
//! shows in place of the live run, coloured by the damage measure.

use std::sync::Arc;
use std::sync::atomic::Ordering;

use eframe::egui;
use softgrip_core::fields::Field;
use softgrip_core::scene::Scene;
use softgrip_core::step::Simulation;
use softgrip_lab::grasp::compute::{Computed, Stage, compute};
use softgrip_lab::grasp::window::{self, Measure};

use crate::jobs::{Job, job_error, progress_with_stop};
use crate::recording::Overlay;
use crate::widgets::ERROR_RED;

/// The state held at one squeeze, for the 3-D view.
pub struct Gripped {
    /// The squeeze solved for, N: the largest finger's force.
    pub squeeze: f64,
    /// The state holding the lift's load, or the squeezed state where it has no equilibrium.
    pub sim: Simulation,
    /// Whether the grip holds the load (an equilibrium was found under it).
    pub held: bool,
    /// The damage measure's largest value in `sim` and where.
    pub peak: window::Peak,
}

/// The Grasp panel's state.
#[derive(Default)]
pub struct GraspPanel {
    job: Option<Job<Computed>>,
    /// The window last computed.
    pub computed: Option<Arc<Computed>>,
    /// The last error of a window or squeeze computation, shown in red.
    pub error: Option<String>,
    /// The squeeze the slider is at (N).
    pub squeeze: f64,
    grip_job: Option<Job<Gripped>>,
    /// The state at the slider's squeeze, once solved.
    pub gripped: Option<Arc<Gripped>>,
    /// Show the gripped state in the 3-D view.
    pub show: bool,
    generation: u64,
}

/// What the panel asks of the viewer.
pub enum Action {
    /// Colour the object by this field (the damage measure's).
    ColorBy(Field),
}

/// The field that shows a damage measure.
pub fn field_of(measure: Measure) -> Field {
    match measure {
        Measure::Strain => Field::GreenStrain,
        Measure::Stress => Field::VonMises,
        Measure::Pressure => Field::ContactPressure,
    }
}

impl GraspPanel {
    /// A window or a squeeze's state is being computed.
    pub fn busy(&self) -> bool {
        self.job.is_some() || self.grip_job.is_some()
    }

    /// Starts the window of `scene` on a background thread (statics only: the dynamic
    /// confirmations are the command line's).
    pub fn start(&mut self, scene: Scene) {
        self.generation += 1;
        self.error = None;
        match Job::spawn("grasp window", self.generation, 0, move |progress| {
            compute(&scene, Default::default(), None, false, |stage| {
                if let Stage::Squeeze(_) = stage {
                    progress.done.fetch_add(1, Ordering::Relaxed);
                }
            })
        }) {
            Ok(job) => self.job = Some(job),
            Err(e) => self.error = Some(e),
        }
    }

    /// Solves the state held at `squeeze` on a background thread (the last asked wins).
    fn grip(&mut self, squeeze: f64) {
        let Some(c) = self.computed.clone() else {
            return;
        };
        let generation = self.generation;
        match Job::spawn("grasp state", generation, 0, move |_| {
            let g = c.gripper.grip(squeeze, c.plan.options.statics)?;
            let held = g.held.is_ok();
            let sim = g.held.unwrap_or(g.squeezed);
            let peak = window::peak(c.plan.options.damage.measure, &sim);
            Ok(Gripped {
                squeeze,
                sim,
                held,
                peak,
            })
        }) {
            Ok(job) => self.grip_job = Some(job),
            Err(e) => self.error = Some(e),
        }
    }

    /// Takes finished jobs' results (each UI frame).
    pub fn poll(&mut self) {
        if let Some((generation, r)) = self.job.as_ref().and_then(|j| j.poll()) {
            self.job = None;
            match r {
                Ok(c) if generation == self.generation => {
                    let c = Arc::new(c);
                    self.squeeze = c.window.least_squeeze();
                    self.computed = Some(Arc::clone(&c));
                    self.gripped = None;
                    self.grip(self.squeeze);
                }
                Ok(_) => {}
                Err(e) => self.error = Some(job_error("grasp window", &e)),
            }
        }
        if let Some((_, r)) = self.grip_job.as_ref().and_then(|j| j.poll()) {
            self.grip_job = None;
            match r {
                Ok(g) => self.gripped = Some(Arc::new(g)),
                Err(e) => self.error = Some(job_error("the state at this squeeze", &e)),
            }
        }
    }

    /// What the 3-D view draws instead of the live run while shown.
    pub fn overlay(&self) -> Option<Overlay> {
        if !self.show {
            return None;
        }
        let g = self.gripped.as_ref()?;
        let c = self.computed.as_ref()?;
        let m = c.plan.options.damage.measure;
        Some(Overlay {
            model: Arc::clone(&g.sim.model),
            state: g.sim.state.clone(),
            markers: Vec::new(),
            exaggerate: 1.0,
            caption: format!(
                "grasp window: squeeze {:.3} N, {}; peak {} {}",
                g.squeeze,
                if g.held {
                    "held"
                } else {
                    "not held: it slides out"
                },
                m.describe(),
                softgrip_lab::report::shown(m, g.peak.value)
            ),
            key: (Arc::as_ptr(g) as usize, 0, g.squeeze.to_bits()),
        })
    }

    /// The panel for `scene` (the one the panels show); what it asks of the viewer.
    pub fn ui(&mut self, ui: &mut egui::Ui, scene: &Scene) -> Option<Action> {
        let mut action = None;
        egui::CollapsingHeader::new("Grasp window")
            .default_open(false)
            .show(ui, |ui| action = self.body(ui, scene));
        action
    }

    fn body(&mut self, ui: &mut egui::Ui, scene: &Scene) -> Option<Action> {
        let plan = softgrip_lab::grasp::plan::plan(scene, Default::default());
        match &plan {
            Ok(p) => {
                ui.label(format!(
                    "how hard may the fingers squeeze: held through a lift of {:.2} m/s^2, {} below {}",
                    p.options.profile.acceleration,
                    p.options.damage.measure.describe(),
                    softgrip_lab::report::shown(p.options.damage.measure, p.options.damage.limit)
                ));
            }
            Err(e) => {
                ui.colored_label(ERROR_RED, e.to_string());
            }
        }
        if let Some(job) = &self.job {
            let done = job.done();
            progress_with_stop(
                ui,
                job,
                egui::ProgressBar::new(0.0).text(format!("{done} squeezes solved")),
            );
        } else if ui
            .add_enabled(plan.is_ok(), egui::Button::new("Compute the window"))
            .on_hover_text("the least squeeze that holds and the most before damage, by statics")
            .clicked()
        {
            self.start(scene.clone());
        }
        if let Some(e) = &self.error {
            ui.colored_label(ERROR_RED, e);
        }
        let c = self.computed.clone()?;
        self.result(ui, &c)
    }

    /// The window found: its figures, its plot and the squeeze slider.
    fn result(&mut self, ui: &mut egui::Ui, c: &Computed) -> Option<Action> {
        let w = &c.window;
        ui.label(match w.most_squeeze() {
            Some(most) if w.exists() => {
                format!("window {:.3} .. {most:.3} N", w.least_squeeze())
            }
            Some(most) => format!(
                "NO WINDOW: it holds from {:.3} N, damaged from {most:.3} N",
                w.least_squeeze()
            ),
            None => format!(
                "window from {:.3} N (the limit not reached)",
                w.least_squeeze()
            ),
        });
        plot(ui, c, self.squeeze);
        let top = w.samples.last().map_or(1.0, |s| s.squeeze);
        let slider = ui.add(egui::Slider::new(&mut self.squeeze, 0.0..=top).text("squeeze (N)"));
        if slider.drag_stopped() || (slider.changed() && !slider.dragged()) {
            self.grip(self.squeeze);
        }
        let mut action = None;
        if ui
            .checkbox(&mut self.show, "show this squeeze in the 3-D view")
            .changed()
            && self.show
        {
            action = Some(Action::ColorBy(field_of(c.plan.options.damage.measure)));
        }
        if self.grip_job.is_some() {
            ui.label("solving this squeeze ...");
        } else if let Some(g) = &self.gripped {
            ui.label(format!(
                "{:.3} N: {}, peak {} {}",
                g.squeeze,
                if g.held { "held" } else { "not held" },
                c.plan.options.damage.measure.describe(),
                softgrip_lab::report::shown(c.plan.options.damage.measure, g.peak.value)
            ));
        }
        action
    }
}

/// The slip margin and the damage over its limit against squeeze, the window shaded, the
/// bounds and the slider's squeeze marked.
fn plot(ui: &mut egui::Ui, c: &Computed, squeeze: f64) {
    let w = &c.window;
    let limit = c.plan.options.damage.limit;
    let margin: Vec<[f64; 2]> = w
        .samples
        .iter()
        .map(|s| [s.squeeze, s.margin.max(-1.0)])
        .collect();
    let damage: Vec<[f64; 2]> = w
        .samples
        .iter()
        .map(|s| [s.squeeze, s.peak.value / limit])
        .collect();
    crate::plot_grid::with_grids(egui_plot::Plot::new("grasp window"))
        .height(160.0)
        .include_y(0.0)
        .include_y(1.2)
        .x_axis_label("squeeze (N)")
        .legend(egui_plot::Legend::default())
        .show(ui, |plot| {
            if w.exists() {
                let top = w
                    .most_squeeze()
                    .unwrap_or_else(|| w.samples.last().map_or(1.0, |s| s.squeeze));
                let least = w.least_squeeze();
                plot.polygon(
                    egui_plot::Polygon::new(
                        "window",
                        vec![[least, -1.0], [top, -1.0], [top, 1.5], [least, 1.5]],
                    )
                    .fill_color(egui::Color32::from_rgba_unmultiplied(120, 200, 120, 50))
                    .stroke(egui::Stroke::NONE),
                );
            }
            plot.line(egui_plot::Line::new("slip margin", margin));
            plot.line(egui_plot::Line::new("damage / limit", damage));
            plot.vline(egui_plot::VLine::new("squeeze shown", squeeze));
        });
}
