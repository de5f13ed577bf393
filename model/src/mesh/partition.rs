//! Automatic substructuring (METHOD §1): a body's mesh cut into N substructures by a
//! graph partitioner (METIS, k-way, on the dual graph whose vertices are the elements and whose
//! edges join elements sharing a face), each part a mesh of its own with its own copy of the
//! nodes it shares with other parts, so that interface detection pairs them as perfect
//! interfaces. Parts are balanced by their dofs: an element weighs its node count, and the
//! partition is refined until the parts' dofs (shared nodes counted in every part that holds
//! them) lie within [`DOF_BALANCE`] of their mean, or the best partition tried is kept.

use std::collections::HashMap;

use crate::mesh::Mesh;

/// One METIS call at a time in the whole process: METIS keeps its random state in globals, so
/// concurrent calls (threads of one process, the factorizations' orderings beside a partition
/// or a deal of ranks) would disturb each other's results. Every METIS call takes this guard.
pub fn metis_guard() -> std::sync::MutexGuard<'static, ()> {
    static METIS: std::sync::Mutex<()> = std::sync::Mutex::new(());
    METIS.lock().unwrap_or_else(|e| e.into_inner())
}

/// Largest relative deviation of a part's dofs from the mean that the partitioner aims for.
pub const DOF_BALANCE: f64 = 0.10;

/// METIS imbalance allowances tried in turn (per mille over the mean weight), tightest last.
const UFACTORS: [i32; 3] = [30, 10, 1];

/// A body's mesh cut into parts: per part, its mesh and the body node each of its nodes copies.
#[derive(Debug, Clone, PartialEq)]
pub struct Partition {
    /// The part of each element of the body's mesh.
    pub part_of: Vec<usize>,
    /// Each part's mesh and, per node, the node of the body's mesh it copies.
    pub parts: Vec<(Mesh, Vec<usize>)>,
}

impl Partition {
    /// Dofs of each part (3 × its nodes, shared nodes counted in every part).
    pub fn dofs(&self) -> Vec<usize> {
        self.parts.iter().map(|(m, _)| m.ndof()).collect()
    }

    /// Largest relative deviation of a part's dofs from the mean.
    pub fn imbalance(&self) -> f64 {
        imbalance(&self.dofs())
    }
}

/// Cuts `mesh` into `parts` connected parts with METIS (k-way on the dual graph), balanced by
/// dofs. The reason when it cannot: fewer elements than parts, a partitioner failure, or an
/// empty part.
pub fn partition(mesh: &Mesh, parts: usize) -> Result<Partition, String> {
    let n = mesh.elements.len();
    if parts == 0 {
        return Err("the number of substructures must be at least 1".into());
    }
    if parts > n {
        return Err(format!(
            "{parts} substructures asked of a mesh of {n} elements (at most one per element)"
        ));
    }
    if parts == 1 {
        let part_of = vec![0; n];
        let parts = split(mesh, &part_of, 1);
        return Ok(Partition { part_of, parts });
    }
    let (xadj, adjncy) = dual_graph(mesh)?;
    let weight: Vec<metis::Idx> = mesh
        .elements
        .iter()
        .map(|e| e.nodes().len() as metis::Idx)
        .collect();
    let nparts = metis::Idx::try_from(parts).map_err(|_| "too many substructures".to_string())?;
    let mut best: Option<Partition> = None;
    for ufactor in UFACTORS {
        // a disconnected body cannot be cut into contiguous parts: it is cut without
        let part = kway(&xadj, &adjncy, &weight, nparts, ufactor, true)
            .or_else(|_| kway(&xadj, &adjncy, &weight, nparts, ufactor, false))
            .map_err(|e| format!("METIS could not partition the mesh: {e}"))?;
        let part_of: Vec<usize> = part.iter().map(|&p| p as usize).collect();
        let mut count = vec![0usize; parts];
        part_of.iter().for_each(|&p| count[p] += 1);
        if let Some(empty) = count.iter().position(|&c| c == 0) {
            return Err(format!(
                "METIS left substructure {empty} of {parts} empty: ask for fewer substructures"
            ));
        }
        let candidate = Partition {
            parts: split(mesh, &part_of, parts),
            part_of,
        };
        let better = best
            .as_ref()
            .is_none_or(|b| candidate.imbalance() < b.imbalance());
        if better {
            best = Some(candidate);
        }
        if best.as_ref().is_some_and(|b| b.imbalance() <= DOF_BALANCE) {
            break;
        }
    }
    Ok(best.expect("at least one partition is tried"))
}

/// One METIS k-way partition of the weighted graph (`contiguous`: connected parts).
fn kway(
    xadj: &[metis::Idx],
    adjncy: &[metis::Idx],
    weight: &[metis::Idx],
    nparts: metis::Idx,
    ufactor: i32,
    contiguous: bool,
) -> Result<Vec<metis::Idx>, String> {
    let mut part = vec![0; weight.len()];
    let _one_at_a_time = metis_guard();
    metis::Graph::new(1, nparts, xadj, adjncy)
        .map_err(|e| format!("the element graph is not valid: {e}"))?
        .set_vwgt(weight)
        .set_option(metis::option::Contig(contiguous))
        .set_option(metis::option::UFactor(ufactor))
        .set_option(metis::option::Seed(1))
        .part_kway(&mut part)
        .map_err(|e| e.to_string())?;
    Ok(part)
}

