//! The parameters the explorer lets the user move: the contact interfaces' friction coefficient
//! and initial gap, the amplitude of the prescribed impact velocity (METHOD §5 laws), and the
//! LATIN settings k, μ, tolerance and the macro problem switch (METHOD §3, §7, §9). Applying them
//! never refactorizes unless k changes (the macro problem is built the first time it is switched
//! on, and again after a change of k).

use lopin_core::interface::{DofLaw, Law};
use lopin_core::{Problem, Settings, Solver};

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
}

impl Params {
    /// The values a built problem and its settings start with.
    pub fn of(problem: &Problem, settings: &Settings) -> Params {
        let contact = problem.interfaces.iter().find_map(|i| match &i.law {
            Law::Contact(c) => Some(c),
            _ => None,
        });
        let velocity = problem
            .interfaces
            .iter()
            .filter_map(|i| match &i.law {
                Law::Boundary(d) => Some(d),
                _ => None,
            })
            .flatten()
            .filter_map(|d| match d.law {
                DofLaw::Velocity(f) if f.amplitude != 0.0 => Some(f.amplitude.abs()),
                _ => None,
            })
            .reduce(f64::max);
        Params {
            friction: contact.map(|c| c.friction),
            gap: contact.map(|c| c.gap.first().copied().unwrap_or(0.0)),
            velocity,
            k: settings.k,
            mu: settings.mu,
            tol: settings.tol,
            two_scale: settings.two_scale,
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
        solver.set_settings(settings)?;
        let changed = |a: Option<f64>, b: Option<f64>| a.filter(|&x| Some(x) != b);
        if let Some(f) = changed(self.friction, before.friction) {
            solver.set_friction(f)?;
        }
        if let Some(g) = changed(self.gap, before.gap) {
            solver.set_gap(g)?;
        }
        if let Some(v) = changed(self.velocity, before.velocity) {
            solver.set_velocity_amplitude(v)?;
        }
        Ok(())
    }

    /// A one-line description for the convergence plot's markers.
    pub fn describe_change(&self, before: &Params) -> String {
        let mut parts = Vec::new();
        let opt = |name: &str, a: Option<f64>, b: Option<f64>, parts: &mut Vec<String>| {
            if let (Some(a), Some(b)) = (a, b) {
                if a != b {
                    parts.push(format!("{name} = {a:.4}"));
                }
            }
        };
        opt("f", self.friction, before.friction, &mut parts);
        opt("gap", self.gap, before.gap, &mut parts);
        opt("v0", self.velocity, before.velocity, &mut parts);
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
        if self.tol != before.tol {
            parts.push(format!("tol = {:.0e}", self.tol));
        }
        parts.join(", ")
    }
}
