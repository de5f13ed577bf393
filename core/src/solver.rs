//! The LATIN solver: the one entry point of the engine. [`Solver::new`] factorizes every
//! substructure operator S once (METHOD §4, §11); [`Solver::solve_with`] iterates
//!
//! 1. local stage (E+, METHOD §5) on every interface, in parallel, contact sequential in time;
//! 2. linear stage (E−, METHOD §4) on every substructure, in parallel, over the time window;
//! 3. error indicator η from the unrelaxed linear-stage output and ŝ (METHOD §6);
//! 4. relaxation s ← μ s_new + (1 − μ) s, with μ = 1 at the first iteration (METHOD §6);
//!
//! until η < tol, window after window (METHOD §7; one window = the non-incremental method), from a
//! cold start or from a given interface state (warm start, METHOD §8).

use crate::counters::{Counters, Instant, IterationRecord};
use crate::error::{LopinError, Result};
use crate::factor::CholeskyFactor;
use crate::interface::Law;
use crate::linear_stage::{linear_stage, IndicatorSums, LinearInput, LinearWork, SubState};
use crate::local_stage::{local_stage, ContactRunning, LocalInput};
use crate::par;
use crate::problem::Problem;
use crate::scene::spec::SolverSpec;
use crate::state::{InterfaceState, TraceHistory};
use crate::substructure::Substructure;

/// Solver settings (METHOD §10 defaults: k = mean √(ρE), μ = 0.8, tol = 1e-3).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Settings {
    /// Search direction k (Pa·s/m). Changing it refactorizes.
    pub k: f64,
    /// Relaxation μ ∈ (0, 1].
    pub mu: f64,
    /// Stopping tolerance on η.
    pub tol: f64,
    /// Iteration limit (per time window).
    pub max_iter: usize,
    /// Window length in steps (None: the whole interval, non-incremental).
    pub window: Option<usize>,
    /// Skip the linear stage of a substructure whose interface inputs ŝ did not change (to a
    /// relative 1e-12) since its last solve over the whole interval, reusing that solve's output.
    pub skip_unchanged: bool,
    /// On a cold start, begin each time window from the last converged step held constant
    /// (true, default) rather than from F = W = 0 (false, the plain METHOD §7 variant; found by
    /// the stress suite to cost 2× the iterations in incremental runs).
    pub hold_window_start: bool,
    /// Normalize a window's η by its own energy plus the mean energy per step of the earlier
    /// windows times the window length (true, default), rather than by the whole energy of steps
    /// 1..m1 (false, METHOD §7): with the cumulative norm the criterion loosens as the run goes
    /// on, and the stress suite saw a 10⁴-step impact gain 20 % energy at η < 1e-3.
    pub per_step_window_norm: bool,
}

impl Settings {
    /// Default iteration limit.
    pub const MAX_ITER: usize = 2000;

    /// The defaults for a problem, overridden by the scene's solver section.
    pub fn for_problem(problem: &Problem, spec: &SolverSpec) -> Self {
        Self {
            k: spec.k.unwrap_or_else(|| problem.default_k()),
            mu: spec.mu.unwrap_or(0.8),
            tol: spec.tol.unwrap_or(1e-3),
            max_iter: spec.max_iter.unwrap_or(Self::MAX_ITER),
            window: spec.window,
            skip_unchanged: true,
            hold_window_start: true,
            per_step_window_norm: true,
        }
    }

    /// Checks every setting.
    pub fn validate(&self) -> Result<()> {
        if !(self.k.is_finite() && self.k > 0.0) {
            return Err(LopinError::setting(
                "k",
                format!("must be positive, got {}", self.k),
            ));
        }
        if !(self.mu > 0.0 && self.mu <= 1.0) {
            return Err(LopinError::setting(
                "mu",
                format!("must lie in (0, 1], got {}", self.mu),
            ));
        }
        if !(self.tol.is_finite() && self.tol > 0.0) {
            return Err(LopinError::setting(
                "tol",
                format!("must be positive, got {}", self.tol),
            ));
        }
        if self.max_iter == 0 {
            return Err(LopinError::setting("max_iter", "must be at least 1"));
        }
        if self.window == Some(0) {
            return Err(LopinError::setting("window", "must be at least 1 step"));
        }
        Ok(())
    }
}

