//! Writes small Gmsh MSH 4.1 files, ASCII or binary, from a description, so that the mesh input
//! (`lopin_core::mesh::msh`) is tested on both encodings without gmsh installed. It follows the
//! format as Gmsh documents it (`$MeshFormat`, `$PhysicalNames`, `$Entities`, `$Nodes`,
//! `$Elements`; binary: little-endian, 4-byte int, 8-byte size_t and double). Entities carry no
//! bounding entities and a zero bounding box: Lopin reads only their physical tags.

use lopin_core::mesh::KUHN_PATHS;

/// A mesh to write: nodes are tagged 1, 2, … in order.
#[derive(Debug, Clone, Default)]
pub struct MshDescription {
    /// Node coordinates.
    pub nodes: Vec<[f64; 3]>,
    /// `(dim, tag, name)` of the physical groups.
    pub physical_names: Vec<(i32, i32, String)>,
    /// `(entity tag, physical tags)` of the surfaces.
    pub surfaces: Vec<(i32, Vec<i32>)>,
    /// `(entity tag, physical tags)` of the volumes.
    pub volumes: Vec<(i32, Vec<i32>)>,
    /// Element blocks: `(entity dim, entity tag, Gmsh element type, node tags per element)`;
    /// elements are tagged 1, 2, … across the blocks.
    pub blocks: Vec<(i32, i32, i32, Vec<Vec<u64>>)>,
}

/// Appends one value in the file's encoding: text (with a separator) or little-endian bytes.
struct Out {
    bytes: Vec<u8>,
    binary: bool,
}

impl Out {
    fn text(&mut self, s: &str) {
        self.bytes.extend_from_slice(s.as_bytes());
    }
    fn int(&mut self, v: i32) {
        if self.binary {
            self.bytes.extend_from_slice(&v.to_le_bytes());
        } else {
            self.text(&format!("{v} "));
        }
    }
    fn size(&mut self, v: u64) {
        if self.binary {
            self.bytes.extend_from_slice(&v.to_le_bytes());
        } else {
            self.text(&format!("{v} "));
        }
    }
    fn float(&mut self, v: f64) {
        if self.binary {
            self.bytes.extend_from_slice(&v.to_le_bytes());
        } else {
            self.text(&format!("{v:e} "));
        }
    }
    /// End of a record: a newline in text (binary records just follow each other).
    fn end(&mut self) {
        if !self.binary {
            self.text("\n");
        }
    }
}

/// The file's bytes.
pub fn write(d: &MshDescription, binary: bool) -> Vec<u8> {
    let mut o = Out {
        bytes: Vec::new(),
        binary,
    };
    o.text(&format!("$MeshFormat\n4.1 {} 8\n", u8::from(binary)));
    if binary {
        o.int(1);
        o.text("\n");
    }
    o.text("$EndMeshFormat\n");
    if !d.physical_names.is_empty() {
        o.text(&format!("$PhysicalNames\n{}\n", d.physical_names.len()));
        for (dim, tag, name) in &d.physical_names {
            o.text(&format!("{dim} {tag} \"{name}\"\n"));
        }
        o.text("$EndPhysicalNames\n");
    }
    o.text("$Entities\n");
    for n in [0, 0, d.surfaces.len(), d.volumes.len()] {
        o.size(n as u64);
    }
    o.end();
    for (tag, physicals) in d.surfaces.iter().chain(&d.volumes) {
        o.int(*tag);
        for _ in 0..6 {
            o.float(0.0);
        }
        o.size(physicals.len() as u64);
        for p in physicals {
            o.int(*p);
        }
        o.size(0);
        o.end();
    }
    if binary {
        o.text("\n");
    }
    o.text("$EndEntities\n$Nodes\n");
    let n = d.nodes.len() as u64;
    for v in [1, n, 1, n] {
        o.size(v);
    }
    o.end();
    // one block holding every node, on the first volume
    let volume = d.volumes.first().map_or(1, |v| v.0);
    o.int(3);
    o.int(volume);
    o.int(0);
    o.size(n);
    o.end();
    for t in 1..=n {
        o.size(t);
        o.end();
    }
    for p in &d.nodes {
        for c in p {
            o.float(*c);
        }
        o.end();
    }
    if binary {
        o.text("\n");
    }
    o.text("$EndNodes\n$Elements\n");
    let total: usize = d.blocks.iter().map(|b| b.3.len()).sum();
    for v in [d.blocks.len() as u64, total as u64, 1, total as u64] {
        o.size(v);
    }
    o.end();
    let mut tag = 0u64;
    for (dim, entity, kind, elements) in &d.blocks {
        o.int(*dim);
        o.int(*entity);
        o.int(*kind);
        o.size(elements.len() as u64);
        o.end();
        for e in elements {
            tag += 1;
            o.size(tag);
            for n in e {
                o.size(*n);
            }
            o.end();
        }
    }
    if binary {
        o.text("\n");
    }
    o.text("$EndElements\n");
    o.bytes
}

