//! Linear stage (E−) of one substructure: the march of METHOD §2 (the trapezoidal rule, or its
//! dissipative Bossak–Newmark extension with the coefficients of [`crate::time::time_scheme`]) driven by
//! the local-stage fields through the search direction F − F̂ = −k (W − Ŵ) (METHOD §3–§4):
//!
//!   S v_m = r_m + Bᵀ A (F̂_m + k Ŵ_m),  r_m = M(c_M v + c_A a) − K(u + d_V v + d_A a),
//!   W_m = B v_m,  F_m = F̂_m + k (Ŵ_m − W_m),
//!
//! with the sums of the error indicator η (METHOD §6, [`crate::stages::indicator`]) accumulated on the way. A step is a
//! [`predict`] (the micro solve) and a [`complete`]; between the two the two-scale linear stage
//! (METHOD §9) solves its macro problem and passes the correction v_m = v¹ + k Z_E α_E.
//!
//! Rayleigh damping C = α M + β K adds C v_m to the equilibrium: S becomes
//! (c_M + α) M + (c_K + β) K + k Bᵀ A B and r_m is unchanged ([`crate::elements::rayleigh`]).
//!
//! No product with K is needed in the march: the solve itself gives
//! (c_K + β) K v_m = rhs_m − (c_M + α) M v_m − k Bᵀ A B v_m, hence c_K K v_m, and
//! K u_m = K u_{m−1} + d_V K v_{m−1} + d_A K a_{m−1} + c_K K v_m (trapezoidal:
//! (Δt/2) K (v_{m−1} + v_m)), K a_m = e_V K (v_m − v_{m−1}) − e_A K a_{m−1},
//! so K(u + d_V v + d_A a) is carried from step to step at O(n) cost (only the triangular solves
//! remain per step; METHOD §11 cost model). A factor kept in single precision solves S v = rhs
//! only to its rounding, which the recovered product would carry from step to step: there
//! c_K K v_m is a product with K.
//!
//! A single-precision solve is also refined against S in double: with a guess g of v_m (the v_m
//! of the previous linear stage when it marched the same step of the same window, else v_{m−1};
//! [`crate::stages::refinement`]), v_m = g + S̃⁻¹ (rhs_m − S g), where S g = (c_M + α) M g +
//! (c_K + β) K g + k Bᵀ A B g costs O(n) with K g carried. At LATIN's fixed point v_m = g, so
//! S v_m = rhs_m exactly whatever the rounding of S̃⁻¹: the iteration converges to the solution
//! of the double-precision linear stage, not to that of a neighbouring one.

use crate::interfaces::interface::Interface;
use crate::linalg::factor::{CholeskyFactor, SolveScratch};
use crate::stages::indicator::IndicatorSums;
use crate::stages::refinement::Guesses;
use crate::state::TraceHistory;
use crate::substructure::Substructure;
use crate::time::time_scheme::StepCoefficients;

/// Kinematic state (u, v, a) of a substructure at one step (empty for a substructure held by
/// another rank of a distributed run).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct SubState {
    /// Displacement.
    pub u: Vec<f64>,
    /// Velocity.
    pub v: Vec<f64>,
    /// Acceleration.
    pub a: Vec<f64>,
    /// K u (carried, see the module doc).
    pub ku: Vec<f64>,
    /// c_K K v (carried; (Δt/2) K v for the trapezoidal rule).
    pub ckv: Vec<f64>,
    /// K a (carried for a dissipative scheme; empty for the trapezoidal rule, which needs none).
    pub ka: Vec<f64>,
}

impl SubState {
    /// The initial state: u₀ = 0 (or the preload's static displacement, in equilibrium with its
    /// interface tractions F₀), v₀ given, a₀ = M⁻¹(f_ext,0 − K u₀ + Bᵀ A F₀ − C v₀) = −M⁻¹ C v₀
    /// (no body load; 0 without damping).
    pub fn initial(sub: &Substructure, time: &StepCoefficients) -> Self {
        let n = sub.ndof();
        let v = sub.initial_velocity_field();
        let (u, ku) = match &sub.prestress {
            Some(p) => {
                let mut ku = vec![0.0; n];
                sub.stiffness.mul_into(&p.displacement, &mut ku);
                (p.displacement.clone(), ku)
            }
            None => (vec![0.0; n], vec![0.0; n]),
        };
        let mut kv = vec![0.0; n];
        sub.stiffness.mul_into(&v, &mut kv);
        let d = sub.material.damping;
        let mut a = vec![0.0; n];
        let mut ka = if time.trapezoidal {
            Vec::new()
        } else {
            vec![0.0; n]
        };
        if !d.is_none() {
            for i in 0..n {
                a[i] = -(d.alpha * v[i] + d.beta * kv[i] / sub.mass[i]);
            }
            if !time.trapezoidal {
                sub.stiffness.mul_into(&a, &mut ka);
            }
        }
        kv.iter_mut().for_each(|x| *x *= time.stiffness);
        Self {
            u,
            v,
            a,
            ku,
            ckv: kv,
            ka,
        }
    }
}

