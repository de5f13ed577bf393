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
//! replicated macro problem. Several configurations of one problem march together
//! ([`TwoScale::run_batched`]): at every step the micro solves of all of them go through each
//! substructure's factor in one pass, then each solves its own macro problem and corrects.

use super::blocks::solve_together;
use super::linear::{BatchInput, LinearOutcome, Operators};
use crate::counters::Instant;
use crate::linalg::factor::{CholeskyFactor, SolveScratch};
use crate::macro_scale::macro_problem::MacroProblem;
use crate::par;
use crate::stages::indicator::IndicatorSums;
use crate::stages::linear_stage::{
    add_guess, complete, form_rhs, predict, trial_force, Correction, LinearInput, LinearWork,
    SubState,
};
use crate::state::TraceHistory;
use crate::substructure::Substructure;

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

impl TwoScaleSub {
    /// Step 1 after the micro solve: F¹ on the trace and its macro forces Êᵀ A F¹.
    fn macro_forces(&mut self, sub: &Substructure, mp: &MacroProblem, i: usize, k: f64) {
        trial_force(sub, &self.work, k, &mut self.trace);
        self.macro_local.iter_mut().for_each(|x| *x = 0.0);
        mp.project(i, &sub.trace_area, &self.trace, &mut self.macro_local);
    }

    /// Step 4 from the macro solution `alpha` (global macro dofs): v_m, W_m, F_m and the state
    /// of step `m` into `out`, the step's η sums kept.
    #[allow(clippy::too_many_arguments)]
    fn correct(
        &mut self,
        sub: &Substructure,
        mp: &MacroProblem,
        i: usize,
        alpha: &[f64],
        lin: &LinearInput<'_>,
        m: usize,
        out: &mut TraceHistory,
    ) {
        for (a, &g) in self.macro_local.iter_mut().zip(&mp.global[i]) {
            *a = alpha[g];
        }
        mp.expand(i, &self.macro_local, &mut self.trace);
        let correction = Correction {
            z: &mp.homogenized_of(i).z,
            alpha: &self.macro_local,
            macro_trace: &self.trace,
        };
        self.sums = complete(sub, &mut self.work, lin, m, out, Some(correction), None);
    }
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
                buf.macro_forces(sub, mp, i, lin.k);
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
                if dist.holds_sub(i) {
                    buf.correct(&ops.subs[i], mp, i, alpha, lin, m, out);
                }
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

/// One substructure of every configuration of a batch ([`TwoScale::run_batched`]): its buffers
/// and s_new per configuration, and the block of right-hand sides solved in one pass.
struct SubBatch<'a> {
    members: Vec<(&'a mut TwoScaleSub, &'a mut TraceHistory)>,
    block: Vec<f64>,
    scratch: Option<SolveScratch>,
}

