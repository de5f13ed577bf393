//! The explorer under random use, driven with egui_kittest (wgpu on the software Vulkan
//! driver): a seeded sequence of user actions — slider drags past both ends of the rail, values
//! set and typed at the extremes (NaN, ±inf, ±1e300, text that is no number), scene switches
//! while a solve and the background study run, pin and unpin, the comparison modes (side by
//! side), section, exploded and deformed views, time scrubbing and playback, probe clicks and
//! camera moves in the 3D view, pausing the study, combo boxes, keys, window resizes (to a
//! tiny window too), clicks, drags and scrolls anywhere, waits for the solve and the study,
//! and a refused value put right — over `two-blocks`, `granular-small` and `granular-poly`
//! (meshed by gmsh).
//!
//! Checked all along: no panic on any thread, every frame draws the window (shapes and the 3D
//! view's paint callback, two side by side), a rendered frame now and then, every finished
//! solve converged, was cancelled or spent its iteration limit with a finite η (settings at the
//! ends of their sliders that LATIN does not converge in max_iter iterations; a value the solver
//! refuses fails with its message, and never a solve midway), and at the end, with the scene's
//! values back, a converged solve.
//!
//! `LOPIN_UI_SEED` picks the sequence (decimal or 0x-hexadecimal; default fixed) and
//! `LOPIN_UI_ACTIONS` its length. A failure prints the seed and the last actions, and writes
//! every action to `random_use-SEED.log` in Cargo's test temporary folder. Every choice comes
//! from the seed, but what a choice meets (a widget shown only once a solve converged, the
//! study's progress) depends on how far the solver got: a replay follows the same path until
//! timing first changes what is on screen, and the log says what each action did.

use common::{harness, settle};
use egui::{Event, Key, Modifiers, PointerButton, Pos2, Rect, Role, Vec2};
use egui_kittest::kittest::{By, NodeT, Queryable};
use lopin_core::splitmix::SplitMix64;
use lopin_explorer::params::Params;
use lopin_explorer::quantity::Quantity;
use lopin_explorer::solve_view::SolveStatus;
use lopin_explorer::ExplorerApp;
use std::fmt::Write as _;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

mod common;

type H = egui_kittest::Harness<'static, ExplorerApp>;

/// The scenes visited: the two demos and a scene meshed by gmsh.
const SCENES: [&str; 3] = ["two-blocks", "granular-small", "granular-poly"];
/// The sequence when `LOPIN_UI_SEED` is not set.
const DEFAULT_SEED: u64 = 20_240_917;
/// Actions when `LOPIN_UI_ACTIONS` is not set.
const DEFAULT_ACTIONS: usize = 2000;
/// The harness's window, points (see `common::harness`).
const WINDOW: Vec2 = Vec2::new(1400.0, 860.0);
/// Window sizes a resize picks (the harness's own more often), points.
const SIZES: [Vec2; 9] = [
    WINDOW,
    WINDOW,
    WINDOW,
    Vec2::new(1920.0, 1080.0),
    Vec2::new(1024.0, 700.0),
    Vec2::new(640.0, 480.0),
    Vec2::new(400.0, 300.0),
    Vec2::new(300.0, 200.0),
    Vec2::new(90.0, 60.0),
];
/// A frame is rendered (lavapipe) every this many actions, and after each scene switch.
const RENDER_EVERY: usize = 100;
/// The longest wait for a solve inside the sequence (a "wait for the solve" action).
const SOLVE_WAIT: Duration = Duration::from_secs(5);
/// The longest wait for the background study to start (the user is idle).
const STUDY_WAIT: Duration = Duration::from_secs(2);

/// Values set on a slider through AccessKit, besides its own ends.
const EXTREME_VALUES: [f64; 12] = [
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    1e300,
    -1e300,
    f64::MAX,
    f64::MIN_POSITIVE,
    1e-300,
    0.0,
    -0.0,
    -1.0,
    1e9,
];

/// Text typed into a value box.
const TYPED: [&str; 26] = [
    "0",
    "-0",
    "1",
    "-1",
    "0.5",
    "1e300",
    "-1e300",
    "1e-300",
    "1e308",
    "1.8e308",
    "NaN",
    "nan",
    "inf",
    "-inf",
    "infinity",
    "abc",
    "",
    "   ",
    "−2",
    "1 000",
    "99999999999999999999",
    "0x10",
    "3.",
    ".",
    "-",
    "1e",
];

/// Checkboxes toggled by name.
const CHECKBOXES: [&str; 6] = [
    "section",
    "exploded",
    "deformed ×",
    "macro problem (two-scale)",
    "wave-matched search direction",
    "pause background study",
];

/// Radio buttons clicked by name.
const RADIOS: [&str; 8] = [
    "x",
    "y",
    "z",
    "auto range",
    "fixed",
    "current",
    "current − A",
    "side by side",
];

/// Buttons clicked by name.
const BUTTONS: [&str; 7] = ["pin A", "unpin", "play", "pause", "<", ">", "reset view"];

/// Keys pressed on their own.
const KEYS: [Key; 9] = [
    Key::Tab,
    Key::Enter,
    Key::Escape,
    Key::Space,
    Key::ArrowLeft,
    Key::ArrowRight,
    Key::ArrowUp,
    Key::Home,
    Key::End,
];

