//! Detection of non-matching interfaces: boundary faces of two substructures that coincide or
//! face each other within a contact's search distance, left unmatched because their nodes do not
//! pair one to one (parts meshed separately, hexahedra on tetrahedra, curved surfaces faceted
//! differently), become one interface coupled by dual mortar ([`crate::interfaces::mortar`];
//! METHOD §1). Side 1, whose nodes carry the interface fields, is the side the other covers
//! best (a small face on a large one: the small face), the finer one when both are covered.
//! Faces overlapping without any side-1 facet fully covered are an error naming the two
//! substructures and a location.

use std::collections::BTreeSet;
use std::sync::Arc;

use crate::error::Result;
use crate::interfaces::detect::{
    box_distance, nonconforming, pair_group, Matches, PairRule, SceneFaces, REL_TOL,
};
use crate::interfaces::facet::Facet;
use crate::interfaces::interface::{Contact, Interface, Law, Side};
use crate::interfaces::mortar::{couple, overlapping_pairs, polygon_area, Coupling};
use crate::mesh::Face;

/// Faces coincide within this fraction of their size along the normal (the sag between two
/// facetings of one curved surface).
pub const SAG: f64 = 0.05;

/// The unmatched faces of one substructure near another, as facets.
struct Candidates {
    /// Index of each facet's face in the substructure's boundary faces.
    faces: Vec<usize>,
    facets: Vec<Facet>,
}

