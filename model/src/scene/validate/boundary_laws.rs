//! The laws a `[[boundary]]` entry prescribes on each dof of its face or surface (METHOD §5,
//! boundary interfaces): a velocity, a traction or an acceleration (a velocity from rest
//! integrated from it) per component with its time function (a ramp, a standard pulse or a table
//! of points), a load along the faces' normal (a pressure), or a clamp.

use crate::interfaces::interface::{BoundaryDof, BoundaryLoad, DofLaw};
use crate::scene::spec::{BoundarySpec, ComponentSpec};
#[cfg(feature = "shock")]
use crate::time::time_function::PulseKind;
use crate::time::time_function::{Shape, TimeFunction};

/// What a boundary prescribes: laws per component, or a load along the faces' normal; or
/// (field, reason).
pub fn boundary_dofs(bc: &BoundarySpec) -> std::result::Result<BoundaryLoad, (String, String)> {
    let load = prescribed(bc)?;
    if bc.preload {
        return preloaded(bc, load);
    }
    Ok(load)
}

/// A preload boundary's load: tractions only, constant (applied in the static phase, held
/// from t₀).
fn preloaded(
    bc: &BoundarySpec,
    load: BoundaryLoad,
) -> std::result::Result<BoundaryLoad, (String, String)> {
    let specs = bc
        .components()
        .into_iter()
        .chain([("normal", &bc.normal)])
        .filter_map(|(axis, c)| c.as_ref().map(|c| (axis, c)));
    for (axis, c) in specs {
        let shaped =
            c.ramp_time > 0.0 || c.pulse.is_some() || c.table.is_some() || c.table_file.is_some();
        if shaped {
            return Err((
                axis.to_string(),
                "a preload is held constant: give it no ramp, pulse or table".into(),
            ));
        }
    }
    let constant = |f: &TimeFunction| TimeFunction::constant(f.amplitude);
    match load {
        BoundaryLoad::Normal { traction, .. } => Ok(BoundaryLoad::Normal {
            traction: constant(&traction),
            preload: true,
        }),
        BoundaryLoad::Components(dofs) => dofs
            .into_iter()
            .map(|d| match &d.law {
                DofLaw::Traction(f) => Ok(BoundaryDof {
                    law: DofLaw::Traction(constant(f)),
                    preload: true,
                    ..d
                }),
                DofLaw::Velocity(_) => Err((
                    if bc.clamped {
                        "clamped".to_string()
                    } else {
                        ["x", "y", "z"][d.component].to_string()
                    },
                    "a preload is a static load: give a `traction` (or `normal = { pressure = … }`), \
                     not a velocity or an acceleration"
                        .into(),
                )),
            })
            .collect::<std::result::Result<Vec<_>, _>>()
            .map(BoundaryLoad::Components),
    }
}

/// The laws a boundary prescribes, before a preload makes them static.
fn prescribed(bc: &BoundarySpec) -> std::result::Result<BoundaryLoad, (String, String)> {
    let comps = bc.components();
    let any_component = comps.iter().any(|(_, c)| c.is_some());
    if let Some((axis, _)) = comps
        .iter()
        .find(|(_, c)| c.as_ref().is_some_and(|c| c.pressure.is_some()))
    {
        return Err((
            format!("{axis}.pressure"),
            "a pressure acts along the faces' normal: give it as `normal = { pressure = … }`"
                .into(),
        ));
    }
    if let Some(n) = &bc.normal {
        if bc.clamped || any_component {
            return Err((
                "normal".into(),
                "a `normal` load cannot be combined with clamped, x, y or z".into(),
            ));
        }
        return normal_load(n).map_err(|(key, r)| match key {
            "" => ("normal".to_string(), r),
            key => (format!("normal.{key}"), r),
        });
    }
    if bc.clamped {
        if any_component {
            return Err((
                "clamped".into(),
                "clamped = true cannot be combined with x, y or z".into(),
            ));
        }
        return Ok(BoundaryLoad::Components(
            (0..3)
                .map(|component| {
                    BoundaryDof::new(component, DofLaw::Velocity(TimeFunction::constant(0.0)))
                })
                .collect(),
        ));
    }
    let mut dofs = Vec::new();
    for (component, (axis, c)) in comps.into_iter().enumerate() {
        let Some(c) = c else { continue };
        let law = component_law(c).map_err(|(key, r)| match key {
            "" => (axis.to_string(), r),
            key => (format!("{axis}.{key}"), r),
        })?;
        dofs.push(BoundaryDof::new(component, law));
    }
    if dofs.is_empty() {
        return Err((
            "x".into(),
            "a boundary must prescribe at least one component (or clamped = true, or a \
             `normal` load)"
                .into(),
        ));
    }
    Ok(BoundaryLoad::Components(dofs))
}

/// A `normal` load: a pressure p (the traction −p along the outward normal) or a traction, with
/// its time function; errors as [`component_law`]'s.
fn normal_load(c: &ComponentSpec) -> std::result::Result<BoundaryLoad, (&'static str, String)> {
    if c.velocity.is_some() || c.acceleration.is_some() {
        return Err((
            "",
            "a `normal` load is a `pressure` or a `traction`, not a velocity or an acceleration"
                .into(),
        ));
    }
    let traction = match (c.pressure, c.traction) {
        (Some(p), None) if p.is_finite() => -p,
        (None, Some(t)) if t.is_finite() => t,
        (Some(_), Some(_)) => {
            return Err(("", "give either `pressure` or `traction`, not both".into()))
        }
        (None, None) => return Err(("", "give `pressure` or `traction`".into())),
        _ => return Err(("", "value must be finite".into())),
    };
    Ok(BoundaryLoad::Normal {
        traction: TimeFunction {
            amplitude: traction,
            shape: shape(c)?,
        },
        preload: false,
    })
}

