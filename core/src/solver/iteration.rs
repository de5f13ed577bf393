//! One LATIN iteration (METHOD §6) on the current window (METHOD §7), owned by the solve in
//! progress [`SolveRun`]: everything the iteration carries from one iteration to the next (s, ŝ,
//! the substructures' kinematic state at the window start, the running contact state, the window
//! and the η norm), so that a caller without threads (the web explorer) can advance a solve one
//! iteration at a time between frames. [`Solver::step`] calls the stages, which are the methods
//! of [`SolveRun`], in METHOD order:
//!
//! 1. [`SolveRun::local_stage`]: E+ (METHOD §5) on every interface, in parallel, contact
//!    sequential in time;
//! 2. [`SolveRun::linear_stage`]: E− over the window, single-scale (METHOD §4, every
//!    substructure in parallel, skipping unchanged ones) or two-scale (METHOD §9, all
//!    substructures in lock-step with one macro solve per step), as the solver's
//!    [`super::linear::LinearStage`] is;
//! 3. [`SolveRun::indicator`]: η from the unrelaxed linear-stage output and ŝ (METHOD §6), with
//!    the window normalisation of METHOD §7, and beside it η̄ on step-averaged fields
//!    ([`crate::stages::indicator`]);
//! 4. [`SolveRun::relaxation`]: s ← μ s_new + (1 − μ) s, μ = 1 at a window's first iteration
//!    (METHOD §6), or its Anderson-accelerated form ([`crate::stages::acceleration`]);
//! 5. [`SolveRun::end_of_window`]: η < tol (or η̄ < tol, as [`Settings::stop`] says) moves to
//!    the next window, a cold one starting from a prediction out of the converged steps
//!    ([`Settings::window_start`], [`crate::scene::settings`]), a warm one from the given state
//!    moved by the difference the converged steps showed (METHOD §8); a non-finite η or the
//!    iteration limit ends the solve unconverged.
//!
//! In a distributed run ([`crate::distributed::distribution`]) the same stages run on every rank over what it
//! holds: the local stage on its interfaces, after receiving s of the other ranks' sides and
//! before sending back their ŝ; the linear stage and the relaxation on its substructures; the
//! η sums gathered, so that every rank takes the same decisions. [`Solver::finish`] gathers the
//! solution onto every rank.

use super::end_energy::end_energy;
use super::linear::{BatchInput, LinearOutcome, LinearStage, Operators};
use super::{non_finite, Control, Iterate, Settings, Solution, Solver};
use crate::counters::{Instant, IterationRecord};
use crate::distributed::distribution::Distribution;
use crate::error::Result;
use crate::interfaces::interface::Law;
use crate::par;
use crate::problem::Problem;
use crate::stages::acceleration::Anderson;
use crate::stages::indicator::{smooth_sums, IndicatorSums, StopTest, WindowNorm};
use crate::stages::linear_stage::{LinearInput, SubState};
use crate::stages::local_stage::{local_stage, ContactRunning, LocalInput};
use crate::state::{InterfaceState, TraceHistory};

