//! The messages between the explorer's two sides: the requests the UI sends (a solve with new
//! parameters, fields at a step, a probe, a recording), the events the solver side answers with
//! (η per iteration, live and converged fields, contact histories, solve reports, probe
//! histories, recording outcomes, the study's stored configurations, errors), and the displayed
//! time step both sides share. The UI
//! side ([`crate::worker`]) and the solver side ([`crate::service`]) depend on this module and
//! on nothing of each other's messages.

use crate::fields::StepFields;
use crate::params::Params;
use crate::picture::Picture;
use lopin_core::counters::StageTimes;
use lopin_core::post::ContactHistory;
use lopin_core::study::Quantities;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

/// A request from the UI.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(crate) enum Request {
    /// Solve (warm) with these parameters; cancels a running solve. A held solve begins only
    /// on [`Request::Release`] of its generation: the UI releases it when the next frame
    /// starts, so that the solver does not share the cores with the drawing of the frame that
    /// shows the stand-in picture.
    /// With `row`, the configuration of that row of the opened result folder: its stored
    /// solution shown, or its stored state the start of the solve.
    Solve {
        generation: u64,
        params: Box<Params>,
        held: bool,
        row: Option<usize>,
    },
    /// Lets a held solve begin.
    Release { generation: u64 },
    /// Fields of the newest solution at this step.
    Fields { step: usize },
    /// History of one node.
    Probe { sub: usize, node: usize },
    /// Record the newest converged solution.
    Record,
    /// Pause or resume the background study, how long the user must be idle before it runs,
    /// and the configuration compared with the current one.
    Study(StudyControl),
}

/// How the background study runs.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StudyControl {
    /// No background solve while paused.
    pub paused: bool,
    /// Seconds without a parameter change (and with no re-solve running) before it runs.
    pub idle_s: f64,
    /// The friction value of the configuration the UI compares with the current one (pinned
    /// "A"): when it is stored, its picture at the displayed step comes first, without waiting
    /// for the user to be idle, paused or not.
    pub pinned: Option<f64>,
    /// How many values it solves at once, on lanes that share the factorizations (each lane
    /// holds one solve's state besides the stored configurations).
    pub lanes: usize,
}

/// How many values the background study solves at once unless told otherwise.
pub const BACKGROUND_LANES: usize = 4;

impl Default for StudyControl {
    fn default() -> Self {
        StudyControl {
            paused: false,
            idle_s: 1.0,
            pinned: None,
            lanes: BACKGROUND_LANES,
        }
    }
}

/// A converged configuration the solver side stored (a background solve, a user's re-solve, or
/// a new picture of a stored one at another time step).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StoredConfig {
    /// Friction coefficient.
    pub value: f64,
    /// Iterations of its solve.
    pub iterations: usize,
    /// Whether the background study solved it.
    pub background: bool,
    /// The friction coefficient of the state its solve started from (None: cold, or a picture
    /// of a configuration stored before).
    pub start: Option<f64>,
    /// Its quantities of interest.
    pub quantities: Quantities,
    /// What the UI draws of it at once.
    pub picture: Picture,
    /// Configurations stored on the solver side.
    pub stored: usize,
    /// Bytes of their states (s and ŝ in f32) on the solver side.
    pub store_bytes: usize,
}

/// How a solve ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// The friction coefficient of the state it started from (a stored configuration or the
    /// newest state), or, with `from_store`, of the one shown; None: cold.
    pub start: Option<f64>,
    /// The two stored friction values whose states, interpolated, it started from (`start` is
    /// then the nearer of them).
    pub between: Option<(f64, f64)>,
    /// Whether the value was stored already and is shown without solving (0 iterations).
    pub from_store: bool,
    /// Wall time of the solve (without post-processing), seconds.
    pub solve_s: f64,
    /// Engine stage times accumulated over the scene (setup, local, linear, post).
    pub stages: StageTimes,
}

/// Velocity and von Mises history of one node (the probe).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// |a| of the step-averaged acceleration (v_m − v_{m−1})/Δt per step m ≥ 1, m/s².
    pub acceleration: Vec<f64>,
    /// Its shock response spectrum per component: (natural frequency in Hz, maximax of x, y, z
    /// in m/s²) at Q = 10 ([`crate::fields::PROBE_Q`]).
    pub spectrum: Vec<(f64, [f64; 3])>,
}

impl ProbeHistory {
    /// The history of node `node` of substructure `sub` from its series, for `generation`.
    pub fn new(generation: u64, sub: usize, node: usize, s: crate::fields::ProbeSeries) -> Self {
        ProbeHistory {
            generation,
            sub,
            node,
            speed: s.speed,
            von_mises: s.von_mises,
            acceleration: s.acceleration,
            spectrum: s.spectrum,
        }
    }
}

/// What the solver side tells the UI.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
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
    Finished(Box<SolveReport>),
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
    /// The study's library was emptied (a parameter other than friction moved): it covers
    /// these friction values.
    StudyReset {
        /// The background study's values.
        grid: Vec<f64>,
    },
    /// A configuration was stored, or a stored one pictured at the displayed step.
    Stored(Arc<StoredConfig>),
    /// The friction values the background study is solving now (empty: none).
    Background(Vec<f64>),
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
