//! One contact normal per node where pieces of one contact meet (METHOD §5).
//!
//! Each two-sided contact interface takes its nodes' normals from its own matched faces. When
//! substructuring cuts a body, its contact with another body comes in pieces, one interface per
//! pair of substructures, and a node of the other body on the line where the cut meets the
//! contact (a grain's node where a cut between two matrix parts meets the grain) lies on two
//! pieces or more. With a normal per piece, the split of that node's contact force between the
//! pieces becomes a mode that turns the force a little and moves the velocities hardly at all,
//! which LATIN converges very slowly. Here every node pair of such a piece whose node lies on
//! several pieces of the same contact (the same substructure and node on one side, the same
//! body on the other) takes one normal: the mean of the pieces' normals there, each weighted by
//! the node's area in its piece. (The uncut body's single interface would sum its faces'
//! normals before normalizing; where a piece's faces around the node are not flat, its
//! normalized normal weighted by its area is not that sum, so the two differ there and the
//! shared normal still depends a little on where the cut runs.) A node on the contacts with
//! two different
//! bodies (a corner of a cell between two neighbours) keeps one normal per contact, and node
//! pairs on one piece keep theirs bit for bit. Non-matching interfaces (a projected side) are
//! left as they are.

use std::collections::HashMap;

use crate::interfaces::interface::{Interface, Law};
use crate::mesh::{norm, Vec3};

/// Gives every contact node pair with a node on several pieces of one contact the mean of those
/// pieces' normals at the node, weighted by its area in each (both nodes, if both are). `body[s]` is
/// substructure s's body. Interfaces with projected (non-matching) sides are left as they are.
pub fn share_normals(interfaces: &mut [Interface], body: &[&str]) {
    // per (substructure, node, body across): the area-weighted normal pointing out of that
    // substructure, and how many contact interfaces with that body hold the node
    let mut around: HashMap<(usize, usize, &str), (Vec3, usize)> = HashMap::new();
    for iface in interfaces.iter() {
        let Some(normals) = contact_normals(iface) else {
            continue;
        };
        for (j, side) in iface.sides.iter().enumerate() {
            // the normal points from side 0 to side 1: out of side 0, into side 1
            let sign = if j == 0 { 1.0 } else { -1.0 };
            let across = body[iface.sides[1 - j].sub];
            for (q, &node) in side.nodes.iter().enumerate() {
                let a = iface.area[3 * q];
                let e = around
                    .entry((side.sub, node, across))
                    .or_insert(([0.0; 3], 0));
                for c in 0..3 {
                    e.0[c] += sign * a * normals[q][c];
                }
                e.1 += 1;
            }
        }
    }
    for iface in interfaces.iter_mut() {
        if contact_normals(iface).is_none() {
            continue;
        }
        let shared: Vec<Option<Vec3>> = (0..iface.len / 3)
            .map(|q| {
                let mut sum = [0.0; 3];
                let mut any = false;
                for (j, side) in iface.sides.iter().enumerate() {
                    let across = body[iface.sides[1 - j].sub];
                    let (v, count) = around[&(side.sub, side.nodes[q], across)];
                    if count > 1 {
                        let sign = if j == 0 { 1.0 } else { -1.0 };
                        for c in 0..3 {
                            sum[c] += sign * v[c];
                        }
                        any = true;
                    }
                }
                let l = norm(sum);
                (any && l > 0.0).then(|| [sum[0] / l, sum[1] / l, sum[2] / l])
            })
            .collect();
        if let Law::Contact(c) = &mut iface.law {
            for (n, s) in c.normal.iter_mut().zip(shared) {
                if let Some(s) = s {
                    *n = s;
                }
            }
        }
    }
}

