//! Meshes: nodes and elements (trilinear hexahedra, and linear tetrahedra from imported Gmsh
//! meshes), structured box generation, and the boundary faces (quadrangles, triangles) used to
//! detect interfaces (METHOD §1: conforming, node-to-node interfaces). Beside them: Gmsh MSH 4.1
//! input ([`msh`]) and the `gmsh` program for `.geo` scripts ([`gmsh`]), automatic
//! substructuring ([`partition`]) and the polyhedral grains of generated samples
//! ([`grain_geometry`]).

#[cfg(feature = "msh")]
pub mod gmsh;
pub mod grain_geometry;
#[cfg(feature = "msh")]
pub mod msh;
#[cfg(feature = "partition")]
pub mod partition;

use std::collections::HashMap;

/// A 3D point or vector.
pub type Vec3 = [f64; 3];

/// One finite element: its kind and its node numbers.
#[derive(Debug, Clone, PartialEq)]
pub enum Element {
    /// Trilinear hexahedron, nodes in the usual order: bottom face (ζ = −1) counter-clockwise
    /// seen from above, then the top face.
    Hex8([usize; 8]),
    /// Linear tetrahedron, nodes 1, 2, 3 counter-clockwise seen from node 0 (positive volume).
    Tet4([usize; 4]),
}

impl Element {
    /// The node numbers.
    pub fn nodes(&self) -> &[usize] {
        match self {
            Self::Hex8(n) => n,
            Self::Tet4(n) => n,
        }
    }

    /// The same element on other node numbers.
    pub fn map_nodes(&self, f: impl FnMut(usize) -> usize) -> Element {
        match self {
            Self::Hex8(n) => Self::Hex8(n.map(f)),
            Self::Tet4(n) => Self::Tet4(n.map(f)),
        }
    }

    /// The node numbers of each face, counter-clockwise seen from outside.
    pub fn face_nodes(&self) -> impl Iterator<Item = Vec<usize>> + '_ {
        let n = self.nodes();
        self.faces()
            .iter()
            .map(move |f| f.iter().map(|&l| n[l]).collect())
    }

    /// Local node lists of the faces, each counter-clockwise seen from outside.
    fn faces(&self) -> &'static [&'static [usize]] {
        match self {
            Self::Hex8(_) => &HEX8_FACES,
            Self::Tet4(_) => &TET4_FACES,
        }
    }
}

/// The Kuhn split of a cube into six tetrahedra: each runs from corner 000 to corner 111 along
/// the axes in one of these orders; the even permutations (the first three) give positively
/// oriented tetrahedra, the odd ones negatively oriented (swap two nodes).
pub const KUHN_PATHS: [[usize; 3]; 6] = [
    [0, 1, 2],
    [1, 2, 0],
    [2, 0, 1],
    [0, 2, 1],
    [1, 0, 2],
    [2, 1, 0],
];

/// Local node lists of the four faces of a positively oriented tetrahedron, counter-clockwise
/// seen from outside.
const TET4_FACES: [&[usize]; 4] = [&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]];

/// Local node lists of the six faces of a hexahedron, ordered counter-clockwise seen from
/// outside (so that the diagonal cross product points outwards).
const HEX8_FACES: [&[usize]; 6] = [
    &[0, 3, 2, 1],
    &[4, 5, 6, 7],
    &[0, 1, 5, 4],
    &[2, 3, 7, 6],
    &[0, 4, 7, 3],
    &[1, 2, 6, 5],
];

/// A boundary face of a mesh: its nodes (outward ordering), centroid, unit outward normal and
/// area.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// Node numbers, counter-clockwise seen from outside.
    pub nodes: Vec<usize>,
    /// Centroid (mean of the nodes).
    pub centroid: Vec3,
    /// Unit outward normal.
    pub normal: Vec3,
    /// Area.
    pub area: f64,
}

/// A finite-element mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<Vec3>,
    /// Elements.
    pub elements: Vec<Element>,
}