impl SceneFaces<'_> {
    /// Phase 3: couples the unmatched faces of every two substructures that are not free of
    /// each other and overlap (coincident, or facing across at most the contact's search
    /// distance) into non-matching interfaces, marking their faces matched.
    pub(crate) fn match_non_matching(
        &self,
        search_bound: f64,
        diameter: f64,
        found: &mut Matches,
    ) -> Result<()> {
        let widest: Vec<f64> = (0..self.subs.len()).map(|s| self.widest_face(s)).collect();
        for s in 0..self.subs.len() {
            let reach = search_bound.max(0.0) + REL_TOL * diameter + SAG * widest[s];
            let (lo, hi) = self.boxes[s];
            for t in self.sweep.meeting(lo[0] - reach, hi[0] + reach) {
                if t <= s {
                    continue;
                }
                let search = match (self.pair_rule)(s, t) {
                    PairRule::Free => continue,
                    PairRule::Contact { search, .. } => search.max(0.0),
                    PairRule::Perfect => 0.0,
                };
                let slack = REL_TOL * diameter + SAG * widest[s];
                if box_distance(&self.boxes[s], &self.boxes[t]) > search + slack {
                    continue;
                }
                // the faces of either within reach of the other's box
                let reach = search + slack + widest[s].max(widest[t]);
                self.couple_pair(s, t, search, reach, found)?;
            }
        }
        Ok(())
    }

    /// The unmatched faces of s within `reach` of t's bounding box.
    fn candidates(&self, s: usize, t: usize, reach: f64, found: &Matches) -> Candidates {
        let (lo, hi) = self.boxes[t];
        let near = |f: &Face| {
            (0..3).all(|c| f.centroid[c] >= lo[c] - reach && f.centroid[c] <= hi[c] + reach)
        };
        let mut out = Candidates {
            faces: Vec::new(),
            facets: Vec::new(),
        };
        for (f, face) in self.faces[s].iter().enumerate() {
            if found.matched[s][f] || !near(face) {
                continue;
            }
            let points = face
                .nodes
                .iter()
                .map(|&n| self.subs[s].mesh.nodes[n])
                .collect();
            out.faces.push(f);
            out.facets
                .push(Facet::new(face.nodes.clone(), points, face.normal));
        }
        out
    }

    /// Couples the unmatched faces of s and t (those within `reach` of the other's bounding
    /// box) that overlap, if any.
    fn couple_pair(
        &self,
        s: usize,
        t: usize,
        search: f64,
        reach: f64,
        found: &mut Matches,
    ) -> Result<()> {
        let (a, b) = (
            self.candidates(s, t, reach, found),
            self.candidates(t, s, reach, found),
        );
        if a.facets.is_empty() || b.facets.is_empty() {
            return Ok(());
        }
        // coincident within the sag either way; a contact's faces up to its search distance
        // apart
        let contact = matches!((self.pair_rule)(s, t), PairRule::Contact { .. });
        let window = |f: &Facet| {
            let h = polygon_area(&f.polygon()).sqrt();
            let above = if contact {
                search + REL_TOL * h
            } else {
                SAG * h
            };
            (-SAG * h, above)
        };
        let pairs = overlapping_pairs(&a.facets, &b.facets, &window);
        if pairs.is_empty() {
            return Ok(());
        }
        // the faces of s and t that matched node to node join the coupling: one interface
        // between the two, not a conforming one beside a non-matching one sharing its nodes
        if found.release(s, t, self.faces) {
            return self.couple_pair(s, t, search, reach, found);
        }
        let (a, b, pairs) = involved(a, b, &pairs);
        let reversed: Vec<(usize, usize)> = overlapping_pairs(&b.facets, &a.facets, &window);
        let from_a = couple(&a.facets, &b.facets, &pairs);
        let from_b = couple(&b.facets, &a.facets, &reversed);
        let fraction = |c: &Coupling, f: &[Facet]| {
            c.covered / f.iter().map(|x| polygon_area(&x.polygon())).sum::<f64>()
        };
        let (fa, fb) = (fraction(&from_a, &a.facets), fraction(&from_b, &b.facets));
        let a_first = if (fa - fb).abs() > 1e-6 {
            fa > fb
        } else {
            from_a.nodes.len() >= from_b.nodes.len()
        };
        let (one, two, c1, c2, p) = if a_first {
            (s, t, &a, &b, pairs)
        } else {
            (t, s, &b, &a, reversed)
        };
        let chosen = if a_first { from_a } else { from_b };
        if chosen.nodes.is_empty() {
            let at = self.faces[one][c1.faces[0]].centroid;
            return Err(nonconforming(self.subs, one, two, at));
        }
        for (sub, c) in [(s, &a), (t, &b)] {
            for &f in &c.faces {
                found.matched[sub][f] = true;
            }
        }
        let rule = (self.pair_rule)(s, t);
        // one interface per face group of the side-1 facets (contacts only): a facet's group
        // with that of the first side-2 facet it overlaps
        let mut first_over = vec![usize::MAX; c1.facets.len()];
        for &(i, j) in &p {
            if first_over[i] == usize::MAX {
                first_over[i] = j;
            }
        }
        let group_of: Vec<usize> = (0..c1.facets.len())
            .map(|i| match rule {
                PairRule::Contact { .. } => pair_group(
                    (self.group)(one, &self.faces[one][c1.faces[i]]),
                    first_over
                        .get(i)
                        .filter(|&&j| j != usize::MAX)
                        .map_or(0, |&j| (self.group)(two, &self.faces[two][c2.faces[j]])),
                ),
                _ => 0,
            })
            .collect();
        let groups: BTreeSet<usize> = group_of.iter().copied().collect();
        if groups.len() == 1 {
            let g = groups.into_iter().next().unwrap_or(0);
            found
                .mortars
                .push((self.mortar_interface(one, two, chosen, rule), g));
            return Ok(());
        }
        for g in groups {
            let part: Vec<(usize, usize)> =
                p.iter().copied().filter(|x| group_of[x.0] == g).collect();
            let c = couple(&c1.facets, &c2.facets, &part);
            if !c.nodes.is_empty() {
                found
                    .mortars
                    .push((self.mortar_interface(one, two, c, rule), g));
            }
        }
        Ok(())
    }

    /// Square root of the largest boundary face area of substructure s.
    fn widest_face(&self, s: usize) -> f64 {
        self.faces[s]
            .iter()
            .map(|f| f.area.sqrt())
            .fold(0.0, f64::max)
    }

    /// The interface of a coupling: side 1 on substructure `one` (its nodes), side 2 on `two`
    /// (the projection; its nodes are each row's heaviest term).
    fn mortar_interface(&self, one: usize, two: usize, c: Coupling, rule: PairRule) -> Interface {
        let heaviest: Vec<usize> = (0..c.projection.rows())
            .map(|q| {
                c.projection
                    .row(q)
                    .into_iter()
                    .max_by(|x, y| x.1.abs().total_cmp(&y.1.abs()))
                    .map_or(0, |x| x.0)
            })
            .collect();
        let area: Vec<f64> = c.area.iter().flat_map(|&a| [a; 3]).collect();
        let law = match rule {
            PairRule::Contact { friction, gap, .. } => Law::Contact(Contact {
                friction,
                gap: c
                    .distance
                    .iter()
                    .map(|&d| gap.unwrap_or(d.max(0.0)))
                    .collect(),
                normal: c.normal.clone(),
                start_gap: None,
            }),
            _ => Law::Perfect,
        };
        Interface {
            name: format!("{}|{}", self.subs[one].name, self.subs[two].name),
            len: 3 * c.nodes.len(),
            sides: vec![
                Side {
                    sub: one,
                    offset: 0,
                    nodes: c.nodes,
                    projection: None,
                },
                Side {
                    sub: two,
                    offset: 0,
                    nodes: heaviest,
                    projection: Some(Arc::new(c.projection)),
                },
            ],
            k_scale: vec![1.0; area.len()],
            area,
            law,
        }
    }
}

/// The facets of `a` and `b` that some pair involves, and the pairs renumbered on them.
fn involved(
    a: Candidates,
    b: Candidates,
    pairs: &[(usize, usize)],
) -> (Candidates, Candidates, Vec<(usize, usize)>) {
    let keep = |c: Candidates, used: BTreeSet<usize>| {
        let mut index = vec![usize::MAX; c.facets.len()];
        let mut out = Candidates {
            faces: Vec::new(),
            facets: Vec::new(),
        };
        for (k, (face, facet)) in c.faces.into_iter().zip(c.facets).enumerate() {
            if used.contains(&k) {
                index[k] = out.facets.len();
                out.faces.push(face);
                out.facets.push(facet);
            }
        }
        (out, index)
    };
    let (a, ia) = keep(a, pairs.iter().map(|p| p.0).collect());
    let (b, ib) = keep(b, pairs.iter().map(|p| p.1).collect());
    let pairs = pairs.iter().map(|&(i, j)| (ia[i], ib[j])).collect();
    (a, b, pairs)
}
