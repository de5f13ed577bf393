//! The preload's static phase: before the dynamics, the structure is brought to the static
//! equilibrium of its preload (tractions marked `preload`: a clamping force or pressure; contact
//! interferences: negative gaps) by LATIN in statics, one step of
//! [`crate::time::time_scheme::StepCoefficients::STATIC`] (METHOD §4 with S = K + k Bᵀ A B: every
//! substructure sees the search direction on its interfaces, so a floating one needs nothing
//! else; METHOD §5 contact and Coulomb friction on displacement jumps). The converged
//! displacement and interface tractions of each substructure ([`crate::substructure::Prestress`],
//! from one more linear stage driven by ŝ, so they are in exact equilibrium) and the gaps the
//! contacts are left with start the dynamics, at rest, with the preload held.

use crate::counters::Instant;
use crate::error::{LopinError, Result};
use crate::interfaces::interface::Law;
use crate::mesh::{dot, Vec3};
use crate::post;
use crate::problem::{Problem, StaticState};
use crate::substructure::Prestress;
use crate::{Settings, Solver};

/// What the static phase took.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreloadReport {
    /// LATIN iterations.
    pub iterations: usize,
    /// Final error indicator η.
    pub eta: f64,
    /// The static search direction k (Pa/m).
    pub k: f64,
    /// Wall time (s).
    pub seconds: f64,
}

/// The search direction of statics, a stiffness per area (Pa/m): the mean Young's modulus of
/// the materials in use over the size of one substructure (the model's diameter over the cube
/// root of the substructure count).
pub fn static_k(p: &Problem) -> f64 {
    let mut used: Vec<usize> = p.subs.iter().map(|s| s.material_id).collect();
    used.sort_unstable();
    used.dedup();
    let young = used
        .iter()
        .map(|&i| p.materials[i].material.young)
        .sum::<f64>()
        / used.len().max(1) as f64;
    let size = p.diameter() / (p.subs.len().max(1) as f64).cbrt();
    young / size
}

/// The tolerance of the static phase: a hundredth of the run's, so the state the dynamics start
/// from is not what limits their accuracy.
pub fn static_tolerance(settings: &Settings) -> f64 {
    0.01 * settings.tol
}

/// Solves the static problem of `problem`'s preload ([`Problem::statics`]) and starts its
/// dynamics from that equilibrium ([`Problem::set_prestress`]). An unconverged static phase is an
/// error saying how far it got.
pub fn prestress(problem: &mut Problem, settings: &Settings) -> Result<PreloadReport> {
    let clock = Instant::now();
    let statics = problem.statics();
    let k = static_k(&statics);
    let static_settings = Settings {
        k,
        tol: static_tolerance(settings),
        window: None,
        two_scale: false,
        ..*settings
    };
    let mut solver = Solver::new(statics, static_settings)?;
    let sol = solver.solve(None)?;
    let p = solver.problem();
    // each substructure's displacement and tractions at the static step, in equilibrium
    let mut subs = Vec::with_capacity(p.subs.len());
    for i in 0..p.subs.len() {
        let mut state = Prestress {
            displacement: Vec::new(),
            traction: Vec::new(),
        };
        post::replay(&solver, &sol, i, 1, &mut |m, st, f, _| {
            if m == 1 {
                state.displacement.clone_from(&st.u);
                state.traction = f.to_vec();
            }
        });
        subs.push(state);
    }
    // the gap each contact node is left with: g0 + n·([u] of the two sides)
    let gaps: Vec<Option<Vec<f64>>> = p
        .interfaces
        .iter()
        .map(|iface| match &iface.law {
            Law::Contact(c) => {
                let trace = |side: usize, node: usize| -> Vec3 {
                    let s = &iface.sides[side];
                    let d = &subs[s.sub].displacement;
                    match &s.projection {
                        Some(p) => std::array::from_fn(|q| {
                            let (nodes, weights) = p.row_slices(node);
                            nodes
                                .iter()
                                .zip(weights)
                                .map(|(&m, &w)| w * d[3 * m + q])
                                .sum()
                        }),
                        None => {
                            let n = s.nodes[node];
                            std::array::from_fn(|q| d[3 * n + q])
                        }
                    }
                };
                Some(
                    (0..iface.node_count())
                        .map(|i| {
                            let (a, b) = (trace(0, i), trace(1, i));
                            let jump: Vec3 = std::array::from_fn(|q| b[q] - a[q]);
                            c.gap[i] + dot(c.normal[i], jump)
                        })
                        .collect(),
                )
            }
            _ => None,
        })
        .collect();
    // an opened joint is the reason to give, converged or not (it often stalls the phase)
    check_joints_stay_closed(p, &gaps)?;
    if !sol.converged {
        return Err(LopinError::setting(
            "preload",
            format!(
                "the static phase did not converge: η = {:.3e} after {} iterations (tolerance \
                 {:.1e}); raise --max-iter, or loosen --tol",
                sol.eta, sol.iterations, static_settings.tol
            ),
        ));
    }
    let report = PreloadReport {
        iterations: sol.iterations,
        eta: sol.eta,
        k,
        seconds: clock.elapsed().as_secs_f64(),
    };
    problem.set_prestress(Some(StaticState { subs, gaps }));
    Ok(report)
}

/// A preload that opens a contact the scene closes (its gap g0 ≤ 0 somewhere) leaves a joint
/// that holds nothing: refused, naming the interface and how far it opened.
fn check_joints_stay_closed(p: &Problem, gaps: &[Option<Vec<f64>>]) -> Result<()> {
    let size = p.diameter();
    for (iface, gap) in p.interfaces.iter().zip(gaps) {
        let (Law::Contact(c), Some(gap)) = (&iface.law, gap) else {
            continue;
        };
        let closed_before = c.gap.iter().any(|&g| g <= 0.0);
        let least = gap.iter().copied().fold(f64::INFINITY, f64::min);
        if closed_before && least > 1e-9 * size {
            return Err(LopinError::setting(
                "preload",
                format!(
                    "the preload opens contact `{}`: after the static phase its gap is at least \
                     {least:.3e} m everywhere; a clamping preload pushes the parts together \
                     (check the sign of its pressure or traction)",
                    iface.name
                ),
            ));
        }
    }
    Ok(())
}
