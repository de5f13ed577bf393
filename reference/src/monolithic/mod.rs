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

use lopin_model::counters::Instant;
use lopin_model::error::{LopinError, Result};
use lopin_model::linalg::factor::CholeskyFactor;
use lopin_model::parameter::Parameter;
use lopin_model::problem::Problem;

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
    /// The static equilibrium of the problem's preload the march starts from (its own static
    /// solve, [`Monolithic::static_start`]; None without preload).
    start: Option<Start>,
}

/// Where the march starts after a preload: the static solution of the reference itself.
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// Displacement u₀ (global dofs).
    pub displacement: Vec<f64>,
    /// Pair forces (P, T₁, T₂) at t₀.
    pub pair_forces: Vec<[f64; 3]>,
    /// Gap per pair at t₀.
    pub gaps: Vec<f64>,
}

impl Monolithic {
    /// Assembles and factorizes the problem and builds the Delassus operator of its contacts.
    pub fn new(problem: Problem) -> Result<Self> {
        let clock = Instant::now();
        let start = Self::static_start(&problem)?;
        let asm = Assembled::new(&problem)?;
        let time = problem.step_coefficients();
        let factor =
            CholeskyFactor::new(asm.free, &asm.free_operator(&time)).map_err(|reason| {
                LopinError::Reference(format!(
                    "factorization of c_M M + c_K K on the free dofs failed: {reason}"
                ))
            })?;
        let delassus = Delassus::new(&asm, &factor);
        Ok(Self {
            problem,
            asm,
            factor,
            delassus,
            controls: ContactControls::default(),
            setup_s: clock.elapsed().as_secs_f64(),
            start,
        })
    }

    /// The reference's own static solve of a preload (None without one): the static problem
    /// ([`Problem::statics`]: one step of statics, S = K on the free dofs) marched once with its
    /// contact solve (Signorini's law on g0 + [u_n], Coulomb friction). Every part must be held
    /// by a prescribed dof: K is factorized as it is.
    pub fn static_start(problem: &Problem) -> Result<Option<Start>> {
        if !problem.needs_preload() {
            return Ok(None);
        }
        let statics = Monolithic::new(problem.statics()).map_err(|e| {
            LopinError::Reference(format!(
                "the preload's static problem: {e} (the reference needs every part held by a \
                 prescribed dof in statics)"
            ))
        })?;
        let sol = statics.solve()?;
        Ok(Some(Start {
            displacement: sol.u[1].clone(),
            pair_forces: sol.pair_forces[1].clone(),
            gaps: sol.gaps[1].clone(),
        }))
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

    /// Sets an interface parameter (METHOD §8) on the problem and the assembled structure;
    /// nothing is refactorized. Friction changes the contact pairs in place; a gap, a velocity,
    /// traction or acceleration amplitude or a pulse duration reassembles the loads and pairs
    /// (the prescribed dofs, hence S on the free dofs, stay the same) and rebuilds the Delassus
    /// operator, since pairs of equal gaps merge.
    pub fn set_parameter(&mut self, parameter: Parameter, value: f64) -> Result<()> {
        parameter.apply(&mut self.problem, value)?;
        match parameter {
            Parameter::Friction => self.asm.set_friction(value),
            Parameter::Gap
            | Parameter::VelocityAmplitude
            | Parameter::TractionAmplitude
            | Parameter::AccelerationAmplitude
            | Parameter::Preload
            | Parameter::PulseDuration => {
                let asm = Assembled::new(&self.problem)?;
                if asm.free_index != self.asm.free_index {
                    return Err(LopinError::Reference(format!(
                        "setting {parameter} changed the prescribed dofs"
                    )));
                }
                self.delassus = Delassus::new(&asm, &self.factor);
                self.asm = asm;
            }
        }
        if parameter.moves_statics() {
            self.start = Self::static_start(&self.problem)?;
        }
        Ok(())
    }

    /// Solves the whole time interval.
    pub fn solve(&self) -> Result<MonoSolution> {
        march::march(
            &self.asm,
            &self.factor,
            &self.delassus,
            self.problem.time,
            self.problem.step_coefficients(),
            self.controls,
            self.start.as_ref(),
        )
    }
}
