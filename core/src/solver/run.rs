//! A LATIN solve in progress ([`SolveRun`]): everything the iteration carries from one
//! iteration to the next (s, ŝ, the substructures' kinematic state at the window start, the
//! running contact state, the window and the η sums), so that a caller without threads (the
//! web explorer) can advance a solve one iteration at a time between frames. One call of
//! [`Solver::step`] is one LATIN iteration of METHOD §6 on the current window of METHOD §7:
//!
//! 1. local stage (E+, METHOD §5) on every interface, in parallel, contact sequential in time;
//! 2. linear stage (E−, METHOD §4) on every substructure, in parallel, over the time window;
//!    with [`super::Settings::two_scale`], the two-scale stage of METHOD §9 instead: all
//!    substructures in lock-step, one macro solve per time step ([`super::two_scale`]);
//! 3. error indicator η from the unrelaxed linear-stage output and ŝ (METHOD §6);
//! 4. relaxation s ← μ s_new + (1 − μ) s, with μ = 1 at the first iteration (METHOD §6);
//!
//! then the window test: η < tol moves to the next window (held start, see
//! [`super::Settings::hold_window_start`]), a non-finite η or the iteration limit ends the solve
//! unconverged.

use super::{two_scale, Control, Iterate, LinearCache, Solution, Solver, UNCHANGED};
use crate::counters::{Instant, IterationRecord};
use crate::error::Result;
use crate::factor::CholeskyFactor;
use crate::interface::Law;
use crate::linear_stage::{linear_stage, IndicatorSums, LinearInput, LinearWork, SubState};
use crate::local_stage::{local_stage, ContactRunning, LocalInput};
use crate::operator_classes::Classes;
use crate::par;
use crate::state::{InterfaceState, TraceHistory};
use crate::substructure::Substructure;

/// A solve between two iterations. Made by [`Solver::begin`], advanced by [`Solver::step`],
/// turned into a [`Solution`] by [`Solver::finish`]; only meaningful with the solver (and the
/// problem parameters) it was begun with.
#[derive(Debug, Clone)]
pub struct SolveRun {
    /// Whether it started from a given state (warm).
    warm: bool,
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
    /// Window length, steps.
    window: usize,
    /// First and last step of the current window.
    m0: usize,
    m1: usize,
    /// Iterations in the current window.
    it: usize,
    /// Iterations in all.
    iterations: usize,
    /// η denominator of the finished windows.
    den_prev: f64,
    /// Last η.
    eta: f64,
    eta_history: Vec<f64>,
    /// Whether every finished window converged.
    converged: bool,
    /// Whether an observer stopped it.
    cancelled: bool,
    /// Whether it has ended (converged, failed or stopped).
    done: bool,
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

impl Solver {
    /// Starts a solve: `start` None for a cold start, or a previous state (warm, METHOD §8),
    /// whose m = 0 entries are replaced by the given initial state.
    pub fn begin(&mut self, start: Option<&InterfaceState>) -> Result<SolveRun> {
        let p = &self.problem;
        let n = p.time.steps;
        self.counters.reset_solve();
        let initial = InterfaceState::cold(p);
        let s = match start {
            Some(st) => {
                st.check_fits(p)?;
                let mut s = st.clone();
                // m = 0 is the given initial state, never iterated (METHOD §1)
                for (h, h0) in s.subs.iter_mut().zip(&initial.subs) {
                    let r = h.at(0);
                    h.f[r.clone()].copy_from_slice(&h0.f[r.clone()]);
                    h.w[r.clone()].copy_from_slice(&h0.w[r]);
                }
                s
            }
            None => initial,
        };
        let hats: Vec<Vec<TraceHistory>> = p
            .interfaces
            .iter()
            .map(|i| {
                i.sides
                    .iter()
                    .map(|side| {
                        let mut h = TraceHistory::zeros(i.len, n);
                        let src = &s.subs[side.sub];
                        let r = src.at(0);
                        h.f[..i.len].copy_from_slice(&src.f[r.start + side.offset..][..i.len]);
                        h.w[..i.len].copy_from_slice(&src.w[r.start + side.offset..][..i.len]);
                        h
                    })
                    .collect()
            })
            .collect();
        let sub_states = p
            .subs
            .iter()
            .map(|s| SubState::initial(s, p.time.dt))
            .collect();
        let contact_start = p
            .interfaces
            .iter()
            .map(|i| match &i.law {
                Law::Contact(c) => Some(ContactRunning::initial(i, c, &s)),
                _ => None,
            })
            .collect();
        let window = self.settings.window.unwrap_or(n).clamp(1, n);
        Ok(SolveRun {
            warm: start.is_some(),
            s_new: s.clone(),
            s,
            hats,
            sub_states,
            contact_start,
            window,
            m0: 1,
            m1: window.min(n),
            it: 0,
            iterations: 0,
            den_prev: 0.0,
            eta: f64::INFINITY,
            eta_history: Vec::new(),
            converged: true,
            cancelled: false,
            done: false,
        })
    }