/// A solve between two iterations. Made by [`Solver::begin`], advanced by [`Solver::step`],
/// turned into a [`Solution`] by [`Solver::finish`]; only meaningful with the solver (and the
/// problem parameters) it was begun with.
///
/// It serializes whole (serde): a checkpoint of a long solve, which [`Solver::step`] continues
/// from to the same result as the uninterrupted solve.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SolveRun {
    /// Whether it started from a given state (warm).
    warm: bool,
    /// A warm solve's given state at the current window's last step, per substructure (F then
    /// W, empty where this rank holds none), as it was before the window iterated.
    #[serde(default)]
    warm_last: Vec<Vec<f64>>,
    /// The converged values less the given ones at the previous window's last step, per
    /// substructure (F then W).
    #[serde(default)]
    warm_shift: Vec<Vec<f64>>,
    /// s = (F, W), relaxed.
    s: InterfaceState,
    /// The linear stage's output before relaxation.
    s_new: InterfaceState,
    /// ŝ of every interface side.
    hats: Vec<Vec<TraceHistory>>,
    /// Kinematic state of every substructure at the start of the current window.
    sub_states: Vec<SubState>,
    /// Running contact state at the start of the current window.
    contact_start: Vec<Option<ContactRunning>>,
    /// Running contact state at the end of the window after the last local stage.
    contact_end: Vec<Option<ContactRunning>>,
    /// Window length, steps.
    window: usize,
    /// First and last step of the current window.
    m0: usize,
    m1: usize,
    /// Iterations in the current window.
    it: usize,
    /// Iterations in all.
    iterations: usize,
    /// η sums of the current window after the last linear stage.
    window_sums: IndicatorSums,
    /// The η denominator carried from the finished windows.
    norm: WindowNorm,
    /// Last η.
    eta: f64,
    eta_history: Vec<f64>,
    /// η̄ sums of the current window after the last linear stage.
    window_smooth: IndicatorSums,
    /// The η̄ denominator carried from the finished windows.
    norm_smooth: WindowNorm,
    /// Last η̄.
    eta_smooth: f64,
    /// The Anderson history of the window and the η weight of each entry of its flat vectors
    /// (set at the window's first iteration; None: plain relaxation).
    anderson: Option<(Anderson, Vec<f64>)>,
    /// Whether every finished window converged.
    converged: bool,
    /// Whether an observer stopped it.
    cancelled: bool,
    /// Whether it has ended (converged, failed or stopped).
    done: bool,
    /// Where a non-finite value appeared, if one did (the solve ended there).
    failure: Option<String>,
}

impl SolveRun {
    /// Whether the solve has ended: [`Solver::step`] does nothing more.
    pub fn is_done(&self) -> bool {
        self.done
    }

    /// Whether it started from a given interface state.
    pub fn is_warm(&self) -> bool {
        self.warm
    }

    /// Iterations so far.
    pub fn iterations(&self) -> usize {
        self.iterations
    }

    /// η of the last iteration (∞ before the first).
    pub fn eta(&self) -> f64 {
        self.eta
    }

    /// η̄ of the last iteration (∞ before the first).
    pub fn eta_smooth(&self) -> f64 {
        self.eta_smooth
    }

    /// Where the first non-finite value appeared and the inputs behind it, if the solve ended on
    /// one ([`Solver::solve`] returns it as [`crate::LopinError::NonFinite`]).
    pub fn failure(&self) -> Option<&str> {
        self.failure.as_deref()
    }

    /// Ends the solve now, as not converged and cancelled (a newer request replaces it; its
    /// state is still the best start for the next one).
    pub fn cancel(&mut self) {
        if !self.done {
            self.cancelled = true;
            self.converged = false;
            self.done = true;
        }
    }
}

/// Adds to every step m ≥ 1 of a trace history `x` (its step 0 the run's initial state) the
/// difference between that initial state and `start0`, the initial state of the history the
/// later steps were copied from (nothing where they agree).
fn shift_by_initial_change(x: &mut [f64], start0: &[f64]) {
    let len = start0.len();
    let shift: Vec<f64> = x[..len].iter().zip(start0).map(|(a, b)| a - b).collect();
    if shift.iter().all(|&d| d == 0.0) {
        return;
    }
    for step in x[len..].chunks_exact_mut(len) {
        for (v, d) in step.iter_mut().zip(&shift) {
            *v += d;
        }
    }
}

