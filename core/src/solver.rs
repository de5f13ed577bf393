//! The LATIN solver: the one entry point of the engine. [`Solver::new`] factorizes the
//! substructure operator S once per class of identical substructures (METHOD §4, §11) and, for
//! the two-scale linear stage, builds the macro problem once (METHOD §9). A solve runs iteration
//! after iteration until η < tol, window after window (METHOD §7; one window = the
//! non-incremental method), from a cold start or from a given interface state (warm start,
//! METHOD §8). One iteration is [`Solver::step`], whose stages, in METHOD order, are the methods
//! of the solve in progress [`SolveRun`] ([`iteration`]):
//!
//! 1. [`SolveRun::local_stage`]: E+ on every interface (METHOD §5);
//! 2. [`SolveRun::linear_stage`]: E− on every substructure, single- or two-scale (METHOD §4, §9;
//!    [`linear`], [`two_scale`], [`skip_cache`]);
//! 3. [`SolveRun::indicator`]: η of the window (METHOD §6–7; [`crate::stages::indicator`]);
//! 4. [`SolveRun::relaxation`]: s ← μ s_new + (1 − μ) s (METHOD §6);
//! 5. [`SolveRun::end_of_window`]: the window test, and the next window's start (METHOD §7).
//!
//! [`Solver::begin`] / [`Solver::step`] / [`Solver::finish`] let a caller without threads advance
//! a solve a few iterations at a time.
//!
//! [`Solver::new_distributed`] runs the same iteration on several ranks ([`crate::distributed::ranks`]):
//! each factorizes and marches only the substructures [`crate::distributed::distribution`] deals it, and
//! reaches the same iterates, η and decisions as the run on one machine.

pub mod batch;
pub(crate) mod blocks;
pub mod end_energy;
pub mod iteration;
mod linear;
mod non_finite;
mod skip_cache;
mod solution;
mod two_scale;

pub use crate::settings::Settings;
pub use iteration::SolveRun;
pub use solution::{Control, Iterate, Solution};

use std::sync::Arc;

use crate::counters::{Counters, Instant, IterationRecord};
use crate::distributed::distribution::Distribution;
use crate::distributed::ranks::Ranks;
use crate::error::{LopinError, Result};
use crate::interfaces::search_direction;
use crate::linalg::factor::CholeskyFactor;
use crate::macro_scale::macro_problem::MacroProblem;
use crate::macro_scale::operator_classes::{factor_classes, Classes};
use crate::par;
use crate::parameter::Parameter;
use crate::problem::Problem;
use crate::scene::settings::FactorPrecision;
use crate::stages::linear_stage::LinearWork;
use crate::state::InterfaceState;
use linear::{LinearStage, SingleScale};
use two_scale::TwoScale;

/// The LATIN solver of a problem: factorizations, the linear stage with its buffers, settings
/// and counters.
#[derive(Debug)]
pub struct Solver {
    problem: Problem,
    settings: Settings,
    /// Substructures sharing one factorization of S.
    classes: Classes,
    /// One factorization per class (None: a class with no substructure on this rank), shared
    /// with the lanes made from this solver ([`Self::lane`]) until one of them refactorizes.
    factors: Arc<Vec<Option<CholeskyFactor>>>,
    /// Which rank holds which substructure and interface (everything on one rank by default).
    distribution: Distribution,
    /// The linear stage the settings ask for, with its buffers.
    linear: LinearStage,
    /// A macro problem built for the current k, kept while the single-scale stage runs so that
    /// switching back to two scales does not rebuild it.
    spare_macro: Option<MacroProblem>,
    counters: Counters,
    /// The preload's static phase, when the problem has one.
    preload: Option<crate::preload::PreloadReport>,
}

impl Solver {
    /// Assembles and factorizes S = c_M M + c_K K + k Bᵀ A B (2/Δt M + Δt/2 K + k Bᵀ A B for the
    /// trapezoidal rule, [`crate::time::time_scheme`]) once per class of identical
    /// substructures ([`crate::macro_scale::operator_classes`]), and the macro problem if the settings ask
    /// for the two-scale linear stage.
    pub fn new(problem: Problem, settings: Settings) -> Result<Self> {
        Self::on_ranks(problem, settings, None)
    }

