//! A boundary facet as a non-matching interface sees it: its shape functions N (linear
//! triangle, bilinear quadrangle), their inverse map from a point of the facet's plane, the
//! facet's consistent mass M_e = ∫ N Nᵀ and the dual basis ψ = D_e M_e⁻¹ N,
//! D_e = diag(∫ N), biorthogonal to N (∫ ψ_i N_j = δ_ij ∫ N_i) and summing to one
//! (METHOD §1 interface fields on a non-matching interface: the dual mortar space).

use crate::mesh::{cross, dot, norm, sub, Vec3};

/// A triangle or quadrangle of an interface side, its nodes counter-clockwise seen from
/// outside, with an orthonormal frame of its plane.
#[derive(Debug, Clone)]
pub struct Facet {
    /// Mesh nodes.
    pub nodes: Vec<usize>,
    /// Their positions.
    pub points: Vec<Vec3>,
    /// Outward unit normal.
    pub normal: Vec3,
    /// Origin of the plane frame (the centroid).
    pub origin: Vec3,
    /// Two unit tangents with t₁ × t₂ = n.
    pub tangents: [Vec3; 2],
}

/// The 3×3 Gauss rule on [−1, 1]²: points and weights.
fn gauss_square() -> impl Iterator<Item = ([f64; 2], f64)> {
    const X: [f64; 3] = [-0.774_596_669_241_483_4, 0.0, 0.774_596_669_241_483_4];
    const W: [f64; 3] = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    (0..9).map(|k| ([X[k % 3], X[k / 3]], W[k % 3] * W[k / 3]))
}

/// The 7-point rule of degree 5 on the reference triangle (area ½): barycentric points and
/// weights summing to 1.
pub fn triangle_rule() -> [([f64; 3], f64); 7] {
    const A: f64 = 0.059_715_871_789_769_82;
    const B: f64 = 0.470_142_064_105_115_1;
    const C: f64 = 0.797_426_985_353_087_3;
    const D: f64 = 0.101_286_507_323_456_3;
    const W1: f64 = 0.132_394_152_788_506_2;
    const W2: f64 = 0.125_939_180_544_827_1;
    [
        ([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], 0.225),
        ([A, B, B], W1),
        ([B, A, B], W1),
        ([B, B, A], W1),
        ([C, D, D], W2),
        ([D, C, D], W2),
        ([D, D, C], W2),
    ]
}

impl Facet {
    /// The facet of `nodes` at `points` with outward unit `normal`.
    pub fn new(nodes: Vec<usize>, points: Vec<Vec3>, normal: Vec3) -> Self {
        let k = points.len() as f64;
        let origin: Vec3 = std::array::from_fn(|a| points.iter().map(|p| p[a]).sum::<f64>() / k);
        let edge = sub(points[1], points[0]);
        let along = sub(edge, scale(normal, dot(edge, normal)));
        let t1 = scale(along, 1.0 / norm(along));
        let t2 = cross(normal, t1);
        Self {
            nodes,
            points,
            normal,
            origin,
            tangents: [t1, t2],
        }
    }

    /// Number of nodes (3 or 4).
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the facet has no nodes (never, for a mesh face).
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Coordinates of a point in the plane frame.
    pub fn to_plane(&self, p: Vec3) -> [f64; 2] {
        let d = sub(p, self.origin);
        [dot(d, self.tangents[0]), dot(d, self.tangents[1])]
    }

    /// The point of the plane at plane coordinates `x`.
    pub fn from_plane(&self, x: [f64; 2]) -> Vec3 {
        std::array::from_fn(|a| {
            self.origin[a] + x[0] * self.tangents[0][a] + x[1] * self.tangents[1][a]
        })
    }

    /// The facet's corners in its plane frame, counter-clockwise.
    pub fn polygon(&self) -> Vec<[f64; 2]> {
        self.corners_on(self)
    }

    /// The facet's corners projected on the plane of `plane`, in its node order (plane
    /// coordinates of that facet's frame).
    pub fn corners_on(&self, plane: &Facet) -> Vec<[f64; 2]> {
        self.points.iter().map(|&q| plane.to_plane(q)).collect()
    }

