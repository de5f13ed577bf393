//! The linear stage (E−) of one LATIN iteration over the current time window, as the solver holds
//! it: one of two variants, chosen by [`crate::Settings::two_scale`] and switched only by
//! [`crate::Solver::set_settings`]:
//!
//! - [`SingleScale`] (METHOD §4): every substructure marches independently, in parallel, with
//!   its [`SkipCache`] over the whole interval;
//! - [`TwoScale`] (METHOD §9): all substructures in lock-step with one macro solve per step.
//!
//! Both hold one [`LinearWork`] per substructure, allocated once with the factorizations, and
//! return the window's η sums (METHOD §6) with what was skipped and the macro time. In a
//! distributed run each rank marches only its substructures ([`crate::distributed::distribution`]) and the
//! per-substructure sums are gathered and added in index order, as on one machine.

use super::skip_cache::SkipCache;
use super::two_scale::TwoScale;
use crate::distributed::distribution::Distribution;
use crate::linalg::factor::CholeskyFactor;
use crate::macro_scale::macro_problem::MacroProblem;
use crate::macro_scale::operator_classes::Classes;
use crate::stages::indicator::IndicatorSums;
use crate::stages::linear_stage::{LinearInput, LinearWork, SubState};
use crate::state::TraceHistory;
use crate::substructure::Substructure;

/// The substructures and their factorized operators S, which the linear stage reads.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Operators<'a> {
    /// Substructures.
    pub subs: &'a [Substructure],
    /// Which factorization each substructure uses.
    pub classes: &'a Classes,
    /// One factorization of S per class with a substructure on this rank.
    pub factors: &'a [Option<CholeskyFactor>],
    /// Which rank holds which substructure.
    pub distribution: &'a Distribution,
}

impl Operators<'_> {
    /// The factorization of substructure `i`'s S (a substructure of this rank).
    pub fn factor(&self, i: usize) -> &CholeskyFactor {
        self.factors[self.classes.of[i]]
            .as_ref()
            .unwrap_or_else(|| panic!("substructure {i} is held by another rank"))
    }
}

/// What one linear stage over a window produced besides s_new.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct LinearOutcome {
    /// η sums of the window, added over the substructures in index order.
    pub sums: IndicatorSums,
    /// Substructures whose march was skipped (inputs unchanged).
    pub skipped: usize,
    /// Seconds in the macro right-hand sides and solves (two-scale only).
    pub macro_s: f64,
}

/// The linear stage of a solver.
#[derive(Debug)]
pub(crate) enum LinearStage {
    /// METHOD §4.
    SingleScale(SingleScale),
    /// METHOD §9 (boxed: it holds the macro problem).
    TwoScale(Box<TwoScale>),
}

impl LinearStage {
    /// Marches the window `lin.steps` of every substructure from `starts` (the states at
    /// m0 − 1), writing s_new into `out`. `whole`: the window is the whole interval and skipping
    /// is allowed.
    pub fn run(
        &mut self,
        ops: Operators<'_>,
        starts: &[SubState],
        lin: &LinearInput<'_>,
        whole: bool,
        out: &mut [TraceHistory],
    ) -> LinearOutcome {
        match self {
            Self::SingleScale(s) => s.run(ops, starts, lin, whole, out),
            Self::TwoScale(t) => t.run(ops, starts, lin, out),
        }
    }

    /// Forgets every substructure's guess of a single-precision refinement
    /// ([`LinearWork::forget_guess`]): a solve starts from none.
    pub fn forget_guesses(&mut self) {
        match self {
            Self::SingleScale(s) => s.subs.iter_mut().for_each(|b| b.work.forget_guess()),
            Self::TwoScale(t) => t.forget_guesses(),
        }
    }

