//! Self-measurement of the explorer (`lopin view SCENE_OR_FOLDER --measure FILE`), as a user who
//! paused and then moves the friction slider: the time from the start of loading (the scene
//! built, or the folder read) to the first converged picture; after the first converged solve the explorer stays idle
//! while the background study stores the slider's range (or for at most [`STUDY_MAX_S`]), then
//! the friction coefficient is set to [`MOVES`] values in turn (alternately a stored grid value
//! and one between two grid values, which is refined warm from its nearest stored neighbour),
//! each at the start of a frame as a slider event would arrive. Per move it records the time to
//! the first picture of the new value (the stored or nearest stored picture, a live iterate or
//! the converged fields: the first mesh built from them, and the start of the next frame, when
//! that frame has been presented) and to the converged picture, and the change → converged
//! report latency; over the whole run, the frame intervals while idle, while the background
//! study solves and while a re-solve runs, and in each of these states eframe's time per frame
//! outside acquiring and presenting the surface (egui, tessellation, command encoding: what is
//! left of a frame is the rasterizer's). A run opened from its stored fields has no slider to
//! move ([`Measure::stored`]): after its first picture the camera orbits for [`ORBIT_FRAMES`]
//! frames (the frame interval of an orbit), then the time scrubber moves to each step of
//! [`SCRUB_AT`] in turn (the time to the picture of that step: read, mesh built, presented), and
//! the report adds the process's peak resident memory. The results are printed and written as
//! JSON, then the window closes.

use crate::protocol::SolveReport;
use lopin_core::counters::Instant;
use std::path::PathBuf;

/// The friction values moved to, in order: stored grid values alternate with values halfway
/// between two grid values.
pub const MOVES: [f64; 8] = [0.35, 0.375, 0.45, 0.525, 0.05, 0.125, 0.2, 0.275];
/// Frames drawn between a converged picture and the next move.
const SETTLE_FRAMES: usize = 20;
/// Longest idle wait for the background study, s.
pub const STUDY_MAX_S: f64 = 90.0;

/// Frames the camera orbits for, in a stored run's measurement.
pub const ORBIT_FRAMES: usize = 60;
/// Drag per orbit frame, pixels (a full turn in about 13 frames' worth of 60).
const ORBIT_PX: f32 = 12.0;
/// Where the time scrubber moves in a stored run's measurement, as fractions of the interval.
pub const SCRUB_AT: [f64; 6] = [0.25, 0.5, 0.75, 1.0, 0.1, 0.6];

/// What the explorer does next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Action {
    /// Nothing.
    Wait,
    /// Set the friction slider to this value (at the start of this frame).
    Move(f64),
    /// Orbit the camera by a drag of this many pixels.
    Orbit(f32),
    /// Move the time scrubber to this fraction of the interval.
    Scrub(f64),
    /// Write the results and close.
    Close,
}

/// What a frame found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FrameState {
    /// The newest request is being solved.
    pub busy: bool,
    /// The newest request converged.
    pub converged: bool,
    /// The background study is solving.
    pub background: bool,
    /// Every value of the study's grid is stored.
    pub study_complete: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    /// Waiting for the first converged solve.
    Start,
    /// Idle while the background study runs.
    Study,
    /// Moving the slider.
    Moves,
    /// Orbiting the camera (stored runs).
    Orbit,
    /// Moving the time scrubber (stored runs).
    Scrub,
    Done,
}

/// One move of the time scrubber as measured.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
struct ScrubRecord {
    /// The step moved to.
    step: Option<usize>,
    /// Input → mesh of that step built, s.
    built_s: Option<f64>,
    /// Input → start of the frame after it, s.
    picture_s: Option<f64>,
}

/// One slider move as measured.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
struct MoveRecord {
    value: f64,
    /// The value was stored: shown without solving.
    stored: bool,
    generation: u64,
    /// Input → first mesh of the new value built, s.
    first_picture_built_s: Option<f64>,
    /// Input → start of the frame after it (the picture presented), s.
    first_picture_s: Option<f64>,
    /// Input → converged mesh built, s.
    converged_built_s: Option<f64>,
    /// Input → start of the frame after it, s.
    converged_picture_s: Option<f64>,
    /// Change → converged report, s.
    report_latency_s: Option<f64>,
    iterations: Option<usize>,
    /// Friction of the state it started from.
    start: Option<f64>,
    /// The two stored friction values whose interpolated states it started from.
    between: Option<(f64, f64)>,
}

