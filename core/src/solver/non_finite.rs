//! Where a non-finite value first appeared in an iteration, and the inputs that feed that place:
//! a non-finite η (METHOD §6) stops the solve at once, and this names the stage (local stage
//! ŝ, METHOD §5, or linear stage s, METHOD §4), the interface or substructure, the step and the
//! scene inputs behind it, instead of letting NaN reach a plot or a file.

use crate::interfaces::interface::{DofLaw, Law};
use crate::problem::Problem;
use crate::state::{InterfaceState, TraceHistory};

/// The first step in `m0..=m1` at which `h` holds a non-finite F or W: (step, "F" or "W", value).
fn first_bad(h: &TraceHistory, (m0, m1): (usize, usize)) -> Option<(usize, &'static str, f64)> {
    if !h.is_present() {
        // held by another rank, which reports it
        return None;
    }
    (m0..=m1).find_map(|m| {
        let r = h.at(m);
        let f = h.f[r.clone()].iter().find(|x| !x.is_finite());
        let w = h.w[r].iter().find(|x| !x.is_finite());
        f.map(|&x| (m, "F", x)).or(w.map(|&x| (m, "W", x)))
    })
}

/// The inputs of an interface's law, as the scene gave them.
fn law_inputs(problem: &Problem, i: usize) -> String {
    let iface = &problem.interfaces[i];
    match &iface.law {
        Law::Perfect => "a perfect interface (no inputs of its own)".into(),
        Law::Contact(c) => {
            let (lo, hi) = c
                .gap
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &g| {
                    (a.min(g), b.max(g))
                });
            format!(
                "contact with friction f = {}, initial gaps {lo:e} … {hi:e} m",
                c.friction
            )
        }
        Law::Boundary(dofs) => {
            let mut laws: Vec<String> = dofs
                .iter()
                .map(|d| {
                    let axis = ["x", "y", "z"][d.component];
                    match &d.law {
                        DofLaw::Velocity(f) => {
                            format!("{axis} velocity {:?} m/s ({})", f.amplitude, f.describe())
                        }
                        DofLaw::Traction(f) => {
                            format!("{axis} traction {:?} Pa ({})", f.amplitude, f.describe())
                        }
                    }
                })
                .collect();
            laws.sort();
            laws.dedup();
            format!("boundary condition: {}", laws.join(", "))
        }
    }
}

/// The inputs of a substructure's linear stage.
fn substructure_inputs(problem: &Problem, s: usize, k: f64) -> String {
    let sub = &problem.subs[s];
    let m = &sub.material;
    let material = &problem.materials[sub.material_id].name;
    format!(
        "body `{}` of material `{material}` (E = {:e} Pa, ν = {}, ρ = {:e} kg/m³), initial \
         velocity {:?} m/s, dt = {:e} s, k = {:e} Pa·s/m",
        sub.body, m.young, m.poisson, m.density, sub.initial_velocity, problem.time.dt, k
    )
}

/// Describes where the first non-finite value of an iteration appeared: ŝ of the local stage
/// first (it feeds the linear stage), then s of the linear stage, the earliest step first.
pub(crate) fn describe(
    problem: &Problem,
    k: f64,
    iteration: usize,
    s_new: &InterfaceState,
    hats: &[Vec<TraceHistory>],
    window: (usize, usize),
) -> String {
    let t = |m: usize| problem.time.time(m);
    let local = hats
        .iter()
        .enumerate()
        .flat_map(|(i, sides)| sides.iter().enumerate().map(move |(k, h)| (i, k, h)))
        .filter_map(|(i, side, h)| first_bad(h, window).map(|b| (b, i, side)))
        .min_by_key(|((m, _, _), _, _)| *m);
    if let Some(((m, what, x), i, side)) = local {
        let iface = &problem.interfaces[i];
        let sub = &problem.subs[iface.sides[side].sub].name;
        return format!(
            "{what}̂ = {x} in the local stage at iteration {iteration}, step {m} (t = {:e} s), on \
             interface `{}` (side of substructure `{sub}`); its inputs: {}",
            t(m),
            iface.name,
            law_inputs(problem, i)
        );
    }
    let linear = s_new
        .subs
        .iter()
        .enumerate()
        .filter_map(|(s, h)| first_bad(h, window).map(|b| (b, s)))
        .min_by_key(|((m, _, _), _)| *m);
    if let Some(((m, what, x), s)) = linear {
        return format!(
            "{what} = {x} in the linear stage at iteration {iteration}, step {m} (t = {:e} s), in \
             substructure `{}`; its inputs: {}",
            t(m),
            problem.subs[s].name,
            substructure_inputs(problem, s, k)
        );
    }
    let largest = s_new
        .subs
        .iter()
        .flat_map(|h| h.f.iter().chain(&h.w))
        .fold(0.0f64, |a, &x| a.max(x.abs()));
    format!(
        "the error indicator η overflowed at iteration {iteration} (interface fields reach \
         {largest:e}): the scene's velocities, tractions or k = {k:e} Pa·s/m are too large"
    )
}
