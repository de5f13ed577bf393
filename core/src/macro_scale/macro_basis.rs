//! The macro space of one two-sided interface (METHOD §9 "Macro space"): the traces of the affine
//! fields of the ambient space on the interface's nodes, orthonormalised for the A-weighted
//! product (Eᵀ A E = I). A planar interface gets 9 functions (3 translations, 3 rotations,
//! 2 extensions, 1 in-plane shear): of the 12 ambient affine fields only 9 have independent
//! traces on a plane, and the orthonormalisation drops the dependent ones by itself (12 on a
//! non-planar interface, fewer on a line). Macro coordinates of a side field X are Eᵀ A X.

use crate::interfaces::interface::Interface;
use crate::mesh::Vec3;

/// Relative norm below which an affine field counts as dependent on the earlier ones.
const DEPENDENT: f64 = 1e-8;

/// An A-orthonormal macro basis on the trace entries of an interface (node-major, component
/// minor, as every side of the interface stores them).
#[derive(Debug, Clone, PartialEq)]
pub struct MacroBasis {
    /// Trace entries per side (3 × nodes).
    pub len: usize,
    /// Number of macro functions.
    pub count: usize,
    /// The functions, column-major: function c is `e[c * len..(c + 1) * len]`.
    pub e: Vec<f64>,
}

impl MacroBasis {
    /// The macro basis of a two-sided interface whose side-1 nodes sit at `positions` (one per
    /// interface node), with the interface's lumped areas `area` (one per trace entry).
    pub fn new(positions: &[Vec3], area: &[f64]) -> Self {
        let len = area.len();
        debug_assert_eq!(len, 3 * positions.len());
        // A-weighted centroid, and a length scale so that the linear fields are O(1)
        let total: f64 = (0..positions.len()).map(|j| area[3 * j]).sum();
        let mut centre = [0.0; 3];
        for (j, p) in positions.iter().enumerate() {
            for c in 0..3 {
                centre[c] += area[3 * j] * p[c] / total;
            }
        }
        let radius = positions
            .iter()
            .map(|p| (0..3).map(|c| (p[c] - centre[c]).powi(2)).sum::<f64>())
            .fold(0.0f64, f64::max)
            .sqrt()
            .max(f64::MIN_POSITIVE);
        // the 12 ambient affine fields: translations e_c, then x_d e_c (d, c = 0..3)
        let mut raw: Vec<Vec<f64>> = Vec::with_capacity(12);
        for c in 0..3 {
            let mut f = vec![0.0; len];
            for j in 0..positions.len() {
                f[3 * j + c] = 1.0;
            }
            raw.push(f);
        }
        for d in 0..3 {
            for c in 0..3 {
                let mut f = vec![0.0; len];
                for (j, p) in positions.iter().enumerate() {
                    f[3 * j + c] = (p[d] - centre[d]) / radius;
                }
                raw.push(f);
            }
        }
        // modified Gram–Schmidt in the A product, twice (re-orthogonalisation), dropping
        // dependent fields
        let dot = |a: &[f64], b: &[f64]| -> f64 {
            a.iter().zip(b).zip(area).map(|((x, y), w)| w * x * y).sum()
        };
        let mut kept: Vec<Vec<f64>> = Vec::with_capacity(12);
        for mut f in raw {
            let start = dot(&f, &f).sqrt();
            for _ in 0..2 {
                for q in &kept {
                    let c = dot(&f, q);
                    f.iter_mut().zip(q).for_each(|(x, y)| *x -= c * y);
                }
            }
            let n = dot(&f, &f).sqrt();
            if n > DEPENDENT * start {
                f.iter_mut().for_each(|x| *x /= n);
                kept.push(f);
            }
        }
        Self {
            len,
            count: kept.len(),
            e: kept.concat(),
        }
    }

    /// The macro basis of a two-sided interface (positions of side 1's nodes).
    pub fn of_interface(iface: &Interface, nodes: &[Vec3]) -> Self {
        let positions: Vec<Vec3> = iface.sides[0].nodes.iter().map(|&n| nodes[n]).collect();
        Self::new(&positions, &iface.area)
    }