/// Panics on any thread (the solver's included) since the hook was installed.
static PANICS: Mutex<Vec<String>> = Mutex::new(Vec::new());

/// Records every panic, then reports it as the default hook does.
fn watch_panics() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let thread = std::thread::current().name().unwrap_or("?").to_string();
        if let Ok(mut p) = PANICS.lock() {
            p.push(format!("thread '{thread}': {info}"));
        }
        default(info);
    }));
}

/// The model's SplitMix64: small, seeded, the same on every platform.
struct Rng(SplitMix64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0.next_u64()
    }

    /// In [0, n).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }

    /// In [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    fn chance(&mut self, p: f32) -> bool {
        self.unit() < p
    }

    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }

    /// A point of `r`, `margin` points inside its edges where it is wide enough.
    fn point_in(&mut self, r: Rect, margin: f32) -> Pos2 {
        let m = margin.min(r.width() / 2.0).min(r.height() / 2.0).max(0.0);
        let r = r.shrink(m);
        Pos2::new(
            r.left() + self.unit() * r.width(),
            r.top() + self.unit() * r.height(),
        )
    }
}

/// A widget of the last frame, as AccessKit describes it.
#[derive(Debug, Clone)]
struct Widget {
    role: Role,
    label: String,
    rect: Rect,
    min: Option<f64>,
    max: Option<f64>,
}

/// Every widget of the last frame with a role worth clicking.
fn widgets(h: &H) -> Vec<Widget> {
    h.query_all(By::new().predicate(|n| {
        matches!(
            n.role(),
            Role::Button
                | Role::CheckBox
                | Role::RadioButton
                | Role::ComboBox
                | Role::Slider
                | Role::SpinButton
                | Role::TextInput
                | Role::Canvas
        )
    }))
    .filter_map(|n| {
        let a = n.accesskit_node();
        let b = a.bounding_box()?;
        Some(Widget {
            role: a.role(),
            label: a.label().unwrap_or_default(),
            rect: Rect::from_min_max(
                Pos2::new(b.x0 as f32, b.y0 as f32),
                Pos2::new(b.x1 as f32, b.y1 as f32),
            ),
            min: a.min_numeric_value(),
            max: a.max_numeric_value(),
        })
    })
    .collect()
}

fn absent(done: bool) -> &'static str {
    if done {
        ""
    } else {
        " (absent)"
    }
}

fn find<'a>(ws: &'a [Widget], role: Role, label: &str) -> Option<&'a Widget> {
    ws.iter().find(|w| w.role == role && w.label == label)
}

/// What a run did, for the summary.
#[derive(Debug, Default)]
struct Tally {
    frames: usize,
    renders: usize,
    converged: usize,
    cancelled: usize,
    /// Solves that spent their iteration limit.
    unconverged: usize,
    refused: usize,
    refusals: Vec<String>,
    switches: usize,
    switches_while_solving: usize,
    switches_while_studying: usize,
    probes: usize,
    typed: usize,
    side_by_side_frames: usize,
    visited: Vec<String>,
    /// Actions and seconds spent, by the first word of their description.
    time: std::collections::BTreeMap<String, (usize, f64)>,
}

/// One seeded run: the harness, the sequence and what was checked.
struct Run {
    h: H,
    rng: Rng,
    seed: u64,
    actions: usize,
    /// Every action done, in order.
    log: Vec<String>,
    tally: Tally,
    /// The session on screen (the scene geometry's address changes with each load).
    session: usize,
    /// Reports of this session already checked.
    checked: usize,
    /// The newest failure message seen in this session.
    failure: Option<String>,
    /// The parameter values the session's scene started with.
    initial: Option<Params>,
    /// The window's size, points.
    window: Vec2,
    started: Instant,
}

impl Drop for Run {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            return;
        }
        let written = self.write_log();
        let from = self.log.len().saturating_sub(40);
        let mut last = String::new();
        for (i, a) in self.log.iter().enumerate().skip(from) {
            let _ = writeln!(last, "  {i:5} {a}");
        }
        eprintln!(
            "random UI use FAILED: LOPIN_UI_SEED={} LOPIN_UI_ACTIONS={} (action {} of {}, frame \
             {}, {:.0} s in)\nlast actions:\n{last}every action: {written}",
            self.seed,
            self.actions,
            self.log.len(),
            self.actions,
            self.tally.frames,
            self.started.elapsed().as_secs_f64(),
        );
    }
}

impl Run {
    fn new(seed: u64, actions: usize) -> Run {
        let mut run = Run {
            h: harness(SCENES[0]),
            rng: Rng(SplitMix64(seed)),
            seed,
            actions,
            log: Vec::new(),
            tally: Tally::default(),
            session: 0,
            checked: 0,
            failure: None,
            initial: None,
            window: WINDOW,
            started: Instant::now(),
        };
        run.frame();
        run
    }