    /// The solver of one rank of a distributed run: the substructures are dealt to the ranks
    /// ([`crate::distributed::distribution::deal`]), and this rank factorizes and marches only its own. Every
    /// rank must make it, with the same problem and settings. Anderson acceleration, which
    /// mixes all substructures' histories, is refused on more than one rank.
    pub fn new_distributed(
        problem: Problem,
        settings: Settings,
        ranks: Arc<dyn Ranks>,
    ) -> Result<Self> {
        Self::on_ranks(problem, settings, Some(ranks))
    }

    fn on_ranks(
        mut problem: Problem,
        settings: Settings,
        ranks: Option<Arc<dyn Ranks>>,
    ) -> Result<Self> {
        settings.validate_for(&problem)?;
        let start = Instant::now();
        // the scheme of the settings: S and the macro problem are built for it
        problem.set_scheme(settings.scheme());
        search_direction::apply(&mut problem, settings.directions);
        let preload = if problem.needs_preload() && !problem.is_prestressed() {
            Some(crate::preload::prestress(&mut problem, &settings)?)
        } else {
            None
        };
        let classes = factor_classes(&problem.subs);
        let distribution = match ranks {
            None => Distribution::single(&problem),
            Some(r) => Distribution::new(&problem, &classes.of, r)
                .map_err(|reason| LopinError::setting("ranks", reason))?,
        };
        check_distributable(&settings, &distribution)?;
        let factors = Arc::new(factorize(
            &problem,
            &classes,
            (settings.k, settings.factors),
            &distribution,
        )?);
        let linear = new_linear_stage(
            &problem,
            &classes,
            &factors,
            &distribution,
            settings.two_scale.then_some(settings.k),
        )?;
        let mut counters = Counters::default();
        counters.setup_s = start.elapsed().as_secs_f64();
        Ok(Self {
            problem,
            settings,
            classes,
            factors,
            distribution,
            linear,
            spare_macro: None,
            counters,
            preload,
        })
    }

    /// What the preload's static phase took, when the problem has one ([`crate::preload`]).
    pub fn preload(&self) -> Option<&crate::preload::PreloadReport> {
        self.preload.as_ref()
    }

    /// After a parameter moved: the preload's static phase again, where the problem has one and
    /// the parameter acts on it (friction, gap, preload); on an error the problem is `before`.
    fn preload_again(&mut self, parameter: Parameter, before: Problem) -> Result<()> {
        if !(parameter.moves_statics() && (self.problem.needs_preload() || before.needs_preload()))
        {
            return Ok(());
        }
        self.problem.set_prestress(None);
        if !self.problem.needs_preload() {
            self.preload = None;
            return Ok(());
        }
        match crate::preload::prestress(&mut self.problem, &self.settings) {
            Ok(r) => {
                self.preload = Some(r);
                Ok(())
            }
            Err(e) => {
                self.problem = before;
                Err(e)
            }
        }
    }

