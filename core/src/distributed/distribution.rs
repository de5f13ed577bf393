//! Which rank holds which part of a distributed LATIN solve, and the messages of one iteration
//! (METHOD §11 "Parallelism"). A substructure is held by one rank
//! ([`crate::distributed::rank_assignment`]: METIS on the substructure graph where the `partition` feature is
//! on, else contiguous runs of equal dofs); an interface by the rank of its first side. A rank
//! factorizes, marches and relaxes only its substructures (METHOD §4, §6) and runs the local
//! stage (METHOD §5) only on its interfaces, so per iteration two point-to-point exchanges
//! carry everything that crosses between ranks:
//!
//! - before the local stage, s = (F, W) of every side whose substructure lies on another rank
//!   than its interface, over the window's steps ([`Distribution::send_traces`]);
//! - after it, ŝ of those sides back to the substructure's rank ([`Distribution::send_hats`]).
//!
//! Sums (η, η̄, the macro right-hand side of METHOD §9) go through [`Ranks::all_sum`] with one
//! non-zero contribution per entry and rank ([`crate::distributed::ranks`]), so every rank reaches the same
//! η and the same decisions as the run on one machine, bit for bit.
//!
//! A rank stores only the interface fields it works on ([`Distribution::needs_trace`],
//! [`Distribution::needs_hat`]): s of its substructures and of the other sides of its
//! interfaces, ŝ of its interfaces and of its substructures' sides. The others stay empty, so
//! memory per rank falls with the number of ranks; [`Distribution::gather_to_root`] assembles the
//! whole solution on rank 0 where a file needs it. Every exchange and sum is timed
//! ([`Distribution::comm_seconds`]).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use crate::counters::Instant;

use crate::distributed::ranks::{OneRank, Ranks};
use crate::interfaces::interface::Interface;
use crate::problem::Problem;
use crate::stages::indicator::IndicatorSums;
use crate::state::{InterfaceState, TraceHistory};

/// One interface side whose substructure and interface lie on different ranks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct CutSide {
    interface: usize,
    side: usize,
    sub: usize,
    /// Offset of the side in the substructure's trace.
    offset: usize,
    /// Trace entries of the side.
    len: usize,
}

/// The cut sides between this rank and one other, in (interface, side) order.
#[derive(Debug, Clone, PartialEq, Eq)]
struct Neighbour {
    rank: usize,
    /// Sides of this rank's substructures on the other rank's interfaces.
    subs_here: Vec<CutSide>,
    /// Sides of the other rank's substructures on this rank's interfaces.
    interfaces_here: Vec<CutSide>,
}

/// The ranks of a solve and what each holds.
#[derive(Debug, Clone)]
pub struct Distribution {
    ranks: Arc<dyn Ranks>,
    /// Rank of every substructure.
    sub_rank: Vec<usize>,
    /// Rank of every interface (that of its first side's substructure).
    interface_rank: Vec<usize>,
    neighbours: Vec<Neighbour>,
    /// Whether this rank stores s of each substructure (its own, and the other sides of its
    /// interfaces).
    trace_needed: Vec<bool>,
    /// Whether this rank stores ŝ of each interface (its own, and its substructures' sides).
    hat_needed: Vec<bool>,
    /// Nanoseconds spent in exchanges and sums between ranks.
    comm_nanos: Arc<AtomicU64>,
}

impl Distribution {
    /// Everything on one rank (the run on one machine).
    pub fn single(problem: &Problem) -> Self {
        Self::single_for(problem.subs.len(), &problem.interfaces)
    }

    /// Everything on one rank, for `subs` substructures and these interfaces.
    pub fn single_for(subs: usize, interfaces: &[Interface]) -> Self {
        Self::with_ranks_of(interfaces, Arc::new(OneRank), vec![0; subs])
    }

    /// The substructures of `problem` dealt to `ranks` by [`deal`].
    pub fn new(
        problem: &Problem,
        class_of: &[usize],
        ranks: Arc<dyn Ranks>,
    ) -> Result<Self, String> {
        // every rank checks (the same refusals everywhere), rank 0's deal is the one used
        let mine = deal(problem, class_of, ranks.size());
        let n = problem.subs.len();
        let mut shared = vec![0.0; n + 1];
        if ranks.rank() == 0 {
            match &mine {
                Ok(r) => shared[..n]
                    .iter_mut()
                    .zip(r)
                    .for_each(|(x, &r)| *x = r as f64),
                Err(_) => shared[n] = 1.0,
            }
        }
        ranks.all_sum(&mut shared);
        if shared[n] > 0.0 {
            return Err(mine.err().unwrap_or_else(|| {
                "rank 0 could not deal the substructures to the ranks".to_string()
            }));
        }
        let sub_rank = shared[..n].iter().map(|&x| x as usize).collect();
        Ok(Self::with_ranks_of(&problem.interfaces, ranks, sub_rank))
    }