    /// Shape functions at reference coordinates ξ (triangle: (ξ, η) with N = (1 − ξ − η, ξ, η);
    /// quadrangle: (ξ, η) ∈ [−1, 1]², nodes at (−1, −1), (1, −1), (1, 1), (−1, 1)).
    pub fn shape(&self, xi: [f64; 2]) -> [f64; 4] {
        shape(self.len(), xi)
    }

    /// The reference coordinates of plane point `x` on this facet whose `corners` on that plane
    /// are given ([`Self::corners_on`]): exact for a triangle, Newton on the bilinear map for a
    /// quadrangle.
    pub fn reference_coordinates(&self, corners: &[[f64; 2]], x: [f64; 2]) -> [f64; 2] {
        debug_assert_eq!(corners.len(), self.len());
        inverse_map(corners, x)
    }

    /// Area element |∂x/∂ξ × ∂x/∂η| at reference coordinates ξ.
    fn jacobian(&self, xi: [f64; 2]) -> f64 {
        let d = shape_derivatives(self.len(), xi);
        let mut g = [[0.0; 3]; 2];
        for (i, p) in self.points.iter().enumerate() {
            for a in 0..3 {
                g[0][a] += d[i][0] * p[a];
                g[1][a] += d[i][1] * p[a];
            }
        }
        norm(cross(g[0], g[1]))
    }

    /// The consistent mass M_e = ∫ N Nᵀ (row-major, len × len), exact for a flat facet.
    pub fn mass(&self) -> Vec<f64> {
        let n = self.len();
        let mut m = vec![0.0; n * n];
        let mut add = |xi: [f64; 2], w: f64| {
            let s = self.shape(xi);
            let w = w * self.jacobian(xi);
            for i in 0..n {
                for j in 0..n {
                    m[i * n + j] += w * s[i] * s[j];
                }
            }
        };
        if n == 3 {
            for (b, w) in triangle_rule() {
                add([b[1], b[2]], 0.5 * w);
            }
        } else {
            for (xi, w) in gauss_square() {
                add(xi, w);
            }
        }
        m
    }

    /// Dual basis coefficients a (row-major): ψ_i = Σ_j a_ij N_j with a = D_e M_e⁻¹.
    pub fn dual_coefficients(&self) -> Vec<f64> {
        let n = self.len();
        let m = self.mass();
        let d: Vec<f64> = (0..n).map(|i| m[i * n..(i + 1) * n].iter().sum()).collect();
        let inv = invert(&m, n);
        (0..n * n).map(|k| d[k / n] * inv[k]).collect()
    }
}

/// Shape functions of a facet of `n` nodes at reference coordinates (see [`Facet::shape`]).
pub fn shape(n: usize, xi: [f64; 2]) -> [f64; 4] {
    if n == 3 {
        [1.0 - xi[0] - xi[1], xi[0], xi[1], 0.0]
    } else {
        let q = |a: f64, b: f64| 0.25 * (1.0 + a * xi[0]) * (1.0 + b * xi[1]);
        [q(-1.0, -1.0), q(1.0, -1.0), q(1.0, 1.0), q(-1.0, 1.0)]
    }
}

/// ∂N/∂(ξ, η) of a facet of `n` nodes.
fn shape_derivatives(n: usize, xi: [f64; 2]) -> [[f64; 2]; 4] {
    if n == 3 {
        [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]
    } else {
        let d = |a: f64, b: f64| [0.25 * a * (1.0 + b * xi[1]), 0.25 * b * (1.0 + a * xi[0])];
        [d(-1.0, -1.0), d(1.0, -1.0), d(1.0, 1.0), d(-1.0, 1.0)]
    }
}

/// Reference coordinates of `x` on the planar triangle or quadrangle `p`.
fn inverse_map(p: &[[f64; 2]], x: [f64; 2]) -> [f64; 2] {
    let n = p.len();
    let mut xi = if n == 3 { [1.0 / 3.0; 2] } else { [0.0; 2] };
    for _ in 0..(if n == 3 { 1 } else { 30 }) {
        let s = shape(n, xi);
        let d = shape_derivatives(n, xi);
        let (mut r, mut j) = ([0.0; 2], [[0.0; 2]; 2]);
        for i in 0..n {
            for a in 0..2 {
                r[a] += s[i] * p[i][a];
                j[a][0] += d[i][0] * p[i][a];
                j[a][1] += d[i][1] * p[i][a];
            }
        }
        let (r0, r1) = (x[0] - r[0], x[1] - r[1]);
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let step = [
            (j[1][1] * r0 - j[0][1] * r1) / det,
            (j[0][0] * r1 - j[1][0] * r0) / det,
        ];
        xi = [xi[0] + step[0], xi[1] + step[1]];
        if step[0].abs().max(step[1].abs()) < 1e-15 {
            break;
        }
    }
    xi
}