impl Solver {
    /// Starts a solve: `start` None for a cold start, or a previous state (warm, METHOD §8),
    /// whose m = 0 entries are replaced by the given initial state (and its later steps shifted
    /// by the change of the initial state, a preload's).
    pub fn begin(&mut self, start: Option<&InterfaceState>) -> Result<SolveRun> {
        let p = &self.problem;
        let n = p.time.steps;
        self.counters.reset_solve();
        self.linear.forget_guesses();
        let dist = &self.distribution;
        // a rank stores only the histories it works on (all of them on one machine)
        let initial = InterfaceState::cold_where(p, &|i| dist.needs_trace(i));
        let s = match start {
            Some(st) => {
                st.check_fits(p)?;
                let mut s = initial;
                for (i, (h, from)) in s.subs.iter_mut().zip(&st.subs).enumerate() {
                    if !h.is_present() {
                        continue;
                    }
                    if !from.is_present() {
                        return Err(crate::error::LopinError::StateMismatch(format!(
                            "the start state lacks substructure `{}`, which rank {} needs",
                            p.subs[i].name,
                            dist.rank()
                        )));
                    }
                    // m = 0 is the given initial state, never iterated (METHOD §1); a start
                    // from another initial state (another preload) is shifted by the change of
                    // that state, the rest of its history taken as the increment on it
                    let r0 = h.at(0).end;
                    h.f[r0..].copy_from_slice(&from.f[r0..]);
                    h.w[r0..].copy_from_slice(&from.w[r0..]);
                    shift_by_initial_change(&mut h.f, &from.f[..r0]);
                    shift_by_initial_change(&mut h.w, &from.w[..r0]);
                }
                s
            }
            None => initial,
        };
        // ŝ starts as the initial state on every step 0 (F̂ = 0 or the preload's, Ŵ = B v₀)
        let hats: Vec<Vec<TraceHistory>> = p
            .interfaces
            .iter()
            .enumerate()
            .map(|(k, i)| {
                i.sides
                    .iter()
                    .map(|side| {
                        if !dist.needs_hat(k) {
                            return TraceHistory::absent(i.len);
                        }
                        let mut h = TraceHistory::zeros(i.len, n);
                        let sub = &p.subs[side.sub];
                        for (j, w) in h.w[..i.len].iter_mut().enumerate() {
                            *w = sub.initial_velocity[sub.trace_component(side.offset + j)];
                        }
                        if let Some(pre) = &sub.prestress {
                            h.f[..i.len]
                                .copy_from_slice(&pre.traction[side.offset..side.offset + i.len]);
                        }
                        h
                    })
                    .collect()
            })
            .collect();
        // the linear stage's output, on this rank's substructures
        let s_new = InterfaceState {
            steps: n,
            subs: s
                .subs
                .iter()
                .enumerate()
                .map(|(i, h)| {
                    if dist.holds_sub(i) {
                        h.clone()
                    } else {
                        TraceHistory::absent(h.len)
                    }
                })
                .collect(),
        };
        let sub_states = p
            .subs
            .iter()
            .enumerate()
            .map(|(i, s)| {
                if self.distribution.holds_sub(i) {
                    SubState::initial(s, &p.step_coefficients())
                } else {
                    SubState::default()
                }
            })
            .collect();
        let contact_start: Vec<Option<ContactRunning>> = p
            .interfaces
            .iter()
            .enumerate()
            .map(|(n, i)| match &i.law {
                Law::Contact(c) if self.distribution.holds_interface(n) => {
                    Some(ContactRunning::initial(i, c, &s))
                }
                _ => None,
            })
            .collect();
        let window = self.settings.window.unwrap_or(n).clamp(1, n);
        let warm_last = if start.is_some() {
            step_values(&s, window)
        } else {
            Vec::new()
        };
        Ok(SolveRun {
            warm: start.is_some(),
            warm_last,
            warm_shift: Vec::new(),
            s_new,
            s,
            hats,
            sub_states,
            contact_end: vec![None; contact_start.len()],
            contact_start,
            window,
            m0: 1,
            m1: window.min(n),
            it: 0,
            iterations: 0,
            window_sums: IndicatorSums::default(),
            norm: WindowNorm::new(self.settings.per_step_window_norm),
            eta: f64::INFINITY,
            eta_history: Vec::new(),
            window_smooth: IndicatorSums::default(),
            norm_smooth: WindowNorm::new(self.settings.per_step_window_norm),
            eta_smooth: f64::INFINITY,
            anderson: (self.settings.anderson > 0)
                .then(|| (Anderson::new(self.settings.anderson), Vec::new())),
            converged: true,
            cancelled: false,
            done: false,
            failure: None,
        })
    }