impl Mesh {
    /// A structured box [min, max] cut into `div` hexahedra along x, y, z.
    /// Node (i, j, l) has number i + (nx+1)(j + (ny+1) l).
    pub fn hex_box(min: Vec3, max: Vec3, div: [usize; 3]) -> Mesh {
        let [nx, ny, nz] = div;
        let coord = |a: usize, i: usize, n: usize| -> f64 {
            if i == n {
                max[a]
            } else {
                min[a] + (max[a] - min[a]) * (i as f64) / (n as f64)
            }
        };
        let mut nodes = Vec::with_capacity((nx + 1) * (ny + 1) * (nz + 1));
        for l in 0..=nz {
            for j in 0..=ny {
                for i in 0..=nx {
                    nodes.push([coord(0, i, nx), coord(1, j, ny), coord(2, l, nz)]);
                }
            }
        }
        let id = |i: usize, j: usize, l: usize| i + (nx + 1) * (j + (ny + 1) * l);
        let mut elements = Vec::with_capacity(nx * ny * nz);
        for l in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    elements.push(Element::Hex8([
                        id(i, j, l),
                        id(i + 1, j, l),
                        id(i + 1, j + 1, l),
                        id(i, j + 1, l),
                        id(i, j, l + 1),
                        id(i + 1, j, l + 1),
                        id(i + 1, j + 1, l + 1),
                        id(i, j + 1, l + 1),
                    ]));
                }
            }
        }
        Mesh { nodes, elements }
    }

    /// Number of degrees of freedom (3 per node, node-major).
    pub fn ndof(&self) -> usize {
        3 * self.nodes.len()
    }

    /// The same nodes with each hexahedron cut into six tetrahedra along its diagonal from
    /// local node 0 to node 6 (the Kuhn split: one tetrahedron per order of the three axes).
    /// Neighbouring hexahedra of a structured box are cut alike, so the result is conforming;
    /// tetrahedra stay as they are.
    pub fn split_into_tets(&self) -> Mesh {
        // local node of the corner with coordinate bits (x, y, z)
        const CORNER: [[[usize; 2]; 2]; 2] = [[[0, 4], [3, 7]], [[1, 5], [2, 6]]];
        let mut elements = Vec::with_capacity(6 * self.elements.len());
        for e in &self.elements {
            match e {
                Element::Hex8(n) => {
                    for (k, path) in KUHN_PATHS.iter().enumerate() {
                        let mut bits = [0usize; 3];
                        let mut t = [n[0]; 4];
                        for (s, &axis) in path.iter().enumerate() {
                            bits[axis] = 1;
                            t[s + 1] = n[CORNER[bits[0]][bits[1]][bits[2]]];
                        }
                        if k >= 3 {
                            t.swap(1, 2);
                        }
                        elements.push(Element::Tet4(t));
                    }
                }
                Element::Tet4(_) => elements.push(e.clone()),
            }
        }
        Mesh {
            nodes: self.nodes.clone(),
            elements,
        }
    }

    /// Axis-aligned bounding box (min, max).
    /// A key equal for meshes equal up to a translation: element connectivity and node
    /// coordinates relative to the first node, rounded to 1e-9 of the mesh size (so translated
    /// copies match although their coordinates differ in the last bits).
    pub fn translation_key(&self) -> Vec<i64> {
        let (lo, hi) = self.bounding_box();
        let size = (0..3)
            .map(|c| hi[c] - lo[c])
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let origin = self.nodes.first().copied().unwrap_or([0.0; 3]);
        let mut key = vec![self.nodes.len() as i64, self.elements.len() as i64];
        for e in &self.elements {
            // the node count tells the kinds apart
            key.push(e.nodes().len() as i64);
            key.extend(e.nodes().iter().map(|&x| x as i64));
        }
        for p in &self.nodes {
            key.extend((0..3).map(|c| ((p[c] - origin[c]) / (1e-9 * size)).round() as i64));
        }
        key
    }

    /// Lower and upper corners of the nodes.
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        bounding_box_of(&self.nodes)
    }

    /// The faces that belong to exactly one element.
    pub fn boundary_faces(&self) -> Vec<Face> {
        let mut count: HashMap<Vec<usize>, (usize, Vec<usize>)> = HashMap::new();
        let mut order = Vec::new();
        for element in &self.elements {
            let n = element.nodes();
            for f in element.faces() {
                let nodes: Vec<usize> = f.iter().map(|&i| n[i]).collect();
                let mut key = nodes.clone();
                key.sort_unstable();
                let entry = count.entry(key.clone()).or_insert_with(|| {
                    order.push(key);
                    (0, nodes)
                });
                entry.0 += 1;
            }
        }
        order
            .into_iter()
            .filter_map(|key| {
                let (c, nodes) = &count[&key];
                (*c == 1).then(|| self.face(nodes.clone()))
            })
            .collect()
    }

    /// Geometry of a (planar) quadrilateral or triangular face given by its nodes: the normal
    /// from the cross product of the diagonals (quadrangle) or of two edges (triangle).
    fn face(&self, nodes: Vec<usize>) -> Face {
        let p: Vec<Vec3> = nodes.iter().map(|&i| self.nodes[i]).collect();
        let mut centroid = [0.0; 3];
        for q in &p {
            for a in 0..3 {
                centroid[a] += q[a] / p.len() as f64;
            }
        }
        let (d1, d2) = match p.len() {
            3 => (sub(p[1], p[0]), sub(p[2], p[0])),
            _ => (sub(p[2], p[0]), sub(p[3], p[1])),
        };
        let c = cross(d1, d2);
        let norm = dot(c, c).sqrt();
        Face {
            nodes,
            centroid,
            normal: [c[0] / norm, c[1] / norm, c[2] / norm],
            area: 0.5 * norm,
        }
    }
}