    /// Writes every action so far to `random_use-SEED.log` in Cargo's test temporary folder;
    /// returns where.
    fn write_log(&self) -> String {
        let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
            .join(format!("random_use-{}.log", self.seed));
        let mut text = format!(
            "LOPIN_UI_SEED={} LOPIN_UI_ACTIONS={}\n",
            self.seed, self.actions
        );
        for (i, a) in self.log.iter().enumerate() {
            let _ = writeln!(text, "{i:5} {a}");
        }
        match std::fs::write(&path, text) {
            Ok(()) => path.display().to_string(),
            Err(e) => format!("(not written to {}: {e})", path.display()),
        }
    }

    fn app(&self) -> &ExplorerApp {
        self.h.state()
    }

    /// Where the current configuration's viewport was drawn.
    fn view(&self) -> Rect {
        self.app().layout.view_rect().unwrap_or(Rect::from_min_max(
            Pos2::new(300.0, 60.0),
            self.window.to_pos2(),
        ))
    }

    /// The left panel's visible part (below the top bar).
    fn left_panel(&self) -> Rect {
        Rect::from_min_max(
            Pos2::new(0.0, self.view().top()),
            Pos2::new(self.view().left().min(300.0), self.window.y),
        )
    }

    /// Runs one frame (no event, or the one queued) and checks it.
    fn frame(&mut self) {
        self.h.step();
        self.tally.frames += 1;
        self.check_frame();
    }

    /// Sends one event in a frame of its own.
    fn event(&mut self, e: Event) {
        self.h.event(e);
        self.frame();
    }

    fn check_frame(&mut self) {
        if let Ok(p) = PANICS.lock() {
            assert!(p.is_empty(), "a thread panicked: {}", p.join("\n"));
        }
        // the window is drawn: shapes, and the 3D view's paint callback in each viewport
        let output = self.h.output();
        assert!(!output.shapes.is_empty(), "a frame without shapes");
        let callbacks: Vec<Rect> = output
            .shapes
            .iter()
            .filter_map(|s| match &s.shape {
                egui::Shape::Callback(c) => Some(c.rect),
                _ => None,
            })
            .collect();
        assert!(
            !callbacks.is_empty(),
            "a frame without the 3D view's paint callback"
        );
        // (a tiny window leaves the view no room)
        assert!(
            self.window.min_elem() < 400.0
                || callbacks
                    .iter()
                    .all(|r| r.width() > 1.0 && r.height() > 1.0),
            "a viewport of no size: {callbacks:?}"
        );
        let app = self.h.state();
        if app.layout.beside_rect().is_some() && app.layout.beside().is_some() {
            self.tally.side_by_side_frames += 1;
            assert!(
                callbacks.len() >= 2,
                "side by side with one viewport drawn: {callbacks:?}"
            );
        }
        // a new session (scene loaded): its own reports, its own starting values
        let session = Arc::as_ptr(&app.geometry) as usize;
        if session != self.session || app.solve.reports().len() < self.checked {
            self.session = session;
            self.checked = 0;
            self.failure = None;
            self.initial = Some(app.solve.params().clone());
            if !self.tally.visited.contains(&app.info.name) {
                self.tally.visited.push(app.info.name.clone());
            }
        }
        // every solve that ended converged, was cancelled, or spent its iteration limit with a
        // finite η (settings at the ends of their sliders, such as k at its least with the
        // tolerance at its tightest, that LATIN does not converge in max_iter iterations: the
        // top bar says so)
        let reports = app.solve.reports();
        for r in &reports[self.checked..] {
            let spent = r.eta.is_finite() && r.iterations >= r.params.settings.max_iter;
            assert!(
                r.converged || r.cancelled || spent,
                "a solve ended neither converged nor cancelled nor at its iteration limit: {r:?}"
            );
            if r.converged {
                self.tally.converged += 1;
            } else if r.cancelled {
                self.tally.cancelled += 1;
            } else {
                self.tally.unconverged += 1;
            }
        }
        self.checked = reports.len();
        // a failure is a refused value, not a solve that broke down midway
        if let SolveStatus::Failed(msg) = app.solve.status() {
            if self.failure.as_deref() != Some(msg.as_str()) {
                assert!(
                    !msg.starts_with("non-finite value during the solve")
                        && !msg.starts_with("probe:"),
                    "the solve failed: {msg}"
                );
                self.failure = Some(msg.clone());
                self.tally.refused += 1;
                if !self.tally.refusals.contains(msg) && self.tally.refusals.len() < 20 {
                    self.tally.refusals.push(msg.clone());
                }
            }
        }
    }

    /// Renders the last frame (the paint callbacks run on the software Vulkan driver) and
    /// checks the 3D view is not one flat colour.
    fn render(&mut self) {
        let t = Instant::now();
        let view = self.view();
        let image = self
            .h
            .render()
            .unwrap_or_else(|e| panic!("the frame does not render: {e}"));
        self.tally.renders += 1;
        let (w, h) = image.dimensions();
        let scale = w as f32 / self.window.x;
        let mut colours = std::collections::HashSet::new();
        let (x0, x1) = ((view.left() * scale) as u32, (view.right() * scale) as u32);
        let (y0, y1) = ((view.top() * scale) as u32, (view.bottom() * scale) as u32);
        for y in (y0..y1.min(h)).step_by(7) {
            for x in (x0..x1.min(w)).step_by(7) {
                colours.insert(image.get_pixel(x, y).0);
            }
        }
        assert!(
            colours.len() > 3 || view.width().min(view.height()) < 200.0,
            "the rendered 3D view is flat: {} colours",
            colours.len()
        );
        let e = self.tally.time.entry("(render)".into()).or_default();
        e.0 += 1;
        e.1 += t.elapsed().as_secs_f64();
    }