/// Called at every step with (m, state at m, F_m, W_m of the trace).
pub type StepVisitor<'a> = dyn FnMut(usize, &SubState, &[f64], &[f64]) + 'a;

/// Scratch vectors of one substructure's linear stage, allocated once.
#[derive(Debug)]
pub struct LinearWork {
    /// State marched in place.
    pub state: SubState,
    /// The right-hand side of step m, r_m + Bᵀ A (F̂_m + k Ŵ_m), solved in place by [`predict`]:
    /// v¹ after it, then v_m after [`complete`] applies the macro correction.
    rhs_then_v: Vec<f64>,
    /// A copy of the right-hand side of step m (plus the macro load), reduced by [`complete`] to
    /// c_K K v_m, which the next step's right-hand side needs (see the module doc).
    rhs_then_ckv: Vec<f64>,
    /// F̂ gathered into trace layout for the current step.
    pub fhat: Vec<f64>,
    /// Ŵ gathered into trace layout for the current step.
    pub what: Vec<f64>,
    scratch: SolveScratch,
    /// The factor keeps single precision: c_K K v_m is computed from K, not from the solve,
    /// and each solve is refined from a guess (see the module doc).
    single: bool,
    /// The guesses of the refinement, a slot a step of the window (single precision only).
    guesses: Guesses,
}

impl LinearWork {
    /// Buffers sized for `sub`.
    pub fn new(sub: &Substructure, factor: &CholeskyFactor, time: &StepCoefficients) -> Self {
        let n = sub.ndof();
        Self {
            state: SubState::initial(sub, time),
            rhs_then_v: vec![0.0; n],
            rhs_then_ckv: vec![0.0; n],
            fhat: vec![0.0; sub.trace_len()],
            what: vec![0.0; sub.trace_len()],
            scratch: factor.scratch(),
            single: factor.is_single(),
            guesses: Guesses::default(),
        }
    }

    /// No buffers: a substructure held by another rank of a distributed run
    /// ([`crate::distributed::distribution`]).
    pub fn idle() -> Self {
        Self {
            state: SubState::default(),
            rhs_then_v: Vec::new(),
            rhs_then_ckv: Vec::new(),
            fhat: Vec::new(),
            what: Vec::new(),
            scratch: SolveScratch::none(),
            single: false,
            guesses: Guesses::default(),
        }
    }

    /// Forgets the guesses of a single-precision solve's refinement, so that a new solve does
    /// not depend on what this substructure solved before.
    pub fn forget_guess(&mut self) {
        self.guesses.forget();
    }

    /// The right-hand side [`form_rhs`] formed, to be replaced by its solution v¹ before
    /// [`complete`].
    pub fn rhs_mut(&mut self) -> &mut [f64] {
        &mut self.rhs_then_v
    }

    /// With a single-precision factor, keeps the solution of step m just found and its
    /// c_K K v (in the buffer the next [`form_rhs`] refills) as the guess a second solve of
    /// that step refines from ([`predict_refined`]); returns whether it did (false in double
    /// precision, where one solve is exact).
    pub fn keep_as_guess(&mut self, sub: &Substructure, input: &LinearInput<'_>, m: usize) -> bool {
        if !self.single {
            return false;
        }
        let LinearWork {
            rhs_then_v: v,
            rhs_then_ckv: ckv,
            guesses,
            ..
        } = self;
        sub.stiffness.mul_into(v, ckv);
        let ck = input.time.stiffness;
        ckv.iter_mut().for_each(|x| *x *= ck);
        guesses.store(m, input.steps.0, v, ckv);
        true
    }

