//! The scene's fixed geometry, extracted once per scene: each substructure's boundary faces
//! (the only faces ever drawn), elements (for sections), centroid, and which of its nodes sit on
//! a contact interface (METHOD §1: conforming node-to-node interfaces), so that contact
//! quantities can be painted on the faces that carry them.

use glam::Vec3;
use lopin_core::mesh::Element;
use lopin_core::Problem;

/// A node on a contact interface: which contact (index among the contact interfaces) and which
/// interface node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactNode {
    /// Index among the scene's contact interfaces (the order of `post::contact`).
    pub contact: usize,
    /// Interface node number.
    pub node: usize,
}

/// Geometry of one substructure.
#[derive(Debug, Clone)]
pub struct SubGeometry {
    /// Node coordinates.
    pub nodes: Vec<Vec3>,
    /// Boundary quadrilaterals (outward ordering).
    pub faces: Vec<[usize; 4]>,
    /// Hexahedra.
    pub elements: Vec<[usize; 8]>,
    /// Mean of the nodes (set by [`SceneGeometry::from_subs`]).
    pub centroid: Vec3,
    /// Contact node of each mesh node, if any.
    pub contact: Vec<Option<ContactNode>>,
    /// Per boundary face: whether it lies inside the assembly, on a face of another
    /// substructure, not wholly on a contact (hidden by its neighbours when the view is assembled;
    /// set by [`SceneGeometry::from_subs`]).
    pub enclosed: Vec<bool>,
}

/// Geometry of the whole scene.
#[derive(Debug, Clone)]
pub struct SceneGeometry {
    /// One per substructure.
    pub subs: Vec<SubGeometry>,
    /// Bounding box corners.
    pub lo: Vec3,
    /// Bounding box corners.
    pub hi: Vec3,
}

