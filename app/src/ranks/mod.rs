//! The ranks this process runs among: one, or, in a binary built with the `mpi`
//! feature and started by `mpirun -np P` with P > 1, the MPI world ([`mpi_world`]). Commands
//! ask [`current`] for the ranks to make their solver on, [`is_root`] whether they print and
//! write the files rank 0 owns, and [`agree`] to turn an error found on some ranks into the same
//! outcome on every rank (one message, from the lowest rank that failed, and no hang).

#[cfg(feature = "mpi")]
pub mod mpi_world;

use std::sync::{Arc, OnceLock};

use lopin_core::distributed::ranks::Ranks;

static RANKS: OnceLock<Arc<dyn Ranks>> = OnceLock::new();

/// Sets the ranks of this process (once, at start-up; later calls are ignored).
pub fn set(ranks: Arc<dyn Ranks>) {
    let _ = RANKS.set(ranks);
}

/// The ranks of a distributed run (None on one rank: the plain solver runs).
pub fn current() -> Option<Arc<dyn Ranks>> {
    RANKS.get().filter(|r| r.size() > 1).cloned()
}

/// Whether this rank prints the results and writes the shared files (rank 0, or the only one).
pub fn is_root() -> bool {
    current().is_none_or(|r| r.rank() == 0)
}

/// The error of a rank whose failure another rank reports: a failure found on any rank of a
/// distributed run ends every rank, and only the lowest rank that failed prints its message
/// (`main` prints nothing for this one).
#[derive(Debug)]
pub struct Silent;

impl std::fmt::Display for Silent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("another rank failed")
    }
}

impl std::error::Error for Silent {}

/// Makes every rank of a distributed run agree on `result`: if any rank failed, every rank
/// returns an error, the lowest failing rank its own (printed by `main`) and the others
/// [`Silent`]. Collective; the identity on one rank.
pub fn agree<T>(result: anyhow::Result<T>) -> anyhow::Result<T> {
    let Some(ranks) = current() else {
        return result;
    };
    let mut failed = vec![0.0; ranks.size()];
    failed[ranks.rank()] = f64::from(u8::from(result.is_err()));
    ranks.all_sum(&mut failed);
    let first = failed.iter().position(|&x| x > 0.0);
    match (result, first) {
        (Ok(v), None) => Ok(v),
        (Err(e), Some(r)) if r == ranks.rank() => Err(e),
        (_, Some(_)) => Err(anyhow::Error::new(Silent)),
        (Err(e), None) => Err(e),
    }
}
