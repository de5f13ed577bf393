//! What the explorer tells a web page about itself, so scripts (the end-to-end browser test,
//! the timing benchmark) can follow it without reading pixels: solver state, the newest solve's
//! parameters, iterations, η and latency, the displayed step and view options, and where the
//! controls a script clicks (friction and time slider rails, section and exploded checkboxes,
//! "pin A" and "side by side") and the viewports (one, or two side by side) are drawn, and
//! where the solver runs. The
//! web crate writes it into the page title and the `data-*` attributes of `#lopin-status`;
//! it is plain data, so the desktop tests check it too.

use crate::app::ExplorerApp;
use crate::solve_view::SolveStatus;

/// The explorer's state as a page shows it.
#[derive(Debug, Clone, PartialEq)]
pub struct PageReport {
    /// "starting", "solving", "converged", "not-converged" or "failed".
    pub state: &'static str,
    /// Scene name.
    pub scene: String,
    /// Generation of the newest parameter change (1 = the first solve).
    pub generation: u64,
    /// Friction coefficient of the newest request, if the scene has contact.
    pub friction: Option<f64>,
    /// Iterations of the newest finished solve (or so far, while solving).
    pub iterations: usize,
    /// Its last η.
    pub eta: f64,
    /// Whether the newest finished solve started warm.
    pub warm: bool,
    /// Seconds from the newest parameter change to its converged solve.
    pub latency_s: Option<f64>,
    /// Seconds the solver took for the newest finished solve (its side's wall time).
    pub solve_s: Option<f64>,
    /// Seconds in the engine's local and linear stages of the newest finished solve.
    pub engine_s: Option<f64>,
    /// Seconds the solver side spent building and factorizing the scene's operators.
    pub setup_s: Option<f64>,
    /// Whether the 3D view has fields to draw.
    pub drawn: bool,
    /// Displayed time step.
    pub step: usize,
    /// Step of the fields on screen, and whether they are a live iterate.
    pub shown_step: Option<(usize, bool)>,
    /// Whether the section is on.
    pub section: bool,
    /// Whether the exploded view is on.
    pub exploded: bool,
    /// Controls a script can click (see [`crate::layout::ControlRects`]): left, top, width, height in
    /// points (CSS pixels at zoom 1).
    pub controls: Vec<(&'static str, [f32; 4])>,
    /// The 3D view (side by side: the current configuration's viewport): left, top, width,
    /// height in points.
    pub view: Option<[f32; 4]>,
    /// The friction value pinned as "A" in the study panel.
    pub pinned: Option<f64>,
    /// Side by side, the pinned configuration's viewport: left, top, width, height in points.
    pub beside: Option<[f32; 4]>,
    /// Whether the pinned configuration's picture is drawn in it.
    pub beside_drawn: bool,
    /// Where the solver runs: "worker" (a Web Worker, [`crate::remote`]), "thread" (a solver
    /// thread) or "page" (the page's frames).
    pub solver: &'static str,
    /// The failure message, if any.
    pub error: Option<String>,
}

impl PageReport {
    /// The report of an explorer after its last frame.
    pub fn of(app: &ExplorerApp) -> PageReport {
        let solve = &app.solve;
        let (state, iterations, eta, warm) = match solve.status() {
            SolveStatus::Starting => ("starting", 0, f64::INFINITY, false),
            SolveStatus::Running {
                iterations, eta, ..
            } => ("solving", *iterations, *eta, false),
            SolveStatus::Done(r) if solve.busy() => ("solving", r.iterations, r.eta, r.warm),
            SolveStatus::Done(r) if r.converged => ("converged", r.iterations, r.eta, r.warm),
            SolveStatus::Done(r) => ("not-converged", r.iterations, r.eta, r.warm),
            SolveStatus::Failed(_) => ("failed", 0, f64::NAN, false),
        };
        let error = match solve.status() {
            SolveStatus::Failed(e) => Some(e.clone()),
            _ => solve.error().map(String::from),
        };
        let shown = app.cache.shown();
        let done = match solve.status() {
            SolveStatus::Done(r) => Some(r),
            _ => None,
        };
        PageReport {
            state,
            scene: app.info.name.clone(),
            generation: solve.generation(),
            friction: solve.requested().friction,
            iterations,
            eta,
            warm,
            latency_s: solve.last_latency(),
            solve_s: done.map(|r| r.solve_s),
            engine_s: done.map(|r| r.stages.local + r.stages.linear),
            setup_s: done.map(|r| r.stages.setup),
            drawn: shown.is_some(),
            step: app.clock.step(),
            shown_step: shown.map(|f| (f.step, f.live)),
            section: app.layout.view.section,
            exploded: app.layout.view.exploded,
            controls: app
                .layout
                .controls
                .iter()
                .map(|(k, r)| (k, rect4(r)))
                .collect(),
            view: app.layout.view_rect().map(rect4),
            pinned: app.study.pinned,
            beside: app.layout.beside_rect().map(rect4),
            beside_drawn: app.layout.beside_rect().is_some() && app.layout.beside().is_some(),
            solver: if solve.remote() {
                "worker"
            } else if cfg!(target_arch = "wasm32") {
                "page"
            } else {
                "thread"
            },
            error,
        }
    }