/// The unit cube [0, 1]³ as 6 tetrahedra (the Kuhn split along the diagonal from the origin),
/// physical volume `cube` (tag 2) and its bottom face z = 0 as two triangles, physical surface
/// `bottom` (tag 1).
pub fn unit_cube_tets() -> MshDescription {
    let nodes: Vec<[f64; 3]> = (0..8)
        .map(|i| [(i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64])
        .collect();
    // node tag of corner bits (x, y, z) = 1 + x + 2y + 4z
    let tag = |c: [usize; 3]| (1 + c[0] + 2 * c[1] + 4 * c[2]) as u64;
    let mut tets = Vec::new();
    for (i, p) in KUHN_PATHS.into_iter().enumerate() {
        let mut c = [0usize; 3];
        let mut t = vec![tag(c)];
        for axis in p {
            c[axis] += 1;
            t.push(tag(c));
        }
        // the odd permutations (the last three) are negatively oriented: swap two nodes
        if i >= 3 {
            t.swap(1, 2);
        }
        tets.push(t);
    }
    MshDescription {
        nodes,
        physical_names: vec![(2, 1, "bottom".into()), (3, 2, "cube".into())],
        surfaces: vec![(1, vec![1])],
        volumes: vec![(1, vec![2])],
        blocks: vec![
            (2, 1, 2, vec![vec![1, 2, 4], vec![1, 4, 3]]),
            (3, 1, 4, tets),
        ],
    }
}

/// A column of two cubes of side `size` stacked along z, each cut into n × n × n cells of six
/// tetrahedra (the Kuhn split, as [`lopin_core::mesh::Mesh::split_into_tets`] cuts a box): the
/// physical volumes `lower` (z < size, tag 1) and `upper` (tag 2) share the nodes of the face
/// z = size, as Gmsh writes a fragmented geometry; the physical surfaces `bottom` (tag 3) and
/// `top` (tag 4) are the faces z = 0 and z = 2 size in triangles.
pub fn stacked_cubes(n: usize, size: f64) -> MshDescription {
    let h = size / n as f64;
    let (nx, nz) = (n + 1, 2 * n + 1);
    let tag = |i: usize, j: usize, k: usize| (1 + i + nx * (j + nx * k)) as u64;
    let mut nodes = Vec::new();
    for k in 0..nz {
        for j in 0..nx {
            for i in 0..nx {
                nodes.push([i as f64 * h, j as f64 * h, k as f64 * h]);
            }
        }
    }
    let (mut lower, mut upper, mut bottom, mut top) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..2 * n {
        for j in 0..n {
            for i in 0..n {
                for (p, path) in KUHN_PATHS.iter().enumerate() {
                    let mut c = [i, j, k];
                    let mut t = vec![tag(c[0], c[1], c[2])];
                    for &axis in path {
                        c[axis] += 1;
                        t.push(tag(c[0], c[1], c[2]));
                    }
                    if p >= 3 {
                        t.swap(1, 2);
                    }
                    if k < n {
                        lower.push(t);
                    } else {
                        upper.push(t);
                    }
                }
            }
        }
    }
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (
                tag(i, j, 0),
                tag(i + 1, j, 0),
                tag(i + 1, j + 1, 0),
                tag(i, j + 1, 0),
            );
            // outward (−z): clockwise seen from above
            bottom.push(vec![a, c, b]);
            bottom.push(vec![a, d, c]);
            let k = 2 * n;
            let (a, b, c, d) = (
                tag(i, j, k),
                tag(i + 1, j, k),
                tag(i + 1, j + 1, k),
                tag(i, j + 1, k),
            );
            top.push(vec![a, b, c]);
            top.push(vec![a, c, d]);
        }
    }
    MshDescription {
        nodes,
        physical_names: vec![
            (2, 3, "bottom".into()),
            (2, 4, "top".into()),
            (3, 1, "lower".into()),
            (3, 2, "upper".into()),
        ],
        surfaces: vec![(1, vec![3]), (2, vec![4])],
        volumes: vec![(1, vec![1]), (2, vec![2])],
        blocks: vec![
            (2, 1, 2, bottom),
            (2, 2, 2, top),
            (3, 1, 4, lower),
            (3, 2, 4, upper),
        ],
    }
}
