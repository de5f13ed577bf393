//! The solve as the UI sees it: it owns the [`Worker`] handle, the parameter values the controls
//! show and those of the newest request, where the solver stands, every η so far with a marker
//! at each parameter change (the convergence plot), the reports of the finished solves, the
//! re-solve latency and the last error message. It applies the worker's events each frame,
//! handing fields, contact histories and probes to the [`FieldCache`], recording outcomes to
//! the [`Recording`] and the study's stored configurations to the [`StudyView`].

use crate::field_cache::FieldCache;
use crate::measure::Measure;
use crate::params::Params;
use crate::protocol::{Event, SolveReport};
use crate::recording::Recording;
use crate::study_view::StudyView;
use crate::worker::Worker;
use lopin_core::counters::Instant;

/// Where the solver stands.
#[derive(Debug, Clone, PartialEq)]
pub enum SolveStatus {
    /// Factorizing / first solve not started.
    Starting,
    /// A solve runs.
    Running {
        /// Its generation.
        generation: u64,
        /// Iterations so far.
        iterations: usize,
        /// Last η.
        eta: f64,
    },
    /// The newest solve ended.
    Done(Box<SolveReport>),
    /// Something failed.
    Failed(String),
}

/// The solve view: parameters, solver status, convergence history and the worker.
pub struct SolveView {
    worker: Worker,
    /// Parameter values shown by the controls.
    params: Params,
    /// Parameter values of the newest solve requested.
    requested: Params,
    status: SolveStatus,
    /// Every η so far: (cumulative iteration, η).
    convergence: Vec<[f64; 2]>,
    /// Parameter changes: (cumulative iteration, description).
    markers: Vec<(f64, String)>,
    /// Reports of the finished solves, oldest first.
    reports: Vec<SolveReport>,
    /// Last error message (bad parameter, failed load, recording).
    error: Option<String>,
    /// Time of the newest parameter change.
    change_time: Option<Instant>,
    /// Seconds from the newest parameter change to its converged solve.
    last_latency: Option<f64>,
    /// The held solve to release at the start of the next frame ([`SolveView::release_held`]).
    to_release: Option<u64>,
}

impl SolveView {
    /// Starts the first (cold) solve with `params` on `worker`.
    pub fn start(mut worker: Worker, params: Params) -> SolveView {
        worker.solve(params.clone());
        SolveView::start_idle(worker, params)
    }

    /// The view of `worker`, nothing requested yet.
    fn start_idle(worker: Worker, params: Params) -> SolveView {
        SolveView {
            worker,
            requested: params.clone(),
            params,
            status: SolveStatus::Starting,
            convergence: Vec::new(),
            markers: vec![(0.0, "start".into())],
            reports: Vec::new(),
            error: None,
            change_time: Some(Instant::now()),
            last_latency: None,
            to_release: None,
        }
    }

    /// Starts by showing row `row` (named `name`) of the opened result folder, with its
    /// parameters `params`, on `worker`.
    pub fn start_row(worker: Worker, params: Params, row: usize, name: String) -> SolveView {
        let mut view = SolveView::start_idle(worker, params);
        view.markers[0].1 = name;
        view.worker.show_row(view.params.clone(), row);
        view
    }

    /// Shows row `row` (named `name`) of the opened result folder with its parameters `params`:
    /// the controls take them, a running solve is cancelled. Returns the request's generation.
    pub fn show_row(&mut self, params: Params, row: usize, name: String) -> u64 {
        self.params = params.clone();
        self.requested_now(name);
        self.worker.show_row(params, row)
    }

    /// The controls' values were requested (marked `what` on the convergence plot): the
    /// latency clock starts, the last error goes.
    fn requested_now(&mut self, what: String) {
        self.markers.push((self.convergence.len() as f64, what));
        self.requested = self.params.clone();
        self.change_time = Some(Instant::now());
        self.last_latency = None;
        self.error = None;
    }

    /// Lets the solve requested in the previous frame iterate: that frame, which shows the new
    /// value's first picture, has been drawn (called at the start of every frame).
    pub fn release_held(&mut self) {
        if let Some(generation) = self.to_release.take() {
            self.worker.release(generation);
        }
    }

    /// The worker, for the states that send it requests (fields, probes, recordings).
    pub fn worker(&mut self) -> &mut Worker {
        &mut self.worker
    }

    /// Parameter values shown by the controls.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The controls' values, to edit: a change launches a re-solve at the end of the frame
    /// ([`SolveView::resolve_if_changed`]).
    pub fn params_mut(&mut self) -> &mut Params {
        &mut self.params
    }

    /// Parameter values of the newest solve requested.
    pub fn requested(&self) -> &Params {
        &self.requested
    }

    /// Where the solver stands.
    pub fn status(&self) -> &SolveStatus {
        &self.status
    }

    /// Every η so far: (cumulative iteration, η).
    pub fn convergence(&self) -> &[[f64; 2]] {
        &self.convergence
    }

