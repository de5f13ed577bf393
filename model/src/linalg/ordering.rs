//! The fill-reducing ordering of a substructure operator's Cholesky factor (METHOD §4, §11: the
//! triangular solves read the whole factor, so fewer entries mean faster solves and less memory):
//! nested dissection of the node graph for large substructures, where it leaves fewer entries in
//! L than faer's approximate minimum degree, and that minimum degree below
//! [`LARGE_NODES`] nodes or where METIS is not compiled in (the browser build).
//!
//! The dissection bisects the graph with METIS (its recursive bisection, through the safe
//! `metis` crate), takes the smaller of the two sides' boundaries as the separator, orders the two
//! remaining halves first (recursively) and the separator last, and keeps the natural order in
//! pieces of at most [`LEAF_NODES`] nodes. The three dofs of a node stay together.

use faer::sparse::Triplet;

use super::factor::LARGE_NODES;

/// Pieces of at most this many nodes are not dissected further.
#[cfg(feature = "partition")]
const LEAF_NODES: usize = 8;

/// The fill-reducing permutation of the dofs for a lower-triangle pattern of `n` dofs (three a
/// node): (new → old, old → new), or None for faer's minimum degree.
pub fn dof_permutation<T>(
    n: usize,
    lower: &[Triplet<usize, usize, T>],
) -> Option<(Vec<usize>, Vec<usize>)> {
    if !cfg!(feature = "partition") || !n.is_multiple_of(3) || n / 3 < LARGE_NODES {
        return None;
    }
    let nodes = nested_dissection(&node_graph(n / 3, lower))?;
    let forward: Vec<usize> = nodes
        .iter()
        .flat_map(|&p| (0..3).map(move |c| 3 * p + c))
        .collect();
    let mut inverse = vec![0; n];
    for (new, &old) in forward.iter().enumerate() {
        inverse[old] = new;
    }
    Some((forward, inverse))
}

/// The adjacency lists of the nodes (dof i belongs to node i / 3), without self loops.
fn node_graph<T>(nodes: usize, lower: &[Triplet<usize, usize, T>]) -> Vec<Vec<usize>> {
    let mut adjacency: Vec<Vec<usize>> = vec![Vec::new(); nodes];
    for t in lower {
        let (a, b) = (t.row / 3, t.col / 3);
        if a != b {
            adjacency[a].push(b);
            adjacency[b].push(a);
        }
    }
    for a in &mut adjacency {
        a.sort_unstable();
        a.dedup();
    }
    adjacency
}

/// The nodes in nested-dissection order (new → old), or None where METIS fails.
#[cfg(feature = "partition")]
fn nested_dissection(graph: &[Vec<usize>]) -> Option<Vec<usize>> {
    /// What the dissection does next.
    enum Step {
        /// Order a piece of the graph.
        Order(Vec<usize>),
        /// Append a separator.
        Emit(Vec<usize>),
    }
    let mut order = Vec::with_capacity(graph.len());
    let mut local = vec![usize::MAX; graph.len()];
    let mut plan = vec![Step::Order((0..graph.len()).collect())];
    while let Some(step) = plan.pop() {
        match step {
            Step::Emit(separator) => order.extend(separator),
            Step::Order(piece) if piece.len() <= LEAF_NODES => order.extend(piece),
            Step::Order(piece) => match bisect(graph, &piece, &mut local) {
                Some((a, b, separator)) => {
                    // the halves first, then their separator (the plan is a stack)
                    plan.push(Step::Emit(separator));
                    plan.push(Step::Order(b));
                    plan.push(Step::Order(a));
                }
                None => order.extend(piece),
            },
        }
    }
    (order.len() == graph.len()).then_some(order)
}

/// Splits `piece` into two halves and a separator between them (no edge joins the halves), or
/// None where METIS fails or leaves a side empty. `local` maps a node to its index in the piece
/// (usize::MAX outside it) and is restored before returning.
#[cfg(feature = "partition")]
fn bisect(
    graph: &[Vec<usize>],
    piece: &[usize],
    local: &mut [usize],
) -> Option<(Vec<usize>, Vec<usize>, Vec<usize>)> {
    for (i, &v) in piece.iter().enumerate() {
        local[v] = i;
    }
    let mut xadj: Vec<metis::Idx> = Vec::with_capacity(piece.len() + 1);
    let mut adjncy: Vec<metis::Idx> = Vec::new();
    xadj.push(0);
    for &v in piece {
        adjncy.extend(
            graph[v]
                .iter()
                .filter(|&&u| local[u] != usize::MAX)
                .map(|&u| local[u] as metis::Idx),
        );
        xadj.push(adjncy.len() as metis::Idx);
    }
    let mut part = vec![0 as metis::Idx; piece.len()];
    let parted = {
        let _one_at_a_time = crate::mesh::partition::metis_guard();
        metis::Graph::new(1, 2, &xadj, &adjncy)
            .ok()
            .and_then(|g| g.part_recursive(&mut part).ok())
            .is_some()
    };
    // the boundary of each side: its nodes with a neighbour on the other side
    let mut boundary = [Vec::new(), Vec::new()];
    if parted {
        for (i, &v) in piece.iter().enumerate() {
            let side = part[i];
            if graph[v]
                .iter()
                .any(|&u| local[u] != usize::MAX && part[local[u]] != side)
            {
                boundary[side as usize].push(i);
            }
        }
    }
    for &v in piece {
        local[v] = usize::MAX;
    }
    if !parted {
        return None;
    }
    // the smaller boundary separates the rest of its side from the other side
    let cut = usize::from(boundary[1].len() < boundary[0].len());
    let mut in_separator = vec![false; piece.len()];
    for &i in &boundary[cut] {
        in_separator[i] = true;
    }
    let (mut halves, mut separator) = ([Vec::new(), Vec::new()], Vec::new());
    for (i, &v) in piece.iter().enumerate() {
        if in_separator[i] {
            separator.push(v);
        } else {
            halves[part[i] as usize].push(v);
        }
    }
    let [a, b] = halves;
    (!a.is_empty() && !b.is_empty()).then_some((a, b, separator))
}