/// What an observer tells the solver after each iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Go on.
    Continue,
    /// Stop now (the solution is returned as not converged and cancelled).
    Stop,
}

/// What an observer sees after each iteration: the record, and the current iterate.
#[derive(Debug, Clone, Copy)]
pub struct Iterate<'a> {
    /// η, window and stage times of this iteration.
    pub record: &'a IterationRecord,
    /// The solver (problem, factorizations, settings) for post-processing the iterate.
    pub solver: &'a Solver,
    /// s = (F, W) after this iteration's relaxation.
    pub state: &'a InterfaceState,
    /// ŝ of every interface side after this iteration's local stage.
    pub hats: &'a [Vec<TraceHistory>],
    /// η after each iteration of this solve so far.
    pub eta_history: &'a [f64],
}

impl Iterate<'_> {
    /// A copy of the iterate as a (not converged) [`Solution`], so that the post-processing of
    /// [`crate::post`] can replay fields from it.
    pub fn snapshot(&self) -> Solution {
        Solution {
            state: self.state.clone(),
            hats: self.hats.to_vec(),
            iterations: self.record.iteration,
            eta: self.record.eta,
            eta_history: self.eta_history.to_vec(),
            converged: false,
            cancelled: false,
        }
    }
}

/// The result of a solve.
#[derive(Debug, Clone)]
pub struct Solution {
    /// s = (F, W), relaxed: the state a warm start restarts from (METHOD §8).
    pub state: InterfaceState,
    /// ŝ = (F̂, Ŵ) of every interface side: the reported interface solution (METHOD §6).
    pub hats: Vec<Vec<TraceHistory>>,
    /// Total LATIN iterations.
    pub iterations: usize,
    /// Last η.
    pub eta: f64,
    /// η after each iteration.
    pub eta_history: Vec<f64>,
    /// Whether every window reached η < tol.
    pub converged: bool,
    /// Whether an observer stopped the solve.
    pub cancelled: bool,
}

/// The LATIN solver of a problem: factorizations, scratch buffers, settings and counters.
#[derive(Debug)]
pub struct Solver {
    problem: Problem,
    settings: Settings,
    factors: Vec<CholeskyFactor>,
    works: Vec<LinearWork>,
    cache: Vec<Option<LinearCache>>,
    counters: Counters,
}

/// Inputs and outputs of a substructure's last whole-interval linear stage (a pure function of
/// ŝ once k, Δt and the mesh are fixed), for skipping unchanged work.
#[derive(Debug, Clone)]
struct LinearCache {
    hat: Vec<f64>,
    out: TraceHistory,
    sums: IndicatorSums,
    end: SubState,
}

/// Relative change below which a substructure's inputs count as unchanged.
const UNCHANGED: f64 = 1e-12;

