//! The background solver of the explorer: one thread owns the [`Solver`] (factorizations
//! computed once per scene, METHOD §4), re-solves warm from the newest interface state whenever
//! a parameter moves (METHOD §8 multiresolution), and streams η, live fields at the displayed
//! step and, at the end, the interface histories back to the UI. A newer parameter change
//! cancels the running solve through a shared generation counter; nothing on the UI thread
//! ever waits for the solver. While recording is on, each converged solve is handed to the
//! recorder (see [`crate::recorder`]) from this thread.

use crate::fields::{self, StepFields};
use crate::params::Params;
use crate::recorder::{RecordedSolve, RecorderSlot};
use lopin_core::counters::{Instant, IterationRecord, StageTimes};
use lopin_core::post::{self, ContactHistory};
use lopin_core::{Control, InterfaceState, Problem, Solution, Solver};
use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender, TryRecvError};
use std::sync::Arc;

/// Seconds between two live field updates while a solve runs.
const LIVE_PERIOD_S: f64 = 0.12;

/// A request from the UI.
#[derive(Debug, Clone)]
enum Command {
    Solve { generation: u64, params: Params },
    Fields { step: usize },
    Probe { sub: usize, node: usize },
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

/// What the worker tells the UI.
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

/// The UI side of the worker: send changes, receive events.
pub struct Worker {
    commands: Sender<Command>,
    events: Receiver<Event>,
    latest: Arc<AtomicU64>,
    display_step: Arc<AtomicUsize>,
    generation: u64,
}

impl Worker {
    /// Starts the worker thread for a built problem (the factorizations are computed there, so
    /// the UI never waits for them; a failure arrives as [`Event::Error`]); `wake` is called
    /// after each event so the UI can repaint. Converged solves go to the recorder in `recorder`
    /// whenever it holds one.
    pub fn spawn(
        problem: Problem,
        settings: lopin_core::Settings,
        wake: Arc<dyn Fn() + Send + Sync>,
        recorder: RecorderSlot,
    ) -> lopin_core::Result<Worker> {
        settings.validate()?;
        let (ctx, crx) = channel();
        let (etx, erx) = channel();
        let latest = Arc::new(AtomicU64::new(0));
        let display_step = Arc::new(AtomicUsize::new(0));
        let applied = Params::of(&problem, &settings);
        let (latest_w, display_w) = (latest.clone(), display_step.clone());
        std::thread::Builder::new()
            .name("lopin-solver".into())
            .spawn(move || match Solver::new(problem, settings) {
                Ok(solver) => WorkerState {
                    solver,
                    applied,
                    solution: None,
                    iterations: Vec::new(),
                    warm: false,
                    recorded: None,
                    recorder,
                    latest: latest_w,
                    display_step: display_w,
                    events: etx,
                    wake,
                }
                .serve(&crx),
                Err(e) => {
                    let _ = etx.send(Event::Error(format!("{e}")));
                    wake();
                }
            })
            .map_err(|e| lopin_core::LopinError::setting("thread", format!("cannot start: {e}")))?;
        Ok(Worker {
            commands: ctx,
            events: erx,
            latest,
            display_step,
            generation: 0,
        })
    }

    /// Asks for a (warm) re-solve with these parameters; cancels a running one. Returns its
    /// generation.
    pub fn solve(&mut self, params: Params) -> u64 {
        self.generation += 1;
        self.latest.store(self.generation, Ordering::SeqCst);
        let _ = self.commands.send(Command::Solve {
            generation: self.generation,
            params,
        });
        self.generation
    }

    /// The step shown on screen (live fields are computed there).
    pub fn set_display_step(&self, step: usize) {
        self.display_step.store(step, Ordering::Relaxed);
    }

    /// Asks for the fields of the latest solution at `step`.
    pub fn request_fields(&self, step: usize) {
        let _ = self.commands.send(Command::Fields { step });
    }

    /// Asks for the history of one node.
    pub fn request_probe(&self, sub: usize, node: usize) {
        let _ = self.commands.send(Command::Probe { sub, node });
    }

    /// Asks to record the newest converged solution (when recording is switched on).
    pub fn request_record(&self) {
        let _ = self.commands.send(Command::Record);
    }

    /// Events received since the last call.
    pub fn poll(&self) -> Vec<Event> {
        self.events.try_iter().collect()
    }

