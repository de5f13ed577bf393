//! The monolithic reference: the same discrete problem as the LATIN engine (same meshes, lumped
//! masses, trapezoidal velocity form of METHOD §2, contact law of METHOD §5 with the persistent
//! normal law and Coulomb friction, prescribed velocities and tractions), solved without
//! decomposition. The structure is assembled once (perfect-interface node pairs merged, contact
//! node pairs kept apart), S = 2/Δt M + Δt/2 K is factorized once on the free dofs, and at each
//! step the contact conditions are solved on the pairs by projected Gauss–Seidel with the
//! Delassus operator, to a relative change of 1e-12.
//!
//! It shares with LATIN only the meshes, element matrices and scene definitions — none of the
//! local-stage, linear-stage or search-direction code — so agreement between the two is a check.

mod assembly;
mod contact_solve;
mod delassus;
mod march;
mod numbering;
mod results;

pub use assembly::{Assembled, ContactPair, PairCopy};
pub use contact_solve::{coulomb_disc, ContactControls};
pub use delassus::Delassus;
pub use march::MonoSolution;
pub use numbering::Numbering;

use crate::counters::Instant;
use crate::error::{LopinError, Result};
use crate::factor::CholeskyFactor;
use crate::problem::Problem;

/// A factorized monolithic reference solver.
#[derive(Debug)]
pub struct Monolithic {
    problem: Problem,
    asm: Assembled,
    factor: CholeskyFactor,
    delassus: Delassus,
    /// Contact iteration controls.
    pub controls: ContactControls,
    setup_s: f64,
}

impl Monolithic {
    /// Assembles and factorizes the problem and builds the Delassus operator of its contacts.
    pub fn new(problem: Problem) -> Result<Self> {
        let clock = Instant::now();
        let asm = Assembled::new(&problem)?;
        let factor = CholeskyFactor::new(asm.free, &asm.free_operator(problem.time.dt)).map_err(
            |reason| {
                LopinError::Reference(format!(
                    "factorization of 2/dt M + dt/2 K on the free dofs failed: {reason}"
                ))
            },
        )?;
        let delassus = Delassus::new(&asm, &factor);
        Ok(Self {
            problem,
            asm,
            factor,
            delassus,
            controls: ContactControls::default(),
            setup_s: clock.elapsed().as_secs_f64(),
        })
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The assembled structure.
    pub fn assembled(&self) -> &Assembled {
        &self.asm
    }

    /// Seconds spent assembling, factorizing and building the Delassus operator.
    pub fn setup_s(&self) -> f64 {
        self.setup_s
    }

    /// Number of assembled dofs and of free (not prescribed) dofs.
    pub fn dofs(&self) -> (usize, usize) {
        (self.asm.numbering.dofs(), self.asm.free)
    }

    /// Sets the friction coefficient of every contact (nothing is refactorized).
    pub fn set_friction(&mut self, f: f64) {
        self.problem.set_friction(f);
        self.asm.set_friction(f);
    }

    /// Solves the whole time interval.
    pub fn solve(&self) -> Result<MonoSolution> {
        march::march(
            &self.asm,
            &self.factor,
            &self.delassus,
            self.problem.time,
            self.controls,
        )
    }
}
