//! The projected warm start of a study (METHOD §8 with §4–§6): instead of the nearest solved
//! configuration's state alone, the affine combination
//!
//! ```text
//!     s(α) = s_near + Σ_j α_j (s_j − s_near)
//! ```
//!
//! of the nearest stored states that lies closest to the new configuration's interface
//! behaviour Γ. Each stored s_j is admissible (the linear stage's output, relaxed: METHOD §6),
//! and the linear stage is affine with the same initial state and loads for every configuration
//! of a study (its parameters live on the interfaces), so s(α) is admissible for any α. The
//! local stage of the new configuration (METHOD §5) maps s(α) to ŝ = P(s(α)) ∈ Γ along E+, and
//! the start minimises the distance between the two in η's weights (METHOD §6):
//!
//! ```text
//!     J(α) = Σ_m Σ_j A_j [ (F_j − F̂_j)²/k_j + k_j (W_j − Ŵ_j)² ]
//! ```
//!
//! by Gauss–Newton over α, each Jacobian column a finite difference of one local stage. No
//! linear-stage solve is made: the projection costs local stages only, and no iteration. The
//! result is reported as ρ_Γ = √(J / D), D being η's denominator, for the nearest state and for
//! the start; the nearest state is kept when no combination does better.
//!
//! Where it pays: on the whole interval with a dissipative scheme (ρ∞ < 1), where a grid of
//! `two-blocks` takes fewer iterations from the projection than from the nearest state (the
//! guide, docs/src/studies.md, gives the figures). With the undamped rule the alternating mode
//! of METHOD §10 makes the distance a poor guide, and on one-step windows each window already
//! starts from the nearest state's converged step.

use crate::interfaces::interface::Law;
use crate::par;
use crate::solver::Solver;
use crate::stages::local_stage::{local_stage, ContactRunning, LocalInput};
use crate::state::{InterfaceState, TraceHistory};

/// Stored states a projection combines by default (the nearest included).
pub const BASIS: usize = 8;
/// Gauss–Newton steps of a projection.
pub const GAUSS_NEWTON_STEPS: usize = 2;
/// Finite-difference step of the Jacobian, in units of α.
const DIFFERENCE_STEP: f64 = 1e-3;

/// A projected start.
#[derive(Debug, Clone)]
pub struct Projection {
    /// The start s(α).
    pub state: InterfaceState,
    /// α of each other state, in the order given.
    pub weights: Vec<f64>,
    /// ρ_Γ of the nearest state alone.
    pub residual_nearest: f64,
    /// ρ_Γ of the start.
    pub residual: f64,
}

/// ρ_Γ's terms of a state, on a solver's problem: the weighted E+ residual of every interface
/// dof and step 1..N after one local stage, and η's denominator.
struct Residual {
    values: Vec<f64>,
    den: f64,
}

impl Residual {
    fn ratio(&self) -> f64 {
        if self.den > 0.0 {
            (self.values.iter().map(|x| x * x).sum::<f64>() / self.den).sqrt()
        } else {
            0.0
        }
    }
}

/// The local stage of the solver's problem from `s` over the whole interval, and the residual
/// s − ŝ in η's weights (METHOD §5, §6).
fn residual(solver: &Solver, s: &InterfaceState) -> Residual {
    let p = solver.problem();
    let n = p.time.steps;
    let k = solver.settings().k;
    let input = LocalInput {
        s,
        k,
        time: p.time,
        step: p.step_coefficients(),
        steps: (1, n),
    };
    let mut values = Vec::new();
    let mut den = 0.0;
    for iface in &p.interfaces {
        let mut hat: Vec<TraceHistory> = iface
            .sides
            .iter()
            .map(|_| TraceHistory::zeros(iface.len, n))
            .collect();
        let start = match &iface.law {
            Law::Contact(c) => Some(ContactRunning::initial(iface, c, s)),
            _ => None,
        };
        local_stage(iface, &input, &mut hat, start.as_ref());
        for (side, h) in iface.sides.iter().zip(&hat) {
            let trace = &s.subs[side.sub];
            for m in 1..=n {
                for j in 0..iface.len {
                    let a = iface.area[j];
                    let kj = k * iface.k_scale[j];
                    let at = m * trace.len + side.offset + j;
                    let (f, w) = (trace.f[at], trace.w[at]);
                    let (fh, wh) = (h.f[m * iface.len + j], h.w[m * iface.len + j]);
                    values.push((a / kj).sqrt() * (f - fh));
                    values.push((a * kj).sqrt() * (w - wh));
                    den += 0.5 * a * ((f * f + fh * fh) / kj + kj * (w * w + wh * wh));
                }
            }
        }
    }
    Residual { values, den }
}

