//! Which rank of a distributed run holds which substructure (METHOD §11): a graph
//! partition of the substructure graph (vertices: substructures weighted by their dofs, the
//! work of their triangular solves; edges: two-sided interfaces weighted by their trace entries,
//! what crosses between ranks when the edge is cut) by METIS k-way, so that ranks get equal
//! work and few trace entries cross between them. Reports, per rank, what it holds and what it
//! sends: the basis of `lopin estimate --ranks P` and of the scaling model of the guide (docs/src/mpi.md).

use std::collections::HashSet;

use serde::Serialize;

use crate::problem::Problem;

/// Bytes per double.
const F64: usize = 8;

/// What one rank holds and exchanges.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RankLoad {
    /// Substructures.
    pub substructures: usize,
    /// Their dofs.
    pub dofs: usize,
    /// Distinct factorizations it computes (classes among its substructures).
    pub factorizations: usize,
    /// Two-sided interfaces with the other side on another rank.
    pub cut_interfaces: usize,
    /// Trace entries of those interfaces on this rank's side (per time step).
    pub cut_entries: usize,
}

impl RankLoad {
    /// Bytes this rank sends per iteration over a window of `steps` steps: the trace fields
    /// (F, W) of its side of every cut interface at steps 1..=steps.
    pub fn bytes_sent(&self, steps: usize) -> usize {
        2 * F64 * self.cut_entries * steps
    }
}

/// The substructures of a problem dealt to ranks.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RankAssignment {
    /// Number of ranks.
    pub ranks: usize,
    /// The rank of every substructure.
    pub rank_of: Vec<usize>,
    /// What every rank holds.
    pub loads: Vec<RankLoad>,
}

impl RankAssignment {
    /// Largest rank dofs over the mean (1 is perfect balance).
    pub fn dof_imbalance(&self) -> f64 {
        let total: usize = self.loads.iter().map(|l| l.dofs).sum();
        let mean = total as f64 / self.ranks as f64;
        self.loads.iter().map(|l| l.dofs).max().unwrap_or(0) as f64 / mean
    }

    /// Two-sided interfaces whose sides lie on different ranks.
    pub fn cut_interfaces(&self) -> usize {
        self.loads.iter().map(|l| l.cut_interfaces).sum::<usize>() / 2
    }
}

/// Deals the substructures of `problem` to `ranks` ranks (`class_of`: the factorization class
/// of every substructure). The reason when it cannot: no rank, more ranks than substructures,
/// or a partitioner failure.
pub fn assign(
    problem: &Problem,
    class_of: &[usize],
    ranks: usize,
) -> Result<RankAssignment, String> {
    let n = problem.subs.len();
    if ranks == 0 {
        return Err("a run needs at least one rank".into());
    }
    if ranks > n {
        return Err(format!(
            "{ranks} ranks for {n} substructures: at most one rank per substructure (cut the \
             bodies into more with `--split` or `substructures = N`)"
        ));
    }
    let rank_of = if ranks == 1 {
        vec![0; n]
    } else {
        partition_graph(problem, ranks)?
    };
    Ok(with_loads(problem, class_of, ranks, rank_of))
}

/// METIS k-way on the substructure graph.
fn partition_graph(problem: &Problem, ranks: usize) -> Result<Vec<usize>, String> {
    let n = problem.subs.len();
    let idx = |x: usize| metis::Idx::try_from(x).map_err(|_| "the model is too large for METIS");
    let mut neighbours: Vec<Vec<(usize, usize)>> = vec![Vec::new(); n];
    for it in problem.interfaces.iter().filter(|i| i.sides.len() == 2) {
        let (a, b) = (it.sides[0].sub, it.sides[1].sub);
        if a != b {
            neighbours[a].push((b, it.len));
            neighbours[b].push((a, it.len));
        }
    }
    let mut xadj = vec![0];
    let mut adjncy = Vec::new();
    let mut adjwgt = Vec::new();
    for list in &mut neighbours {
        // several interfaces between one pair (contact and perfect) are one edge
        list.sort_unstable();
        let mut merged: Vec<(usize, usize)> = Vec::with_capacity(list.len());
        for &(t, w) in list.iter() {
            match merged.last_mut() {
                Some((u, v)) if *u == t => *v += w,
                _ => merged.push((t, w)),
            }
        }
        for (t, w) in merged {
            adjncy.push(idx(t)?);
            adjwgt.push(idx(w.max(1))?);
        }
        xadj.push(idx(adjncy.len())?);
    }
    let vwgt: Vec<metis::Idx> = problem
        .subs
        .iter()
        .map(|s| idx(s.ndof().max(1)))
        .collect::<Result<_, _>>()?;
    let mut part = vec![0; n];
    // one METIS call at a time gives the same deal to every caller (ranks that are threads of
    // one process included)
    let _one_at_a_time = crate::mesh::partition::metis_guard();
    metis::Graph::new(1, idx(ranks)?, &xadj, &adjncy)
        .map_err(|e| format!("the substructure graph is not valid: {e}"))?
        .set_vwgt(&vwgt)
        .set_adjwgt(&adjwgt)
        .set_option(metis::option::Seed(1))
        .part_kway(&mut part)
        .map_err(|e| format!("METIS could not deal the substructures: {e}"))?;
    let rank_of: Vec<usize> = part.iter().map(|&p| p as usize).collect();
    let used: HashSet<usize> = rank_of.iter().copied().collect();
    if used.len() < ranks {
        return Err(format!(
            "METIS left {} of {ranks} ranks without a substructure: use fewer ranks",
            ranks - used.len()
        ));
    }
    Ok(rank_of)
}

/// What every rank holds under `rank_of`.
fn with_loads(
    problem: &Problem,
    class_of: &[usize],
    ranks: usize,
    rank_of: Vec<usize>,
) -> RankAssignment {
    let mut loads = vec![
        RankLoad {
            substructures: 0,
            dofs: 0,
            factorizations: 0,
            cut_interfaces: 0,
            cut_entries: 0,
        };
        ranks
    ];
    let mut classes: Vec<HashSet<usize>> = vec![HashSet::new(); ranks];
    for (i, s) in problem.subs.iter().enumerate() {
        let r = rank_of[i];
        loads[r].substructures += 1;
        loads[r].dofs += s.ndof();
        classes[r].insert(class_of.get(i).copied().unwrap_or(i));
    }
    for (load, set) in loads.iter_mut().zip(&classes) {
        load.factorizations = set.len();
    }
    for it in problem.interfaces.iter().filter(|i| i.sides.len() == 2) {
        let (a, b) = (rank_of[it.sides[0].sub], rank_of[it.sides[1].sub]);
        if a != b {
            for r in [a, b] {
                loads[r].cut_interfaces += 1;
                loads[r].cut_entries += it.len;
            }
        }
    }
    RankAssignment {
        ranks,
        rank_of,
        loads,
    }
}
