//! Agreement between a converged LATIN solution and the monolithic reference, the yardstick of
//! every LATIN run: nodal velocities of every substructure at every step, and step-averaged interface
//! forces, both as max differences over space–time normalized by the reference's max magnitude.
//!
//! Forces are compared per substructure dof as the sum over that dof's interface copies of
//! A F̂ (METHOD §1: one copy per interface; §6: ŝ is the reported interface solution), step
//! averaged (F_m + F_{m−1})/2 (METHOD §2). The sum is what both solvers determine uniquely: where
//! several conditions hold on one dof (a perfect interface meeting a clamp) the share of each is
//! not defined, but their total is the substructure's equilibrium M a + K u.
//!
//! Beside these, the quantities the undamped rule's alternating mode v_m = (−1)^m c cannot touch
//! (METHOD §10): displacements, step-averaged velocities (v_m + v_{m−1})/2, the total
//! energy ½vᵀMv + ½uᵀKu per step (the mode carries kinetic energy, so this one sees what of it
//! is left) and the step-averaged normal force of each contact interface (METHOD §5).

use lopin_core::interfaces::interface::Law;
use lopin_core::post::{contact, energy, replay};
use lopin_core::solver::{Solution, Solver};

use lopin_reference::monolithic::{MonoSolution, Monolithic};

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
    /// max |u_latin − u_ref| / max |u_ref|.
    pub rel_diff_displacement: f64,
    /// max |v̄_latin − v̄_ref| / max |v̄_ref| of the step-averaged velocities.
    pub rel_diff_velocity_avg: f64,
    /// max over steps |E_latin − E_ref| / max E_ref of the total (kinetic + strain) energy.
    pub rel_diff_energy: f64,
    /// max |N_latin − N_ref| / max |N_ref| of the step-averaged normal force of every contact
    /// interface (0 without contact).
    pub rel_diff_contact_force: f64,
    /// Where the step-averaged force differs most: (substructure, dof, step m).
    pub worst_force: (usize, usize, usize),
}

impl Comparison {
    /// Where the largest step-averaged force difference sits, in words: the substructure, the
    /// node's position and component, the step and time, and every interface on that node.
    pub fn describe_worst_force(&self, solver: &Solver) -> String {
        let p = solver.problem();
        let (s, d, m) = self.worst_force;
        let sub = &p.subs[s];
        let node = d / 3;
        let x = sub.mesh.nodes[node];
        let on: Vec<&str> = sub
            .sides
            .iter()
            .filter(|r| {
                p.interfaces[r.interface].sides[r.side]
                    .nodes
                    .contains(&node)
            })
            .map(|r| p.interfaces[r.interface].name.as_str())
            .collect();
        format!(
            "substructure `{}`, node at ({:.3e}, {:.3e}, {:.3e}) m, component {}, step {m} (t = {:.3e} s), on {}",
            sub.name,
            x[0],
            x[1],
            x[2],
            ["x", "y", "z"][d % 3],
            m as f64 * p.time.dt,
            if on.is_empty() { "no interface".to_string() } else { on.join(", ") }
        )
    }
}

/// max |a − b| and max |b| accumulated over pairs of values.
#[derive(Debug, Clone, Copy, Default)]
struct MaxDiff {
    diff: f64,
    scale: f64,
}

impl MaxDiff {
    fn add(&mut self, latin: f64, reference: f64) {
        self.diff = self.diff.max((latin - reference).abs());
        self.scale = self.scale.max(reference.abs());
    }

    fn merge(&mut self, o: MaxDiff) {
        self.diff = self.diff.max(o.diff);
        self.scale = self.scale.max(o.scale);
    }

    /// diff / scale (diff itself when the scale vanishes).
    fn relative(&self) -> f64 {
        if self.scale > 0.0 {
            self.diff / self.scale
        } else {
            self.diff
        }
    }
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
    let (mut du, mut dv_avg) = (MaxDiff::default(), MaxDiff::default());
    for i in 0..p.subs.len() {
        let mut err: f64 = 0.0;
        let (mut u_err, mut v_avg_err) = (MaxDiff::default(), MaxDiff::default());
        // step m − 1 of both, for the averages (replay starts at m = 0, the initial state)
        let mut prev: Option<(Vec<f64>, Vec<f64>)> = None;
        replay(solver, sol, i, steps, &mut |m, st, _, _| {
            let vr = reference.sub_velocity(mono, m, i);
            for (a, b) in st.v.iter().zip(&vr) {
                err = err.max((a - b).abs());
            }
            for (a, b) in st.u.iter().zip(reference.sub_displacement(mono, m, i)) {
                u_err.add(*a, b);
            }
            if let Some((vl, vr_prev)) = &prev {
                for d in 0..st.v.len() {
                    v_avg_err.add(0.5 * (st.v[d] + vl[d]), 0.5 * (vr[d] + vr_prev[d]));
                }
            }
            prev = Some((st.v.clone(), vr));
        });
        dv = dv.max(err);
        du.merge(u_err);
        dv_avg.merge(v_avg_err);
    }
    let mut de = MaxDiff::default();
    let (el, er) = (energy(solver, sol), reference.energy(mono));
    for m in 0..=steps {
        de.add(el.total(m), er.total(m));
    }
    let mut dn = MaxDiff::default();
    let ref_contact = reference.contact(mono);
    for cl in contact(solver, sol) {
        if let Some(cr) = ref_contact.iter().find(|c| c.interface == cl.interface) {
            for (a, b) in cl.normal_force.iter().zip(&cr.normal_force) {
                dn.add(*a, *b);
            }
        }
    }
    for v in &mono.v {
        vmax = v.iter().fold(vmax, |acc, x| acc.max(x.abs()));
    }
    let latin = latin_sub_forces(solver, sol);
    let mut df: f64 = 0.0;
    let mut fmax: f64 = 0.0;
    let mut worst_force = (0, 0, 0);
    let mut prev_ref = reference.sub_forces(mono, 0);
    for m in 1..=steps {
        let now_ref = reference.sub_forces(mono, m);
        for (s, (fr_now, fr_prev)) in now_ref.iter().zip(&prev_ref).enumerate() {
            for d in 0..fr_now.len() {
                let r = 0.5 * (fr_now[d] + fr_prev[d]);
                let l = 0.5 * (latin[m][s][d] + latin[m - 1][s][d]);
                if (l - r).abs() > df {
                    df = (l - r).abs();
                    worst_force = (s, d, m);
                }
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
        rel_diff_displacement: du.relative(),
        rel_diff_velocity_avg: dv_avg.relative(),
        rel_diff_energy: de.relative(),
        rel_diff_contact_force: dn.relative(),
        worst_force,
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
                    let force = iface.area[j] * h.f[r.start + j];
                    match (&iface.law, &side.projection) {
                        // the mortar side: Pᵀ A F̂
                        (_, Some(p)) => {
                            let (nodes, weights) = p.row_slices(j / 3);
                            for (&n, &w) in nodes.iter().zip(weights) {
                                f[3 * n + j % 3] += w * force;
                            }
                        }
                        (Law::Boundary(d), None) => f[3 * side.nodes[j] + d[j].component] += force,
                        _ => f[3 * side.nodes[j / 3] + j % 3] += force,
                    }
                }
            }
        }
    }
    out
}
