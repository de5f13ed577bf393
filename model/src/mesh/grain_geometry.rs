//! Polyhedral grains: the seed paper's granular material, N seeded, non-overlapping
//! random convex polyhedral grains inside a cube of matrix ([`place_grains`]), and the Gmsh
//! `.geo` script that builds the cube and the grains, fragments them so that every grain shares
//! conforming surfaces with the matrix, and names the physical groups ([`geo_script`]).
//!
//! A grain is the convex hull of points drawn on a sphere at least 0.7 √(4π/n) apart (no tiny
//! edges), scaled by a random factor in [0.75, 1] along each axis and randomly rotated; shapes
//! with two nearly coplanar adjacent faces are redrawn (Gmsh would leave a flat tetrahedron
//! across their edge). Grains are placed by random sequential addition of their circumscribed
//! spheres, `gap` apart and `gap` away from the cube's faces.
//!
//! Physical groups of the script: volumes `matrix` (tag 1) and `grain1` … `grainN` (tags 2 …
//! N + 1, in placement order); surfaces `x-`, `x+`, `y-`, `y+`, `bottom` (z = 0) and `top`
//! (z = L) (tags 1 … 6). Meshed with `gmsh -3 sample.geo -format msh41 -o sample.msh` (Gmsh
//! 4.8.4): the 10 grains of radius 0.12 L to 0.2 L (gap 0.04 L) of `granular-poly` give 5,714
//! nodes at a mesh size of 0.06 L; the 50 grains of radius 0.08 L to 0.14 L (gap 0.02 L) of
//! `granular-poly-paper` 237,172 nodes at 0.0152 L.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt::Write;

use crate::mesh::{bounding_box_of, cross, dot, norm, sub, Vec3};
use crate::splitmix::SplitMix64;

/// Parameters of a polyhedral granular sample.
#[derive(Debug, Clone, PartialEq)]
pub struct GrainLayout {
    /// Side L of the cube of matrix; its lower corner is the origin.
    pub side: f64,
    /// Number N of grains.
    pub grains: usize,
    /// Smallest and largest circumscribed radius of a grain (each grain's is drawn in between).
    pub radius: [f64; 2],
    /// Points drawn per grain, all of which become hull vertices (at least 6; e.g. 12).
    pub vertices: usize,
    /// Smallest distance kept between the circumscribed spheres of two grains, and between a
    /// sphere and the cube's faces (positive).
    pub gap: f64,
    /// Seed of the placement (the same seed always gives the same grains).
    pub seed: u64,
}

/// A convex polyhedron: vertices and outward-oriented triangular faces (counter-clockwise seen
/// from outside).
#[derive(Debug, Clone, PartialEq)]
pub struct Polyhedron {
    /// Centre of the circumscribed sphere.
    pub centre: Vec3,
    /// Radius of the circumscribed sphere (every vertex lies within it).
    pub radius: f64,
    /// Vertices, every one a corner of the hull.
    pub vertices: Vec<Vec3>,
    /// Triangular faces: vertex indices counter-clockwise seen from outside.
    pub faces: Vec<[usize; 3]>,
}

impl Polyhedron {
    /// Volume by the divergence theorem, V = Σ a · (b × c) / 6 over the faces (a, b, c);
    /// positive for outward-oriented faces.
    pub fn volume(&self) -> f64 {
        let v = |i: usize| self.vertices[i];
        let six_v: f64 = self
            .faces
            .iter()
            .map(|f| dot(v(f[0]), cross(v(f[1]), v(f[2]))))
            .sum();
        six_v / 6.0
    }

    /// Lower and upper corners of the axis-aligned bounding box.
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        bounding_box_of(&self.vertices)
    }

    /// Whether `p` lies inside or on the boundary (within 10⁻⁹ radius of a face's plane).
    pub fn contains(&self, p: Vec3) -> bool {
        self.faces.iter().all(|f| {
            let a = self.vertices[f[0]];
            let n = cross(sub(self.vertices[f[1]], a), sub(self.vertices[f[2]], a));
            dot(n, sub(p, a)) <= 1e-9 * self.radius * norm(n)
        })
    }
}

/// Placement tries per grain before [`place_grains`] gives up.
const TRIES_PER_GRAIN: usize = 10_000;

/// Placement tries of a whole sample before [`place_grains`] gives up, however many grains.
const MAX_TRIES: usize = 2_000_000;

