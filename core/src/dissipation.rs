//! The work the contact interfaces dissipate over the interval, from ŝ (METHOD §5, with the work
//! rule of METHOD §2): on every contact node and step,
//!
//!   ΔD = A ((1 − γ) F̂₁,m−1 + γ F̂₁,m) · Δ[u],  [u] = u₂ − u₁ (the displacement jump of the
//!   scheme's update of the velocity jump Ŵ₂ − Ŵ₁),
//!
//! split into its tangential part (friction work, ≥ 0 under Coulomb's law) and its normal part
//! (0 for the persistent contact law once the gap is closed). With the energy balance of
//! [`crate::post::energy`], input work − (kinetic + strain energy) at the end equals the two
//! together on a converged solve: the conservation law the tests check. A study's quantity of
//! interest.

use crate::interfaces::interface::Law;
use crate::mesh::{dot, Vec3};
use crate::solver::{Solution, Solver};

/// Work dissipated by the contact interfaces over the interval (J).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactWork {
    /// Tangential part: the work of friction.
    pub friction: f64,
    /// Normal part.
    pub normal: f64,
}

/// The contact work of a solution. In a distributed run every rank calls it: each interface is
/// computed on its rank and the totals are summed over the ranks in interface order, the same
/// bits as on one machine.
pub fn contact_work(solver: &Solver, sol: &Solution) -> ContactWork {
    let p = solver.problem();
    let dist = solver.distribution();
    let step = p.step_coefficients();
    let gamma = p.scheme.parameters().1;
    let n = p.time.steps;
    let mut per_interface: Vec<f64> = Vec::new();
    for (k, iface) in p.interfaces.iter().enumerate() {
        let Law::Contact(c) = &iface.law else {
            continue;
        };
        if !dist.holds_interface(k) {
            // −0: the neutral element of the sum over the ranks
            per_interface.extend([-0.0, -0.0]);
            continue;
        }
        let (h1, h2) = (&sol.hats[k][0], &sol.hats[k][1]);
        let nn = iface.node_count();
        let mut work = ContactWork::default();
        let mut prev_jump = vec![[0.0; 3]; nn];
        let mut prev_force = vec![[0.0; 3]; nn];
        let mut prev_accel = vec![[0.0; 3]; nn];
        for m in 0..=n {
            let r = h1.at(m);
            for i in 0..nn {
                let at = |x: &[f64]| -> Vec3 { std::array::from_fn(|q| x[r.start + 3 * i + q]) };
                let force = at(&h1.f);
                let (w1, w2) = (at(&h1.w), at(&h2.w));
                let jump: Vec3 = std::array::from_fn(|q| w2[q] - w1[q]);
                if m > 0 {
                    let mut du = [0.0; 3];
                    for q in 0..3 {
                        (du[q], prev_accel[i][q]) =
                            step.advance(0.0, prev_jump[i][q], prev_accel[i][q], jump[q]);
                    }
                    let nrm = c.normal[i];
                    let mean: Vec3 = std::array::from_fn(|q| {
                        (1.0 - gamma) * prev_force[i][q] + gamma * force[q]
                    });
                    let (fn_, un) = (dot(mean, nrm), dot(du, nrm));
                    let area = iface.area[3 * i];
                    work.normal += area * fn_ * un;
                    work.friction += area * (dot(mean, du) - fn_ * un);
                }
                prev_jump[i] = jump;
                prev_force[i] = force;
            }
        }
        per_interface.extend([work.friction, work.normal]);
    }
    dist.all_sum(&mut per_interface);
    let mut total = ContactWork::default();
    for pair in per_interface.chunks_exact(2) {
        total.friction += pair[0];
        total.normal += pair[1];
    }
    total
}
