//! Interface fields over the whole time grid: the linear-stage output s = (F, W) per
//! substructure trace (the warm-start state of METHOD §8) and the local-stage output
//! ŝ = (F̂, Ŵ) per interface side (METHOD §6). Layout: step-major, `[m * len + j]`, m = 0..=N.

use crate::error::{LopinError, Result};
use crate::problem::Problem;

/// (F, W) of one trace (substructure trace or interface side) at every step m = 0..=N.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TraceHistory {
    /// Entries per step.
    pub len: usize,
    /// F, step-major.
    pub f: Vec<f64>,
    /// W, step-major.
    pub w: Vec<f64>,
}

impl TraceHistory {
    /// Zero fields for steps 0..=steps.
    pub fn zeros(len: usize, steps: usize) -> Self {
        Self {
            len,
            f: vec![0.0; len * (steps + 1)],
            w: vec![0.0; len * (steps + 1)],
        }
    }

    /// Range of step m in the arrays.
    pub fn at(&self, m: usize) -> std::ops::Range<usize> {
        m * self.len..(m + 1) * self.len
    }
}

/// s = (F, W) for every substructure trace at every step: what a warm start restarts from.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct InterfaceState {
    /// Number of time steps N.
    pub steps: usize,
    /// One history per substructure (trace layout of METHOD §11).
    pub subs: Vec<TraceHistory>,
}

impl InterfaceState {
    /// The cold start of METHOD §6: F = W = 0 for m ≥ 1; at m = 0 the given initial state
    /// W₀ = B v₀, F₀ = 0.
    pub fn cold(problem: &Problem) -> Self {
        let steps = problem.time.steps;
        let subs = problem
            .subs
            .iter()
            .map(|s| {
                let mut h = TraceHistory::zeros(s.trace_len(), steps);
                for (j, &d) in s.trace_dofs.iter().enumerate() {
                    h.w[j] = s.initial_velocity[d % 3];
                }
                h
            })
            .collect();
        Self { steps, subs }
    }

    /// Checks that this state has the layout of `problem` (same steps and trace sizes).
    pub fn check_fits(&self, problem: &Problem) -> Result<()> {
        if self.steps != problem.time.steps {
            return Err(LopinError::StateMismatch(format!(
                "{} steps in the state, {} in the problem",
                self.steps, problem.time.steps
            )));
        }
        if self.subs.len() != problem.subs.len() {
            return Err(LopinError::StateMismatch(format!(
                "{} substructures in the state, {} in the problem",
                self.subs.len(),
                problem.subs.len()
            )));
        }
        for (h, s) in self.subs.iter().zip(&problem.subs) {
            if h.len != s.trace_len() || h.f.len() != h.len * (self.steps + 1) {
                return Err(LopinError::StateMismatch(format!(
                    "substructure `{}` has {} trace dofs, the state {}",
                    s.name,
                    s.trace_len(),
                    h.len
                )));
            }
        }
        Ok(())
    }

    /// Number of stored doubles (F and W).
    pub fn size(&self) -> usize {
        self.subs.iter().map(|h| h.f.len() + h.w.len()).sum()
    }
}
