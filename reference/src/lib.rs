//! `lopin-reference`: the independent reference Lopin's LATIN solver is judged against — the
//! monolithic solver of the same discrete problem, contact and friction included
//! ([`monolithic`]), and the exact solution of the `bar` scene ([`exact`]).
//!
//! Its independence from the solver is a crate boundary: it depends on `lopin-model` (meshes,
//! elements, interfaces, scenes) and not on `lopin-core`. The comparison of the two solvers
//! and the stress suite are in `lopin-judge`.
//!
//! ```
//! use lopin_model::scene;
//! use lopin_reference::monolithic::Monolithic;
//! let opened = scene::open("two-blocks", &scene::Overrides::default())?;
//! let reference = Monolithic::new(opened.problem)?;
//! let mono = reference.solve()?;
//! assert!(mono.v.iter().flatten().all(|v| v.is_finite()));
//! # Ok::<(), lopin_model::LopinError>(())
//! ```

pub mod exact;
pub mod monolithic;
