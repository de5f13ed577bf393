//! The explorer application: its state (scene, parameters, view options, time, caches) and the
//! per-frame logic that receives the worker's events, requests the fields the screen needs and
//! lays out the panels. The same type runs on the desktop (eframe, wgpu) and in tests
//! (egui_kittest).

use crate::camera::Camera;
use crate::colormap::Range;
use crate::fields::StepFields;
use crate::geometry::SceneGeometry;
use crate::measure::Measure;
use crate::mesh_build::{self, MeshData, MeshInputs};
use crate::params::Params;
use crate::quantity::Quantity;
use crate::recorder::{RecorderFactory, RecorderSlot};
use crate::section::Section;
use crate::worker::{Event, ProbeHistory, SolveReport, Worker};
use lopin_core::counters::Instant;
use lopin_core::post::ContactHistory;
use lopin_core::{scene, Settings};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Mesh versions are unique across scenes: the GPU resources outlive a scene change.
static MESH_VERSION: AtomicU64 = AtomicU64::new(1);

/// How the explorer starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    /// Built-in scene name or path to a .toml scene file.
    pub scene: String,
    /// Hide wall-clock figures (timings, frame rate) so screenshots are reproducible.
    pub reproducible: bool,
    /// Measure re-solve latency and frame time, print them and close (see [`Measure`]).
    pub measure: Option<std::path::PathBuf>,
    /// Makes Rerun recorders for the "record to Rerun" toggle (None: recording unavailable).
    pub recorder: Option<RecorderFactory>,
    /// Start with recording switched on.
    pub record: bool,
    /// Two-scale linear stage on or off (None: the scene's `solver.macro`).
    pub two_scale: Option<bool>,
}

impl Options {
    /// Options for a scene, everything else default.
    pub fn scene(scene: &str) -> Options {
        Options {
            scene: scene.into(),
            reproducible: false,
            measure: None,
            recorder: None,
            record: false,
            two_scale: None,
        }
    }
}

/// Scene facts shown in the sizes panel.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneInfo {
    /// Scene name.
    pub name: String,
    /// One-line description.
    pub description: String,
    /// Substructures.
    pub subs: usize,
    /// Interfaces (all kinds).
    pub interfaces: usize,
    /// Contact interfaces.
    pub contacts: usize,
    /// Degrees of freedom.
    pub dofs: usize,
    /// Time steps.
    pub steps: usize,
    /// Time step, s.
    pub dt: f64,
}

/// View options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewOptions {
    /// Coloured quantity.
    pub quantity: Quantity,
    /// Fixed colour range instead of automatic.
    pub fixed_range: bool,
    /// The fixed range, display units.
    pub range_min: f64,
    /// The fixed range, display units.
    pub range_max: f64,
    /// Draw the deformed shape.
    pub deformed: bool,
    /// Deformation scale factor.
    pub deform_scale: f32,
    /// Pull substructures apart.
    pub exploded: bool,
    /// How far (fraction of each substructure's distance from the centre).
    pub explode_amount: f32,
    /// Show a section.
    pub section: bool,
    /// Section axis 0, 1, 2.
    pub section_axis: usize,
    /// Section position as a fraction of the scene's extent along the axis.
    pub section_fraction: f32,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            quantity: Quantity::VonMises,
            fixed_range: false,
            range_min: 0.0,
            range_max: 1.0,
            deformed: false,
            deform_scale: 100.0,
            exploded: false,
            explode_amount: 0.35,
            section: false,
            section_axis: 1,
            section_fraction: 0.5,
        }
    }
}

/// Where the solver stands.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveStatus {
    /// Factorizing / first solve not started.
    Starting,
    /// A solve runs.
    Running {
        /// Its generation.
        generation: u64,
        /// Iterations so far.
        iterations: usize,
        /// Last η.
        eta: f64,
    },
    /// The newest solve ended.
    Done(SolveReport),
    /// Something failed.
    Failed(String),
}