    /// Substructure i on rank `sub_rank[i]`.
    pub fn with_ranks_of(
        interfaces: &[Interface],
        ranks: Arc<dyn Ranks>,
        sub_rank: Vec<usize>,
    ) -> Self {
        let me = ranks.rank();
        let interface_rank: Vec<usize> = interfaces
            .iter()
            .map(|i| sub_rank[i.sides[0].sub])
            .collect();
        let mut neighbours: Vec<Neighbour> = (0..ranks.size())
            .map(|rank| Neighbour {
                rank,
                subs_here: Vec::new(),
                interfaces_here: Vec::new(),
            })
            .collect();
        for (i, iface) in interfaces.iter().enumerate() {
            for (j, side) in iface.sides.iter().enumerate() {
                let (at_sub, at_iface) = (sub_rank[side.sub], interface_rank[i]);
                if at_sub == at_iface {
                    continue;
                }
                let cut = CutSide {
                    interface: i,
                    side: j,
                    sub: side.sub,
                    offset: side.offset,
                    len: iface.len,
                };
                if at_sub == me {
                    neighbours[at_iface].subs_here.push(cut);
                } else if at_iface == me {
                    neighbours[at_sub].interfaces_here.push(cut);
                }
            }
        }
        neighbours.retain(|n| !n.subs_here.is_empty() || !n.interfaces_here.is_empty());
        let mut trace_needed: Vec<bool> = sub_rank.iter().map(|&r| r == me).collect();
        let mut hat_needed: Vec<bool> = interface_rank.iter().map(|&r| r == me).collect();
        for (i, iface) in interfaces.iter().enumerate() {
            for side in &iface.sides {
                if interface_rank[i] == me {
                    trace_needed[side.sub] = true;
                }
                if sub_rank[side.sub] == me {
                    hat_needed[i] = true;
                }
            }
        }
        Self {
            ranks,
            sub_rank,
            interface_rank,
            neighbours,
            trace_needed,
            hat_needed,
            comm_nanos: Arc::new(AtomicU64::new(0)),
        }
    }

    /// Whether this rank stores s of substructure `i`: it holds it, or an interface it holds
    /// has a side on it.
    pub fn needs_trace(&self, i: usize) -> bool {
        self.trace_needed[i]
    }

    /// Whether this rank stores ŝ of interface `i`: it holds it, or one of its substructures
    /// is a side of it.
    pub fn needs_hat(&self, i: usize) -> bool {
        self.hat_needed[i]
    }

    /// Seconds this rank has spent in exchanges and sums between ranks (waiting included), since
    /// the distribution was made; 0 on one machine.
    pub fn comm_seconds(&self) -> f64 {
        self.comm_nanos.load(Ordering::Relaxed) as f64 * 1e-9
    }

    /// Runs `f`, adding its wall time to the communication clock.
    fn timed<T>(&self, f: impl FnOnce() -> T) -> T {
        let t = Instant::now();
        let out = f();
        let nanos = u64::try_from(t.elapsed().as_nanos()).unwrap_or(u64::MAX);
        self.comm_nanos.fetch_add(nanos, Ordering::Relaxed);
        out
    }

    /// The communication between ranks.
    pub fn ranks(&self) -> &dyn Ranks {
        &*self.ranks
    }

    /// This rank.
    pub fn rank(&self) -> usize {
        self.ranks.rank()
    }

    /// Number of ranks.
    pub fn size(&self) -> usize {
        self.ranks.size()
    }

    /// Whether everything is on this one rank.
    pub fn is_single(&self) -> bool {
        self.ranks.size() == 1
    }

    /// Rank of every substructure.
    pub fn sub_ranks(&self) -> &[usize] {
        &self.sub_rank
    }

    /// Whether this rank holds substructure `i`.
    pub fn holds_sub(&self, i: usize) -> bool {
        self.sub_rank[i] == self.ranks.rank()
    }

    /// Whether this rank holds interface `i` (runs its local stage).
    pub fn holds_interface(&self, i: usize) -> bool {
        self.interface_rank[i] == self.ranks.rank()
    }

