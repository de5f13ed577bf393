//! Ranks as threads of one process ([`crate::distributed::ranks::Ranks`] over channels and a barrier): the
//! distributed solver runs, tested, without MPI. [`run`] starts P ranks, each calling the same
//! closure with its own [`ThreadRanks`], and returns their results in rank order.

use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Barrier, Mutex};

use crate::distributed::ranks::Ranks;

/// What the ranks of one [`run`] share.
#[derive(Debug)]
struct Shared {
    size: usize,
    barrier: Barrier,
    sum: Mutex<Vec<f64>>,
}

/// One rank of a [`run`].
#[derive(Debug)]
pub struct ThreadRanks {
    rank: usize,
    shared: Arc<Shared>,
    /// Sender to every rank.
    to: Vec<Sender<Vec<f64>>>,
    /// Receiver from every rank.
    from: Vec<Mutex<Receiver<Vec<f64>>>>,
}

impl Ranks for ThreadRanks {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_sum(&self, values: &mut [f64]) {
        let s = &self.shared;
        // the previous sum has been read by every rank before rank 0 clears it
        s.barrier.wait();
        if self.rank == 0 {
            let mut sum = lock(&s.sum);
            sum.clear();
            // −0, the neutral element of addition (+0 would turn −0 into +0)
            sum.resize(values.len(), -0.0);
        }
        s.barrier.wait();
        {
            let mut sum = lock(&s.sum);
            sum.iter_mut().zip(values.iter()).for_each(|(a, b)| *a += b);
        }
        s.barrier.wait();
        values.copy_from_slice(&lock(&s.sum));
    }

    fn exchange(&self, send: &[(usize, Vec<f64>)], receive: &[(usize, usize)]) -> Vec<Vec<f64>> {
        for (to, data) in send {
            // a rank that ended drops its receivers; its peers then end on their receive
            let _ = self.to[*to].send(data.clone());
        }
        receive
            .iter()
            .map(|&(from, len)| {
                let data = lock(&self.from[from])
                    .recv()
                    .unwrap_or_else(|_| panic!("rank {from} ended during an exchange"));
                assert_eq!(data.len(), len, "message length from rank {from}");
                data
            })
            .collect()
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Runs `body` on `size` ranks, one thread each, and returns their results in rank order.
pub fn run<R, F>(size: usize, body: F) -> Vec<R>
where
    R: Send,
    F: Fn(Arc<ThreadRanks>) -> R + Sync,
{
    let shared = Arc::new(Shared {
        size,
        barrier: Barrier::new(size),
        sum: Mutex::new(Vec::new()),
    });
    // channel[a][b]: from rank a to rank b
    let mut senders: Vec<Vec<Option<Sender<Vec<f64>>>>> = (0..size).map(|_| Vec::new()).collect();
    let mut receivers: Vec<Vec<Option<Receiver<Vec<f64>>>>> = (0..size)
        .map(|_| (0..size).map(|_| None).collect())
        .collect();
    for (a, row) in senders.iter_mut().enumerate() {
        for b in 0..size {
            let (tx, rx) = channel();
            row.push(Some(tx));
            receivers[b][a] = Some(rx);
        }
    }
    let ranks: Vec<Arc<ThreadRanks>> = (0..size)
        .map(|r| {
            Arc::new(ThreadRanks {
                rank: r,
                shared: shared.clone(),
                to: senders[r].iter_mut().filter_map(Option::take).collect(),
                from: receivers[r]
                    .iter_mut()
                    .filter_map(Option::take)
                    .map(Mutex::new)
                    .collect(),
            })
        })
        .collect();
    std::thread::scope(|scope| {
        let handles: Vec<_> = ranks
            .into_iter()
            .map(|r| {
                let body = &body;
                scope.spawn(move || body(r))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().unwrap_or_else(|e| std::panic::resume_unwind(e)))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sums_and_exchanges_between_three_ranks() {
        let out = run(3, |r| {
            let me = r.rank();
            let mut v = vec![0.0; 3];
            v[me] = (me + 1) as f64;
            r.all_sum(&mut v);
            // a ring: send to the next rank, receive from the previous one
            let next = (me + 1) % 3;
            let prev = (me + 2) % 3;
            let got = r.exchange(&[(next, vec![me as f64; me + 1])], &[(prev, prev + 1)]);
            (v, got)
        });
        for (me, (v, got)) in out.into_iter().enumerate() {
            assert_eq!(v, vec![1.0, 2.0, 3.0]);
            let prev = (me + 2) % 3;
            assert_eq!(got, vec![vec![prev as f64; prev + 1]]);
        }
    }
}