/// The explorer.
pub struct ExplorerApp {
    /// Start options.
    pub options: Options,
    /// Scene facts.
    pub info: SceneInfo,
    /// Fixed geometry.
    pub geometry: Arc<SceneGeometry>,
    worker: Worker,
    /// Parameter values shown by the controls.
    pub params: Params,
    /// Parameter values of the newest solve requested.
    pub requested: Params,
    /// View options.
    pub view: ViewOptions,
    /// Displayed time step.
    pub step: usize,
    /// Playing the time steps.
    pub playing: bool,
    play_clock: f64,
    /// The camera.
    pub camera: Camera,
    /// Solver status.
    pub status: SolveStatus,
    /// Every η so far: (cumulative iteration, η).
    pub convergence: Vec<[f64; 2]>,
    /// Parameter changes: (cumulative iteration, description).
    pub markers: Vec<(f64, String)>,
    /// Reports of the finished solves, oldest first.
    pub reports: Vec<SolveReport>,
    fields: HashMap<usize, Arc<StepFields>>,
    fields_generation: u64,
    live: Option<Arc<StepFields>>,
    shown: Option<Arc<StepFields>>,
    requested_step: Option<usize>,
    /// Contact histories of the newest solution or iterate.
    pub contact: Option<Arc<Vec<ContactHistory>>>,
    /// Drawn mesh and its version.
    pub mesh: Arc<MeshData>,
    /// Incremented at each mesh rebuild.
    pub mesh_version: u64,
    mesh_key: Option<(usize, usize, MeshInputs)>,
    /// Picked node (substructure, node).
    pub probe: Option<(usize, usize)>,
    /// Its history.
    pub probe_history: Option<Arc<ProbeHistory>>,
    /// Last error message (bad parameter, failed load).
    pub error: Option<String>,
    /// Whether the GPU view is available (wgpu backend).
    pub gpu: bool,
    /// Time of the newest parameter change.
    change_time: Option<Instant>,
    /// Seconds from the newest parameter change to its converged solve.
    pub last_latency: Option<f64>,
    /// Recent frame intervals, s.
    pub frame_intervals: std::collections::VecDeque<f64>,
    last_frame: Option<Instant>,
    measure: Option<Measure>,
    /// Where some controls were drawn in the last frame, points: "friction" and "time" (slider
    /// rails), "section" and "exploded" (checkboxes). Scripts driving the web page click there.
    pub controls: std::collections::BTreeMap<&'static str, egui::Rect>,
    /// Where the 3D view was drawn in the last frame, points.
    pub view_rect: Option<egui::Rect>,
    /// Scene chosen in the picker (loaded at the end of the frame).
    pub pending_scene: Option<String>,
    /// The recorder converged solves go to while recording is on.
    recorder: RecorderSlot,
    /// Whether converged solves are recorded.
    pub recording: bool,
    /// Where they go.
    pub recording_target: Option<String>,
    /// How many solves were recorded for this scene.
    pub recorded_solves: usize,
    ctx: egui::Context,
}

/// Loads a scene: spec, problem, settings, geometry.
pub(crate) fn load(
    name_or_path: &str,
) -> lopin_core::Result<(
    scene::SceneSpec,
    lopin_core::Problem,
    Settings,
    SceneGeometry,
)> {
    let spec = scene::load(name_or_path)?;
    let problem = scene::build::build(&spec, &scene::source_label(name_or_path))?;
    let settings = Settings::for_problem(&problem, &spec.solver);
    let geo = SceneGeometry::of(&problem);
    Ok((spec, problem, settings, geo))
}

impl ExplorerApp {
    /// Builds the explorer on a scene; the first (cold) solve starts at once in the background.
    pub fn new(cc: &eframe::CreationContext<'_>, options: Options) -> lopin_core::Result<Self> {
        let gpu = match &cc.wgpu_render_state {
            Some(rs) => {
                crate::render::install(rs);
                true
            }
            None => false,
        };
        Self::with_context(cc.egui_ctx.clone(), options, gpu)
    }