    /// Before the local stage: s of steps m0..=m1 of every cut side, from the substructure's
    /// rank into the interface rank's copy of `s`.
    pub fn send_traces(&self, s: &mut InterfaceState, steps: (usize, usize)) {
        self.transfer(
            s,
            steps,
            |n| &n.subs_here,
            |n| &n.interfaces_here,
            |s, c| (&mut s.subs[c.sub], c.offset),
        );
    }

    /// After the local stage: ŝ of steps m0..=m1 of every cut side, from the interface's rank
    /// into the substructure rank's copy of `hats`.
    pub fn send_hats(&self, hats: &mut [Vec<TraceHistory>], steps: (usize, usize)) {
        self.transfer(
            hats,
            steps,
            |n| &n.interfaces_here,
            |n| &n.subs_here,
            |h, c| (&mut h[c.interface][c.side], 0),
        );
    }

    /// One exchange of (F, W) of steps m0..=m1 of cut sides: this rank sends the sides
    /// `outgoing` lists and receives those `incoming` lists, each side's history and offset of
    /// its entries in a step found in `x` by `side`.
    fn transfer<X: ?Sized>(
        &self,
        x: &mut X,
        (m0, m1): (usize, usize),
        outgoing: impl Fn(&Neighbour) -> &Vec<CutSide>,
        incoming: impl Fn(&Neighbour) -> &Vec<CutSide>,
        side: impl for<'a> Fn(&'a mut X, &CutSide) -> (&'a mut TraceHistory, usize),
    ) {
        if self.is_single() {
            return;
        }
        let mut send: Vec<(usize, Vec<f64>)> = Vec::new();
        for n in self.neighbours.iter().filter(|n| !outgoing(n).is_empty()) {
            let mut out = Vec::new();
            for c in outgoing(n) {
                let (h, offset) = side(x, c);
                for m in m0..=m1 {
                    let r = h.at(m).start + offset..h.at(m).start + offset + c.len;
                    out.extend_from_slice(&h.f[r.clone()]);
                    out.extend_from_slice(&h.w[r]);
                }
            }
            send.push((n.rank, out));
        }
        let from: Vec<&Neighbour> = self
            .neighbours
            .iter()
            .filter(|n| !incoming(n).is_empty())
            .collect();
        let receive: Vec<(usize, usize)> = from
            .iter()
            .map(|n| {
                let values = incoming(n).iter().map(|c| 2 * c.len).sum::<usize>();
                (n.rank, values * (m1 + 1 - m0))
            })
            .collect();
        let got = self.timed(|| self.ranks.exchange(&send, &receive));
        for (n, data) in from.into_iter().zip(got) {
            let mut at = 0;
            for c in incoming(n) {
                let (h, offset) = side(x, c);
                for m in m0..=m1 {
                    let start = h.at(m).start + offset;
                    h.f[start..start + c.len].copy_from_slice(&data[at..at + c.len]);
                    at += c.len;
                    h.w[start..start + c.len].copy_from_slice(&data[at..at + c.len]);
                    at += c.len;
                }
            }
        }
    }

    /// Whether this rank holds a member of each of the `count` classes of `class_of` (the
    /// classes whose operators it computes).
    pub fn holds_classes(&self, class_of: &[usize], count: usize) -> Vec<bool> {
        let mut held = vec![false; count];
        for (i, &c) in class_of.iter().enumerate() {
            held[c] |= self.holds_sub(i);
        }
        held
    }

    /// `values` ← the sum over the ranks (exact where each entry has at most two non-zero
    /// contributions, [`crate::distributed::ranks`]).
    pub fn all_sum(&self, values: &mut [f64]) {
        if !self.is_single() {
            self.timed(|| self.ranks.all_sum(values));
        }
    }

    /// η sums computed one per item on the rank that holds it (None elsewhere), summed over the
    /// ranks and added in item order: the same total on every rank and on one machine.
    pub fn gathered_sums(
        &self,
        items: impl Iterator<Item = Option<IndicatorSums>>,
    ) -> IndicatorSums {
        let mut flat: Vec<f64> = items
            .flat_map(|s| {
                // −0: the neutral element of the sum over the ranks ([`crate::distributed::ranks`])
                s.map_or([-0.0, -0.0], |s| [s.num, s.den])
            })
            .collect();
        self.all_sum(&mut flat);
        let mut total = IndicatorSums::default();
        for pair in flat.chunks_exact(2) {
            total.add(IndicatorSums {
                num: pair[0],
                den: pair[1],
            });
        }
        total
    }

