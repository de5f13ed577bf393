//! `lopin-core`: a LATIN domain-decomposition solver for transient linear elastodynamics on
//! decomposed 3D structures whose interfaces carry the nonlinearity (perfect, unilateral contact
//! with Coulomb friction, boundary conditions). The method is specified in METHOD.md; each module
//! names the sections it implements.
//!
//! ```no_run
//! use lopin_core::{scene, Settings, Solver};
//! let spec = scene::load("two-blocks")?;
//! let problem = scene::build::build(&spec, "two-blocks")?;
//! let settings = Settings::for_problem(&problem, &spec.solver);
//! let mut solver = Solver::new(problem, settings)?;
//! let cold = solver.solve(None)?;
//! solver.set_friction(0.5)?;
//! let warm = solver.solve(Some(&cold.state))?; // METHOD §8 warm start
//! # Ok::<(), lopin_core::LopinError>(())
//! ```

pub mod compare;
pub mod counters;
pub mod detect;
pub mod error;
pub mod estimate;
pub mod factor;
pub mod hex8;
pub mod interface;
pub mod linear_stage;
pub mod local_stage;
pub mod macro_basis;
pub mod macro_problem;
pub mod material;
pub mod mesh;
pub mod monolithic;
pub mod operator_classes;
mod par;
pub mod post;
pub mod problem;
pub mod scene;
pub mod solver;
pub mod sparse;
pub mod state;
pub mod stress;
pub mod substructure;
pub mod sweep;
pub mod time_function;

pub use error::{LopinError, Result};
pub use problem::Problem;
pub use solver::{Control, Iterate, Settings, Solution, SolveRun, Solver};
pub use state::InterfaceState;
