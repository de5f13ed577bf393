//! The explorer's "record to Rerun" hook: what a recorder is given after each converged solve
//! (solver, solution, the LATIN iterations of METHOD §7 that led to it, the parameters), and how
//! the host program supplies recorders. The explorer itself never depends on Rerun: the desktop
//! binary passes a [`RecorderFactory`] built on the rerun SDK, the web build passes none (and the
//! toggle says why it is unavailable).

use crate::params::Params;
use lopin_core::counters::IterationRecord;
use lopin_core::{Solution, Solver};
use std::sync::{Arc, Mutex};

/// One converged solve, as a recorder sees it.
pub struct RecordedSolve<'a> {
    /// The solver (problem, settings, factorizations).
    pub solver: &'a Solver,
    /// The converged solution.
    pub solution: &'a Solution,
    /// The LATIN iterations of this solve, in order.
    pub iterations: &'a [IterationRecord],
    /// The parameters it solved for.
    pub params: &'a Params,
    /// Whether it started from the previous solution.
    pub warm: bool,
}

/// Something that records solves (a Rerun recording on the desktop).
pub trait SolveRecorder: Send {
    /// Where the recording goes (a file or a viewer address), shown in the UI.
    fn target(&self) -> String;
    /// Records one converged solve; the message says what failed.
    fn record(&mut self, solve: &RecordedSolve<'_>) -> Result<(), String>;
}

/// Makes a recorder for a scene (its name); the message says why it could not.
type MakeRecorder = dyn Fn(&str) -> Result<Box<dyn SolveRecorder>, String> + Send + Sync;

/// How the host program makes recorders; `None` in [`crate::Options`] hides recording.
#[derive(Clone)]
pub struct RecorderFactory(pub Arc<MakeRecorder>);

impl RecorderFactory {
    /// Wraps a closure.
    pub fn new(
        make: impl Fn(&str) -> Result<Box<dyn SolveRecorder>, String> + Send + Sync + 'static,
    ) -> Self {
        RecorderFactory(Arc::new(make))
    }

    /// A recorder for scene `name`.
    pub fn make(&self, name: &str) -> Result<Box<dyn SolveRecorder>, String> {
        (self.0)(name)
    }
}

impl std::fmt::Debug for RecorderFactory {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("RecorderFactory")
    }
}

impl PartialEq for RecorderFactory {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The recorder in use, shared by the UI (which switches it on and off) and the solver thread
/// (which records into it).
pub type RecorderSlot = Arc<Mutex<Option<Box<dyn SolveRecorder>>>>;