/// The measurement in progress.
#[derive(Debug, Clone)]
pub struct Measure {
    path: PathBuf,
    /// A stored run: orbit and scrub instead of moving the slider.
    stored: bool,
    orbit_frames: Vec<f64>,
    scrubs: Vec<ScrubRecord>,
    /// Frame start of the newest scrub.
    scrub_start: Option<Instant>,
    /// Surface triangles of the scene.
    triangles: usize,
    /// When the scene or folder began to load.
    opened: Instant,
    /// From `opened` to the frame that found the first solve converged (or the stored
    /// configuration shown), s.
    first_converged_s: Option<f64>,
    phase: Phase,
    settle: usize,
    study_started: Option<Instant>,
    study_s: f64,
    moves: Vec<MoveRecord>,
    /// Frame start of the newest move.
    move_start: Option<Instant>,
    /// The first / converged picture was built in the last frame: stamp the next frame start.
    pending: [bool; 2],
    idle_frames: Vec<f64>,
    background_frames: Vec<f64>,
    busy_frames: Vec<f64>,
    busy_ui: Vec<f64>,
    background_ui: Vec<f64>,
    idle_ui: Vec<f64>,
    busy_cpu: Vec<f64>,
    background_cpu: Vec<f64>,
    idle_cpu: Vec<f64>,
}

fn stats(v: &[f64]) -> Stats {
    let mut s = v.to_vec();
    s.sort_by(f64::total_cmp);
    let pick = |q: f64| {
        if s.is_empty() {
            f64::NAN
        } else {
            s[((s.len() - 1) as f64 * q).round() as usize]
        }
    };
    Stats {
        count: s.len(),
        median: pick(0.5),
        p90: pick(0.9),
        max: pick(1.0),
    }
}

/// Order statistics of a sample.
#[derive(Debug, Clone, Copy, serde::Serialize)]
struct Stats {
    count: usize,
    median: f64,
    p90: f64,
    max: f64,
}

impl Measure {
    /// A measurement writing its results to `path`.
    pub fn new(path: PathBuf) -> Measure {
        Measure {
            path,
            stored: false,
            orbit_frames: Vec::new(),
            scrubs: Vec::new(),
            scrub_start: None,
            triangles: 0,
            opened: Instant::now(),
            first_converged_s: None,
            phase: Phase::Start,
            settle: SETTLE_FRAMES,
            study_started: None,
            study_s: 0.0,
            moves: Vec::new(),
            move_start: None,
            pending: [false; 2],
            idle_frames: Vec::new(),
            background_frames: Vec::new(),
            busy_frames: Vec::new(),
            busy_ui: Vec::new(),
            background_ui: Vec::new(),
            idle_ui: Vec::new(),
            busy_cpu: Vec::new(),
            background_cpu: Vec::new(),
            idle_cpu: Vec::new(),
        }
    }

    /// The measurement of a run opened from its stored fields (orbit and scrub).
    pub fn stored(path: PathBuf) -> Measure {
        Measure {
            stored: true,
            ..Measure::new(path)
        }
    }

    /// The scene's surface triangles, for the report.
    pub fn set_triangles(&mut self, triangles: usize) {
        self.triangles = triangles;
    }

    /// The step the scrubber was moved to by [`Action::Scrub`] (after clamping).
    pub fn on_scrub(&mut self, step: usize) {
        if let Some(s) = self.scrubs.last_mut() {
            s.step = Some(step);
        }
    }

    /// Counts the time to the first converged picture from `t` (when loading began) instead
    /// of from the measurement's creation.
    pub fn opened_at(&mut self, t: Instant) {
        self.opened = t;
    }

    /// Records one frame interval (from the start of the previous frame to this one's) under
    /// what the previous frame found, and stamps the pictures the previous frame built.
    pub fn on_frame(&mut self, dt: f64, previous: FrameState) {
        if let (Some(t0), Some(m)) = (self.move_start, self.moves.last_mut()) {
            let now = t0.elapsed().as_secs_f64();
            if self.pending[0] {
                m.first_picture_s = Some(now);
            }
            if self.pending[1] {
                m.converged_picture_s = Some(now);
            }
        }
        if let (Some(t0), Some(s)) = (self.scrub_start, self.scrubs.last_mut()) {
            if self.pending[1] && s.picture_s.is_none() && s.built_s.is_some() {
                s.picture_s = Some(t0.elapsed().as_secs_f64());
            }
        }
        self.pending = [false; 2];
        if self.phase == Phase::Start || dt <= 0.0 {
            return;
        }
        if self.phase == Phase::Orbit {
            self.orbit_frames.push(dt);
        }
        self.bin(previous).0.push(dt);
    }

