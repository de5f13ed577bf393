//! Post-processing, computed only when asked: the fields of a converged solution come from one
//! more linear stage driven by ŝ (METHOD §6 "at convergence"), replayed per substructure up to the
//! step wanted. Energies use the exact discrete identity of METHOD §2; interface forces are
//! reported as step averages (F_m + F_{m−1})/2 (METHOD §2, §10 "force ringing").

use crate::counters::Instant;
use crate::hex8;
use crate::interface::Law;
use crate::linear_stage::{linear_stage, LinearInput, LinearWork, StepVisitor};
use crate::mesh::{dot, Element, Vec3};
use crate::par;
use crate::solver::{Solution, Solver};
use crate::state::TraceHistory;
use crate::substructure::Substructure;

/// Replays the linear stage of substructure `i` driven by ŝ over steps 1..=until, calling
/// `visit(m, state, F, W)` at m = 0 (initial state) and at every step.
pub fn replay(
    solver: &Solver,
    sol: &Solution,
    i: usize,
    until: usize,
    visit: &mut StepVisitor<'_>,
) {
    let p = solver.problem();
    let sub = &p.subs[i];
    let factor = solver.factor(i);
    let mut work = LinearWork::new(sub, factor, p.time.dt);
    let mut out = TraceHistory::zeros(sub.trace_len(), p.time.steps);
    let h0 = &sol.state.subs[i];
    visit(0, &work.state, &h0.f[h0.at(0)], &h0.w[h0.at(0)]);
    let until = until.min(p.time.steps);
    if until == 0 {
        return;
    }
    let input = LinearInput {
        interfaces: &p.interfaces,
        hats: &sol.hats,
        k: solver.settings().k,
        dt: p.time.dt,
        steps: (1, until),
    };
    linear_stage(sub, factor, &mut work, &input, &mut out, Some(visit));
}

/// Nodal velocities of every substructure at every step of a converged solution: `[m][sub][dof]`.
pub fn velocity_history(solver: &Solver, sol: &Solution) -> Vec<Vec<Vec<f64>>> {
    let p = solver.problem();
    let n = p.time.steps;
    let mut out = vec![vec![Vec::new(); p.subs.len()]; n + 1];
    for i in 0..p.subs.len() {
        replay(solver, sol, i, n, &mut |m, st, _, _| {
            out[m][i].clone_from(&st.v)
        });
    }
    out
}

/// Displacement and velocity of one substructure at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct SubFields {
    /// Nodal displacements (node-major).
    pub u: Vec<f64>,
    /// Nodal velocities (node-major).
    pub v: Vec<f64>,
}

/// u and v of every substructure at step m.
pub fn fields_at(solver: &Solver, sol: &Solution, m: usize) -> Vec<SubFields> {
    let t = Instant::now();
    let n = solver.problem().subs.len();
    let out = par::map_range(n, |i| {
        let mut f = SubFields {
            u: Vec::new(),
            v: Vec::new(),
        };
        replay(solver, sol, i, m, &mut |step, st, _, _| {
            if step == m {
                f.u.clone_from(&st.u);
                f.v.clone_from(&st.v);
            }
        });
        f
    });
    solver.counters().add_post(t.elapsed().as_secs_f64());
    out
}

/// u and v of every substructure at every step, `[sub][m]`, m = 0..=N: one replay per
/// substructure (what exports need; [`fields_at`] replays up to one step).
pub fn history(solver: &Solver, sol: &Solution) -> Vec<Vec<SubFields>> {
    let t = Instant::now();
    let p = solver.problem();
    let n = p.time.steps;
    let out = par::map_range(p.subs.len(), |i| {
        let mut steps = Vec::with_capacity(n + 1);
        replay(solver, sol, i, n, &mut |_, st, _, _| {
            steps.push(SubFields {
                u: st.u.clone(),
                v: st.v.clone(),
            });
        });
        steps
    });
    solver.counters().add_post(t.elapsed().as_secs_f64());
    out
}

/// Element von Mises stress (at the element centre) of substructure `i` for displacements `u`.
pub fn von_mises(solver: &Solver, i: usize, u: &[f64]) -> Vec<f64> {
    element_stress(solver, i, u)
        .iter()
        .map(hex8::von_mises)
        .collect()
}

/// Element stress tensors (Voigt xx, yy, zz, xy, yz, zx) of substructure `i`.
pub fn element_stress(solver: &Solver, i: usize, u: &[f64]) -> Vec<[f64; 6]> {
    let sub = &solver.problem().subs[i];
    sub.mesh
        .elements
        .iter()
        .map(|e| match e {
            Element::Hex8(nodes) => hex_centre_stress(sub, nodes, u),
        })
        .collect()
}

/// Stress tensor (Voigt) at the centre of one hexahedron `nodes` of `sub` for displacements `u`.
pub fn hex_centre_stress(sub: &Substructure, nodes: &[usize; 8], u: &[f64]) -> [f64; 6] {
    let x: [Vec3; 8] = std::array::from_fn(|a| sub.mesh.nodes[nodes[a]]);
    let ue: [f64; 24] = std::array::from_fn(|d| u[3 * nodes[d / 3] + d % 3]);
    hex8::centre_stress(&x, &sub.material, &ue)
}