    /// Parameter changes: (cumulative iteration, description); the first is the start.
    pub fn markers(&self) -> &[(f64, String)] {
        &self.markers
    }

    /// Reports of the finished solves, oldest first.
    pub fn reports(&self) -> &[SolveReport] {
        &self.reports
    }

    /// Last error message (bad parameter, failed load, recording).
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Shows an error message until the next parameter change.
    pub fn set_error(&mut self, message: String) {
        self.error = Some(message);
    }

    /// Seconds from the newest parameter change to its converged solve.
    pub fn last_latency(&self) -> Option<f64> {
        self.last_latency
    }

    /// Generation of the newest parameter change.
    pub fn generation(&self) -> u64 {
        self.worker.generation()
    }

    /// Whether the newest request has converged.
    pub fn converged(&self) -> bool {
        matches!(&self.status, SolveStatus::Done(r)
            if r.converged && r.generation == self.worker.generation())
    }

    /// Whether the newest request is still being solved.
    pub fn busy(&self) -> bool {
        !matches!(&self.status, SolveStatus::Done(r) if r.generation == self.worker.generation())
            && !matches!(self.status, SolveStatus::Failed(_))
    }

    /// Generation of the newest solve that ended without being cancelled (0: none yet).
    pub fn last_done_generation(&self) -> u64 {
        self.reports
            .iter()
            .rev()
            .find(|r| !r.cancelled)
            .map_or(0, |r| r.generation)
    }

    /// Whether the solver runs behind a byte link (the browser's Web Worker).
    pub fn remote(&self) -> bool {
        self.worker.is_remote()
    }

    /// Whether the solver runs on the UI thread (browser) and needs another frame to go on.
    pub fn needs_frames(&self) -> bool {
        self.worker.needs_frames()
    }

    /// Launches a warm re-solve if the controls moved since the newest request (a running
    /// solve is cancelled and the new one starts from the nearest stored configuration or its
    /// newest iterate). Returns the new request's generation, if one was sent.
    pub fn resolve_if_changed(&mut self) -> Option<u64> {
        if self.params == self.requested {
            return None;
        }
        let what = self.params.describe_change(&self.requested);
        self.requested_now(what);
        if self.worker.is_remote() {
            // a solver with its own thread in the browser begins at once
            return Some(self.worker.solve(self.params.clone()));
        }
        // held until the next frame: this frame draws the new value's first picture
        let generation = self.worker.solve_held(self.params.clone());
        self.to_release = Some(generation);
        Some(self.worker.generation())
    }

    /// Receives the worker's events: η, status and reports stay here, fields, contact
    /// histories and probes go to `cache`, recording outcomes to `recording`, stored
    /// configurations to `study`, finished solves to `measure`.
    pub fn apply_events(
        &mut self,
        cache: &mut FieldCache,
        recording: &mut Recording,
        study: &mut StudyView,
        mut measure: Option<&mut Measure>,
    ) {
        for e in self.worker.poll() {
            self.apply(e, cache, recording, study, measure.as_deref_mut());
        }
    }

    fn apply(
        &mut self,
        e: Event,
        cache: &mut FieldCache,
        recording: &mut Recording,
        study: &mut StudyView,
        measure: Option<&mut Measure>,
    ) {
        let newest = self.worker.generation();
        match e {
            Event::Progress { generation, eta } => {
                self.convergence
                    .push([self.convergence.len() as f64 + 1.0, eta]);
                let iterations = match &self.status {
                    SolveStatus::Running {
                        generation: g,
                        iterations,
                        ..
                    } if *g == generation => iterations + 1,
                    _ => 1,
                };
                if generation == newest {
                    self.status = SolveStatus::Running {
                        generation,
                        iterations,
                        eta,
                    };
                }
            }
            Event::Fields(f) => cache.receive_fields(f, newest),
            Event::Contact {
                generation,
                histories,
            } => {
                if generation == newest {
                    cache.receive_contact(histories);
                }
            }
            Event::Finished(report) => {
                if report.generation == newest {
                    if report.converged {
                        self.last_latency = self.change_time.map(|t| t.elapsed().as_secs_f64());
                    }
                    cache.solve_finished(&mut self.worker);
                    self.status = SolveStatus::Done(report.clone());
                }
                if let Some(m) = measure {
                    m.on_finished(&report, self.last_latency);
                }
                self.reports.push(*report);
            }
            Event::Probe(p) => cache.receive_probe(p),
            Event::Recorded { target, .. } => recording.recorded(target),
            Event::RecordFailed(msg) => self.error = Some(format!("recording: {msg}")),
            Event::Error(msg) => {
                self.error = Some(msg.clone());
                self.status = SolveStatus::Failed(msg);
            }
            Event::StudyReset { grid } => study.reset(grid),
            Event::Stored(c) => study.receive(&c),
            Event::Background(value) => study.set_running(value),
        }
    }
}
