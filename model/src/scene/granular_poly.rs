//! The seed paper's granular material with polyhedral grains (`[granular_poly]`): N
//! seeded, non-overlapping random convex polyhedra in a cube of matrix
//! ([`crate::mesh::grain_geometry`]), fragmented and meshed with tetrahedra by gmsh (cached by the
//! generated script, [`crate::mesh::gmsh`]), the matrix cut into substructures by the graph
//! partitioner. The table expands into mesh bodies (`matrix`, `grain1` … `grainN`), a contact
//! interface with Coulomb friction between every grain and the matrix (zero initial gap: the
//! fragmented surfaces are conforming), and the loading of SCENES.md `granular`: the top face
//! pushed along −z at V₀ with a (1 − cos) ramp, the bottom face clamped, the lateral faces free.

use crate::error::{LopinError, Result};
use crate::mesh::grain_geometry::{place_grains, GrainLayout, Polyhedron};
use crate::scene::spec::{
    BoundarySpec, ComponentSpec, InterfaceKind, InterfaceSpec, MeshBodySpec, SceneSpec,
};
pub use crate::scene::tables::GranularPolySpec;

/// Most hull points per grain (the hull is found by brute force, O(n⁴), and each grain may take
/// 64 shape attempts per placement try).
const MAX_VERTICES: usize = 24;

/// Most grains in a sample: gmsh fragments the cube with every grain at once, a cost that grows
/// faster than the grain count.
pub const MAX_GRAINS: usize = 500;

/// Physical range of the cube side (m): a laboratory specimen to a large structure.
const SIDE_RANGE: (f64, f64) = (1e-4, 1e2);

impl GranularPolySpec {
    /// The grain layout the table describes.
    pub fn layout(&self) -> GrainLayout {
        GrainLayout {
            side: self.side,
            grains: self.grains,
            radius: self.radius,
            vertices: self.vertices,
            gap: self.gap,
            seed: self.seed,
        }
    }

    /// The gmsh script of the sample made of `grains` (placed by [`placed_grains`]).
    pub fn script(&self, grains: &[Polyhedron]) -> String {
        crate::mesh::grain_geometry::geo_script(&self.layout(), grains, self.mesh_size)
    }
}

/// Checks the `[granular_poly]` table of `spec` without meshing (errors name `source`, the
/// field and the reason): no listed bodies, interfaces or boundaries, the materials, positive
/// sizes, and a layout whose grains can be placed.
pub fn validate(spec: &SceneSpec, source: &str) -> Result<()> {
    placed_grains(spec, source).map(|_| ())
}

/// The grains of the `[granular_poly]` table of `spec`, placed once its table is checked as
/// [`validate`] says (none without a table).
pub fn placed_grains(spec: &SceneSpec, source: &str) -> Result<Vec<Polyhedron>> {
    let Some(g) = &spec.granular_poly else {
        return Ok(Vec::new());
    };
    check_scene_entries(spec, g, source)?;
    check_sizes(g, source)?;
    check_resolution(g, source)?;
    check_load_and_grains(spec, g, source)?;
    check_packing(g, source)?;
    // counted (from the mesh size) and admitted before any grain is drawn or meshed
    crate::scene::admission::admit(
        spec,
        source,
        crate::scene::admission::SolveShape::smallest(),
    )?;
    match place_grains(&g.layout()) {
        Ok(grains) => Ok(grains),
        Err(reason) => Err(table_error(source, "grains", reason)),
    }
}

/// The error for field `field` of the `[granular_poly]` table of `source`.
fn table_error(source: &str, field: &str, reason: String) -> LopinError {
    LopinError::scene(source, format!("granular_poly.{field}"), reason)
}

/// Checks what the table asks of the rest of the scene: no listed bodies, mesh bodies,
/// interfaces or boundaries, no `[granular]` table beside it, and its matrix and grain
/// materials defined.
fn check_scene_entries(spec: &SceneSpec, g: &GranularPolySpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(table_error(source, field, reason));
    for (len, field) in [
        (spec.bodies.len(), "body"),
        (spec.mesh_bodies.len(), "mesh_body"),
        (spec.interfaces.len(), "interface"),
        (spec.boundaries.len(), "boundary"),
    ] {
        if len > 0 {
            return Err(LopinError::scene(
                source,
                field,
                format!(
                    "a scene with a [granular_poly] table generates its bodies, interfaces and \
                     boundaries: remove the {len} [[{field}]] entr{}",
                    if len == 1 { "y" } else { "ies" }
                ),
            ));
        }
    }
    if spec.granular.is_some() {
        return err(
            "side",
            "a scene has either a [granular] or a [granular_poly] table, not both".into(),
        );
    }
    for (field, name) in [("matrix", &g.matrix), ("grain", &g.grain)] {
        if !spec.materials.iter().any(|m| &m.name == name) {
            return err(field, format!("no material named `{name}`"));
        }
    }
    Ok(())
}

