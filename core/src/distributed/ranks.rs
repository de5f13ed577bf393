//! The ranks of a distributed run, as the solver sees them (METHOD §11): who this
//! process is, an element-wise sum over all ranks, and a point-to-point exchange of trace
//! fields between neighbouring ranks. [`Ranks`] is the whole contract; [`OneRank`] is the run
//! on one machine (every operation is the identity), the `lopin` binary's `mpi` feature
//! implements it on MPI, and [`crate::distributed::thread_ranks`] on threads of one process (tests).
//!
//! Exactness: the solver only ever sums vectors in which every entry has at most two
//! contributions (a per-substructure quantity from the rank that holds the substructure; a
//! macro dof from the two sides of its interface), every other rank contributing −0, the
//! neutral element of IEEE addition (x + (−0) = x for every x, +0 and −0 included; +0 would
//! turn a −0 into +0). Two terms commute, so [`Ranks::all_sum`] gives the same bits in any
//! reduction order, and a distributed run equals the run on one machine bit for bit.

use std::fmt::Debug;

/// The ranks of a run and the communication between them. Every method is collective: all
/// ranks call it, in the same order, with the same lengths.
pub trait Ranks: Debug + Send + Sync {
    /// This rank, 0..size.
    fn rank(&self) -> usize;

    /// Number of ranks.
    fn size(&self) -> usize;

    /// `values` ← the element-wise sum of every rank's `values`.
    fn all_sum(&self, values: &mut [f64]);

    /// Sends each `(to, data)` and receives, from each `(from, len)` of `receive`, one message
    /// of `len` values; returns them in `receive`'s order. Between two ranks, the sends of one
    /// call are received by the matching receive of the same call.
    fn exchange(&self, send: &[(usize, Vec<f64>)], receive: &[(usize, usize)]) -> Vec<Vec<f64>>;
}

/// The run on one machine: one rank, nothing to exchange.
#[derive(Debug, Clone, Copy, Default)]
pub struct OneRank;

impl Ranks for OneRank {
    fn rank(&self) -> usize {
        0
    }

    fn size(&self) -> usize {
        1
    }

    fn all_sum(&self, _values: &mut [f64]) {}

    fn exchange(&self, send: &[(usize, Vec<f64>)], receive: &[(usize, usize)]) -> Vec<Vec<f64>> {
        debug_assert!(send.is_empty() && receive.is_empty());
        Vec::new()
    }
}
