//! The solver side of the explorer's worker: owns the [`Solver`] (factorizations computed once
//! per scene, METHOD §4), re-solves warm whenever a parameter moves (METHOD §8 multiresolution:
//! from the nearest stored configuration, or the newest interface state), and answers field,
//! probe and record requests. It also runs the background study ([`crate::study`]): when the
//! user has been idle for a while, it solves the friction grid's values nearest-first, several
//! at once on lanes that share the factorizations ([`crate::background`]), each warm from its
//! nearest stored neighbour, and keeps every converged configuration (states in f32,
//! a picture for the UI), so a value already stored is shown again without solving; the
//! configuration the UI compares with (pinned "A") is pictured at each displayed step first,
//! paused or not. It is a
//! state machine advanced one [`Service::tick`] at a time (one LATIN iteration or one request),
//! so the same code runs on a background thread on the desktop and a few iterations per frame
//! in the browser's worker. A newer solve request cancels the running solve (the user's or the
//! background's) at the next tick; a cancelled user iterate is still a good start for the new
//! one. It reads and writes only the messages of [`crate::protocol`].

use crate::background::{BackgroundSolve, Lanes};
use crate::fields::{self, StepFields};
use crate::params::Params;
use crate::picture::Picture;
use crate::protocol::{
    DisplayStep, Event, ProbeHistory, Request, SolveReport, StoredConfig, StudyControl,
};
use crate::recorder::{RecordedSolve, RecorderSlot};
use crate::result_folder::{RowSource, StoredResult};
use crate::schedule::Next;
use crate::study::{self, Library, StoredStart};
use lopin_core::counters::{Instant, IterationRecord};
use lopin_core::post;
use lopin_core::state::InterfaceState;
use lopin_core::study::Quantities;
use lopin_core::{Control, Problem, Solution, SolveRun, Solver};
use std::sync::mpsc::Sender;
use std::sync::Arc;
use std::time::Duration;

/// Seconds between two live field updates while a solve runs (unless set otherwise,
/// [`Service::set_live_period`]).
const LIVE_PERIOD_S: f64 = 0.12;

/// The user's solve between two ticks.
struct Running {
    /// The generation of the change it solves.
    generation: u64,
    params: Params,
    run: SolveRun,
    /// The friction value of the state it started from (between two, the nearer).
    start: Option<f64>,
    /// The two stored friction values whose interpolated states it started from.
    between: Option<(f64, f64)>,
    started: Instant,
    last_live: Instant,
    iterations: Vec<IterationRecord>,
}

/// What the library keeps of a converged configuration besides its states: its quantities of
/// interest and its picture at the displayed step.
struct Kept {
    quantities: Quantities,
    picture: Picture,
}

impl Kept {
    /// Of `sol`, solved by `solver` (set to its parameters), with its fields `f`.
    fn of(solver: &Solver, sol: &Solution, f: &StepFields) -> Kept {
        let c = post::contact(solver, sol);
        Kept {
            quantities: Quantities::of(solver, sol),
            picture: Picture::of(f, &c),
        }
    }
}

/// The newest solution the user asked for.
struct Current {
    generation: u64,
    solution: Solution,
    params: Params,
}