/// Inverse of a small dense SPD matrix (row-major n × n) by Gauss–Jordan.
fn invert(m: &[f64], n: usize) -> Vec<f64> {
    let mut a = m.to_vec();
    let mut inv: Vec<f64> = (0..n * n)
        .map(|k| if k / n == k % n { 1.0 } else { 0.0 })
        .collect();
    for c in 0..n {
        let p = a[c * n + c];
        for j in 0..n {
            a[c * n + j] /= p;
            inv[c * n + j] /= p;
        }
        for r in 0..n {
            if r != c {
                let l = a[r * n + c];
                for j in 0..n {
                    a[r * n + j] -= l * a[c * n + j];
                    inv[r * n + j] -= l * inv[c * n + j];
                }
            }
        }
    }
    inv
}

fn scale(v: Vec3, s: f64) -> Vec3 {
    [v[0] * s, v[1] * s, v[2] * s]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> Facet {
        // a non-parallelogram quadrangle in the plane z = 0.3, normal +z
        let p = vec![
            [0.0, 0.0, 0.3],
            [2.0, 0.0, 0.3],
            [1.7, 1.2, 0.3],
            [0.2, 1.0, 0.3],
        ];
        Facet::new(vec![0, 1, 2, 3], p, [0.0, 0.0, 1.0])
    }

    fn triangle() -> Facet {
        let p = vec![[0.0, 0.0, 0.0], [1.0, 0.2, 0.1], [0.3, 0.9, -0.2]];
        let n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
        let l = norm(n);
        Facet::new(vec![0, 1, 2], p, [n[0] / l, n[1] / l, n[2] / l])
    }

    /// The dual basis is biorthogonal to N: a M_e = D_e, for a triangle and a distorted
    /// quadrangle, and its coefficients' columns sum to one (Σ ψ_i = 1), to 1e-12.
    #[test]
    fn dual_basis_is_biorthogonal_and_sums_to_one() {
        for f in [quad(), triangle()] {
            let n = f.len();
            let (m, a) = (f.mass(), f.dual_coefficients());
            for i in 0..n {
                let d: f64 = m[i * n..(i + 1) * n].iter().sum();
                for k in 0..n {
                    let am: f64 = (0..n).map(|j| a[i * n + j] * m[j * n + k]).sum();
                    let expect = if i == k { d } else { 0.0 };
                    assert!((am - expect).abs() < 1e-12 * d, "{i},{k}: {am} vs {expect}");
                }
                let column: f64 = (0..n).map(|r| a[r * n + i]).sum();
                assert!((column - 1.0).abs() < 1e-12, "column {i}: {column}");
            }
            let area: f64 = m.iter().sum();
            let exact = if n == 3 {
                0.5 * norm(cross(
                    sub(f.points[1], f.points[0]),
                    sub(f.points[2], f.points[0]),
                ))
            } else {
                // shoelace in the plane z = 0.3
                let p = &f.points;
                0.5 * (0..4)
                    .map(|i| p[i][0] * p[(i + 1) % 4][1] - p[(i + 1) % 4][0] * p[i][1])
                    .sum::<f64>()
            };
            assert!((area - exact).abs() < 1e-12 * exact, "{area} vs {exact}");
        }
    }

    /// The inverse map returns the reference coordinates a point was made from.
    #[test]
    fn inverse_map_recovers_reference_coordinates() {
        for f in [quad(), triangle()] {
            for xi in [[0.2, 0.3], [-0.5, 0.1], [0.05, 0.05]] {
                let xi = if f.len() == 3 { xi.map(f64::abs) } else { xi };
                let s = f.shape(xi);
                let p: Vec3 =
                    std::array::from_fn(|a| (0..f.len()).map(|i| s[i] * f.points[i][a]).sum());
                let back = f.reference_coordinates(&f.polygon(), f.to_plane(p));
                assert!((back[0] - xi[0]).abs() < 1e-12 && (back[1] - xi[1]).abs() < 1e-12);
            }
        }
    }
}