/// Grain indices bucketed by the cube of side `h` their centre lies in.
struct NeighbourGrid {
    h: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl NeighbourGrid {
    fn new(h: f64) -> Self {
        Self {
            h,
            cells: HashMap::new(),
        }
    }

    fn key(&self, p: Vec3) -> [i64; 3] {
        // `as` saturates: far-off centres share the outermost cells, which only adds candidates
        p.map(|x| (x / self.h).floor() as i64)
    }

    fn insert(&mut self, p: Vec3, index: usize) {
        let key = self.key(p);
        self.cells.entry(key).or_default().push(index);
    }

    /// The grains whose centre lies within `h` of `p` (and perhaps a few farther), in
    /// increasing order.
    fn around(&self, p: Vec3) -> Vec<usize> {
        let [i, j, k] = self.key(p);
        let mut out = Vec::new();
        for di in -1..=1i64 {
            for dj in -1..=1i64 {
                for dk in -1..=1i64 {
                    let key = [
                        i.saturating_add(di),
                        j.saturating_add(dj),
                        k.saturating_add(dk),
                    ];
                    if let Some(list) = self.cells.get(&key) {
                        out.extend_from_slice(list);
                    }
                }
            }
        }
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Places the grains: Err(reason) when N grains cannot be placed after a bounded number of tries
/// (10 000 × N, at most 2 000 000; the reason says how many were placed), or when the parameters are invalid
/// (non-positive side, radius not positive or radius[0] > radius[1], vertices < 6, no grains,
/// gap not positive, or 2 (radius[1] + gap) > side).
///
/// Each try draws a radius r uniformly in `radius` and a centre uniformly in
/// [r + gap, L − r − gap]³; it fails if its sphere comes within `gap` of an earlier grain's, or
/// if one grain's bounding box would hold another grain entirely (the script selects grains by
/// bounding box).
pub fn place_grains(layout: &GrainLayout) -> Result<Vec<Polyhedron>, String> {
    let (side, n, [r0, r1], vertices, gap) = (
        layout.side,
        layout.grains,
        layout.radius,
        layout.vertices,
        layout.gap,
    );
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(side) {
        return Err(format!("the side of the cube must be positive, got {side}"));
    }
    if !positive(r0) || !positive(r1) || r0 > r1 {
        return Err(format!(
            "the grain radii must be positive and increasing, got [{r0}, {r1}]"
        ));
    }
    if vertices < 6 {
        return Err(format!("a grain needs at least 6 vertices, got {vertices}"));
    }
    if n == 0 {
        return Err("the sample needs at least one grain".to_string());
    }
    if !positive(gap) {
        return Err(format!(
            "the gap between grains must be positive, got {gap}"
        ));
    }
    if 2.0 * (r1 + gap) > side {
        return Err(format!(
            "a grain of radius {r1} with gap {gap} does not fit in side {side}"
        ));
    }
    let eps = selection_eps(layout);
    let mut rng = SplitMix64(layout.seed);
    let mut grains: Vec<Polyhedron> = Vec::with_capacity(n.min(1024));
    // grains that can conflict have centres closer than 2 r1 + gap: a grid of that spacing
    // finds them among the 27 cells around a centre
    let mut near = NeighbourGrid::new(2.0 * r1 + gap + 2.0 * eps);
    let most_tries = TRIES_PER_GRAIN.saturating_mul(n).min(MAX_TRIES);
    let mut tries = 0;
    while grains.len() < n && tries < most_tries {
        tries += 1;
        let r = r0 + (r1 - r0) * rng.unit();
        let lo = r + gap;
        let centre = [0; 3].map(|_| lo + (side - 2.0 * lo) * rng.unit());
        let around = near.around(centre);
        if around
            .iter()
            .any(|&g| norm(sub(grains[g].centre, centre)) < grains[g].radius + r + gap)
        {
            continue;
        }
        let Some(new) = random_polyhedron(&mut rng, centre, r, vertices) else {
            continue;
        };
        if around.iter().all(|&g| {
            let g = &grains[g];
            !box_holds(g, &new, eps) && !box_holds(&new, g, eps)
        }) {
            near.insert(centre, grains.len());
            grains.push(new);
        }
    }
    if grains.len() < n {
        let placed = grains.len();
        return Err(format!(
            "placed only {placed} of {n} grains in {tries} tries: use fewer or smaller grains, \
             a smaller gap or a larger cube"
        ));
    }
    Ok(grains)
}

/// The gmsh .geo script (OpenCASCADE kernel) of the sample, meshed with tetrahedra of size about
/// `mesh_size`: the cube is volume 1, grain k volume k + 1, built from points, lines (one per
/// edge), curve loops, plane surfaces and a surface loop (tags from 1000 up and `newll`,
/// `newsl`: clear of the box's and of those OpenCASCADE binds itself); all are fragmented, then
/// the physical groups are selected by bounding box. The 3-D algorithm is Delaunay (1), whose
/// mesh is the same at every run; HXT (10) is faster with better tetrahedra, but not repeatable.
pub fn geo_script(layout: &GrainLayout, grains: &[Polyhedron], mesh_size: f64) -> String {
    let GrainLayout {
        side: l,
        grains: n,
        radius: [r0, r1],
        ..
    } = *layout;
    // writing to a String cannot fail: the results of write! are dropped
    let mut s = format!(
        "// Generated by Lopin (grain_geometry): side = {l}, grains = {n}, radius = [{r0}, {r1}], \
         vertices = {}, gap = {}, seed = {}, mesh_size = {mesh_size}\n\
         SetFactory(\"OpenCASCADE\");\n\
         Mesh.CharacteristicLengthMax = {mesh_size};\n\
         Mesh.CharacteristicLengthMin = {};\n\
         Mesh.ElementOrder = 1;\nMesh.Algorithm3D = 1;\nMesh.Optimize = 1;\n\
         Box(1) = {{0, 0, 0, {l}, {l}, {l}}};\n",
        layout.vertices,
        layout.gap,
        layout.seed,
        mesh_size / 4.0
    );
    let (mut point, mut line, mut surface) = (1000, 1000, 1000);
    for (k, g) in grains.iter().enumerate() {
        let _ = writeln!(s, "// grain {}", k + 1);
        let first = point;
        for v in &g.vertices {
            let _ = writeln!(s, "Point({point}) = {{{}, {}, {}}};", v[0], v[1], v[2]);
            point += 1;
        }
        let mut lines: HashMap<(usize, usize), i64> = HashMap::new();
        let mut surfaces = Vec::with_capacity(g.faces.len());
        for f in &g.faces {
            let mut curves = Vec::with_capacity(3);
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                // the neighbour face runs along an edge the other way: its line, reversed
                if let Some(&t) = lines.get(&(b, a)) {
                    curves.push(-t);
                } else {
                    let _ = writeln!(s, "Line({line}) = {{{}, {}}};", first + a, first + b);
                    lines.insert((a, b), line);
                    curves.push(line);
                    line += 1;
                }
            }
            let _ = writeln!(s, "ll = newll; Curve Loop(ll) = {{{}}};", join(&curves));
            let _ = writeln!(s, "Plane Surface({surface}) = {{ll}};");
            surfaces.push(surface);
            surface += 1;
        }
        let _ = writeln!(s, "sl = newsl; Surface Loop(sl) = {{{}}};", join(&surfaces));
        let _ = writeln!(s, "Volume({}) = {{sl}};", k + 2);
    }
    if !grains.is_empty() {
        let last = grains.len() + 1;
        let _ = writeln!(
            s,
            "BooleanFragments{{ Volume{{1}}; Delete; }}{{ Volume{{2:{last}}}; Delete; }}"
        );
    }
    let in_box = |lo: Vec3, hi: Vec3| {
        let [a, b, c, d, e, f] = [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]];
        format!(
            "In BoundingBox{{{a} - eps, {b} - eps, {c} - eps, {d} + eps, {e} + eps, {f} + eps}}"
        )
    };
    let _ = writeln!(
        s,
        "eps = {};\nmatrix() = Volume {};",
        selection_eps(layout),
        in_box([0.0; 3], [l; 3])
    );
    for (k, g) in (1..).zip(grains) {
        let (lo, hi) = g.bounding_box();
        let _ = writeln!(
            s,
            "grain{k}() = Volume {};\nPhysical Volume(\"grain{k}\", {}) = grain{k}();\n\
             matrix() -= grain{k}();",
            in_box(lo, hi),
            k + 1
        );
    }
    s += "Physical Volume(\"matrix\", 1) = matrix();\n";
    for (tag, name) in (1..).zip(["x-", "x+", "y-", "y+", "bottom", "top"]) {
        let (mut lo, mut hi) = ([0.0; 3], [l; 3]);
        let axis = (tag - 1) / 2;
        (lo[axis], hi[axis]) = if tag % 2 == 1 { (0.0, 0.0) } else { (l, l) };
        let _ = writeln!(
            s,
            "Physical Surface(\"{name}\", {tag}) = Surface {};",
            in_box(lo, hi)
        );
    }
    s
}

/// The tolerance of the bounding-box selections: well below the grains and the gap, well above
/// the geometric tolerance of OpenCASCADE (10⁻⁷).
fn selection_eps(layout: &GrainLayout) -> f64 {
    (1e-4 * layout.side).min(0.25 * layout.gap)
}

/// Whether the bounding box of `a`, grown by `eps`, holds every vertex of `b`.
fn box_holds(a: &Polyhedron, b: &Polyhedron, eps: f64) -> bool {
    let (lo, hi) = a.bounding_box();
    let inside = |p: &Vec3| (0..3).all(|i| p[i] >= lo[i] - eps && p[i] <= hi[i] + eps);
    b.vertices.iter().all(inside)
}

/// Shape attempts per placement try.
const SHAPE_ATTEMPTS: i32 = 64;

/// Smallest fold asked of a grain (angle between the normals of two adjacent faces), as a
/// fraction of the mean angular spacing √(4π/n) of its n points: 8° for 12 points.
const MIN_FOLD: f64 = 0.14;

/// A random convex polyhedron in the sphere (`centre`, `r`) with `n` vertices and folds of
/// at least [`MIN_FOLD`] √(4π/n) (a bound relaxed by 20 % after every 16 failed attempts);
/// None, a failed placement try, after [`SHAPE_ATTEMPTS`] failed attempts.
fn random_polyhedron(rng: &mut SplitMix64, centre: Vec3, r: f64, n: usize) -> Option<Polyhedron> {
    let spacing = (4.0 * PI / n as f64).sqrt();
    for attempt in 0..SHAPE_ATTEMPTS {
        let points = random_points(rng, centre, r, n, spacing);
        let Some(faces) = convex_hull(&points, 1e-7 * r) else {
            continue;
        };
        if smallest_fold(&points, &faces) < MIN_FOLD * spacing * 0.8f64.powi(attempt / 16) {
            continue;
        }
        // keep only the points the hull uses (all of them: points on an ellipsoid are extremal)
        let mut index = vec![usize::MAX; n];
        let mut vertices = Vec::with_capacity(n);
        for &i in faces.iter().flatten() {
            if index[i] == usize::MAX {
                index[i] = vertices.len();
                vertices.push(points[i]);
            }
        }
        let faces = faces.iter().map(|f| f.map(|i| index[i])).collect();
        let radius = r;
        return Some(Polyhedron {
            centre,
            radius,
            vertices,
            faces,
        });
    }
    None
}

/// `n` points on the sphere (`centre`, `r`) in directions at least 0.7 `spacing` apart (a
/// bound relaxed by 10 % after every 1000 rejections), scaled by a random factor in [0.75, 1]
/// along each axis, then turned by a uniform random rotation.
fn random_points(rng: &mut SplitMix64, centre: Vec3, r: f64, n: usize, spacing: f64) -> Vec<Vec3> {
    let mut cos_sep = (0.7 * spacing).cos();
    let mut dirs: Vec<Vec3> = Vec::with_capacity(n);
    let mut rejected = 0;
    while dirs.len() < n {
        let z = 2.0 * rng.unit() - 1.0;
        let (s, phi) = ((1.0 - z * z).sqrt(), 2.0 * PI * rng.unit());
        let d = [s * phi.cos(), s * phi.sin(), z];
        if dirs.iter().all(|e| dot(d, *e) < cos_sep) {
            dirs.push(d);
        } else {
            rejected += 1;
            if rejected % 1000 == 0 {
                cos_sep = (1.1 * cos_sep.acos()).min(PI).cos();
            }
        }
    }
    let scale = [0; 3].map(|_| r * (0.75 + 0.25 * rng.unit()));
    // a uniform random unit quaternion (w, q) (Shoemake 1992): v ↦ v + w t + q × t, t = 2 q × v
    let (u1, u2, u3) = (rng.unit(), 2.0 * PI * rng.unit(), 2.0 * PI * rng.unit());
    let w = (1.0 - u1).sqrt() * u2.sin();
    let q = [
        (1.0 - u1).sqrt() * u2.cos(),
        u1.sqrt() * u3.sin(),
        u1.sqrt() * u3.cos(),
    ];
    let turn = |d: &Vec3| {
        let v = [0, 1, 2].map(|a| scale[a] * d[a]);
        let t = cross(q, v).map(|c| 2.0 * c);
        let qt = cross(q, t);
        [0, 1, 2].map(|a| centre[a] + v[a] + w * t[a] + qt[a])
    };
    dirs.iter().map(turn).collect()
}

/// The smallest angle between the normals of two faces sharing an edge.
fn smallest_fold(p: &[Vec3], faces: &[[usize; 3]]) -> f64 {
    let mut normals = HashMap::new();
    for f in faces {
        let n = cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
        for e in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            normals.insert(e, n.map(|c| c / norm(n)));
        }
    }
    let fold = |(&(a, b), &n): (&(usize, usize), &Vec3)| {
        normals
            .get(&(b, a))
            .map_or(PI, |&m| dot(n, m).clamp(-1.0, 1.0).acos())
    };
    normals.iter().map(fold).fold(PI, f64::min)
}

