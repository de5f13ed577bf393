//! The explorer application: a thin composition of the scene (facts, geometry) and the
//! sub-states the panels borrow — [`SolveView`] (parameters, solver status, worker events),
//! [`FieldCache`] (fields on screen, contact histories, probe), [`StudyView`] (the background
//! study's stored configurations, the stand-in picture, the pinned configuration),
//! [`Recording`], [`Clock`] and [`Layout`] (view options, camera, drawn mesh) — with the
//! per-frame order: receive events, request the fields the screen needs, lay out the panels,
//! re-solve if a parameter moved (the nearest stored picture goes on screen at once), rebuild
//! the mesh (against the pinned configuration's picture for the difference field or side by
//! side), draw the 3D view (one viewport, or the pinned and the current configurations side by
//! side). The same type runs on the desktop (eframe, wgpu), in the browser
//! and in tests (egui_kittest).

use crate::clock::Clock;
use crate::field_cache::FieldCache;
use crate::geometry::SceneGeometry;
use crate::layout::{Against, Layout};
use crate::measure::{Action, FrameState, Measure};
use crate::params::{FrictionTargets, Params};
use crate::recorder::RecorderFactory;
use crate::recording::Recording;
use crate::remote::Connector;
use crate::result_folder::{FolderKind, FolderOpener, OpenedFolder, ResultTable, RowSource};
use crate::results_panel::ResultsView;
use crate::solve_view::SolveView;
use crate::stored_run::StoredRun;
use crate::study_view::{Compare, StudyView};
use crate::wire::Start;
use crate::worker::Worker;
use lopin_core::counters::Instant;
use lopin_core::scene;
use lopin_core::window_choice::Task;
use std::sync::Arc;

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
    /// Opens result folders (`scene` naming a folder, or the "open" field of the top bar);
    /// None: folders cannot be opened (the browser).
    pub opener: Option<FolderOpener>,
    /// Starts the solver behind a byte link (the browser's Web Worker) for scenes; None: a
    /// solver thread on the desktop, the page's own frames in a browser.
    pub connector: Option<Connector>,
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
            opener: None,
            connector: None,
        }
    }
}

/// What the explorer opens: a scene, solved cold first, or a result folder, whose first
/// configuration is shown from its stored state.
#[derive(Debug)]
pub enum Loaded {
    /// A scene.
    Scene(Box<scene::Opened>),
    /// A result folder.
    Folder(Box<OpenedFolder>),
    /// A run folder with stored step fields, opened without the scene.
    Stored(Box<StoredRun>),
}

/// What [`ExplorerApp::assemble`] puts together.
struct Parts {
    info: SceneInfo,
    geometry: SceneGeometry,
    solve: SolveView,
    results: Option<ResultsView>,
    friction_targets: FrictionTargets,
    recording: Recording,
    clock: Clock,
    stored: bool,
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

/// The explorer: the scene and its sub-states, composed once per frame.
pub struct ExplorerApp {
    options: Options,
    /// Scene facts.
    pub info: SceneInfo,
    /// Fixed geometry.
    pub geometry: Arc<SceneGeometry>,
    /// Parameters, solver status, convergence history and the worker.
    pub solve: SolveView,
    /// Fields on screen, contact histories and the probe.
    pub cache: FieldCache,
    /// The background study's configurations, the stand-in and the pinned configuration.
    pub study: StudyView,
    /// What the friction slider moves (every contact or one zone) and each one's value.
    pub friction_targets: FrictionTargets,
    /// The "record to Rerun" toggle.
    pub recording: Recording,
    /// Displayed time step, playback and frame timing.
    pub clock: Clock,
    /// View options, camera and the drawn mesh.
    pub layout: Layout,
    /// Scene chosen in the picker (loaded at the end of the frame).
    pub pending_scene: Option<String>,
    /// The opened result folder: its table, the row shown.
    pub results: Option<ResultsView>,
    /// The folder typed in the top bar's "open" field.
    pub folder_input: String,
    /// Folder to open at the end of the frame.
    pub pending_folder: Option<std::path::PathBuf>,
    /// Whether it shows a run opened from its stored fields (the parameters cannot move).
    pub stored: bool,
    /// Whether the GPU view is available (wgpu backend).
    gpu: bool,
    measure: Option<Measure>,
    ctx: egui::Context,
}

/// Opens what `options.scene` names: a result folder (a directory, read by `options.opener`)
/// or a scene ([`load_scene`]).
pub(crate) fn load(options: &Options) -> Result<Loaded, String> {
    let path = std::path::Path::new(&options.scene);
    if path.is_dir() {
        return open_folder(options, path);
    }
    load_scene(options)
        .map(|o| Loaded::Scene(Box::new(o)))
        .map_err(|e| e.to_string())
}

/// What the solver side calls after each event: a repaint of `ctx`.
fn repaint_wake(ctx: &egui::Context) -> Arc<dyn Fn() + Send + Sync> {
    let ctx = ctx.clone();
    Arc::new(move || ctx.request_repaint())
}

/// Opens a result folder with the options' opener.
fn open_folder(options: &Options, path: &std::path::Path) -> Result<Loaded, String> {
    let opener = options.opener.as_ref().ok_or_else(|| {
        format!(
            "{}: a folder; this explorer opens scenes only (result folders open in the desktop \
             explorer, `lopin view FOLDER`)",
            path.display()
        )
    })?;
    opener.open(path)
}

/// Opens a scene for the explorer ([`scene::open`] for the interactive task: one-step windows
/// on a scene with contact, else the whole interval, re-solved warm after each change), with its
/// options over the scene's `[solver]` table.
pub(crate) fn load_scene(options: &Options) -> lopin_core::Result<scene::Opened> {
    let overrides = scene::Overrides {
        solver: scene::spec::SolverSpec {
            two_scale: options.two_scale,
            ..Default::default()
        },
        ..scene::Overrides::for_task(Task::Interactive)
    };
    scene::open(&options.scene, &overrides)
}

impl ExplorerApp {
    /// Builds the explorer on a scene; the first (cold) solve starts at once in the background.
    pub fn new(cc: &eframe::CreationContext<'_>, options: Options) -> Result<Self, String> {
        let loaded = load(&options)?;
        Self::opened(cc, options, loaded)
    }