    fn with_context(ctx: egui::Context, options: Options, gpu: bool) -> lopin_core::Result<Self> {
        let (spec, problem, mut settings, geo) = load(&options.scene)?;
        if let Some(on) = options.two_scale {
            settings.two_scale = on;
        }
        let info = SceneInfo {
            name: spec.name.clone(),
            description: spec.description.clone(),
            subs: problem.subs.len(),
            interfaces: problem.interfaces.len(),
            contacts: problem.contact_count(),
            dofs: problem.dof_count(),
            steps: problem.time.steps,
            dt: problem.time.dt,
        };
        let params = Params::of(&problem, &settings);
        let wake_ctx = ctx.clone();
        let recorder: RecorderSlot = Arc::new(Mutex::new(None));
        let mut worker = Worker::spawn(
            problem,
            settings,
            Arc::new(move || wake_ctx.request_repaint()),
            recorder.clone(),
        )?;
        let step = info.steps / 2;
        worker.set_display_step(step);
        worker.solve(params.clone());
        let camera = Camera::framing(geo.lo, geo.hi);
        let measure = options.measure.clone().map(Measure::new);
        let record = options.record;
        let mut app = ExplorerApp {
            options,
            info,
            geometry: Arc::new(geo),
            worker,
            requested: params.clone(),
            params,
            view: ViewOptions::default(),
            step,
            playing: false,
            play_clock: 0.0,
            camera,
            status: SolveStatus::Starting,
            convergence: Vec::new(),
            markers: vec![(0.0, "start".into())],
            reports: Vec::new(),
            fields: HashMap::new(),
            fields_generation: 0,
            live: None,
            shown: None,
            requested_step: None,
            contact: None,
            mesh: Arc::new(MeshData::default()),
            mesh_version: 0,
            mesh_key: None,
            probe: None,
            probe_history: None,
            error: None,
            gpu,
            change_time: Some(Instant::now()),
            last_latency: None,
            frame_intervals: Default::default(),
            last_frame: None,
            measure,
            controls: Default::default(),
            view_rect: None,
            pending_scene: None,
            recorder,
            recording: false,
            recording_target: None,
            recorded_solves: 0,
            ctx,
        };
        if record {
            app.set_recording(true);
        }
        Ok(app)
    }

    /// Switches recording on (a recorder is made for this scene and the newest converged
    /// solution is recorded at once, then every later one) or off (the recording is closed).
    pub fn set_recording(&mut self, on: bool) {
        if !on {
            self.stop_recording();
            return;
        }
        let Some(factory) = &self.options.recorder else {
            self.error = Some("recording is not available in this build".into());
            return;
        };
        match factory.make(&self.info.name) {
            Ok(rec) => {
                self.recording_target = Some(rec.target());
                if let Ok(mut slot) = self.recorder.lock() {
                    *slot = Some(rec);
                }
                self.recording = true;
                self.worker.request_record();
            }
            Err(e) => {
                self.recording = false;
                self.error = Some(format!("cannot record: {e}"));
            }
        }
    }

    /// Closes the recording (the file is complete once this returns).
    fn stop_recording(&mut self) {
        self.recording = false;
        let rec = self.recorder.lock().ok().and_then(|mut slot| slot.take());
        drop(rec);
    }

    /// Replaces the scene (from the picker); on failure the current one stays and the error is
    /// shown.
    pub fn load_scene(&mut self, name_or_path: &str) {
        let recording = self.recording;
        let options = Options {
            scene: name_or_path.into(),
            record: recording,
            ..self.options.clone()
        };
        // the old scene's recording is complete before the new scene's starts
        self.stop_recording();
        match Self::with_context(self.ctx.clone(), options, self.gpu) {
            Ok(app) => *self = app,
            Err(e) => {
                self.error = Some(format!("{e}"));
                if recording {
                    self.set_recording(true);
                }
            }
        }
    }

    /// Launches a warm re-solve if the controls moved since the newest request (a running
    /// solve is cancelled and the new one starts from its newest iterate).
    pub fn resolve_if_changed(&mut self) {
        if self.params == self.requested {
            return;
        }
        let what = self.params.describe_change(&self.requested);
        self.markers.push((self.convergence.len() as f64, what));
        self.requested = self.params.clone();
        self.worker.solve(self.params.clone());
        self.change_time = Some(Instant::now());
        self.last_latency = None;
        self.error = None;
    }

    /// Generation of the newest parameter change.
    pub fn generation(&self) -> u64 {
        self.worker.generation()
    }

    /// Whether the newest request has converged.
    pub fn converged(&self) -> bool {
        matches!(&self.status, SolveStatus::Done(r)
            if r.converged && r.generation == self.worker.generation())
    }

