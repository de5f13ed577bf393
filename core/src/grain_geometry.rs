//! Polyhedral grains (issue 17): the seed paper's granular material, N seeded, non-overlapping
//! random convex polyhedral grains inside a cube of matrix ([`place_grains`]), and the Gmsh
//! `.geo` script that builds the cube and the grains, fragments them so that every grain shares
//! conforming surfaces with the matrix, and names the physical groups ([`geo_script`]).
//!
//! A grain is the convex hull of points drawn on a sphere with a minimum angular separation (no
//! sliver faces), scaled by a random factor in [0.75, 1] along each axis and randomly rotated:
//! its circumscribed sphere is the drawn one. Grains are placed by random sequential addition:
//! a sphere closer than `gap` to an earlier one or to the cube's faces is redrawn.
//!
//! Physical groups of the script: volumes `matrix` (tag 1) and `grain1` … `grainN` (tags 2 …
//! N + 1, in placement order); surfaces `x-`, `x+`, `y-`, `y+`, `bottom` (z = 0) and `top`
//! (z = L) (tags 1 … 6).

use std::collections::HashMap;
use std::f64::consts::PI;

use crate::mesh::{cross, dot, norm, sub, Vec3};
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
    /// Vertices (every one is a corner of the hull).
    pub vertices: Vec<Vec3>,
    /// Triangular faces, vertex indices counter-clockwise seen from outside.
    pub faces: Vec<[usize; 3]>,
}

impl Polyhedron {
    /// Volume by the divergence theorem, V = Σ_faces a · (b × c) / 6 over the faces (a, b, c);
    /// positive for outward-oriented faces.
    pub fn volume(&self) -> f64 {
        let v = &self.vertices;
        self.faces
            .iter()
            .map(|f| triple(v[f[0]], v[f[1]], v[f[2]]))
            .sum::<f64>()
            / 6.0
    }

    /// Lower and upper corners of the axis-aligned bounding box.
    pub fn bounding_box(&self) -> (Vec3, Vec3) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.vertices {
            for a in 0..3 {
                lo[a] = lo[a].min(p[a]);
                hi[a] = hi[a].max(p[a]);
            }
        }
        (lo, hi)
    }

    /// Whether `p` lies inside or on the boundary (within 10⁻⁹ of the radius of every face's
    /// plane).
    pub fn contains(&self, p: Vec3) -> bool {
        let tol = 1e-9 * self.radius;
        self.faces.iter().all(|f| {
            let a = self.vertices[f[0]];
            let n = cross(sub(self.vertices[f[1]], a), sub(self.vertices[f[2]], a));
            dot(n, sub(p, a)) <= tol * norm(n)
        })
    }
}

/// Placement tries per grain before [`place_grains`] gives up.
const TRIES_PER_GRAIN: usize = 10_000;

/// Places the grains: Err(reason) when N grains cannot be placed after a bounded number of tries
/// (10 000 × N; the reason says how many were placed), or when the parameters are invalid
/// (non-positive side, radius not positive or radius[0] > radius[1], vertices < 6, no grains,
/// gap not positive, or 2 (radius[1] + gap) > side).
///
/// Each try draws a radius r uniformly in `radius` and a centre uniformly in [r + gap, L − r −
/// gap]³, and is rejected if its sphere comes within `gap` of an earlier grain's, or if one
/// grain's bounding box would hold another one entirely (the script selects grains by bounding
/// box).
pub fn place_grains(layout: &GrainLayout) -> Result<Vec<Polyhedron>, String> {
    let GrainLayout {
        side,
        grains: n,
        radius: [r0, r1],
        vertices,
        gap,
        seed,
    } = *layout;
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(side) {
        return Err(format!("the side of the cube must be positive, got {side}"));
    }
    if !positive(r0) || !positive(r1) || r0 > r1 {
        return Err(format!(
            "the grain radii must be positive and in increasing order, got [{r0}, {r1}]"
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
            "a grain of radius {r1} with gap {gap} does not fit in a cube of side {side}"
        ));
    }
    let eps = selection_eps(layout);
    let mut rng = SplitMix64(seed);
    let mut grains: Vec<Polyhedron> = Vec::with_capacity(n);
    let mut tries = 0;
    while grains.len() < n && tries < TRIES_PER_GRAIN * n {
        tries += 1;
        let r = r0 + (r1 - r0) * rng.unit();
        let lo = r + gap;
        let centre = [0; 3].map(|_| lo + (side - 2.0 * lo) * rng.unit());
        if grains
            .iter()
            .any(|g| norm(sub(g.centre, centre)) < g.radius + r + gap)
        {
            continue;
        }
        let Some(grain) = random_polyhedron(&mut rng, centre, r, vertices) else {
            continue;
        };
        if grains
            .iter()
            .all(|g| !box_holds(g, &grain, eps) && !box_holds(&grain, g, eps))
        {
            grains.push(grain);
        }
    }
    if grains.len() < n {
        return Err(format!(
            "placed only {} of {n} grains in {tries} tries: use fewer or smaller grains, a \
             smaller gap or a larger cube",
            grains.len()
        ));
    }
    Ok(grains)
}

