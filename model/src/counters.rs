//! Per-stage timings collected by the engine itself (setup/factorization, local stage, linear
//! stage, post-processing) and the per-iteration record, read by the CLI tables, the explorer and
//! the benchmarks. Wall clock from `web-time` (std on native, `performance.now()` on wasm32).

use std::sync::atomic::{AtomicU64, Ordering};

pub use web_time::Instant;

/// One LATIN iteration as seen from outside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// Cumulative iteration number within the solve (1-based).
    pub iteration: usize,
    /// First step of the window this iteration worked on.
    pub window_start: usize,
    /// Last step of that window.
    pub window_end: usize,
    /// Error indicator η after this iteration.
    pub eta: f64,
    /// The smooth indicator η̄ (step-averaged fields, `lopin_core::stages::indicator::smooth_sums`).
    pub eta_smooth: f64,
    /// Seconds in the local stage.
    pub local_s: f64,
    /// Seconds in the linear stage (macro problem included).
    pub linear_s: f64,
    /// Of which seconds in the macro problem (right-hand side, solve; METHOD §9 steps 2–3).
    pub macro_s: f64,
    /// Seconds of this rank in exchanges and sums between ranks, waiting included (0 on one
    /// machine; part of the local and linear stages' seconds).
    pub comm_s: f64,
    /// Substructure linear stages skipped because their inputs did not change.
    pub skipped: usize,
}

/// Totals per stage, in seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StageTimes {
    /// Assembly and factorization.
    pub setup: f64,
    /// Local stages.
    pub local: f64,
    /// Linear stages.
    pub linear: f64,
    /// Post-processing.
    pub post: f64,
}

/// Counters of a solver.
#[derive(Debug, Default)]
pub struct Counters {
    /// Seconds spent building and factorizing the substructure operators.
    pub setup_s: f64,
    /// Records of the iterations of the last solve.
    pub iterations: Vec<IterationRecord>,
    post_bits: AtomicU64,
}

impl Counters {
    /// Stage totals of the last solve (setup included).
    pub fn stage_times(&self) -> StageTimes {
        StageTimes {
            setup: self.setup_s,
            local: self.iterations.iter().map(|r| r.local_s).sum(),
            linear: self.iterations.iter().map(|r| r.linear_s).sum(),
            post: self.post_s(),
        }
    }

    /// Seconds spent in post-processing since the last solve started.
    pub fn post_s(&self) -> f64 {
        f64::from_bits(self.post_bits.load(Ordering::Relaxed))
    }

    /// Adds post-processing time (callable through a shared reference).
    pub fn add_post(&self, seconds: f64) {
        let mut cur = self.post_bits.load(Ordering::Relaxed);
        loop {
            let new = (f64::from_bits(cur) + seconds).to_bits();
            match self
                .post_bits
                .compare_exchange(cur, new, Ordering::Relaxed, Ordering::Relaxed)
            {
                Ok(_) => break,
                Err(actual) => cur = actual,
            }
        }
    }

    /// Substructure linear stages skipped during the last solve.
    pub fn skipped_solves(&self) -> usize {
        self.iterations.iter().map(|r| r.skipped).sum()
    }

    /// Clears the per-solve counters (the setup time stays).
    pub fn reset_solve(&mut self) {
        self.iterations.clear();
        self.post_bits.store(0f64.to_bits(), Ordering::Relaxed);
    }
}