#[cfg(not(feature = "partition"))]
fn nested_dissection(_: &[Vec<usize>]) -> Option<Vec<usize>> {
    None
}

#[cfg(all(test, feature = "partition"))]
mod tests {
    use super::*;

    /// An SPD matrix on an nx × ny × nz grid of nodes, three dofs a node, each node joined to its
    /// 26 neighbours (the pattern of a hexahedral mesh): lower-triangle triplets, −1 between
    /// neighbours' like components, 30 on the diagonal.
    fn grid(nx: usize, ny: usize, nz: usize) -> Vec<Triplet<usize, usize, f64>> {
        let id = |x: usize, y: usize, z: usize| (z * ny + y) * nx + x;
        let mut t = Vec::new();
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let a = id(x, y, z);
                    for c in 0..3 {
                        t.push(Triplet::new(3 * a + c, 3 * a + c, 30.0));
                    }
                    for (dx, dy, dz) in (0..27).map(|k| (k % 3, k / 3 % 3, k / 9)) {
                        let (u, v, w) = (x + dx, y + dy, z + dz);
                        if u == 0 || v == 0 || w == 0 || u > nx || v > ny || w > nz {
                            continue;
                        }
                        let b = id(u - 1, v - 1, w - 1);
                        if b > a {
                            for c in 0..3 {
                                t.push(Triplet::new(3 * b + c, 3 * a + c, -1.0));
                            }
                        }
                    }
                }
            }
        }
        t
    }

    /// On a 20 × 20 × 12 grid (4,800 nodes) the dissection leaves fewer entries in L than the
    /// minimum degree, and the factor it orders solves the system to rounding.
    #[test]
    fn the_dissection_leaves_fewer_entries_and_solves_the_same_system() {
        use crate::linalg::factor::{factorize_ordered, CholeskyFactor};
        let (nx, ny, nz) = (20, 20, 12);
        let n = 3 * nx * ny * nz;
        let t = grid(nx, ny, nz);
        let (amd, _) = factorize_ordered::<f64>(n, &t, None).expect("SPD");
        let (nd, _) = factorize_ordered::<f64>(n, &t, dof_permutation(n, &t)).expect("SPD");
        println!(
            "entries of L: minimum degree {}, dissection {}",
            amd.len_val(),
            nd.len_val()
        );
        assert!(
            nd.len_val() * 10 < amd.len_val() * 9,
            "{} against {}",
            nd.len_val(),
            amd.len_val()
        );
        let factor = CholeskyFactor::new(n, &t).expect("SPD");
        assert_eq!(factor.factor_nnz(), nd.len_val(), "the factor is dissected");
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let mut b = vec![0.0; n];
        for e in &t {
            b[e.row] += e.val * x[e.col];
            if e.row != e.col {
                b[e.col] += e.val * x[e.row];
            }
        }
        let mut scratch = factor.scratch();
        factor.solve_in_place(&mut b, &mut scratch);
        let error = b
            .iter()
            .zip(&x)
            .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
        assert!(error < 1e-12, "{error:e}");
    }

    /// The dissection of a 16 × 16 × 12 grid is a permutation of all dofs with the inverse it
    /// returns, the three dofs of a node together and in order; a small grid keeps the minimum
    /// degree.
    #[test]
    fn the_dissection_is_a_permutation_keeping_each_nodes_dofs_together() {
        let (nx, ny, nz) = (16, 16, 12);
        let n = 3 * nx * ny * nz;
        assert!(n / 3 >= LARGE_NODES);
        let (forward, inverse) = dof_permutation(n, &grid(nx, ny, nz)).expect("dissected");
        let mut seen = vec![false; n];
        for (new, &old) in forward.iter().enumerate() {
            assert!(!seen[old]);
            seen[old] = true;
            assert_eq!(inverse[old], new);
            assert_eq!(old % 3, new % 3, "a node's dofs stay in order");
            if new % 3 > 0 {
                assert_eq!(forward[new - 1] / 3, old / 3, "a node's dofs stay together");
            }
        }
        assert!(seen.iter().all(|&s| s));
        // small substructures keep faer's minimum degree
        assert!(dof_permutation(3 * 27, &grid(3, 3, 3)).is_none());
    }
}