/// The gmsh .geo script (OpenCASCADE kernel) of the sample, meshed with tetrahedra of size about
/// `mesh_size`: the cube is volume 1, grain k volume k + 1 built from points, lines (one per
/// shared edge), curve loops, plane surfaces and a surface loop (tags from 1000 up, clear of
/// the box's), then all are fragmented and the physical groups selected by bounding box.
pub fn geo_script(layout: &GrainLayout, grains: &[Polyhedron], mesh_size: f64) -> String {
    let l = layout.side;
    let mut s = String::new();
    let mut w = |line: String| {
        s.push_str(&line);
        s.push('\n');
    };
    w(format!(
        "// Generated by Lopin (grain_geometry): side = {l}, grains = {}, radius = [{}, {}], \
         vertices = {}, gap = {}, seed = {}, mesh_size = {mesh_size}",
        layout.grains, layout.radius[0], layout.radius[1], layout.vertices, layout.gap, layout.seed
    ));
    w("SetFactory(\"OpenCASCADE\");".into());
    w(format!("Mesh.CharacteristicLengthMax = {mesh_size};"));
    w(format!(
        "Mesh.CharacteristicLengthMin = {};",
        mesh_size / 4.0
    ));
    w("Mesh.ElementOrder = 1;\nMesh.Algorithm3D = 1;\nMesh.Optimize = 1;".into());
    w(format!("Box(1) = {{0, 0, 0, {l}, {l}, {l}}};"));
    let (mut point, mut line, mut surface) = (1000usize, 1000i64, 1000i64);
    for (k, g) in grains.iter().enumerate() {
        w(format!("// grain {}", k + 1));
        let p0 = point;
        for v in &g.vertices {
            w(format!(
                "Point({point}) = {{{}, {}, {}}};",
                v[0], v[1], v[2]
            ));
            point += 1;
        }
        let mut lines: HashMap<(usize, usize), i64> = HashMap::new();
        let mut surfaces = Vec::with_capacity(g.faces.len());
        for f in &g.faces {
            let mut loop_ = Vec::with_capacity(3);
            for (a, b) in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
                if let Some(&t) = lines.get(&(b, a)) {
                    loop_.push(-t);
                } else {
                    w(format!("Line({line}) = {{{}, {}}};", p0 + a, p0 + b));
                    lines.insert((a, b), line);
                    loop_.push(line);
                    line += 1;
                }
            }
            w(format!(
                "ll = newll; Curve Loop(ll) = {{{}}};",
                join(&loop_)
            ));
            w(format!("Plane Surface({surface}) = {{ll}};"));
            surfaces.push(surface);
            surface += 1;
        }
        w(format!(
            "sl = newsl; Surface Loop(sl) = {{{}}};",
            join(&surfaces)
        ));
        w(format!("Volume({}) = {{sl}};", k + 2));
    }
    if !grains.is_empty() {
        w(format!(
            "BooleanFragments{{ Volume{{1}}; Delete; }}{{ Volume{{2:{}}}; Delete; }}",
            grains.len() + 1
        ));
    }
    let eps = selection_eps(layout);
    w(format!("eps = {eps};"));
    let in_box = |kind: &str, lo: Vec3, hi: Vec3| {
        format!(
            "{kind} In BoundingBox{{{} - eps, {} - eps, {} - eps, {} + eps, {} + eps, {} + eps}}",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        )
    };
    w(format!(
        "matrix() = {};",
        in_box("Volume", [0.0; 3], [l; 3])
    ));
    for (k, g) in grains.iter().enumerate() {
        let (lo, hi) = g.bounding_box();
        w(format!("grain{}() = {};", k + 1, in_box("Volume", lo, hi)));
        w(format!(
            "Physical Volume(\"grain{}\", {}) = grain{}();",
            k + 1,
            k + 2,
            k + 1
        ));
        w(format!("matrix() -= grain{}();", k + 1));
    }
    w("Physical Volume(\"matrix\", 1) = matrix();".into());
    for (t, (name, axis, at)) in [
        ("x-", 0, 0.0),
        ("x+", 0, l),
        ("y-", 1, 0.0),
        ("y+", 1, l),
        ("bottom", 2, 0.0),
        ("top", 2, l),
    ]
    .into_iter()
    .enumerate()
    {
        let (mut lo, mut hi) = ([0.0; 3], [l; 3]);
        (lo[axis], hi[axis]) = (at, at);
        w(format!(
            "Physical Surface(\"{name}\", {}) = {};",
            t + 1,
            in_box("Surface", lo, hi)
        ));
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
    b.vertices
        .iter()
        .all(|p| (0..3).all(|i| p[i] >= lo[i] - eps && p[i] <= hi[i] + eps))
}

