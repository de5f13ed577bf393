//! The outer surface of a substructure as a triangle mesh over its own surface nodes only
//! (boundary quadrilaterals split in two, vertices renumbered compactly), what a recording draws
//! per time step, and nodal von Mises stress on it (element-centre values of METHOD §2 averaged
//! to the nodes, as in the explorer).

use lopin_core::mesh::Mesh;

/// A substructure surface: which mesh nodes are vertices, and the triangles over them.
#[derive(Debug, Clone, PartialEq)]
pub struct Surface {
    /// Mesh node of each vertex.
    pub nodes: Vec<usize>,
    /// Triangles (vertex indices), outward ordering.
    pub triangles: Vec<[u32; 3]>,
}

impl Surface {
    /// The boundary of `mesh`.
    pub fn of(mesh: &Mesh) -> Surface {
        let mut vertex = vec![u32::MAX; mesh.nodes.len()];
        let mut nodes = Vec::new();
        let mut triangles = Vec::new();
        for face in mesh.boundary_faces() {
            let ids: Vec<u32> = face
                .nodes
                .iter()
                .map(|&n| {
                    if vertex[n] == u32::MAX {
                        vertex[n] = nodes.len() as u32;
                        nodes.push(n);
                    }
                    vertex[n]
                })
                .collect();
            for k in 1..ids.len().saturating_sub(1) {
                triangles.push([ids[0], ids[k], ids[k + 1]]);
            }
        }
        Surface { nodes, triangles }
    }

    /// Vertex positions x + scale·u (u node-major).
    pub fn positions(&self, mesh: &Mesh, u: &[f64], scale: f64) -> Vec<[f32; 3]> {
        self.nodes
            .iter()
            .map(|&n| {
                let x = mesh.nodes[n];
                std::array::from_fn(|c| (x[c] + scale * u[3 * n + c]) as f32)
            })
            .collect()
    }

    /// Values of a nodal field at the vertices.
    pub fn pick(&self, nodal: &[f64]) -> Vec<f64> {
        self.nodes.iter().map(|&n| nodal[n]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_box_surface_has_its_boundary_nodes_and_two_triangles_per_face() {
        let mesh = Mesh::hex_box([0.0; 3], [1.0, 2.0, 3.0], [2, 3, 4]);
        let s = Surface::of(&mesh);
        // all nodes but the interior (1 × 2 × 3) ones
        assert_eq!(s.nodes.len(), 3 * 4 * 5 - 2 * 3);
        // 2 (xy·2 + yz·2 + zx·2) quads, two triangles each
        assert_eq!(s.triangles.len(), 2 * 2 * (2 * 3 + 3 * 4 + 4 * 2));
        let u = vec![1e-3; 3 * mesh.nodes.len()];
        let p = s.positions(&mesh, &u, 10.0);
        let x = mesh.nodes[s.nodes[5]];
        assert!((f64::from(p[5][2]) - (x[2] + 1e-2)).abs() < 1e-6);
        // every triangle's vertices exist
        assert!(s
            .triangles
            .iter()
            .flatten()
            .all(|&v| (v as usize) < s.nodes.len()));
    }
}
