//! 1D bars as 3D scenes: a chain of box bodies one hexahedron across (section h × h, ν = 0),
//! each body one substructure, perfect interfaces between touching bodies unless a contact is
//! asked for. Node x-velocities are read back per 1D station for comparison with [`crate::mono1d`].

use lopin_core::post;
use lopin_core::scene::spec::{
    BodySpec, BoundarySpec, ComponentSpec, InterfaceKind, InterfaceSpec, MaterialSpec, SceneSpec,
    SolverSpec,
};
use lopin_core::time::time_function::{Ramp, TimeGrid};
use lopin_core::{Solution, Solver};

/// One body of the chain.
#[derive(Debug, Clone)]
pub struct Segment {
    /// Left end.
    pub x0: f64,
    /// Number of elements.
    pub elements: usize,
    /// Young's modulus (ρ = 1 unless `density` differs).
    pub young: f64,
    /// Density.
    pub density: f64,
    /// Initial velocity along x.
    pub velocity: f64,
}

/// A 1D bar problem.
#[derive(Debug, Clone)]
pub struct Bar1d {
    /// Element length (also the section size).
    pub h: f64,
    /// Bodies, left to right.
    pub segments: Vec<Segment>,
    /// Time grid.
    pub time: TimeGrid,
    /// Imposed x-velocity at x = x0 of the first segment: (V0, ramp duration, ramp profile).
    pub push: Option<(f64, f64, Ramp)>,
    /// Frictionless contacts between segment i and i + 1 (search distance).
    pub contacts: Vec<(usize, f64)>,
}

impl Bar1d {
    /// Uniform bar [0, L] of E = ρ = 1 cut into `counts` elements per substructure.
    pub fn uniform(counts: &[usize], h: f64, time: TimeGrid, push: (f64, f64, Ramp)) -> Self {
        let mut x0 = 0.0;
        let segments = counts
            .iter()
            .map(|&n| {
                let s = Segment {
                    x0,
                    elements: n,
                    young: 1.0,
                    density: 1.0,
                    velocity: 0.0,
                };
                x0 += n as f64 * h;
                s
            })
            .collect();
        Self {
            h,
            segments,
            time,
            push: Some(push),
            contacts: vec![],
        }
    }

    /// The scene.
    pub fn spec(&self) -> SceneSpec {
        let mut materials: Vec<MaterialSpec> = Vec::new();
        let mut bodies = Vec::new();
        for (i, s) in self.segments.iter().enumerate() {
            let name = format!("E{}rho{}", s.young, s.density);
            if !materials.iter().any(|m| m.name == name) {
                materials.push(MaterialSpec {
                    name: name.clone(),
                    young: s.young,
                    poisson: 0.0,
                    density: s.density,
                    ..MaterialSpec::default()
                });
            }
            bodies.push(BodySpec {
                name: format!("s{i}"),
                material: name,
                min: [s.x0, 0.0, 0.0],
                max: [s.x0 + s.elements as f64 * self.h, self.h, self.h],
                divisions: [s.elements, 1, 1],
                split: [1, 1, 1],
                velocity: [s.velocity, 0.0, 0.0],
                elements: None,
                substructures: None,
            });
        }
        let interfaces = self
            .contacts
            .iter()
            .map(|&(i, search)| InterfaceSpec {
                bodies: [format!("s{i}"), format!("s{}", i + 1)],
                kind: InterfaceKind::Contact,
                friction: Some(0.0),
                gap: None,
                search: Some(search),
            })
            .collect();
        let boundaries = self
            .push
            .map(|(v, t, ramp)| BoundarySpec {
                body: "s0".into(),
                face: "x-".into(),
                surface: None,
                clamped: false,
                preload: false,
                x: Some(ComponentSpec {
                    velocity: Some(v),
                    traction: None,
                    ramp,
                    ramp_time: t,
                    ..ComponentSpec::default()
                }),
                y: None,
                z: None,
                normal: None,
            })
            .into_iter()
            .collect();
        SceneSpec {
            name: "bar1d".into(),
            description: String::new(),
            refine_axes: "x".into(),
            split_axes: "x".into(),
            time: self.time,
            solver: SolverSpec::default(),
            materials,
            granular: None,
            bodies,
            mesh_bodies: Vec::new(),
            granular_poly: None,
            interfaces,
            boundaries,
            zones: Vec::new(),
        }
    }

    /// x-velocity per 1D station (global node index along the chain, segments concatenated with
    /// shared end nodes counted per segment: station = segment's first node index + local index),
    /// `[m][chain node]`, read from the LATIN solution. Checks that all four nodes of a section
    /// and both copies of an interface node agree.
    pub fn stations(&self, solver: &Solver, sol: &Solution) -> Vec<Vec<f64>> {
        let p = solver.problem();
        let n = p.time.steps;
        let total: usize = self.segments.iter().map(|s| s.elements + 1).sum();
        let mut out = vec![vec![f64::NAN; total]; n + 1];
        let mut first = 0;
        for (i, seg) in self.segments.iter().enumerate() {
            let sub = &p.subs[i];
            post::replay(solver, sol, i, n, &mut |m, st, _, _| {
                for (node, x) in sub.mesh.nodes.iter().enumerate() {
                    let local = ((x[0] - seg.x0) / self.h).round() as usize;
                    let v = st.v[3 * node];
                    let slot = &mut out[m][first + local];
                    if slot.is_nan() {
                        *slot = v;
                    } else {
                        assert!(
                            (*slot - v).abs() <= 1e-9 * (1.0 + v.abs()),
                            "section not uniform"
                        );
                    }
                }
            });
            first += seg.elements + 1;
        }
        out
    }
}