impl TwoScale {
    /// The two-scale linear stages of several configurations of one problem whose operators S
    /// are the same (they differ only in interface parameters, initial states and loads): at
    /// every step, the micro solves of every configuration marching that step go through each
    /// substructure's factor in one pass (step 1), then each configuration solves its own macro
    /// problem (steps 2–3) and corrects (step 4). Configurations with windows of different
    /// lengths march while they have steps. Every configuration must be on one machine.
    /// Returns each configuration's outcome, as [`Self::run`] would (bit for bit for a lone
    /// configuration: a block of one column is the single solve).
    pub fn run_batched(
        stages: &mut [&mut TwoScale],
        inputs: &[BatchInput<'_>],
        outs: &mut [&mut [TraceHistory]],
    ) -> Vec<LinearOutcome> {
        let lanes = stages.len();
        let subs = inputs.first().map_or(0, |b| b.ops.subs.len());
        let mut by_sub: Vec<SubBatch<'_>> = (0..subs)
            .map(|_| SubBatch {
                members: Vec::with_capacity(lanes),
                block: Vec::new(),
                scratch: None,
            })
            .collect();
        let mut mps: Vec<&MacroProblem> = Vec::with_capacity(lanes);
        let mut rhs: Vec<(&mut Vec<f64>, &mut SolveScratch)> = Vec::with_capacity(lanes);
        for (c, (stage, out)) in stages.iter_mut().zip(outs.iter_mut()).enumerate() {
            let TwoScale {
                macro_problem,
                subs: bufs,
                macro_rhs,
                scratch,
            } = &mut **stage;
            for (i, (buf, o)) in bufs.iter_mut().zip(out.iter_mut()).enumerate() {
                buf.work.state.clone_from(&inputs[c].starts[i]);
                by_sub[i].members.push((buf, o));
            }
            mps.push(macro_problem);
            rhs.push((macro_rhs, scratch));
        }
        let length = |c: usize| inputs[c].lin.steps.1 + 1 - inputs[c].lin.steps.0;
        let longest = (0..lanes).map(length).max().unwrap_or(0);
        let mut outcomes = vec![LinearOutcome::default(); lanes];
        let mut step_sums: Vec<Vec<Option<IndicatorSums>>> = (0..lanes)
            .map(|c| Vec::with_capacity(length(c) * subs))
            .collect();
        for step in 0..longest {
            let marching: Vec<usize> = (0..lanes).filter(|&c| step < length(c)).collect();
            let Some(&first) = marching.first() else {
                break;
            };
            // 1. the micro solves of every configuration in one pass through each factor, and
            // their macro forces
            par::for_each_mut(&mut by_sub, |i, batch| {
                let factor = inputs[first].ops.factor(i);
                predict_together(i, factor, batch, &marching, inputs, step);
                for &c in &marching {
                    let input = &inputs[c];
                    let sub = &input.ops.subs[i];
                    batch.members[c].0.macro_forces(sub, mps[c], i, input.lin.k);
                }
            });
            // 2.–3. each configuration's macro right-hand side and solve
            for &c in &marching {
                let t = Instant::now();
                let (b, scratch) = &mut rhs[c];
                b.iter_mut().for_each(|x| *x = -0.0);
                for (batch, global) in by_sub.iter().zip(&mps[c].global) {
                    for (&g, &r) in global.iter().zip(&batch.members[c].0.macro_local) {
                        b[g] -= r;
                    }
                }
                mps[c].solve_in_place(b, scratch);
                outcomes[c].macro_s += t.elapsed().as_secs_f64();
            }
            // 4. corrections
            let alphas: Vec<&[f64]> = rhs.iter().map(|(b, _)| &b[..]).collect();
            par::for_each_mut(&mut by_sub, |i, batch| {
                for &c in &marching {
                    let input = &inputs[c];
                    let (buf, out) = &mut batch.members[c];
                    let m = input.lin.steps.0 + step;
                    buf.correct(&input.ops.subs[i], mps[c], i, alphas[c], &input.lin, m, out);
                }
            });
            for &c in &marching {
                step_sums[c].extend(by_sub.iter().map(|b| Some(b.members[c].0.sums)));
            }
        }
        for (c, sums) in step_sums.into_iter().enumerate() {
            outcomes[c].sums = inputs[c].ops.distribution.gathered_sums(sums.into_iter());
        }
        outcomes
    }
}

/// Step 1's micro solves of substructure `i` for the configurations `marching` at step `step`
/// of their windows: their right-hand sides solved in one pass through `factor`.
fn predict_together(
    i: usize,
    factor: &CholeskyFactor,
    batch: &mut SubBatch<'_>,
    marching: &[usize],
    inputs: &[BatchInput<'_>],
    step: usize,
) {
    for &c in marching {
        let input = &inputs[c];
        let sub: &Substructure = &input.ops.subs[i];
        let work = &mut batch.members[c].0.work;
        form_rhs(sub, work, &input.lin, input.lin.steps.0 + step, None);
    }
    let works = batch
        .members
        .iter_mut()
        .enumerate()
        .filter(|(c, _)| marching.contains(c))
        .map(|(_, member)| &mut member.0.work);
    solve_together(
        factor,
        works,
        marching.len(),
        &mut batch.block,
        &mut batch.scratch,
    );
    for &c in marching {
        add_guess(&mut batch.members[c].0.work);
    }
}