/// A component's law, or (the key at fault, empty for the component itself; the reason).
fn component_law(c: &ComponentSpec) -> std::result::Result<DofLaw, (&'static str, String)> {
    let f = |amplitude: f64| -> std::result::Result<TimeFunction, (&'static str, String)> {
        Ok(TimeFunction {
            amplitude,
            shape: shape(c)?,
        })
    };
    match (c.velocity, c.traction, c.acceleration) {
        (Some(v), None, None) if v.is_finite() => Ok(DofLaw::Velocity(f(v)?)),
        (None, Some(t), None) if t.is_finite() => Ok(DofLaw::Traction(f(t)?)),
        (None, None, Some(a)) if a.is_finite() => Ok(DofLaw::Velocity(
            TimeFunction::from_acceleration(a, shape(c)?),
        )),
        (None, None, None) => Err(("", "give `velocity`, `traction` or `acceleration`".into())),
        (v, t, a) if [v, t, a].iter().filter(|x| x.is_some()).count() > 1 => Err((
            "",
            "give one of `velocity`, `traction` and `acceleration`, not several".into(),
        )),
        _ => Err(("", "value must be finite".into())),
    }
}

/// The shape of a component's time function: its ramp, pulse or table, checked; errors as
/// [`component_law`]'s.
fn shape(c: &ComponentSpec) -> std::result::Result<Shape, (&'static str, String)> {
    if !(c.ramp_time.is_finite() && c.ramp_time >= 0.0) {
        return Err((
            "",
            format!(
                "ramp_time must be a non-negative number, got {:?}",
                c.ramp_time
            ),
        ));
    }
    #[cfg(feature = "shock")]
    if let Some(shape) = pulse_or_table(c)? {
        return Ok(shape);
    }
    Ok(Shape::Ramp {
        profile: c.ramp,
        time: c.ramp_time,
    })
}

/// A component's pulse or table, checked (None: it has neither, and follows its ramp).
#[cfg(feature = "shock")]
fn pulse_or_table(c: &ComponentSpec) -> std::result::Result<Option<Shape>, (&'static str, String)> {
    let table = c.table.is_some() || c.table_file.is_some();
    let given = [
        (c.ramp_time > 0.0, "ramp_time"),
        (c.pulse.is_some(), "pulse"),
        (table, "table"),
    ];
    let named: Vec<&str> = given.iter().filter(|g| g.0).map(|g| g.1).collect();
    if named.len() > 1 {
        return Err((
            "",
            format!(
                "give one time function: `{}` and `{}` both describe it",
                named[0], named[1]
            ),
        ));
    }
    if c.pulse.is_none() {
        for (key, v) in [("duration", c.duration), ("rise", c.rise)] {
            if v.is_some() {
                return Err((
                    key,
                    format!("`{key}` is a pulse's: give `pulse` too, or remove it"),
                ));
            }
        }
    }
    if let Some(kind) = c.pulse {
        return pulse(kind, c.duration, c.rise).map(Some);
    }
    if table {
        return match &c.table {
            Some(points) => check_table(points)
                .map(|()| Some(Shape::Table(points.clone().into())))
                .map_err(|r| ("table", r)),
            None => Err((
                "table_file",
                format!(
                    "`{}` was not read: only a scene file reads its tables (give the points \
                     inline as `table`)",
                    c.table_file.as_deref().unwrap_or_default()
                ),
            )),
        };
    }
    Ok(None)
}

#[cfg(feature = "shock")]
/// A pulse of `kind`, its duration and (a trapezoid's) rise checked.
fn pulse(
    kind: PulseKind,
    duration: Option<f64>,
    rise: Option<f64>,
) -> std::result::Result<Shape, (&'static str, String)> {
    let name = kind.name();
    let Some(duration) = duration else {
        return Err((
            "duration",
            format!("a {name} pulse needs its `duration` (s)"),
        ));
    };
    if !(duration.is_finite() && duration > 0.0) {
        return Err(("duration", format!("must be positive, got {duration:?}")));
    }
    let rise = match (kind, rise) {
        (PulseKind::Trapezoid, None) => {
            return Err((
                "rise",
                "a trapezoid pulse needs its rise (and fall) time (s)".into(),
            ))
        }
        (PulseKind::Trapezoid, Some(r)) if !(r.is_finite() && r > 0.0 && r <= duration / 2.0) => {
            return Err((
                "rise",
                format!(
                    "must lie in (0, duration / 2] = (0, {:e}] s, got {r:?}",
                    duration / 2.0
                ),
            ))
        }
        (PulseKind::Trapezoid, Some(r)) => r,
        (_, Some(_)) => {
            return Err((
                "rise",
                format!("a trapezoid pulse's, not a {name}'s: remove it"),
            ))
        }
        (_, None) => 0.0,
    };
    Ok(Shape::Pulse {
        kind,
        duration,
        rise,
    })
}

/// A table's points: at least one, finite, times from 0 and strictly increasing.
#[cfg(feature = "shock")]
fn check_table(points: &[[f64; 2]]) -> std::result::Result<(), String> {
    if points.is_empty() {
        return Err("table: give at least one [t, value] point".into());
    }
    for (i, &[t, v]) in points.iter().enumerate() {
        if !(t.is_finite() && v.is_finite()) {
            return Err(format!("table[{i}] = [{t:?}, {v:?}]: not a finite number"));
        }
        if t < 0.0 {
            return Err(format!("table[{i}]: time {t:e} s is before 0"));
        }
        if i > 0 && t <= points[i - 1][0] {
            return Err(format!(
                "table[{i}]: time {t:e} s is not after the previous point's {:e} s (times must \
                 increase)",
                points[i - 1][0]
            ));
        }
    }
    Ok(())
}
