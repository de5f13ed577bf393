//! The dual mortar coupling of a non-matching interface (METHOD §1, interfaces with a
//! discretization of their own). The interface nodes are the nodes of side 1 (the non-mortar
//! side); its fields F, W are nodal values there, paired with the lumped areas
//! A_q = ∫ N_q: the local stage stays pointwise (METHOD §5). Side 1 sees them as today (its
//! trace is the nodal selection B). Side 2 (the mortar side) sees them through the projection
//!
//!   (P v)_q = (1 / A_q) Σ_m (∫ ψ_q N_m dΓ) v_m,
//!
//! with ψ the dual basis of side 1 ([`crate::interfaces::facet`]) and the integrals computed on
//! the common refinement of the two face meshes: each side-2 facet projected on the plane of a
//! side-1 facet and clipped by it (the mortar segments), each segment split into triangles with
//! a 7-point rule of degree 5. Its forces are Pᵀ A F, so the work A·F·W is the same seen from
//! both sides; Σ_m P_qm = 1 and P reproduces every linear field on a side-1 facet that the
//! side-2 facets cover (rigid motions and uniform tractions pass exactly).
//!
//! Side-1 facets that side 2 covers only partly are left out of the interface (counted in
//! [`Coupling::left_out`]): a node keeps the facets that are covered.

use std::collections::{BTreeMap, HashMap};

use crate::interfaces::facet::{triangle_rule, Facet};
use crate::interfaces::interface::Projection;
use crate::mesh::{dot, norm, Vec3};

/// Faces are facing when n₁·n₂ < −FACING (25.8° apart at most).
pub const FACING: f64 = 0.9;
/// A side-1 facet is covered when the side-2 facets cover it to this relative area.
const COVERED: f64 = 1e-8;

/// A non-matching interface's coupling between side-1 facets and side-2 facets.
#[derive(Debug, Clone)]
pub struct Coupling {
    /// Interface nodes: the side-1 mesh nodes of the covered facets, in increasing order.
    pub nodes: Vec<usize>,
    /// Lumped area A_q = ∫ N_q over the covered facets.
    pub area: Vec<f64>,
    /// Unit normal per node (the facets' normals weighted by A), outward of side 1.
    pub normal: Vec<Vec3>,
    /// Weighted distance across the interface, n_q · ((P x)_q − x_q).
    pub distance: Vec<f64>,
    /// P, one row per interface node over side-2 mesh nodes.
    pub projection: Projection,
    /// Side-1 facets left out (partly covered) and their area.
    pub left_out: (usize, f64),
    /// Area of the covered side-1 facets.
    pub covered: f64,
}

