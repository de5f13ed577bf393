//! Configurations of one problem solved together (METHOD §4, §8, §11). The parameters a study
//! moves (friction, gaps, initial velocities, load amplitudes and times, preloads) enter the
//! interface laws, the initial states and the loads, never the substructure operators S, so
//! every configuration can use the same factorizations. A [`Lane`] is one configuration's
//! solver ([`Solver::lane`]: its own problem, settings, buffers and solve in progress, the
//! factorizations shared); [`step_together`] runs one LATIN iteration of several lanes: each
//! lane's local stage, then one linear stage for all of them in which every substructure solves
//! the right-hand sides of all lanes at one step in one pass through its factor (the triangular
//! solves are bound by reading the factor from memory, so B columns cost far less than B
//! solves), then each lane's indicator, relaxation and end of window. A lane that converged
//! leaves the batch; another configuration may take its place at once (lanes need not be at
//! the same window or iteration).
//!
//! Lanes on the two-scale stage (METHOD §9) march together likewise, each solving its own macro
//! problem between the shared micro solves of a step; single-scale and two-scale lanes of one
//! batch form two groups. Each lane reaches the iterates it would reach alone up to the rounding
//! of the blocked solve (bit for bit when it marches alone). Lanes whose factorizations are no
//! longer shared (one changed its k or scheme) march each on its own in the same iteration.

use std::sync::Arc;

use super::linear::{BatchInput, LinearOutcome, Operators};
use super::{new_linear_stage, Control, Iterate, LinearStage, SolveRun, Solver};
use crate::counters::{Counters, Instant};
use crate::error::{LopinError, Result};
use crate::state::TraceHistory;

/// One configuration of a batch: its solver and its solve in progress.
pub struct Lane<'a> {
    /// The configuration's solver (made by [`Solver::lane`] from the batch's first).
    pub solver: &'a mut Solver,
    /// Its solve in progress ([`Solver::begin`]).
    pub run: &'a mut SolveRun,
}

impl Solver {
    /// A solver of another configuration of this problem that shares this solver's
    /// factorizations: the problem and its parameters as they are now (set it with
    /// [`Self::set_parameter_in`]), the settings, fresh buffers and counters. Only on one
    /// machine (a distributed solver's lanes would need ranks of their own).
    pub fn lane(&self) -> Result<Solver> {
        if !self.distribution.is_single() {
            return Err(LopinError::setting(
                "batch",
                "configurations solved together share one machine's factorizations: a \
                 distributed run solves them one at a time",
            ));
        }
        let two_scale = matches!(self.linear, LinearStage::TwoScale(_));
        let linear = new_linear_stage(
            &self.problem,
            &self.classes,
            &self.factors,
            &self.distribution,
            two_scale.then_some(self.settings.k),
        )?;
        Ok(Solver {
            problem: self.problem.clone(),
            settings: self.settings,
            classes: self.classes.clone(),
            factors: Arc::clone(&self.factors),
            distribution: self.distribution.clone(),
            linear,
            spare_macro: None,
            counters: Counters::default(),
            preload: self.preload,
        })
    }

    /// Whether `other` uses the same factorizations (a lane of this solver that has not
    /// refactorized since).
    pub fn shares_factors(&self, other: &Solver) -> bool {
        Arc::ptr_eq(&self.factors, &other.factors)
    }
}

/// One LATIN iteration of every lane whose solve has not ended, the linear stages of the lanes
/// of one variant (single- or two-scale) that share the first such lane's factorizations
/// marched together (module doc). `observer(l, iterate)` sees lane `l`'s iterate as [`Solver::step`] shows it.
/// Returns, per lane, whether its solve has ended.
pub fn step_together(
    lanes: &mut [Lane<'_>],
    observer: &mut dyn FnMut(usize, &Iterate<'_>) -> Control,
) -> Vec<bool> {
    let begun: Vec<_> = lanes
        .iter_mut()
        .map(|l| l.solver.iteration_local(l.run))
        .collect();
    let t_linear = Instant::now();
    // the lanes that march together: those of the first lane's variant of the linear stage on
    // its factorizations, and likewise for the first lane of the other variant
    let mut group: Vec<Option<usize>> = vec![None; lanes.len()];
    for l in 0..lanes.len() {
        if begun[l].is_none() {
            continue;
        }
        let linear = &lanes[l].solver.linear;
        let leader =
            (0..l).find(|&f| group[f] == Some(f) && lanes[f].solver.linear.same_variant(linear));
        group[l] = match leader {
            None => Some(l),
            Some(f) => lanes[f].solver.shares_factors(lanes[l].solver).then_some(f),
        };
    }
    let mut outcomes: Vec<Option<LinearOutcome>> = vec![None; lanes.len()];
    let leaders: Vec<usize> = (0..lanes.len()).filter(|&l| group[l] == Some(l)).collect();
    for leader in leaders {
        let mut stages: Vec<&mut LinearStage> = Vec::new();
        let mut inputs: Vec<BatchInput<'_>> = Vec::new();
        let mut outs: Vec<&mut [TraceHistory]> = Vec::new();
        let mut runs = Vec::new();
        for (l, lane) in lanes.iter_mut().enumerate() {
            if group[l] != Some(leader) {
                continue;
            }
            let Solver {
                problem,
                settings,
                classes,
                factors,
                distribution,
                linear,
                ..
            } = &mut *lane.solver;
            let ops = Operators {
                subs: &problem.subs,
                classes,
                factors,
                distribution,
            };
            let (input, out) = lane.run.batch_parts(problem, ops, settings);
            stages.push(linear);
            inputs.push(input);
            outs.push(out);
            runs.push(l);
        }
        let results = LinearStage::run_batched(stages, &inputs, &mut outs);
        for (&l, outcome) in runs.iter().zip(results) {
            outcomes[l] = Some(outcome);
        }
    }
    lanes
        .iter_mut()
        .enumerate()
        .map(|(l, lane)| {
            let Some(b) = begun[l] else {
                return true;
            };
            let solver = &mut *lane.solver;
            let outcome = match outcomes[l] {
                Some(o) => {
                    lane.run.set_window_sums(o.sums);
                    o
                }
                None => solver.iteration_linear(lane.run),
            };
            solver.iteration_end(lane.run, b, outcome, t_linear, &mut |it| observer(l, it))
        })
        .collect()
}