    /// Replaces the right-hand side [`form_rhs`] formed by its solution with `factor`, S's.
    pub fn solve_in_place(&mut self, factor: &CholeskyFactor) {
        factor.solve_in_place(&mut self.rhs_then_v, &mut self.scratch);
    }

    /// Gathers ŝ of step m from the interface sides of `sub` into trace layout.
    pub fn gather_hat(
        &mut self,
        sub: &Substructure,
        interfaces: &[Interface],
        hats: &[Vec<TraceHistory>],
        m: usize,
    ) {
        for side in &sub.sides {
            let off = interfaces[side.interface].sides[side.side].offset;
            let h = &hats[side.interface][side.side];
            let r = h.at(m);
            self.fhat[off..off + h.len].copy_from_slice(&h.f[r.clone()]);
            self.what[off..off + h.len].copy_from_slice(&h.w[r]);
        }
    }
}

/// What the linear stage needs besides the substructure.
#[derive(Clone, Copy)]
pub struct LinearInput<'a> {
    /// All interfaces (for side offsets).
    pub interfaces: &'a [Interface],
    /// ŝ of every interface side.
    pub hats: &'a [Vec<TraceHistory>],
    /// Search direction k (S was factorized with it).
    pub k: f64,
    /// The time step and the scheme's coefficients (S was factorized with them).
    pub time: StepCoefficients,
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
    visit: Option<&mut StepVisitor<'_>>,
) -> IndicatorSums {
    march(sub, factor, work, input, out, visit, predict)
}

