//! Post-processing, computed only when asked: the fields of a converged solution come from one
//! more linear stage driven by ŝ (METHOD §6 "at convergence"), replayed per substructure up to the
//! step wanted. Energies use the exact discrete identity of METHOD §2: the work of the boundary
//! forces is ((1 − γ) F_{m−1} + γ F_m)·(u_m − u_{m−1}) (½ (F_m + F_{m−1})·Δt/2 (W_m + W_{m−1})
//! for the trapezoidal rule, γ = ½), and the same rule applied to C v gives the energy D_m the
//! Rayleigh damping dissipates, so that E_m + D_m = E_0 + W_m; with a dissipative scheme
//! E_m + D_m − E_0 − W_m is minus the energy the scheme removed, never positive
//! ([`crate::time::time_scheme`]); interface forces are
//! reported as step averages (F_m + F_{m−1})/2 (METHOD §2, §10 "force ringing").

use crate::counters::Instant;
use crate::elements::hex8;
use crate::interfaces::interface::Law;
use crate::mesh::{dot, Element, Vec3};
use crate::par;
use crate::solver::blocks::{class_blocks, solve_together};
use crate::solver::{Solution, Solver};
use crate::stages::linear_stage::{
    add_guess, complete, form_rhs, march, predict_refined, LinearInput, LinearWork, StepVisitor,
    SubState,
};
use crate::state::TraceHistory;
use crate::substructure::{SideRef, Substructure};

pub use crate::histories::{ContactHistory, EnergyHistory, Summary};

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
    let mut work = LinearWork::new(sub, factor, &p.step_coefficients());
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
        time: p.step_coefficients(),
        steps: (1, until),
    };
    march(
        sub,
        factor,
        &mut work,
        &input,
        &mut out,
        Some(visit),
        predict_refined,
    );
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

/// The velocity of node `node` of substructure `sub` at every step m = 0..=N.
pub fn node_velocity(solver: &Solver, sol: &Solution, sub: usize, node: usize) -> Vec<[f64; 3]> {
    let p = solver.problem();
    let mut out = Vec::with_capacity(p.time.steps + 1);
    replay(solver, sol, sub, p.time.steps, &mut |_, st, _, _| {
        out.push(std::array::from_fn(|c| st.v[3 * node + c]));
    });
    out
}

