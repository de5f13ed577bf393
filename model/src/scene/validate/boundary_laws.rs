//! The laws a `[[boundary]]` entry prescribes on each dof of its face or surface (METHOD §5,
//! boundary interfaces): a velocity or a traction per component with its ramp, or a clamp.

use crate::interfaces::interface::{BoundaryDof, DofLaw};
use crate::scene::spec::{BoundarySpec, ComponentSpec};
use crate::time::time_function::TimeFunction;

/// The prescribed dofs of a boundary, or (field, reason).
pub fn boundary_dofs(bc: &BoundarySpec) -> std::result::Result<Vec<BoundaryDof>, (String, String)> {
    let comps = bc.components();
    if bc.clamped {
        if comps.iter().any(|(_, c)| c.is_some()) {
            return Err((
                "clamped".into(),
                "clamped = true cannot be combined with x, y or z".into(),
            ));
        }
        return Ok((0..3)
            .map(|component| BoundaryDof {
                component,
                law: DofLaw::Velocity(TimeFunction::constant(0.0)),
            })
            .collect());
    }
    let mut dofs = Vec::new();
    for (component, (axis, c)) in comps.into_iter().enumerate() {
        let Some(c) = c else { continue };
        dofs.push(BoundaryDof {
            component,
            law: component_law(c).map_err(|r| (axis.to_string(), r))?,
        });
    }
    if dofs.is_empty() {
        return Err((
            "x".into(),
            "a boundary must prescribe at least one component (or clamped = true)".into(),
        ));
    }
    Ok(dofs)
}

fn component_law(c: &ComponentSpec) -> std::result::Result<DofLaw, String> {
    if !(c.ramp_time.is_finite() && c.ramp_time >= 0.0) {
        return Err(format!(
            "ramp_time must be a non-negative number, got {:?}",
            c.ramp_time
        ));
    }
    let f = |amplitude: f64| TimeFunction {
        amplitude,
        ramp: c.ramp,
        ramp_time: c.ramp_time,
    };
    match (c.velocity, c.traction) {
        (Some(v), None) if v.is_finite() => Ok(DofLaw::Velocity(f(v))),
        (None, Some(t)) if t.is_finite() => Ok(DofLaw::Traction(f(t))),
        (Some(_), Some(_)) => Err("give either `velocity` or `traction`, not both".into()),
        (None, None) => Err("give `velocity` or `traction`".into()),
        _ => Err("value must be finite".into()),
    }
}