    /// Which rank holds which substructure.
    pub fn distribution(&self) -> &Distribution {
        &self.distribution
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// Changes the settings; refactorizes once if k, ρ∞, the direction shape or the factors'
    /// precision changed, and
    /// switches the linear stage when the two-scale switch changed (building the macro problem
    /// if none is held for these operators).
    /// On an error the solver keeps its previous settings.
    pub fn set_settings(&mut self, settings: Settings) -> Result<()> {
        settings.validate_for(&self.problem)?;
        check_distributable(&settings, &self.distribution)?;
        let start = Instant::now();
        let (scheme, directions) = (self.problem.scheme, self.settings.directions);
        self.problem.set_scheme(settings.scheme());
        if settings.directions != directions {
            // the classes of identical operators may split or merge with the direction
            search_direction::apply(&mut self.problem, settings.directions);
            let classes = std::mem::replace(&mut self.classes, factor_classes(&self.problem.subs));
            if let Err(e) = self.refactorize(settings.k, settings.factors) {
                search_direction::apply(&mut self.problem, directions);
                self.classes = classes;
                self.problem.set_scheme(scheme);
                return Err(e);
            }
        } else if settings.k != self.settings.k
            || self.problem.scheme != scheme
            || settings.factors != self.settings.factors
        {
            if let Err(e) = self.refactorize(settings.k, settings.factors) {
                self.problem.set_scheme(scheme);
                return Err(e);
            }
        }
        // the operators are those of the new k, direction and scheme from here on
        self.settings.k = settings.k;
        self.settings.directions = settings.directions;
        self.settings.rho_inf = settings.rho_inf;
        self.settings.factors = settings.factors;
        self.set_scale(settings.two_scale, settings.k)?;
        self.settings = settings;
        self.counters.setup_s += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// Changes the time scheme of the problem (METHOD §2, [`crate::time::time_scheme`]): the
    /// settings' ρ∞ ([`Self::set_settings`]). S changes, so every class is refactorized and the
    /// macro problem rebuilt if the two-scale stage runs. A warm start from a state of another
    /// scheme is legitimate (it is only a start). On an error the solver keeps its previous
    /// scheme.
    pub fn set_scheme(&mut self, scheme: crate::time::time_scheme::TimeScheme) -> Result<()> {
        self.set_settings(Settings {
            rho_inf: scheme.rho_inf,
            ..self.settings
        })
    }

    /// Factorizes S of every class for search direction `k` and the current scheme, and leaves
    /// the single-scale linear stage on the new factors (the macro problem, built on the old
    /// ones, is dropped). On an error nothing changes.
    fn refactorize(&mut self, k: f64, precision: FactorPrecision) -> Result<()> {
        self.factors = Arc::new(factorize(
            &self.problem,
            &self.classes,
            (k, precision),
            &self.distribution,
        )?);
        self.linear = new_linear_stage(
            &self.problem,
            &self.classes,
            &self.factors,
            &self.distribution,
            None,
        )?;
        self.spare_macro = None;
        self.settings.two_scale = false;
        Ok(())
    }

    /// Makes the linear stage single- or two-scale (METHOD §4 or §9) for the factorizations of
    /// search direction `k`.
    fn set_scale(&mut self, two_scale: bool, k: f64) -> Result<()> {
        if two_scale == matches!(self.linear, LinearStage::TwoScale(_)) {
            return Ok(());
        }
        let macro_problem = match (two_scale, self.spare_macro.take()) {
            (true, Some(mp)) => Some(mp),
            (true, None) => Some(MacroProblem::new(
                &self.problem,
                k,
                &self.classes,
                &self.factors,
                &self.distribution,
            )?),
            (false, _) => None,
        };
        let placeholder = LinearStage::SingleScale(SingleScale::new(Vec::new()));
        let (works, previous) = std::mem::replace(&mut self.linear, placeholder).into_parts();
        self.linear = match macro_problem {
            Some(mp) => LinearStage::TwoScale(Box::new(TwoScale::new(works, mp))),
            None => {
                self.spare_macro = previous;
                LinearStage::SingleScale(SingleScale::new(works))
            }
        };
        Ok(())
    }

    /// Sets an interface parameter (friction, gap, velocity amplitude) on the problem, checked;
    /// nothing is refactorized.
    pub fn set_parameter(&mut self, parameter: Parameter, value: f64) -> Result<()> {
        self.set_parameter_in(parameter, None, value)
    }

    /// [`Self::set_parameter`] on the interfaces of one zone of the problem (an index into
    /// `problem().zones`; None: every interface).
    pub fn set_parameter_in(
        &mut self,
        parameter: Parameter,
        zone: Option<usize>,
        value: f64,
    ) -> Result<()> {
        let before = self.problem.clone();
        parameter.apply_in(&mut self.problem, zone, value)?;
        self.preload_again(parameter, before)
    }

    /// Adds time spent outside `new` on setup (e.g. assembling the scene).
    pub fn add_setup_time(&mut self, seconds: f64) {
        self.counters.setup_s += seconds;
    }

    /// The per-stage counters.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// The distinct factorizations of S held on this rank (one per class of identical
    /// substructures with a substructure here; every class on one machine).
    pub fn factors(&self) -> Vec<&CholeskyFactor> {
        self.factors.iter().flatten().collect()
    }

    /// Bytes of the factorizations held on this rank (values and structure,
    /// [`CholeskyFactor::bytes`]).
    pub fn factor_bytes(&self) -> usize {
        self.factors
            .iter()
            .flatten()
            .map(CholeskyFactor::bytes)
            .sum()
    }

    /// The factorizations held on this rank with their class index.
    pub fn class_factors(&self) -> impl Iterator<Item = (usize, &CholeskyFactor)> {
        self.factors
            .iter()
            .enumerate()
            .filter_map(|(c, f)| Some((c, f.as_ref()?)))
    }

    /// The factorization of substructure `i`'s operator S.
    ///
    /// # Panics
    /// If substructure `i` is held by another rank of a distributed run.
    pub fn factor(&self, i: usize) -> &CholeskyFactor {
        self.factors[self.classes.of[i]]
            .as_ref()
            .unwrap_or_else(|| panic!("substructure {i} is held by another rank"))
    }

    /// Which substructures share a factorization.
    pub fn classes(&self) -> &Classes {
        &self.classes
    }

    /// The macro problem built for the current k: the two-scale stage's, or the one kept while
    /// the single-scale stage runs (None if the two-scale stage was never asked for at this k).
    pub fn macro_problem(&self) -> Option<&MacroProblem> {
        self.linear.macro_problem().or(self.spare_macro.as_ref())
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
        self.conclude(run)
    }

    /// The solution of an ended run, or the non-finite value that ended it
    /// ([`LopinError::NonFinite`]).
    pub fn conclude(&self, run: SolveRun) -> Result<Solution> {
        if let Some(failure) = run.failure() {
            return Err(LopinError::NonFinite(failure.to_string()));
        }
        Ok(self.finish(run))
    }
}

/// Refuses settings a distributed run cannot honour.
fn check_distributable(settings: &Settings, distribution: &Distribution) -> Result<()> {
    if settings.anderson > 0 && !distribution.is_single() {
        return Err(LopinError::setting(
            "anderson",
            "Anderson acceleration mixes the histories of all substructures and runs on one \
             rank only: use plain relaxation (anderson = 0) or one rank",
        ));
    }
    Ok(())
}

/// Factorizes S of the representative of every class with a substructure on this rank, for
/// search direction k, its factor kept in `precision`.
fn factorize(
    problem: &Problem,
    classes: &Classes,
    (k, precision): (f64, FactorPrecision),
    distribution: &Distribution,
) -> Result<Vec<Option<CholeskyFactor>>> {
    let time = problem.step_coefficients();
    let needed = distribution.holds_classes(&classes.of, classes.count());
    par::map_range(classes.count(), |c| {
        if !needed[c] {
            return Ok(None);
        }
        let sub = &problem.subs[classes.representatives[c]];
        let triplets = sub.operator_triplets(&time, k);
        // `single_for` is false in the browser build, which has no single-precision factor
        let factor = match precision.single_for(sub.ndof()) {
            #[cfg(not(target_arch = "wasm32"))]
            true => CholeskyFactor::try_new_single(sub.ndof(), &triplets),
            _ => CholeskyFactor::try_new(sub.ndof(), &triplets),
        };
        factor
            .map(Some)
            .map_err(|failure| LopinError::Factorization {
                sub: sub.name.clone(),
                reason: sub.describe_failure(&failure),
            })
    })
    .into_iter()
    .collect()
}

/// A linear stage with fresh buffers on these factorizations: two-scale with the macro problem
/// of search direction k where `macro_k` gives it (METHOD §9), else single-scale (METHOD §4).
fn new_linear_stage(
    problem: &Problem,
    classes: &Classes,
    factors: &[Option<CholeskyFactor>],
    distribution: &Distribution,
    macro_k: Option<f64>,
) -> Result<LinearStage> {
    let works = make_works(problem, classes, factors, distribution);
    Ok(match macro_k {
        Some(k) => {
            let mp = MacroProblem::new(problem, k, classes, factors, distribution)?;
            LinearStage::TwoScale(Box::new(TwoScale::new(works, mp)))
        }
        None => LinearStage::SingleScale(SingleScale::new(works)),
    })
}

/// Scratch buffers of every substructure's linear stage (none for those on other ranks).
fn make_works(
    problem: &Problem,
    classes: &Classes,
    factors: &[Option<CholeskyFactor>],
    distribution: &Distribution,
) -> Vec<LinearWork> {
    let time = problem.step_coefficients();
    problem
        .subs
        .iter()
        .enumerate()
        .map(|(i, s)| match &factors[classes.of[i]] {
            Some(f) if distribution.holds_sub(i) => LinearWork::new(s, f, &time),
            _ => LinearWork::idle(),
        })
        .collect()
}