/// The solver and everything the worker remembers between requests.
pub(crate) struct Service {
    /// The user's solver (the background study solves on lanes of its own).
    solver: Solver,
    /// The parameter values the solver holds.
    applied: Params,
    running: Option<Running>,
    /// The background study's configurations in progress.
    background: Lanes,
    current: Option<Current>,
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
    /// The converged configurations of the study.
    library: Library,
    control: StudyControl,
    /// When the newest solve request arrived.
    last_change: Instant,
    /// The user's solve that waits for its release ([`Request::Release`]) before it begins.
    held: Option<(u64, Params)>,
    /// The rows of the opened result folder and their loader.
    rows: Option<RowSource>,
    /// Seconds between two live field updates while a solve runs.
    live_period_s: f64,
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
        rows: Option<RowSource>,
    ) -> Option<Service> {
        let applied = Params::of(&problem, &settings);
        match Solver::new(problem, settings) {
            Ok(solver) => Some(Service {
                solver,
                applied,
                running: None,
                background: Lanes::default(),
                current: None,
                iterations: Vec::new(),
                warm: false,
                recorded: None,
                recorder,
                display_step,
                events,
                wake,
                library: Library::default(),
                control: StudyControl::default(),
                last_change: Instant::now(),
                held: None,
                rows,
                live_period_s: LIVE_PERIOD_S,
            }),
            Err(e) => {
                let _ = events.send(Event::Error(format!("{e}")));
                wake();
                None
            }
        }
    }

    /// Sets how often a running solve's live fields are computed: a UI that draws them
    /// seldom spares the solver the work.
    pub(crate) fn set_live_period(&mut self, period: Duration) {
        self.live_period_s = period.as_secs_f64();
    }

    fn send(&self, e: Event) {
        let _ = self.events.send(e);
        (self.wake)();
    }

    /// Whether a solve is under way (the user's or the background study's) or waits for its
    /// release.
    pub(crate) fn solving(&self) -> bool {
        self.running.is_some() || self.held.is_some() || !self.background.is_empty()
    }

    /// Whether the running solve is the background study's (requests are served before its
    /// next iteration; the solver thread pauses after each of them).
    pub(crate) fn in_background(&self) -> bool {
        self.running.is_none() && !self.background.is_empty()
    }

    /// Does one unit of work: applies study controls, starts the newest requested solve
    /// (cancelling a running one; a held one begins when its release comes), or serves the
    /// oldest other request first if only the background study is solving, or runs one
    /// iteration of the running solve, or serves the oldest other request (field and probe
    /// requests wait while the user's solve runs), or, with nothing else to do, one unit of the
    /// background study. Returns whether work remains.
    pub(crate) fn tick(&mut self, queue: &mut Vec<Request>) -> bool {
        while let Some(i) = queue.iter().position(|c| matches!(c, Request::Study(_))) {
            if let Request::Study(c) = queue.remove(i) {
                self.control = c;
                if c.paused {
                    self.cancel_background();
                }
            }
        }
        let solve = queue
            .iter()
            .rposition(|c| matches!(c, Request::Solve { .. }));
        if let Some(i) = solve {
            let c = queue.remove(i);
            queue.retain(|c| !matches!(c, Request::Solve { .. }));
            self.last_change = Instant::now();
            if let Some(mut r) = self.running.take() {
                r.run.cancel();
                self.conclude(r);
            }
            if self.background.forget() {
                self.send(Event::Background(Vec::new()));
            }
            self.held = None;
            if let Request::Solve {
                generation,
                params,
                held,
                row,
            } = c
            {
                let params = *params;
                if let Some(row) = row {
                    self.begin_row(generation, params, row);
                } else if held {
                    // begun on its release: the frame drawing its first picture keeps the cores
                    self.held = Some((generation, params));
                } else {
                    self.begin(generation, params);
                }
            }
        }
        // (a release may come in the same batch as its request: the UI's next frame came first)
        while let Some(i) = queue
            .iter()
            .position(|c| matches!(c, Request::Release { .. }))
        {
            if let Request::Release { generation } = queue.remove(i) {
                if let Some((g, params)) = self.held.take_if(|h| h.0 == generation) {
                    self.begin(g, params);
                }
            }
        }
        if solve.is_some() {
            return true;
        }
        // requests are served before the background study's next iteration
        if !self.in_background() || queue.is_empty() {
            if let Some(mut r) = self.running.take() {
                if self.iterate(&mut r) {
                    self.conclude(r);
                } else {
                    self.running = Some(r);
                }
                return true;
            }
            if !self.background.is_empty() {
                for ended in self.background.step() {
                    self.conclude_background(ended);
                }
                self.fill_lanes();
                return true;
            }
        }
        if queue.is_empty() {
            return self.study_tick();
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
            Request::Solve { .. } | Request::Study(_) | Request::Release { .. } => {}
        }
        true
    }

    /// One [`Service::tick`], and what to do next: at once while work remains, after a pause
    /// as long as the tick when it was the background study's, else wait for a request (or for
    /// the background work due after [`Service::idle_wait`]).
    pub(crate) fn work(&mut self, queue: &mut Vec<Request>) -> Next {
        let started = Instant::now();
        if !self.tick(queue) {
            Next::Wait(self.idle_wait())
        } else if self.in_background() {
            Next::After(started.elapsed())
        } else {
            Next::Now
        }
    }

    /// How long to wait for a request before [`Service::tick`] has background work (None:
    /// none is coming until a request arrives).
    pub(crate) fn idle_wait(&self) -> Option<Duration> {
        if self.pinned_unpictured().is_some() {
            return Some(Duration::ZERO);
        }
        let current = self.study_value()?;
        let step = self.display_step.get();
        let work = self.library.next_value(current, &[]).is_some()
            || self.library.next_picture(current, step).is_some();
        if !work {
            return None;
        }
        let left = self.control.idle_s - self.last_change.elapsed().as_secs_f64();
        Some(Duration::from_secs_f64(left.max(0.0)))
    }

    /// The friction value the background study orders its work around (the user's newest),
    /// when it may run: not paused, its lanes could be made, the user's solve converged and in
    /// the library.
    fn study_value(&self) -> Option<f64> {
        if self.control.paused
            || self.running.is_some()
            || self.held.is_some()
            || self.background.failed()
        {
            return None;
        }
        let c = self.current.as_ref()?;
        if !c.solution.converged || !self.library.holds_base_of(&c.params) {
            return None;
        }
        c.params.friction
    }

    /// The stored configuration the UI compares with the current one, if its picture is not at
    /// the displayed step.
    fn pinned_unpictured(&self) -> Option<usize> {
        let index = self.library.exact(self.control.pinned?)?;
        let step = self.display_step.get();
        (self.library.entries()[index].pictured_step != step).then_some(index)
    }

    /// One unit of the background study: the picture at the displayed step of the configuration
    /// the UI compares with (at once, paused or not), or, once the user has been idle long
    /// enough, starts solving the next grid value, or pictures a stored configuration at the
    /// displayed step. Returns whether it did something.
    fn study_tick(&mut self) -> bool {
        if let Some(index) = self.pinned_unpictured() {
            self.send_picture(index, self.display_step.get());
            return true;
        }
        let Some(current) = self.study_value() else {
            return false;
        };
        if self.last_change.elapsed().as_secs_f64() < self.control.idle_s {
            return false;
        }
        if self.fill_lanes() {
            return true;
        }
        let step = self.display_step.get();
        let Some(index) = self.library.next_picture(current, step) else {
            return false;
        };
        self.send_picture(index, step);
        true
    }

    /// Pictures stored configuration `index` at `step` and sends the picture.
    fn send_picture(&mut self, index: usize, step: usize) {
        self.library.pictured(index, step);
        if let Some(sol) = self.library.solution(index) {
            let e = self.library.entries()[index].clone();
            let f = fields::compute(&self.solver, &sol, step, 0, false);
            let c = post::contact(&self.solver, &sol);
            self.send_stored(StoredConfig {
                value: e.value,
                iterations: e.iterations,
                background: true,
                start: None,
                quantities: e.quantities,
                picture: Picture::of(&f, &c),
                stored: 0,
                store_bytes: 0,
            });
        }
    }

    /// Begins background solves of the grid values nearest the user's, not stored and not in
    /// progress, until [`StudyControl::lanes`] are in progress; each starts from the stored
    /// configurations beside its value (else the user's newest state). Returns whether one began.
    fn fill_lanes(&mut self) -> bool {
        let Some(current) = self.study_value() else {
            return false;
        };
        let mut began = false;
        while self.background.len() < self.control.lanes.max(1) {
            // a lane that cannot be made stops the filling; no value is given up for it
            if self
                .background
                .make_ready(&self.solver, &self.applied)
                .is_err()
            {
                break;
            }
            let (Some(c), Some(value)) = (
                self.current.as_ref(),
                self.library.next_value(current, &self.background.values()),
            ) else {
                break;
            };
            let params = Params {
                friction: Some(value),
                ..c.params.clone()
            };
            let stored = self.library.start_beside(value, Some(current));
            let (state, start) = match &stored {
                Some((s, v, _)) => (s, Some(*v)),
                None => (&c.solution.state, Some(current)),
            };
            let begun = self.background.begin(params, Some(state), start);
            match begun {
                Ok(()) => began = true,
                // a value that cannot be set or begun is given up, not reported
                Err(_) => self.library.give_up(value),
            }
        }
        if began {
            self.send(Event::Background(self.background.values()));
        }
        began
    }

    /// A background solve ended: a converged configuration is stored and its picture sent; a
    /// failed or unconverged one is given up.
    fn conclude_background(&mut self, ended: BackgroundSolve) {
        let BackgroundSolve {
            solver,
            params,
            run,
            start,
        } = ended;
        let value = params.friction.unwrap_or(f64::NAN);
        if run.failure().is_some() {
            self.library.give_up(value);
        } else {
            let sol = solver.finish(run);
            if sol.converged && !sol.cancelled {
                let step = self.display_step.get();
                let f = fields::compute(&solver, &sol, step, 0, false);
                let kept = Kept::of(&solver, &sol, &f);
                self.store(value, &sol, kept, true, start);
            } else if !sol.cancelled {
                self.library.give_up(value);
            }
        }
        self.background.keep(solver, params);
        self.send(Event::Background(self.background.values()));
    }

    fn cancel_background(&mut self) {
        if self.background.cancel() {
            self.send(Event::Background(Vec::new()));
        }
    }

    fn begin(&mut self, generation: u64, params: Params) {
        if self.adopt_stored(generation, &params) {
            return;
        }
        self.start_run(generation, params, None);
    }

    /// The library takes `params`' base (emptied if it had another); if it stores their
    /// friction value, that configuration is shown. Returns whether it was.
    fn adopt_stored(&mut self, generation: u64, params: &Params) -> bool {
        if self.library.adopt(params) {
            self.send(Event::StudyReset {
                grid: study::grid(),
            });
        }
        if let Some(index) = params.friction.and_then(|v| self.library.exact(v)) {
            self.show_stored(generation, params.clone(), index);
            return true;
        }
        false
    }

    /// Shows row `row` of the opened result folder: stored in the library already, its stored
    /// solution as it is, or a warm solve from its stored state; a state that cannot be read is
    /// an error naming its file, and nothing else changes.
    fn begin_row(&mut self, generation: u64, params: Params, row: usize) {
        let Some(source) = &self.rows else {
            self.begin(generation, params);
            return;
        };
        let (Some(assigned), loader) = (source.rows.get(row).cloned(), source.loader.clone())
        else {
            self.send(Event::Error(format!("the folder has no row {row}")));
            return;
        };
        if self.adopt_stored(generation, &params) {
            return;
        }
        let stored = match loader(row, self.solver.problem()) {
            Ok(s) => s,
            Err(e) => {
                self.send(Event::Error(e));
                return;
            }
        };
        if let Err(e) = self.apply(&params) {
            self.send(Event::Error(format!("{e}")));
            return;
        }
        // every zone's value of the row (the friction slider holds one of them)
        for a in assigned.iter().filter(|a| a.zone.is_some()) {
            if let Err(e) = self.solver.set_parameter_in(a.parameter, a.zone, a.value) {
                self.send(Event::Error(format!("{e}")));
                return;
            }
        }
        match stored {
            StoredResult::Solution(solution) => {
                let converged = solution.converged;
                let shown = self.show_solution(generation, params, *solution, Instant::now());
                if converged {
                    self.store_current(shown, None);
                }
            }
            StoredResult::State(state) => {
                self.start_run(generation, params, Some(state));
            }
        }
    }

    /// Sets `params` on the user's solver.
    fn apply(&mut self, params: &Params) -> lopin_core::Result<()> {
        params.apply(&self.applied, &mut self.solver)?;
        self.applied = params.clone();
        Ok(())
    }

    /// Starts a solve for `params`, warm from the interpolation of the two stored configurations
    /// around its friction value, else from the nearest stored one, or from the user's newest
    /// state where that is strictly nearer (on a tie with a single stored one, the newest).
    /// With `from`, the solve starts from that state (a stored configuration of its own
    /// parameters).
    fn start_run(&mut self, generation: u64, params: Params, from: Option<InterfaceState>) {
        if let Err(e) = self.apply(&params) {
            self.send(Event::Error(format!("{e}")));
            return;
        }
        let newest = self.current.as_ref();
        let held = newest.and_then(|c| c.params.friction);
        let stored: Option<StoredStart> = if from.is_some() {
            None
        } else {
            params
                .friction
                .and_then(|v| self.library.start_beside(v, held))
        };
        let (state, start, between) = match (&from, &stored) {
            (Some(s), _) => (Some(s), params.friction, None),
            (None, Some((s, v, b))) => (Some(s), Some(*v), *b),
            (None, None) => (
                newest.map(|c| &c.solution.state),
                newest.and_then(|c| c.params.friction),
                None,
            ),
        };
        match self.solver.begin(state) {
            Ok(run) => {
                self.running = Some(Running {
                    generation,
                    params,
                    run,
                    start,
                    between,
                    started: Instant::now(),
                    last_live: Instant::now(),
                    iterations: Vec::new(),
                });
            }
            Err(e) => self.send(Event::Error(format!("{e}"))),
        }
    }

    /// Shows stored configuration `index` as the converged solution of `generation`, without
    /// solving.
    fn show_stored(&mut self, generation: u64, params: Params, index: usize) {
        let started = Instant::now();
        let Some(solution) = self.library.solution(index) else {
            self.start_run(generation, params, None);
            return;
        };
        self.show_solution(generation, params, solution, started);
    }

    /// Shows a converged `solution` of `params` as the newest solution of `generation`,
    /// without solving; gives back the fields sent.
    fn show_solution(
        &mut self,
        generation: u64,
        params: Params,
        solution: Solution,
        started: Instant,
    ) -> Option<Arc<StepFields>> {
        let report = SolveReport {
            generation,
            params: params.clone(),
            iterations: 0,
            eta: solution.eta,
            converged: solution.converged,
            cancelled: false,
            warm: true,
            start: params.friction,
            between: None,
            from_store: true,
            solve_s: started.elapsed().as_secs_f64(),
            stages: self.solver.counters().stage_times(),
        };
        let c = post::contact(&self.solver, &solution);
        self.current = Some(Current {
            generation,
            solution,
            params,
        });
        self.iterations = Vec::new();
        self.warm = true;
        let shown = self.serve_fields(self.display_step.get());
        self.send(Event::Contact {
            generation,
            histories: Arc::new(c),
        });
        self.send(Event::Finished(Box::new(report)));
        self.record();
        shown
    }

    /// One iteration of the user's solve: sends its η and, every live period, the live fields
    /// at the shown step. Returns whether the solve has ended.
    fn iterate(&mut self, r: &mut Running) -> bool {
        let (events, display) = (&self.events, &self.display_step);
        let generation = r.generation;
        let (iterations, last_live) = (&mut r.iterations, &mut r.last_live);
        let period = self.live_period_s;
        let done = self.solver.step(&mut r.run, &mut |it| {
            iterations.push(*it.record);
            let _ = events.send(Event::Progress {
                generation,
                eta: it.record.eta,
            });
            if last_live.elapsed().as_secs_f64() >= period {
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

    /// The user's solve ended (converged, failed or cancelled): it keeps its state, reports,
    /// sends the converged fields and records them; a converged one is stored in the library
    /// and its picture sent.
    fn conclude(&mut self, r: Running) {
        let generation = r.generation;
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
            generation,
            params: r.params.clone(),
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            cancelled: sol.cancelled,
            warm,
            start: r.start,
            between: r.between,
            from_store: false,
            solve_s,
            stages: self.solver.counters().stage_times(),
        };
        let (cancelled, converged) = (sol.cancelled, sol.converged);
        // a cancelled iterate is still the newest state: the next solve starts there
        self.current = Some(Current {
            generation,
            solution: sol,
            params: r.params,
        });
        self.iterations = r.iterations;
        self.warm = warm;
        let mut shown = None;
        if !cancelled {
            shown = self.serve_fields(self.display_step.get());
            if let Some(c) = &self.current {
                let h = post::contact(&self.solver, &c.solution);
                self.send(Event::Contact {
                    generation,
                    histories: Arc::new(h),
                });
            }
        }
        self.send(Event::Finished(Box::new(report)));
        if converged {
            self.record();
            self.store_current(shown, r.start);
        }
    }

    /// Keeps the user's newest solution in the library, with its fields `shown` at the
    /// displayed step (when the scene has a friction value to key it); it started from `start`.
    fn store_current(&mut self, shown: Option<Arc<StepFields>>, start: Option<f64>) {
        if let (Some(c), Some(f)) = (self.current.take(), shown) {
            if let Some(value) = c.params.friction {
                let f = Arc::try_unwrap(f).unwrap_or_else(|f| (*f).clone());
                let kept = Kept::of(&self.solver, &c.solution, &f);
                self.store(value, &c.solution, kept, false, start);
            }
            self.current = Some(c);
        }
    }

    /// Keeps a converged configuration with what was drawn of it, and sends its picture.
    fn store(
        &mut self,
        value: f64,
        sol: &Solution,
        kept: Kept,
        background: bool,
        start: Option<f64>,
    ) {
        self.library
            .insert(value, sol, kept.quantities, kept.picture.step);
        self.send_stored(StoredConfig {
            value,
            iterations: sol.iterations,
            background,
            start,
            quantities: kept.quantities,
            picture: kept.picture,
            stored: 0,
            store_bytes: 0,
        });
    }

    fn send_stored(&self, mut c: StoredConfig) {
        c.stored = self.library.entries().len();
        c.store_bytes = self.library.bytes();
        self.send(Event::Stored(Arc::new(c)));
    }

    /// Hands the newest converged solution to the recorder, if one is on and it has not seen it.
    fn record(&mut self) {
        let Some(c) = &self.current else {
            return;
        };
        if !c.solution.converged || self.recorded == Some(c.generation) {
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
                solution: &c.solution,
                iterations: &self.iterations,
                params: &c.params,
                warm: self.warm,
            };
            rec.record(&solve).map(|()| rec.target())
        };
        let generation = c.generation;
        match outcome {
            Ok(target) => {
                self.recorded = Some(generation);
                self.send(Event::Recorded { generation, target });
            }
            Err(e) => self.send(Event::RecordFailed(e)),
        }
    }

    /// Sends the fields of the user's newest solution at `step`, and gives them back.
    fn serve_fields(&mut self, step: usize) -> Option<Arc<StepFields>> {
        let c = self.current.as_ref()?;
        let step = step.min(self.solver.problem().time.steps);
        let f = Arc::new(fields::compute(
            &self.solver,
            &c.solution,
            step,
            c.generation,
            false,
        ));
        self.send(Event::Fields(f.clone()));
        Some(f)
    }

    fn serve_probe(&mut self, sub: usize, node: usize) {
        let Some(c) = &self.current else {
            return;
        };
        let p = self.solver.problem();
        if sub >= p.subs.len() || node >= p.subs[sub].mesh.nodes.len() {
            self.send(Event::Error(format!(
                "probe: no node {node} in substructure {sub}"
            )));
            return;
        }
        let h = fields::probe(&self.solver, &c.solution, sub, node);
        let history = ProbeHistory::new(c.generation, sub, node, h);
        self.send(Event::Probe(Arc::new(history)));
    }
}