/// Checks the sizes of the sample: the cube side within [`SIDE_RANGE`], the smallest grain
/// radius and the gap not below their fractions of the side, at most [`MAX_GRAINS`] grains,
/// and a positive mesh size smaller than the side.
fn check_sizes(g: &GranularPolySpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(table_error(source, field, reason));
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !(g.side.is_finite() && (SIDE_RANGE.0..=SIDE_RANGE.1).contains(&g.side)) {
        return err(
            "side",
            format!(
                "the cube side lies in [{:e}, {:e}] m, got {:?}",
                SIDE_RANGE.0, SIDE_RANGE.1, g.side
            ),
        );
    }
    let finest = 1e-3 * g.side;
    if !(g.radius[0].is_finite() && g.radius[0] >= finest) {
        return err(
            "radius",
            format!(
                "a grain's radius is at least 1e-3 of the cube side ({finest:e} m), got {:?}",
                g.radius[0]
            ),
        );
    }
    if !(g.gap.is_finite() && g.gap >= 1e-2 * finest) {
        return err(
            "gap",
            format!(
                "the gap between grains is at least 1e-5 of the cube side ({:e} m), got {:?}",
                1e-2 * finest,
                g.gap
            ),
        );
    }
    if g.grains > MAX_GRAINS {
        return err(
            "grains",
            format!(
                "at most {MAX_GRAINS} polyhedral grains (gmsh fragments the cube with all of \
                 them at once), got {}; for more, use a [granular] table of hexahedral cells",
                g.grains
            ),
        );
    }
    if !positive(g.mesh_size) || g.mesh_size >= g.side {
        return err(
            "mesh_size",
            format!(
                "must be positive and smaller than the cube side {}, got {}",
                g.side, g.mesh_size
            ),
        );
    }
    Ok(())
}

/// Checks that the mesh size resolves the sample: the smallest grain spans at least half an
/// element and the gap between grains at least a quarter of one.
fn check_resolution(g: &GranularPolySpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(table_error(source, field, reason));
    // a grain narrower than one element, or a matrix sliver thinner than a quarter of one, is not
    // resolved at `mesh_size`: gmsh would refine around it far beyond the mesh admitted here
    if g.radius[0] < 0.5 * g.mesh_size {
        return err(
            "radius",
            format!(
                "the smallest grain radius {:?} m is below half the mesh size {:?} m: a grain \
                 must span at least one element (raise radius[0] or lower mesh_size)",
                g.radius[0], g.mesh_size
            ),
        );
    }
    if g.gap < 0.25 * g.mesh_size {
        return err(
            "gap",
            format!(
                "the gap {:?} m is below a quarter of the mesh size {:?} m: the matrix between \
                 two grains must hold a quarter of an element (raise gap or lower mesh_size)",
                g.gap, g.mesh_size
            ),
        );
    }
    Ok(())
}

/// Checks the load and the grain shapes: a valid friction coefficient, a ramp that fits the
/// run, a finite velocity, at least one matrix substructure and at most [`MAX_VERTICES`] hull
/// points per grain.
fn check_load_and_grains(spec: &SceneSpec, g: &GranularPolySpec, source: &str) -> Result<()> {
    let err = |field: &str, reason: String| Err(table_error(source, field, reason));
    if let Err(reason) = crate::scene::validate::check_friction(g.friction) {
        return err("friction", reason);
    }
    if let Err(reason) = crate::scene::granular::check_ramp_steps(g.ramp_steps, spec.time.steps) {
        return err("ramp_steps", reason);
    }
    if !g.velocity.is_finite() {
        return err("velocity", format!("must be finite, got {}", g.velocity));
    }
    if g.matrix_substructures == 0 {
        return err("matrix_substructures", "must be at least 1".into());
    }
    if g.vertices > MAX_VERTICES {
        return err(
            "vertices",
            format!(
                "at most {MAX_VERTICES} hull points per grain, got {}",
                g.vertices
            ),
        );
    }
    Ok(())
}

