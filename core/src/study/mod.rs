//! Parametric studies over several interface parameters (METHOD §8 multiresolution):
//! which parameters move ([`target`]: f, gap, v0, everywhere or in one zone), which
//! configurations are solved ([`design`]: grids, Latin hypercube or Monte Carlo samples from
//! uniform, normal and lognormal distributions), in which order ([`path`]: a greedy
//! nearest-neighbour path in scaled parameter space, cut into chains that run at once), from
//! which start ([`store`]: converged states kept in f32, the nearest solved configuration) and
//! what is reported of each ([`quantities`]); [`runner`] runs the chains at once.

pub mod design;
pub mod path;
pub mod projection;
pub mod quantities;
pub mod runner;
pub mod store;

pub use design::{Design, Sampling, Spread};
pub use lopin_model::target::{self, Target};
pub use path::{Chains, Path};
pub use quantities::Quantities;
pub use store::StateStore;
