//! A parameter of the interface laws as users name it: one interface parameter
//! ([`crate::Parameter`]: f, gap, v0, t0, a0, preload, duration, METHOD §5) on every interface it applies
//! to, or on one zone's ([`crate::interfaces::zone`]), written `f` or `f@ZONE` ([`Target`]); and a value given
//! to one, `f@ZONE=0.3` ([`Assignment`]), which a run applies to its built problem. Studies move
//! targets; runs and the explorer assign them.

use crate::error::{LopinError, Result};
use crate::parameter::Parameter;
use crate::problem::Problem;

/// One parameter a study moves.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Target {
    /// Which law parameter.
    pub parameter: Parameter,
    /// The zone (index into `problem.zones`), or None for every interface.
    pub zone: Option<usize>,
    /// `f`, `gap`, `v0`, or `f@ZONE`: how files and figures name it.
    pub label: String,
}

impl Target {
    /// Parses `NAME` or `NAME@ZONE` against a problem's zones.
    pub fn parse(text: &str, problem: &Problem) -> Result<Self> {
        let (name, zone) = match text.split_once('@') {
            Some((n, z)) => (n.trim(), Some(z.trim())),
            None => (text.trim(), None),
        };
        let parameter = Parameter::parse(name)?;
        let zone = match zone {
            None => None,
            Some(z) => {
                let names: Vec<&str> = problem.zones.iter().map(|x| x.name.as_str()).collect();
                let found = names.iter().position(|n| *n == z).ok_or_else(|| {
                    LopinError::setting(
                        "param",
                        if names.is_empty() {
                            format!("unknown zone `{z}`: the scene defines no [[zone]]")
                        } else {
                            format!("unknown zone `{z}` (zones: {})", names.join(", "))
                        },
                    )
                })?;
                Some(found)
            }
        };
        let target = Self {
            parameter,
            zone,
            label: match zone {
                Some(z) => format!("{}@{}", parameter.name(), problem.zones[z].name),
                None => parameter.name().to_string(),
            },
        };
        if parameter.current_in(problem, zone).is_none() {
            return Err(LopinError::setting(
                "param",
                format!(
                    "`{}` applies to nothing in this scene ({})",
                    target.label,
                    match parameter {
                        Parameter::VelocityAmplitude => "no non-zero prescribed velocity",
                        Parameter::TractionAmplitude => "no non-zero prescribed traction",
                        Parameter::AccelerationAmplitude => "no non-zero prescribed acceleration",
                        Parameter::Preload => "no preload traction",
                        Parameter::PulseDuration => "no boundary pulse",
                        Parameter::Friction | Parameter::Gap => "no contact interface",
                    }
                ),
            ));
        }
        Ok(target)
    }

    /// Sets `value` on the problem (checked as [`Parameter::apply_in`] does).
    pub fn apply(&self, problem: &mut Problem, value: f64) -> Result<()> {
        self.parameter.apply_in(problem, self.zone, value)
    }
}

/// A value given to a parameter, as the command line writes it: `f=0.3`, `gap@top=1e-5`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Assignment {
    /// `f`, `gap`, `v0` or `NAME@ZONE` ([`Target::parse`] reads it against a problem).
    pub target: String,
    /// The value.
    pub value: f64,
}

impl Assignment {
    /// Parses `NAME=VALUE` or `NAME@ZONE=VALUE` (the name and value checked here, the zone and
    /// the value's range against the problem when applied).
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |reason: String| LopinError::setting("set", reason);
        let (target, value) = text.split_once('=').ok_or_else(|| {
            bad(format!(
                "expected NAME=VALUE or NAME@ZONE=VALUE, got `{text}`"
            ))
        })?;
        let target = target.trim();
        let parameter = Parameter::parse(name_of(target))?;
        let value: f64 = value
            .trim()
            .parse()
            .map_err(|_| bad(format!("`{}` is not a number (in `{text}`)", value.trim())))?;
        parameter.check(value)?;
        Ok(Self {
            target: target.to_string(),
            value,
        })
    }

    /// The parameter it sets.
    pub fn parameter(&self) -> Result<Parameter> {
        Parameter::parse(name_of(&self.target))
    }

    /// Sets the value on a problem (the target read against its zones, the value checked
    /// against it).
    pub fn apply(&self, problem: &mut Problem) -> Result<()> {
        Target::parse(&self.target, problem)?.apply(problem, self.value)
    }
}

/// The parameter's name in `NAME` or `NAME@ZONE`.
fn name_of(target: &str) -> &str {
    target.split_once('@').map_or(target, |(n, _)| n.trim())
}

impl std::fmt::Display for Assignment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.target, self.value)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn assignments_parse_and_say_what_is_wrong() {
        let a = Assignment::parse("f@top=0.25").expect("parses");
        assert_eq!((a.target.as_str(), a.value), ("f@top", 0.25));
        assert_eq!(a.parameter().ok(), Some(Parameter::Friction));
        assert_eq!(a.to_string(), "f@top=0.25");
        assert_eq!(
            Assignment::parse("gap=1e-5").expect("gap").parameter().ok(),
            Some(Parameter::Gap)
        );
        for (bad, says) in [
            ("f", "NAME=VALUE"),
            ("f=abc", "not a number"),
            ("mu=0.3", "mu"),
            ("f=-1", "non-negative"),
            ("f=20", "[0, 10]"),
        ] {
            let e = Assignment::parse(bad).expect_err(bad).to_string();
            assert!(e.contains(says), "{bad}: {e}");
        }
    }
}