/// Attempts at a polyhedron with folds wide enough before a placement try fails.
const SHAPE_ATTEMPTS: i32 = 64;

/// Smallest fold (angle between the normals of two adjacent faces) asked of a grain, as a
/// fraction of the mean spacing √(4π/n) of its n points (8° for 12 points): two nearly coplanar
/// faces would leave a flat tetrahedron across their common edge.
const MIN_FOLD: f64 = 0.14;

/// A random convex polyhedron in the sphere (`centre`, `radius`) with `n` vertices, its folds at
/// least [`MIN_FOLD`] √(4π/n) (a bound relaxed by 20 % after every 16 failed attempts); None (a
/// failed try) after [`SHAPE_ATTEMPTS`] failed attempts.
fn random_polyhedron(
    rng: &mut SplitMix64,
    centre: Vec3,
    radius: f64,
    n: usize,
) -> Option<Polyhedron> {
    let spacing = (4.0 * PI / n as f64).sqrt();
    for attempt in 0..SHAPE_ATTEMPTS {
        let points = random_points(rng, centre, radius, n, spacing);
        let Some(faces) = convex_hull(&points, 1e-7 * radius) else {
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
        return Some(Polyhedron {
            centre,
            radius,
            vertices,
            faces,
        });
    }
    None
}

/// `n` points on the sphere (`centre`, `radius`) in directions at least 0.7 `spacing` apart (a
/// bound relaxed by 10 % after every 1000 rejections, so that no edge is tiny), scaled by a
/// random factor in [0.75, 1] along each axis, then turned by a uniform random rotation.
fn random_points(
    rng: &mut SplitMix64,
    centre: Vec3,
    radius: f64,
    n: usize,
    spacing: f64,
) -> Vec<Vec3> {
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
    let scale = [0; 3].map(|_| 0.75 + 0.25 * rng.unit());
    // a uniform random unit quaternion (w, q) (Shoemake 1992); v ↦ v + w t + q × t, t = 2 q × v
    let (u1, u2, u3) = (rng.unit(), 2.0 * PI * rng.unit(), 2.0 * PI * rng.unit());
    let w = (1.0 - u1).sqrt() * u2.sin();
    let q = [
        (1.0 - u1).sqrt() * u2.cos(),
        u1.sqrt() * u3.sin(),
        u1.sqrt() * u3.cos(),
    ];
    dirs.iter()
        .map(|d| {
            let v = [0, 1, 2].map(|a| radius * scale[a] * d[a]);
            let t = cross(q, v).map(|c| 2.0 * c);
            let qt = cross(q, t);
            [0, 1, 2].map(|a| centre[a] + v[a] + w * t[a] + qt[a])
        })
        .collect()
}

/// The smallest angle between the normals of two faces sharing an edge.
fn smallest_fold(p: &[Vec3], faces: &[[usize; 3]]) -> f64 {
    let normal = |f: &[usize; 3]| {
        let n = cross(sub(p[f[1]], p[f[0]]), sub(p[f[2]], p[f[0]]));
        n.map(|c| c / norm(n))
    };
    let mut by_edge = HashMap::new();
    for f in faces {
        for e in [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])] {
            by_edge.insert(e, normal(f));
        }
    }
    let mut smallest = PI;
    for (&(a, b), &n) in &by_edge {
        if let Some(&m) = by_edge.get(&(b, a)) {
            smallest = smallest.min(dot(n, m).clamp(-1.0, 1.0).acos());
        }
    }
    smallest
}

