//! Runs on several ranks (METHOD §11): the `Ranks` contract and its single-rank form
//! ([`ranks`]), ranks as threads of one process for the tests ([`thread_ranks`]), which rank
//! holds which substructure and interface ([`distribution`]) and the METIS assignment of
//! substructures to ranks ([`rank_assignment`]).

pub mod distribution;
#[cfg(feature = "partition")]
pub mod rank_assignment;
pub mod ranks;
pub mod thread_ranks;
