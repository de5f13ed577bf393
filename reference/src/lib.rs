//! `lopin-reference`: independent judges of the LATIN solver of `lopin-core` — the monolithic
//! reference ([`monolithic`]), the exact solution of the `bar` scene ([`exact`]), the comparison
//! of a LATIN solution with the reference ([`compare`]) and the numerical stability stress suite
//! ([`stress`]).
//!
//! That the reference uses nothing of the LATIN iteration is checked by the compiler: without
//! the default `judge` feature this crate depends on a `lopin-core` built without its `latin`
//! feature (no solver, local or linear stage, state, post-processing of LATIN solutions), and
//! `monolithic` and `exact` still compile (`cargo check -p lopin-reference
//! --no-default-features`, run by CI). `compare` and `stress` run LATIN, so they need `judge`.
//!
//! ```no_run
//! use lopin_core::{scene, Settings, Solver};
//! use lopin_reference::{compare::compare, monolithic::Monolithic};
//! let spec = scene::load("two-blocks")?;
//! let problem = scene::build::build(&spec, "two-blocks")?;
//! let reference = Monolithic::new(problem.clone())?;
//! let mono = reference.solve()?;
//! let mut solver = Solver::new(problem, Settings::for_problem(reference.problem(), &spec.solver))?;
//! let sol = solver.solve(None)?;
//! let c = compare(&solver, &sol, &reference, &mono);
//! println!("{:.2e} {:.2e}", c.rel_diff_velocity, c.rel_diff_force);
//! # Ok::<(), lopin_core::LopinError>(())
//! ```

#[cfg(feature = "judge")]
pub mod compare;
pub mod exact;
pub mod monolithic;
#[cfg(feature = "judge")]
pub mod stress;