    /// Function c.
    pub fn column(&self, c: usize) -> &[f64] {
        &self.e[c * self.len..(c + 1) * self.len]
    }

    /// Macro coordinates Eᵀ A x of a side field x, added into `out` with factor `scale`.
    pub fn project_add(&self, area: &[f64], x: &[f64], scale: f64, out: &mut [f64]) {
        for (c, o) in out.iter_mut().enumerate().take(self.count) {
            let col = self.column(c);
            let s: f64 = col
                .iter()
                .zip(area)
                .zip(x)
                .map(|((e, a), v)| e * a * v)
                .sum();
            *o += scale * s;
        }
    }

    /// x += E α (a macro field on the side's entries).
    pub fn expand_add(&self, alpha: &[f64], x: &mut [f64]) {
        for (c, &a) in alpha.iter().enumerate().take(self.count) {
            if a != 0.0 {
                x.iter_mut()
                    .zip(self.column(c))
                    .for_each(|(xi, e)| *xi += a * e);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(nx: usize, ny: usize, z: impl Fn(f64, f64) -> f64) -> (Vec<Vec3>, Vec<f64>) {
        let mut p = Vec::new();
        let mut a = Vec::new();
        for j in 0..=ny {
            for i in 0..=nx {
                let (x, y) = (i as f64 * 0.1, j as f64 * 0.05);
                p.push([x, y, z(x, y)]);
                let w = if i == 0 || i == nx { 0.5 } else { 1.0 }
                    * if j == 0 || j == ny { 0.5 } else { 1.0 }
                    * 0.005;
                a.extend([w; 3]);
            }
        }
        (p, a)
    }

    fn gram(b: &MacroBasis, area: &[f64]) -> Vec<f64> {
        let mut g = vec![0.0; b.count * b.count];
        for r in 0..b.count {
            let mut row = vec![0.0; b.count];
            b.project_add(area, b.column(r), 1.0, &mut row);
            g[r * b.count..(r + 1) * b.count].copy_from_slice(&row);
        }
        g
    }

    #[test]
    fn a_planar_interface_has_nine_orthonormal_functions() {
        let (p, a) = grid(4, 3, |_, _| 0.02);
        let b = MacroBasis::new(&p, &a);
        assert_eq!(b.count, 9);
        let g = gram(&b, &a);
        for r in 0..9 {
            for c in 0..9 {
                let want = if r == c { 1.0 } else { 0.0 };
                assert!(
                    (g[r * 9 + c] - want).abs() < 1e-12,
                    "G[{r},{c}] = {}",
                    g[r * 9 + c]
                );
            }
        }
    }

    #[test]
    fn a_curved_interface_has_twelve_and_a_line_fewer() {
        let (p, a) = grid(4, 3, |x, y| 0.3 * x * y + 0.1 * x * x);
        assert_eq!(MacroBasis::new(&p, &a).count, 12);
        let (p, a) = grid(5, 0, |_, _| 0.0);
        // on a line: 3 translations, 2 rotations, 1 extension
        assert_eq!(MacroBasis::new(&p, &a).count, 6);
    }

    #[test]
    fn the_basis_spans_rigid_motions_and_extensions_of_the_plane() {
        let (p, a) = grid(4, 3, |_, _| 0.0);
        let b = MacroBasis::new(&p, &a);
        // a rotation about x plus an extension along y plus a translation: affine, so it must
        // be reproduced exactly by its projection
        let f: Vec<f64> = p
            .iter()
            .flat_map(|q| [0.3, 2.0 * q[1] - 0.1, q[1] + 1.0])
            .collect();
        let mut alpha = vec![0.0; b.count];
        b.project_add(&a, &f, 1.0, &mut alpha);
        let mut back = vec![0.0; f.len()];
        b.expand_add(&alpha, &mut back);
        for (x, y) in f.iter().zip(&back) {
            assert!((x - y).abs() < 1e-12);
        }
    }
}