    /// Whether the newest request is still being solved.
    pub fn busy(&self) -> bool {
        !matches!(&self.status, SolveStatus::Done(r) if r.generation == self.worker.generation())
            && !matches!(self.status, SolveStatus::Failed(_))
    }

    /// The fields on screen, if any have arrived.
    pub fn shown_fields(&self) -> Option<&Arc<StepFields>> {
        self.shown.as_ref()
    }

    /// Physical time of the displayed step, s.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.info.dt
    }

    /// Moves the time scrubber.
    pub fn set_step(&mut self, step: usize) {
        self.step = step.min(self.info.steps);
        self.worker.set_display_step(self.step);
    }

    /// Picks a node for the probe.
    pub fn set_probe(&mut self, sub: usize, node: usize) {
        self.probe = Some((sub, node));
        self.probe_history = None;
        self.worker.request_probe(sub, node);
    }

    /// The section plane of the current options.
    pub fn section(&self) -> Option<Section> {
        self.view.section.then(|| {
            let a = self.view.section_axis;
            let (lo, hi) = (self.geometry.lo[a], self.geometry.hi[a]);
            let position = lo + (hi - lo) * self.view.section_fraction;
            Section {
                axis: a,
                position,
                // cut away the half on the camera's side, so the cut face looks at the viewer
                facing: if self.camera.eye()[a] > position {
                    1.0
                } else {
                    -1.0
                },
            }
        })
    }

    fn mesh_inputs(&self) -> MeshInputs {
        MeshInputs {
            quantity: self.view.quantity,
            range: if self.view.fixed_range {
                Range::Fixed {
                    min: self.view.range_min,
                    max: self.view.range_max,
                }
            } else {
                Range::Auto
            },
            deform: if self.view.deformed {
                self.view.deform_scale
            } else {
                0.0
            },
            explode: if self.view.exploded {
                self.view.explode_amount
            } else {
                0.0
            },
            section: self.section(),
        }
    }

    /// Receives worker events and brings caches up to date (called once per frame).
    pub fn pump(&mut self) {
        for e in self.worker.poll() {
            self.handle(e);
        }
        // fields for the displayed step: the converged ones if cached, else the live iterate
        let exact = self
            .fields
            .get(&self.step)
            .filter(|_| self.fields_generation == self.last_done_generation())
            .cloned();
        match exact {
            Some(f) => self.shown = Some(f),
            None => {
                if self.busy() {
                    if let Some(l) = &self.live {
                        self.shown = Some(l.clone());
                    }
                } else if self.requested_step != Some(self.step) {
                    self.worker.request_fields(self.step);
                    self.requested_step = Some(self.step);
                }
            }
        }
    }

    fn last_done_generation(&self) -> u64 {
        self.reports
            .iter()
            .rev()
            .find(|r| !r.cancelled)
            .map_or(0, |r| r.generation)
    }

    fn handle(&mut self, e: Event) {
        match e {
            Event::Progress { generation, eta } => {
                self.convergence
                    .push([self.convergence.len() as f64 + 1.0, eta]);
                let iterations = match &self.status {
                    SolveStatus::Running {
                        generation: g,
                        iterations,
                        ..
                    } if *g == generation => iterations + 1,
                    _ => 1,
                };
                if generation == self.worker.generation() {
                    self.status = SolveStatus::Running {
                        generation,
                        iterations,
                        eta,
                    };
                }
            }
            Event::Fields(f) => {
                if f.live {
                    if f.generation == self.worker.generation() {
                        self.live = Some(f);
                    }
                } else {
                    if f.generation != self.fields_generation {
                        self.fields.clear();
                        self.fields_generation = f.generation;
                    }
                    if self.requested_step == Some(f.step) {
                        self.requested_step = None;
                    }
                    self.fields.insert(f.step, f);
                }
            }
            Event::Contact {
                generation,
                histories,
            } => {
                if generation == self.worker.generation() {
                    self.contact = Some(histories);
                }
            }
            Event::Finished(report) => {
                if report.generation == self.worker.generation() {
                    if report.converged {
                        self.last_latency = self.change_time.map(|t| t.elapsed().as_secs_f64());
                    }
                    self.live = None;
                    self.requested_step = None;
                    if let Some((s, n)) = self.probe {
                        self.probe_history = None;
                        self.worker.request_probe(s, n);
                    }
                    self.status = SolveStatus::Done(report.clone());
                }
                if let Some(m) = &mut self.measure {
                    m.on_finished(&report, self.last_latency);
                }
                self.reports.push(report);
            }
            Event::Probe(p) => {
                if Some((p.sub, p.node)) == self.probe {
                    self.probe_history = Some(p);
                }
            }
            Event::Recorded { target, .. } => {
                self.recorded_solves += 1;
                self.recording_target = Some(target);
            }
            Event::RecordFailed(msg) => self.error = Some(format!("recording: {msg}")),
            Event::Error(msg) => {
                self.error = Some(msg.clone());
                self.status = SolveStatus::Failed(msg);
            }
        }
    }

    fn rebuild_mesh_if_needed(&mut self) {
        let Some(f) = &self.shown else {
            return;
        };
        let inputs = self.mesh_inputs();
        let key = (
            Arc::as_ptr(f) as usize,
            self.contact.as_ref().map_or(0, |c| Arc::as_ptr(c) as usize),
            inputs,
        );
        if self.mesh_key == Some(key) {
            return;
        }
        let contact = self.contact.as_deref().map(Vec::as_slice);
        self.mesh = Arc::new(mesh_build::build(&self.geometry, f, contact, &inputs));
        self.mesh_version = MESH_VERSION.fetch_add(1, Ordering::Relaxed);
        self.mesh_key = Some(key);
    }

    fn advance_time(&mut self, dt: f64) {
        if !self.playing || self.info.steps == 0 {
            return;
        }
        // the whole run plays in about 4 seconds
        self.play_clock += dt * self.info.steps as f64 / 4.0;
        let advance = self.play_clock.floor() as usize;
        if advance > 0 {
            self.play_clock -= advance as f64;
            let next = (self.step + advance) % (self.info.steps + 1);
            self.set_step(next);
        }
        self.ctx.request_repaint();
    }

    fn frame_clock(&mut self) -> f64 {
        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        if dt > 0.0 {
            self.frame_intervals.push_back(dt);
            if self.frame_intervals.len() > 120 {
                self.frame_intervals.pop_front();
            }
        }
        let busy = self.busy();
        if let Some(m) = &mut self.measure {
            m.on_frame(dt, busy);
        }
        dt
    }

    /// Frames per second over the recent frames.
    pub fn fps(&self) -> Option<f64> {
        let n = self.frame_intervals.len();
        (n >= 5).then(|| n as f64 / self.frame_intervals.iter().sum::<f64>())
    }

    /// Lays out one frame (shared by eframe and the tests).
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let started = Instant::now();
        let dt = self.frame_clock();
        if dt > 0.0 {
            self.worker.set_frame_interval(dt);
        }
        self.pump();
        self.advance_time(dt.min(0.1));
        crate::panels::top_bar(self, ui);
        crate::panels::controls(self, ui);
        crate::timeline::show(self, ui);
        crate::plots::show(self, ui);
        // after the panels, so a change made in them is drawn in this same frame
        self.rebuild_mesh_if_needed();
        egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| crate::view3d::show(self, ui));
        self.resolve_if_changed();
        if self.worker.needs_frames() {
            // the solver runs on this thread (browser): the next frame goes on with it
            ui.ctx().request_repaint();
        }
        let (converged, busy) = (self.converged(), self.busy());
        if let Some(m) = &mut self.measure {
            m.on_ui_time(started.elapsed().as_secs_f64(), busy);
            match m.next_action(converged) {
                crate::measure::Action::Wait => {}
                crate::measure::Action::Nudge => {
                    if let Some(f) = self.params.friction {
                        self.params.friction = Some(if f >= 0.45 { 0.05 } else { f + 0.05 });
                    }
                }
                crate::measure::Action::Close => {
                    ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
                }
            }
            ui.ctx().request_repaint();
        }
        if let Some(name) = self.pending_scene.take() {
            self.load_scene(&name);
        }
    }
}

impl eframe::App for ExplorerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }
}