    /// [`Self::new`] on a scene already opened ([`load`]).
    pub(crate) fn opened(
        cc: &eframe::CreationContext<'_>,
        options: Options,
        loaded: Loaded,
    ) -> Result<Self, String> {
        let gpu = match &cc.wgpu_render_state {
            Some(rs) => {
                crate::render::install(rs);
                true
            }
            None => false,
        };
        Self::with_context(cc.egui_ctx.clone(), options, loaded, gpu)
    }

    fn with_context(
        ctx: egui::Context,
        options: Options,
        loaded: Loaded,
        gpu: bool,
    ) -> Result<Self, String> {
        let (opened, folder) = match loaded {
            Loaded::Scene(o) => (*o, None),
            Loaded::Stored(run) => return Self::with_stored(ctx, options, *run, gpu),
            Loaded::Folder(f) => {
                let f = *f;
                let OpenedFolder {
                    path,
                    kind,
                    scene,
                    table,
                    loader,
                    first,
                } = f;
                (scene, Some((path, kind, table, loader, first)))
            }
        };
        let scene::Opened {
            spec,
            problem,
            settings,
            ..
        } = opened;
        let geo = SceneGeometry::of(&problem);
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
        let base = Params::of(&problem, &settings);
        let mut friction_targets = FrictionTargets::of(&problem);
        let recording = Recording::new(options.recorder.clone(), &info.name);
        let rows = folder.as_ref().map(|(_, _, table, loader, _)| RowSource {
            rows: table.rows.iter().map(|r| r.assigned.clone()).collect(),
            loader: loader.clone(),
        });
        let wake = repaint_wake(&ctx);
        let remote = match (&options.connector, &rows) {
            (Some(connector), None) => {
                let start = Start {
                    scene: options.scene.clone(),
                    two_scale: options.two_scale,
                };
                let ctx = ctx.clone();
                let wake: crate::remote::Wake = Arc::new(move |within| match within {
                    Some(d) => ctx.request_repaint_after(d),
                    None => ctx.request_repaint(),
                });
                // without a solver side (a page that cannot start workers), the solver runs
                // in the UI's frames
                Worker::spawn_remote(start, wake, connector).ok()
            }
            _ => None,
        };
        let worker = match remote {
            Some(w) => w,
            None => Worker::spawn_with_rows(problem, settings, wake, recording.slot(), rows)
                .map_err(|e| e.to_string())?,
        };
        let clock = Clock::new(info.steps, info.dt, worker.display_step());
        let (solve, results) = match folder {
            None => (SolveView::start(worker, base), None),
            Some((path, kind, table, _, first)) => {
                let results = ResultsView::new(path, kind, table, base, first);
                let params = results.params_of(first);
                results.give_friction(first, &mut friction_targets);
                let name = results.row_name(first);
                let solve = SolveView::start_row(worker, params, first, name);
                (solve, Some(results))
            }
        };
        let parts = Parts {
            info,
            geometry: geo,
            solve,
            results,
            friction_targets,
            recording,
            clock,
            stored: false,
        };
        Ok(Self::assemble(ctx, options, parts, gpu))
    }