/// The convex hull of points in general position by brute force (O(n⁴)): every triple with all
/// other points strictly on one side of its plane is a face, oriented outward. None when a
/// fourth point lies within `tol` of a face's plane, or when the faces do not close into a
/// consistently oriented surface.
fn convex_hull(p: &[Vec3], tol: f64) -> Option<Vec<[usize; 3]>> {
    let n = p.len();
    let mut faces = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let nrm = cross(sub(p[j], p[i]), sub(p[k], p[i]));
                let len = norm(nrm);
                let (mut above, mut below, mut on) = (false, false, false);
                for (m, &q) in p.iter().enumerate() {
                    if m == i || m == j || m == k {
                        continue;
                    }
                    let d = dot(nrm, sub(q, p[i]));
                    above |= d > tol * len;
                    below |= d < -tol * len;
                    on |= d.abs() <= tol * len;
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
    // a closed, consistently oriented surface: each directed edge once, with its reverse
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

fn join(tags: &[i64]) -> String {
    tags.iter()
        .map(|t| t.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// a · (b × c).
fn triple(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    dot(a, cross(b, c))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The `granular-poly` layout.
    fn small() -> GrainLayout {
        GrainLayout {
            side: 0.1,
            grains: 10,
            radius: [0.012, 0.02],
            vertices: 12,
            gap: 0.004,
            seed: 1,
        }
    }

    /// Undirected edges of a polyhedron.
    fn edges(g: &Polyhedron) -> usize {
        let mut e: Vec<(usize, usize)> = g
            .faces
            .iter()
            .flat_map(|f| [(f[0], f[1]), (f[1], f[2]), (f[2], f[0])])
            .map(|(a, b)| (a.min(b), a.max(b)))
            .collect();
        e.sort_unstable();
        e.dedup();
        e.len()
    }

    #[test]
    fn the_same_seed_gives_the_same_grains_and_another_seed_others() {
        let a = place_grains(&small()).expect("places");
        let b = place_grains(&small()).expect("places");
        let c = place_grains(&GrainLayout { seed: 2, ..small() }).expect("places");
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(a.len(), 10);
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
                let (v, e, f) = (g.vertices.len(), edges(&g), g.faces.len());
                assert_eq!(v, vertices, "every drawn point is a hull vertex");
                assert_eq!(v + f, e + 2, "Euler: V - E + F = 2");
                assert!(g.vertices.iter().all(|&p| g.contains(p)), "convex");
                assert!(g.contains(g.centre));
                let c = g.centre;
                let fan: f64 = g
                    .faces
                    .iter()
                    .map(|t| {
                        triple(
                            sub(g.vertices[t[0]], c),
                            sub(g.vertices[t[1]], c),
                            sub(g.vertices[t[2]], c),
                        )
                    })
                    .sum::<f64>()
                    / 6.0;
                let volume = g.volume();
                assert!(volume > 0.0, "outward faces");
                assert!(
                    (volume - fan).abs() < 1e-9 * volume,
                    "{volume} vs fan {fan}"
                );
                // a scaled sphere: the volume lies between those of the inscribed shapes
                let ball = 4.0 / 3.0 * PI * g.radius.powi(3);
                assert!(
                    volume < ball && volume > 0.05 * ball,
                    "volume {volume}, ball {ball}"
                );
                for p in &g.vertices {
                    let d = norm(sub(*p, c));
                    assert!(d <= g.radius * (1.0 + 1e-12) && d >= 0.75 * g.radius * (1.0 - 1e-12));
                }
                let outside = [c[0] + 1.01 * g.radius, c[1], c[2]];
                assert!(!g.contains(outside));
            }
        }
    }

    #[test]
    fn grains_keep_the_gap_between_them_and_to_the_cube() {
        for seed in 1..6 {
            let layout = GrainLayout { seed, ..small() };
            let grains = place_grains(&layout).expect("places");
            let eps = selection_eps(&layout);
            for (i, a) in grains.iter().enumerate() {
                assert!((layout.radius[0]..=layout.radius[1]).contains(&a.radius));
                for x in a.centre {
                    assert!(x >= a.radius + layout.gap && x <= layout.side - a.radius - layout.gap);
                }
                for b in &grains[i + 1..] {
                    assert!(norm(sub(a.centre, b.centre)) >= a.radius + b.radius + layout.gap);
                    assert!(!box_holds(a, b, eps) && !box_holds(b, a, eps));
                }
            }
        }
    }

    #[test]
    fn invalid_parameters_are_refused_with_a_reason() {
        let cases = [
            (
                GrainLayout {
                    side: 0.0,
                    ..small()
                },
                "side",
            ),
            (
                GrainLayout {
                    side: f64::NAN,
                    ..small()
                },
                "side",
            ),
            (
                GrainLayout {
                    radius: [0.02, 0.012],
                    ..small()
                },
                "radii",
            ),
            (
                GrainLayout {
                    radius: [0.0, 0.012],
                    ..small()
                },
                "radii",
            ),
            (
                GrainLayout {
                    vertices: 5,
                    ..small()
                },
                "vertices",
            ),
            (
                GrainLayout {
                    grains: 0,
                    ..small()
                },
                "grain",
            ),
            (
                GrainLayout {
                    gap: -0.001,
                    ..small()
                },
                "gap",
            ),
            (
                GrainLayout {
                    radius: [0.02, 0.05],
                    ..small()
                },
                "does not fit",
            ),
        ];
        for (layout, word) in cases {
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
            vertices: 12,
            gap: 0.01,
            seed: 1,
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
        let layout = small();
        let grains = place_grains(&layout).expect("places");
        let geo = geo_script(&layout, &grains, 0.01);
        assert!(geo.starts_with("// Generated by Lopin") && geo.contains("seed = 1"));
        assert!(geo.contains("SetFactory(\"OpenCASCADE\");\n"));
        assert!(geo.contains("Box(1) = {0, 0, 0, 0.1, 0.1, 0.1};"));
        assert!(geo.contains("BooleanFragments{ Volume{1}; Delete; }{ Volume{2:11}; Delete; }"));
        let count = |prefix: &str| geo.lines().filter(|l| l.starts_with(prefix)).count();
        assert_eq!(
            count("Point("),
            grains.iter().map(|g| g.vertices.len()).sum::<usize>()
        );
        assert_eq!(
            count("Line("),
            grains.iter().map(edges).sum::<usize>(),
            "one line per edge"
        );
        assert_eq!(
            count("Plane Surface("),
            grains.iter().map(|g| g.faces.len()).sum::<usize>()
        );
        assert_eq!(count("Volume("), 10);
        for k in 1..=10 {
            assert!(geo.contains(&format!(
                "Physical Volume(\"grain{k}\", {}) = grain{k}();",
                k + 1
            )));
        }
        for name in [
            "\"matrix\"",
            "\"bottom\"",
            "\"top\"",
            "\"x-\"",
            "\"x+\"",
            "\"y-\"",
            "\"y+\"",
        ] {
            assert!(geo.contains(name), "{name}");
        }
    }
}
