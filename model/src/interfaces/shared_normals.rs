//! One contact normal per node where pieces of one contact meet (METHOD §5).
//!
//! Each two-sided contact interface takes its nodes' normals from its own matched faces (the
//! area-weighted sum Σ_f (A_f / k_f) n_f over a node's faces f of k_f nodes, normalized). When
//! substructuring cuts a body, its contact with another body comes in pieces, one interface per
//! pair of substructures, and a node of the other body on the line where the cut meets the
//! contact (a grain's node where a cut between two matrix parts meets the grain) lies on two
//! pieces or more. With a normal per piece, the split of that node's contact force between the
//! pieces becomes a mode that turns the force a little and moves the velocities hardly at all,
//! which LATIN converges very slowly. Here a node on several pieces of one contact (the same
//! substructure and node on one side, the same body on the other) takes the sum over all those
//! pieces' faces around it, normalized: the normal the uncut body's single interface gives it,
//! whatever the cut. A node on the contacts with two different bodies (a corner of a cell
//! between two neighbours) keeps one normal per contact, and node pairs with no such node keep
//! their piece's normal bit for bit. Non-matching interfaces are not pieces here.

use std::collections::HashMap;

use crate::mesh::{norm, unit, Vec3};

/// A node of one side of a contact: (substructure, node, the body across).
pub type SideNode<'a> = (usize, usize, &'a str);

/// The face sums of the contact nodes, over every piece of their contact.
#[derive(Debug, Default)]
pub struct SharedNormals<'a> {
    /// Per side node: Σ (A_f / k_f) n_f pointing out of its substructure, the last piece that
    /// added to it, and how many pieces did.
    sums: HashMap<SideNode<'a>, (Vec3, usize, usize)>,
}

impl<'a> SharedNormals<'a> {
    /// Adds a face's share `a` of area at a node pair of contact piece `piece`: `n` is the face's
    /// unit normal pointing out of `first`'s substructure into `second`'s.
    pub fn add(
        &mut self,
        piece: usize,
        first: SideNode<'a>,
        second: SideNode<'a>,
        a: f64,
        n: Vec3,
    ) {
        for (node, sign) in [(first, a), (second, -a)] {
            let e = self.sums.entry(node).or_insert(([0.0; 3], piece, 0));
            for c in 0..3 {
                e.0[c] += sign * n[c];
            }
            if e.2 == 0 || e.1 != piece {
                e.1 = piece;
                e.2 += 1;
            }
        }
    }

    /// The normal (out of `first`'s substructure) of a node pair one of whose nodes lies on
    /// several pieces of its contact: the normalized sum of the faces around the shared node(s);
    /// None where neither does.
    pub fn normal(&self, first: SideNode<'a>, second: SideNode<'a>) -> Option<Vec3> {
        let mut sum = [0.0; 3];
        let mut any = false;
        for (node, sign) in [(first, 1.0), (second, -1.0)] {
            if let Some(&(v, _, pieces)) = self.sums.get(&node) {
                if pieces > 1 {
                    for c in 0..3 {
                        sum[c] += sign * v[c];
                    }
                    any = true;
                }
            }
        }
        (any && norm(sum) > 0.0).then(|| unit(sum))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_on_two_pieces_gets_the_sum_of_all_its_faces() {
        // a grain (substructure 2) against two parts (0 and 1) of one matrix: grain node 7 has
        // two faces on piece 0 (matrix node 10 across) and one on piece 1 (matrix node 20)
        let (s, c) = (0.6f64, 0.8f64);
        let faces: [(usize, usize, f64, Vec3); 3] = [
            (0, 10, 1.0, [s, 0.0, c]),
            (0, 10, 0.5, [0.0, 0.0, 1.0]),
            (1, 20, 3.0, [-s, 0.0, c]),
        ];
        let mut shared = SharedNormals::default();
        for &(piece, matrix_node, a, n) in &faces {
            shared.add(piece, (piece, matrix_node, "grain"), (2, 7, "matrix"), a, n);
        }
        // grain node 8 lies on piece 0 only
        shared.add(0, (0, 11, "grain"), (2, 8, "matrix"), 2.0, [0.0, 0.0, 1.0]);
        // Σ a n over the three faces, out of the matrix: (−1.2, 0, 3.7)
        let want = unit([s - 3.0 * s, 0.0, c + 0.5 + 3.0 * c]);
        for piece in [(0, 10), (1, 20)] {
            let got = shared
                .normal((piece.0, piece.1, "grain"), (2, 7, "matrix"))
                .expect("a shared node");
            for k in 0..3 {
                assert!((got[k] - want[k]).abs() < 1e-15, "{got:?} against {want:?}");
            }
        }
        assert_eq!(shared.normal((0, 11, "grain"), (2, 8, "matrix")), None);
    }

    #[test]
    fn a_corner_between_two_other_bodies_is_not_shared() {
        // cell 2's node 7 touches cell 0 along x and cell 1 along y: two contacts, not pieces
        // of one
        let mut shared = SharedNormals::default();
        shared.add(0, (0, 4, "cell2"), (2, 7, "cell0"), 1.0, [1.0, 0.0, 0.0]);
        shared.add(1, (1, 9, "cell2"), (2, 7, "cell1"), 1.0, [0.0, 1.0, 0.0]);
        assert_eq!(shared.normal((0, 4, "cell2"), (2, 7, "cell0")), None);
        assert_eq!(shared.normal((1, 9, "cell2"), (2, 7, "cell1")), None);
    }

    #[test]
    fn faces_of_one_piece_count_it_once() {
        let mut shared = SharedNormals::default();
        for n in [[0.0, 0.6, 0.8], [0.0, -0.6, 0.8]] {
            shared.add(3, (0, 1, "b"), (1, 1, "a"), 1.0, n);
        }
        assert_eq!(shared.normal((0, 1, "b"), (1, 1, "a")), None);
    }
}