    /// One LATIN iteration of `run`, then `observer` sees the iterate (it may stop the solve),
    /// then the window test. Returns whether the solve has ended.
    pub fn step(
        &mut self,
        run: &mut SolveRun,
        observer: &mut dyn FnMut(&Iterate<'_>) -> Control,
    ) -> bool {
        if run.done {
            return true;
        }
        let p = &self.problem;
        let set = self.settings;
        let n = p.time.steps;
        let (m0, m1) = (run.m0, run.m1);
        run.it += 1;
        run.iterations += 1;
        // 1. local stage
        let t_local = Instant::now();
        let input = LocalInput {
            s: &run.s,
            k: set.k,
            time: p.time,
            steps: (m0, m1),
        };
        let starts = &run.contact_start;
        let interfaces = &p.interfaces;
        let contact_end = par::map_mut(&mut run.hats, |i, hat| {
            local_stage(&interfaces[i], &input, hat, starts[i].as_ref())
        });
        let local_s = t_local.elapsed().as_secs_f64();
        // 2. linear stage
        let t_linear = Instant::now();
        let lin = LinearInput {
            interfaces,
            hats: &run.hats,
            k: set.k,
            dt: p.time.dt,
            steps: (m0, m1),
        };
        let (results, macro_s) = if let (true, Some(mp)) = (set.two_scale, &self.macro_problem) {
            // METHOD §9: all substructures in lock-step with the macro problem
            let ts = two_scale::TwoScale {
                subs: &p.subs,
                classes: &self.classes,
                factors: &self.factors,
                macro_problem: mp,
            };
            let (sums, macro_s) = two_scale::linear_stage_two_scale(
                &ts,
                &mut self.works,
                &run.sub_states,
                &lin,
                &mut run.s_new.subs,
            );
            self.cache.iter_mut().for_each(|c| *c = None);
            (vec![(sums, false)], macro_s)
        } else {
            let whole = set.skip_unchanged && m0 == 1 && m1 == n;
            let ss = SingleScale {
                subs: &p.subs,
                classes: &self.classes,
                factors: &self.factors,
                states: &run.sub_states,
                whole,
            };
            let out = ss.run(&mut self.works, &mut self.cache, &mut run.s_new.subs, &lin);
            (out, 0.0)
        };
        let skipped = results.iter().filter(|r| r.1).count();
        // 3. error indicator
        let mut last = IndicatorSums::default();
        results.into_iter().for_each(|r| last.add(r.0));
        run.eta = IndicatorSums {
            num: last.num,
            den: last.den
                + if set.per_step_window_norm && m0 > 1 {
                    run.den_prev * (m1 + 1 - m0) as f64 / (m0 - 1) as f64
                } else {
                    run.den_prev
                },
        }
        .eta();
        // 4. relaxation (μ = 1 at the first iteration)
        let mu = if run.it == 1 { 1.0 } else { set.mu };
        relax(&mut run.s, &run.s_new, mu, (m0, m1));
        let linear_s = t_linear.elapsed().as_secs_f64();
        run.eta_history.push(run.eta);
        let record = IterationRecord {
            iteration: run.iterations,
            window_start: m0,
            window_end: m1,
            eta: run.eta,
            local_s,
            linear_s,
            macro_s,
            skipped,
        };
        self.counters.iterations.push(record);
        let iterate = Iterate {
            record: &record,
            solver: self,
            state: &run.s,
            hats: &run.hats,
            eta_history: &run.eta_history,
        };
        if observer(&iterate) == Control::Stop {
            run.cancel();
            return true;
        }
        let window_converged = run.eta < set.tol;
        if !window_converged && run.eta.is_finite() && run.it < set.max_iter {
            return false;
        }
        // the window ends: its end state starts the next one
        for (st, w) in run.sub_states.iter_mut().zip(&self.works) {
            st.clone_from(&w.state);
        }
        for (start, end) in run.contact_start.iter_mut().zip(contact_end) {
            if end.is_some() {
                *start = end;
            }
        }
        run.den_prev += last.den;
        if !window_converged {
            run.converged = false;
            run.done = true;
            return true;
        }
        run.m0 = m1 + 1;
        run.m1 = (run.m0 + run.window - 1).min(n);
        run.it = 0;
        if run.m0 > n {
            run.done = true;
            return true;
        }
        if set.hold_window_start && !run.warm {
            // a cold window starts from the last converged step, held constant
            // (instead of F = W = 0): the interface state changes little over a window
            for h in &mut run.s.subs {
                let prev = h.at(run.m0 - 1);
                for m in run.m0..=run.m1 {
                    let r = h.at(m);
                    h.f.copy_within(prev.clone(), r.start);
                    h.w.copy_within(prev.clone(), r.start);
                }
            }
        }
        false
    }

    /// The solution a run reached (converged, or the newest iterate of an unconverged or
    /// cancelled one).
    pub fn finish(&self, run: SolveRun) -> Solution {
        Solution {
            state: run.s,
            hats: run.hats,
            iterations: run.iterations,
            eta: run.eta,
            eta_history: run.eta_history,
            converged: run.converged && run.done && !run.cancelled,
            cancelled: run.cancelled,
        }
    }
}

/// The single-scale linear stage (METHOD §4): every substructure independent, in parallel.
struct SingleScale<'a> {
    subs: &'a [Substructure],
    classes: &'a Classes,
    factors: &'a [CholeskyFactor],
    /// State of every substructure at the window start.
    states: &'a [SubState],
    /// Whether the window is the whole interval (then unchanged substructures are skipped).
    whole: bool,
}

impl SingleScale<'_> {
    /// Marches the window of `lin` for every substructure, skipping those whose whole-interval
    /// inputs did not change. Returns each one's η sums and whether it was skipped.
    fn run(
        &self,
        works: &mut [LinearWork],
        cache: &mut [Option<LinearCache>],
        out: &mut [TraceHistory],
        lin: &LinearInput<'_>,
    ) -> Vec<(IndicatorSums, bool)> {
        let mut bundle: Vec<(&mut LinearWork, &mut TraceHistory, &mut Option<LinearCache>)> = works
            .iter_mut()
            .zip(out.iter_mut())
            .zip(cache.iter_mut())
            .map(|((w, o), c)| (w, o, c))
            .collect();
        par::map_mut(&mut bundle, |i, (work, out, cache)| {
            let sub = &self.subs[i];
            let hat = self.whole.then(|| gather_hat(sub, lin.hats));
            if let (Some(h), Some(c)) = (&hat, cache.as_ref()) {
                if unchanged(h, &c.hat) {
                    out.f.copy_from_slice(&c.out.f);
                    out.w.copy_from_slice(&c.out.w);
                    work.state.clone_from(&c.end);
                    return (c.sums, true);
                }
            }
            work.state.clone_from(&self.states[i]);
            let factor = &self.factors[self.classes.of[i]];
            let sums = linear_stage(sub, factor, work, lin, out, None);
            match (cache.as_mut(), hat) {
                (Some(c), Some(hat)) => {
                    c.hat = hat;
                    c.out.clone_from(out);
                    c.sums = sums;
                    c.end.clone_from(&work.state);
                }
                (None, Some(hat)) => {
                    **cache = Some(LinearCache {
                        hat,
                        out: (*out).clone(),
                        sums,
                        end: work.state.clone(),
                    })
                }
                (_, None) => **cache = None,
            }
            (sums, false)
        })
    }
}

/// ŝ of every side of `sub`, all steps, concatenated (the inputs of its linear stage).
fn gather_hat(sub: &Substructure, hats: &[Vec<TraceHistory>]) -> Vec<f64> {
    let mut v = Vec::new();
    for &(i, side) in &sub.sides {
        v.extend_from_slice(&hats[i][side].f);
        v.extend_from_slice(&hats[i][side].w);
    }
    v
}

/// Whether two input vectors agree to a relative 1e-12 (of the largest entry).
fn unchanged(a: &[f64], b: &[f64]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= UNCHANGED * scale)
}

/// s ← μ s_new + (1 − μ) s on steps m0..=m1.
fn relax(s: &mut InterfaceState, s_new: &InterfaceState, mu: f64, (m0, m1): (usize, usize)) {
    for (h, hn) in s.subs.iter_mut().zip(&s_new.subs) {
        let r = m0 * h.len..(m1 + 1) * h.len;
        for (x, y) in h.f[r.clone()].iter_mut().zip(&hn.f[r.clone()]) {
            *x = mu * y + (1.0 - mu) * *x;
        }
        for (x, y) in h.w[r.clone()].iter_mut().zip(&hn.w[r]) {
            *x = mu * y + (1.0 - mu) * *x;
        }
    }
}