/// The node nearest to `point` over every substructure: (substructure, node, distance).
pub fn nearest_node(problem: &crate::Problem, point: Vec3) -> Option<(usize, usize, f64)> {
    problem
        .subs
        .iter()
        .enumerate()
        .flat_map(|(s, sub)| {
            sub.mesh.nodes.iter().enumerate().map(move |(n, x)| {
                let d: Vec3 = std::array::from_fn(|c| x[c] - point[c]);
                (s, n, dot(d, d).sqrt())
            })
        })
        .min_by(|a, b| a.2.total_cmp(&b.2))
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
/// substructure (what exports need; [`fields_at`] replays up to one step). In a distributed run,
/// of this rank's substructures only (the others' lists are empty; [`gather_history`]).
pub fn history(solver: &Solver, sol: &Solution) -> Vec<Vec<SubFields>> {
    let t = Instant::now();
    let p = solver.problem();
    let n = p.time.steps;
    let dist = solver.distribution();
    let out = par::map_range(p.subs.len(), |i| {
        let mut steps = Vec::with_capacity(n + 1);
        if !dist.holds_sub(i) {
            return steps;
        }
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

/// Completes a distributed run's [`history`] on rank 0 (every rank calls it; the others keep
/// theirs): each rank sends the fields of its substructures to rank 0 in one message.
pub fn gather_history(solver: &Solver, history: &mut [Vec<SubFields>]) {
    let dist = solver.distribution();
    if dist.is_single() {
        return;
    }
    let p = solver.problem();
    let steps = p.time.steps + 1;
    let size = |i: usize| 2 * steps * p.subs[i].ndof();
    let on = |r: usize| (0..p.subs.len()).filter(move |&i| dist.sub_ranks()[i] == r);
    if dist.rank() == 0 {
        let receive: Vec<(usize, usize)> = (1..dist.size())
            .map(|r| (r, on(r).map(size).sum()))
            .collect();
        let got = dist.ranks().exchange(&[], &receive);
        for (r, data) in (1..dist.size()).zip(got) {
            let mut at = 0;
            for i in on(r) {
                let d = p.subs[i].ndof();
                history[i] = (0..steps)
                    .map(|_| {
                        let f = SubFields {
                            u: data[at..at + d].to_vec(),
                            v: data[at + d..at + 2 * d].to_vec(),
                        };
                        at += 2 * d;
                        f
                    })
                    .collect();
            }
        }
    } else {
        let mut data = Vec::new();
        for i in on(dist.rank()) {
            for f in &history[i] {
                data.extend_from_slice(&f.u);
                data.extend_from_slice(&f.v);
            }
        }
        dist.ranks().exchange(&[(0, data)], &[]);
    }
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
        .map(|e| stress_of(sub, e, u))
        .collect()
}

/// Stress tensor (Voigt) of one element of `sub` (at the centre of a hexahedron, constant on a
/// tetrahedron) for displacements `u`.
pub fn stress_of(sub: &Substructure, element: &Element, u: &[f64]) -> [f64; 6] {
    match element {
        Element::Hex8(nodes) => hex_centre_stress(sub, nodes, u),
        Element::Tet4(nodes) => tet_stress(sub, nodes, u),
    }
}

/// The (constant) stress tensor (Voigt) of one tetrahedron `nodes` of `sub` for displacements
/// `u`.
pub fn tet_stress(sub: &Substructure, nodes: &[usize; 4], u: &[f64]) -> [f64; 6] {
    let x: [Vec3; 4] = std::array::from_fn(|a| sub.mesh.nodes[nodes[a]]);
    let ue: [f64; 12] = std::array::from_fn(|d| u[3 * nodes[d / 3] + d % 3]);
    crate::elements::tet4::stress(&x, &sub.material, &ue)
}

/// Stress tensor (Voigt) at the centre of one hexahedron `nodes` of `sub` for displacements `u`.
pub fn hex_centre_stress(sub: &Substructure, nodes: &[usize; 8], u: &[f64]) -> [f64; 6] {
    let x: [Vec3; 8] = std::array::from_fn(|a| sub.mesh.nodes[nodes[a]]);
    let ue: [f64; 24] = std::array::from_fn(|d| u[3 * nodes[d / 3] + d % 3]);
    hex8::centre_stress(&x, &sub.material, &ue)
}

/// The energy a substructure's Rayleigh damping dissipates, step by step: the scheme's work of
/// the force C v = α M v + β K v (K v from the carried c_K K v), the same rule as the boundary
/// work.
struct Viscous<'a> {
    sub: &'a Substructure,
    c_k: f64,
    /// C v, v and u of the previous step.
    prev: [Vec<f64>; 3],
    cv: Vec<f64>,
    /// Cumulative dissipated energy per step.
    dissipated: Vec<f64>,
}

impl<'a> Viscous<'a> {
    /// None for an undamped substructure.
    fn new(sub: &'a Substructure, c_k: f64, steps: usize) -> Option<Self> {
        (!sub.material.damping.is_none()).then(|| Self {
            sub,
            c_k,
            prev: std::array::from_fn(|_| vec![0.0; sub.ndof()]),
            cv: vec![0.0; sub.ndof()],
            dissipated: vec![0.0; steps + 1],
        })
    }

    /// Adds step m (m = 0: the initial state, nothing dissipated yet).
    fn step(&mut self, m: usize, st: &SubState, dt: f64, (trapezoidal, gamma): (bool, f64)) {
        let d = self.sub.material.damping;
        for i in 0..self.cv.len() {
            self.cv[i] = d.alpha * self.sub.mass[i] * st.v[i] + d.beta * st.ckv[i] / self.c_k;
        }
        let [cvp, vp, up] = &mut self.prev;
        if m > 0 {
            let dd: f64 = (0..self.cv.len())
                .map(|i| {
                    if trapezoidal {
                        0.25 * dt * (self.cv[i] + cvp[i]) * (st.v[i] + vp[i])
                    } else {
                        (gamma * self.cv[i] + (1.0 - gamma) * cvp[i]) * (st.u[i] - up[i])
                    }
                })
                .sum();
            self.dissipated[m] = self.dissipated[m - 1] + dd;
        }
        cvp.copy_from_slice(&self.cv);
        vp.copy_from_slice(&st.v);
        up.copy_from_slice(&st.u);
    }
}

/// Replays every substructure this rank holds driven by ŝ over steps 1..=until, in the blocks
/// the solve's linear stage marched in (on windows, substructures that share a factorization
/// together; over the whole interval with the skip cache, each alone: [`crate::solver::blocks`]),
/// in parallel: `start(i)` makes substructure `i`'s
/// visitor, which `visit(visitor, m, state, F, W)` hands every step (m = 0: the initial state).
/// Gives back the visitors of the substructures held, by increasing index.
pub fn replay_blocks<T: Send>(
    solver: &Solver,
    sol: &Solution,
    until: usize,
    start: impl Fn(usize) -> T + Sync,
    visit: impl Fn(&mut T, usize, &SubState, &[f64], &[f64]) + Sync,
) -> Vec<(usize, T)> {
    let p = solver.problem();
    let dist = solver.distribution();
    let settings = solver.settings();
    let whole = settings.window.is_none_or(|w| w >= p.time.steps);
    let blocks = class_blocks(
        solver.classes(),
        |i| dist.holds_sub(i),
        whole && settings.skip_unchanged,
    );
    let until = until.min(p.time.steps);
    let input = LinearInput {
        interfaces: &p.interfaces,
        hats: &sol.hats,
        k: solver.settings().k,
        time: p.step_coefficients(),
        steps: (1, until.max(1)),
    };
    let per_block = par::map_range(blocks.len(), |b| {
        let (width, members) = &blocks[b];
        let factor = solver.factor(members[0]);
        let mut works: Vec<LinearWork> = members
            .iter()
            .map(|&i| LinearWork::new(&p.subs[i], factor, &input.time))
            .collect();
        let mut outs: Vec<TraceHistory> = members
            .iter()
            .map(|&i| TraceHistory::zeros(p.subs[i].trace_len(), p.time.steps))
            .collect();
        let mut visitors: Vec<T> = members.iter().map(|&i| start(i)).collect();
        for ((visitor, work), &i) in visitors.iter_mut().zip(&works).zip(members) {
            let h0 = &sol.state.subs[i];
            visit(visitor, 0, &work.state, &h0.f[h0.at(0)], &h0.w[h0.at(0)]);
        }
        let (mut block, mut scratch) = (Vec::new(), None);
        for m in 1..=until {
            // a single-precision factor's solve refined once more (as [`predict_refined`])
            for pass in 0..2 {
                for (work, &i) in works.iter_mut().zip(members) {
                    form_rhs(&p.subs[i], work, &input, m, None);
                }
                solve_together(factor, works.iter_mut(), *width, &mut block, &mut scratch);
                let mut again = false;
                for (work, &i) in works.iter_mut().zip(members) {
                    add_guess(work);
                    again |= pass == 0 && work.keep_as_guess(&p.subs[i], &input, m);
                }
                if !again {
                    break;
                }
            }
            for (((work, out), visitor), &i) in works
                .iter_mut()
                .zip(&mut outs)
                .zip(&mut visitors)
                .zip(members)
            {
                complete(&p.subs[i], work, &input, m, out, None, None);
                let r = out.at(m);
                visit(visitor, m, &work.state, &out.f[r.clone()], &out.w[r]);
            }
        }
        members.iter().copied().zip(visitors).collect::<Vec<_>>()
    });
    let mut all: Vec<(usize, T)> = per_block.into_iter().flatten().collect();
    all.sort_by_key(|(i, _)| *i);
    all
}

/// What the energy balance gathers of one substructure over the replay.
struct SubEnergy<'a> {
    sub: &'a Substructure,
    ranges: Vec<std::ops::Range<usize>>,
    /// Kinetic, strain and input work per step.
    histories: [Vec<f64>; 3],
    prev_f: Vec<f64>,
    prev_w: Vec<f64>,
    prev_u: Vec<f64>,
    viscous: Option<Viscous<'a>>,
}

impl SubEnergy<'_> {
    /// Adds step m of the replay (m = 0: the initial state).
    fn step(
        &mut self,
        m: usize,
        st: &SubState,
        (f, w): (&[f64], &[f64]),
        scheme: (f64, bool, f64),
    ) {
        let (dt, trapezoidal, gamma) = scheme;
        let sub = self.sub;
        if let Some(d) = self.viscous.as_mut() {
            d.step(m, st, dt, (trapezoidal, gamma));
        }
        let [kin, strain, work] = &mut self.histories;
        kin[m] = kinetic_energy(sub, &st.v);
        strain[m] = strain_energy(st);
        if m > 0 {
            // u_m − u_{m−1} of the trace dof: Δt/2 (W_m + W_{m−1}) for the trapezoidal rule,
            // the Newmark update otherwise
            let prev_u = &self.prev_u;
            let prev_w = &self.prev_w;
            let dw = boundary_work(sub, &self.ranges, gamma, (f, &self.prev_f), |j| {
                if trapezoidal {
                    0.5 * dt * (w[j] + prev_w[j])
                } else {
                    sub.trace_value(j, &st.u) - prev_u[j]
                }
            });
            work[m] = work[m - 1] + dw;
        }
        self.prev_f.copy_from_slice(f);
        self.prev_w.copy_from_slice(w);
        if !trapezoidal {
            for (j, u) in self.prev_u.iter_mut().enumerate() {
                *u = sub.trace_value(j, &st.u);
            }
        }
    }
}

/// The energy balance of the converged fields.
pub fn energy(solver: &Solver, sol: &Solution) -> EnergyHistory {
    let t = Instant::now();
    let p = solver.problem();
    let n = p.time.steps;
    let scheme = (
        p.time.dt,
        p.scheme.is_trapezoidal(),
        p.scheme.parameters().1,
    );
    let c_k = p.step_coefficients().stiffness;
    let dist = solver.distribution();
    let replayed = replay_blocks(
        solver,
        sol,
        n,
        |i| {
            let sub = &p.subs[i];
            SubEnergy {
                sub,
                ranges: boundary_ranges(p, sub),
                histories: std::array::from_fn(|_| vec![0.0; n + 1]),
                prev_f: vec![0.0; sub.trace_len()],
                prev_w: vec![0.0; sub.trace_len()],
                prev_u: vec![0.0; sub.trace_len()],
                viscous: Viscous::new(sub, c_k, n),
            }
        },
        |e, m, st, f, w| e.step(m, st, (f, w), scheme),
    );
    // −0: the neutral element of the sum over the ranks
    let mut per_sub: Vec<[Vec<f64>; 4]> = (0..p.subs.len())
        .map(|_| std::array::from_fn(|_| vec![-0.0; n + 1]))
        .collect();
    for (i, e) in replayed {
        let [kin, strain, work] = e.histories;
        let damping = e.viscous.map_or_else(|| vec![0.0; n + 1], |d| d.dissipated);
        per_sub[i] = [kin, strain, work, damping];
    }
    let mut e = EnergyHistory {
        kinetic: vec![0.0; n + 1],
        strain: vec![0.0; n + 1],
        input_work: vec![0.0; n + 1],
        damping: vec![0.0; n + 1],
    };
    // distributed: every substructure's histories from its rank, added in index order
    let per_sub = if dist.is_single() {
        per_sub
    } else {
        let mut flat: Vec<f64> = per_sub.iter().flatten().flatten().copied().collect();
        dist.all_sum(&mut flat);
        flat.chunks_exact(4 * (n + 1))
            .map(|c| std::array::from_fn(|q| c[q * (n + 1)..(q + 1) * (n + 1)].to_vec()))
            .collect()
    };
    for [k, s, w, d] in per_sub {
        for m in 0..=n {
            e.kinetic[m] += k[m];
            e.strain[m] += s[m];
            e.input_work[m] += w[m];
            e.damping[m] += d[m];
        }
    }
    solver.counters().add_post(t.elapsed().as_secs_f64());
    e
}

/// ½ vᵀ M v of a substructure (lumped M).
pub(crate) fn kinetic_energy(sub: &Substructure, v: &[f64]) -> f64 {
    0.5 * v
        .iter()
        .zip(&sub.mass)
        .map(|(v, mm)| mm * v * v)
        .sum::<f64>()
}

/// ½ uᵀ K u of a substructure's state, from the K u its march carries.
pub(crate) fn strain_energy(state: &SubState) -> f64 {
    0.5 * dot_slices(&state.u, &state.ku)
}

fn dot_slices(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The trace ranges of a substructure's sides on boundary interfaces (whose work is the input).
pub(crate) fn boundary_ranges(
    p: &crate::Problem,
    sub: &Substructure,
) -> Vec<std::ops::Range<usize>> {
    sub.sides
        .iter()
        .filter(|s| p.interfaces[s.interface].is_boundary())
        .map(|&SideRef { interface: k, side }| {
            let off = p.interfaces[k].sides[side].offset;
            off..off + p.interfaces[k].len
        })
        .collect()
}

/// The work of the boundary tractions over one step (METHOD §2):
/// Σ_j A_j (γ F_m + (1 − γ) F_{m−1}) Δu_j over the trace entries of `ranges`, Δu_j from `du`.
pub(crate) fn boundary_work(
    sub: &Substructure,
    ranges: &[std::ops::Range<usize>],
    gamma: f64,
    (f, prev_f): (&[f64], &[f64]),
    du: impl Fn(usize) -> f64,
) -> f64 {
    let mut dw = 0.0;
    for r in ranges {
        for j in r.clone() {
            dw += sub.trace_area[j] * (gamma * f[j] + (1.0 - gamma) * prev_f[j]) * du(j);
        }
    }
    dw
}

/// Contact histories of every contact interface, from a solution that holds ŝ of all of them
/// (one machine, or rank 0 after [`crate::distributed::distribution::Distribution::gather_to_root`]).
pub fn contact(solver: &Solver, sol: &Solution) -> Vec<ContactHistory> {
    contact_where(solver, sol, &|_| true)
}

/// [`contact`] in a distributed run, called by every rank: each contact interface's history is
/// computed on the rank that holds the interface and summed over the ranks (the others add −0,
/// [`crate::distributed::ranks`]), so every rank gets every history, equal bit for bit to [`contact`] on one
/// machine.
pub fn gathered_contact(solver: &Solver, sol: &Solution) -> Vec<ContactHistory> {
    let dist = solver.distribution();
    if dist.is_single() {
        return contact(solver, sol);
    }
    let mut out = contact_where(solver, sol, &|k| dist.holds_interface(k));
    let mut flat: Vec<f64> = Vec::new();
    for h in &out {
        flat.extend(h.pressure.iter().flatten());
        flat.extend(h.gap.iter().flatten());
        flat.extend(h.slip.iter().flatten());
        flat.extend(&h.normal_force);
    }
    dist.all_sum(&mut flat);
    let mut at = flat.into_iter();
    for h in &mut out {
        for x in h.pressure.iter_mut().chain(&mut h.gap).chain(&mut h.slip) {
            x.iter_mut().for_each(|v| *v = at.next().unwrap_or(0.0));
        }
        h.normal_force
            .iter_mut()
            .for_each(|v| *v = at.next().unwrap_or(0.0));
    }
    out
}

/// Contact histories of every contact interface, computed where `take` says; the others are
/// filled with −0 (the neutral element of the sum over the ranks).
fn contact_where(
    solver: &Solver,
    sol: &Solution,
    take: &dyn Fn(usize) -> bool,
) -> Vec<ContactHistory> {
    let t = Instant::now();
    let p = solver.problem();
    let (n, dt) = (p.time.steps, p.time.dt);
    let step = p.step_coefficients();
    let out = p
        .interfaces
        .iter()
        .enumerate()
        .filter_map(|(k, iface)| {
            let Law::Contact(c) = &iface.law else {
                return None;
            };
            let nn = iface.node_count();
            if !take(k) {
                return Some(ContactHistory {
                    interface: k,
                    pressure: vec![vec![-0.0; nn]; n + 1],
                    gap: vec![vec![-0.0; nn]; n + 1],
                    slip: vec![vec![-0.0; nn]; n + 1],
                    normal_force: vec![-0.0; n + 1],
                });
            }
            let (h1, h2) = (&sol.hats[k][0], &sol.hats[k][1]);
            let mut h = ContactHistory {
                interface: k,
                pressure: vec![vec![0.0; nn]; n + 1],
                gap: vec![vec![0.0; nn]; n + 1],
                slip: vec![vec![0.0; nn]; n + 1],
                normal_force: vec![0.0; n + 1],
            };
            let mut slip_vec = vec![[0.0; 3]; nn];
            let mut prev_jump = vec![[0.0; 3]; nn];
            // acceleration jump of the scheme's displacement update (unused when trapezoidal)
            let mut prev_accel = vec![[0.0; 3]; nn];
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
                        h.gap[0][i] = c.gap_at_start()[i];
                    } else {
                        let jn = dot(jump, nrm);
                        let jn_prev = dot(prev_jump[i], nrm);
                        if step.trapezoidal {
                            h.gap[m][i] = h.gap[m - 1][i] + 0.5 * dt * (jn + jn_prev);
                            for q in 0..3 {
                                let t_now = jump[q] - jn * nrm[q];
                                let t_prev = prev_jump[i][q] - jn_prev * nrm[q];
                                slip_vec[i][q] += 0.5 * dt * (t_now + t_prev);
                            }
                        } else {
                            // the displacement jump of the scheme's update
                            let mut du = [0.0; 3];
                            for q in 0..3 {
                                (du[q], prev_accel[i][q]) =
                                    step.advance(0.0, prev_jump[i][q], prev_accel[i][q], jump[q]);
                            }
                            let dn = dot(du, nrm);
                            h.gap[m][i] = h.gap[m - 1][i] + dn;
                            for q in 0..3 {
                                slip_vec[i][q] += du[q] - dn * nrm[q];
                            }
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

/// Energy and contact summary of a solution (in a distributed run every rank calls it and gets
/// the whole summary).
pub fn summary(solver: &Solver, sol: &Solution) -> Summary {
    Summary::from_histories(&energy(solver, sol), &gathered_contact(solver, sol))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene;
    use crate::solver::Settings;

    fn solve(toml: &str, tol: f64, window: Option<usize>) -> (Solver, Solution) {
        let spec = scene::from_toml(toml, "test").expect("scene");
        let problem = scene::problem_of(&spec, "test").expect("build");
        let mut settings = Settings::for_problem(&problem, &spec.solver);
        settings.tol = tol;
        settings.window = window;
        let mut solver = Solver::new(problem, settings).expect("solver");
        let sol = solver.solve(None).expect("solve");
        assert!(sol.converged);
        (solver, sol)
    }

    /// A free block (two substructures, no boundary) moving at a uniform initial velocity keeps
    /// its kinetic energy ½ ρ V |v|², no strain energy and no input work, at every step.
    #[test]
    fn a_free_block_in_uniform_motion_keeps_its_kinetic_energy() {
        let toml = r#"
            name = "free"
            [time]
            dt = 1e-6
            steps = 10
            [[material]]
            name = "steel"
            young = 210e9
            poisson = 0.3
            density = 7800.0
            [[body]]
            name = "A"
            material = "steel"
            min = [0.0, 0.0, 0.0]
            max = [0.02, 0.01, 0.01]
            divisions = [4, 2, 2]
            split = [2, 1, 1]
            velocity = [3.0, -4.0, 0.0]
        "#;
        let (solver, sol) = solve(toml, 1e-10, None);
        let e = energy(&solver, &sol);
        let exact = 0.5 * 7800.0 * (0.02 * 0.01 * 0.01) * 25.0;
        for m in 0..=10 {
            assert!(
                (e.kinetic[m] - exact).abs() < 1e-9 * exact,
                "m = {m}: {}",
                e.kinetic[m]
            );
            assert!(
                e.strain[m].abs() < 1e-12 * exact,
                "m = {m}: {}",
                e.strain[m]
            );
            assert_eq!(e.input_work[m], 0.0);
        }
    }

    /// The trapezoidal rule conserves energy: in the `bar` scene (pushed at one end, perfect
    /// interfaces) kinetic + strain energy equals the work of the prescribed velocity at every
    /// step, to the iteration's tolerance (η < 1e-9 per one-step window here: 1e-7 of the final
    /// energy).
    #[test]
    fn bar_energy_equals_input_work_at_every_step() {
        let spec = scene::load("bar").expect("scene");
        let toml = scene::to_toml(&spec);
        let (solver, sol) = solve(&toml, 1e-9, Some(1));
        let e = energy(&solver, &sol);
        let n = solver.problem().time.steps;
        let scale = e.input_work[n];
        assert!(scale > 0.0);
        for m in 0..=n {
            let gap = e.kinetic[m] + e.strain[m] - e.input_work[m];
            assert!(gap.abs() < 1e-7 * scale, "m = {m}: {gap:e} of {scale:e}");
        }
    }
}
