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
//! [`TwoScale`] owns the macro problem and every buffer the steps use, allocated once when the
//! variant is made; a window allocates only its η sums. In a distributed run each rank marches
//! its substructures; b is summed over the ranks (each macro dof has the two sides of its
//! interface as its only contributions, so the sum is exact), and every rank solves the same
//! replicated macro problem.

use super::linear::{LinearOutcome, Operators};
use crate::counters::Instant;
use crate::linalg::factor::SolveScratch;
use crate::macro_scale::macro_problem::MacroProblem;
use crate::par;
use crate::stages::indicator::IndicatorSums;
use crate::stages::linear_stage::{
    complete, predict, trial_force, Correction, LinearInput, LinearWork, SubState,
};
use crate::state::TraceHistory;

/// One substructure's buffers in the two-scale stage.
#[derive(Debug)]
struct TwoScaleSub {
    work: LinearWork,
    /// F¹ on the trace after step 1; Ê α on the trace after step 4.
    trace: Vec<f64>,
    /// Êᵀ A F¹ after step 1; α_E (its macro unknowns) after step 4.
    macro_local: Vec<f64>,
    /// η sums of the current step.
    sums: IndicatorSums,
}

/// The two-scale linear stage (METHOD §9) with its macro problem.
#[derive(Debug)]
pub(crate) struct TwoScale {
    macro_problem: MacroProblem,
    subs: Vec<TwoScaleSub>,
    /// The macro right-hand side b, then α (global macro dofs).
    macro_rhs: Vec<f64>,
    scratch: SolveScratch,
}

impl TwoScale {
    /// The stage over these buffers and this macro problem (built for the same k).
    pub fn new(works: Vec<LinearWork>, macro_problem: MacroProblem) -> Self {
        let subs = works
            .into_iter()
            .enumerate()
            .map(|(i, work)| TwoScaleSub {
                trace: vec![0.0; work.fhat.len()],
                macro_local: vec![0.0; macro_problem.global[i].len()],
                work,
                sums: IndicatorSums::default(),
            })
            .collect();
        Self {
            macro_rhs: vec![0.0; macro_problem.size],
            scratch: macro_problem.scratch(),
            macro_problem,
            subs,
        }
    }

    /// The macro problem.
    pub fn macro_problem(&self) -> &MacroProblem {
        &self.macro_problem
    }

    /// Forgets every substructure's guess of a single-precision refinement.
    pub fn forget_guesses(&mut self) {
        self.subs.iter_mut().for_each(|b| b.work.forget_guess());
    }

    /// Substructure `i`'s state at the last step of the last run.
    pub fn end_state(&self, i: usize) -> &SubState {
        &self.subs[i].work.state
    }

    /// The work buffers and the macro problem.
    pub fn into_parts(self) -> (Vec<LinearWork>, MacroProblem) {
        (
            self.subs.into_iter().map(|b| b.work).collect(),
            self.macro_problem,
        )
    }

    /// Marches the window of `lin` for all substructures from `starts` (the states at m0 − 1),
    /// writing s_new into `out`.
    pub fn run(
        &mut self,
        ops: Operators<'_>,
        starts: &[SubState],
        lin: &LinearInput<'_>,
        out: &mut [TraceHistory],
    ) -> LinearOutcome {
        let Self {
            macro_problem: mp,
            subs,
            macro_rhs: b,
            scratch,
        } = self;
        for (buf, start) in subs.iter_mut().zip(starts) {
            buf.work.state.clone_from(start);
        }
        let mut outcome = LinearOutcome::default();
        let dist = ops.distribution;
        let (m0, m1) = lin.steps;
        // η sums per step and substructure, added in that order after the window
        let mut step_sums: Vec<Option<IndicatorSums>> =
            Vec::with_capacity((m1 + 1 - m0) * subs.len());
        for m in m0..=m1 {
            // 1. micro solves and macro forces of F¹
            par::for_each_mut(subs, |i, buf| {
                if !dist.holds_sub(i) {
                    return;
                }
                let sub = &ops.subs[i];
                predict(sub, ops.factor(i), &mut buf.work, lin, m);
                trial_force(sub, &buf.work, lin.k, &mut buf.trace);
                buf.macro_local.iter_mut().for_each(|x| *x = 0.0);
                mp.project(i, &sub.trace_area, &buf.trace, &mut buf.macro_local);
            });
            // 2.–3. macro right-hand side and solve
            let t = Instant::now();
            // −0: b_g = −r_a − r_b exactly, on one rank or summed over two ([`crate::distributed::ranks`])
            b.iter_mut().for_each(|x| *x = -0.0);
            for (i, (buf, global)) in subs.iter().zip(&mp.global).enumerate() {
                if dist.holds_sub(i) {
                    for (&g, &r) in global.iter().zip(&buf.macro_local) {
                        b[g] -= r;
                    }
                }
            }
            dist.all_sum(b);
            mp.solve_in_place(b, scratch);
            outcome.macro_s += t.elapsed().as_secs_f64();
            // 4. correction
            let (mp, alpha) = (&*mp, &*b);
            par::for_each_zip_mut(subs, out, |i, buf, out| {
                if !dist.holds_sub(i) {
                    return;
                }
                let sub = &ops.subs[i];
                for (a, &g) in buf.macro_local.iter_mut().zip(&mp.global[i]) {
                    *a = alpha[g];
                }
                mp.expand(i, &buf.macro_local, &mut buf.trace);
                let correction = Correction {
                    z: &mp.homogenized_of(i).z,
                    alpha: &buf.macro_local,
                    macro_trace: &buf.trace,
                };
                buf.sums = complete(sub, &mut buf.work, lin, m, out, Some(correction));
            });
            step_sums.extend(
                subs.iter()
                    .enumerate()
                    .map(|(i, buf)| dist.holds_sub(i).then_some(buf.sums)),
            );
        }
        outcome.sums = dist.gathered_sums(step_sums.into_iter());
        outcome
    }
}
