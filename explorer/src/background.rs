//! The background study's lanes (METHOD §8 with §4, §11): the grid values the explorer's
//! background study solves at once, each on a lane of its own — a solver that shares the
//! factorizations of the user's solver ([`Solver::lane`]), with the friction value of its
//! configuration — all advanced one LATIN iteration at a time together
//! ([`lopin_core::solver::batch::step_together`]), so that every linear stage solves the
//! right-hand sides of all lanes in one pass through each substructure's factor. The user's
//! solver is never changed by the background study. A lane whose solve ended is handed back
//! with its solve ([`BackgroundSolve`]); its solver is kept for the next value while the user's parameters
//! stay as they are.

use crate::params::Params;
use lopin_core::solver::batch::{self, step_together};
use lopin_core::state::InterfaceState;
use lopin_core::{Control, SolveRun, Solver};

/// A background configuration being solved, or one whose solve ended.
pub(crate) struct BackgroundSolve {
    /// The lane's solver, set to the configuration's parameters.
    pub solver: Solver,
    /// The configuration's parameters.
    pub params: Params,
    /// Its solve.
    pub run: SolveRun,
    /// The friction value of the stored state it started from.
    pub start: Option<f64>,
}

/// The lanes of the background study: those solving, and spare solvers with the parameters they
/// hold.
#[derive(Default)]
pub(crate) struct Lanes {
    busy: Vec<BackgroundSolve>,
    spare: Vec<(Solver, Params)>,
    /// A lane could not be made: no more until the user's parameters change.
    failed: bool,
}

impl Lanes {
    /// How many configurations are being solved.
    pub fn len(&self) -> usize {
        self.busy.len()
    }

    /// Whether none is.
    pub fn is_empty(&self) -> bool {
        self.busy.is_empty()
    }

    /// The friction values being solved, in the order they began.
    pub fn values(&self) -> Vec<f64> {
        self.busy.iter().filter_map(|l| l.params.friction).collect()
    }

    /// Makes sure a lane is free for [`Lanes::begin`]: a spare one, or a new lane of `user`
    /// (whose problem holds the parameters `applied`). An error here concerns the solver, not a
    /// value.
    pub fn make_ready(&mut self, user: &Solver, applied: &Params) -> lopin_core::Result<()> {
        if self.spare.is_empty() {
            match user.lane() {
                Ok(lane) => self.spare.push((lane, applied.clone())),
                Err(e) => {
                    self.failed = true;
                    return Err(e);
                }
            }
        }
        Ok(())
    }

    /// Whether a lane could not be made since the user's parameters last changed.
    pub fn failed(&self) -> bool {
        self.failed
    }

    /// Begins solving `params` from `state` on the lane [`Lanes::make_ready`] made free; `start`
    /// is the friction value of that state. An error concerns this value.
    pub fn begin(
        &mut self,
        params: Params,
        state: Option<&InterfaceState>,
        start: Option<f64>,
    ) -> lopin_core::Result<()> {
        let Some((mut solver, before)) = self.spare.pop() else {
            return Err(lopin_core::LopinError::setting(
                "background",
                "no lane is ready",
            ));
        };
        // a lane whose parameters could not all be set is dropped
        params.apply(&before, &mut solver)?;
        match solver.begin(state) {
            Ok(run) => {
                self.busy.push(BackgroundSolve {
                    solver,
                    params,
                    run,
                    start,
                });
                Ok(())
            }
            Err(e) => {
                self.spare.push((solver, params));
                Err(e)
            }
        }
    }

    /// One LATIN iteration of every lane together; gives back the configurations whose solves
    /// ended (converged, failed or out of iterations), in the order they began. Hand each
    /// solver back with [`Lanes::keep`].
    pub fn step(&mut self) -> Vec<BackgroundSolve> {
        let ended = {
            let mut lanes: Vec<batch::Lane<'_>> = self
                .busy
                .iter_mut()
                .map(|l| batch::Lane {
                    solver: &mut l.solver,
                    run: &mut l.run,
                })
                .collect();
            step_together(&mut lanes, &mut |_, _| Control::Continue)
        };
        let (done, going): (Vec<_>, Vec<_>) = self
            .busy
            .drain(..)
            .zip(ended)
            .partition(|(_, ended)| *ended);
        self.busy = going.into_iter().map(|(l, _)| l).collect();
        done.into_iter().map(|(l, _)| l).collect()
    }

    /// Keeps a lane's solver, set to `params`, for the next value.
    pub fn keep(&mut self, solver: Solver, params: Params) {
        self.spare.push((solver, params));
    }

    /// Stops every solve (nothing is stored); the solvers are kept. Returns whether one ran.
    pub fn cancel(&mut self) -> bool {
        let any = !self.busy.is_empty();
        for l in self.busy.drain(..) {
            self.spare.push((l.solver, l.params));
        }
        any
    }

    /// Stops every solve and drops every lane (the user's parameters changed).
    pub fn forget(&mut self) -> bool {
        let any = self.cancel();
        self.spare.clear();
        self.failed = false;
        any
    }
}