/// Energy balance over time (all substructures summed), m = 0..=N.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyHistory {
    /// ½ vᵀ M v.
    pub kinetic: Vec<f64>,
    /// ½ uᵀ K u.
    pub strain: Vec<f64>,
    /// Cumulative work of the boundary interfaces (imposed velocities and tractions).
    pub input_work: Vec<f64>,
}

impl EnergyHistory {
    /// Kinetic + strain energy at step m.
    pub fn total(&self, m: usize) -> f64 {
        self.kinetic[m] + self.strain[m]
    }

    /// max over m of E_m / (E_0 + W_in,m), over steps where the denominator is positive:
    /// ≤ 1 when no energy is created.
    pub fn max_total_over_input(&self) -> f64 {
        let e0 = self.total(0);
        (0..self.kinetic.len())
            .filter_map(|m| {
                let avail = e0 + self.input_work[m];
                (avail > 0.0).then(|| self.total(m) / avail)
            })
            .fold(0.0, f64::max)
    }
}

/// The energy balance of the converged fields.
pub fn energy(solver: &Solver, sol: &Solution) -> EnergyHistory {
    let t = Instant::now();
    let p = solver.problem();
    let n = p.time.steps;
    let dt = p.time.dt;
    let per_sub = par::map_range(p.subs.len(), |i| {
        let sub = &p.subs[i];
        // boundary trace ranges of this substructure
        let ranges: Vec<std::ops::Range<usize>> = sub
            .sides
            .iter()
            .filter(|(k, _)| p.interfaces[*k].is_boundary())
            .map(|&(k, side)| {
                let off = p.interfaces[k].sides[side].offset;
                off..off + p.interfaces[k].len
            })
            .collect();
        let mut kin = vec![0.0; n + 1];
        let mut strain = vec![0.0; n + 1];
        let mut work = vec![0.0; n + 1];
        let mut prev_f = vec![0.0; sub.trace_len()];
        let mut prev_w = vec![0.0; sub.trace_len()];
        replay(solver, sol, i, n, &mut |m, st, f, w| {
            kin[m] = 0.5
                * st.v
                    .iter()
                    .zip(&sub.mass)
                    .map(|(v, mm)| mm * v * v)
                    .sum::<f64>();
            strain[m] = 0.5 * sub.stiffness.quadratic_form(&st.u);
            if m > 0 {
                let mut dw = 0.0;
                for r in &ranges {
                    for j in r.clone() {
                        dw += sub.trace_area[j]
                            * 0.5
                            * (f[j] + prev_f[j])
                            * 0.5
                            * dt
                            * (w[j] + prev_w[j]);
                    }
                }
                work[m] = work[m - 1] + dw;
            }
            prev_f.copy_from_slice(f);
            prev_w.copy_from_slice(w);
        });
        (kin, strain, work)
    });
    let mut e = EnergyHistory {
        kinetic: vec![0.0; n + 1],
        strain: vec![0.0; n + 1],
        input_work: vec![0.0; n + 1],
    };
    for (k, s, w) in per_sub {
        for m in 0..=n {
            e.kinetic[m] += k[m];
            e.strain[m] += s[m];
            e.input_work[m] += w[m];
        }
    }
    solver.counters().add_post(t.elapsed().as_secs_f64());
    e
}

/// Contact quantities of one contact interface over time, from ŝ (METHOD §5).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactHistory {
    /// Interface index.
    pub interface: usize,
    /// Contact pressure p_m = −F̂₁·n per step and node (point values).
    pub pressure: Vec<Vec<f64>>,
    /// Gap ĝ_m per step and node.
    pub gap: Vec<Vec<f64>>,
    /// Magnitude of the accumulated tangential relative displacement per step and node.
    pub slip: Vec<Vec<f64>>,
    /// Step-averaged total normal force Σ A (p_m + p_{m−1})/2 per step.
    pub normal_force: Vec<f64>,
}

impl ContactHistory {
    /// Largest slip over nodes and steps.
    pub fn max_slip(&self) -> f64 {
        self.slip.iter().flatten().copied().fold(0.0, f64::max)
    }

