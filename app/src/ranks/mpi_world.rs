//! [`Ranks`] on MPI (feature `mpi`, the `mpi` crate on the system's OpenMPI): the world
//! communicator, an all-reduce for [`Ranks::all_sum`] and non-blocking point-to-point messages
//! for [`Ranks::exchange`]. [`init`] starts MPI (a binary started without `mpirun` is one
//! rank and runs as without the feature) and makes a panic on any rank end the whole job
//! (MPI_Abort) with a message naming the rank, instead of leaving the others waiting.

use std::sync::Arc;

use lopin_core::distributed::ranks::Ranks;
use mpi::collective::SystemOperation;
use mpi::environment::Universe;
use mpi::topology::SimpleCommunicator;
use mpi::traits::{Communicator, CommunicatorCollectives, Destination, Source};

/// The MPI world: calls come from the thread that started MPI (the solver's main thread).
#[derive(Debug, Clone, Copy)]
pub struct MpiWorld {
    rank: usize,
    size: usize,
}

/// Starts MPI and sets [`super::current`]; keep the returned universe alive until the end of
/// `main` (dropping it finalizes MPI). None if MPI cannot start.
pub fn init() -> Option<Universe> {
    let (universe, _) = mpi::initialize_with_threading(mpi::Threading::Funneled)?;
    let world = universe.world();
    let me = MpiWorld {
        rank: usize::try_from(world.rank()).unwrap_or(0),
        size: usize::try_from(world.size()).unwrap_or(1),
    };
    if me.size > 1 {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            eprintln!("error: rank {} of {} stopped:", me.rank, me.size);
            previous(info);
            abort(3);
        }));
    }
    super::set(Arc::new(me));
    Some(universe)
}

/// Ends every rank of the job with `code` (after a failure on this rank only).
pub fn abort(code: i32) -> ! {
    SimpleCommunicator::world().abort(code)
}

impl Ranks for MpiWorld {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.size
    }

    fn all_sum(&self, values: &mut [f64]) {
        let send = values.to_vec();
        SimpleCommunicator::world().all_reduce_into(&send[..], values, SystemOperation::sum());
    }

    fn exchange(&self, send: &[(usize, Vec<f64>)], receive: &[(usize, usize)]) -> Vec<Vec<f64>> {
        let world = SimpleCommunicator::world();
        let mut got: Vec<Vec<f64>> = receive.iter().map(|&(_, n)| vec![0.0; n]).collect();
        mpi::request::scope(|scope| {
            let mut requests = Vec::with_capacity(send.len() + receive.len());
            for (buf, &(from, _)) in got.iter_mut().zip(receive) {
                requests.push(
                    world
                        .process_at_rank(rank_index(from))
                        .immediate_receive_into(scope, &mut buf[..]),
                );
            }
            for (to, data) in send {
                requests.push(
                    world
                        .process_at_rank(rank_index(*to))
                        .immediate_send(scope, &data[..]),
                );
            }
            for r in requests {
                r.wait();
            }
        });
        got
    }
}

/// An MPI rank number (ranks always fit: MPI counts them in a C int).
fn rank_index(r: usize) -> i32 {
    i32::try_from(r).unwrap_or(i32::MAX)
}