    /// The explorer on a run opened from its stored fields: its one row shown from the
    /// store, the parameters fixed.
    fn with_stored(
        ctx: egui::Context,
        options: Options,
        run: StoredRun,
        gpu: bool,
    ) -> Result<Self, String> {
        let worker = Worker::spawn_stored(&run, repaint_wake(&ctx)).map_err(|e| e.to_string())?;
        let clock = Clock::new(run.info.steps, run.info.dt, worker.display_step());
        let table = ResultTable::single_run(run.outcome.iterations, run.outcome.converged);
        let results = ResultsView::new(run.path, FolderKind::Run, table, run.params.clone(), 0);
        let solve = SolveView::start_row(worker, run.params, 0, "run".into());
        let parts = Parts {
            recording: Recording::new(None, &run.info.name),
            info: run.info,
            geometry: run.geometry,
            solve,
            results: Some(results),
            friction_targets: run.friction_targets,
            clock,
            stored: true,
        };
        Ok(Self::assemble(ctx, options, parts, gpu))
    }

    /// The explorer from its parts, the study, layout and measurement made for them.
    fn assemble(ctx: egui::Context, options: Options, parts: Parts, gpu: bool) -> Self {
        let study = StudyView::new(parts.solve.params());
        let layout = Layout::new(&parts.geometry);
        let measure = options.measure.clone().map(|path| {
            let mut m = if parts.stored {
                Measure::stored(path)
            } else {
                Measure::new(path)
            };
            m.set_triangles(parts.geometry.assembled_triangle_count());
            m
        });
        let record = options.record && !parts.stored;
        let mut app = ExplorerApp {
            options,
            info: parts.info,
            geometry: Arc::new(parts.geometry),
            solve: parts.solve,
            cache: FieldCache::default(),
            study,
            friction_targets: parts.friction_targets,
            recording: parts.recording,
            clock: parts.clock,
            layout,
            pending_scene: None,
            results: parts.results,
            folder_input: String::new(),
            pending_folder: None,
            stored: parts.stored,
            gpu,
            measure,
            ctx,
        };
        if record {
            app.set_recording(true);
        }
        app
    }

    /// Counts the measurement's time to the first converged picture from `t` (when the scene or
    /// folder began to load).
    pub fn measure_from(&mut self, t: Instant) {
        if let Some(m) = &mut self.measure {
            m.opened_at(t);
        }
    }

    /// Switches recording on (a recorder is made for this scene and the newest converged
    /// solution is recorded at once, then every later one) or off (the recording is closed).
    pub fn set_recording(&mut self, on: bool) {
        if let Err(e) = self.recording.set(on, self.solve.worker()) {
            self.solve.set_error(e);
        }
    }

    /// Replaces the scene (from the picker); on failure the current one stays and the error is
    /// shown.
    pub fn load_scene(&mut self, name_or_path: &str) {
        let recording = self.recording.is_on();
        let options = Options {
            scene: name_or_path.into(),
            record: recording,
            ..self.options.clone()
        };
        // the old scene's recording is complete before the new scene's starts
        self.recording.stop();
        match load(&options)
            .and_then(|l| Self::with_context(self.ctx.clone(), options, l, self.gpu))
        {
            Ok(app) => *self = app,
            Err(e) => {
                self.solve.set_error(e);
                if recording {
                    self.set_recording(true);
                }
            }
        }
    }

    /// Opens a result folder (the top bar's "open" field); on failure the current scene or
    /// folder stays and the error is shown.
    pub fn load_folder(&mut self, path: &std::path::Path) {
        let recording = self.recording.is_on();
        let options = Options {
            scene: path.display().to_string(),
            record: recording,
            ..self.options.clone()
        };
        let loaded = if path.is_dir() {
            open_folder(&options, path)
        } else {
            Err(format!("{}: not a folder", path.display()))
        };
        self.recording.stop();
        match loaded.and_then(|l| Self::with_context(self.ctx.clone(), options, l, self.gpu)) {
            Ok(app) => *self = app,
            Err(e) => {
                self.solve.set_error(e);
                if recording {
                    self.set_recording(true);
                }
            }
        }
    }

    /// Shows row `r` of the opened result folder: its stored solution, or a warm solve from its
    /// stored state; the controls take its parameter values.
    pub fn show_row(&mut self, r: usize) {
        let Some(results) = &mut self.results else {
            return;
        };
        if r >= results.table.rows.len() {
            return;
        }
        results.shown = Some(r);
        let params = results.params_of(r);
        results.give_friction(r, &mut self.friction_targets);
        let name = results.row_name(r);
        let generation = self.solve.show_row(params, r, name);
        let step = self.clock.step();
        self.study
            .on_request(generation, self.solve.requested(), step, &mut self.cache);
    }