    /// Frames while `busy` holds and `limit` has not passed, the solver working meanwhile;
    /// whether `busy` ended.
    fn frames_while(&mut self, limit: Duration, busy: impl Fn(&ExplorerApp) -> bool) -> bool {
        let t = Instant::now();
        while busy(self.app()) && t.elapsed() < limit {
            self.frame();
            std::thread::sleep(Duration::from_millis(8));
        }
        !busy(self.app())
    }

    /// Frames for `d` of wall time.
    fn wait(&mut self, d: Duration) {
        self.frames_while(d, |_| true);
    }

    /// Frames until the newest request ended (solved, refused) or `limit` passed.
    fn wait_for_solve(&mut self, limit: Duration) -> bool {
        self.frames_while(limit, |app| app.solve.busy())
    }

    /// Frames until the background study solves a value or `limit` passed.
    fn wait_for_study(&mut self, limit: Duration) -> bool {
        self.frames_while(limit, |app| app.study.running().is_empty())
    }

    /// A click at `pos`: pointer there, pressed, released, a frame each.
    fn click_at(&mut self, pos: Pos2, button: PointerButton, modifiers: Modifiers) {
        self.event(Event::PointerMoved(pos));
        for pressed in [true, false] {
            self.event(Event::PointerButton {
                pos,
                button,
                pressed,
                modifiers,
            });
        }
    }

    /// A drag from `a` to `b` through `steps` moves.
    fn drag(
        &mut self,
        a: Pos2,
        b: Pos2,
        button: PointerButton,
        modifiers: Modifiers,
        steps: usize,
    ) {
        self.event(Event::PointerMoved(a));
        self.event(Event::PointerButton {
            pos: a,
            button,
            pressed: true,
            modifiers,
        });
        for k in 1..=steps {
            let t = k as f32 / steps as f32;
            self.event(Event::PointerMoved(a + (b - a) * t));
        }
        self.event(Event::PointerButton {
            pos: b,
            button,
            pressed: false,
            modifiers,
        });
    }

    fn key(&mut self, key: Key, modifiers: Modifiers) {
        for pressed in [true, false] {
            self.event(Event::Key {
                key,
                physical_key: None,
                pressed,
                repeat: false,
                modifiers,
            });
        }
    }

    fn wheel(&mut self, at: Pos2, delta: Vec2) {
        self.event(Event::PointerMoved(at));
        self.event(Event::MouseWheel {
            unit: egui::MouseWheelUnit::Point,
            delta,
            phase: egui::TouchPhase::Move,
            source: egui::MouseWheelSource::Wheel,
            modifiers: Modifiers::NONE,
        });
    }

    /// The widget `role`/`label` where it can be clicked: a widget of the left panel scrolled
    /// out of view is brought into it first (as a user scrolls to it).
    fn reach(&mut self, role: Role, label: &str) -> Option<Widget> {
        let ws = widgets(&self.h);
        let w = find(&ws, role, label)?.clone();
        let panel = self.left_panel();
        if w.rect.center().x < panel.right() && !panel.contains_rect(w.rect) {
            {
                let node =
                    self.h
                        .query_all(By::new().predicate(|n| {
                            n.role() == role && n.label().as_deref() == Some(label)
                        }));
                if let Some(n) = node.into_iter().next() {
                    n.scroll_to_me();
                }
            }
            self.frame();
            self.frame();
            let ws = widgets(&self.h);
            return find(&ws, role, label).cloned();
        }
        Some(w)
    }

    fn click_widget(&mut self, role: Role, label: &str) -> bool {
        match self.reach(role, label) {
            Some(w) => {
                self.click_at(w.rect.center(), PointerButton::Primary, Modifiers::NONE);
                true
            }
            None => false,
        }
    }

    /// The value box of the slider at `rail` (to its right, on its line).
    fn value_box(&self, rail: Rect) -> Option<Widget> {
        widgets(&self.h)
            .into_iter()
            .filter(|w| {
                w.role == Role::SpinButton
                    && w.rect.left() >= rail.right() - 1.0
                    && (w.rect.center().y - rail.center().y).abs() < rail.height().max(8.0)
            })
            .min_by(|a, b| a.rect.left().total_cmp(&b.rect.left()))
    }