/// Checks that the grains can be packed at all: the spheres of the smallest grains, each with
/// half the gap around it, fill no more than random close packing (64 %) of the cube.
fn check_packing(g: &GranularPolySpec, source: &str) -> Result<()> {
    // the spheres of the smallest grains, each with half the gap around it, cannot fill more
    // than random close packing (64 %) of the cube: refused before any try
    let ball = 4.0 / 3.0 * std::f64::consts::PI * (g.radius[0] + 0.5 * g.gap).powi(3);
    let most = (0.64 * g.side.powi(3) / ball).floor();
    if ball.is_finite() && ball > 0.0 && g.grains as f64 > most {
        return Err(table_error(
            source,
            "grains",
            format!(
                "{} grains of radius at least {} with gap {} cannot fit in a cube of side {} \
                 (at most about {most})",
                g.grains, g.radius[0], g.gap, g.side
            ),
        ));
    }
    Ok(())
}

/// Expands the `[granular_poly]` table into the scene it describes: meshes the sample with gmsh
/// (or takes it from the cache) and lists the mesh bodies, contacts and boundaries.
pub fn expand(spec: &SceneSpec, source: &str) -> Result<SceneSpec> {
    if spec.granular_poly.is_none() {
        return Ok(spec.clone());
    }
    expand_placed(spec, source, &placed_grains(spec, source)?)
}

/// [`expand`] with the grains already placed ([`placed_grains`]).
pub fn expand_placed(spec: &SceneSpec, source: &str, grains: &[Polyhedron]) -> Result<SceneSpec> {
    let Some(g) = &spec.granular_poly else {
        return Ok(spec.clone());
    };
    let mesh = mesh_file(&g.script(grains), &spec.name)
        .map_err(|reason| LopinError::scene(source, "granular_poly", reason))?;
    let body = |name: String, material: &str, substructures: usize| MeshBodySpec {
        name,
        material: material.to_string(),
        mesh: mesh.clone(),
        volume: None,
        velocity: [0.0; 3],
        substructures: (substructures > 1).then_some(substructures),
    };
    let mut mesh_bodies = vec![body("matrix".into(), &g.matrix, g.matrix_substructures)];
    mesh_bodies.extend((1..=g.grains).map(|k| body(format!("grain{k}"), &g.grain, 1)));
    let interfaces = (1..=g.grains)
        .map(|k| InterfaceSpec {
            bodies: [format!("grain{k}"), "matrix".into()],
            kind: InterfaceKind::Contact,
            friction: Some(g.friction),
            gap: Some(0.0),
            search: None,
        })
        .collect();
    let ramp_time = g.ramp_steps as f64 * spec.time.dt;
    let boundaries = vec![
        BoundarySpec {
            body: "matrix".into(),
            face: String::new(),
            surface: Some("top".into()),
            clamped: false,
            preload: false,
            x: None,
            y: None,
            z: Some(ComponentSpec::velocity(-g.velocity, ramp_time)),
            normal: None,
        },
        BoundarySpec {
            body: "matrix".into(),
            face: String::new(),
            surface: Some("bottom".into()),
            clamped: true,
            preload: false,
            x: None,
            y: None,
            z: None,
            normal: None,
        },
    ];
    Ok(SceneSpec {
        granular_poly: None,
        mesh_bodies,
        interfaces,
        boundaries,
        ..spec.clone()
    })
}

/// The MSH file of the sample: meshed by gmsh now or taken from the cache.
#[cfg(feature = "msh")]
fn mesh_file(script: &str, name: &str) -> std::result::Result<String, String> {
    crate::mesh::gmsh::mesh_script(name, script)
        .map(|p| p.display().to_string())
        .map_err(|e| e.to_string())
}

#[cfg(not(feature = "msh"))]
fn mesh_file(_: &str, _: &str) -> std::result::Result<String, String> {
    Err(NOT_MESHED.into())
}

/// Why a build without the `msh` feature (the web build) opens no `[granular_poly]` scene.
pub const NOT_MESHED: &str = "this build of Lopin meshes no polyhedral grains (the web build): \
                              run the scene with the `lopin` command line";