    /// Picks a node for the probe.
    pub fn set_probe(&mut self, sub: usize, node: usize) {
        self.cache.set_probe(sub, node, self.solve.worker());
    }

    /// Releases the solve requested in the previous frame, receives worker events and brings
    /// caches up to date (called once per frame).
    pub fn pump(&mut self) {
        self.solve.release_held();
        self.solve.apply_events(
            &mut self.cache,
            &mut self.recording,
            &mut self.study,
            self.measure.as_mut(),
        );
        self.show_displayed_step();
        let (busy, newest) = (self.solve.busy(), self.solve.generation());
        let stale = self
            .study
            .stand_in
            .is_some_and(|s| s.generation != newest || !busy);
        if stale {
            self.study.stand_in = None;
        }
    }

    /// Puts the displayed step's fields on screen: the converged ones if cached (else asked
    /// for), or the live iterate.
    fn show_displayed_step(&mut self) {
        let (busy, done) = (self.solve.busy(), self.solve.last_done_generation());
        let newest = self.solve.generation();
        self.cache
            .show_step(self.clock.step(), busy, done, newest, self.solve.worker());
    }

    /// What this frame finds, for the measurement.
    fn frame_state(&self) -> FrameState {
        FrameState {
            busy: self.solve.busy(),
            converged: self.solve.converged(),
            background: !self.study.running().is_empty(),
            study_complete: self.study.complete(),
        }
    }

    /// The note over the 3D view: the stand-in shown while a re-solve refines it, or what is
    /// compared.
    fn view_note(&self) -> Option<String> {
        let compare = match (self.study.compare, self.study.pinned) {
            (Compare::Difference, Some(a)) => Some(if self.layout.mesh().difference {
                format!("difference: current − A (f = {a:.3})")
            } else {
                format!("A (f = {a:.3}) has no picture at this step yet: current shown")
            }),
            _ => None,
        };
        let stand_in = self.study.stand_in.map(|s| {
            if s.exact {
                format!("stored: f = {:.3}", s.value)
            } else {
                format!("nearest stored: f = {:.3}, refining", s.value)
            }
        });
        match (stand_in, compare) {
            (Some(a), Some(b)) => Some(format!("{a}\n{b}")),
            (a, b) => a.or(b),
        }
    }

