//! The interface parameters a user moves without refactorizing anything (METHOD §5 laws, §8
//! multiresolution): the friction coefficient and initial gap of every contact interface, the
//! amplitude of every non-zero prescribed velocity, traction and acceleration, the preload (the
//! amplitude of the tractions a static phase applies), and the duration of every boundary pulse.
//! One type reads a parameter's current value from a problem and applies a new one, validated; the
//! solver, sweeps, the explorer and the monolithic reference all go through it.

use crate::error::{LopinError, Result};
use crate::interfaces::interface::{BoundaryDof, DofLaw, Law};
use crate::problem::Problem;
use crate::time::time_function::TimeFunction;

/// A parameter of the interfaces' laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Parameter {
    /// Friction coefficient f of every contact interface.
    Friction,
    /// Initial gap g0 (m) of every contact node.
    Gap,
    /// Amplitude V0 (m/s) of every non-zero prescribed velocity.
    VelocityAmplitude,
    /// Amplitude t0 (Pa) of every non-zero prescribed traction.
    TractionAmplitude,
    /// Amplitude a0 (m/s²) of every non-zero prescribed acceleration.
    AccelerationAmplitude,
    /// Amplitude (Pa) of every preload traction (a clamping pressure: the preload's static phase
    /// applies it and the dynamics hold it).
    Preload,
    /// Duration T (s) of every standard pulse a boundary prescribes (a trapezoid's rise scales
    /// with it).
    PulseDuration,
}

impl Parameter {
    /// Every parameter, in the order tables and panels list them.
    pub const ALL: [Parameter; 7] = [
        Self::Friction,
        Self::Gap,
        Self::VelocityAmplitude,
        Self::TractionAmplitude,
        Self::AccelerationAmplitude,
        Self::Preload,
        Self::PulseDuration,
    ];