    /// Clicks a value box, types `text` and ends the edit: Enter, Escape, Tab or a click
    /// elsewhere. Returns how it ended.
    fn type_into(&mut self, w: &Widget, text: &str) -> &'static str {
        self.click_at(w.rect.center(), PointerButton::Primary, Modifiers::NONE);
        self.event(Event::Text(text.to_string()));
        match self.rng.below(4) {
            0 => {
                self.key(Key::Escape, Modifiers::NONE);
                "Escape"
            }
            1 => {
                self.key(Key::Tab, Modifiers::NONE);
                "Tab"
            }
            2 => {
                let p = self.rng.point_in(self.view(), 20.0);
                self.click_at(p, PointerButton::Primary, Modifiers::NONE);
                "a click in the view"
            }
            _ => {
                self.key(Key::Enter, Modifiers::NONE);
                "Enter"
            }
        }
    }

    /// Switches to another of [`SCENES`] through the picker (or, if its entry cannot be
    /// clicked, as the picker does).
    fn switch_scene(&mut self, to: &str) -> String {
        let (solving, studying) = (
            self.app().solve.busy(),
            !self.app().study.running().is_empty(),
        );
        let mut how = "picker";
        if !self.click_widget(Role::ComboBox, "scene") {
            how = "pending_scene";
        } else {
            self.frame();
            let ws = widgets(&self.h);
            match ws
                .iter()
                .find(|w| w.label == to && w.role != Role::ComboBox)
            {
                Some(w) => {
                    let at = w.rect.center();
                    self.click_at(at, PointerButton::Primary, Modifiers::NONE);
                }
                None => how = "pending_scene",
            }
        }
        if self.app().info.name != to {
            self.key(Key::Escape, Modifiers::NONE);
            self.h.state_mut().pending_scene = Some(to.to_string());
            self.frame();
            how = "pending_scene";
        }
        assert_eq!(self.app().info.name, to, "the scene did not load");
        self.tally.switches += 1;
        self.tally.switches_while_solving += usize::from(solving);
        self.tally.switches_while_studying += usize::from(studying);
        self.render();
        format!(
            "switch scene to {to} via {how} ({}{})",
            if solving { "while solving" } else { "idle" },
            if studying { ", study running" } else { "" }
        )
    }

    /// One random action; returns what it did.
    fn act(&mut self) -> String {
        // weights in thousandths
        match self.rng.below(1000) {
            0..150 => self.drag_slider(),
            150..210 => self.set_slider(),
            210..290 => self.type_slider(),
            290..320 => self.type_other(),
            320..400 => {
                let label = *self.rng.pick(&CHECKBOXES);
                let done = self.click_widget(Role::CheckBox, label);
                format!("toggle \"{label}\"{}", absent(done))
            }
            400..460 => {
                let label = *self.rng.pick(&RADIOS);
                let done = self.click_widget(Role::RadioButton, label);
                format!("radio \"{label}\"{}", absent(done))
            }
            460..530 => {
                let label = *self.rng.pick(&BUTTONS);
                let done = self.click_widget(Role::Button, label);
                format!("button \"{label}\"{}", absent(done))
            }
            530..580 => self.compare(),
            580..620 => self.combo(),
            620..680 => self.probe(),
            680..730 => self.camera(),
            730..800 => self.monkey_widget(),
            800..840 => self.anywhere(),
            840..860 => {
                let p = self.rng.point_in(self.left_panel(), 10.0);
                let dy = (self.rng.unit() - 0.5) * 1200.0;
                self.wheel(p, Vec2::new(0.0, dy));
                format!("scroll the left panel by {dy:.0}")
            }
            860..870 => self.resize(),
            870..880 => {
                let key = *self.rng.pick(&KEYS);
                let shift = self.rng.chance(0.2);
                let modifiers = if shift {
                    Modifiers::SHIFT
                } else {
                    Modifiers::NONE
                };
                self.key(key, modifiers);
                format!("key {key:?}{}", if shift { " with shift" } else { "" })
            }
            880..950 => {
                let ms = 20 + self.rng.below(130) as u64;
                self.wait(Duration::from_millis(ms));
                format!("wait {ms} ms")
            }
            950..965 => {
                let done = self.wait_for_solve(SOLVE_WAIT);
                let what = format!("wait for the solve: {}", self.outcome(done));
                // a converged value is worth comparing with
                if self.app().solve.converged() && self.rng.chance(0.5) {
                    format!("{what}, then {}", self.compare())
                } else {
                    what
                }
            }
            965..975 => self.idle(),
            975..990 => self.undo(),
            _ => {
                let to = self.other_scene();
                self.switch_scene(&to)
            }
        }
    }

    /// Puts the scene's values back after a refused one, as a user corrects a typo (through the
    /// model: the refused value may sit in any control); otherwise a frame.
    fn undo(&mut self) -> String {
        if !matches!(self.app().solve.status(), SolveStatus::Failed(_)) {
            self.frame();
            return "undo: nothing refused".into();
        }
        let initial = self.initial.clone().expect("a session");
        *self.h.state_mut().solve.params_mut() = initial;
        self.frame();
        "undo: the scene's values back after a refused one".into()
    }

    /// Stays idle: the solve ends, then the background study starts (resumed first, now and
    /// then, if paused); sometimes another scene is picked while it runs.
    fn idle(&mut self) -> String {
        let mut what = String::from("stay idle");
        if self.app().study.paused && self.rng.chance(0.5) {
            self.click_widget(Role::CheckBox, "pause background study");
            what += ", resume the study";
        }
        let solved = self.wait_for_solve(SOLVE_WAIT);
        let _ = write!(what, ": the solve {}", self.outcome(solved));
        if !solved || self.app().study.paused {
            return what;
        }
        if !self.wait_for_study(STUDY_WAIT) {
            return what + ", the study did not start";
        }
        what += ", the study runs";
        if self.rng.chance(0.4) {
            let to = self.other_scene();
            what = format!("{what}, then {}", self.switch_scene(&to));
        }
        what
    }

    fn other_scene(&mut self) -> String {
        let others: Vec<&str> = SCENES
            .iter()
            .copied()
            .filter(|s| *s != self.app().info.name)
            .collect();
        self.rng.pick(&others).to_string()
    }

    /// Resizes the window (to a tiny one, too) for a few frames; back to the harness's size
    /// most of the time.
    fn resize(&mut self) -> String {
        let size = *self.rng.pick(&SIZES);
        self.window = size;
        self.h.set_size(size);
        for _ in 0..3 {
            self.frame();
        }
        if size != WINDOW && self.rng.chance(0.7) {
            self.window = WINDOW;
            self.h.set_size(WINDOW);
            self.frame();
            return format!("resize the window to {} × {}, then back", size.x, size.y);
        }
        format!("resize the window to {} × {}", size.x, size.y)
    }

    /// Pins the current value as A and picks how it is compared (as a user does in a row).
    fn compare(&mut self) -> String {
        let pinned = self.click_widget(Role::Button, "pin A");
        let mode = *self
            .rng
            .pick(&["side by side", "side by side", "current − A", "current"]);
        let done = self.click_widget(Role::RadioButton, mode);
        format!("pin A{}, then \"{mode}\"{}", absent(pinned), absent(done))
    }

    fn outcome(&self, done: bool) -> String {
        if !done {
            return "still solving".into();
        }
        match self.app().solve.status() {
            SolveStatus::Done(r) if r.from_store => "shown from the store".into(),
            SolveStatus::Done(r) => format!(
                "{} after {} iterations",
                if r.converged {
                    "converged"
                } else {
                    "not converged"
                },
                r.iterations
            ),
            SolveStatus::Failed(m) => format!("refused: {m}"),
            s => format!("{s:?}"),
        }
    }

    fn sliders(&self) -> Vec<Widget> {
        widgets(&self.h)
            .into_iter()
            .filter(|w| w.role == Role::Slider)
            .collect()
    }

    /// A drag along a slider's rail, from and to anywhere on it or past its ends.
    fn drag_slider(&mut self) -> String {
        let sliders = self.sliders();
        if sliders.is_empty() {
            return "drag a slider (none)".into();
        }
        let label = self.rng.pick(&sliders).label.clone();
        let Some(w) = self.reach(Role::Slider, &label) else {
            return format!("drag slider \"{label}\" (gone)");
        };
        let mut at = || match self.rng.below(6) {
            0 => -0.5,
            1 => 1.5,
            _ => self.rng.unit() * 1.2 - 0.1,
        };
        let (a, b) = (at(), at());
        let y = w.rect.center().y;
        let x = |t: f32| w.rect.left() + t * w.rect.width();
        let steps = 1 + self.rng.below(4);
        self.drag(
            Pos2::new(x(a), y),
            Pos2::new(x(b), y),
            PointerButton::Primary,
            Modifiers::NONE,
            steps,
        );
        format!("drag slider \"{label}\" from {a:.2} to {b:.2} of its rail")
    }

    /// A value set on a slider through AccessKit: its ends, past them, or an extreme.
    fn set_slider(&mut self) -> String {
        let sliders = self.sliders();
        if sliders.is_empty() {
            return "set a slider (none)".into();
        }
        let w = self.rng.pick(&sliders).clone();
        let (lo, hi) = (w.min.unwrap_or(0.0), w.max.unwrap_or(1.0));
        let value = match self.rng.below(5) {
            0 => lo,
            1 => hi,
            2 => hi + (hi - lo) * 10.0,
            _ => *self.rng.pick(&EXTREME_VALUES),
        };
        {
            let node = self.h.query_all(By::new().predicate(|n| {
                n.role() == Role::Slider && n.label().as_deref() == Some(w.label.as_str())
            }));
            if let Some(n) = node.into_iter().next() {
                n.set_value_accesskit(value);
            }
        }
        self.frame();
        format!("set slider \"{}\" to {value:e}", w.label)
    }

    /// Text typed into a slider's value box.
    fn type_slider(&mut self) -> String {
        let sliders = self.sliders();
        if sliders.is_empty() {
            return "type into a slider (none)".into();
        }
        let label = self.rng.pick(&sliders).label.clone();
        let Some(rail) = self.reach(Role::Slider, &label) else {
            return format!("type into slider \"{label}\" (gone)");
        };
        let Some(value_box) = self.value_box(rail.rect) else {
            return format!("type into slider \"{label}\" (no value box)");
        };
        let text = self.typed_text();
        let end = self.type_into(&value_box, &text);
        self.tally.typed += 1;
        format!("type {text:?} into slider \"{label}\", then {end}")
    }

    /// Text typed into a value box of the view options (fixed range, deformation scale).
    fn type_other(&mut self) -> String {
        let (panel, sliders) = (self.left_panel(), self.sliders());
        let boxes: Vec<Widget> = widgets(&self.h)
            .into_iter()
            .filter(|w| {
                w.role == Role::SpinButton
                    && panel.contains(w.rect.center())
                    && !sliders
                        .iter()
                        .any(|s| (s.rect.center().y - w.rect.center().y).abs() < 4.0)
            })
            .collect();
        if boxes.is_empty() {
            return "type into a value box (none)".into();
        }
        let w = self.rng.pick(&boxes).clone();
        let text = self.typed_text();
        let end = self.type_into(&w, &text);
        self.tally.typed += 1;
        format!("type {text:?} into value box \"{}\", then {end}", w.label)
    }

    fn typed_text(&mut self) -> String {
        if self.rng.chance(0.25) {
            let x = (self.rng.unit() - 0.3) * 10f32.powi(self.rng.below(12) as i32 - 6);
            format!("{x}")
        } else {
            self.rng.pick(&TYPED).to_string()
        }
    }

    /// Opens the field or the study's quantity combo box and picks an entry (or closes it).
    fn combo(&mut self) -> String {
        let (combo, entries): (&str, Vec<String>) = if self.rng.chance(0.75) {
            (
                "field",
                Quantity::ALL
                    .iter()
                    .map(|q| q.label().to_string())
                    .collect(),
            )
        } else {
            (
                "quantity",
                lopin_core::study::Quantities::NAMES
                    .iter()
                    .map(|(n, u)| format!("{n} ({u})"))
                    .collect(),
            )
        };
        if !self.click_widget(Role::ComboBox, combo) {
            return format!("combo \"{combo}\" (absent)");
        }
        self.frame();
        if self.rng.chance(0.15) {
            self.key(Key::Escape, Modifiers::NONE);
            return format!("open combo \"{combo}\", then Escape");
        }
        let entry = self.rng.pick(&entries).clone();
        let ws = widgets(&self.h);
        match ws
            .iter()
            .find(|w| w.label == entry && w.role != Role::ComboBox)
        {
            Some(w) => {
                let at = w.rect.center();
                self.click_at(at, PointerButton::Primary, Modifiers::NONE);
                format!("combo \"{combo}\": pick \"{entry}\"")
            }
            None => {
                self.key(Key::Escape, Modifiers::NONE);
                format!("combo \"{combo}\": no entry \"{entry}\"")
            }
        }
    }

    /// A click in the current configuration's viewport (picks a probe node on the body).
    fn probe(&mut self) -> String {
        let view = self.view();
        let p = if self.rng.chance(0.5) {
            view.center() + Vec2::new(self.rng.unit() - 0.5, self.rng.unit() - 0.5) * 120.0
        } else {
            self.rng.point_in(view, 2.0)
        };
        self.click_at(p, PointerButton::Primary, Modifiers::NONE);
        self.tally.probes += 1;
        let picked = self.app().cache.probe();
        format!(
            "probe click at ({:.0}, {:.0}): {}",
            p.x,
            p.y,
            picked.map_or("nothing picked".to_string(), |(s, n)| format!(
                "substructure {s} node {n}"
            ))
        )
    }

    /// Orbit, pan, zoom or a double-click in a viewport (A's, side by side, as well).
    fn camera(&mut self) -> String {
        let rect = match self.app().layout.beside_rect() {
            Some(a) if self.rng.chance(0.5) => a,
            _ => self.view(),
        };
        let a = self.rng.point_in(rect, 5.0);
        let b = a + Vec2::new(self.rng.unit() - 0.5, self.rng.unit() - 0.5) * 600.0;
        match self.rng.below(5) {
            0 => {
                self.drag(a, b, PointerButton::Primary, Modifiers::NONE, 3);
                "orbit drag".into()
            }
            1 => {
                let button = if self.rng.chance(0.5) {
                    PointerButton::Secondary
                } else {
                    PointerButton::Middle
                };
                self.drag(a, b, button, Modifiers::NONE, 3);
                format!("pan drag ({button:?})")
            }
            2 => {
                self.drag(a, b, PointerButton::Primary, Modifiers::SHIFT, 2);
                "shift-drag pan".into()
            }
            3 => {
                let dy = (self.rng.unit() - 0.5) * 4000.0;
                self.wheel(a, Vec2::new(0.0, dy));
                format!("zoom by scrolling {dy:.0}")
            }
            _ => {
                self.click_at(a, PointerButton::Primary, Modifiers::NONE);
                self.click_at(a, PointerButton::Primary, Modifiers::NONE);
                "double-click (reset the camera)".into()
            }
        }
    }

    /// A click on any widget of the window but the scene picker and its entries.
    fn monkey_widget(&mut self) -> String {
        let window = self.window;
        let ws: Vec<Widget> = widgets(&self.h)
            .into_iter()
            .filter(|w| {
                w.label != "scene"
                    && !lopin_core::scene::registry::SCENES.contains(&w.label.as_str())
                    && w.rect.width() > 0.0
                    && w.rect.height() > 0.0
                    && Rect::from_min_size(Pos2::ZERO, window).contains(w.rect.center())
            })
            .collect();
        if ws.is_empty() {
            return "click a widget (none)".into();
        }
        let w = self.rng.pick(&ws).clone();
        let button = if self.rng.chance(0.85) {
            PointerButton::Primary
        } else {
            PointerButton::Secondary
        };
        self.click_at(w.rect.center(), button, Modifiers::NONE);
        format!("{button:?} click on {:?} \"{}\"", w.role, w.label)
    }

    /// A click or a drag anywhere below the top bar (which holds the scene picker).
    fn anywhere(&mut self) -> String {
        let area = Rect::from_min_max(Pos2::new(0.0, self.view().top()), self.window.to_pos2());
        let a = self.rng.point_in(area, 1.0);
        if self.rng.chance(0.5) {
            self.click_at(a, PointerButton::Primary, Modifiers::NONE);
            format!("click at ({:.0}, {:.0})", a.x, a.y)
        } else {
            let b = self.rng.point_in(area, 1.0);
            self.drag(a, b, PointerButton::Primary, Modifiers::NONE, 2);
            format!(
                "drag from ({:.0}, {:.0}) to ({:.0}, {:.0})",
                a.x, a.y, b.x, b.y
            )
        }
    }

    /// Brings the session's scene values back (through the model: a typed value may sit in any
    /// control), stops playback and waits for the converged solve.
    fn finish(&mut self) {
        let initial = self.initial.clone().expect("a session");
        self.window = WINDOW;
        self.h.set_size(WINDOW);
        let app = self.h.state_mut();
        if app.clock.playing() {
            app.clock.toggle_play();
        }
        *app.solve.params_mut() = initial;
        self.log
            .push("restore the scene's values and settle".into());
        settle(&mut self.h);
        self.frame();
        let app = self.app();
        assert!(
            app.solve.converged(),
            "the last solve did not converge: {:?}",
            app.solve.status()
        );
        assert!(
            !app.layout.mesh().vertices.is_empty(),
            "nothing drawn at the end"
        );
        self.render();
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    match std::env::var(name) {
        Ok(v) => {
            let v = v.trim();
            let parsed = match v.strip_prefix("0x") {
                Some(hex) => u64::from_str_radix(hex, 16)
                    .ok()
                    .and_then(|x| x.to_string().parse().ok()),
                None => v.parse().ok(),
            };
            parsed.unwrap_or_else(|| panic!("{name}={v} is not a number"))
        }
        Err(_) => default,
    }
}