    /// Lays out one frame (shared by eframe and the tests).
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let started = Instant::now();
        let dt = self.clock.frame();
        let previous = self.frame_state();
        if let Some(m) = &mut self.measure {
            m.on_frame(dt, previous);
        }
        if dt > 0.0 {
            self.solve.worker().set_frame_interval(dt);
        }
        self.pump();
        // the measurement's slider move arrives with this frame, as a user's would
        let mut close = false;
        if let Some(m) = &mut self.measure {
            match m.next_action(previous) {
                Action::Wait => {}
                Action::Move(f) => {
                    if let Some(p) = &mut self.solve.params_mut().friction {
                        *p = f;
                    }
                }
                Action::Orbit(px) => self.layout.camera.orbit(px, 0.0),
                Action::Scrub(at) => {
                    let steps = self.clock.steps();
                    self.clock.set_step((at * steps as f64).round() as usize);
                    m.on_scrub(self.clock.step());
                }
                Action::Close => close = true,
            }
        }
        if self.clock.advance(dt.min(0.1)) {
            self.ctx.request_repaint();
        }
        let reproducible = self.options.reproducible;
        let folder_field = self
            .options
            .opener
            .is_some()
            .then_some(&mut self.folder_input);
        match crate::panels::top_bar(ui, &self.info, &self.solve, reproducible, folder_field) {
            Some(crate::panels::Picked::Scene(name)) => self.pending_scene = Some(name),
            Some(crate::panels::Picked::Folder(path)) => self.pending_folder = Some(path),
            None => {}
        }
        let mut row_clicked = None;
        crate::panels::left(ui, |ui| {
            if let Some(results) = &mut self.results {
                row_clicked = crate::results_panel::show(ui, results);
                ui.separator();
            }
            if self.stored {
                ui.label(
                    "Stored fields: the run's own parameter values (`lopin view SCENE` \
                     re-solves the scene)",
                );
            }
            ui.add_enabled_ui(!self.stored, |ui| {
                crate::panels::parameters(
                    ui,
                    self.solve.params_mut(),
                    &mut self.friction_targets,
                    &mut self.layout.controls,
                );
                if self.stored {
                    return;
                }
                ui.separator();
                let friction = self.solve.params().friction;
                let label = self.solve.params().friction_label();
                crate::study_panel::show(
                    ui,
                    &mut self.study,
                    friction,
                    &label,
                    &mut self.layout.controls,
                );
            });
            ui.separator();
            crate::panels::view_options(ui, &mut self.layout, &self.info);
            ui.separator();
            crate::panels::recording(ui, &mut self.recording, &mut self.solve);
            ui.separator();
            crate::panels::sizes(
                ui,
                &self.info,
                &self.geometry,
                &self.solve,
                &self.clock,
                reproducible,
            );
        });
        if let Some(r) = row_clicked {
            self.show_row(r);
        } else if self.results.is_some() && self.solve.params() != self.solve.requested() {
            // a control moved away from the row shown
            if let Some(results) = &mut self.results {
                results.shown = None;
            }
        }
        crate::timeline::show(ui, &mut self.clock, &mut self.layout.controls);
        // a step moved in this frame is asked for now, not a frame later
        self.show_displayed_step();
        crate::plots::show(ui, &self.solve, &self.cache, &self.clock, &self.info);
        // after the panels, so a change made in them is drawn in this same frame: a new request
        // puts the nearest stored picture on screen at once
        if let Some(generation) = self.solve.resolve_if_changed() {
            // the solve is released at the start of the next frame: ask for it
            ui.ctx().request_repaint();
            let step = self.clock.step();
            self.study
                .on_request(generation, self.solve.requested(), step, &mut self.cache);
            if let Some(m) = &mut self.measure {
                m.on_request(generation);
            }
        }
        self.study.sync(self.solve.worker());
        let pinned = match self.study.compared() {
            Some(_) => self.study.pinned_drawn(self.clock.step()),
            None => None,
        };
        let against = match (self.study.compare, &pinned) {
            (Compare::Difference, Some(d)) => Against::Minus(d),
            (Compare::SideBySide, Some(d)) => Against::Beside(d),
            _ => Against::Nothing,
        };
        let rebuilt = self
            .layout
            .rebuild_mesh_if_needed(&self.geometry, &self.cache, against);
        if let (true, Some(m), Some(f)) = (rebuilt, &mut self.measure, self.cache.shown()) {
            m.on_mesh(f.generation, f.live, f.step);
        }
        let note = self.view_note();
        let labels = self.study.side_by_side().map(|a| {
            let b = self.solve.requested().friction.unwrap_or(f64::NAN);
            let f = self.solve.requested().friction_label();
            (format!("A: {f} = {a:.3}"), format!("B: {f} = {b:.3}"))
        });
        let side = labels
            .as_ref()
            .map(|(a, b)| crate::view3d::SideBySide { a, b });
        let picked = egui::CentralPanel::default()
            .frame(egui::Frame::NONE)
            .show(ui, |ui| {
                crate::view3d::show(
                    ui,
                    &mut self.layout,
                    &self.geometry,
                    self.gpu,
                    note.as_deref(),
                    side,
                )
            })
            .inner;
        if let Some((sub, node)) = picked {
            self.set_probe(sub, node);
        }
        if self.solve.needs_frames() {
            // the solver runs on this thread (browser): the next frame goes on with it
            ui.ctx().request_repaint();
        } else if let Some(wait) = self.solve.worker().idle_wait() {
            // the background study starts once the user has been idle long enough
            ui.ctx().request_repaint_after(wait);
        }
        let now = self.frame_state();
        if let Some(m) = &mut self.measure {
            m.on_ui_time(started.elapsed().as_secs_f64(), now);
            if close {
                ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
            }
            ui.ctx().request_repaint();
        }
        if let Some(name) = self.pending_scene.take() {
            self.load_scene(&name);
        }
        if let Some(path) = self.pending_folder.take() {
            self.load_folder(&path);
        }
    }
}

impl eframe::App for ExplorerApp {
    /// The panels' colour: from the next frame they are drawn without a fill over it
    /// ([`crate::panels::panel_frame`]).
    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        crate::panels::mark_cleared_to_panel_fill(&self.ctx);
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut egui::Ui, frame: &mut eframe::Frame) {
        // the last frame's time in egui and the painter, vsync waiting excluded
        if let (true, Some(cpu)) = (self.measure.is_some(), frame.info().cpu_usage) {
            let state = self.frame_state();
            if let Some(m) = &mut self.measure {
                m.on_cpu_time(f64::from(cpu), state);
            }
        }
        self.frame(ui);
    }
}
