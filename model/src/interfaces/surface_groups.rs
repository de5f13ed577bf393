//! Contact interfaces split by physical surface, for zones that name surfaces of Gmsh meshes
//! (the interfaces of METHOD §1, whose laws of §5 a zone's parameters set). Faces
//! are numbered by group (0: on no named surface, g ≥ 1: on the g-th surface the zones name),
//! and [`crate::interfaces::detect::detect_interfaces_grouped`] deals each contact node pair to one group
//! by [`deal`]. A node keeps its whole lumped area (the sum over all its faces), so the split
//! interfaces hold the unsplit one's node pairs, areas, normals and gaps, and no node pair lies
//! in two interfaces (a pair in two would split its normal force between two frictions in no
//! unique way). Where the nodes on the line between two surfaces go sets each zone's area:
//! [`deal`] keeps every group's area within one node's area of its faces' area.

use std::collections::BTreeMap;

/// The group of each node, from its lumped area and its area per group (the share of its
/// faces in each group). A node whose faces are all in one group goes to it. The others (on
/// the lines where surfaces meet), in the order given, go to the group among theirs whose
/// faces' area is the least covered so far (on a tie, the surface named first, a named surface
/// before none), so that with two groups each ends within the largest such node's area of the
/// area of its faces. Deterministic: the same nodes in the same order give the same groups.
pub fn deal(nodes: &[(f64, &BTreeMap<usize, f64>)]) -> Vec<usize> {
    // the area of each group's faces, and the area dealt to it so far
    let mut faces: BTreeMap<usize, f64> = BTreeMap::new();
    let mut dealt: BTreeMap<usize, f64> = BTreeMap::new();
    for (_, by_group) in nodes {
        for (&g, &a) in *by_group {
            *faces.entry(g).or_default() += a;
        }
    }
    let mut out: Vec<Option<usize>> = nodes
        .iter()
        .map(|(area, by_group)| {
            let mut groups = by_group.keys();
            match (groups.next(), groups.next()) {
                (Some(&g), None) => {
                    *dealt.entry(g).or_default() += area;
                    Some(g)
                }
                _ => None,
            }
        })
        .collect();
    // named groups in order, then 0
    let rank = |g: usize| if g == 0 { usize::MAX } else { g };
    for (slot, (area, by_group)) in out.iter_mut().zip(nodes) {
        if slot.is_some() {
            continue;
        }
        let deficit = |g: usize| faces[&g] - dealt.get(&g).copied().unwrap_or(0.0);
        let g = by_group
            .keys()
            .copied()
            .max_by(|&a, &b| {
                deficit(a)
                    .total_cmp(&deficit(b))
                    .then(rank(b).cmp(&rank(a)))
            })
            .unwrap_or(0);
        *dealt.entry(g).or_default() += area;
        *slot = Some(g);
    }
    out.into_iter().map(|g| g.unwrap_or(0)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn groups(v: &[(usize, f64)]) -> BTreeMap<usize, f64> {
        v.iter().copied().collect()
    }

    #[test]
    fn nodes_of_one_group_stay_in_it_and_shared_ones_even_out_the_areas() {
        // a strip of 10 nodes of area 1: 0–3 on surface 1, 6–9 on surface 2, and 4, 5 on the
        // line between (a quarter of 4 on surface 1, three quarters of 5 on surface 2)
        let by: Vec<BTreeMap<usize, f64>> = (0..10)
            .map(|i| match i {
                0..=3 => groups(&[(1, 1.0)]),
                4 => groups(&[(1, 0.25), (2, 0.75)]),
                5 => groups(&[(1, 0.75), (2, 0.25)]),
                _ => groups(&[(2, 1.0)]),
            })
            .collect();
        let nodes: Vec<(f64, &BTreeMap<usize, f64>)> = by.iter().map(|b| (1.0, b)).collect();
        let g = deal(&nodes);
        assert_eq!(&g[..4], &[1, 1, 1, 1]);
        assert_eq!(&g[6..], &[2, 2, 2, 2]);
        // faces: 5 each; after the sure nodes 4 each, so node 4 goes to surface 1 (named
        // first), node 5 to surface 2 (now the less covered): 5 and 5
        assert_eq!(&g[4..6], &[1, 2]);
        // a named surface before none, on a tie
        let (a, b) = (groups(&[(0, 0.5), (3, 0.5)]), groups(&[(3, 0.5), (0, 0.5)]));
        assert_eq!(deal(&[(1.0, &a)]), vec![3]);
        assert_eq!(deal(&[(1.0, &b)]), vec![3]);
        assert_eq!(deal(&[]), Vec::<usize>::new());
    }

    #[test]
    fn with_two_groups_each_ends_within_one_node_of_its_faces_area() {
        // 200 nodes in a pseudo-random mix of shares and areas
        let mut x = 12345u64;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut by = Vec::new();
        let mut areas = Vec::new();
        for _ in 0..200 {
            let a = 0.5 + next();
            let share = match next() {
                s if s < 0.3 => 0.0,
                s if s < 0.6 => 1.0,
                _ => next(),
            };
            let mut m = BTreeMap::new();
            if share > 0.0 {
                m.insert(1, a * share);
            }
            if share < 1.0 {
                m.insert(2, a * (1.0 - share));
            }
            by.push(m);
            areas.push(a);
        }
        let nodes: Vec<(f64, &BTreeMap<usize, f64>)> = areas.iter().copied().zip(&by).collect();
        let g = deal(&nodes);
        let largest = areas.iter().fold(0.0f64, |m, &a| m.max(a));
        for group in [1, 2] {
            let faces: f64 = by.iter().filter_map(|m| m.get(&group)).sum();
            let dealt: f64 = (0..200).filter(|&i| g[i] == group).map(|i| areas[i]).sum();
            assert!(
                (dealt - faces).abs() <= largest,
                "group {group}: {dealt} against {faces}"
            );
        }
    }
}
