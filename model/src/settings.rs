//! The solver's settings, every knob in one place (METHOD §2 time scheme, §3 search direction,
//! §6 relaxation and stopping test, §7 time windows, §9 two-scale switch, §10 defaults), the
//! checks every setting gets, and the one precedence rule that resolves them: the defaults, under
//! the scene's `[solver]` table, under the command line or the explorer. Each of those layers
//! is a [`SolverSpec`] (every field optional); [`SolverSpec::over`] stacks two, and
//! [`Settings::for_problem`] resolves the stack against a problem's defaults.

use crate::error::{LopinError, Result};
use crate::interfaces::search_direction::Directions;
use crate::problem::Problem;
use crate::scene::settings::{FactorPrecision, StopTest, WindowStart};
use crate::scene::spec::SolverSpec;
use crate::time::time_scheme::TimeScheme;

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
    /// On a cold start, where each time window's iteration begins ([`WindowStart`]): the
    /// default (`Auto`) extrapolates the mean change of the last two converged steps at
    /// tolerances of 1e-3 and tighter and holds the last step above; `Zero` is the plain METHOD
    /// §7 variant (more iterations than `Hold` in incremental runs: the guide,
    /// docs/src/iterations.md, gives the figures).
    #[serde(default)]
    pub window_start: WindowStart,
    /// Normalize a window's η by its own energy plus the mean energy per step of the earlier
    /// windows times the window length (true, default), rather than by the whole energy of steps
    /// 1..m1 (false, METHOD §7): with the cumulative norm the criterion loosens as the run goes
    /// on, and a long impact can gain energy while η is below the tolerance.
    pub per_step_window_norm: bool,
    /// Two-scale linear stage: the macro problem of METHOD §9 couples all substructures at every
    /// time step (false: the single-scale linear stage of METHOD §4).
    #[serde(default, rename = "macro")]
    pub two_scale: bool,
    /// Shape of the search direction: the scalar k, or matched to the P and S waves
    /// ([`crate::interfaces::search_direction`]). Changing it refactorizes.
    #[serde(default)]
    pub directions: Directions,
    /// Which indicator the stopping test reads: η, or η̄ on step-averaged fields
    /// (`lopin_core::stages::indicator`).
    #[serde(default)]
    pub stop: StopTest,
    /// Depth of the Anderson acceleration of the relaxation (`lopin_core::stages::acceleration`;
    /// 0: the plain relaxation of METHOD §6).
    #[serde(default)]
    pub anderson: usize,
    /// Spectral radius at infinite frequency of the time scheme (METHOD §2; 1: the undamped
    /// trapezoidal rule). The problem's scheme follows it; changing it refactorizes.
    #[serde(default = "undamped", skip_serializing_if = "is_undamped")]
    pub rho_inf: f64,
    /// The precision the factors of S keep ([`FactorPrecision`]). Changing it refactorizes.
    /// Left out of records when double (the default), so records and fingerprints of runs that
    /// never asked read as before.
    #[serde(default, skip_serializing_if = "FactorPrecision::is_auto")]
    pub factors: FactorPrecision,
}

fn undamped() -> f64 {
    1.0
}

/// Whether ρ∞ is the default (left out of records, which read it back as the default).
fn is_undamped(rho_inf: &f64) -> bool {
    *rho_inf == 1.0
}

impl Settings {
    /// Default iteration limit.
    pub const MAX_ITER: usize = 2000;
    /// Largest Anderson depth accepted.
    pub const MAX_ANDERSON: usize = 50;

    /// The defaults for a problem under a layer of settings (the scene's `[solver]` table, or
    /// that table under the command line's, [`SolverSpec::over`]). The window is the layer's
    /// length (None: the whole interval); a command picks it with
    /// [`crate::window_choice::choose`].
    pub fn for_problem(problem: &Problem, spec: &SolverSpec) -> Self {
        Self::under(problem.default_k(), spec)
    }

    /// The defaults of METHOD §10 for a model of impedance scale `k0` = mean √(ρE).
    pub fn defaults(k0: f64) -> Self {
        Self::under(k0, &SolverSpec::default())
    }

    /// The defaults for impedance scale `k0` under a layer.
    fn under(k0: f64, spec: &SolverSpec) -> Self {
        Self {
            k: spec.k.unwrap_or(k0),
            mu: spec.mu.unwrap_or(0.8),
            tol: spec.tol.unwrap_or(1e-3),
            max_iter: spec.max_iter.unwrap_or(Self::MAX_ITER),
            window: spec.window.and_then(|w| w.steps()),
            skip_unchanged: true,
            window_start: spec.window_start.unwrap_or_default(),
            per_step_window_norm: true,
            two_scale: spec.two_scale.unwrap_or(false),
            directions: spec.directions.unwrap_or_default(),
            stop: spec.stop.unwrap_or_default(),
            anderson: spec.anderson.unwrap_or(0),
            rho_inf: spec.rho_inf.unwrap_or(1.0),
            factors: spec.factors.unwrap_or_default(),
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
        if self.anderson > Self::MAX_ANDERSON {
            return Err(LopinError::setting(
                "anderson",
                format!(
                    "depth {} is more than {} (each level keeps two copies of the interface state)",
                    self.anderson,
                    Self::MAX_ANDERSON
                ),
            ));
        }
        if self.window == Some(0) {
            return Err(LopinError::setting("window", "must be at least 1 step"));
        }
        TimeScheme::new(self.rho_inf)
            .check()
            .map_err(|reason| LopinError::setting("rho_inf", reason))
    }

    /// The time scheme these settings ask for.
    pub fn scheme(&self) -> TimeScheme {
        TimeScheme::new(self.rho_inf)
    }

    /// Checks the settings against a problem: k within [`crate::scene::validate::K_RANGE`]
    /// times the problem's impedance scale k0 = mean √(ρE) (METHOD §10), the error naming both.
    pub fn validate_for(&self, problem: &Problem) -> Result<()> {
        self.validate()?;
        if problem.statics {
            // statics relates tractions to displacements: k is a stiffness per area (Pa/m),
            // not an impedance
            return Ok(());
        }
        crate::scene::validate::check_k_against(self.k, problem.default_k())
            .map_err(|reason| LopinError::setting("k", reason))
    }
}
