//! Interface fields over the whole time grid: the linear-stage output s = (F, W) per
//! substructure trace (the warm-start state of METHOD §8) and the local-stage output
//! ŝ = (F̂, Ŵ) per interface side (METHOD §6). Layout: step-major, `[m * len + j]`, m = 0..=N.
//! In a distributed run a rank stores only the histories it works on; the others are empty
//! ([`TraceHistory::absent`]) and keep their length per step.

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

    /// A history this rank does not store (a distributed run's other ranks hold it): `len`
    /// entries per step, no values.
    pub fn absent(len: usize) -> Self {
        Self {
            len,
            f: Vec::new(),
            w: Vec::new(),
        }
    }

    /// Whether the values are stored here (a history of no entries always is).
    pub fn is_present(&self) -> bool {
        self.len == 0 || !self.f.is_empty()
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
    /// W₀ = B v₀, F₀ = 0 (the preload's tractions, after a static phase).
    pub fn cold(problem: &Problem) -> Self {
        Self::cold_where(problem, &|_| true)
    }

    /// [`Self::cold`] for the substructures `keep` says, the others absent.
    pub fn cold_where(problem: &Problem, keep: &dyn Fn(usize) -> bool) -> Self {
        let steps = problem.time.steps;
        let subs = problem
            .subs
            .iter()
            .enumerate()
            .map(|(i, s)| {
                if !keep(i) {
                    return TraceHistory::absent(s.trace_len());
                }
                let mut h = TraceHistory::zeros(s.trace_len(), steps);
                for j in 0..s.trace_len() {
                    h.w[j] = s.initial_velocity[s.trace_component(j)];
                }
                if let Some(p) = &s.prestress {
                    h.f[..s.trace_len()].copy_from_slice(&p.traction);
                }
                h
            })
            .collect();
        Self { steps, subs }
    }

    /// Checks that this state has the layout of `problem` (same steps and trace sizes); absent
    /// histories (a distributed run's other ranks) pass.
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
            let stored = if h.is_present() {
                h.len * (self.steps + 1)
            } else {
                0
            };
            if h.len != s.trace_len() || h.f.len() != stored || h.w.len() != stored {
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