/// The normals of a two-sided contact interface whose sides are node lists.
fn contact_normals(iface: &Interface) -> Option<&[Vec3]> {
    match &iface.law {
        Law::Contact(c)
            if iface.sides.len() == 2 && iface.sides.iter().all(|s| s.projection.is_none()) =>
        {
            Some(&c.normal)
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interfaces::interface::{Contact, Side};

    /// A contact interface between substructures `a` and `b` on node pairs `pairs`, with nodal
    /// areas and normals (out of `a`).
    fn contact(
        a: usize,
        b: usize,
        pairs: &[(usize, usize)],
        area: &[f64],
        n: &[Vec3],
    ) -> Interface {
        let side = |sub, nodes: Vec<usize>| Side {
            sub,
            offset: 0,
            nodes,
            projection: None,
        };
        Interface {
            name: format!("{a}|{b}"),
            sides: vec![
                side(a, pairs.iter().map(|p| p.0).collect()),
                side(b, pairs.iter().map(|p| p.1).collect()),
            ],
            len: 3 * pairs.len(),
            area: area.iter().flat_map(|&x| [x; 3]).collect(),
            k_scale: vec![1.0; 3 * pairs.len()],
            law: Law::Contact(Contact {
                friction: 0.3,
                gap: vec![0.0; pairs.len()],
                normal: n.to_vec(),
                start_gap: None,
            }),
        }
    }

    fn normals(i: &Interface) -> &[Vec3] {
        match &i.law {
            Law::Contact(c) => &c.normal,
            _ => unreachable!(),
        }
    }

    #[test]
    fn a_node_shared_by_two_contacts_gets_the_normal_of_all_its_faces() {
        let (s, c) = (0.6f64, 0.8f64);
        // a grain (substructure 2) against two parts (0 and 1) of one matrix: its node 7 lies
        // on both pieces of that contact, with normals tilted apart; node 8 is on the first
        // piece only. The second piece has the grain as its first side, so its normal points
        // out of the grain.
        let mut ifaces = vec![
            contact(
                0,
                2,
                &[(10, 7), (11, 8)],
                &[1.0, 2.0],
                &[[s, 0.0, c], [0.0, 0.0, 1.0]],
            ),
            contact(2, 1, &[(7, 20)], &[3.0], &[[s, 0.0, -c]]),
        ];
        share_normals(&mut ifaces, &["matrix", "matrix", "grain"]);
        // out of matrix part 0 into the grain: 1 (s, 0, c) + 3 (−s, 0, c) = (−2s, 0, 4c)
        let l = (4.0 * s * s + 16.0 * c * c).sqrt();
        let expected = [-2.0 * s / l, 0.0, 4.0 * c / l];
        for (got, want) in normals(&ifaces[0])[0].iter().zip(expected) {
            assert!((got - want).abs() < 1e-15, "{got} against {want}");
        }
        // the second interface's normal points the other way (out of the grain), the same line
        for (got, want) in normals(&ifaces[1])[0].iter().zip(expected) {
            assert!((got + want).abs() < 1e-15, "{got} against {}", -want);
        }
        // a node on one contact only keeps its normal bit for bit
        assert_eq!(normals(&ifaces[0])[1], [0.0, 0.0, 1.0]);
    }

    #[test]
    fn contacts_sharing_no_node_keep_their_normals_bit_for_bit() {
        let n = [0.1f64, -0.2, 0.97];
        let l = norm(n);
        let n = [n[0] / l, n[1] / l, n[2] / l];
        let before = vec![
            contact(0, 2, &[(1, 1), (2, 2)], &[0.3, 0.7], &[n, [1.0, 0.0, 0.0]]),
            contact(1, 2, &[(5, 3)], &[0.5], &[[0.0, 1.0, 0.0]]),
        ];
        let mut after = before.clone();
        share_normals(&mut after, &["matrix", "matrix", "grain"]);
        assert_eq!(after, before);
    }

    #[test]
    fn a_corner_between_two_other_bodies_keeps_a_normal_per_contact() {
        // cell 2's node 7 touches cell 0 along x and cell 1 along y: two contacts, not pieces
        // of one
        let before = vec![
            contact(0, 2, &[(4, 7)], &[1.0], &[[1.0, 0.0, 0.0]]),
            contact(1, 2, &[(9, 7)], &[1.0], &[[0.0, 1.0, 0.0]]),
        ];
        let mut after = before.clone();
        share_normals(&mut after, &["cell0", "cell1", "cell2"]);
        assert_eq!(after, before);
    }
}