fn v3(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

impl SceneGeometry {
    /// Extracts the geometry of a problem.
    pub fn of(problem: &Problem) -> SceneGeometry {
        let mut subs: Vec<SubGeometry> = problem
            .subs
            .iter()
            .map(|s| {
                let nodes: Vec<Vec3> = s.mesh.nodes.iter().map(|&p| v3(p)).collect();
                let faces = s
                    .mesh
                    .boundary_faces()
                    .into_iter()
                    .filter_map(|f| match f.nodes[..] {
                        // a triangle as a quadrangle with its last node repeated: its second
                        // triangle is empty
                        [a, b, c] => Some([a, b, c, c]),
                        [a, b, c, d] => Some([a, b, c, d]),
                        _ => None,
                    })
                    .collect();
                let elements = s
                    .mesh
                    .elements
                    .iter()
                    .map(|e| match e {
                        Element::Hex8(n) => *n,
                        // a tetrahedron as a collapsed hexahedron (bottom a b c c, top d d d d):
                        // its twelve edges hold the tetrahedron's six, so a section cuts it
                        Element::Tet4([a, b, c, d]) => [*a, *b, *c, *c, *d, *d, *d, *d],
                    })
                    .collect();
                SubGeometry {
                    contact: vec![None; nodes.len()],
                    centroid: Vec3::ZERO,
                    enclosed: Vec::new(),
                    nodes,
                    faces,
                    elements,
                }
            })
            .collect();
        for (c, iface) in problem
            .interfaces
            .iter()
            .filter(|i| i.is_contact())
            .enumerate()
        {
            for side in &iface.sides {
                // the mortar side of a non-matching contact: each face node shows the
                // interface node that weighs most on it
                let nodes: Vec<(usize, usize)> = match &side.projection {
                    Some(p) => {
                        let mut best: std::collections::BTreeMap<usize, (f64, usize)> =
                            Default::default();
                        for k in 0..p.rows() {
                            for (n, w) in p.row(k) {
                                let e = best.entry(n).or_insert((f64::NEG_INFINITY, k));
                                if w > e.0 {
                                    *e = (w, k);
                                }
                            }
                        }
                        best.into_iter().map(|(n, (_, k))| (k, n)).collect()
                    }
                    None => side.nodes.iter().copied().enumerate().collect(),
                };
                for (k, n) in nodes {
                    let slot = &mut subs[side.sub].contact[n];
                    if slot.is_none() {
                        *slot = Some(ContactNode {
                            contact: c,
                            node: k,
                        });
                    }
                }
            }
        }
        SceneGeometry::from_subs(subs)
    }

    /// The geometry of these substructures (a stored run's, read back), with what follows from
    /// them: each one's centroid and enclosed faces, and the bounding box.
    pub fn from_subs(mut subs: Vec<SubGeometry>) -> SceneGeometry {
        for s in &mut subs {
            s.centroid = s.nodes.iter().copied().sum::<Vec3>() / (s.nodes.len().max(1) as f32);
        }
        mark_enclosed(&mut subs);
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for s in &subs {
            for &p in &s.nodes {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if !lo.is_finite() {
            (lo, hi) = (Vec3::ZERO, Vec3::ONE);
        }
        SceneGeometry { subs, lo, hi }
    }

    /// Centre of the bounding box.
    pub fn centre(&self) -> Vec3 {
        0.5 * (self.lo + self.hi)
    }

    /// Offset of substructure `i` in the exploded view (factor 0: none).
    pub fn explode_offset(&self, i: usize, factor: f32) -> Vec3 {
        (self.subs[i].centroid - self.centre()) * factor
    }

    /// Number of surface triangles drawn when the view is assembled (enclosed faces left out).
    pub fn assembled_triangle_count(&self) -> usize {
        self.subs
            .iter()
            .flat_map(|s| s.faces.iter().zip(&s.enclosed))
            .filter(|(_, &e)| !e)
            .map(|(f, _)| if f[2] == f[3] { 1 } else { 2 })
            .sum()
    }

    /// Number of surface triangles.
    pub fn triangle_count(&self) -> usize {
        self.subs
            .iter()
            .flat_map(|s| &s.faces)
            .map(|f| if f[2] == f[3] { 1 } else { 2 })
            .sum()
    }
}

/// Marks each substructure's boundary faces that coincide with a boundary face of another
/// substructure (the same corner positions) where neither lies wholly on a contact: the faces
/// of a perfect interface, which the two sides hide from each other while the view is
/// assembled (a contact's faces stay, since a contact may open). Faces of non-matching interfaces have no twin and stay drawn.
fn mark_enclosed(subs: &mut [SubGeometry]) {
    type Key = [[u32; 3]; 4];
    // the distinct corners, sorted (a triangle's repeated node may be any of its three on
    // the other side, whose ordering is reversed)
    let key = |g: &SubGeometry, f: &[usize; 4]| -> Key {
        let mut corners: Vec<[u32; 3]> = f
            .iter()
            .map(|&n| g.nodes[n].to_array().map(f32::to_bits))
            .collect();
        corners.sort_unstable();
        corners.dedup();
        let mut k = [[u32::MAX; 3]; 4];
        k[..corners.len()].copy_from_slice(&corners);
        k
    };
    let mut first: std::collections::HashMap<Key, (usize, usize)> = Default::default();
    let mut twins = Vec::new();
    for (i, g) in subs.iter().enumerate() {
        for (k, f) in g.faces.iter().enumerate() {
            if f.iter().all(|&n| g.contact[n].is_some()) {
                continue;
            }
            match first.entry(key(g, f)) {
                std::collections::hash_map::Entry::Occupied(e) => {
                    let &(j, l) = e.get();
                    if j != i {
                        twins.push((i, k));
                        twins.push((j, l));
                    }
                }
                std::collections::hash_map::Entry::Vacant(e) => {
                    e.insert((i, k));
                }
            }
        }
    }
    for g in subs.iter_mut() {
        g.enclosed = vec![false; g.faces.len()];
    }
    for (i, k) in twins {
        subs[i].enclosed[k] = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lopin_core::scene;

    fn geometry(name: &str, split: usize) -> SceneGeometry {
        let overrides = scene::Overrides {
            split,
            ..Default::default()
        };
        SceneGeometry::of(&scene::open(name, &overrides).expect("opens").problem)
    }

    /// Splitting the blocks of `two-blocks` (hexahedra) and `granular-poly` (tetrahedra) into
    /// more substructures adds only faces between two of them: the faces drawn when the view is
    /// assembled are the same number, those of the outer surface and the contacts, and every
    /// face the split added is enclosed, on both sides.
    #[test]
    fn a_split_adds_only_enclosed_faces() {
        for name in ["two-blocks", "granular-poly"] {
            let (one, two) = (geometry(name, 1), geometry(name, 2));
            assert!(two.subs.len() > one.subs.len(), "{name}: split");
            assert_eq!(
                one.assembled_triangle_count(),
                two.assembled_triangle_count(),
                "{name}"
            );
            let added = two.triangle_count() - one.triangle_count();
            assert!(added > 0, "{name}");
            let enclosed = |g: &SceneGeometry| g.triangle_count() - g.assembled_triangle_count();
            assert_eq!(enclosed(&two) - enclosed(&one), added, "{name}");
        }
    }
}
