//! `lopin-judge`: the LATIN solver of `lopin-core` judged against the monolithic reference of
//! `lopin-reference`: the comparison of a LATIN solution with the reference ([`compare`]) and
//! the numerical stability stress suite ([`stress`]: adverse settings on small scenes, each
//! solve checked against the reference). It is the one crate that sees both solvers; the
//! reference itself depends on the model only (`lopin-model`).
//!
//! ```
//! use lopin_core::scene::{self, spec::SolverSpec, Overrides};
//! use lopin_core::window_choice::WindowRequest;
//! use lopin_core::Solver;
//! use lopin_judge::compare::compare;
//! use lopin_reference::monolithic::Monolithic;
//!
//! let tight = Overrides {
//!     solver: SolverSpec {
//!         tol: Some(1e-6),
//!         window: Some(WindowRequest::Whole),
//!         ..Default::default()
//!     },
//!     ..Default::default()
//! };
//! let opened = scene::open("two-blocks", &tight)?;
//! let reference = Monolithic::new(opened.problem.clone())?;
//! let mono = reference.solve()?;
//! let mut solver = Solver::new(opened.problem, opened.settings)?;
//! let sol = solver.solve(None)?;
//! let c = compare(&solver, &sol, &reference, &mono);
//! assert!(c.rel_diff_velocity < 1e-3 && c.rel_diff_force < 1e-3, "{c:?}");
//! # Ok::<(), lopin_core::LopinError>(())
//! ```

pub mod compare;
pub mod stress;