    /// The page title: scene, state, friction and iterations at a glance.
    pub fn title(&self) -> String {
        let f = self
            .friction
            .map(|f| format!(" f={f:.3}"))
            .unwrap_or_default();
        format!(
            "Lopin {}: {}{f} ({} it, eta {:.1e})",
            self.scene, self.state, self.iterations, self.eta
        )
    }

    /// Where a control is, if it was drawn.
    pub fn control(&self, name: &str) -> Option<[f32; 4]> {
        self.controls.iter().find(|(k, _)| *k == name).map(|c| c.1)
    }

    /// The controls as a JSON object of name → [left, top, width, height].
    pub fn controls_json(&self) -> String {
        let map: serde_json::Map<String, serde_json::Value> = self
            .controls
            .iter()
            .map(|(k, r)| (k.to_string(), serde_json::json!(r)))
            .collect();
        serde_json::Value::Object(map).to_string()
    }

    /// `data-*` attribute names and values of the status element.
    pub fn attributes(&self) -> Vec<(&'static str, String)> {
        let opt = |x: Option<f64>| x.map_or_else(String::new, |v| format!("{v}"));
        vec![
            ("data-state", self.state.to_string()),
            ("data-scene", self.scene.clone()),
            ("data-generation", self.generation.to_string()),
            ("data-friction", opt(self.friction)),
            ("data-iterations", self.iterations.to_string()),
            ("data-eta", format!("{:e}", self.eta)),
            ("data-warm", self.warm.to_string()),
            ("data-latency-s", opt(self.latency_s)),
            ("data-solve-s", opt(self.solve_s)),
            ("data-engine-s", opt(self.engine_s)),
            ("data-setup-s", opt(self.setup_s)),
            ("data-drawn", self.drawn.to_string()),
            ("data-step", self.step.to_string()),
            (
                "data-shown-step",
                self.shown_step
                    .map_or_else(String::new, |(s, _)| s.to_string()),
            ),
            (
                "data-shown-live",
                self.shown_step
                    .map_or_else(String::new, |(_, l)| l.to_string()),
            ),
            ("data-section", self.section.to_string()),
            ("data-exploded", self.exploded.to_string()),
            ("data-view", list4(self.view)),
            ("data-pinned", opt(self.pinned)),
            ("data-beside", list4(self.beside)),
            ("data-beside-drawn", self.beside_drawn.to_string()),
            ("data-controls", self.controls_json()),
            ("data-solver", self.solver.to_string()),
            ("data-error", self.error.clone().unwrap_or_default()),
        ]
    }
}

fn rect4(r: egui::Rect) -> [f32; 4] {
    [r.min.x, r.min.y, r.width(), r.height()]
}

fn list4(r: Option<[f32; 4]>) -> String {
    r.map(|r| format!("{},{},{},{}", r[0], r[1], r[2], r[3]))
        .unwrap_or_default()
}
