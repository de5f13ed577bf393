//! Self-measurement of the explorer (`lopin view SCENE --measure FILE`): after the first
//! converged solve, the friction coefficient is moved by 0.05 several times, as a user would
//! with the slider, and the time from each change to its converged re-solve and the frame
//! intervals while re-solves run are recorded, printed and written as JSON. Then the window
//! closes.

use crate::protocol::SolveReport;
use std::path::PathBuf;

/// Slider moves measured.
const MOVES: usize = 8;
/// Frames drawn between a converged re-solve and the next move.
const SETTLE_FRAMES: usize = 20;

/// What the explorer does next.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Nothing.
    Wait,
    /// Move the friction slider by 0.05.
    Nudge,
    /// Write the results and close.
    Close,
}

/// The measurement in progress.
#[derive(Debug, Clone)]
pub struct Measure {
    path: PathBuf,
    moves: usize,
    waiting: bool,
    settle: usize,
    latencies: Vec<f64>,
    iterations: Vec<usize>,
    busy_frames: Vec<f64>,
    idle_frames: Vec<f64>,
    busy_ui: Vec<f64>,
    idle_ui: Vec<f64>,
    done: bool,
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
            moves: 0,
            waiting: false,
            settle: SETTLE_FRAMES,
            latencies: Vec::new(),
            iterations: Vec::new(),
            busy_frames: Vec::new(),
            idle_frames: Vec::new(),
            busy_ui: Vec::new(),
            idle_ui: Vec::new(),
            done: false,
        }
    }

    /// Records one frame interval.
    pub fn on_frame(&mut self, dt: f64, busy: bool) {
        if self.moves == 0 || dt <= 0.0 {
            return;
        }
        if busy {
            self.busy_frames.push(dt);
        } else {
            self.idle_frames.push(dt);
        }
    }

    /// Records the time the UI thread spent laying out one frame (logic, mesh rebuild, panels).
    pub fn on_ui_time(&mut self, seconds: f64, busy: bool) {
        if self.moves == 0 {
            return;
        }
        if busy {
            self.busy_ui.push(seconds);
        } else {
            self.idle_ui.push(seconds);
        }
    }

    /// Records the end of a solve.
    pub fn on_finished(&mut self, report: &SolveReport, latency: Option<f64>) {
        if self.waiting && report.converged && !report.cancelled {
            if let Some(l) = latency {
                self.latencies.push(l);
                self.iterations.push(report.iterations);
            }
            self.waiting = false;
            self.settle = SETTLE_FRAMES;
        }
    }

    /// The next step of the measurement.
    pub fn next_action(&mut self, converged: bool) -> Action {
        if self.done || self.waiting || !converged {
            return Action::Wait;
        }
        if self.settle > 0 {
            self.settle -= 1;
            return Action::Wait;
        }
        if self.moves < MOVES {
            self.moves += 1;
            self.waiting = true;
            return Action::Nudge;
        }
        self.done = true;
        self.report();
        Action::Close
    }

    fn report(&self) {
        let ms = |v: &[f64]| stats(&v.iter().map(|x| 1e3 * x).collect::<Vec<_>>());
        let (busy, idle) = (stats(&self.busy_frames), stats(&self.idle_frames));
        let report = serde_json::json!({
            "moves": self.latencies.len(),
            "resolve_latency_s": stats(&self.latencies),
            "resolve_latency_all_s": self.latencies,
            "iterations": self.iterations,
            "frame_interval_while_solving_s": busy,
            "fps_while_solving_median": 1.0 / busy.median,
            "frame_interval_idle_s": idle,
            "fps_idle_median": 1.0 / idle.median,
            "ui_thread_ms_per_frame_while_solving": ms(&self.busy_ui),
            "ui_thread_ms_per_frame_idle": ms(&self.idle_ui),
        });
        let text = format!("{report:#}\n");
        print!("{text}");
        if let Err(e) = std::fs::write(&self.path, &text) {
            eprintln!("error: cannot write {}: {e}", self.path.display());
        }
    }
}