    /// The linear stages of several configurations of one problem that share their operators
    /// S, all of one variant, marched together ([`SingleScale::run_batched`],
    /// [`TwoScale::run_batched`]). Returns each configuration's outcome.
    pub fn run_batched(
        stages: Vec<&mut LinearStage>,
        inputs: &[BatchInput<'_>],
        outs: &mut [&mut [TraceHistory]],
    ) -> Vec<LinearOutcome> {
        debug_assert!(
            inputs.iter().all(|b| b.ops.distribution.is_single()),
            "configurations marched together are on one machine"
        );
        let mut singles = Vec::with_capacity(stages.len());
        let mut twos = Vec::with_capacity(stages.len());
        for stage in stages {
            match stage {
                Self::SingleScale(s) => singles.push(s),
                Self::TwoScale(t) => twos.push(&mut **t),
            }
        }
        assert!(
            singles.is_empty() || twos.is_empty(),
            "configurations marched together use one variant of the linear stage"
        );
        if twos.is_empty() {
            SingleScale::run_batched(&mut singles, inputs, outs)
        } else {
            TwoScale::run_batched(&mut twos, inputs, outs)
        }
    }

    /// Whether `other` is the same variant.
    pub fn same_variant(&self, other: &LinearStage) -> bool {
        std::mem::discriminant(self) == std::mem::discriminant(other)
    }

    /// The state of every substructure at the last step of the last run.
    pub fn end_state(&self, i: usize) -> &SubState {
        match self {
            Self::SingleScale(s) => &s.subs[i].work.state,
            Self::TwoScale(t) => t.end_state(i),
        }
    }

    /// The macro problem of the two-scale variant.
    pub fn macro_problem(&self) -> Option<&MacroProblem> {
        match self {
            Self::SingleScale(_) => None,
            Self::TwoScale(t) => Some(t.macro_problem()),
        }
    }

    /// The work buffers, and the macro problem of the two-scale variant (to switch variant).
    pub fn into_parts(self) -> (Vec<LinearWork>, Option<MacroProblem>) {
        match self {
            Self::SingleScale(s) => (s.subs.into_iter().map(|b| b.work).collect(), None),
            Self::TwoScale(t) => {
                let (works, mp) = (*t).into_parts();
                (works, Some(mp))
            }
        }
    }
}

/// One substructure's buffers in the single-scale stage.
#[derive(Debug)]
pub(super) struct SingleScaleSub {
    pub work: LinearWork,
    pub skip: SkipCache,
    /// η sums of its last march (or replay).
    pub sums: IndicatorSums,
    /// Whether its last march was skipped.
    pub skipped: bool,
}

/// The single-scale linear stage (METHOD §4): every substructure independent, in parallel, those
/// that share a factorization marching in blocks ([`super::blocks`]).
#[derive(Debug)]
pub(crate) struct SingleScale {
    pub(super) subs: Vec<SingleScaleSub>,
}

impl SingleScale {
    /// The stage over these buffers, with an empty skip cache.
    pub fn new(works: Vec<LinearWork>) -> Self {
        Self {
            subs: works
                .into_iter()
                .map(|work| SingleScaleSub {
                    work,
                    skip: SkipCache::default(),
                    sums: IndicatorSums::default(),
                    skipped: false,
                })
                .collect(),
        }
    }

    fn run(
        &mut self,
        ops: Operators<'_>,
        starts: &[SubState],
        lin: &LinearInput<'_>,
        whole: bool,
        out: &mut [TraceHistory],
    ) -> LinearOutcome {
        let input = BatchInput {
            ops,
            starts,
            lin: *lin,
            whole,
        };
        super::blocks::march_all(&mut [self], &[input], &mut [out]);
        self.outcome(ops)
    }

    /// The η sums and skips of the last march, gathered over the ranks.
    fn outcome(&self, ops: Operators<'_>) -> LinearOutcome {
        let dist = ops.distribution;
        let held = |i: usize| dist.holds_sub(i);
        let mut skipped = [self
            .subs
            .iter()
            .enumerate()
            .filter(|&(i, b)| held(i) && b.skipped)
            .count() as f64];
        dist.all_sum(&mut skipped);
        LinearOutcome {
            sums: dist.gathered_sums(
                self.subs
                    .iter()
                    .enumerate()
                    .map(|(i, b)| held(i).then_some(b.sums)),
            ),
            skipped: skipped[0] as usize,
            macro_s: 0.0,
        }
    }
}

/// What one configuration of a batch marches with ([`SingleScale::run_batched`]).
pub(crate) struct BatchInput<'a> {
    /// Its substructures and the factorizations every configuration of the batch shares.
    pub ops: Operators<'a>,
    /// Its substructures' states at its window start.
    pub starts: &'a [SubState],
    /// Its ŝ, k, scheme and window.
    pub lin: LinearInput<'a>,
    /// Its window is the whole interval and skipping is allowed.
    pub whole: bool,
}

impl SingleScale {
    /// The linear stages of several configurations of one problem whose operators S are the same
    /// (they differ only in interface parameters, initial states and loads): the substructures
    /// of all of them march step by step in the blocks of [`super::blocks`], the right-hand
    /// sides of one step solved in one pass through the shared factor (METHOD §4, §11: the
    /// solve reads the factor once for all columns). Configurations with windows of different
    /// lengths march while they have steps; a substructure a configuration's skip cache replays
    /// takes no column. Every configuration must be on one machine. Returns each
    /// configuration's outcome, as [`Self::run`] would.
    pub fn run_batched(
        stages: &mut [&mut SingleScale],
        inputs: &[BatchInput<'_>],
        outs: &mut [&mut [TraceHistory]],
    ) -> Vec<LinearOutcome> {
        super::blocks::march_all(stages, inputs, outs);
        stages
            .iter()
            .zip(inputs)
            .map(|(stage, input)| stage.outcome(input.ops))
            .collect()
    }
}
