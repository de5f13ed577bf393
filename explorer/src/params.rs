//! The parameters the explorer lets the user move: the contact interfaces' friction coefficient
//! (on every contact, or on one zone of the scene, [`FrictionTargets`]) and initial gap, the
//! amplitudes of the prescribed impact velocity, tractions and base accelerations and the
//! duration of a boundary pulse (METHOD §5 laws), and the
//! LATIN settings k, μ, tolerance, the macro problem switch, the time scheme's ρ∞ and the shape of
//! the search direction (METHOD §2, §3, §7, §9). Applying them never refactorizes unless k, ρ∞ or
//! the direction shape changes (the macro problem is built the first time it is switched on, and
//! again after such a change).

use lopin_core::interfaces::search_direction::Directions;
use lopin_core::{Parameter, Problem, Settings, Solver};
use std::sync::Arc;

/// One set of parameter values.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Params {
    /// Friction coefficient of the contact interfaces the friction slider moves: every one, or
    /// those of zone `friction_zone` (None: the scene has no contact).
    pub friction: Option<f64>,
    /// The zone the friction slider moves (an index into `zones`; None: every contact).
    pub friction_zone: Option<usize>,
    /// The names of the scene's zones (`[[zone]]`).
    pub zones: Arc<[String]>,
    /// Initial gap of every contact node, m (None: the scene has no contact).
    pub gap: Option<f64>,
    /// Amplitude of the prescribed impact velocity, m/s (None: nothing is prescribed).
    pub velocity: Option<f64>,
    /// Amplitude of the prescribed tractions, Pa (None: nothing is prescribed).
    pub traction: Option<f64>,
    /// Amplitude of the prescribed (base) accelerations, m/s² (None: nothing is prescribed).
    pub acceleration: Option<f64>,
    /// Amplitude of the preload tractions, Pa (None: the scene has no preload traction).
    pub preload: Option<f64>,
    /// Duration of the boundary pulses, s (None: the scene prescribes no pulse).
    pub duration: Option<f64>,
    /// The solver settings; the panel moves k, μ, the tolerance, the macro switch, ρ∞ and the
    /// shape of the search direction.
    #[serde(with = "crate::wire::as_json")]
    pub settings: Settings,
}

impl Params {
    /// The values a built problem and its settings start with.
    pub fn of(problem: &Problem, settings: &Settings) -> Params {
        Params {
            friction: Parameter::Friction.current(problem),
            friction_zone: None,
            zones: problem.zones.iter().map(|z| z.name.clone()).collect(),
            gap: Parameter::Gap.current(problem),
            velocity: Parameter::VelocityAmplitude.current(problem),
            traction: Parameter::TractionAmplitude.current(problem),
            acceleration: Parameter::AccelerationAmplitude.current(problem),
            preload: Parameter::Preload.current(problem),
            duration: Parameter::PulseDuration.current(problem),
            settings: *settings,
        }
    }

    /// The value of an interface parameter (None: the scene has nothing it applies to).
    pub fn get(&self, p: Parameter) -> Option<f64> {
        match p {
            Parameter::Friction => self.friction,
            Parameter::Gap => self.gap,
            Parameter::VelocityAmplitude => self.velocity,
            Parameter::TractionAmplitude => self.traction,
            Parameter::AccelerationAmplitude => self.acceleration,
            Parameter::Preload => self.preload,
            Parameter::PulseDuration => self.duration,
        }
    }

    /// Sets on the solver the values that differ from `before` (what it holds now), so that a
    /// scene's own per-interface values stay until the user moves that control. Validated
    /// there; a new k refactorizes.
    pub fn apply(&self, before: &Params, solver: &mut Solver) -> lopin_core::Result<()> {
        solver.set_settings(self.settings)?;
        for p in Parameter::ALL {
            if let Some(v) = self.get(p).filter(|&v| Some(v) != before.get(p)) {
                match p {
                    Parameter::Friction => solver.set_parameter_in(p, self.friction_zone, v)?,
                    _ => solver.set_parameter(p, v)?,
                }
            }
        }
        Ok(())
    }

    /// The name of what the friction slider moves: `f`, or `f@ZONE`.
    pub fn friction_label(&self) -> String {
        match self.friction_zone.and_then(|z| self.zones.get(z)) {
            Some(name) => format!("f@{name}"),
            None => "f".into(),
        }
    }