    /// One LATIN iteration of `run` (its five stages, in METHOD order), with `observer` shown
    /// the iterate before the end-of-window test (it may stop the solve). Returns whether the
    /// solve has ended.
    pub fn step(
        &mut self,
        run: &mut SolveRun,
        observer: &mut dyn FnMut(&Iterate<'_>) -> Control,
    ) -> bool {
        let Some(begun) = self.iteration_local(run) else {
            return true;
        };
        let t_linear = Instant::now();
        let outcome = self.iteration_linear(run);
        self.iteration_end(run, begun, outcome, t_linear, observer)
    }

    /// Stage 2 of one iteration of `run` on this solver's own linear stage.
    pub(super) fn iteration_linear(&mut self, run: &mut SolveRun) -> LinearOutcome {
        let ops = Operators {
            subs: &self.problem.subs,
            classes: &self.classes,
            factors: &self.factors,
            distribution: &self.distribution,
        };
        run.linear_stage(&self.problem, &mut self.linear, ops, &self.settings)
    }

    /// The start of one iteration of `run`: stage 1 (None: the solve has ended).
    pub(super) fn iteration_local(&mut self, run: &mut SolveRun) -> Option<Begun> {
        if run.done {
            return None;
        }
        run.it += 1;
        run.iterations += 1;
        let comm0 = self.distribution.comm_seconds();
        let t_local = Instant::now();
        run.local_stage(&self.problem, self.settings.k, &self.distribution);
        Some(Begun {
            comm0,
            local_s: t_local.elapsed().as_secs_f64(),
        })
    }

    /// The rest of one iteration of `run` after its linear stage (begun at `t_linear`): stages
    /// 3 to 5, the record and the observer. Returns whether the solve has ended.
    pub(super) fn iteration_end(
        &mut self,
        run: &mut SolveRun,
        begun: Begun,
        outcome: LinearOutcome,
        t_linear: Instant,
        observer: &mut dyn FnMut(&Iterate<'_>) -> Control,
    ) -> bool {
        let set = self.settings;
        let Begun { comm0, local_s } = begun;
        run.indicator(outcome.sums, &self.problem, set.k, &self.distribution);
        if !run.eta.is_finite() {
            // the first non-finite value stops the solve where it appeared
            run.failure = Some(non_finite::describe(
                &self.problem,
                set.k,
                run.iterations,
                &run.s_new,
                &run.hats,
                (run.m0, run.m1),
            ));
            run.converged = false;
            run.done = true;
            return true;
        }
        run.relaxation(&self.problem, set.k, set.mu, &self.distribution);
        let linear_s = t_linear.elapsed().as_secs_f64();
        let record = IterationRecord {
            iteration: run.iterations,
            window_start: run.m0,
            window_end: run.m1,
            eta: run.eta,
            eta_smooth: run.eta_smooth,
            local_s,
            linear_s,
            macro_s: outcome.macro_s,
            comm_s: self.distribution.comm_seconds() - comm0,
            skipped: outcome.skipped,
        };
        self.counters.iterations.push(record);
        let iterate = Iterate {
            record: &record,
            solver: self,
            state: &run.s,
            hats: &run.hats,
            eta_history: &run.eta_history,
        };
        let stop = observer(&iterate) == Control::Stop;
        if self.distribution.any(stop) {
            run.cancel();
            return true;
        }
        run.end_of_window(&self.linear, &set, &self.distribution)
    }

    /// Completes a distributed solution on rank 0 (every rank calls it; the others keep their
    /// parts): s of every substructure and ŝ of every interface, as on one machine.
    pub fn gather_to_root(&self, sol: &mut Solution) {
        self.distribution
            .gather_to_root(&mut sol.state, &mut sol.hats);
    }

    /// Checks that a run restored from a checkpoint has the layout of this solver's problem
    /// (steps, traces, interfaces, substructures).
    pub fn check_restored(&self, run: &SolveRun) -> Result<()> {
        let p = &self.problem;
        run.s.check_fits(p)?;
        run.s_new.check_fits(p)?;
        if run.hats.len() != p.interfaces.len()
            || run.sub_states.len() != p.subs.len()
            || run.contact_start.len() != p.interfaces.len()
        {
            return Err(crate::error::LopinError::StateMismatch(format!(
                "{} interfaces and {} substructures in the checkpoint, {} and {} in the problem",
                run.hats.len(),
                run.sub_states.len(),
                p.interfaces.len(),
                p.subs.len()
            )));
        }
        Ok(())
    }

    /// The solution a run reached (converged, or the newest iterate of an unconverged or
    /// cancelled one). In a distributed run it holds what this rank stored (its substructures'
    /// s, its interfaces' ŝ and the sides it exchanged; the rest absent): enough to warm-start
    /// the next solve on the same ranks and to post-process its substructures;
    /// [`Solver::gather_to_root`] completes it on rank 0 for files.
    pub fn finish(&self, run: SolveRun) -> Solution {
        let reached_end = run.m0 > self.problem.time.steps && !run.cancelled;
        let end = (reached_end && matches!(self.linear, LinearStage::SingleScale(_)))
            .then(|| {
                end_energy(
                    &self.problem,
                    &self.distribution,
                    &run.s_new,
                    &run.sub_states,
                )
            })
            .flatten();
        Solution {
            end,
            state: run.s,
            hats: run.hats,
            iterations: run.iterations,
            eta: run.eta,
            eta_smooth: run.eta_smooth.is_finite().then_some(run.eta_smooth),
            eta_history: run.eta_history,
            converged: run.converged && run.done && !run.cancelled,
            cancelled: run.cancelled,
        }
    }
}

/// What the start of an iteration measured ([`Solver::iteration_local`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Begun {
    /// Seconds in communication between ranks before it.
    comm0: f64,
    /// Seconds of its local stage.
    local_s: f64,
}

impl SolveRun {
    /// Stage 1, local stage (E+, METHOD §5): ŝ of every interface side over the window from s,
    /// in parallel over interfaces; contact laws march in time from the window's start state.
    /// Distributed: on this rank's interfaces, between the two exchanges of cut sides.
    pub(crate) fn local_stage(&mut self, problem: &Problem, k: f64, distribution: &Distribution) {
        let steps = (self.m0, self.m1);
        distribution.send_traces(&mut self.s, steps);
        let input = LocalInput {
            s: &self.s,
            k,
            time: problem.time,
            step: problem.step_coefficients(),
            steps: (self.m0, self.m1),
        };
        let starts = &self.contact_start;
        let interfaces = &problem.interfaces;
        self.contact_end = par::map_mut(&mut self.hats, |i, hat| {
            if !distribution.holds_interface(i) {
                return None;
            }
            local_stage(&interfaces[i], &input, hat, starts[i].as_ref())
        });
        distribution.send_hats(&mut self.hats, steps);
    }

