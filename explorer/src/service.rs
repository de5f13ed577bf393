//! The solver side of the explorer's worker: owns the [`Solver`] (factorizations computed once
//! per scene, METHOD §4), re-solves warm from the newest interface state whenever a parameter
//! moves (METHOD §8 multiresolution), and answers field, probe and record requests. It is a
//! state machine advanced one [`Service::tick`] at a time (one LATIN iteration or one request),
//! so the same code runs on a background thread on the desktop and a few iterations per frame
//! in the browser, where there are no threads. A newer solve request cancels the running solve
//! at the next tick; the cancelled iterate is still the best start for the new one. It reads
//! and writes only the messages of [`crate::protocol`].

use crate::fields;
use crate::params::Params;
use crate::protocol::{DisplayStep, Event, ProbeHistory, Request, SolveReport};
use crate::recorder::{RecordedSolve, RecorderSlot};
use lopin_core::counters::{Instant, IterationRecord};
use lopin_core::post;
use lopin_core::{Control, Problem, Solution, SolveRun, Solver};
use std::sync::mpsc::Sender;
use std::sync::Arc;

/// Seconds between two live field updates while a solve runs.
const LIVE_PERIOD_S: f64 = 0.12;

/// A solve between two ticks.
struct Running {
    generation: u64,
    params: Params,
    run: SolveRun,
    started: Instant,
    last_live: Instant,
    iterations: Vec<IterationRecord>,
}

/// The solver and everything the worker remembers between requests.
pub(crate) struct Service {
    solver: Solver,
    /// The parameter values the solver holds.
    applied: Params,
    running: Option<Running>,
    solution: Option<(u64, Solution)>,
    /// The iterations of the newest solve.
    iterations: Vec<IterationRecord>,
    /// Whether the newest solve started warm.
    warm: bool,
    /// Generation of the newest recorded solution.
    recorded: Option<u64>,
    recorder: RecorderSlot,
    display_step: DisplayStep,
    events: Sender<Event>,
    wake: Arc<dyn Fn() + Send + Sync>,
}

impl Service {
    /// Factorizes the scene's operators; a failure is sent as [`Event::Error`] and gives None.
    pub(crate) fn start(
        problem: Problem,
        settings: lopin_core::Settings,
        recorder: RecorderSlot,
        display_step: DisplayStep,
        events: Sender<Event>,
        wake: Arc<dyn Fn() + Send + Sync>,
    ) -> Option<Service> {
        let applied = Params::of(&problem, &settings);
        match Solver::new(problem, settings) {
            Ok(solver) => Some(Service {
                solver,
                applied,
                running: None,
                solution: None,
                iterations: Vec::new(),
                warm: false,
                recorded: None,
                recorder,
                display_step,
                events,
                wake,
            }),
            Err(e) => {
                let _ = events.send(Event::Error(format!("{e}")));
                wake();
                None
            }
        }
    }

    fn send(&self, e: Event) {
        let _ = self.events.send(e);
        (self.wake)();
    }

    /// Whether a solve is under way.
    pub(crate) fn solving(&self) -> bool {
        self.running.is_some()
    }

    /// Does one unit of work: starts the newest requested solve (cancelling a running one), or
    /// runs one iteration of the running solve, or serves the oldest other request (field and
    /// probe requests wait until no solve runs). Returns whether work remains.
    pub(crate) fn tick(&mut self, queue: &mut Vec<Request>) -> bool {
        if let Some(i) = queue
            .iter()
            .rposition(|c| matches!(c, Request::Solve { .. }))
        {
            let c = queue.remove(i);
            queue.retain(|c| !matches!(c, Request::Solve { .. }));
            if let Some(mut r) = self.running.take() {
                r.run.cancel();
                self.conclude(r);
            }
            if let Request::Solve { generation, params } = c {
                self.begin(generation, params);
            }
            return true;
        }
        if let Some(mut r) = self.running.take() {
            if self.iterate(&mut r) {
                self.conclude(r);
            } else {
                self.running = Some(r);
            }
            return true;
        }
        if queue.is_empty() {
            return false;
        }
        match queue.remove(0) {
            Request::Fields { step } => {
                if !queue
                    .iter()
                    .any(|q| matches!(q, Request::Fields { step: s } if *s == step))
                {
                    self.serve_fields(step);
                }
            }
            Request::Probe { sub, node } => self.serve_probe(sub, node),
            Request::Record => self.record(),
            Request::Solve { .. } => {}
        }
        !queue.is_empty()
    }

