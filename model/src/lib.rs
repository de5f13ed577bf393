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
//! let opened = scene::open("two-blocks", &scene::Overrides::default())?;
//! assert_eq!(opened.problem.subs.len(), 2);
//! assert_eq!(opened.problem.dof_count(), 4356);
//! assert_eq!(opened.settings.mu, 0.8);
//! # Ok::<(), lopin_model::LopinError>(())
//! ```

pub mod counters;
pub mod elements;
pub mod error;
pub mod histories;
pub mod interfaces;
pub mod linalg;
pub mod mesh;
pub mod parameter;
pub mod problem;
pub mod scene;
pub mod settings;
pub mod shock_spectrum;
pub mod splitmix;
pub mod substructure;
pub mod target;
pub mod time;
pub mod window_choice;

pub use error::{LopinError, Result};
pub use parameter::Parameter;
pub use problem::Problem;
pub use settings::Settings;