    /// Whether any rank passes `flag` true.
    pub fn any(&self, flag: bool) -> bool {
        if self.is_single() {
            return flag;
        }
        let mut v = [f64::from(u8::from(flag))];
        self.all_sum(&mut v);
        v[0] > 0.0
    }

    /// Makes the whole solution complete on rank 0: s of every substructure and ŝ of every
    /// interface side. Every other rank sends what it holds (its substructures' s, its
    /// interfaces' ŝ) in messages of bounded size; rank 0 allocates what it lacks. The other
    /// ranks keep only their own parts.
    pub fn gather_to_root(&self, s: &mut InterfaceState, hats: &mut [Vec<TraceHistory>]) {
        if self.is_single() {
            return;
        }
        const PIECE: usize = 1 << 22;
        let me = self.rank();
        let steps = s.steps;
        let mut owners: Vec<usize> = self.sub_rank.clone();
        let mut items: Vec<&mut TraceHistory> = s.subs.iter_mut().collect();
        for (k, sides) in hats.iter_mut().enumerate() {
            for h in sides {
                owners.push(self.interface_rank[k]);
                items.push(h);
            }
        }
        let values = |h: &TraceHistory| 2 * h.len * (steps + 1);
        // the same pieces on every rank: runs of items of one owner, up to PIECE values each
        let mut pieces: Vec<(usize, Vec<usize>)> = Vec::new();
        for rank in 1..self.size() {
            let mut piece: Vec<usize> = Vec::new();
            let mut size = 0;
            for (n, _) in owners.iter().enumerate().filter(|&(_, &o)| o == rank) {
                let v = values(items[n]);
                if !piece.is_empty() && size + v > PIECE {
                    pieces.push((rank, std::mem::take(&mut piece)));
                    size = 0;
                }
                piece.push(n);
                size += v;
            }
            if !piece.is_empty() {
                pieces.push((rank, piece));
            }
        }
        for (rank, piece) in pieces {
            let total: usize = piece.iter().map(|&n| values(items[n])).sum();
            let (send, receive) = if me == rank {
                let mut data = Vec::with_capacity(total);
                for &n in &piece {
                    data.extend_from_slice(&items[n].f);
                    data.extend_from_slice(&items[n].w);
                }
                (vec![(0, data)], Vec::new())
            } else if me == 0 {
                (Vec::new(), vec![(rank, total)])
            } else {
                (Vec::new(), Vec::new())
            };
            let got = self.timed(|| self.ranks.exchange(&send, &receive));
            if let Some(data) = got.into_iter().next() {
                let mut at = 0;
                for &n in &piece {
                    let h = &mut *items[n];
                    let half = h.len * (steps + 1);
                    h.f = data[at..at + half].to_vec();
                    h.w = data[at + half..at + 2 * half].to_vec();
                    at += 2 * half;
                }
            }
        }
    }
}

/// The rank of every substructure of `problem` among `ranks`: METIS on the substructure graph
/// ([`crate::distributed::rank_assignment`]) where the `partition` feature is on, else contiguous runs of
/// about equal dofs. The reason when it cannot (more ranks than substructures).
pub fn deal(problem: &Problem, class_of: &[usize], ranks: usize) -> Result<Vec<usize>, String> {
    #[cfg(feature = "partition")]
    {
        crate::distributed::rank_assignment::assign(problem, class_of, ranks).map(|a| a.rank_of)
    }
    #[cfg(not(feature = "partition"))]
    {
        let _ = class_of;
        let n = problem.subs.len();
        if ranks == 0 || ranks > n {
            return Err(format!(
                "{ranks} ranks for {n} substructures: at least one and at most one rank per \
                 substructure"
            ));
        }
        let total: usize = problem.subs.iter().map(|s| s.ndof()).sum();
        let mut out = Vec::with_capacity(n);
        let mut before = 0;
        let mut previous = 0;
        for (i, s) in problem.subs.iter().enumerate() {
            // by the dofs before the middle of this substructure, one rank after another, and
            // never leaving a rank empty
            let middle = before + s.ndof() / 2;
            let by_dofs = middle * ranks / total.max(1);
            let lowest = ranks.saturating_sub(n - i);
            let r = if i == 0 {
                0
            } else {
                by_dofs
                    .clamp(previous, previous + 1)
                    .max(lowest)
                    .min(ranks - 1)
            };
            out.push(r);
            previous = r;
            before += s.ndof();
        }
        Ok(out)
    }
}