    /// Stage 2, linear stage (E−, METHOD §4 or §9 as `linear` is): s_new over the window from ŝ,
    /// every substructure starting from its state at the window start. Skipping unchanged
    /// substructures is allowed when the window is the whole interval.
    pub(crate) fn linear_stage(
        &mut self,
        problem: &Problem,
        linear: &mut LinearStage,
        ops: Operators<'_>,
        settings: &Settings,
    ) -> LinearOutcome {
        let (m0, m1) = (self.m0, self.m1);
        let whole = settings.skip_unchanged && m0 == 1 && m1 == problem.time.steps;
        let lin = LinearInput {
            interfaces: &problem.interfaces,
            hats: &self.hats,
            k: settings.k,
            time: problem.step_coefficients(),
            steps: (m0, m1),
        };
        let outcome = linear.run(ops, &self.sub_states, &lin, whole, &mut self.s_new.subs);
        self.window_sums = outcome.sums;
        outcome
    }

    /// What stage 2 of this run reads when it marches with other runs sharing its operators
    /// ([`super::linear::SingleScale::run_batched`]): its input and its s_new to write.
    pub(crate) fn batch_parts<'a>(
        &'a mut self,
        problem: &'a Problem,
        ops: Operators<'a>,
        settings: &Settings,
    ) -> (BatchInput<'a>, &'a mut [TraceHistory]) {
        let (m0, m1) = (self.m0, self.m1);
        let input = BatchInput {
            ops,
            starts: &self.sub_states,
            lin: LinearInput {
                interfaces: &problem.interfaces,
                hats: &self.hats,
                k: settings.k,
                time: problem.step_coefficients(),
                steps: (m0, m1),
            },
            whole: settings.skip_unchanged && m0 == 1 && m1 == problem.time.steps,
        };
        (input, &mut self.s_new.subs)
    }

