//! Linear stage (E−) of one substructure: the trapezoidal march of METHOD §2 driven by the
//! local-stage fields through the search direction F − F̂ = −k (W − Ŵ) (METHOD §3–§4):
//!
//!   S v_m = r_m + Bᵀ A (F̂_m + k Ŵ_m),  r_m = M(2/Δt v + a) − K(u + Δt/2 v),
//!   W_m = B v_m,  F_m = F̂_m + k (Ŵ_m − W_m),
//!
//! with the sums of the error indicator η (METHOD §6) accumulated on the way. A step is a
//! [`predict`] (the micro solve) and a [`complete`]; between the two the two-scale linear stage
//! (METHOD §9) solves its macro problem and passes the correction v_m = v¹ + k Z_E α_E.
//!
//! No product with K is needed in the march: the solve itself gives
//! (Δt/2) K v_m = rhs_m − (2/Δt) M v_m − k Bᵀ A B v_m, and K u_m = K u_{m−1} + (Δt/2) K (v_{m−1} + v_m),
//! so K(u + Δt/2 v) is carried from step to step at O(n) cost (only the triangular solves
//! remain per step; METHOD §11 cost model).

use crate::factor::{CholeskyFactor, SolveScratch};
use crate::interface::Interface;
use crate::state::TraceHistory;
use crate::substructure::Substructure;

/// Kinematic state (u, v, a) of a substructure at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct SubState {
    /// Displacement.
    pub u: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
    /// Acceleration.
    pub a: Vec<f64>,
    /// K u (carried, see the module doc).
    pub ku: Vec<f64>,
    /// (Δt/2) K v (carried).
    pub half_dt_kv: Vec<f64>,
}

impl SubState {
    /// The initial state: u₀ = 0, v₀ given, a₀ = M⁻¹(f_ext,0 − K u₀) = 0 (no interface force at
    /// t₀, no body load).
    pub fn initial(sub: &Substructure, dt: f64) -> Self {
        let n = sub.ndof();
        let v = sub.initial_velocity_field();
        let mut half_dt_kv = vec![0.0; n];
        sub.stiffness.mul_into(&v, &mut half_dt_kv);
        half_dt_kv.iter_mut().for_each(|x| *x *= 0.5 * dt);
        Self {
            u: vec![0.0; n],
            v,
            a: vec![0.0; n],
            ku: vec![0.0; n],
            half_dt_kv,
        }
    }
}

/// Called at every step with (m, state at m, F_m, W_m of the trace).
pub type StepVisitor<'a> = dyn FnMut(usize, &SubState, &[f64], &[f64]) + 'a;

/// Numerator and denominator sums of η² (METHOD §6).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct IndicatorSums {
    /// Σ A [(F − F̂)²/k + k (W − Ŵ)²].
    pub num: f64,
    /// ½ Σ A [(F² + F̂²)/k + k (W² + Ŵ²)].
    pub den: f64,
}

impl IndicatorSums {
    /// Adds another set of sums.
    pub fn add(&mut self, o: IndicatorSums) {
        self.num += o.num;
        self.den += o.den;
    }

    /// η = √(num / den) (0 when both vanish).
    pub fn eta(&self) -> f64 {
        if self.num == 0.0 {
            0.0
        } else {
            (self.num / self.den).sqrt()
        }
    }
}

/// Scratch vectors of one substructure's linear stage, allocated once.
#[derive(Debug)]
pub struct LinearWork {
    /// State marched in place.
    pub state: SubState,
    y: Vec<f64>,
    rhs: Vec<f64>,
    /// F̂ gathered into trace layout for the current step.
    pub fhat: Vec<f64>,
    /// Ŵ gathered into trace layout for the current step.
    pub what: Vec<f64>,
    scratch: SolveScratch,
}

impl LinearWork {
    /// Buffers sized for `sub`.
    pub fn new(sub: &Substructure, factor: &CholeskyFactor, dt: f64) -> Self {
        let n = sub.ndof();
        Self {
            state: SubState::initial(sub, dt),
            y: vec![0.0; n],
            rhs: vec![0.0; n],
            fhat: vec![0.0; sub.trace_len()],
            what: vec![0.0; sub.trace_len()],
            scratch: factor.scratch(),
        }
    }

    /// Gathers ŝ of step m from the interface sides of `sub` into trace layout.
    pub fn gather_hat(
        &mut self,
        sub: &Substructure,
        interfaces: &[Interface],
        hats: &[Vec<TraceHistory>],
        m: usize,
    ) {
        for &(i, side) in &sub.sides {
            let off = interfaces[i].sides[side].offset;
            let h = &hats[i][side];
            let r = h.at(m);
            self.fhat[off..off + h.len].copy_from_slice(&h.f[r.clone()]);
            self.what[off..off + h.len].copy_from_slice(&h.w[r]);
        }
    }
}

/// What the linear stage needs besides the substructure.
pub struct LinearInput<'a> {
    /// All interfaces (for side offsets).
    pub interfaces: &'a [Interface],
    /// ŝ of every interface side.
    pub hats: &'a [Vec<TraceHistory>],
    /// Search direction k (S was factorized with it).
    pub k: f64,
    /// Time step.
    pub dt: f64,
    /// Steps m0..=m1.
    pub steps: (usize, usize),
}

