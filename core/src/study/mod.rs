//! The study engine (METHOD §8 multiresolution), under every parametric front end: a sweep is a
//! study of one parameter, the explorer's slider and background study are studies of the friction
//! coefficient. Which parameters move ([`target`]: f, gap, v0, t0, a0, preload, duration,
//! everywhere or in one zone), which configurations are solved ([`design`]: value lists and ranges,
//! grids, Latin hypercube or Monte Carlo samples from uniform, normal and lognormal distributions),
//! in which order ([`path`]: a greedy nearest-neighbour path in scaled parameter space, cut into
//! chains that run at once), from which start ([`predictor`], the one `Predictor`, reading what a
//! [`chain`] has converged to: its last states and the [`store`] of converged states kept in f32),
//! and what is reported of each ([`quantities`]); [`runner`] runs the chains at once, each on a
//! thread, or [`batched`] in lanes that share one factorization and solve together.

pub mod batched;
pub mod chain;
pub mod design;
pub mod path;
pub mod predictor;
pub mod projection;
pub mod quantities;
pub mod runner;
pub mod store;

pub use chain::Chain;
pub use design::{Design, Sampling, Spread};
pub use lopin_model::target::{self, Target};
pub use path::{Chains, Path};
pub use predictor::{Predictor, Start};
pub use quantities::Quantities;
pub use store::StateStore;
