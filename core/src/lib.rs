//! `lopin-core`: a LATIN domain-decomposition solver for transient linear elastodynamics on
//! decomposed 3D structures whose interfaces carry the nonlinearity (perfect, unilateral contact
//! with Coulomb friction, boundary conditions). The method is specified in METHOD.md; each module
//! names the sections it implements.
//!
//! The LATIN iteration (solver, stages, state, macro problem, post-processing, sweeps) sits behind
//! the default `latin` feature; without it the crate holds only the problem description (meshes,
//! element matrices, interfaces, scenes, factorization), which is all the monolithic reference of
//! `lopin-reference` may use.
//!
//! ```no_run
//! use lopin_core::{scene, Parameter, Settings, Solver};
//! let spec = scene::load("two-blocks")?;
//! let problem = scene::build::build(&spec, "two-blocks")?;
//! let settings = Settings::for_problem(&problem, &spec.solver);
//! let mut solver = Solver::new(problem, settings)?;
//! let cold = solver.solve(None)?;
//! solver.set_parameter(Parameter::Friction, 0.5)?;
//! let warm = solver.solve(Some(&cold.state))?; // METHOD §8 warm start
//! # Ok::<(), lopin_core::LopinError>(())
//! ```

pub mod acceleration;
pub mod box_sweep;
pub mod counters;
pub mod dense;
pub mod detect;
#[cfg(feature = "latin")]
pub mod dissipation;
#[cfg(feature = "latin")]
pub mod distribution;
pub mod error;
#[cfg(feature = "latin")]
pub mod estimate;
pub mod factor;
#[cfg(feature = "msh")]
pub mod gmsh;
pub mod grain_geometry;
pub mod hex8;
pub mod histories;
#[cfg(feature = "latin")]
pub mod indicator;
pub mod interface;
#[cfg(feature = "latin")]
pub mod linear_stage;
#[cfg(feature = "latin")]
pub mod local_stage;
#[cfg(feature = "latin")]
pub mod macro_basis;
#[cfg(feature = "latin")]
pub mod macro_problem;
pub mod material;
pub mod mesh;
#[cfg(feature = "msh")]
pub mod msh;
#[cfg(feature = "latin")]
pub mod operator_classes;
#[cfg(feature = "latin")]
mod par;
pub mod parameter;
#[cfg(feature = "partition")]
pub mod partition;
#[cfg(feature = "latin")]
pub mod post;
pub mod problem;
#[cfg(feature = "partition")]
pub mod rank_assignment;
pub mod ranks;
pub mod scene;
pub mod search_direction;
#[cfg(feature = "latin")]
pub mod solver;
pub mod sparse;
pub mod splitmix;
#[cfg(feature = "latin")]
pub mod state;
pub mod stop_test;
#[cfg(feature = "latin")]
pub mod study;
pub mod substructure;
pub mod surface_groups;
#[cfg(feature = "latin")]
pub mod sweep;
pub mod tet4;
#[cfg(feature = "latin")]
pub mod thread_ranks;
pub mod time_function;
pub mod time_scheme;
pub mod window_choice;
pub mod window_start;
pub mod zone;

pub use error::{LopinError, Result};
pub use parameter::Parameter;
pub use problem::Problem;
#[cfg(feature = "latin")]
pub use solver::{Control, Iterate, Settings, Solution, SolveRun, Solver};
#[cfg(feature = "latin")]
pub use state::InterfaceState;