/// Marches steps m0..=m1 from `work.state` (the state at m0 − 1), writing s_new into `out` and
/// returning the η sums over these steps. `visit(m, state, F, W)` sees every step.
pub fn linear_stage(
    sub: &Substructure,
    factor: &CholeskyFactor,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    out: &mut TraceHistory,
    mut visit: Option<&mut StepVisitor<'_>>,
) -> IndicatorSums {
    let (m0, m1) = input.steps;
    let mut sums = IndicatorSums::default();
    for m in m0..=m1 {
        predict(sub, factor, work, input, m);
        sums.add(complete(sub, work, input, m, out, None));
        if let Some(f) = visit.as_mut() {
            let r = out.at(m);
            f(m, &work.state, &out.f[r.clone()], &out.w[r]);
        }
    }
    sums
}

/// Micro solve of step m (METHOD §4; §9 step 1): gathers ŝ_m, forms
/// r_m + Bᵀ A (F̂_m + k Ŵ_m) and solves with S for v¹. Afterwards [`trial_force`] gives
/// F¹ = F̂_m + k (Ŵ_m − B v¹); [`complete`] ends the step.
pub fn predict(
    sub: &Substructure,
    factor: &CholeskyFactor,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    m: usize,
) {
    let (k, dt) = (input.k, input.dt);
    work.gather_hat(sub, input.interfaces, input.hats, m);
    let LinearWork {
        state,
        y,
        rhs,
        fhat,
        what,
        scratch,
    } = work;
    // r_m = M(2/Δt v + a) − K(u + Δt/2 v) + Bᵀ A (F̂ + k Ŵ)
    for i in 0..rhs.len() {
        rhs[i] = sub.mass[i] * (2.0 / dt * state.v[i] + state.a[i])
            - (state.ku[i] + state.half_dt_kv[i]);
    }
    for (j, &d) in sub.trace_dofs.iter().enumerate() {
        rhs[d] += sub.trace_area[j] * (fhat[j] + k * what[j]);
    }
    y.copy_from_slice(rhs);
    factor.solve_in_place(rhs, scratch);
}

/// F¹ = F̂_m + k (Ŵ_m − B v¹) on the trace, after [`predict`] (METHOD §9 step 1).
pub fn trial_force(sub: &Substructure, work: &LinearWork, k: f64, out: &mut [f64]) {
    for (j, &d) in sub.trace_dofs.iter().enumerate() {
        out[j] = work.fhat[j] + k * (work.what[j] - work.rhs[d]);
    }
}

/// The macro correction of one step (METHOD §9 step 4): v_m = v¹ + k Z_E α_E, and the macro
/// velocity Ê α_E that enters the search direction F = F̂ + k (Ŵ + Ê α − W).
#[derive(Debug, Clone, Copy)]
pub struct Correction<'a> {
    /// Z_E = S⁻¹ Bᵀ A Ê, dofs × macro functions, column-major.
    pub z: &'a [f64],
    /// α_E, the macro unknowns of the substructure's interfaces.
    pub alpha: &'a [f64],
    /// Ê α_E on the trace.
    pub macro_trace: &'a [f64],
}

/// Ends step m after [`predict`]: applies the macro correction if any, writes W_m = B v_m and
/// F_m = F̂_m + k (Ŵ_m [+ Ê α] − W_m) into `out`, updates (u, v, a) (METHOD §2) and returns this
/// step's η sums (METHOD §6).
pub fn complete(
    sub: &Substructure,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    m: usize,
    out: &mut TraceHistory,
    correction: Option<Correction<'_>>,
) -> IndicatorSums {
    let (k, dt) = (input.k, input.dt);
    let LinearWork {
        state,
        y,
        rhs,
        fhat,
        what,
        ..
    } = work;
    let n = rhs.len();
    if let Some(c) = &correction {
        // S v = rhs + k Bᵀ A Ê α ⇒ v = v¹ + k Z α; the extra load enters y as well
        for (col, &a) in c.alpha.iter().enumerate() {
            if a != 0.0 {
                let z = &c.z[col * n..(col + 1) * n];
                rhs.iter_mut().zip(z).for_each(|(v, zi)| *v += k * a * zi);
            }
        }
        for (j, &d) in sub.trace_dofs.iter().enumerate() {
            y[d] += k * sub.trace_area[j] * c.macro_trace[j];
        }
    }
    let mut sums = IndicatorSums::default();
    // rhs now holds v_m; y becomes (Δt/2) K v_m = rhs_m − 2/Δt M v_m − k BᵀAB v_m
    for i in 0..n {
        y[i] -= 2.0 / dt * sub.mass[i] * rhs[i];
    }
    let r = out.at(m);
    for (j, &d) in sub.trace_dofs.iter().enumerate() {
        let w = rhs[d];
        let a = sub.trace_area[j];
        y[d] -= k * a * w;
        let macro_w = correction.as_ref().map_or(0.0, |c| c.macro_trace[j]);
        let f = fhat[j] + k * (what[j] + macro_w - w);
        out.w[r.start + j] = w;
        out.f[r.start + j] = f;
        let (df, dw) = (f - fhat[j], w - what[j]);
        sums.num += a * (df * df / k + k * dw * dw);
        sums.den += 0.5 * a * ((f * f + fhat[j] * fhat[j]) / k + k * (w * w + what[j] * what[j]));
    }
    for i in 0..n {
        let v_new = rhs[i];
        let a_new = 2.0 / dt * (v_new - state.v[i]) - state.a[i];
        state.u[i] += 0.5 * dt * (state.v[i] + v_new);
        state.v[i] = v_new;
        state.a[i] = a_new;
        state.ku[i] += state.half_dt_kv[i] + y[i];
        state.half_dt_kv[i] = y[i];
    }
    sums
}
