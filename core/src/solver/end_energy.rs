//! The energy balance at the end of a finished single-scale solve, from what its last linear
//! stages left (METHOD §2, §4): the kinetic energy ½ vᵀ M v and strain energy ½ uᵀ K u of each
//! substructure's end state (K u as the march carries it), and the work of the boundary interfaces
//! Σ_m Σ_j A_j (γ F_m + (1 − γ) F_{m−1}) Δt/2 (W_m + W_{m−1}) from the linear stage's trace
//! fields. Each window's last linear stage marched what a replay driven by the converged ŝ
//! marches, in the same blocks ([`crate::post::replay_blocks`]), so these are the end values of
//! [`crate::post::energy`] (same sums in the same order, bit for bit; to rounding for a lane of
//! a batch, whose blocks hold the other lanes' columns) without marching the interval again.
//! Trapezoidal rule only:
//! the dissipative scheme's work needs the trace displacements of every step, which only a
//! replay gives.

use crate::distributed::distribution::Distribution;
use crate::post::{boundary_ranges, boundary_work, kinetic_energy, strain_energy};
use crate::problem::Problem;
use crate::stages::linear_stage::SubState;
use crate::state::InterfaceState;

/// Energies at the last step of a solve (J), summed over the substructures.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct EndEnergy {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Strain energy.
    pub strain: f64,
    /// Work of the boundary interfaces over the interval.
    pub input_work: f64,
}

/// The end energies of a solve whose linear stage output over every step is `fields` and whose
/// substructures ended in `ends` (None for the dissipative scheme, module doc). In a
/// distributed run every rank calls it: each substructure counted on its rank, summed over the
/// ranks.
pub fn end_energy(
    problem: &Problem,
    distribution: &Distribution,
    fields: &InterfaceState,
    ends: &[SubState],
) -> Option<EndEnergy> {
    if !problem.scheme.is_trapezoidal() {
        return None;
    }
    let (n, dt) = (problem.time.steps, problem.time.dt);
    let gamma = problem.scheme.parameters().1;
    let mut per_sub: Vec<f64> = Vec::with_capacity(3 * problem.subs.len());
    for (i, sub) in problem.subs.iter().enumerate() {
        if !distribution.holds_sub(i) {
            // −0: the neutral element of the sum over the ranks
            per_sub.extend([-0.0, -0.0, -0.0]);
            continue;
        }
        let end = &ends[i];
        let h = &fields.subs[i];
        let ranges = boundary_ranges(problem, sub);
        let mut work = 0.0;
        for m in 1..=n {
            let (now, before) = (h.at(m), h.at(m - 1));
            let (f, w) = (&h.f[now.clone()], &h.w[now]);
            let (prev_f, prev_w) = (&h.f[before.clone()], &h.w[before]);
            work += boundary_work(sub, &ranges, gamma, (f, prev_f), |j| {
                0.5 * dt * (w[j] + prev_w[j])
            });
        }
        per_sub.extend([kinetic_energy(sub, &end.v), strain_energy(end), work]);
    }
    if !distribution.is_single() {
        distribution.all_sum(&mut per_sub);
    }
    let mut e = EndEnergy::default();
    for c in per_sub.chunks_exact(3) {
        e.kinetic += c[0];
        e.strain += c[1];
        e.input_work += c[2];
    }
    Some(e)
}
