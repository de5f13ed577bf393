//! The messages between the explorer's two sides: the requests the UI sends (a solve with new
//! parameters, fields at a step, a probe, a recording), the events the solver side answers with
//! (η per iteration, live and converged fields, contact histories, solve reports, probe
//! histories, recording outcomes, errors), and the displayed time step both sides share. The UI
//! side ([`crate::worker`]) and the solver side ([`crate::service`]) depend on this module and
//! on nothing of each other's messages.

use crate::fields::StepFields;
use crate::params::Params;
use lopin_core::counters::StageTimes;
use lopin_core::post::ContactHistory;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// A request from the UI.
#[derive(Debug, Clone)]
pub(crate) enum Request {
    /// Solve (warm) with these parameters; cancels a running solve.
    Solve { generation: u64, params: Params },
    /// Fields of the newest solution at this step.
    Fields { step: usize },
    /// History of one node.
    Probe { sub: usize, node: usize },
    /// Record the newest converged solution.
    Record,
}

/// How a solve ended.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveReport {
    /// Generation of the parameter change that started it.
    pub generation: u64,
    /// The parameters it solved for.
    pub params: Params,
    /// LATIN iterations of this solve.
    pub iterations: usize,
    /// Last η.
    pub eta: f64,
    /// Whether η < tol was reached.
    pub converged: bool,
    /// Whether a newer change stopped it.
    pub cancelled: bool,
    /// Whether it started from a previous state (warm) or from zero (cold).
    pub warm: bool,
    /// Wall time of the solve (without post-processing), seconds.
    pub solve_s: f64,
    /// Engine stage times accumulated over the scene (setup, local, linear, post).
    pub stages: StageTimes,
}

/// Velocity and von Mises history of one node (the probe).
#[derive(Debug, Clone, PartialEq)]
pub struct ProbeHistory {
    /// Generation of the solution it comes from.
    pub generation: u64,
    /// Substructure and node.
    pub sub: usize,
    /// Node of that substructure's mesh.
    pub node: usize,
    /// |v| per step, m/s.
    pub speed: Vec<f64>,
    /// Node-averaged von Mises stress per step, Pa.
    pub von_mises: Vec<f64>,
}

/// What the solver side tells the UI.
#[derive(Debug, Clone)]
pub enum Event {
    /// One LATIN iteration done.
    Progress {
        /// Generation of the running solve.
        generation: u64,
        /// η of this iteration.
        eta: f64,
    },
    /// Fields at one step (live iterate or converged solution).
    Fields(Arc<StepFields>),
    /// Contact histories (live iterate or converged solution).
    Contact {
        /// Generation they come from.
        generation: u64,
        /// One per contact interface.
        histories: Arc<Vec<ContactHistory>>,
    },
    /// A solve ended.
    Finished(SolveReport),
    /// A probe history is ready.
    Probe(Arc<ProbeHistory>),
    /// A converged solve was recorded.
    Recorded {
        /// Its generation.
        generation: u64,
        /// Where it went.
        target: String,
    },
    /// Recording a solve failed: the message says why.
    RecordFailed(String),
    /// A request failed (bad parameter): the message says which and why.
    Error(String),
}

/// The time step on screen, shared by the UI (which moves it) and the solver side (which
/// computes the live fields of a running solve there).
#[derive(Debug, Clone, Default)]
pub struct DisplayStep(Arc<AtomicUsize>);

impl DisplayStep {
    /// Moves the displayed step.
    pub fn set(&self, step: usize) {
        self.0.store(step, Ordering::Relaxed);
    }

    /// The displayed step.
    pub fn get(&self) -> usize {
        self.0.load(Ordering::Relaxed)
    }
}