    /// Parses `f`/`friction`, `gap`/`g0`, `v0`/`velocity`, `t0`/`traction`,
    /// `a0`/`acceleration`, `preload`, `duration`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "f" | "friction" => Ok(Self::Friction),
            "gap" | "g0" => Ok(Self::Gap),
            "v0" | "velocity" => Ok(Self::VelocityAmplitude),
            "t0" | "traction" => Ok(Self::TractionAmplitude),
            "a0" | "acceleration" => Ok(Self::AccelerationAmplitude),
            "preload" => Ok(Self::Preload),
            "duration" => Ok(Self::PulseDuration),
            _ => Err(LopinError::setting(
                "param",
                format!(
                    "unknown parameter `{name}` (sweepable: f, gap, v0, t0, a0, preload, duration)"
                ),
            )),
        }
    }

    /// Whether moving it moves the preload's static equilibrium (friction, gap, preload), so
    /// that the static phase must be solved again.
    pub fn moves_statics(&self) -> bool {
        matches!(self, Self::Friction | Self::Gap | Self::Preload)
    }

    /// Short name used in files, tables and plot markers.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Friction => "f",
            Self::Gap => "gap",
            Self::VelocityAmplitude => "v0",
            Self::TractionAmplitude => "t0",
            Self::AccelerationAmplitude => "a0",
            Self::Preload => "preload",
            Self::PulseDuration => "duration",
        }
    }

    /// Unit of the value (empty for the friction coefficient).
    pub fn unit(&self) -> &'static str {
        match self {
            Self::Friction => "",
            Self::Gap => "m",
            Self::VelocityAmplitude => "m/s",
            Self::TractionAmplitude => "Pa",
            Self::AccelerationAmplitude => "m/s²",
            Self::Preload => "Pa",
            Self::PulseDuration => "s",
        }
    }

    /// Checks a value: f non-negative and in the friction range of scenes
    /// ([`crate::scene::validate::FRICTION_RANGE`]), gap finite (negative: an interference the
    /// preload's static phase closes), v0 finite. The
    /// error names the setting the way the solver's setters always have (`friction`, `gap`,
    /// `v0`).
    pub fn check(&self, value: f64) -> Result<()> {
        match self {
            Self::Friction if !(value.is_finite() && value >= 0.0) => Err(LopinError::setting(
                "friction",
                format!("must be non-negative, got {value:?}"),
            )),
            Self::Friction => crate::scene::validate::check_friction(value)
                .map_err(|reason| LopinError::setting("friction", reason)),
            Self::Gap if !value.is_finite() => Err(LopinError::setting(
                "gap",
                format!("must be a number (negative: an interference), got {value:?}"),
            )),
            Self::VelocityAmplitude if !value.is_finite() => Err(LopinError::setting(
                "v0",
                format!("must be finite, got {value:?}"),
            )),
            Self::TractionAmplitude if !value.is_finite() => Err(LopinError::setting(
                "t0",
                format!("must be finite, got {value:?}"),
            )),
            Self::AccelerationAmplitude if !value.is_finite() => Err(LopinError::setting(
                "a0",
                format!("must be finite, got {value:?}"),
            )),
            Self::Preload if !(value.is_finite() && value >= 0.0) => Err(LopinError::setting(
                "preload",
                format!(
                    "must be a non-negative amplitude (the scene's directions are kept), got {value:?}"
                ),
            )),
            Self::PulseDuration if !(value.is_finite() && value > 0.0) => Err(LopinError::setting(
                "duration",
                format!("must be positive, got {value:?}"),
            )),
            _ => Ok(()),
        }
    }

    /// The value the problem holds now: the first contact interface's friction or first gap, the
    /// largest prescribed velocity amplitude. None when the problem has nothing it applies to.
    pub fn current(&self, problem: &Problem) -> Option<f64> {
        self.current_in(problem, None)
    }

    /// [`Self::current`] among the interfaces of `zone` (an index into `problem.zones`; None:
    /// all).
    pub fn current_in(&self, problem: &Problem, zone: Option<usize>) -> Option<f64> {
        let reached = |i: usize| zone.is_none_or(|z| problem.zones[z].holds(i));
        let interfaces = problem
            .interfaces
            .iter()
            .enumerate()
            .filter(|&(i, _)| reached(i))
            .map(|(_, iface)| iface);
        let boundary_dofs = interfaces
            .clone()
            .filter_map(|i| match &i.law {
                Law::Boundary(d) => Some(d),
                _ => None,
            })
            .flatten();
        let contact = interfaces.clone().find_map(|i| match &i.law {
            Law::Contact(c) => Some(c),
            _ => None,
        });
        match self {
            Self::Friction => contact.map(|c| c.friction),
            Self::Gap => contact.map(|c| c.gap.first().copied().unwrap_or(0.0)),
            Self::VelocityAmplitude => largest(boundary_dofs, |d| velocity(d, false)),
            Self::AccelerationAmplitude => largest(boundary_dofs, |d| velocity(d, true)),
            Self::TractionAmplitude => largest(boundary_dofs, |d| traction(d, false)),
            Self::Preload => largest(boundary_dofs, |d| traction(d, true)),
            Self::PulseDuration => boundary_dofs
                .filter_map(BoundaryDof::pulse_duration)
                .reduce(f64::max),
        }
    }

    /// Checks a value against a problem: a velocity amplitude no faster than the slowest wave
    /// speed of the materials in use (small strains), a gap no larger than the model.
    pub fn check_for(&self, problem: &Problem, value: f64) -> Result<()> {
        self.check(value)?;
        match self {
            Self::VelocityAmplitude => {
                let slowest = crate::elements::material::slowest(problem.subs.iter().map(|s| {
                    let name = &problem.materials[s.material_id].name;
                    (s.material.bar_speed(), name.as_str())
                }));
                crate::elements::material::check_small_strain_speed(value, slowest)
                    .map_err(|reason| LopinError::setting("v0", reason))?;
            }
            Self::Gap => {
                let size = problem.diameter();
                if value.abs() > size {
                    return Err(LopinError::setting(
                        "gap",
                        format!("{value:?} m exceeds the size of the whole model ({size:.4e} m)"),
                    ));
                }
            }
            Self::PulseDuration => {
                crate::scene::validate::check_pulse_duration(value, problem.time.end())
                    .map_err(|reason| LopinError::setting("duration", reason))?;
            }
            Self::Friction
            | Self::TractionAmplitude
            | Self::AccelerationAmplitude
            | Self::Preload => {}
        }
        Ok(())
    }

    /// Checks `value` (against the problem too, [`Self::check_for`]) and sets it on every
    /// interface it applies to.
    pub fn apply(&self, problem: &mut Problem, value: f64) -> Result<()> {
        self.apply_in(problem, None, value)
    }

    /// [`Self::apply`] on the interfaces of `zone` only (an index into `problem.zones`; None:
    /// every interface).
    pub fn apply_in(&self, problem: &mut Problem, zone: Option<usize>, value: f64) -> Result<()> {
        self.check_for(problem, value)?;
        if let Some(z) = zone {
            if z >= problem.zones.len() {
                return Err(LopinError::setting(
                    "param",
                    format!("zone {z} of {}", problem.zones.len()),
                ));
            }
        }
        match self {
            Self::Friction => problem.set_friction(value, zone),
            Self::Gap => problem.set_gap(value, zone),
            Self::VelocityAmplitude => problem.set_velocity_amplitude(value, zone),
            Self::TractionAmplitude => problem.set_traction_amplitude(value, zone),
            Self::AccelerationAmplitude => problem.set_acceleration_amplitude(value, zone),
            Self::Preload => problem.set_preload(value, zone),
            Self::PulseDuration => problem.set_pulse_duration(value, zone),
        }
        Ok(())
    }
}

/// The largest non-zero amplitude among the laws `law` picks out of `dofs`.
fn largest<'a>(
    dofs: impl Iterator<Item = &'a BoundaryDof>,
    law: impl Fn(&'a BoundaryDof) -> Option<&'a TimeFunction>,
) -> Option<f64> {
    dofs.filter_map(law)
        .filter(|f| f.amplitude != 0.0)
        .map(|f| f.amplitude.abs())
        .reduce(f64::max)
}

/// A dof's prescribed velocity: one integrated from an acceleration, or not.
fn velocity(d: &BoundaryDof, integrated: bool) -> Option<&TimeFunction> {
    match &d.law {
        DofLaw::Velocity(f) if f.acceleration().is_some() == integrated => Some(f),
        _ => None,
    }
}

/// A dof's prescribed traction: a preload's, or not.
fn traction(d: &BoundaryDof, preload: bool) -> Option<&TimeFunction> {
    match &d.law {
        DofLaw::Traction(f) if d.preload == preload => Some(f),
        _ => None,
    }
}

impl std::fmt::Display for Parameter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Parameter {
    type Err = LopinError;
    fn from_str(s: &str) -> Result<Self> {
        Self::parse(s)
    }
}
