//! `lopin-core`: a LATIN domain-decomposition solver for transient linear elastodynamics on
//! decomposed 3D structures whose interfaces carry the nonlinearity (perfect, unilateral contact
//! with Coulomb friction, boundary conditions). The method is specified in METHOD.md; each module
//! names the sections it implements.
//!
//! The problem it solves (meshes, elements, materials, interfaces, scenes, factorization) is the
//! crate `lopin-model`, which the monolithic reference of `lopin-reference` builds on too; its
//! modules are re-exported here (`lopin_core::scene` is `lopin_model::scene`), so a user of the
//! solver needs one dependency.
//!
//! # Solve, change the friction, solve warm, read a field
//!
//! A scene comes from the registry of built-in scenes, a TOML file or code (next example).
//! [`scene::open`] turns it into a [`Problem`] (meshes, substructures, interfaces) and the
//! [`Settings`] of its solve (the defaults under the scene's `[solver]` under the overrides);
//! the [`Solver`] factorizes every substructure once and iterates (METHOD §2–§7).
//! A parameter of the interfaces ([`Parameter`]) changes without a new factorization, and the
//! next solve restarts from the converged interface state (METHOD §8):
//!
//! ```
//! use lopin_core::{post, scene, Parameter, Solver};
//!
//! let opened = scene::open("two-blocks", &scene::Overrides::default())?;
//! let mut solver = Solver::new(opened.problem, opened.settings)?;
//! let cold = solver.solve(None)?;
//! assert!(cold.converged && cold.eta < 1e-3);
//!
//! solver.set_parameter(Parameter::Friction, 0.5)?;
//! let warm = solver.solve(Some(&cold.state))?;
//! assert!(warm.converged);
//!
//! // displacements and velocities of every substructure at the last step
//! let last = solver.problem().time.steps;
//! let fields = post::fields_at(&solver, &warm, last);
//! // the top block (substructure 0) is pushed down: its largest downward displacement
//! let down = fields[0].u.chunks(3).map(|u| -u[2]).fold(0.0, f64::max);
//! assert!(down > 0.0 && down < 1e-3, "{down}");
//! # Ok::<(), lopin_core::LopinError>(())
//! ```
//!
//! # A scene built in code
//!
//! The scene schema ([`scene::spec`]) is plain data: the same tables as a scene file. A steel
//! cube clamped at the bottom, its top pushed down at 1 m/s through a (1 − cos) ramp, checked by
//! the front door [`scene::open`] as a file would be:
//!
//! ```
//! use lopin_core::scene::spec::{BodySpec, BoundarySpec, ComponentSpec, MaterialSpec, SceneSpec};
//! use lopin_core::time::time_function::TimeGrid;
//! use lopin_core::{post, scene, Solver};
//!
//! let cube = BodySpec {
//!     name: "cube".into(),
//!     material: "steel".into(),
//!     min: [0.0; 3],
//!     max: [0.01; 3],
//!     divisions: [4, 4, 4],
//!     split: [1, 1, 2],
//!     velocity: [0.0; 3],
//!     elements: None,
//!     substructures: None,
//! };
//! let face = |face: &str| BoundarySpec {
//!     body: "cube".into(),
//!     face: face.into(),
//!     surface: None,
//!     clamped: false,
//!     preload: false,
//!     x: None,
//!     y: None,
//!     z: None,
//!     normal: None,
//! };
//! let spec = SceneSpec {
//!     name: "cube".into(),
//!     description: "a pushed steel cube".into(),
//!     refine_axes: "xyz".into(),
//!     split_axes: "xy".into(),
//!     time: TimeGrid { dt: 2e-7, steps: 20 },
//!     solver: Default::default(),
//!     materials: vec![MaterialSpec {
//!         name: "steel".into(),
//!         young: 210e9,
//!         poisson: 0.3,
//!         density: 7800.0,
//!         ..MaterialSpec::default()
//!     }],
//!     granular: None,
//!     granular_poly: None,
//!     bodies: vec![cube],
//!     mesh_bodies: vec![],
//!     interfaces: vec![],
//!     boundaries: vec![
//!         BoundarySpec { z: Some(ComponentSpec::velocity(-1.0, 1e-6)), ..face("z+") },
//!         BoundarySpec { clamped: true, ..face("z-") },
//!     ],
//!     zones: vec![],
//! };
//! let opened = scene::open(scene::Source::spec(spec.clone(), "cube"), &Default::default())?;
//! assert_eq!(opened.problem.subs.len(), 2);
//! let mut solver = Solver::new(opened.problem, opened.settings)?;
//! let sol = solver.solve(None)?;
//! assert!(sol.converged);
//! // the energy balance: the work the load put in is the kinetic plus strain energy
//! // (the trapezoidal rule conserves energy; LATIN's tolerance leaves a small gap)
//! let energy = post::energy(&solver, &sol);
//! let last = spec.time.steps;
//! let (stored, input) = (energy.total(last), energy.input_work[last]);
//! assert!(input > 0.0 && (stored - input).abs() <= 0.05 * input, "{stored} against {input}");
//! # Ok::<(), lopin_core::LopinError>(())
//! ```

pub mod dissipation;
pub mod distributed;
pub mod estimate;
pub mod macro_scale;
mod par;
pub mod post;
pub mod preload;
pub mod solver;
pub mod stages;
pub mod state;
pub mod study;

pub use lopin_model::{
    counters, elements, error, histories, interfaces, linalg, mesh, parameter, problem, scene,
    settings, shock_spectrum, splitmix, substructure, target, time, window_choice,
};

pub use error::{LopinError, Result};
pub use parameter::Parameter;
pub use problem::Problem;
pub use solver::{Control, Iterate, Settings, Solution, SolveRun, Solver};
pub use state::InterfaceState;