/// The march of [`linear_stage`] with the micro solve `solve`: [`predict`], or
/// [`predict_refined`] for a replay, which has no iteration to refine a single-precision solve
/// over.
pub fn march(
    sub: &Substructure,
    factor: &CholeskyFactor,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    out: &mut TraceHistory,
    mut visit: Option<&mut StepVisitor<'_>>,
    solve: fn(&Substructure, &CholeskyFactor, &mut LinearWork, &LinearInput<'_>, usize),
) -> IndicatorSums {
    let (m0, m1) = input.steps;
    let mut sums = IndicatorSums::default();
    for m in m0..=m1 {
        solve(sub, factor, work, input, m);
        sums.add(complete(sub, work, input, m, out, None, None));
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
    form_rhs(sub, work, input, m, None);
    work.solve_in_place(factor);
    add_guess(work);
}

/// [`predict`], refined once more from its solution where the factor keeps single precision (a
/// second solve and a product with K): v_m to double-precision accuracy in one step.
pub fn predict_refined(
    sub: &Substructure,
    factor: &CholeskyFactor,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    m: usize,
) {
    predict(sub, factor, work, input, m);
    if work.keep_as_guess(sub, input, m) {
        predict(sub, factor, work, input, m);
    }
}

/// [`predict`] without its solve: gathers ŝ_m and forms r_m + Bᵀ A (F̂_m + k Ŵ_m) in
/// [`LinearWork::rhs_mut`] (less S g for a single-precision factor), where a caller solving
/// several right-hand sides through one pass of the factor puts the solution back and calls
/// [`add_guess`] before [`complete`].
///
/// With `prev` the state at m − 1 is read from there instead of the work's own state (the first
/// step of a window, whose start the march then need not copy; [`complete`] with it ends it).
pub fn form_rhs(
    sub: &Substructure,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    m: usize,
    prev: Option<&SubState>,
) {
    let (k, c) = (input.k, &input.time);
    work.gather_hat(sub, input.interfaces, input.hats, m);
    let LinearWork {
        state,
        rhs_then_ckv: y,
        rhs_then_v: rhs,
        fhat,
        what,
        ..
    } = work;
    let state = prev.unwrap_or(state);
    // r_m = M(c_M v + c_A a) − K(u + d_V v + d_A a) + Bᵀ A (F̂ + k Ŵ)
    let n = rhs.len();
    let (rhs, mass) = (&mut rhs[..n], &sub.mass[..n]);
    let (v, a, ku, ckv) = (
        &state.v[..n],
        &state.a[..n],
        &state.ku[..n],
        &state.ckv[..n],
    );
    let c_mass = c.mass;
    if c.trapezoidal {
        for i in 0..n {
            rhs[i] = mass[i] * (c_mass * v[i] + a[i]) - (ku[i] + ckv[i]);
        }
    } else {
        let ka = &state.ka[..n];
        let (ratio, mass_a, u_from_a) = (c.u_from_v / c.stiffness, c.mass_a, c.u_from_a);
        for i in 0..n {
            rhs[i] = mass[i] * (c_mass * v[i] + mass_a * a[i])
                - (ku[i] + ratio * ckv[i] + u_from_a * ka[i]);
        }
    }
    for j in 0..sub.trace_len() {
        let x = sub.trace_area[j] * (fhat[j] + k * sub.trace_k[j] * what[j]);
        sub.add_trace(j, x, rhs);
    }
    y.copy_from_slice(rhs);
    if work.single {
        subtract_guess(sub, work, k, c, (m, input.steps.0), prev);
    }
}

/// rhs_m −= S g for the refinement of a single-precision solve (module doc): g the previous
/// linear stage's v_m when it marched step m of the window starting at m0, else v_{m−1} from
/// `prev` or the state.
fn subtract_guess(
    sub: &Substructure,
    work: &mut LinearWork,
    k: f64,
    c: &StepCoefficients,
    (m, m0): (usize, usize),
    prev: Option<&SubState>,
) {
    let n = work.rhs_then_v.len();
    let LinearWork {
        rhs_then_v: rhs,
        guesses,
        state,
        ..
    } = work;
    let state = prev.unwrap_or(state);
    let (g, ckg) = guesses.take(m, m0, (&state.v, &state.ckv));
    let (cm, ck) = sub.operator_coefficients(c);
    let scale = ck / c.stiffness;
    for i in 0..n {
        rhs[i] -= cm * sub.mass[i] * g[i] + scale * ckg[i];
    }
    for j in 0..sub.trace_len() {
        let w = sub.trace_value(j, g);
        sub.add_trace(j, -k * sub.trace_k[j] * sub.trace_area[j] * w, rhs);
    }
}

/// After the solve of [`form_rhs`]'s right-hand side: v = g + the solution for a
/// single-precision factor (module doc); nothing otherwise.
pub fn add_guess(work: &mut LinearWork) {
    if let Some(g) = work.guesses.take_current() {
        work.rhs_then_v.iter_mut().zip(g).for_each(|(v, g)| *v += g);
    }
}

/// F¹ = F̂_m + k (Ŵ_m − B v¹) on the trace, after [`predict`] (METHOD §9 step 1).
pub fn trial_force(sub: &Substructure, work: &LinearWork, k: f64, out: &mut [f64]) {
    for j in 0..sub.trace_len() {
        let w = sub.trace_value(j, &work.rhs_then_v);
        out[j] = work.fhat[j] + k * sub.trace_k[j] * (work.what[j] - w);
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
/// step's η sums (METHOD §6). With `prev` (after [`form_rhs`] with it) the state at m − 1
/// is read from there and the work's state becomes the state at m without having held it.
pub fn complete(
    sub: &Substructure,
    work: &mut LinearWork,
    input: &LinearInput<'_>,
    m: usize,
    out: &mut TraceHistory,
    correction: Option<Correction<'_>>,
    prev: Option<&SubState>,
) -> IndicatorSums {
    let (k, c) = (input.k, &input.time);
    let single = work.single;
    let LinearWork {
        state,
        rhs_then_ckv: y,
        rhs_then_v: rhs,
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
        for j in 0..sub.trace_len() {
            let x = k * sub.trace_k[j] * sub.trace_area[j] * c.macro_trace[j];
            sub.add_trace(j, x, y);
        }
    }
    let mut sums = IndicatorSums::default();
    // rhs now holds v_m; y becomes (c_K + β) K v_m = rhs_m − (c_M + α) M v_m − k BᵀAB v_m
    let (cm, ck) = sub.operator_coefficients(c);
    let mass = &sub.mass[..n];
    for (yi, (&mi, &vi)) in y[..n].iter_mut().zip(mass.iter().zip(&rhs[..n])) {
        *yi -= cm * mi * vi;
    }
    let r = out.at(m);
    for j in 0..sub.trace_len() {
        let w = sub.trace_value(j, rhs);
        let (a, kj) = (sub.trace_area[j], k * sub.trace_k[j]);
        sub.add_trace(j, -kj * a * w, y);
        let macro_w = correction.as_ref().map_or(0.0, |c| c.macro_trace[j]);
        let f = fhat[j] + kj * (what[j] + macro_w - w);
        out.w[r.start + j] = w;
        out.f[r.start + j] = f;
        sums.add_dof(a, kj, (f, w), (fhat[j], what[j]));
    }
    if single {
        // a single-precision factor solves S v = rhs only to its rounding: c_K K v_m from K
        sub.stiffness.mul_into(rhs, y);
        y.iter_mut().for_each(|x| *x *= c.stiffness);
    } else if ck != c.stiffness {
        // damped by β: c_K K v_m from (c_K + β) K v_m
        let scale = c.stiffness / ck;
        y.iter_mut().for_each(|x| *x *= scale);
    }
    // K u_m = K u + d_V K v + d_A K a + c_K K v_m; K a_m = e_V K (v_m − v) − e_A K a (carried
    // only for a dissipative scheme; the trapezoidal rule keeps its formulas as written)
    if c.trapezoidal {
        advance_all::<true>(c, state, prev, rhs, y);
    } else {
        advance_all::<false>(c, state, prev, rhs, y);
    }
    if single {
        // the next linear stage's guess of this step
        let LinearWork { guesses, state, .. } = work;
        guesses.store(m, input.steps.0, &state.v, &state.ckv);
    }
    sums
}

/// The state at m in `next` from the one at m − 1 (`prev`, else `next` itself), v_m (`v_new`)
/// and c_K K v_m (`y`), dof by dof ([`advance_dof`]), for a scheme known to be the trapezoidal
/// rule or not: slices of one length and no branch, so that the loop runs in vector registers.
#[inline(always)]
fn advance_all<const TRAPEZOIDAL: bool>(
    c: &StepCoefficients,
    next: &mut SubState,
    prev: Option<&SubState>,
    v_new: &[f64],
    y: &[f64],
) {
    let n = v_new.len();
    let (c, ka_len) = (*c, if TRAPEZOIDAL { 0 } else { n });
    let carried = (c.u_from_v / c.stiffness, c.a_from_dv / c.stiffness);
    let (v_new, y) = (&v_new[..n], &y[..n]);
    let SubState {
        u,
        v,
        a,
        ku,
        ckv,
        ka,
    } = next;
    let (u, v, a) = (&mut u[..n], &mut v[..n], &mut a[..n]);
    let (ku, ckv, ka) = (&mut ku[..n], &mut ckv[..n], &mut ka[..ka_len]);
    // the loop over dofs, reading the state at m − 1 from the given slices
    macro_rules! advance_from {
        ($u0:expr, $v0:expr, $a0:expr, $ku0:expr, $ckv0:expr, $ka0:expr) => {
            for i in 0..n {
                let ka_i = if TRAPEZOIDAL { 0.0 } else { $ka0[i] };
                let from = [$u0[i], $v0[i], $a0[i], $ku0[i], $ckv0[i], ka_i];
                let to = advance_dof::<TRAPEZOIDAL>(&c, carried, from, v_new[i], y[i]);
                [u[i], v[i], a[i], ku[i], ckv[i]] = [to[0], to[1], to[2], to[3], to[4]];
                if !TRAPEZOIDAL {
                    ka[i] = to[5];
                }
            }
        };
    }
    match prev {
        None => advance_from!(u, v, a, ku, ckv, ka),
        Some(p) => {
            let (pu, pv, pa) = (&p.u[..n], &p.v[..n], &p.a[..n]);
            let (pku, pckv, pka) = (&p.ku[..n], &p.ckv[..n], &p.ka[..ka_len]);
            advance_from!(pu, pv, pa, pku, pckv, pka)
        }
    }
}

/// One dof's (u, v, a, K u, c_K K v, K a) at m from those at m − 1, v_m and c_K K v_m (`y`),
/// with `(ratio, dk)` = (d_V / c_K, e_V / c_K): the Newmark update and the carried products of
/// the module doc (K a only for a dissipative scheme; the trapezoidal rule's formulas as written).
#[inline(always)]
fn advance_dof<const TRAPEZOIDAL: bool>(
    c: &StepCoefficients,
    (ratio, dk): (f64, f64),
    [u, v, a, ku, ckv, ka]: [f64; 6],
    v_new: f64,
    y: f64,
) -> [f64; 6] {
    let (u_new, a_new) = c.advance_as::<TRAPEZOIDAL>(u, v, a, v_new);
    if TRAPEZOIDAL {
        [u_new, v_new, a_new, ku + (ckv + y), y, ka]
    } else {
        let ku_new = ku + (ratio * ckv + c.u_from_a * ka + y);
        let ka_new = dk * (y - ckv) - c.a_from_a * ka;
        [u_new, v_new, a_new, ku_new, y, ka_new]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene;

    /// Solves A x = b by Gaussian elimination with partial pivoting (dense, A row-major n×n).
    fn dense_solve(mut a: Vec<f64>, mut b: Vec<f64>) -> Vec<f64> {
        let n = b.len();
        for c in 0..n {
            let p = (c..n)
                .max_by(|&i, &j| a[i * n + c].abs().total_cmp(&a[j * n + c].abs()))
                .unwrap_or(c);
            if p != c {
                for j in 0..n {
                    a.swap(c * n + j, p * n + j);
                }
                b.swap(c, p);
            }
            for r in c + 1..n {
                let l = a[r * n + c] / a[c * n + c];
                for j in c..n {
                    a[r * n + j] -= l * a[c * n + j];
                }
                b[r] -= l * b[c];
            }
        }
        for c in (0..n).rev() {
            let s: f64 = (c + 1..n).map(|j| a[c * n + j] * b[j]).sum();
            b[c] = (b[c] - s) / a[c * n + c];
        }
        b
    }

    /// A reproducible stream of numbers in [−1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }

    /// Three steps of the linear stage of the `bar` scene's first substructure (60 dofs, a
    /// boundary and a perfect interface on its trace) driven by random ŝ, against a dense solve
    /// of the same steps: S v_m = M(c_M v + c_A a) − K(u + d_V v + d_A a) + Bᵀ A (F̂ + k Ŵ) with
    /// S = c_M M + c_K K + k Bᵀ A B formed densely and solved by Gaussian elimination (METHOD §2,
    /// §4), for the trapezoidal rule and the dissipative scheme (ρ∞ = 0.7). Also checks the
    /// discrete equation of motion M [(1 − α_m) a_m + α_m a_{m−1}] + K u_m = Bᵀ A F_m, the search
    /// direction F − F̂ = −k (W − Ŵ), the carried K u (module doc) and the Newmark kinematics at
    /// every step.
    #[test]
    fn linear_stage_matches_a_dense_solve() {
        for rho in [1.0, 0.7] {
            dense_check(crate::time::time_scheme::TimeScheme::new(rho));
        }
    }

    fn dense_check(scheme: crate::time::time_scheme::TimeScheme) {
        let spec = scene::load("bar").expect("scene");
        let problem = scene::problem_of(&spec, "bar").expect("build");
        let sub = &problem.subs[0];
        let (n, dt, k) = (sub.ndof(), problem.time.dt, problem.default_k());
        let c = scheme.coefficients(dt);
        let (alpha_m, gamma, _) = scheme.parameters();
        assert_eq!(n, 60);
        assert!(
            sub.sides.len() >= 2,
            "a boundary and an interface on the trace"
        );
        let factor = CholeskyFactor::new(n, &sub.operator_triplets(&c, k)).expect("factor");
        let steps = 3;
        let mut seed = 7;
        let scale_f = 1e6;
        let hats: Vec<Vec<TraceHistory>> = problem
            .interfaces
            .iter()
            .map(|i| {
                i.sides
                    .iter()
                    .map(|_| {
                        let mut h = TraceHistory::zeros(i.len, problem.time.steps);
                        h.f.iter_mut().for_each(|x| *x = scale_f * noise(&mut seed));
                        h.w.iter_mut().for_each(|x| *x = noise(&mut seed));
                        h
                    })
                    .collect()
            })
            .collect();
        let input = LinearInput {
            interfaces: &problem.interfaces,
            hats: &hats,
            k,
            time: c,
            steps: (1, steps),
        };
        let mut work = LinearWork::new(sub, &factor, &c);
        // a non-trivial start: the initial velocity field plus noise in u and v
        let start = {
            let mut s = SubState::initial(sub, &c);
            s.u.iter_mut().for_each(|x| *x = 1e-6 * noise(&mut seed));
            s.v.iter_mut().for_each(|x| *x += noise(&mut seed));
            sub.stiffness.mul_into(&s.u, &mut s.ku);
            sub.stiffness.mul_into(&s.v, &mut s.ckv);
            s.ckv.iter_mut().for_each(|x| *x *= c.stiffness);
            s
        };
        work.state = start.clone();
        let mut out = TraceHistory::zeros(sub.trace_len(), problem.time.steps);
        let mut states = Vec::new();
        linear_stage(
            sub,
            &factor,
            &mut work,
            &input,
            &mut out,
            Some(&mut |_, st: &SubState, _: &[f64], _: &[f64]| states.push(st.clone())),
        );
        // dense K and S
        let mut kd = vec![0.0; n * n];
        let mut col = vec![0.0; n];
        let mut e = vec![0.0; n];
        for j in 0..n {
            e[j] = 1.0;
            sub.stiffness.mul_into(&e, &mut col);
            e[j] = 0.0;
            for i in 0..n {
                kd[i * n + j] = col[i];
            }
        }
        let mut sd: Vec<f64> = kd.iter().map(|x| c.stiffness * x).collect();
        for i in 0..n {
            sd[i * n + i] += c.mass * sub.mass[i];
        }
        for (j, &d) in sub.trace_dofs.iter().enumerate() {
            sd[d * n + d] += k * sub.trace_area[j];
        }
        let kmul = |x: &[f64]| -> Vec<f64> {
            (0..n)
                .map(|i| (0..n).map(|j| kd[i * n + j] * x[j]).sum())
                .collect()
        };
        let rel = |a: &[f64], b: &[f64]| {
            let d = a
                .iter()
                .zip(b)
                .map(|(x, y)| (x - y).abs())
                .fold(0.0, f64::max);
            d / b.iter().map(|x| x.abs()).fold(f64::MIN_POSITIVE, f64::max)
        };
        let mut prev = start;
        let mut ghat = LinearWork::new(sub, &factor, &c);
        for m in 1..=steps {
            ghat.gather_hat(sub, &problem.interfaces, &hats, m);
            let (fhat, what) = (&ghat.fhat, &ghat.what);
            let kpre: Vec<f64> = prev
                .u
                .iter()
                .zip(&prev.v)
                .zip(&prev.a)
                .map(|((u, v), a)| u + c.u_from_v * v + c.u_from_a * a)
                .collect();
            let kpre = kmul(&kpre);
            let mut rhs: Vec<f64> = (0..n)
                .map(|i| sub.mass[i] * (c.mass * prev.v[i] + c.mass_a * prev.a[i]) - kpre[i])
                .collect();
            for (j, &d) in sub.trace_dofs.iter().enumerate() {
                rhs[d] += sub.trace_area[j] * (fhat[j] + k * what[j]);
            }
            let v = dense_solve(sd.clone(), rhs);
            let st = &states[m - 1];
            assert!(rel(&st.v, &v) < 1e-10, "step {m}: v {}", rel(&st.v, &v));
            // search direction and W = B v on the trace
            let r = out.at(m);
            for (j, &d) in sub.trace_dofs.iter().enumerate() {
                let (f, w) = (out.f[r.start + j], out.w[r.start + j]);
                assert!((w - st.v[d]).abs() <= 1e-12 * st.v[d].abs().max(1.0));
                assert!((f - fhat[j] + k * (w - what[j])).abs() <= 1e-9 * scale_f);
            }
            // M a + K u = Bᵀ A F, and the carried K u
            let ku = kmul(&st.u);
            assert!(
                rel(&st.ku, &ku) < 1e-10,
                "step {m}: K u {}",
                rel(&st.ku, &ku)
            );
            let mut force = vec![0.0; n];
            for (j, &d) in sub.trace_dofs.iter().enumerate() {
                force[d] += sub.trace_area[j] * out.f[r.start + j];
            }
            let lhs: Vec<f64> = (0..n)
                .map(|i| sub.mass[i] * ((1.0 - alpha_m) * st.a[i] + alpha_m * prev.a[i]) + ku[i])
                .collect();
            assert!(
                rel(&lhs, &force) < 1e-9,
                "step {m}: motion {}",
                rel(&lhs, &force)
            );
            // Newmark kinematics (trapezoidal for ρ∞ = 1)
            let beta = scheme.parameters().2;
            for i in 0..n {
                let du = prev.u[i]
                    + dt * prev.v[i]
                    + dt * dt * ((0.5 - beta) * prev.a[i] + beta * st.a[i])
                    - st.u[i];
                let dv = prev.v[i] + dt * ((1.0 - gamma) * prev.a[i] + gamma * st.a[i]) - st.v[i];
                assert!(du.abs() <= 1e-12 * st.u[i].abs().max(1e-9));
                assert!(dv.abs() <= 1e-10 * st.v[i].abs().max(1.0));
            }
            prev = st.clone();
        }
    }
}