    /// The η sums of a linear stage marched with other runs ([`Self::batch_parts`]).
    pub(crate) fn set_window_sums(&mut self, sums: IndicatorSums) {
        self.window_sums = sums;
    }

    /// Stage 3, error indicator (METHOD §6–7): η of the window from its sums and the norm carried
    /// from the finished windows; η̄ likewise from the step averages of s_new and ŝ.
    pub(crate) fn indicator(
        &mut self,
        window: IndicatorSums,
        problem: &Problem,
        k: f64,
        distribution: &Distribution,
    ) {
        self.eta = self.norm.eta(window, (self.m0, self.m1));
        self.eta_history.push(self.eta);
        let steps = (self.m0, self.m1);
        self.window_smooth = smooth_sums(
            &problem.interfaces,
            k,
            &self.s_new,
            &self.hats,
            steps,
            distribution,
        );
        self.eta_smooth = self.norm_smooth.eta(self.window_smooth, steps);
    }

    /// Stage 4, relaxation (METHOD §6): s ← μ s_new + (1 − μ) s on the window's steps, with
    /// μ = 1 at the window's first iteration.
    /// Distributed: on this rank's substructures (Anderson runs on one rank only).
    pub(crate) fn relaxation(
        &mut self,
        problem: &Problem,
        k: f64,
        mu: f64,
        distribution: &Distribution,
    ) {
        let mu = if self.it == 1 { 1.0 } else { mu };
        let steps = (self.m0, self.m1);
        match &mut self.anderson {
            None => relax(&mut self.s, &self.s_new, mu, steps, &|i| {
                distribution.holds_sub(i)
            }),
            Some((acc, weights)) => {
                if self.it == 1 {
                    acc.reset();
                    *weights = window_weights(problem, k, &self.s, steps);
                }
                let (mut x, g) = (flatten(&self.s, steps), flatten(&self.s_new, steps));
                acc.step(&mut x, &g, weights, mu);
                unflatten(&mut self.s, &x, steps);
            }
        }
    }

    /// Stage 5, end of window (METHOD §7): unless η < tol or the window's iteration limit is
    /// reached, the window goes on (a non-finite η has ended the solve before this stage). Otherwise its end states (substructures
    /// from the last linear stage, contacts from the last local stage) start the next window, a
    /// cold next window starts from a prediction out of the converged steps
    /// ([`crate::scene::settings`]), and an unconverged
    /// window ends the solve. Returns whether the solve has ended.
    pub(crate) fn end_of_window(
        &mut self,
        linear: &LinearStage,
        settings: &Settings,
        distribution: &Distribution,
    ) -> bool {
        let tested = match settings.stop {
            StopTest::Eta => self.eta,
            StopTest::Smooth => self.eta_smooth,
        };
        let window_converged = tested < settings.tol;
        if !window_converged && self.it < settings.max_iter {
            return false;
        }
        for (i, st) in self.sub_states.iter_mut().enumerate() {
            st.clone_from(linear.end_state(i));
        }
        for (start, end) in self.contact_start.iter_mut().zip(&mut self.contact_end) {
            if end.is_some() {
                *start = end.take();
            }
        }
        self.norm.close_window(self.window_sums);
        self.norm_smooth.close_window(self.window_smooth);
        if !window_converged {
            self.converged = false;
            self.done = true;
            return true;
        }
        let n = self.s.steps;
        self.m0 = self.m1 + 1;
        self.m1 = (self.m0 + self.window - 1).min(n);
        self.it = 0;
        if self.m0 > n {
            self.done = true;
            return true;
        }
        if self.warm {
            // a warm window starts from the given state moved as the converged steps showed
            self.shift_warm_window(distribution);
        } else {
            // a cold window starts from a prediction out of the converged steps before it
            let start = settings.window_start.resolve(settings.tol);
            for (i, h) in self.s.subs.iter_mut().enumerate() {
                if !distribution.holds_sub(i) {
                    continue;
                }
                let steps = (self.m0, self.m1);
                start.fill(&mut h.f, h.len, steps);
                start.fill(&mut h.w, h.len, steps);
            }
        }
        false
    }
}