/// Pairs (i, j) of an `a` facet and a `b` facet that face each other (normals at most 25.8°
/// from opposite), overlap when b is projected on a's plane (area above 1e-12 of a's), and
/// where they overlap lie within `window(a)` = (lowest, highest) distance of each other along
/// a's normal (b in front: positive), measured at the overlap's corners (so that two facetings
/// of one curved surface pair where they overlap).
pub fn overlapping_pairs(
    a: &[Facet],
    b: &[Facet],
    window: &dyn Fn(&Facet) -> (f64, f64),
) -> Vec<(usize, usize)> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let boxes_b: Vec<(Vec3, Vec3)> = b.iter().map(|f| bounds(&f.points, 0.0)).collect();
    let cell = boxes_b
        .iter()
        .map(|(lo, hi)| (0..3).map(|c| hi[c] - lo[c]).fold(0.0, f64::max))
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    let key = |p: Vec3| -> [i64; 3] { std::array::from_fn(|c| (p[c] / cell).floor() as i64) };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (j, (lo, hi)) in boxes_b.iter().enumerate() {
        let (k0, k1) = (key(*lo), key(*hi));
        for x in k0[0]..=k1[0] {
            for y in k0[1]..=k1[1] {
                for z in k0[2]..=k1[2] {
                    grid.entry([x, y, z]).or_default().push(j);
                }
            }
        }
    }
    let mut pairs = Vec::new();
    for (i, f) in a.iter().enumerate() {
        let (lo_d, hi_d) = window(f);
        let (lo, hi) = bounds(&f.points, lo_d.abs().max(hi_d.abs()));
        let (k0, k1) = (key(lo), key(hi));
        let mut seen: Vec<usize> = Vec::new();
        for x in k0[0]..=k1[0] {
            for y in k0[1]..=k1[1] {
                for z in k0[2]..=k1[2] {
                    if let Some(js) = grid.get(&[x, y, z]) {
                        seen.extend(js);
                    }
                }
            }
        }
        seen.sort_unstable();
        seen.dedup();
        let poly = f.polygon();
        let area = polygon_area(&poly);
        for j in seen {
            let g = &b[j];
            if dot(f.normal, g.normal) > -FACING {
                continue;
            }
            let overlap = clip(&counter_clockwise(&g.corners_on(f)), &poly);
            if polygon_area(&overlap) <= 1e-12 * area {
                continue;
            }
            // distance along a's normal from a's plane to b's plane at each corner
            let slope = dot(f.normal, g.normal);
            let inside = overlap.iter().all(|&x| {
                let p = f.from_plane(x);
                let d = dot(crate::mesh::sub(g.origin, p), g.normal) / slope;
                d >= lo_d && d <= hi_d
            });
            if inside {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// The coupling of side-1 facets `one` with side-2 facets `two` over their overlapping
/// `pairs` (indices into `one`, `two`; [`overlapping_pairs`]).
pub fn couple(one: &[Facet], two: &[Facet], pairs: &[(usize, usize)]) -> Coupling {
    let mut by_facet: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for &(i, j) in pairs {
        by_facet.entry(i).or_default().push(j);
    }
    // per side-1 node: A, Σ A n, and its row Σ ∫ ψ N_m by side-2 mesh node
    let mut area: BTreeMap<usize, (f64, Vec3)> = BTreeMap::new();
    let mut rows: BTreeMap<usize, BTreeMap<usize, f64>> = BTreeMap::new();
    let (mut left_out, mut left_area, mut covered) = (0, 0.0, 0.0);
    for (&i, js) in &by_facet {
        let f = &one[i];
        let poly = f.polygon();
        let full = polygon_area(&poly);
        let a = f.dual_coefficients();
        let n = f.len();
        let mut part: Vec<(usize, usize, f64)> = Vec::new();
        let mut d = [0.0; 4];
        let mut seen = 0.0;
        for &j in js {
            let g = &two[j];
            let corners = g.corners_on(f);
            let segment = clip(&counter_clockwise(&corners), &poly);
            let s_area = polygon_area(&segment);
            if s_area <= 1e-12 * full {
                continue;
            }
            seen += s_area;
            for (x, w) in segment_rule(&segment) {
                let nf = f.shape(f.reference_coordinates(&poly, x));
                let ng = g.shape(g.reference_coordinates(&corners, x));
                for (k, dk) in d.iter_mut().enumerate().take(n) {
                    *dk += w * nf[k];
                    let psi: f64 = (0..n).map(|l| a[k * n + l] * nf[l]).sum();
                    for (m, &node) in g.nodes.iter().enumerate() {
                        part.push((f.nodes[k], node, w * psi * ng[m]));
                    }
                }
            }
        }
        if (seen - full).abs() > COVERED * full.max(f64::MIN_POSITIVE) {
            left_out += 1;
            left_area += full;
            continue;
        }
        covered += full;
        for (k, &dk) in d.iter().enumerate().take(n) {
            let e = area.entry(f.nodes[k]).or_default();
            e.0 += dk;
            for c in 0..3 {
                e.1[c] += dk * f.normal[c];
            }
        }
        for (q, m, w) in part {
            *rows.entry(q).or_default().entry(m).or_default() += w;
        }
    }
    // the positions of side-2 nodes, for the weighted distance
    let position2: HashMap<usize, Vec3> = two
        .iter()
        .flat_map(|g| g.nodes.iter().copied().zip(g.points.iter().copied()))
        .collect();
    let position1: HashMap<usize, Vec3> = one
        .iter()
        .flat_map(|f| f.nodes.iter().copied().zip(f.points.iter().copied()))
        .collect();
    let mut projection = Projection::default();
    let (mut nodes, mut areas, mut normals, mut distance) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (&q, &(aq, weighted)) in &area {
        let l = norm(weighted);
        let normal = [weighted[0] / l, weighted[1] / l, weighted[2] / l];
        let mut across = [0.0; 3];
        let row: Vec<(usize, f64)> = rows
            .get(&q)
            .map(|r| r.iter().map(|(&m, &w)| (m, w / aq)).collect())
            .unwrap_or_default();
        for &(m, w) in &row {
            let p = position2[&m];
            for c in 0..3 {
                across[c] += w * p[c];
            }
        }
        projection.push_row(&row);
        nodes.push(q);
        areas.push(aq);
        normals.push(normal);
        distance.push(dot(crate::mesh::sub(across, position1[&q]), normal));
    }
    Coupling {
        nodes,
        area: areas,
        normal: normals,
        distance,
        projection,
        left_out: (left_out, left_area),
        covered,
    }
}

/// A polygon's corners, counter-clockwise (a side-2 facet projected on a side-1 facet's plane
/// turns the other way).
fn counter_clockwise(corners: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut p = corners.to_vec();
    if polygon_signed_area(&p) < 0.0 {
        p.reverse();
    }
    p
}

/// The intersection of polygon `subject` with the convex polygon `by` (both counter-clockwise;
/// Sutherland–Hodgman).
pub fn clip(subject: &[[f64; 2]], by: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut out = subject.to_vec();
    for i in 0..by.len() {
        if out.is_empty() {
            break;
        }
        let (a, b) = (by[i], by[(i + 1) % by.len()]);
        let side = |p: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        for k in 0..input.len() {
            let (p, q) = (input[k], input[(k + 1) % input.len()]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

/// Signed area of a polygon (positive counter-clockwise).
fn polygon_signed_area(p: &[[f64; 2]]) -> f64 {
    0.5 * (0..p.len())
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum::<f64>()
}

/// Area of a counter-clockwise polygon (0 when empty).
pub fn polygon_area(p: &[[f64; 2]]) -> f64 {
    if p.len() < 3 {
        0.0
    } else {
        polygon_signed_area(p).max(0.0)
    }
}

/// Quadrature points and weights on a convex polygon: a fan of triangles from its vertex
/// mean, each with the 7-point rule of degree 5.
fn segment_rule(p: &[[f64; 2]]) -> Vec<([f64; 2], f64)> {
    let k = p.len() as f64;
    let c = [
        p.iter().map(|x| x[0]).sum::<f64>() / k,
        p.iter().map(|x| x[1]).sum::<f64>() / k,
    ];
    let mut out = Vec::with_capacity(7 * p.len());
    for i in 0..p.len() {
        let (a, b) = (p[i], p[(i + 1) % p.len()]);
        let area = 0.5 * ((a[0] - c[0]) * (b[1] - c[1]) - (b[0] - c[0]) * (a[1] - c[1]));
        if area <= 0.0 {
            continue;
        }
        for (l, w) in triangle_rule() {
            let x = [
                l[0] * c[0] + l[1] * a[0] + l[2] * b[0],
                l[0] * c[1] + l[1] * a[1] + l[2] * b[1],
            ];
            out.push((x, w * area));
        }
    }
    out
}

/// Bounding box of points, grown by `margin`.
fn bounds(p: &[Vec3], margin: f64) -> (Vec3, Vec3) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for q in p {
        for c in 0..3 {
            lo[c] = lo[c].min(q[c] - margin);
            hi[c] = hi[c].max(q[c] + margin);
        }
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quadrangles of an nx × ny grid of [0, 1]² at height z, normal `up` (±1).
    fn grid(nx: usize, ny: usize, z: f64, up: f64, first: usize) -> Vec<Facet> {
        let id = |i: usize, j: usize| first + j * (nx + 1) + i;
        let at = |i: usize, j: usize| [i as f64 / nx as f64, j as f64 / ny as f64, z];
        let mut out = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let mut c = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                if up < 0.0 {
                    c.reverse();
                }
                out.push(Facet::new(
                    c.iter().map(|&(a, b)| id(a, b)).collect(),
                    c.iter().map(|&(a, b)| at(a, b)).collect(),
                    [0.0, 0.0, up],
                ));
            }
        }
        out
    }

    /// A 3 × 3 grid of quadrangles (side 1, normal +z) under a 4 × 5 grid (side 2, normal −z)
    /// 0.01 above: areas add to the face, every row of P sums to one, P reproduces a linear
    /// field, the weighted distance is the gap, to 1e-12.
    #[test]
    fn projection_reproduces_linear_fields_on_non_matching_grids() {
        let one = grid(3, 3, 0.0, 1.0, 0);
        let two = grid(4, 5, 0.01, -1.0, 100);
        let pairs = overlapping_pairs(&one, &two, &|_| (-1e-9, 0.02));
        let c = couple(&one, &two, &pairs);
        assert_eq!(c.nodes.len(), 16);
        assert_eq!(c.left_out.0, 0);
        assert!((c.area.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        let field = |p: Vec3| 0.3 + 1.7 * p[0] - 0.4 * p[1];
        let pos = |m: usize| {
            let (i, j) = ((m - 100) % 5, (m - 100) / 5);
            [i as f64 / 4.0, j as f64 / 5.0, 0.01]
        };
        for (q, &node) in c.nodes.iter().enumerate() {
            let row = c.projection.row(q);
            let sum: f64 = row.iter().map(|x| x.1).sum();
            assert!((sum - 1.0).abs() < 1e-12, "row {q}: {sum}");
            let (i, j) = (node % 4, node / 4);
            let x = [i as f64 / 3.0, j as f64 / 3.0, 0.0];
            let projected: f64 = row.iter().map(|&(m, w)| w * field(pos(m))).sum();
            assert!((projected - field(x)).abs() < 1e-12, "node {node}");
            assert!((c.distance[q] - 0.01).abs() < 1e-12);
            assert!((c.normal[q][2] - 1.0).abs() < 1e-12);
        }
    }

    /// A small face on a large one: the small side is covered; the large one, as side 1, keeps
    /// only its covered facets.
    #[test]
    fn a_small_face_on_a_large_one_is_covered_only_from_the_small_side() {
        let large = grid(4, 4, 0.0, 1.0, 0);
        let mut small = grid(2, 2, 0.0, -1.0, 100);
        for f in &mut small {
            for p in &mut f.points {
                p[0] = 0.25 + 0.5 * p[0];
                p[1] = 0.25 + 0.5 * p[1];
            }
            *f = Facet::new(f.nodes.clone(), f.points.clone(), f.normal);
        }
        let window = |_: &Facet| (-1e-9, 1e-9);
        let from_small = couple(&small, &large, &overlapping_pairs(&small, &large, &window));
        assert_eq!(from_small.left_out.0, 0);
        assert!((from_small.covered - 0.25).abs() < 1e-12);
        let from_large = couple(&large, &small, &overlapping_pairs(&large, &small, &window));
        assert_eq!(
            from_large.left_out.0, 0,
            "the large face's facets inside: 4 covered"
        );
        assert!((from_large.covered - 0.25).abs() < 1e-12);
    }

    #[test]
    fn clipping_two_squares_gives_their_overlap() {
        let a = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let b = [[0.5, 0.25], [1.5, 0.25], [1.5, 1.25], [0.5, 1.25]];
        assert!((polygon_area(&clip(&b, &a)) - 0.375).abs() < 1e-15);
        let far = [[2.0, 2.0], [3.0, 2.0], [3.0, 3.0]];
        assert_eq!(polygon_area(&clip(&far, &a)), 0.0);
    }
}