#[test]
fn the_explorer_survives_random_use() {
    let seed: u64 = env_or("LOPIN_UI_SEED", DEFAULT_SEED);
    let actions: usize = env_or("LOPIN_UI_ACTIONS", DEFAULT_ACTIONS);
    watch_panics();
    println!("random UI use: LOPIN_UI_SEED={seed} LOPIN_UI_ACTIONS={actions}");
    let mut run = Run::new(seed, actions);
    settle(&mut run.h);
    for i in 0..actions {
        // every scene is visited: a third of the way in and two thirds, the next one not seen
        // yet is loaded while the background study runs
        let forced = (i == actions / 3 || i == 2 * actions / 3)
            .then(|| {
                SCENES
                    .iter()
                    .find(|s| !run.tally.visited.iter().any(|v| v == *s))
            })
            .flatten();
        let started = Instant::now();
        let what = match forced {
            Some(to) => {
                run.wait_for_solve(SOLVE_WAIT);
                run.h.state_mut().study.paused = false;
                run.wait_for_study(STUDY_WAIT);
                run.switch_scene(to)
            }
            None => run.act(),
        };
        let kind = what.split_whitespace().next().unwrap_or("?").to_string();
        let e = run.tally.time.entry(kind).or_default();
        e.0 += 1;
        e.1 += started.elapsed().as_secs_f64();
        run.log.push(what);
        // the accessibility tree names the 3D view
        let views = run
            .h
            .query_all_by(|n| n.label().is_some_and(|l| l.starts_with("3D view")))
            .count();
        assert!(views >= 1, "no 3D view in the accessibility tree");
        if i % RENDER_EVERY == RENDER_EVERY - 1 {
            run.render();
        }
    }
    run.finish();
    let t = &run.tally;
    println!(
        "random UI use: seed {seed}, {actions} actions, {} frames, {} renders in {:.1} s; scenes \
         {:?}; solves: {} converged, {} cancelled, {} at their iteration limit, {} values \
         refused; {} scene switches ({} \
         while solving, {} while the study ran); {} probe clicks, {} values typed, {} frames \
         side by side",
        t.frames,
        t.renders,
        run.started.elapsed().as_secs_f64(),
        t.visited,
        t.converged,
        t.cancelled,
        t.unconverged,
        t.refused,
        t.switches,
        t.switches_while_solving,
        t.switches_while_studying,
        t.probes,
        t.typed,
        t.side_by_side_frames,
    );
    println!("  every action: {}", run.write_log());
    let mut times = String::new();
    for (k, (n, s)) in &t.time {
        let _ = write!(times, " {k} {n}× {s:.1} s;");
    }
    println!("  actions by their first word:{times}");
    for r in &t.refusals {
        println!("  refused: {r}");
    }
    assert!(
        SCENES.iter().all(|s| t.visited.iter().any(|v| v == s)) || actions < 3,
        "scenes visited: {:?}",
        t.visited
    );
}