impl SolveRun {
    /// A warm window's start (METHOD §8): the given state's values on the window, moved by the
    /// difference d between the converged values and the given ones at the previous window's
    /// last step, times the share α of the difference before that persisted over the previous
    /// window (least squares, in [0, 1], F and W apart; α = 1 on the second window). Where the
    /// change of parameter moved the solution smoothly, the start carries the move on; where
    /// the differences are the tolerance's noise, α ≈ 0 keeps the given state.
    fn shift_warm_window(&mut self, distribution: &Distribution) {
        let (m0, m1) = (self.m0, self.m1);
        let next_last = step_values(&self.s, m1);
        self.warm_shift.resize(self.s.subs.len(), Vec::new());
        for (i, h) in self.s.subs.iter_mut().enumerate() {
            let given = self.warm_last.get(i).map_or(&[][..], |g| &g[..]);
            if !distribution.holds_sub(i) || given.is_empty() {
                continue;
            }
            let len = h.len;
            let prev = h.at(m0 - 1);
            let converged = h.f[prev.clone()].iter().chain(&h.w[prev]);
            let d: Vec<f64> = converged.zip(given).map(|(c, g)| c - g).collect();
            let before = &self.warm_shift[i];
            let share = |r: std::ops::Range<usize>| persisted_share(&d[r.clone()], before.get(r));
            let (af, aw) = (share(0..len), share(len..2 * len));
            for m in m0..=m1 {
                let r = h.at(m);
                for (x, dj) in h.f[r.clone()].iter_mut().zip(&d[..len]) {
                    *x += af * dj;
                }
                for (x, dj) in h.w[r].iter_mut().zip(&d[len..]) {
                    *x += aw * dj;
                }
            }
            self.warm_shift[i] = d;
        }
        self.warm_last = next_last;
    }
}