    /// Smallest gap over nodes and steps.
    pub fn min_gap(&self) -> f64 {
        self.gap
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest step-averaged normal force.
    pub fn peak_normal_force(&self) -> f64 {
        self.normal_force.iter().copied().fold(0.0, f64::max)
    }
}

/// Contact histories of every contact interface.
pub fn contact(solver: &Solver, sol: &Solution) -> Vec<ContactHistory> {
    let t = Instant::now();
    let p = solver.problem();
    let (n, dt) = (p.time.steps, p.time.dt);
    let out = p
        .interfaces
        .iter()
        .enumerate()
        .filter_map(|(k, iface)| {
            let Law::Contact(c) = &iface.law else {
                return None;
            };
            let (h1, h2) = (&sol.hats[k][0], &sol.hats[k][1]);
            let nn = iface.node_count();
            let mut h = ContactHistory {
                interface: k,
                pressure: vec![vec![0.0; nn]; n + 1],
                gap: vec![vec![0.0; nn]; n + 1],
                slip: vec![vec![0.0; nn]; n + 1],
                normal_force: vec![0.0; n + 1],
            };
            let mut slip_vec = vec![[0.0; 3]; nn];
            let mut prev_jump = vec![[0.0; 3]; nn];
            for m in 0..=n {
                let r = h1.at(m);
                let mut force = 0.0;
                for i in 0..nn {
                    let nrm = c.normal[i];
                    let at =
                        |x: &[f64]| -> Vec3 { std::array::from_fn(|q| x[r.start + 3 * i + q]) };
                    let f1 = at(&h1.f);
                    let jump: Vec3 = {
                        let (w1, w2) = (at(&h1.w), at(&h2.w));
                        std::array::from_fn(|q| w2[q] - w1[q])
                    };
                    let p_m = -dot(f1, nrm);
                    h.pressure[m][i] = p_m;
                    force += iface.area[3 * i] * p_m;
                    if m == 0 {
                        h.gap[0][i] = c.gap[i];
                    } else {
                        let jn = dot(jump, nrm);
                        let jn_prev = dot(prev_jump[i], nrm);
                        h.gap[m][i] = h.gap[m - 1][i] + 0.5 * dt * (jn + jn_prev);
                        for q in 0..3 {
                            let t_now = jump[q] - jn * nrm[q];
                            let t_prev = prev_jump[i][q] - jn_prev * nrm[q];
                            slip_vec[i][q] += 0.5 * dt * (t_now + t_prev);
                        }
                        h.slip[m][i] = dot(slip_vec[i], slip_vec[i]).sqrt();
                    }
                    prev_jump[i] = jump;
                }
                h.normal_force[m] = force;
            }
            // step averages (F_m + F_{m−1})/2
            for m in (1..=n).rev() {
                h.normal_force[m] = 0.5 * (h.normal_force[m] + h.normal_force[m - 1]);
            }
            Some(h)
        })
        .collect();
    solver.counters().add_post(t.elapsed().as_secs_f64());
    out
}

/// Step-averaged resultant force (Σ A F̂ on side 1) of every interface, per step.
pub fn interface_forces(solver: &Solver, sol: &Solution) -> Vec<Vec<Vec3>> {
    let p = solver.problem();
    let n = p.time.steps;
    p.interfaces
        .iter()
        .enumerate()
        .map(|(k, iface)| {
            let h = &sol.hats[k][0];
            let point: Vec<Vec3> = (0..=n)
                .map(|m| {
                    let r = h.at(m);
                    let mut f = [0.0; 3];
                    for j in 0..iface.len {
                        let comp = match &iface.law {
                            Law::Boundary(d) => d[j].component,
                            _ => j % 3,
                        };
                        f[comp] += iface.area[j] * h.f[r.start + j];
                    }
                    f
                })
                .collect();
            (0..=n)
                .map(|m| {
                    if m == 0 {
                        point[0]
                    } else {
                        std::array::from_fn(|q| 0.5 * (point[m][q] + point[m - 1][q]))
                    }
                })
                .collect()
        })
        .collect()
}

/// The headline numbers of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Kinetic energy at the end.
    pub kinetic_end: f64,
    /// Strain energy at the end.
    pub strain_end: f64,
    /// Total input work of the boundary interfaces at the end.
    pub input_work: f64,
    /// max_m E_m / (E_0 + W_in,m).
    pub max_total_over_input: f64,
    /// Largest slip on contact interfaces (0 without contact).
    pub max_slip: f64,
    /// Largest step-averaged total normal force on a contact interface (0 without contact).
    pub peak_normal_force: f64,
    /// Smallest gap on contact interfaces (None without contact).
    pub min_gap: Option<f64>,
}

/// Energy and contact summary of a solution.
pub fn summary(solver: &Solver, sol: &Solution) -> Summary {
    Summary::from_histories(&energy(solver, sol), &contact(solver, sol))
}

impl Summary {
    /// The headline numbers of an energy balance and contact histories.
    pub fn from_histories(e: &EnergyHistory, c: &[ContactHistory]) -> Self {
        let n = e.kinetic.len() - 1;
        Summary {
            kinetic_end: e.kinetic[n],
            strain_end: e.strain[n],
            input_work: e.input_work[n],
            max_total_over_input: e.max_total_over_input(),
            max_slip: c.iter().map(ContactHistory::max_slip).fold(0.0, f64::max),
            peak_normal_force: c
                .iter()
                .map(ContactHistory::peak_normal_force)
                .fold(0.0, f64::max),
            min_gap: c.iter().map(ContactHistory::min_gap).reduce(f64::min),
        }
    }
}