    /// Blocks until the next event (tests and benchmarks).
    pub fn wait(&self, timeout: std::time::Duration) -> Option<Event> {
        self.events.recv_timeout(timeout).ok()
    }

    /// Generation of the newest change.
    pub fn generation(&self) -> u64 {
        self.generation
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        // stops a running solve; the thread ends when it sees the channel closed
        self.latest.store(u64::MAX, Ordering::SeqCst);
    }
}

struct WorkerState {
    solver: Solver,
    /// The parameter values the solver holds.
    applied: Params,
    solution: Option<(u64, Solution)>,
    /// The iterations of the newest solve.
    iterations: Vec<IterationRecord>,
    /// Whether the newest solve started warm.
    warm: bool,
    /// Generation of the newest recorded solution.
    recorded: Option<u64>,
    recorder: RecorderSlot,
    latest: Arc<AtomicU64>,
    display_step: Arc<AtomicUsize>,
    events: Sender<Event>,
    wake: Arc<dyn Fn() + Send + Sync>,
}

impl WorkerState {
    fn send(&self, e: Event) {
        let _ = self.events.send(e);
        (self.wake)();
    }

    fn serve(&mut self, commands: &Receiver<Command>) {
        let mut queue: Vec<Command> = Vec::new();
        loop {
            if queue.is_empty() {
                match commands.recv() {
                    Ok(c) => queue.push(c),
                    Err(_) => return,
                }
            }
            loop {
                match commands.try_recv() {
                    Ok(c) => queue.push(c),
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return,
                }
            }
            // only the newest solve matters; field and probe requests are served after it
            let newest = queue
                .iter()
                .rposition(|c| matches!(c, Command::Solve { .. }));
            if let Some(i) = newest {
                let c = queue.remove(i);
                queue.retain(|c| !matches!(c, Command::Solve { .. }));
                if let Command::Solve { generation, params } = c {
                    self.run_solve(generation, &params);
                }
                continue;
            }
            let c = queue.remove(0);
            match c {
                Command::Fields { step } => {
                    if !queue
                        .iter()
                        .any(|q| matches!(q, Command::Fields { step: s } if *s == step))
                    {
                        self.serve_fields(step);
                    }
                }
                Command::Probe { sub, node } => self.serve_probe(sub, node),
                Command::Record => self.record(),
                Command::Solve { .. } => {}
            }
        }
    }

    fn run_solve(&mut self, generation: u64, params: &Params) {
        if let Err(e) = params.apply(&self.applied, &mut self.solver) {
            self.send(Event::Error(format!("{e}")));
            return;
        }
        self.applied = params.clone();
        let start: Option<InterfaceState> = self.solution.as_ref().map(|(_, s)| s.state.clone());
        let warm = start.is_some();
        let t0 = Instant::now();
        let mut last_live = Instant::now();
        let latest = self.latest.clone();
        let display = self.display_step.clone();
        let events = self.events.clone();
        let wake = self.wake.clone();
        let mut iterations = Vec::new();
        let result = self.solver.solve_observed(start.as_ref(), &mut |it| {
            iterations.push(*it.record);
            let _ = events.send(Event::Progress {
                generation,
                eta: it.record.eta,
            });
            if latest.load(Ordering::SeqCst) != generation {
                wake();
                return Control::Stop;
            }
            if last_live.elapsed().as_secs_f64() >= LIVE_PERIOD_S {
                last_live = Instant::now();
                let snap = it.snapshot();
                let step = display.load(Ordering::Relaxed);
                let f = fields::compute(it.solver, &snap, step, generation, true);
                let _ = events.send(Event::Fields(Arc::new(f)));
                let c = post::contact(it.solver, &snap);
                let _ = events.send(Event::Contact {
                    generation,
                    histories: Arc::new(c),
                });
            }
            wake();
            Control::Continue
        });
        let solve_s = t0.elapsed().as_secs_f64();
        match result {
            Ok(sol) => {
                let report = SolveReport {
                    generation,
                    params: params.clone(),
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
                self.solution = Some((generation, sol));
                self.iterations = iterations;
                self.warm = warm;
                if !cancelled {
                    self.serve_fields(self.display_step.load(Ordering::Relaxed));
                    if let Some((_, sol)) = &self.solution {
                        let c = post::contact(&self.solver, sol);
                        self.send(Event::Contact {
                            generation,
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
            Err(e) => self.send(Event::Error(format!("{e}"))),
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