/// The dual graph of the mesh in CSR form: elements joined when they share a face (the same
/// node set).
fn dual_graph(mesh: &Mesh) -> Result<(Vec<metis::Idx>, Vec<metis::Idx>), String> {
    let mut by_face: HashMap<Vec<usize>, usize> = HashMap::new();
    let mut neighbours: Vec<Vec<metis::Idx>> = vec![Vec::new(); mesh.elements.len()];
    let idx = |i: usize| metis::Idx::try_from(i).map_err(|_| "the mesh is too large for METIS");
    for (e, element) in mesh.elements.iter().enumerate() {
        for face in element.face_nodes() {
            let mut key = face;
            key.sort_unstable();
            match by_face.remove(&key) {
                Some(other) => {
                    neighbours[e].push(idx(other)?);
                    neighbours[other].push(idx(e)?);
                }
                None => {
                    by_face.insert(key, e);
                }
            }
        }
    }
    let mut xadj = Vec::with_capacity(neighbours.len() + 1);
    xadj.push(0);
    let mut adjncy = Vec::new();
    for list in neighbours {
        adjncy.extend(list);
        xadj.push(idx(adjncy.len())?);
    }
    Ok((xadj, adjncy))
}

/// The meshes of the parts (`part_of` per element, parts 0..parts), each with its own nodes in
/// the order they are first met, and per node the mesh node it copies.
pub fn split(mesh: &Mesh, part_of: &[usize], parts: usize) -> Vec<(Mesh, Vec<usize>)> {
    let mut out: Vec<(Mesh, Vec<usize>)> = (0..parts)
        .map(|_| {
            (
                Mesh {
                    nodes: Vec::new(),
                    elements: Vec::new(),
                },
                Vec::new(),
            )
        })
        .collect();
    let mut local: Vec<HashMap<usize, usize>> = vec![HashMap::new(); parts];
    for (element, &p) in mesh.elements.iter().zip(part_of) {
        let (m, origin) = &mut out[p];
        let renumbered = element.map_nodes(|n| {
            *local[p].entry(n).or_insert_with(|| {
                m.nodes.push(mesh.nodes[n]);
                origin.push(n);
                m.nodes.len() - 1
            })
        });
        m.elements.push(renumbered);
    }
    out
}

fn imbalance(dofs: &[usize]) -> f64 {
    let mean = dofs.iter().sum::<usize>() as f64 / dofs.len().max(1) as f64;
    dofs.iter()
        .map(|&d| (d as f64 - mean).abs() / mean)
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Element;

    fn tets() -> Mesh {
        Mesh::hex_box([0.0; 3], [1.0, 0.5, 0.5], [12, 6, 6]).split_into_tets()
    }

    #[test]
    fn every_element_lands_in_exactly_one_part_and_the_parts_are_balanced_by_dofs() {
        let mesh = tets();
        for parts in [1, 4, 16] {
            let p = partition(&mesh, parts).expect("partitions");
            assert_eq!(p.parts.len(), parts);
            assert_eq!(p.part_of.len(), mesh.elements.len());
            let total: usize = p.parts.iter().map(|(m, _)| m.elements.len()).sum();
            assert_eq!(total, mesh.elements.len());
            assert!(
                p.imbalance() <= DOF_BALANCE,
                "{parts} parts: {:?}",
                p.dofs()
            );
            // every part's nodes are copies at the same places
            for (m, origin) in &p.parts {
                for (q, &o) in m.nodes.iter().zip(origin) {
                    assert_eq!(*q, mesh.nodes[o]);
                }
            }
        }
    }

    #[test]
    fn a_part_is_the_elements_given_to_it_with_their_own_nodes() {
        let mesh = Mesh::hex_box([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1]);
        let parts = split(&mesh, &[0, 1], 2);
        assert_eq!(parts[0].0.nodes.len(), 8);
        assert_eq!(parts[1].0.nodes.len(), 8);
        // the shared face's 4 nodes are copied into both parts
        let shared = parts[0].1.iter().filter(|n| parts[1].1.contains(n)).count();
        assert_eq!(shared, 4);
        let Element::Hex8(n) = parts[1].0.elements[0] else {
            panic!("a hexahedron stays one")
        };
        assert_eq!(parts[1].1[n[0]], 1);
    }

    #[test]
    fn too_many_parts_are_refused() {
        let mesh = Mesh::hex_box([0.0; 3], [1.0; 3], [1, 1, 2]);
        let e = partition(&mesh, 3).expect_err("refused");
        assert!(
            e.contains("3 substructures") && e.contains("2 elements"),
            "{e}"
        );
        assert!(partition(&mesh, 0).is_err());
    }
}
