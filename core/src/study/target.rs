//! A study parameter: one interface parameter ([`crate::Parameter`]: f, gap, v0) on every
//! interface it applies to, or on one zone's ([`crate::interfaces::zone`]), written `f` or `f@ZONE`.

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
                        _ => "no contact interface",
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
