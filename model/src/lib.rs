//! `lopin-model`: the mechanical problem Lopin solves, without the solver. Meshes and elements
//! (trilinear hexahedra, linear tetrahedra, lumped mass), materials, the time grid and the time
//! scheme (METHOD §1–§2), interfaces and their laws (METHOD §5), substructures and their
//! factorization, scenes (the schema, the built-in registry, validation, admission of a solve's
//! size, building a [`Problem`]), interface detection, automatic substructuring, Gmsh input,
//! zones and the parameters a study moves ([`Parameter`]). The LATIN solver (`lopin-core`) and
//! the monolithic reference (`lopin-reference`) both build on it; neither is visible from here.
//!
//! ```
//! use lopin_model::scene;
//! let spec = scene::load("two-blocks")?;
//! let problem = scene::build::build(&spec, "two-blocks")?;
//! assert_eq!(problem.subs.len(), 2);
//! assert_eq!(problem.dof_count(), 4356);
//! # Ok::<(), lopin_model::LopinError>(())
//! ```

pub mod box_sweep;
pub mod counters;
pub mod dense;
pub mod detect;
pub mod error;
pub mod factor;
#[cfg(feature = "msh")]
pub mod gmsh;
pub mod grain_geometry;
pub mod hex8;
pub mod histories;
pub mod interface;
pub mod material;
pub mod mesh;
#[cfg(feature = "msh")]
pub mod msh;
pub mod parameter;
#[cfg(feature = "partition")]
pub mod partition;
pub mod problem;
pub mod scene;
pub mod search_direction;
pub mod sparse;
pub mod splitmix;
pub mod substructure;
pub mod surface_groups;
pub mod tet4;
pub mod time_function;
pub mod time_scheme;
pub mod zone;

pub use error::{LopinError, Result};
pub use parameter::Parameter;
pub use problem::Problem;
