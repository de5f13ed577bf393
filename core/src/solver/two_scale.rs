//! The two-scale linear stage over a time window (METHOD §9 "Per time step"): all substructures
//! march in lock-step, and at every step m
//!
//! 1. micro solve (parallel): v¹ = S⁻¹ (r_m + Bᵀ A (F̂_m + k Ŵ_m)), F¹ = F̂_m + k (Ŵ_m − B v¹);
//! 2. macro right-hand side b = −Σ_E assemble(Êᵀ A F¹);
//! 3. macro solve L α = b;
//! 4. correction (parallel): v_m = v¹ + k Z_E α_E, W_m = B v_m,
//!    F_m = F̂_m + k (Ŵ_m + Ê α_E − W_m), then u_m, a_m.
//!
//! After step 4 the macro forces balance on every internal interface: Êᵀ A F_E + Êᵀ A F_E' = 0.

use crate::counters::Instant;
use crate::factor::CholeskyFactor;
use crate::linear_stage::{
    complete, predict, trial_force, Correction, IndicatorSums, LinearInput, LinearWork, SubState,
};
use crate::macro_problem::MacroProblem;
use crate::operator_classes::Classes;
use crate::par;
use crate::state::TraceHistory;
use crate::substructure::Substructure;

/// Per-substructure buffers of the macro steps.
struct MacroWork<'a> {
    /// Global macro dof of each macro unknown of the substructure.
    global: &'a [usize],
    /// F¹ on the trace, then Ê α on the trace.
    trace: Vec<f64>,
    /// Êᵀ A F¹, then α_E.
    local: Vec<f64>,
}

/// What the two-scale stage needs besides the per-substructure buffers.
pub(super) struct TwoScale<'a> {
    pub subs: &'a [Substructure],
    pub classes: &'a Classes,
    pub factors: &'a [CholeskyFactor],
    pub macro_problem: &'a MacroProblem,
}

/// Marches the window of `lin` for all substructures from `states` (the state at m0 − 1),
/// writing s_new into `out`. Returns the η sums and the seconds spent in steps 2–3.
pub(super) fn linear_stage_two_scale(
    ts: &TwoScale<'_>,
    works: &mut [LinearWork],
    states: &[SubState],
    lin: &LinearInput<'_>,
    out: &mut [TraceHistory],
) -> (IndicatorSums, f64) {
    let mp = ts.macro_problem;
    let mut macro_works: Vec<MacroWork> = ts
        .subs
        .iter()
        .enumerate()
        .map(|(i, sub)| {
            let global = &mp.global[i];
            MacroWork {
                local: vec![0.0; global.len()],
                global,
                trace: vec![0.0; sub.trace_len()],
            }
        })
        .collect();
    let mut bundle: Vec<(&mut LinearWork, &mut MacroWork, &mut TraceHistory)> = works
        .iter_mut()
        .zip(macro_works.iter_mut())
        .zip(out.iter_mut())
        .map(|((w, m), o)| (w, m, o))
        .collect();
    for (i, (w, _, _)) in bundle.iter_mut().enumerate() {
        w.state.clone_from(&states[i]);
    }
    let mut b = vec![0.0; mp.size];
    let mut scratch = mp.scratch();
    let mut sums = IndicatorSums::default();
    let mut macro_s = 0.0;
    let (m0, m1) = lin.steps;
    for m in m0..=m1 {
        // 1. micro solves and macro forces of F¹
        par::map_mut(&mut bundle, |i, (work, mw, _)| {
            let sub = &ts.subs[i];
            predict(sub, &ts.factors[ts.classes.of[i]], work, lin, m);
            trial_force(sub, work, lin.k, &mut mw.trace);
            mw.local.iter_mut().for_each(|x| *x = 0.0);
            mp.project(i, &sub.trace_area, &mw.trace, &mut mw.local);
        });
        // 2.–3. macro right-hand side and solve
        let t = Instant::now();
        b.iter_mut().for_each(|x| *x = 0.0);
        for (_, mw, _) in &bundle {
            for (&g, &r) in mw.global.iter().zip(&mw.local) {
                b[g] -= r;
            }
        }
        mp.solve_in_place(&mut b, &mut scratch);
        macro_s += t.elapsed().as_secs_f64();
        // 4. correction
        let b = &b;
        let step_sums = par::map_mut(&mut bundle, |i, (work, mw, out)| {
            let sub = &ts.subs[i];
            for (a, &g) in mw.local.iter_mut().zip(mw.global) {
                *a = b[g];
            }
            mp.expand(i, &mw.local, &mut mw.trace);
            let correction = Correction {
                z: &mp.homogenized_of(i).z,
                alpha: &mw.local,
                macro_trace: &mw.trace,
            };
            complete(sub, work, lin, m, out, Some(correction))
        });
        step_sums.into_iter().for_each(|s| sums.add(s));
    }
    (sums, macro_s)
}
