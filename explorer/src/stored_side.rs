//! The solver side of a run opened from its stored fields ([`crate::stored_run`]): it answers
//! the UI's requests from the [`FieldStore`] — the run's row shown as a converged solve of 0
//! iterations, the fields of a step read when asked, a probe's history read node by node
//! through the steps — and refuses what needs a solver (another parameter value, a recording)
//! with a message that says how to get it. It reads and writes only the messages of
//! [`crate::protocol`], like [`crate::service`].

use crate::fields::{self, StepFields};
use crate::params::Params;
use crate::protocol::{DisplayStep, Event, ProbeHistory, Request, SolveReport};
use crate::stored_run::{FieldStore, StoredOutcome, StoredRun};
use lopin_core::counters::{Instant, StageTimes};
use lopin_core::post::ContactHistory;
use std::sync::mpsc::Sender;
use std::sync::Arc;

/// Answers requests from stored fields.
pub(crate) struct StoredSide {
    store: Arc<dyn FieldStore>,
    params: Params,
    contact: Arc<Vec<ContactHistory>>,
    outcome: StoredOutcome,
    /// Time step and interval length, s.
    dt: f64,
    end: f64,
    steps: usize,
    /// The folder, as error messages name it.
    folder: String,
    /// Generation of the newest request shown (None: nothing shown yet).
    shown: Option<u64>,
    display_step: DisplayStep,
    events: Sender<Event>,
    wake: Arc<dyn Fn() + Send + Sync>,
}

impl StoredSide {
    /// The side of `run`, sending to `events`.
    pub(crate) fn new(
        run: &StoredRun,
        display_step: DisplayStep,
        events: Sender<Event>,
        wake: Arc<dyn Fn() + Send + Sync>,
    ) -> StoredSide {
        StoredSide {
            store: run.store.clone(),
            params: run.params.clone(),
            contact: run.contact.clone(),
            outcome: run.outcome,
            dt: run.info.dt,
            end: run.info.dt * run.info.steps as f64,
            steps: run.info.steps,
            folder: run.path.display().to_string(),
            shown: None,
            display_step,
            events,
            wake,
        }
    }

    fn send(&self, e: Event) {
        let _ = self.events.send(e);
        (self.wake)();
    }

    /// Answers one request.
    pub(crate) fn receive(&mut self, request: Request) {
        match request {
            Request::Solve {
                generation,
                params,
                row,
                ..
            } => {
                if row.is_some() || *params == self.params {
                    self.show(generation);
                } else {
                    self.send(Event::Error(format!(
                        "{}: a run opened from its stored fields shows its own parameter values \
                         only (`lopin view SCENE` re-solves the scene)",
                        self.folder
                    )));
                }
            }
            Request::Fields { step } => {
                if let Some(generation) = self.shown {
                    self.serve_fields(generation, step);
                }
            }
            Request::Probe { sub, node } => self.serve_probe(sub, node),
            Request::Record => self.send(Event::RecordFailed(format!(
                "{}: a run opened from its stored fields is recorded with `lopin export FOLDER \
                 --rerun FILE`",
                self.folder
            ))),
            Request::Release { .. } | Request::Study(_) => {}
        }
    }

    /// Shows the stored run as the converged solve of `generation`.
    fn show(&mut self, generation: u64) {
        let started = Instant::now();
        self.shown = Some(generation);
        self.serve_fields(generation, self.display_step.get());
        self.send(Event::Contact {
            generation,
            histories: self.contact.clone(),
        });
        let o = self.outcome;
        self.send(Event::Finished(Box::new(SolveReport {
            generation,
            params: self.params.clone(),
            iterations: 0,
            eta: o.eta,
            converged: o.converged,
            cancelled: false,
            warm: true,
            start: self.params.friction,
            between: None,
            from_store: true,
            solve_s: started.elapsed().as_secs_f64(),
            stages: StageTimes::default(),
        })));
    }

    fn serve_fields(&mut self, generation: u64, step: usize) {
        let step = step.min(self.steps);
        match self.store.step(step) {
            Ok(subs) => self.send(Event::Fields(Arc::new(StepFields {
                generation,
                step,
                live: false,
                subs,
            }))),
            Err(e) => self.send(Event::Error(e)),
        }
    }

    fn serve_probe(&mut self, sub: usize, node: usize) {
        let Some(generation) = self.shown else {
            return;
        };
        match self.store.node(sub, node) {
            Ok(s) => {
                let h = fields::probe_series(&s.velocity, s.von_mises, self.dt, self.end);
                let history = ProbeHistory::new(generation, sub, node, h);
                self.send(Event::Probe(Arc::new(history)));
            }
            Err(e) => self.send(Event::Error(e)),
        }
    }
}