/// The least-squares share of `before` in `now`, in [0, 1]: 1 without a history, 0 where
/// `before` vanishes.
fn persisted_share(now: &[f64], before: Option<&[f64]>) -> f64 {
    let Some(before) = before else {
        return 1.0;
    };
    let (num, den) = now
        .iter()
        .zip(before)
        .fold((0.0, 0.0), |(n, d), (a, b)| (n + a * b, d + b * b));
    if den > 0.0 {
        (num / den).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Every substructure's F then W at step m (empty where this rank holds none).
fn step_values(s: &InterfaceState, m: usize) -> Vec<Vec<f64>> {
    s.subs
        .iter()
        .map(|h| {
            if h.f.is_empty() {
                return Vec::new();
            }
            let r = h.at(m);
            let mut v = h.f[r.clone()].to_vec();
            v.extend_from_slice(&h.w[r]);
            v
        })
        .collect()
}

/// A state on steps m0..=m1 as one flat vector: every substructure's F then W, step-major.
fn flatten(s: &InterfaceState, (m0, m1): (usize, usize)) -> Vec<f64> {
    let mut x = Vec::new();
    for h in &s.subs {
        let r = m0 * h.len..(m1 + 1) * h.len;
        x.extend_from_slice(&h.f[r.clone()]);
        x.extend_from_slice(&h.w[r]);
    }
    x
}

/// The η weight of each entry of [`flatten`]'s vector: A/k_j on forces, A k_j on velocities
/// (METHOD §6).
fn window_weights(
    problem: &Problem,
    k: f64,
    s: &InterfaceState,
    (m0, m1): (usize, usize),
) -> Vec<f64> {
    let mut w = Vec::new();
    for (h, sub) in s.subs.iter().zip(&problem.subs) {
        let weight = |j: usize, force: bool| {
            let kj = k * sub.trace_k[j];
            sub.trace_area[j] * if force { 1.0 / kj } else { kj }
        };
        for force in [true, false] {
            for _ in m0..=m1 {
                w.extend((0..h.len).map(|j| weight(j, force)));
            }
        }
    }
    w
}

/// Writes the flat vector of [`flatten`] back into s on steps m0..=m1.
fn unflatten(s: &mut InterfaceState, x: &[f64], (m0, m1): (usize, usize)) {
    let mut at = 0;
    for h in &mut s.subs {
        let r = m0 * h.len..(m1 + 1) * h.len;
        let n = r.len();
        h.f[r.clone()].copy_from_slice(&x[at..at + n]);
        h.w[r].copy_from_slice(&x[at + n..at + 2 * n]);
        at += 2 * n;
    }
}

/// s ← μ s_new + (1 − μ) s on steps m0..=m1, for the substructures `held` says.
fn relax(
    s: &mut InterfaceState,
    s_new: &InterfaceState,
    mu: f64,
    (m0, m1): (usize, usize),
    held: &dyn Fn(usize) -> bool,
) {
    for (i, (h, hn)) in s.subs.iter_mut().zip(&s_new.subs).enumerate() {
        if !held(i) {
            continue;
        }
        let r = m0 * h.len..(m1 + 1) * h.len;
        for (x, y) in h.f[r.clone()].iter_mut().zip(&hn.f[r.clone()]) {
            *x = mu * y + (1.0 - mu) * *x;
        }
        for (x, y) in h.w[r.clone()].iter_mut().zip(&hn.w[r]) {
            *x = mu * y + (1.0 - mu) * *x;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_persisted_share_is_the_least_squares_fit_in_zero_one() {
        assert_eq!(persisted_share(&[1.0, 2.0], None), 1.0);
        assert!((persisted_share(&[1.0, 2.0], Some(&[2.0, 4.0])) - 0.5).abs() < 1e-15);
        assert_eq!(persisted_share(&[4.0, 8.0], Some(&[1.0, 2.0])), 1.0);
        assert_eq!(persisted_share(&[1.0, -1.0], Some(&[1.0, 1.0])), 0.0);
        assert_eq!(persisted_share(&[-1.0, -2.0], Some(&[1.0, 2.0])), 0.0);
        assert_eq!(persisted_share(&[1.0, 2.0], Some(&[0.0, 0.0])), 0.0);
    }

    #[test]
    fn relaxation_mixes_the_window_and_leaves_other_steps() {
        // one trace of 2 entries over steps 0..=4; window [2, 3]
        let state = |f: f64, w: f64| InterfaceState {
            steps: 4,
            subs: vec![TraceHistory {
                len: 2,
                f: vec![f; 10],
                w: vec![w; 10],
            }],
        };
        let mut s = state(1.0, -2.0);
        let s_new = state(3.0, 4.0);
        relax(&mut s, &s_new, 0.8, (2, 3), &|_| true);
        let h = &s.subs[0];
        for m in 0..=4 {
            let r = h.at(m);
            let (f, w) = if (2..=3).contains(&m) {
                (0.8 * 3.0 + 0.2 * 1.0, 0.8 * 4.0 + 0.2 * -2.0)
            } else {
                (1.0, -2.0)
            };
            assert!(
                h.f[r.clone()].iter().all(|&x| (x - f).abs() < 1e-15),
                "F at m = {m}"
            );
            assert!(
                h.w[r].iter().all(|&x| (x - w).abs() < 1e-15),
                "W at m = {m}"
            );
        }
        // μ = 1 takes the new fields
        relax(&mut s, &s_new, 1.0, (1, 4), &|_| true);
        assert_eq!(s.subs[0].f[2..], s_new.subs[0].f[2..]);
        assert_eq!(s.subs[0].w[2..], s_new.subs[0].w[2..]);
    }
}