/// x ← x + c y on every stored history.
fn add_scaled(x: &mut InterfaceState, c: f64, y: &InterfaceState) {
    for (h, g) in x.subs.iter_mut().zip(&y.subs) {
        for (a, b) in h.f.iter_mut().zip(&g.f) {
            *a += c * b;
        }
        for (a, b) in h.w.iter_mut().zip(&g.w) {
            *a += c * b;
        }
    }
}

/// s_near + Σ α_j d_j.
fn combine(near: &InterfaceState, dirs: &[InterfaceState], alpha: &[f64]) -> InterfaceState {
    let mut s = near.clone();
    for (d, &a) in dirs.iter().zip(alpha) {
        if a != 0.0 {
            add_scaled(&mut s, a, d);
        }
    }
    s
}

/// The projected start for the solver's current parameters from the nearest stored state
/// `near` and `others` (METHOD §8; module doc), with `steps` Gauss–Newton steps. The solver
/// must hold every substructure and interface (one rank). m = 0 of the start is the problem's
/// initial state.
pub fn project(
    solver: &Solver,
    near: &InterfaceState,
    others: &[InterfaceState],
    steps: usize,
) -> Projection {
    let initial = InterfaceState::cold_where(solver.problem(), &|_| true);
    let mut base = near.clone();
    for (h, h0) in base.subs.iter_mut().zip(&initial.subs) {
        let r = h0.at(0);
        h.f[r.clone()].copy_from_slice(&h0.f[r.clone()]);
        h.w[r.clone()].copy_from_slice(&h0.w[r]);
    }
    let dirs: Vec<InterfaceState> = others
        .iter()
        .map(|o| {
            let mut d = o.clone();
            add_scaled(&mut d, -1.0, &base);
            for h in &mut d.subs {
                let r = h.at(0);
                h.f[r.clone()].fill(0.0);
                h.w[r].fill(0.0);
            }
            d
        })
        .collect();
    let mut alpha = vec![0.0; dirs.len()];
    let mut r = residual(solver, &base);
    let residual_nearest = r.ratio();
    let mut best = residual_nearest;
    for _ in 0..if dirs.is_empty() { 0 } else { steps } {
        let columns: Vec<Vec<f64>> = par::map_range(alpha.len(), |j| {
            let mut a = alpha.clone();
            a[j] += DIFFERENCE_STEP;
            let rj = residual(solver, &combine(&base, &dirs, &a));
            rj.values
                .iter()
                .zip(&r.values)
                .map(|(x, y)| (x - y) / DIFFERENCE_STEP)
                .collect()
        });
        let n = columns.len();
        let mut normal = vec![0.0; n * n];
        let mut rhs = vec![0.0; n];
        for i in 0..n {
            for j in i..n {
                let v: f64 = columns[i].iter().zip(&columns[j]).map(|(x, y)| x * y).sum();
                normal[i * n + j] = v;
                normal[j * n + i] = v;
            }
            rhs[i] = -columns[i]
                .iter()
                .zip(&r.values)
                .map(|(x, y)| x * y)
                .sum::<f64>();
        }
        // a whisper of ridge: nearly equal stored states make the normal matrix singular
        let largest = (0..n).map(|i| normal[i * n + i]).fold(0.0, f64::max);
        if largest <= 0.0 {
            break;
        }
        for i in 0..n {
            normal[i * n + i] += 1e-10 * largest;
        }
        let step = crate::linalg::dense::solve_spd(normal, rhs);
        if !step.iter().all(|x| x.is_finite()) {
            break;
        }
        // the residual is piecewise linear in α (the contact law's cases): halve the step
        // until it decreases
        let mut taken = None;
        for t in [1.0, 0.5, 0.25] {
            let a: Vec<f64> = alpha.iter().zip(&step).map(|(x, y)| x + t * y).collect();
            let ra = residual(solver, &combine(&base, &dirs, &a));
            if ra.ratio() < best {
                taken = Some((a, ra));
                break;
            }
        }
        let Some((a, ra)) = taken else { break };
        best = ra.ratio();
        alpha = a;
        r = ra;
    }
    Projection {
        state: combine(&base, &dirs, &alpha),
        weights: alpha,
        residual_nearest,
        residual: best,
    }
}
