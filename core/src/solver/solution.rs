//! What a solve hands out: the observer's view of each iterate ([`Iterate`]) and its answer
//! ([`Control`]), and the result of a solve ([`Solution`]: s to restart from, ŝ to report;
//! METHOD §6, §8).

use super::Solver;
use crate::counters::IterationRecord;
use crate::state::{InterfaceState, TraceHistory};

/// What an observer tells the solver after each iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on.
    Continue,
    /// Stop now (the solution is returned as not converged and cancelled).
    Stop,
}

/// What an observer sees after each iteration: the record, and the current iterate.
#[derive(Debug, Clone, Copy)]
pub struct Iterate<'a> {
    /// η, window and stage times of this iteration.
    pub record: &'a IterationRecord,
    /// The solver (problem, factorizations, settings) for post-processing the iterate.
    pub solver: &'a Solver,
    /// s = (F, W) after this iteration's relaxation.
    pub state: &'a InterfaceState,
    /// ŝ of every interface side after this iteration's local stage.
    pub hats: &'a [Vec<TraceHistory>],
    /// η after each iteration of this solve so far.
    pub eta_history: &'a [f64],
}

impl Iterate<'_> {
    /// A copy of the iterate as a (not converged) [`Solution`], so that the post-processing of
    /// [`crate::post`] can replay fields from it.
    pub fn snapshot(&self) -> Solution {
        Solution {
            state: self.state.clone(),
            hats: self.hats.to_vec(),
            iterations: self.record.iteration,
            eta: self.record.eta,
            eta_smooth: Some(self.record.eta_smooth),
            eta_history: self.eta_history.to_vec(),
            converged: false,
            cancelled: false,
            end: None,
        }
    }
}

/// The result of a solve.
#[derive(Debug, Clone)]
pub struct Solution {
    /// s = (F, W), relaxed: the state a warm start restarts from (METHOD §8).
    pub state: InterfaceState,
    /// ŝ = (F̂, Ŵ) of every interface side: the reported interface solution (METHOD §6).
    pub hats: Vec<Vec<TraceHistory>>,
    /// Total LATIN iterations.
    pub iterations: usize,
    /// Last η.
    pub eta: f64,
    /// Last η̄ (step-averaged fields; None for a solution read back from a file, which keeps
    /// only η).
    pub eta_smooth: Option<f64>,
    /// η after each iteration.
    pub eta_history: Vec<f64>,
    /// Whether every window reached η < tol.
    pub converged: bool,
    /// Whether an observer stopped the solve.
    pub cancelled: bool,
    /// The energies at the last step, taken from the last linear stages of a single-scale
    /// solve that reached the end of the interval ([`super::end_energy`]; None otherwise: a
    /// replay gives them).
    pub end: Option<super::end_energy::EndEnergy>,
}
