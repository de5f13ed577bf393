//! The parameters the explorer lets the user move: the contact interfaces' friction coefficient
//! and initial gap, the amplitude of the prescribed impact velocity (METHOD §5 laws), and the
//! LATIN settings k, μ, tolerance, the macro problem switch, the time scheme's ρ∞ and the shape of
//! the search direction (METHOD §2, §3, §7, §9). Applying them never refactorizes unless k, ρ∞ or
//! the direction shape changes (the macro problem is built the first time it is switched on, and
//! again after such a change).

use lopin_core::search_direction::Directions;
use lopin_core::time_scheme::TimeScheme;
use lopin_core::{Parameter, Problem, Settings, Solver};

/// One set of parameter values.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// Friction coefficient of every contact interface (None: the scene has no contact).
    pub friction: Option<f64>,
    /// Initial gap of every contact node, m (None: the scene has no contact).
    pub gap: Option<f64>,
    /// Amplitude of the prescribed impact velocity, m/s (None: nothing is prescribed).
    pub velocity: Option<f64>,
    /// Search direction k, Pa·s/m.
    pub k: f64,
    /// Relaxation μ.
    pub mu: f64,
    /// Stopping tolerance on η.
    pub tol: f64,
    /// Two-scale linear stage with the macro problem (METHOD §9).
    pub two_scale: bool,
    /// Spectral radius at infinite frequency of the time scheme (1: the trapezoidal rule).
    pub rho_inf: f64,
    /// Wave-matched search direction (ρc_p normal, ρc_s tangential) instead of the scalar k.
    pub wave: bool,
}

impl Params {
    /// The values a built problem and its settings start with.
    pub fn of(problem: &Problem, settings: &Settings) -> Params {
        Params {
            friction: Parameter::Friction.current(problem),
            gap: Parameter::Gap.current(problem),
            velocity: Parameter::VelocityAmplitude.current(problem),
            k: settings.k,
            mu: settings.mu,
            tol: settings.tol,
            two_scale: settings.two_scale,
            rho_inf: problem.scheme.rho_inf,
            wave: settings.directions == Directions::Wave,
        }
    }

    /// The value of an interface parameter (None: the scene has nothing it applies to).
    pub fn get(&self, p: Parameter) -> Option<f64> {
        match p {
            Parameter::Friction => self.friction,
            Parameter::Gap => self.gap,
            Parameter::VelocityAmplitude => self.velocity,
        }
    }

    /// Sets on the solver the values that differ from `before` (what it holds now), so that a
    /// scene's own per-interface values stay until the user moves that control. Validated
    /// there; a new k refactorizes.
    pub fn apply(&self, before: &Params, solver: &mut Solver) -> lopin_core::Result<()> {
        let mut settings = *solver.settings();
        settings.k = self.k;
        settings.mu = self.mu;
        settings.tol = self.tol;
        settings.two_scale = self.two_scale;
        settings.directions = if self.wave {
            Directions::Wave
        } else {
            Directions::Isotropic
        };
        solver.set_scheme(TimeScheme::new(self.rho_inf))?;
        solver.set_settings(settings)?;
        for p in Parameter::ALL {
            if let Some(v) = self.get(p).filter(|&v| Some(v) != before.get(p)) {
                solver.set_parameter(p, v)?;
            }
        }
        Ok(())
    }

    /// A one-line description for the convergence plot's markers.
    pub fn describe_change(&self, before: &Params) -> String {
        let mut parts = Vec::new();
        for p in Parameter::ALL {
            if let (Some(a), Some(b)) = (self.get(p), before.get(p)) {
                if a != b {
                    parts.push(format!("{} = {a:.4}", p.name()));
                }
            }
        }
        if self.k != before.k {
            parts.push(format!("k = {:.3e}", self.k));
        }
        if self.mu != before.mu {
            parts.push(format!("μ = {:.2}", self.mu));
        }
        if self.two_scale != before.two_scale {
            parts.push(format!(
                "macro {}",
                if self.two_scale { "on" } else { "off" }
            ));
        }
        if self.rho_inf != before.rho_inf {
            parts.push(format!("ρ∞ = {:.2}", self.rho_inf));
        }
        if self.wave != before.wave {
            parts.push(format!(
                "{} direction",
                if self.wave { "wave" } else { "scalar" }
            ));
        }
        if self.tol != before.tol {
            parts.push(format!("tol = {:.0e}", self.tol));
        }
        parts.join(", ")
    }
}