/// The convex hull of points in general position by brute force (O(n⁴)): every triple with all
/// other points strictly on one side of its plane is a face, oriented outward. None when a
/// fourth point lies within `tol` of a face's plane, or when the faces do not close into a
/// consistently oriented surface (each directed edge once, and its reverse once).
fn convex_hull(p: &[Vec3], tol: f64) -> Option<Vec<[usize; 3]>> {
    let n = p.len();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let normal = cross(sub(p[j], p[i]), sub(p[k], p[i]));
                let t = tol * norm(normal);
                let (mut above, mut below, mut on) = (false, false, false);
                for m in (0..n).filter(|&m| m != i && m != j && m != k) {
                    let d = dot(normal, sub(p[m], p[i]));
                    (above, below, on) = (above || d > t, below || d < -t, on || d.abs() <= t);
                }
                match (above, below) {
                    (true, true) => {}
                    _ if on => return None,
                    (false, _) => faces.push([i, j, k]),
                    (true, false) => faces.push([i, k, j]),
                }
            }
        }
    }
    let mut edges = HashMap::new();
    for f in &faces {
        for e in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            *edges.entry(e).or_insert(0) += 1;
        }
    }
    let closed = edges
        .iter()
        .all(|(&(a, b), &c)| c == 1 && edges.get(&(b, a)) == Some(&1));
    (closed && !faces.is_empty()).then_some(faces)
}