/// Lower and upper corners of a set of points (infinite corners for none).
pub fn bounding_box_of(points: &[Vec3]) -> (Vec3, Vec3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
    }
    (lo, hi)
}

/// a − b.
pub fn sub(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · b.
pub fn dot(a: Vec3, b: Vec3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b.
pub fn cross(a: Vec3, b: Vec3) -> Vec3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
pub fn norm(a: Vec3) -> f64 {
    dot(a, a).sqrt()
}

/// `a` divided by its norm.
pub fn unit(a: Vec3) -> Vec3 {
    let l = norm(a);
    [a[0] / l, a[1] / l, a[2] / l]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_boundary_has_six_sides_of_faces_with_outward_normals() {
        let m = Mesh::hex_box([0.0; 3], [2.0, 1.0, 1.0], [2, 1, 1]);
        let faces = m.boundary_faces();
        assert_eq!(faces.len(), 2 * 2 + 2 * 2 + 2);
        let total: f64 = faces.iter().map(|f| f.area).sum();
        assert!((total - 2.0 * (2.0 + 2.0 + 1.0)).abs() < 1e-12);
        for f in &faces {
            // outward: the normal points away from the box centre (1, 0.5, 0.5)
            let d = sub(f.centroid, [1.0, 0.5, 0.5]);
            assert!(dot(d, f.normal) > 0.0);
        }
    }

    #[test]
    fn a_box_split_into_tetrahedra_is_conforming_and_fills_the_box() {
        let hexes = Mesh::hex_box([0.0; 3], [2.0, 1.0, 0.5], [3, 2, 2]);
        let m = hexes.split_into_tets();
        assert_eq!(m.elements.len(), 6 * hexes.elements.len());
        assert_eq!(m.nodes, hexes.nodes);
        let mut volume = 0.0;
        for e in &m.elements {
            let Element::Tet4(n) = e else {
                panic!("{e:?} is not a tetrahedron")
            };
            let v = crate::elements::tet4::signed_volume(&n.map(|i| m.nodes[i]));
            assert!(v > 0.0, "{n:?}: volume {v}");
            volume += v;
        }
        assert!((volume - 1.0).abs() < 1e-12, "{volume}");
        // conforming: the boundary is the box's surface, in triangles, two per boundary quad
        let faces = m.boundary_faces();
        assert_eq!(faces.len(), 2 * hexes.boundary_faces().len());
        assert!(faces.iter().all(|f| f.nodes.len() == 3));
        let area: f64 = faces.iter().map(|f| f.area).sum();
        assert!((area - 2.0 * (2.0 + 1.0 + 0.5)).abs() < 1e-12, "{area}");
        for f in &faces {
            let d = sub(f.centroid, [1.0, 0.5, 0.25]);
            assert!(dot(d, f.normal) > 0.0, "inward face {f:?}");
        }
        // a translated copy has the same key, a hexahedral mesh of the same nodes another one
        let moved = Mesh::hex_box([5.0, 0.0, 0.0], [7.0, 1.0, 0.5], [3, 2, 2]).split_into_tets();
        assert_eq!(moved.translation_key(), m.translation_key());
        assert_ne!(hexes.translation_key(), m.translation_key());
    }
}