    /// The frame intervals, UI-thread times and eframe times of frames in state `s`.
    fn bin(&mut self, s: FrameState) -> (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>) {
        if s.busy {
            (&mut self.busy_frames, &mut self.busy_ui, &mut self.busy_cpu)
        } else if s.background {
            (
                &mut self.background_frames,
                &mut self.background_ui,
                &mut self.background_cpu,
            )
        } else {
            (&mut self.idle_frames, &mut self.idle_ui, &mut self.idle_cpu)
        }
    }

    /// Records the time the UI thread spent laying out one frame (logic, mesh rebuild, panels).
    pub fn on_ui_time(&mut self, seconds: f64, s: FrameState) {
        if self.phase != Phase::Start {
            self.bin(s).1.push(seconds);
        }
    }

    /// Records the time eframe spent on the last frame (egui and the painter: layout,
    /// tessellation, rendering and submitting; the wait for the presentation excluded).
    pub fn on_cpu_time(&mut self, seconds: f64, s: FrameState) {
        if self.phase != Phase::Start {
            self.bin(s).2.push(seconds);
        }
    }

    /// The move's request went out with this generation.
    pub fn on_request(&mut self, generation: u64) {
        if let Some(m) = self.moves.last_mut() {
            if m.generation == 0 {
                m.generation = generation;
            }
        }
    }

    /// A mesh was built from fields of `generation` at `step` (`live`: not converged yet).
    pub fn on_mesh(&mut self, generation: u64, live: bool, step: usize) {
        if let (Some(t0), Some(s)) = (self.scrub_start, self.scrubs.last_mut()) {
            if s.step == Some(step) && s.built_s.is_none() && !live {
                s.built_s = Some(t0.elapsed().as_secs_f64());
                self.pending[1] = true;
            }
            return;
        }
        let (Some(t0), Some(m)) = (self.move_start, self.moves.last_mut()) else {
            return;
        };
        if generation != m.generation || m.generation == 0 {
            return;
        }
        let now = t0.elapsed().as_secs_f64();
        if m.first_picture_built_s.is_none() {
            m.first_picture_built_s = Some(now);
            self.pending[0] = true;
        }
        if !live && m.converged_built_s.is_none() {
            m.converged_built_s = Some(now);
            self.pending[1] = true;
        }
    }

    /// Records the end of a solve.
    pub fn on_finished(&mut self, report: &SolveReport, latency: Option<f64>) {
        if let Some(m) = self.moves.last_mut() {
            if report.generation == m.generation && report.converged && !report.cancelled {
                m.report_latency_s = latency;
                m.iterations = Some(report.iterations);
                m.start = report.start;
                m.between = report.between;
                m.stored = report.from_store;
            }
        }
    }

    /// The next step of the measurement, at the start of a frame.
    pub fn next_action(&mut self, s: FrameState) -> Action {
        match self.phase {
            Phase::Start => {
                if s.converged && self.first_converged_s.is_none() {
                    self.first_converged_s = Some(self.opened.elapsed().as_secs_f64());
                }
                if s.converged && self.settled() {
                    if self.stored {
                        self.phase = Phase::Orbit;
                    } else {
                        self.phase = Phase::Study;
                        self.study_started = Some(Instant::now());
                    }
                }
                Action::Wait
            }
            Phase::Orbit => {
                if self.orbit_frames.len() >= ORBIT_FRAMES {
                    self.phase = Phase::Scrub;
                    self.settle = SETTLE_FRAMES;
                    return Action::Wait;
                }
                Action::Orbit(ORBIT_PX)
            }
            Phase::Scrub => {
                let done = self.scrubs.last().is_none_or(|s| s.picture_s.is_some());
                if !(done && self.settled()) {
                    return Action::Wait;
                }
                let Some(&at) = SCRUB_AT.get(self.scrubs.len()) else {
                    self.phase = Phase::Done;
                    self.report_stored();
                    return Action::Close;
                };
                self.scrubs.push(ScrubRecord {
                    step: None,
                    built_s: None,
                    picture_s: None,
                });
                self.scrub_start = Some(Instant::now());
                self.settle = SETTLE_FRAMES;
                Action::Scrub(at)
            }
            Phase::Study => {
                let waited = self
                    .study_started
                    .map_or(0.0, |t| t.elapsed().as_secs_f64());
                if (s.study_complete && !s.background) || waited > STUDY_MAX_S {
                    self.study_s = waited;
                    self.phase = Phase::Moves;
                    self.settle = 0;
                }
                Action::Wait
            }
            Phase::Moves => {
                let done = self
                    .moves
                    .last()
                    .is_none_or(|m| m.converged_picture_s.is_some());
                if !(done && s.converged && self.settled()) {
                    return Action::Wait;
                }
                let Some(&value) = MOVES.get(self.moves.len()) else {
                    self.phase = Phase::Done;
                    self.report();
                    return Action::Close;
                };
                self.moves.push(MoveRecord {
                    value,
                    stored: false,
                    generation: 0,
                    first_picture_built_s: None,
                    first_picture_s: None,
                    converged_built_s: None,
                    converged_picture_s: None,
                    report_latency_s: None,
                    iterations: None,
                    start: None,
                    between: None,
                });
                self.move_start = Some(Instant::now());
                self.settle = SETTLE_FRAMES;
                Action::Move(value)
            }
            Phase::Done => Action::Wait,
        }
    }

