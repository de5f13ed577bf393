//! Quantities of the reference solution in the shapes the LATIN post-processing reports
//! (post.rs): energy balance (METHOD §2 identity), contact histories per contact interface
//! (METHOD §5: pressure, gap, slip, step-averaged normal force) and the interface force on every
//! substructure dof, M_E ā + K_E u = Σ_Γ Bᵀ A F (METHOD §2 equilibrium of substructure E, with
//! the inertia acceleration ā_m = (1 − α_m) a_m + α_m a_{m−1} of the scheme: a_m for the
//! trapezoidal rule).

use std::borrow::Cow;

use super::{MonoSolution, Monolithic};
use lopin_model::histories::{ContactHistory, EnergyHistory, Summary};
use lopin_model::interfaces::interface::Law;
use lopin_model::mesh::{dot, Vec3};

impl Monolithic {
    /// The acceleration the equation of motion of step m holds: ā_m = (1 − α_m) a_m + α_m a_{m−1}
    /// (a_m for the trapezoidal rule and at m = 0).
    fn inertia_acceleration<'s>(&self, sol: &'s MonoSolution, m: usize) -> Cow<'s, [f64]> {
        let alpha_m = self.problem.scheme.parameters().0;
        if m == 0 || self.problem.scheme.is_trapezoidal() {
            return Cow::Borrowed(&sol.a[m]);
        }
        sol.a[m]
            .iter()
            .zip(&sol.a[m - 1])
            .map(|(a, ap)| (1.0 - alpha_m) * a + alpha_m * ap)
            .collect()
    }

    /// Kinetic and strain energy, the cumulative work of the boundary conditions and the energy
    /// dissipated by the damping.
    pub fn energy(&self, sol: &MonoSolution) -> EnergyHistory {
        let asm = &self.asm;
        let n = asm.numbering.dofs();
        let steps = sol.v.len() - 1;
        let dt = self.problem.time.dt;
        let mut boundary = vec![false; n];
        for (g, p) in asm.prescribed.iter().enumerate() {
            boundary[g] = p.is_some();
        }
        for &(g, _, _) in &asm.tractions {
            boundary[g] = true;
        }
        let mut e = EnergyHistory {
            kinetic: vec![0.0; steps + 1],
            strain: vec![0.0; steps + 1],
            input_work: vec![0.0; steps + 1],
            damping: vec![0.0; steps + 1],
        };
        let mut prev_b = vec![0.0; n];
        let mut ku = vec![0.0; n];
        let mut cv = vec![0.0; n];
        let mut prev_cv = vec![0.0; n];
        let trapezoidal = self.problem.scheme.is_trapezoidal();
        let gamma = self.problem.scheme.parameters().1;
        for m in 0..=steps {
            let (u, v, a) = (&sol.u[m], &sol.v[m], &self.inertia_acceleration(sol, m));
            e.kinetic[m] = 0.5 * (0..n).map(|g| asm.mass[g] * v[g] * v[g]).sum::<f64>();
            asm.stiffness.mul_into(u, &mut ku);
            e.strain[m] = 0.5 * dot_slices(u, &ku);
            if let Some(c) = &asm.damping {
                c.mul_into(v, &mut cv);
            }
            // boundary force = M a + C v + K u − contact forces, on boundary dofs
            let mut b: Vec<f64> = (0..n)
                .map(|g| {
                    if boundary[g] {
                        asm.mass[g] * a[g] + cv[g] + ku[g]
                    } else {
                        0.0
                    }
                })
                .collect();
            for (p, pair) in asm.pairs.iter().enumerate() {
                let f1 = side1_force(pair.frame, sol.pair_forces[m][p]);
                for c in 0..3 {
                    if boundary[3 * pair.a + c] {
                        b[3 * pair.a + c] -= f1[c];
                    }
                    for &(node, w) in &pair.across {
                        if boundary[3 * node + c] {
                            b[3 * node + c] += w * f1[c];
                        }
                    }
                }
            }
            if m > 0 {
                let (vp, up) = (&sol.v[m - 1], &sol.u[m - 1]);
                // the scheme's work of a force history x on the dofs g
                let work = |x: &[f64], xp: &[f64], g: usize| {
                    if trapezoidal {
                        0.25 * dt * (x[g] + xp[g]) * (v[g] + vp[g])
                    } else {
                        (gamma * x[g] + (1.0 - gamma) * xp[g]) * (u[g] - up[g])
                    }
                };
                let dw: f64 = (0..n)
                    .filter(|&g| boundary[g])
                    .map(|g| work(&b, &prev_b, g))
                    .sum();
                e.input_work[m] = e.input_work[m - 1] + dw;
                let dd: f64 = if asm.damping.is_some() {
                    (0..n).map(|g| work(&cv, &prev_cv, g)).sum()
                } else {
                    0.0
                };
                e.damping[m] = e.damping[m - 1] + dd;
            }
            prev_b = b;
            std::mem::swap(&mut prev_cv, &mut cv);
        }
        e
    }

    /// Contact histories of every contact interface (the force of a pair is shared among its
    /// copies in proportion to area: one pressure per pair).
    pub fn contact(&self, sol: &MonoSolution) -> Vec<ContactHistory> {
        let steps = sol.v.len() - 1;
        let mut out: Vec<ContactHistory> = self
            .problem
            .interfaces
            .iter()
            .enumerate()
            .filter(|(_, i)| matches!(i.law, Law::Contact(_)))
            .map(|(k, i)| {
                let nn = i.node_count();
                ContactHistory {
                    interface: k,
                    pressure: vec![vec![0.0; nn]; steps + 1],
                    gap: vec![vec![0.0; nn]; steps + 1],
                    slip: vec![vec![0.0; nn]; steps + 1],
                    normal_force: vec![0.0; steps + 1],
                }
            })
            .collect();
        for (p, pair) in self.asm.pairs.iter().enumerate() {
            let area = pair.area();
            for copy in &pair.copies {
                let Some(h) = out.iter_mut().find(|h| h.interface == copy.interface) else {
                    continue;
                };
                for m in 0..=steps {
                    let pressure = sol.pair_forces[m][p][0] / area;
                    h.pressure[m][copy.node] = pressure;
                    h.gap[m][copy.node] = sol.gaps[m][p];
                    h.slip[m][copy.node] = dot(sol.slips[m][p], sol.slips[m][p]).sqrt();
                    h.normal_force[m] += copy.area * pressure;
                }
            }
        }
        for h in &mut out {
            for m in (1..=steps).rev() {
                h.normal_force[m] = 0.5 * (h.normal_force[m] + h.normal_force[m - 1]);
            }
        }
        out
    }

    /// Energy and contact summary.
    pub fn summary(&self, sol: &MonoSolution) -> Summary {
        Summary::from_histories(&self.energy(sol), &self.contact(sol))
    }

    /// Total interface force on every dof of every substructure at step m:
    /// M_E ā_E + C_E v_E + K_E u_E (C_E = α_E M_E + β_E K_E, the substructure's damping).
    pub fn sub_forces(&self, sol: &MonoSolution, m: usize) -> Vec<Vec<f64>> {
        let inertia = self.inertia_acceleration(sol, m);
        self.problem
            .subs
            .iter()
            .enumerate()
            .map(|(s, sub)| {
                let (u, a) = (self.gather(&sol.u[m], s), self.gather(&inertia, s));
                let d = sub.material.damping;
                // K (u + β v) + M (ā + α v)
                let (u, a) = if d.is_none() {
                    (u, a)
                } else {
                    let v = self.gather(&sol.v[m], s);
                    (
                        u.iter().zip(&v).map(|(u, v)| u + d.beta * v).collect(),
                        a.iter().zip(&v).map(|(a, v)| a + d.alpha * v).collect(),
                    )
                };
                let mut f = vec![0.0; sub.ndof()];
                sub.stiffness.mul_into(&u, &mut f);
                for d in 0..sub.ndof() {
                    f[d] += sub.mass[d] * a[d];
                }
                f
            })
            .collect()
    }

    /// Velocity of every dof of substructure `s` at step m.
    pub fn sub_velocity(&self, sol: &MonoSolution, m: usize, s: usize) -> Vec<f64> {
        self.gather(&sol.v[m], s)
    }

    /// Displacement of every dof of substructure `s` at step m.
    pub fn sub_displacement(&self, sol: &MonoSolution, m: usize, s: usize) -> Vec<f64> {
        self.gather(&sol.u[m], s)
    }

    /// The values of a global field on the dofs of substructure `s`.
    fn gather(&self, x: &[f64], s: usize) -> Vec<f64> {
        (0..self.problem.subs[s].ndof())
            .map(|d| x[self.asm.numbering.dof(s, d)])
            .collect()
    }
}

fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Nodal force on side 1 of a pair in global axes: −P n + T₁ t₁ + T₂ t₂.
fn side1_force(frame: [Vec3; 3], f: [f64; 3]) -> Vec3 {
    std::array::from_fn(|c| -f[0] * frame[0][c] + f[1] * frame[1][c] + f[2] * frame[2][c])
}