    fn begin(&mut self, generation: u64, params: Params) {
        if let Err(e) = params.apply(&self.applied, &mut self.solver) {
            self.send(Event::Error(format!("{e}")));
            return;
        }
        self.applied = params.clone();
        let start = self.solution.as_ref().map(|(_, s)| &s.state);
        match self.solver.begin(start) {
            Ok(run) => {
                self.running = Some(Running {
                    generation,
                    params,
                    run,
                    started: Instant::now(),
                    last_live: Instant::now(),
                    iterations: Vec::new(),
                })
            }
            Err(e) => self.send(Event::Error(format!("{e}"))),
        }
    }

    /// One iteration; sends its η and, every [`LIVE_PERIOD_S`], the live fields at the shown
    /// step. Returns whether the solve has ended.
    fn iterate(&mut self, r: &mut Running) -> bool {
        let (events, display) = (&self.events, &self.display_step);
        let generation = r.generation;
        let (iterations, last_live) = (&mut r.iterations, &mut r.last_live);
        let done = self.solver.step(&mut r.run, &mut |it| {
            iterations.push(*it.record);
            let _ = events.send(Event::Progress {
                generation,
                eta: it.record.eta,
            });
            if last_live.elapsed().as_secs_f64() >= LIVE_PERIOD_S {
                *last_live = Instant::now();
                let snap = it.snapshot();
                let step = display.get();
                let f = fields::compute(it.solver, &snap, step, generation, true);
                let _ = events.send(Event::Fields(Arc::new(f)));
                let c = post::contact(it.solver, &snap);
                let _ = events.send(Event::Contact {
                    generation,
                    histories: Arc::new(c),
                });
            }
            Control::Continue
        });
        (self.wake)();
        done
    }

    /// A solve ended (converged, failed or cancelled): keep its state, report, send the
    /// converged fields and record them.
    fn conclude(&mut self, r: Running) {
        if let Some(failure) = r.run.failure() {
            // keep the last good state to restart from; say where the solve broke down
            self.send(Event::Error(format!(
                "non-finite value during the solve: {failure}"
            )));
            return;
        }
        let warm = r.run.is_warm();
        let solve_s = r.started.elapsed().as_secs_f64();
        let sol = self.solver.finish(r.run);
        let report = SolveReport {
            generation: r.generation,
            params: r.params,
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            cancelled: sol.cancelled,
            warm,
            solve_s,
            stages: self.solver.counters().stage_times(),
        };
        let cancelled = sol.cancelled;
        // a cancelled iterate is still the newest state: the next solve starts there
        self.solution = Some((r.generation, sol));
        self.iterations = r.iterations;
        self.warm = warm;
        if !cancelled {
            self.serve_fields(self.display_step.get());
            if let Some((_, sol)) = &self.solution {
                let c = post::contact(&self.solver, sol);
                self.send(Event::Contact {
                    generation: r.generation,
                    histories: Arc::new(c),
                });
            }
        }
        let converged = report.converged;
        self.send(Event::Finished(report));
        if converged {
            self.record();
        }
    }

    /// Hands the newest converged solution to the recorder, if one is on and it has not seen it.
    fn record(&mut self) {
        let Some((generation, sol)) = &self.solution else {
            return;
        };
        if !sol.converged || self.recorded == Some(*generation) {
            return;
        }
        let outcome = {
            let Ok(mut slot) = self.recorder.lock() else {
                return;
            };
            let Some(rec) = slot.as_mut() else {
                return;
            };
            let solve = RecordedSolve {
                solver: &self.solver,
                solution: sol,
                iterations: &self.iterations,
                params: &self.applied,
                warm: self.warm,
            };
            rec.record(&solve).map(|()| rec.target())
        };
        let generation = *generation;
        match outcome {
            Ok(target) => {
                self.recorded = Some(generation);
                self.send(Event::Recorded { generation, target });
            }
            Err(e) => self.send(Event::RecordFailed(e)),
        }
    }

    fn serve_fields(&mut self, step: usize) {
        if let Some((generation, sol)) = &self.solution {
            let step = step.min(self.solver.problem().time.steps);
            let f = fields::compute(&self.solver, sol, step, *generation, false);
            self.send(Event::Fields(Arc::new(f)));
        }
    }

    fn serve_probe(&mut self, sub: usize, node: usize) {
        let Some((generation, sol)) = &self.solution else {
            return;
        };
        let p = self.solver.problem();
        if sub >= p.subs.len() || node >= p.subs[sub].mesh.nodes.len() {
            self.send(Event::Error(format!(
                "probe: no node {node} in substructure {sub}"
            )));
            return;
        }
        let h = fields::probe(&self.solver, sol, sub, node);
        self.send(Event::Probe(Arc::new(ProbeHistory {
            generation: *generation,
            sub,
            node,
            speed: h.0,
            von_mises: h.1,
        })));
    }
}