    fn settled(&mut self) -> bool {
        if self.settle > 0 {
            self.settle -= 1;
            return false;
        }
        true
    }

    /// The stored run's report: first picture, orbit frames, scrubs and peak memory.
    fn report_stored(&self) {
        let orbit = stats(&self.orbit_frames);
        let report = serde_json::json!({
            "open_to_first_picture_s": self.first_converged_s,
            "triangles": self.triangles,
            "orbit_frame_interval_s": orbit,
            "fps_orbit_median": 1.0 / orbit.median,
            "scrubs": self.scrubs,
            "scrub_built_s": stats(&self.scrubs.iter().filter_map(|s| s.built_s).collect::<Vec<_>>()),
            "scrub_picture_s": stats(&self.scrubs.iter().filter_map(|s| s.picture_s).collect::<Vec<_>>()),
            "peak_memory_bytes": peak_memory_bytes(),
        });
        self.write(&report);
    }

    fn write(&self, report: &serde_json::Value) {
        let text = format!("{report:#}\n");
        print!("{text}");
        if let Err(e) = std::fs::write(&self.path, &text) {
            eprintln!("error: cannot write {}: {e}", self.path.display());
        }
    }

    fn report(&self) {
        let ms = |v: &[f64]| stats(&v.iter().map(|x| 1e3 * x).collect::<Vec<_>>());
        let pick = |f: fn(&MoveRecord) -> Option<f64>, stored: Option<bool>| -> Vec<f64> {
            self.moves
                .iter()
                .filter(|m| stored.is_none_or(|s| m.stored == s))
                .filter_map(f)
                .collect()
        };
        let first = |m: &MoveRecord| m.first_picture_s;
        let converged = |m: &MoveRecord| m.converged_picture_s;
        let (busy, idle, bg) = (
            stats(&self.busy_frames),
            stats(&self.idle_frames),
            stats(&self.background_frames),
        );
        let report = serde_json::json!({
            "moves": self.moves,
            "open_to_first_converged_s": self.first_converged_s,
            "study_wait_s": self.study_s,
            "first_picture_s": stats(&pick(first, None)),
            "first_picture_built_s": stats(&pick(|m| m.first_picture_built_s, None)),
            "converged_picture_s": stats(&pick(converged, None)),
            "converged_picture_stored_s": stats(&pick(converged, Some(true))),
            "converged_picture_refined_s": stats(&pick(converged, Some(false))),
            "report_latency_s": stats(&pick(|m| m.report_latency_s, None)),
            "frame_interval_idle_s": idle,
            "fps_idle_median": 1.0 / idle.median,
            "frame_interval_background_study_s": bg,
            "fps_background_study_median": 1.0 / bg.median,
            "frame_interval_while_solving_s": busy,
            "fps_while_solving_median": 1.0 / busy.median,
            "ui_thread_ms_per_frame_idle": ms(&self.idle_ui),
            "ui_thread_ms_per_frame_background_study": ms(&self.background_ui),
            "ui_thread_ms_per_frame_while_solving": ms(&self.busy_ui),
            "frame_cpu_ms_idle": ms(&self.idle_cpu),
            "frame_cpu_ms_background_study": ms(&self.background_cpu),
            "frame_cpu_ms_while_solving": ms(&self.busy_cpu),
        });
        self.write(&report);
    }
}

/// The process's peak resident memory, bytes (`VmHWM` of /proc/self/status; None elsewhere).
fn peak_memory_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}