    /// A one-line description for the convergence plot's markers.
    pub fn describe_change(&self, before: &Params) -> String {
        let mut parts = Vec::new();
        for p in Parameter::ALL {
            if let (Some(a), Some(b)) = (self.get(p), before.get(p)) {
                if a != b {
                    let name = match p {
                        Parameter::Friction => self.friction_label(),
                        _ => p.name().to_string(),
                    };
                    parts.push(format!("{name} = {a:.4}"));
                }
            }
        }
        let (s, b) = (&self.settings, &before.settings);
        if s.k != b.k {
            parts.push(format!("k = {:.3e}", s.k));
        }
        if s.mu != b.mu {
            parts.push(format!("μ = {:.2}", s.mu));
        }
        if s.two_scale != b.two_scale {
            parts.push(format!("macro {}", if s.two_scale { "on" } else { "off" }));
        }
        if s.rho_inf != b.rho_inf {
            parts.push(format!("ρ∞ = {:.2}", s.rho_inf));
        }
        if s.directions != b.directions {
            parts.push(format!(
                "{} direction",
                if s.directions == Directions::Wave {
                    "wave"
                } else {
                    "scalar"
                }
            ));
        }
        if s.tol != b.tol {
            parts.push(format!("tol = {:.0e}", s.tol));
        }
        parts.join(", ")
    }
}

/// What the friction slider moves and the value it last gave each target: every contact
/// (target None) or one zone. Switching the target shows that target's value without changing
/// the problem; a move on every contact gives each zone that value too.
#[derive(Debug, Clone, PartialEq)]
pub struct FrictionTargets {
    /// The value of every contact, then of each zone (None: no contact there).
    values: Vec<Option<f64>>,
}

impl FrictionTargets {
    /// The targets of a built problem, with its current values.
    pub fn of(problem: &Problem) -> FrictionTargets {
        let mut values = vec![Parameter::Friction.current(problem)];
        values.extend(
            (0..problem.zones.len()).map(|z| Parameter::Friction.current_in(problem, Some(z))),
        );
        FrictionTargets { values }
    }

    /// The targets with these values: every contact, then each zone (None: no contact there).
    pub fn from_values(values: Vec<Option<f64>>) -> FrictionTargets {
        let values = if values.is_empty() {
            vec![None]
        } else {
            values
        };
        FrictionTargets { values }
    }

    /// Each target's value: every contact, then each zone.
    pub fn values(&self) -> &[Option<f64>] {
        &self.values
    }

    /// The zones the slider can move alone (those with a contact interface).
    pub fn zones(&self) -> impl Iterator<Item = usize> + '_ {
        (0..self.values.len() - 1).filter(|&z| self.values[slot(Some(z))].is_some())
    }

    /// Points the slider at `to` (None: every contact): `p` shows its value.
    pub fn switch(&mut self, p: &mut Params, to: Option<usize>) {
        if to == p.friction_zone || self.values.get(slot(to)).is_none() {
            return;
        }
        self.values[slot(p.friction_zone)] = p.friction;
        p.friction_zone = to;
        p.friction = self.values[slot(to)];
    }

    /// Records a move of the slider to `p.friction`.
    pub fn moved(&mut self, p: &Params) {
        self.set(p.friction_zone, p.friction);
    }

    /// Records `value` given to target `zone` (None: every contact) other than by the slider (a
    /// stored configuration shown).
    pub fn set(&mut self, zone: Option<usize>, value: Option<f64>) {
        match zone {
            Some(_) => {
                if let Some(v) = self.values.get_mut(slot(zone)) {
                    *v = value;
                }
            }
            None => {
                for v in self.values.iter_mut().filter(|v| v.is_some()) {
                    *v = value;
                }
            }
        }
    }
}

/// The index in [`FrictionTargets`]'s values of a target (None: every contact).
fn slot(target: Option<usize>) -> usize {
    target.map_or(0, |z| z + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slider_shows_each_targets_own_value_and_every_contact_sets_all() {
        let mut p = Params {
            friction: Some(0.3),
            friction_zone: None,
            zones: vec!["upper".to_string(), "lower".to_string()].into(),
            gap: None,
            velocity: None,
            traction: None,
            acceleration: None,
            preload: None,
            duration: None,
            settings: Settings::defaults(1.0),
        };
        let mut t = FrictionTargets {
            values: vec![Some(0.3), Some(0.3), Some(0.3)],
        };
        assert_eq!(t.zones().collect::<Vec<_>>(), vec![0, 1]);
        t.switch(&mut p, Some(0));
        assert_eq!((p.friction_zone, p.friction), (Some(0), Some(0.3)));
        assert_eq!(p.friction_label(), "f@upper");
        p.friction = Some(0.1);
        t.moved(&p);
        t.switch(&mut p, Some(1));
        assert_eq!((p.friction_zone, p.friction), (Some(1), Some(0.3)));
        t.switch(&mut p, Some(0));
        assert_eq!(p.friction, Some(0.1));
        // every contact: shows its last value, and a move gives it to every zone
        t.switch(&mut p, None);
        assert_eq!((p.friction_zone, p.friction), (None, Some(0.3)));
        assert_eq!(p.friction_label(), "f");
        p.friction = Some(0.5);
        t.moved(&p);
        t.switch(&mut p, Some(0));
        assert_eq!(p.friction, Some(0.5));
        // an unknown zone is ignored
        t.switch(&mut p, Some(7));
        assert_eq!(p.friction_zone, Some(0));
        let before = p.clone();
        p.friction = Some(0.2);
        assert_eq!(p.describe_change(&before), "f@upper = 0.2000");
    }
}