/// Tags separated by commas.
fn join(tags: &[i64]) -> String {
    tags.iter()
        .map(i64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `granular-poly` layout.
    fn small() -> GrainLayout {
        let radius = [0.012, 0.02];
        GrainLayout {
            side: 0.1,
            grains: 10,
            radius,
            vertices: 12,
            gap: 0.004,
            seed: 1,
        }
    }

    /// The number of undirected edges.
    fn edges(g: &Polyhedron) -> usize {
        let mut e: Vec<_> = g
            .faces
            .iter()
            .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
            .collect();
        e.iter_mut().for_each(|e| *e = (e.0.min(e.1), e.0.max(e.1)));
        e.sort_unstable();
        e.dedup();
        e.len()
    }

    #[test]
    fn the_same_seed_gives_the_same_grains_and_another_seed_others() {
        let a = place_grains(&small()).expect("places");
        assert_eq!(a.len(), 10);
        assert_eq!(a, place_grains(&small()).expect("places"));
        let other = place_grains(&GrainLayout { seed: 2, ..small() }).expect("places");
        assert_ne!(a, other);
    }

    /// 6 V by the fan of tetrahedra from the centre.
    fn fan_volume6(g: &Polyhedron) -> f64 {
        let p = |i: usize| sub(g.vertices[i], g.centre);
        g.faces
            .iter()
            .map(|t| dot(p(t[0]), cross(p(t[1]), p(t[2]))))
            .sum()
    }

    #[test]
    fn every_grain_is_a_closed_outward_convex_polyhedron() {
        for (vertices, seed) in [(6, 3), (12, 1), (12, 2), (20, 4), (30, 5)] {
            let layout = GrainLayout {
                vertices,
                seed,
                ..small()
            };
            for g in place_grains(&layout).expect("places") {
                let (v, e, f, c, r) = (
                    g.vertices.len(),
                    edges(&g),
                    g.faces.len(),
                    g.centre,
                    g.radius,
                );
                assert_eq!(v, vertices, "every drawn point is a hull vertex");
                assert_eq!(v + f, e + 2, "Euler: V - E + F = 2");
                assert!(g.vertices.iter().all(|&p| g.contains(p)), "convex");
                let (volume, fan) = (g.volume(), fan_volume6(&g) / 6.0);
                assert!(
                    volume > 0.05 * r.powi(3) && volume < 4.2 * r.powi(3),
                    "{volume}"
                );
                assert!(
                    (volume - fan).abs() < 1e-9 * volume,
                    "{volume} vs fan {fan}"
                );
                let d: Vec<f64> = g.vertices.iter().map(|&q| norm(sub(q, c)) / r).collect();
                assert!(
                    d.iter().all(|d| (0.75 - 1e-12..=1.0 + 1e-12).contains(d)),
                    "{d:?}"
                );
                assert!(g.contains(c) && !g.contains([c[0] + 1.01 * r, c[1], c[2]]));
                let fold = smallest_fold(&g.vertices, &g.faces) / (4.0 * PI / v as f64).sqrt();
                assert!(fold > 0.5 * MIN_FOLD, "fold {fold}");
            }
        }
    }

    #[test]
    fn grains_keep_the_gap_between_them_and_to_the_cube() {
        for seed in 1..6 {
            let layout = GrainLayout { seed, ..small() };
            let grains = place_grains(&layout).expect("places");
            let (gap, side, eps) = (layout.gap, layout.side, selection_eps(&layout));
            for (i, a) in grains.iter().enumerate() {
                assert!((layout.radius[0]..=layout.radius[1]).contains(&a.radius));
                let inner = a.radius + gap..=side - a.radius - gap;
                assert!(a.centre.iter().all(|x| inner.contains(x)), "{:?}", a.centre);
                for b in &grains[i + 1..] {
                    assert!(norm(sub(a.centre, b.centre)) >= a.radius + b.radius + gap);
                    assert!(!box_holds(a, b, eps) && !box_holds(b, a, eps));
                }
            }
        }
    }

    #[test]
    fn invalid_parameters_are_refused_with_a_reason() {
        type Change = fn(&mut GrainLayout);
        let cases: [(Change, &str); 8] = [
            (|l| l.side = 0.0, "side"),
            (|l| l.side = f64::NAN, "side"),
            (|l| l.radius = [0.02, 0.012], "radii"),
            (|l| l.radius = [0.0, 0.012], "radii"),
            (|l| l.vertices = 5, "vertices"),
            (|l| l.grains = 0, "grain"),
            (|l| l.gap = -0.001, "gap"),
            (|l| l.radius = [0.02, 0.05], "does not fit"),
        ];
        for (change, word) in cases {
            let mut layout = small();
            change(&mut layout);
            let err = place_grains(&layout).expect_err("invalid");
            assert!(err.contains(word), "{err}");
        }
    }

    #[test]
    fn an_impossible_layout_says_how_many_grains_were_placed() {
        let layout = GrainLayout {
            side: 1.0,
            grains: 100,
            radius: [0.3, 0.3],
            gap: 0.01,
            ..small()
        };
        let err = place_grains(&layout).expect_err("impossible");
        assert!(
            err.contains("placed only") && err.contains("of 100 grains"),
            "{err}"
        );
        assert!(err.contains("larger cube"), "{err}");
    }

    #[test]
    fn the_script_builds_every_grain_once_and_names_every_group() {
        let grains = place_grains(&small()).expect("places");
        let geo = geo_script(&small(), &grains, 0.0055);
        assert!(geo.starts_with("// Generated by Lopin") && geo.contains("seed = 1"));
        assert!(geo.contains("SetFactory(\"OpenCASCADE\");\n"));
        assert!(geo.contains("Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};"));
        assert!(geo.contains("BooleanFragments{ Volume{1}; Delete; }{ Volume{2:11}; Delete; }"));
        let count = |prefix: &str| geo.lines().filter(|l| l.starts_with(prefix)).count();
        let total = |f: fn(&Polyhedron) -> usize| grains.iter().map(f).sum::<usize>();
        assert_eq!(count("Point("), total(|g| g.vertices.len()));
        assert_eq!(count("Line("), total(edges), "one line per edge");
        assert_eq!(count("Plane Surface("), total(|g| g.faces.len()));
        assert_eq!(count("Volume("), 10);
        for k in 1..=10 {
            let group = format!("Physical Volume(\"grain{k}\", {}) = grain{k}();", k + 1);
            assert!(geo.contains(&group), "{group}");
        }
        for name in ["matrix", "bottom", "top", "x-", "x+", "y-", "y+"] {
            assert!(geo.contains(&format!("(\"{name}\", ")), "{name}");
        }
    }
}
