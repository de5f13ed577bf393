//! The cutting plane: an axis-aligned plane x_a = c. Each hexahedron it crosses is cut along its
//! 12 edges into a convex polygon whose corners carry linearly interpolated positions and field
//! values, so the cut face shows the field inside the body (as the seed paper's partial
//! sections do).

use glam::Vec3;

/// A cutting plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// Axis 0, 1, 2 = x, y, z of the plane's normal.
    pub axis: usize,
    /// Position of the plane along that axis (m, undeformed coordinates).
    pub position: f32,
    /// +1: the half x_a > c is cut away; −1: the half x_a < c.
    pub facing: f32,
}

/// The 12 edges of a hexahedron (local node pairs).
const EDGES: [(usize, usize); 12] = [
    (0, 1),
    (1, 2),
    (2, 3),
    (3, 0),
    (4, 5),
    (5, 6),
    (6, 7),
    (7, 4),
    (0, 4),
    (1, 5),
    (2, 6),
    (3, 7),
];

/// A corner of a cut polygon: the two nodes of the cut edge and the weight of the second.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CutPoint {
    /// First node (global number in its substructure).
    pub a: usize,
    /// Second node.
    pub b: usize,
    /// Weight of `b` (position = (1 − t) x_a + t x_b).
    pub t: f32,
}

impl Section {
    /// Signed distance of a point from the plane (positive: the removed side).
    pub fn side(&self, p: Vec3) -> f32 {
        self.facing * (p[self.axis] - self.position)
    }

    /// The polygon cut from hexahedron `hex` (node numbers into `nodes`), ordered around its
    /// centre, or None if the plane misses it.
    pub fn cut(&self, nodes: &[Vec3], hex: &[usize; 8]) -> Option<Vec<CutPoint>> {
        let d: [f32; 8] = std::array::from_fn(|i| self.side(nodes[hex[i]]));
        if d.iter().all(|&x| x > 0.0) || d.iter().all(|&x| x <= 0.0) {
            return None;
        }
        let mut pts: Vec<(CutPoint, Vec3)> = Vec::with_capacity(6);
        for (i, j) in EDGES {
            let (di, dj) = (d[i], d[j]);
            if (di > 0.0) == (dj > 0.0) {
                continue;
            }
            let t = di / (di - dj);
            let p = nodes[hex[i]].lerp(nodes[hex[j]], t);
            if pts
                .iter()
                .any(|(_, q)| q.distance(p) < 1e-7 * (1.0 + p.length()))
            {
                continue;
            }
            pts.push((
                CutPoint {
                    a: hex[i],
                    b: hex[j],
                    t,
                },
                p,
            ));
        }
        if pts.len() < 3 {
            return None;
        }
        let (u, v) = ((self.axis + 1) % 3, (self.axis + 2) % 3);
        let c = pts.iter().map(|(_, p)| *p).sum::<Vec3>() / pts.len() as f32;
        pts.sort_by(|(_, p), (_, q)| {
            let ap = (p[v] - c[v]).atan2(p[u] - c[u]);
            let aq = (q[v] - c[v]).atan2(q[u] - c[u]);
            ap.total_cmp(&aq)
        });
        Some(pts.into_iter().map(|(cp, _)| cp).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_hex() -> (Vec<Vec3>, [usize; 8]) {
        let n = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(1.0, 1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        ];
        (n, [0, 1, 2, 3, 4, 5, 6, 7])
    }

    #[test]
    fn a_mid_plane_cuts_a_unit_cube_into_a_unit_square() {
        let (n, h) = unit_hex();
        let s = Section {
            axis: 0,
            position: 0.25,
            facing: -1.0,
        };
        let poly = s.cut(&n, &h).expect("the plane crosses the cube");
        assert_eq!(poly.len(), 4);
        // every corner lies on the plane, and the polygon's area is 1 (shoelace in y, z)
        let p: Vec<Vec3> = poly.iter().map(|c| n[c.a].lerp(n[c.b], c.t)).collect();
        assert!(p.iter().all(|q| (q.x - 0.25).abs() < 1e-6));
        let area: f32 = (0..4)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % 4]);
                a.y * b.z - b.y * a.z
            })
            .sum::<f32>()
            .abs()
            * 0.5;
        assert!((area - 1.0).abs() < 1e-6, "{area}");
    }

    /// A tetrahedron enters the explorer as a collapsed hexahedron (bottom a b c c, top d d d d,
    /// `geometry.rs`): the plane x = 0.25 cuts the corner tetrahedron of the unit cube in the
    /// triangle (0.25, 0, 0), (0.25, 0.75, 0), (0.25, 0, 0.75), of area 0.75²/2.
    #[test]
    fn a_plane_cuts_a_collapsed_tetrahedron_in_a_triangle() {
        let (n, _) = unit_hex();
        // corners (0,0,0), (1,0,0), (0,1,0), (0,0,1) of the unit hexahedron's nodes
        let tet = [0, 1, 3, 3, 4, 4, 4, 4];
        let s = Section {
            axis: 0,
            position: 0.25,
            facing: -1.0,
        };
        let poly = s.cut(&n, &tet).expect("the plane crosses the tetrahedron");
        assert_eq!(poly.len(), 3);
        let p: Vec<Vec3> = poly.iter().map(|c| n[c.a].lerp(n[c.b], c.t)).collect();
        assert!(p.iter().all(|q| (q.x - 0.25).abs() < 1e-6));
        let area: f32 = (0..3)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % 3]);
                a.y * b.z - b.y * a.z
            })
            .sum::<f32>()
            .abs()
            * 0.5;
        assert!((area - 0.28125).abs() < 1e-6, "{area}");
    }

    #[test]
    fn a_plane_outside_misses() {
        let (n, h) = unit_hex();
        for position in [-0.5, 1.0, 2.0] {
            let s = Section {
                axis: 2,
                position,
                facing: 1.0,
            };
            assert!(s.cut(&n, &h).is_none());
        }
    }
}
