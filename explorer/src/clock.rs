//! The explorer's clocks: the displayed time step (shared with the solver side, which computes
//! live fields there), play/pause and the playback position between two steps, and the wall
//! clock of the frames (recent frame intervals, frames per second).

use crate::protocol::DisplayStep;
use lopin_core::counters::Instant;
use std::collections::VecDeque;

/// Frame intervals kept for the frame rate.
const FRAMES_KEPT: usize = 120;

/// Displayed step, playback and frame timing.
pub struct Clock {
    step: usize,
    /// Time steps of the scene (the last step's index).
    steps: usize,
    /// Time step, s.
    dt: f64,
    playing: bool,
    /// Steps to advance, fractional part carried between frames.
    play_clock: f64,
    display: DisplayStep,
    /// Recent frame intervals, s.
    frame_intervals: VecDeque<f64>,
    last_frame: Option<Instant>,
}

impl Clock {
    /// A clock over `steps` time steps of `dt` seconds, paused at the middle step, which it
    /// writes into `display`.
    pub fn new(steps: usize, dt: f64, display: DisplayStep) -> Clock {
        let step = steps / 2;
        display.set(step);
        Clock {
            step,
            steps,
            dt,
            playing: false,
            play_clock: 0.0,
            display,
            frame_intervals: VecDeque::new(),
            last_frame: None,
        }
    }

    /// Displayed time step.
    pub fn step(&self) -> usize {
        self.step
    }

    /// Last time step.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Moves the time scrubber (clamped to the last step).
    pub fn set_step(&mut self, step: usize) {
        self.step = step.min(self.steps);
        self.display.set(self.step);
    }

    /// Physical time of the displayed step, s.
    pub fn time(&self) -> f64 {
        self.step as f64 * self.dt
    }

    /// Whether the time steps play.
    pub fn playing(&self) -> bool {
        self.playing
    }

    /// Play ↔ pause.
    pub fn toggle_play(&mut self) {
        self.playing = !self.playing;
    }

    /// Advances playback by `dt` seconds of wall time (the whole run plays in about 4 seconds,
    /// then starts over). Returns whether it plays, so another frame must follow.
    pub fn advance(&mut self, dt: f64) -> bool {
        if !self.playing || self.steps == 0 {
            return false;
        }
        self.play_clock += dt * self.steps as f64 / 4.0;
        let advance = self.play_clock.floor() as usize;
        if advance > 0 {
            self.play_clock -= advance as f64;
            let next = (self.step + advance) % (self.steps + 1);
            self.set_step(next);
        }
        true
    }

    /// Starts a frame: returns the seconds since the previous one (0 for the first) and keeps
    /// it among the recent intervals.
    pub fn frame(&mut self) -> f64 {
        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        if dt > 0.0 {
            self.frame_intervals.push_back(dt);
            if self.frame_intervals.len() > FRAMES_KEPT {
                self.frame_intervals.pop_front();
            }
        }
        dt
    }

    /// Frames per second over the recent frames.
    pub fn fps(&self) -> Option<f64> {
        let n = self.frame_intervals.len();
        (n >= 5).then(|| n as f64 / self.frame_intervals.iter().sum::<f64>())
    }
}
