//! The LATIN solver: the one entry point of the engine. [`Solver::new`] factorizes the
//! substructure operator S once per class of identical substructures (METHOD §4, §11) and, for
//! the two-scale linear stage, builds the macro problem once (METHOD §9); [`Solver::solve_with`] iterates (one iteration
//! is [`Solver::step`], see [`run`]) until η < tol, window after window (METHOD §7; one window =
//! the non-incremental method), from a cold start or from a given interface state (warm start,
//! METHOD §8). [`Solver::begin`] / [`Solver::step`] / [`Solver::finish`] let a caller without
//! threads advance a solve a few iterations at a time.

mod run;
mod two_scale;
pub use run::SolveRun;

use crate::counters::{Counters, Instant, IterationRecord};
use crate::error::{LopinError, Result};
use crate::factor::CholeskyFactor;
use crate::linear_stage::{IndicatorSums, LinearWork, SubState};
use crate::macro_problem::MacroProblem;
use crate::operator_classes::{factor_classes, Classes};
use crate::par;
use crate::problem::Problem;
use crate::scene::spec::SolverSpec;
use crate::state::{InterfaceState, TraceHistory};

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
    /// Two-scale linear stage: the macro problem of METHOD §9 couples all substructures at every
    /// time step (false: the single-scale linear stage of METHOD §4).
    #[serde(default, rename = "macro")]
    pub two_scale: bool,
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
            two_scale: spec.two_scale.unwrap_or(false),
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
    /// Substructures sharing one factorization of S.
    classes: Classes,
    /// One factorization per class.
    factors: Vec<CholeskyFactor>,
    /// The macro problem (two-scale linear stage), built when first needed.
    macro_problem: Option<MacroProblem>,
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
    /// Assembles and factorizes S = 2/Δt M + Δt/2 K + k Bᵀ A B once per class of identical
    /// substructures ([`crate::operator_classes`]), and the macro problem if the settings ask
    /// for the two-scale linear stage.
    pub fn new(problem: Problem, settings: Settings) -> Result<Self> {
        settings.validate()?;
        let start = Instant::now();
        let classes = factor_classes(&problem.subs);
        let factors = factorize(&problem, &classes, settings.k)?;
        let works = make_works(&problem, &classes, &factors);
        let cache = vec![None; problem.subs.len()];
        let mut solver = Self {
            problem,
            settings,
            classes,
            factors,
            macro_problem: None,
            works,
            cache,
            counters: Counters::default(),
        };
        if settings.two_scale {
            solver.build_macro()?;
        }
        solver.counters.setup_s = start.elapsed().as_secs_f64();
        Ok(solver)
    }

    /// Builds the macro problem for the current k (METHOD §9: homogenized operators once per
    /// class, the global operator factorized once).
    fn build_macro(&mut self) -> Result<()> {
        let mp = MacroProblem::new(&self.problem, self.settings.k, &self.classes, &self.factors)?;
        self.macro_problem = Some(mp);
        Ok(())
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Changes the settings; refactorizes only if k changed, and builds the macro problem when
    /// the two-scale stage is asked for and k changed or it was not built yet.
    pub fn set_settings(&mut self, settings: Settings) -> Result<()> {
        settings.validate()?;
        let start = Instant::now();
        if settings.k != self.settings.k {
            self.factors = factorize(&self.problem, &self.classes, settings.k)?;
            self.works = make_works(&self.problem, &self.classes, &self.factors);
            self.cache.iter_mut().for_each(|c| *c = None);
            self.macro_problem = None;
        }
        self.settings = settings;
        if settings.two_scale && self.macro_problem.is_none() {
            self.build_macro()?;
        }
        self.counters.setup_s += start.elapsed().as_secs_f64();
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

    /// The distinct factorizations of S (one per class of identical substructures).
    pub fn factors(&self) -> &[CholeskyFactor] {
        &self.factors
    }

    /// The factorization of substructure `i`'s operator S.
    pub fn factor(&self, i: usize) -> &CholeskyFactor {
        &self.factors[self.classes.of[i]]
    }

    /// Which substructures share a factorization.
    pub fn classes(&self) -> &Classes {
        &self.classes
    }

    /// The macro problem, if the two-scale stage has been used with the current k.
    pub fn macro_problem(&self) -> Option<&MacroProblem> {
        self.macro_problem.as_ref()
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
        let mut run = self.begin(start)?;
        while !self.step(&mut run, observer) {}
        Ok(self.finish(run))
    }
}

/// Factorizes S of every class representative.
fn factorize(problem: &Problem, classes: &Classes, k: f64) -> Result<Vec<CholeskyFactor>> {
    let dt = problem.time.dt;
    par::map_range(classes.count(), |c| {
        let sub = &problem.subs[classes.representatives[c]];
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

/// Scratch buffers of every substructure's linear stage.
fn make_works(problem: &Problem, classes: &Classes, factors: &[CholeskyFactor]) -> Vec<LinearWork> {
    problem
        .subs
        .iter()
        .enumerate()
        .map(|(i, s)| LinearWork::new(s, &factors[classes.of[i]], problem.time.dt))
        .collect()
}
