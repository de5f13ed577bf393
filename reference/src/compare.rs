//! Agreement between a converged LATIN solution and the monolithic reference (issue: reference
//! yardstick): nodal velocities of every substructure at every step, and step-averaged interface
//! forces, both as max differences over space–time normalized by the reference's max magnitude.
//!
//! Forces are compared per substructure dof as the sum over that dof's interface copies of
//! A F̂ (METHOD §1: one copy per interface; §6: ŝ is the reported interface solution), step
//! averaged (F_m + F_{m−1})/2 (METHOD §2). The sum is what both solvers determine uniquely: where
//! several conditions hold on one dof (a perfect interface meeting a clamp) the share of each is
//! not defined, but their total is the substructure's equilibrium M a + K u.

use lopin_core::interface::Law;
use lopin_core::post::replay;
use lopin_core::solver::{Solution, Solver};

use crate::monolithic::{MonoSolution, Monolithic};

/// Relative differences LATIN − reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Comparison {
    /// max |v_latin − v_ref| / max |v_ref| over all dofs and steps.
    pub rel_diff_velocity: f64,
    /// max |F_latin − F_ref| / max |F_ref| of the step-averaged interface forces.
    pub rel_diff_force: f64,
    /// max |v_ref|.
    pub max_velocity: f64,
    /// max |F_ref| (N).
    pub max_force: f64,
}

/// Compares a converged LATIN solution with the reference solution of the same problem.
pub fn compare(
    solver: &Solver,
    sol: &Solution,
    reference: &Monolithic,
    mono: &MonoSolution,
) -> Comparison {
    let p = solver.problem();
    let steps = p.time.steps;
    let mut dv: f64 = 0.0;
    let mut vmax: f64 = 0.0;
    for (i, _) in p.subs.iter().enumerate() {
        let mut err: f64 = 0.0;
        replay(solver, sol, i, steps, &mut |m, st, _, _| {
            let vr = reference.sub_velocity(mono, m, i);
            for (a, b) in st.v.iter().zip(&vr) {
                err = err.max((a - b).abs());
            }
        });
        dv = dv.max(err);
    }
    for v in &mono.v {
        vmax = v.iter().fold(vmax, |acc, x| acc.max(x.abs()));
    }
    let latin = latin_sub_forces(solver, sol);
    let mut df: f64 = 0.0;
    let mut fmax: f64 = 0.0;
    let mut prev_ref = reference.sub_forces(mono, 0);
    for m in 1..=steps {
        let now_ref = reference.sub_forces(mono, m);
        for (s, (fr_now, fr_prev)) in now_ref.iter().zip(&prev_ref).enumerate() {
            for d in 0..fr_now.len() {
                let r = 0.5 * (fr_now[d] + fr_prev[d]);
                let l = 0.5 * (latin[m][s][d] + latin[m - 1][s][d]);
                df = df.max((l - r).abs());
                fmax = fmax.max(r.abs());
            }
        }
        prev_ref = now_ref;
    }
    Comparison {
        rel_diff_velocity: if vmax > 0.0 { dv / vmax } else { dv },
        rel_diff_force: if fmax > 0.0 { df / fmax } else { df },
        max_velocity: vmax,
        max_force: fmax,
    }
}

/// Σ over interface copies of A F̂ per substructure dof, per step: `[m][sub][dof]`.
fn latin_sub_forces(solver: &Solver, sol: &Solution) -> Vec<Vec<Vec<f64>>> {
    let p = solver.problem();
    let steps = p.time.steps;
    let mut out: Vec<Vec<Vec<f64>>> = (0..=steps)
        .map(|_| p.subs.iter().map(|s| vec![0.0; s.ndof()]).collect())
        .collect();
    for (k, iface) in p.interfaces.iter().enumerate() {
        for (side_no, side) in iface.sides.iter().enumerate() {
            let h = &sol.hats[k][side_no];
            for (m, per_sub) in out.iter_mut().enumerate() {
                let r = h.at(m);
                let f = &mut per_sub[side.sub];
                for j in 0..iface.len {
                    let dof = match &iface.law {
                        Law::Boundary(d) => 3 * side.nodes[j] + d[j].component,
                        _ => 3 * side.nodes[j / 3] + j % 3,
                    };
                    f[dof] += iface.area[j] * h.f[r.start + j];
                }
            }
        }
    }
    out
}