impl Solver {
    /// Assembles and factorizes S = 2/Δt M + Δt/2 K + k Bᵀ A B for every substructure, once.
    pub fn new(problem: Problem, settings: Settings) -> Result<Self> {
        settings.validate()?;
        let start = Instant::now();
        let factors = factorize(&problem, settings.k)?;
        let dt = problem.time.dt;
        let works = problem
            .subs
            .iter()
            .zip(&factors)
            .map(|(s, f)| LinearWork::new(s, f, dt))
            .collect();
        let mut counters = Counters::default();
        counters.setup_s = start.elapsed().as_secs_f64();
        let cache = vec![None; problem.subs.len()];
        Ok(Self {
            problem,
            settings,
            factors,
            works,
            cache,
            counters,
        })
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Changes the settings; refactorizes only if k changed.
    pub fn set_settings(&mut self, settings: Settings) -> Result<()> {
        settings.validate()?;
        if settings.k != self.settings.k {
            let start = Instant::now();
            self.factors = factorize(&self.problem, settings.k)?;
            let dt = self.problem.time.dt;
            self.works = self
                .problem
                .subs
                .iter()
                .zip(&self.factors)
                .map(|(s, f)| LinearWork::new(s, f, dt))
                .collect();
            self.counters.setup_s += start.elapsed().as_secs_f64();
            self.cache.iter_mut().for_each(|c| *c = None);
        }
        self.settings = settings;
        Ok(())
    }

    /// Sets the friction coefficient of every contact interface (nothing is refactorized).
    pub fn set_friction(&mut self, f: f64) -> Result<()> {
        if !(f.is_finite() && f >= 0.0) {
            return Err(LopinError::setting(
                "friction",
                format!("must be non-negative, got {f}"),
            ));
        }
        self.problem.set_friction(f);
        Ok(())
    }

    /// Sets the initial gap of every contact node (nothing is refactorized).
    pub fn set_gap(&mut self, g0: f64) -> Result<()> {
        if !(g0.is_finite() && g0 >= 0.0) {
            return Err(LopinError::setting(
                "gap",
                format!("must be non-negative, got {g0}"),
            ));
        }
        self.problem.set_gap(g0);
        Ok(())
    }

    /// Sets the amplitude of every non-zero prescribed velocity (nothing is refactorized).
    pub fn set_velocity_amplitude(&mut self, v: f64) -> Result<()> {
        if !v.is_finite() {
            return Err(LopinError::setting(
                "v0",
                format!("must be finite, got {v}"),
            ));
        }
        self.problem.set_velocity_amplitude(v);
        Ok(())
    }

    /// Adds time spent outside `new` on setup (e.g. assembling the scene).
    pub fn add_setup_time(&mut self, seconds: f64) {
        self.counters.setup_s += seconds;
    }

    /// The per-stage counters.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// The factorizations of S (one per substructure).
    pub fn factors(&self) -> &[CholeskyFactor] {
        &self.factors
    }

    /// Solves without an observer. `start`: None for a cold start, or a previous state.
    pub fn solve(&mut self, start: Option<&InterfaceState>) -> Result<Solution> {
        self.solve_with(start, &mut |_| Control::Continue)
    }

    /// Solves, calling `observer` after every iteration (progress bars, live plots, cancel).
    pub fn solve_with(
        &mut self,
        start: Option<&InterfaceState>,
        observer: &mut dyn FnMut(&IterationRecord) -> Control,
    ) -> Result<Solution> {
        self.solve_observed(start, &mut |it| observer(it.record))
    }

    /// Solves, showing `observer` the current iterate after every iteration (a live view
    /// replays fields from it with [`Iterate::snapshot`]).
    pub fn solve_observed(
        &mut self,
        start: Option<&InterfaceState>,
        observer: &mut dyn FnMut(&Iterate<'_>) -> Control,
    ) -> Result<Solution> {
        let p = &self.problem;
        let set = self.settings;
        let n = p.time.steps;
        self.counters.reset_solve();
        let initial = InterfaceState::cold(p);
        let mut s = match start {
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
        let mut s_new = s.clone();
        let mut hats: Vec<Vec<TraceHistory>> = p
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
        let mut sub_states: Vec<SubState> = p
            .subs
            .iter()
            .map(|s| SubState::initial(s, p.time.dt))
            .collect();
        let mut contact_start: Vec<Option<ContactRunning>> = p
            .interfaces
            .iter()
            .map(|i| match &i.law {
                Law::Contact(c) => Some(ContactRunning::initial(i, c, &s)),
                _ => None,
            })
            .collect();
        let window = set.window.unwrap_or(n).clamp(1, n);
        let mut den_prev = 0.0;
        let mut iterations = 0;
        let mut eta = f64::INFINITY;
        let mut eta_history = Vec::new();
        let mut converged = true;
        let mut cancelled = false;
        let mut m0 = 1;
        while m0 <= n {
            let m1 = (m0 + window - 1).min(n);
            let mut it = 0;
            let mut contact_end;
            let mut last;
            let window_converged = loop {
                it += 1;
                iterations += 1;
                // 1. local stage
                let t_local = Instant::now();
                let input = LocalInput {
                    s: &s,
                    k: set.k,
                    time: p.time,
                    steps: (m0, m1),
                };
                let starts = &contact_start;
                let interfaces = &p.interfaces;
                contact_end = par::map_mut(&mut hats, |i, hat| {
                    local_stage(&interfaces[i], &input, hat, starts[i].as_ref())
                });
                let local_s = t_local.elapsed().as_secs_f64();
                // 2. linear stage
                let t_linear = Instant::now();
                let lin = LinearInput {
                    interfaces,
                    hats: &hats,
                    k: set.k,
                    dt: p.time.dt,
                    steps: (m0, m1),
                };
                let whole = set.skip_unchanged && m0 == 1 && m1 == n;
                let mut bundle: Vec<(
                    &mut LinearWork,
                    &mut TraceHistory,
                    &mut Option<LinearCache>,
                )> = self
                    .works
                    .iter_mut()
                    .zip(s_new.subs.iter_mut())
                    .zip(self.cache.iter_mut())
                    .map(|((w, o), c)| (w, o, c))
                    .collect();
                let (subs, factors, states) = (&p.subs, &self.factors, &sub_states);
                let results = par::map_mut(&mut bundle, |i, (work, out, cache)| {
                    let sub = &subs[i];
                    let hat = whole.then(|| gather_hat(sub, &hats));
                    if let (Some(h), Some(c)) = (&hat, cache.as_ref()) {
                        if unchanged(h, &c.hat) {
                            out.f.copy_from_slice(&c.out.f);
                            out.w.copy_from_slice(&c.out.w);
                            work.state.clone_from(&c.end);
                            return (c.sums, true);
                        }
                    }
                    work.state.clone_from(&states[i]);
                    let sums = linear_stage(sub, &factors[i], work, &lin, out, None);
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
                });
                let skipped = results.iter().filter(|r| r.1).count();
                let sums: Vec<IndicatorSums> = results.into_iter().map(|r| r.0).collect();
                // 3. error indicator
                last = IndicatorSums::default();
                sums.into_iter().for_each(|x| last.add(x));
                eta = IndicatorSums {
                    num: last.num,
                    den: last.den
                        + if set.per_step_window_norm && m0 > 1 {
                            den_prev * (m1 + 1 - m0) as f64 / (m0 - 1) as f64
                        } else {
                            den_prev
                        },
                }
                .eta();
                // 4. relaxation (μ = 1 at the first iteration)
                let mu = if it == 1 { 1.0 } else { set.mu };
                relax(&mut s, &s_new, mu, (m0, m1));
                let linear_s = t_linear.elapsed().as_secs_f64();
                eta_history.push(eta);
                let record = IterationRecord {
                    iteration: iterations,
                    window_start: m0,
                    window_end: m1,
                    eta,
                    local_s,
                    linear_s,
                    skipped,
                };
                self.counters.iterations.push(record);
                let iterate = Iterate {
                    record: &record,
                    solver: self,
                    state: &s,
                    hats: &hats,
                    eta_history: &eta_history,
                };
                if observer(&iterate) == Control::Stop {
                    cancelled = true;
                    break false;
                }
                if eta < set.tol {
                    break true;
                }
                if !eta.is_finite() || it >= set.max_iter {
                    break false;
                }
            };
            for (st, w) in sub_states.iter_mut().zip(&self.works) {
                st.clone_from(&w.state);
            }
            for (start, end) in contact_start.iter_mut().zip(contact_end) {
                if end.is_some() {
                    *start = end;
                }
            }
            den_prev += last.den;
            if !window_converged {
                converged = false;
                break;
            }
            m0 = m1 + 1;
            if set.hold_window_start && start.is_none() && m0 <= n {
                // a cold window starts from the last converged step, held constant
                // (instead of F = W = 0): the interface state changes little over a window
                let m1_next = (m0 + window - 1).min(n);
                for h in &mut s.subs {
                    let prev = h.at(m0 - 1);
                    for m in m0..=m1_next {
                        let r = h.at(m);
                        h.f.copy_within(prev.clone(), r.start);
                        h.w.copy_within(prev.clone(), r.start);
                    }
                }
            }
        }
        Ok(Solution {
            state: s,
            hats,
            iterations,
            eta,
            eta_history,
            converged,
            cancelled,
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

fn factorize(problem: &Problem, k: f64) -> Result<Vec<CholeskyFactor>> {
    let dt = problem.time.dt;
    par::map_range(problem.subs.len(), |i| {
        let sub = &problem.subs[i];
        CholeskyFactor::new(sub.ndof(), &sub.operator_triplets(dt, k)).map_err(|reason| {
            LopinError::Factorization {
                sub: sub.name.clone(),
                reason,
            }
        })
    })
    .into_iter()
    .collect()
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
