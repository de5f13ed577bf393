//! The scene description: the serde schema shared by the registry and TOML scene files
//! (materials, boxes with mesh divisions and substructure splits, interface overrides, boundary
//! conditions, time grid, solver settings, or a `[granular]` generator table), plus `--refine`
//! and `--split`.

use serde::{Deserialize, Serialize};

use crate::error::{LopinError, Result};
use crate::scene::exact::exactly;
use crate::scene::granular::GranularSpec;
use crate::scene::granular_poly::GranularPolySpec;
use crate::time::time_function::{Ramp, TimeGrid};

/// A whole scene.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Scene name.
    pub name: String,
    /// One-line description.
    #[serde(default)]
    pub description: String,
    /// Axes whose mesh divisions `--refine k` multiplies (e.g. "x" for the 1D bar).
    #[serde(default = "default_refine_axes")]
    pub refine_axes: String,
    /// Axes whose substructure count `--split n` multiplies.
    #[serde(default = "default_split_axes")]
    pub split_axes: String,
    /// Time grid.
    pub time: TimeGrid,
    /// Solver settings (all optional; defaults of METHOD §10).
    #[serde(default)]
    pub solver: SolverSpec,
    /// Materials.
    #[serde(rename = "material")]
    pub materials: Vec<MaterialSpec>,
    /// A generated granular material (`[granular]`): when present, the bodies, interfaces and
    /// boundaries are generated from it and must not be listed ([`crate::scene::granular`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub granular: Option<GranularSpec>,
    /// A generated granular material with polyhedral grains meshed by gmsh (`[granular_poly]`):
    /// when present, the bodies, interfaces and boundaries are generated from it
    /// ([`crate::scene::granular_poly`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub granular_poly: Option<GranularPolySpec>,
    /// Bodies: boxes meshed with hexahedra and cut into substructures.
    #[serde(default, rename = "body", skip_serializing_if = "Vec::is_empty")]
    pub bodies: Vec<BodySpec>,
    /// Bodies taken from the physical volumes of Gmsh files (`[[mesh_body]]`).
    #[serde(default, rename = "mesh_body", skip_serializing_if = "Vec::is_empty")]
    pub mesh_bodies: Vec<MeshBodySpec>,
    /// How pairs of bodies are joined (default: perfect where they touch).
    #[serde(default, rename = "interface", skip_serializing_if = "Vec::is_empty")]
    pub interfaces: Vec<InterfaceSpec>,
    /// Boundary conditions on faces of bodies (faces not named are free).
    #[serde(default, rename = "boundary", skip_serializing_if = "Vec::is_empty")]
    pub boundaries: Vec<BoundarySpec>,
    /// Named groups of interfaces whose parameters a study moves apart (`[[zone]]`).
    #[serde(default, rename = "zone", skip_serializing_if = "Vec::is_empty")]
    pub zones: Vec<crate::interfaces::zone::ZoneSpec>,
}

fn default_refine_axes() -> String {
    "xyz".into()
}

fn default_split_axes() -> String {
    "xy".into()
}

/// Optional solver settings carried by a scene.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Stopping tolerance on η.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
    /// Relaxation μ.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Search direction k (Pa·s/m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k: Option<f64>,
    /// Iteration limit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iter: Option<usize>,
    /// Time-window length in steps (absent: whole interval).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window: Option<usize>,
    /// Spectral radius at infinite frequency of the time scheme (1: the undamped trapezoidal
    /// rule; smaller damps the highest frequencies, [`crate::time::time_scheme`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    /// Shape of the search direction, `isotropic` (the scalar k) or `wave` (ρc_p normal, ρc_s
    /// tangential; [`crate::interfaces::search_direction`]); absent: isotropic.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub directions: Option<crate::interfaces::search_direction::Directions>,
    /// Which indicator ends a window: `eta` (METHOD §6) or `smooth` (η̄ on step-averaged
    /// fields, `lopin_core::stages::indicator`); absent: eta.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<crate::scene::settings::StopTest>,
    /// Where a cold time window's iteration starts: `zero`, `hold`, `linear`, `smooth` or
    /// `auto` ([`crate::scene::settings`]); absent: auto.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window_start: Option<crate::scene::settings::WindowStart>,
    /// Depth of the Anderson acceleration of the relaxation (absent or 0: plain relaxation,
    /// `lopin_core::stages::acceleration`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anderson: Option<usize>,
    /// Two-scale linear stage with the macro problem of METHOD §9 (absent: off).
    #[serde(default, rename = "macro", skip_serializing_if = "Option::is_none")]
    pub two_scale: Option<bool>,
}

/// A named material.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Name referenced by bodies.
    pub name: String,
    /// Young's modulus E (Pa).
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
}

/// A box-shaped body.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    /// Name referenced by interfaces and boundaries.
    pub name: String,
    /// Material name.
    pub material: String,
    /// Lower corner (m).
    #[serde(deserialize_with = "exactly")]
    pub min: [f64; 3],
    /// Upper corner (m).
    #[serde(deserialize_with = "exactly")]
    pub max: [f64; 3],
    /// Hexahedra along x, y, z for the whole body.
    #[serde(deserialize_with = "exactly")]
    pub divisions: [usize; 3],
    /// Substructures along x, y, z (each must divide the divisions).
    #[serde(default = "ones", deserialize_with = "exactly")]
    pub split: [usize; 3],
    /// Initial velocity (m/s).
    #[serde(default, deserialize_with = "exactly")]
    pub velocity: [f64; 3],
    /// Element kind of the box's mesh: `hex8` (absent) or `tet4` (each hexahedron cut into six
    /// tetrahedra along its diagonal, [`crate::mesh::Mesh::split_into_tets`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements: Option<ElementKind>,
    /// Substructures cut from the body's mesh by the graph partitioner
    /// ([`crate::mesh::partition`]); instead of `split`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substructures: Option<usize>,
}

/// A body taken from a Gmsh MSH 4.1 file: the cells of one physical volume, one substructure or
/// `substructures` cut by the graph partitioner.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshBodySpec {
    /// Name referenced by interfaces and boundaries.
    pub name: String,
    /// Material name.
    pub material: String,
    /// The .msh file, or a .geo script that gmsh meshes ([`crate::mesh::gmsh`]), relative to the
    /// scene file (or absolute).
    pub mesh: String,
    /// The physical volume (absent: the body's name).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<String>,
    /// Initial velocity (m/s).
    #[serde(default, deserialize_with = "exactly")]
    pub velocity: [f64; 3],
    /// Substructures cut from the body's mesh by the graph partitioner
    /// ([`crate::mesh::partition`]); absent: the body is one substructure.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub substructures: Option<usize>,
}

impl MeshBodySpec {
    /// The physical volume the body is.
    pub fn volume_name(&self) -> &str {
        self.volume.as_deref().unwrap_or(&self.name)
    }
}

/// The element kind of a box body's mesh.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    /// Trilinear hexahedra.
    #[default]
    Hex8,
    /// Linear tetrahedra, six per hexahedron of the box grid.
    Tet4,
}

fn ones() -> [usize; 3] {
    [1, 1, 1]
}

/// Kind of junction between two bodies.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum InterfaceKind {
    /// Perfect bond.
    Perfect,
    /// Unilateral contact with Coulomb friction.
    Contact,
    /// No interaction.
    Free,
}

/// Override for the junction between two bodies.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InterfaceSpec {
    /// The two bodies.
    #[serde(deserialize_with = "exactly")]
    pub bodies: [String; 2],
    /// Kind of junction.
    pub kind: InterfaceKind,
    /// Friction coefficient (contact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<f64>,
    /// Initial gap g0 (contact; default: the geometric distance).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gap: Option<f64>,
    /// Largest distance at which facing faces are paired (contact; default 0: touching).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub search: Option<f64>,
}

/// A boundary condition on one face of a body's box.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundarySpec {
    /// Body name.
    pub body: String,
    /// Face of the body's box: "x-", "x+", "y-", "y+", "z-" or "z+" (box bodies).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub face: String,
    /// Physical surface of the body's mesh file (mesh bodies).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<String>,
    /// Shorthand for zero velocity on x, y and z.
    #[serde(default, skip_serializing_if = "is_false")]
    pub clamped: bool,
    /// Prescription on the x component (absent: free).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<ComponentSpec>,
    /// Prescription on the y component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<ComponentSpec>,
    /// Prescription on the z component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<ComponentSpec>,
}

impl BoundarySpec {
    /// The prescriptions of the x, y and z components, with the axis names fields use.
    pub fn components(&self) -> [(&'static str, &Option<ComponentSpec>); 3] {
        [("x", &self.x), ("y", &self.y), ("z", &self.z)]
    }
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// A prescribed velocity or traction on one component, with its ramp.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentSpec {
    /// Velocity amplitude V₀ (m/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
    /// Traction amplitude (Pa, force per area on the body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<f64>,
    /// Ramp profile ("cosine" default, "linear", "step").
    #[serde(default)]
    pub ramp: Ramp,
    /// Ramp duration t_r (s).
    #[serde(default)]
    pub ramp_time: f64,
}

impl ComponentSpec {
    /// A velocity with the default (1 − cos) ramp.
    pub fn velocity(v: f64, ramp_time: f64) -> Self {
        Self {
            velocity: Some(v),
            traction: None,
            ramp: Ramp::Cosine,
            ramp_time,
        }
    }
}

impl SceneSpec {
    /// Multiplies the mesh divisions along `refine_axes` by k (of a granular scene: the
    /// hexahedra per cell edge, along all axes). A product that does not fit a count is an error
    /// naming `refine` and the body (nothing is changed then).
    pub fn refine(&mut self, k: usize) -> Result<()> {
        if let Some(g) = &mut self.granular_poly {
            // a generated sample is meshed finer
            g.mesh_size /= k.max(1) as f64;
            return Ok(());
        }
        if k > 1 && !self.mesh_bodies.is_empty() {
            return Err(LopinError::setting(
                "refine",
                format!(
                    "mesh bodies (`{}`) come as meshed in their file: refine the mesh in gmsh instead",
                    self.mesh_bodies[0].name
                ),
            ));
        }
        let axes = axes_of(&self.refine_axes);
        self.multiply_counts(
            "refine",
            k,
            &axes,
            |g| (&mut g.cell_elements, "hexahedra per cell edge"),
            |b| (&mut b.divisions, "hexahedra"),
        )
    }

    /// Multiplies the number of substructures along `split_axes` by n. A granular scene has one
    /// substructure per cell: there the request is recorded and validation rejects n ≠ 1 with a
    /// message saying so. A product that does not fit a count is an error naming `split`.
    pub fn split(&mut self, n: usize) -> Result<()> {
        if let Some(g) = &mut self.granular_poly {
            // the matrix of a polyhedral sample is cut into n times more substructures
            g.matrix_substructures = g
                .matrix_substructures
                .checked_mul(n)
                .ok_or_else(|| LopinError::setting("split", "does not fit a 64-bit count"))?;
            return Ok(());
        }
        let axes = axes_of(&self.split_axes);
        self.multiply_counts(
            "split",
            n,
            &axes,
            |g| (&mut g.requested_split, "as the requested split"),
            |b| (&mut b.split, "substructures"),
        )
    }

    /// Multiplies the granular count `cell` and each body's counts `body` along `axes` by
    /// `factor`, all or nothing: a product that does not fit is an error naming `setting`.
    fn multiply_counts(
        &mut self,
        setting: &str,
        factor: usize,
        axes: &[usize],
        cell: fn(&mut GranularSpec) -> (&mut usize, &'static str),
        body: fn(&mut BodySpec) -> (&mut [usize; 3], &'static str),
    ) -> Result<()> {
        let too_large = |count: usize, what: String| {
            LopinError::setting(
                setting,
                format!("{factor} times {count} {what} does not fit a 64-bit count"),
            )
        };
        let mut scaled = self.clone();
        if let Some(g) = &mut scaled.granular {
            let (count, what) = cell(g);
            *count = count
                .checked_mul(factor)
                .ok_or_else(|| too_large(*count, what.into()))?;
        }
        for b in &mut scaled.bodies {
            let name = b.name.clone();
            let (counts, what) = body(b);
            for &a in axes {
                counts[a] = counts[a]
                    .checked_mul(factor)
                    .ok_or_else(|| too_large(counts[a], format!("{what} of body `{name}`")))?;
            }
        }
        *self = scaled;
        Ok(())
    }

    /// Whether the scene asks for contact interfaces (a contact override, or the grains of a
    /// granular scene).
    pub fn has_contact(&self) -> bool {
        self.granular.as_ref().is_some_and(|g| g.grains > 0)
            || self.granular_poly.as_ref().is_some_and(|g| g.grains > 0)
            || self
                .interfaces
                .iter()
                .any(|i| i.kind == InterfaceKind::Contact)
    }

    /// Sets the friction coefficient of every contact override (and of the grain/matrix
    /// contacts of a granular scene).
    pub fn set_friction(&mut self, f: f64) {
        if let Some(g) = &mut self.granular {
            g.friction = f;
        }
        if let Some(g) = &mut self.granular_poly {
            g.friction = f;
        }
        for i in &mut self.interfaces {
            if i.kind == InterfaceKind::Contact {
                i.friction = Some(f);
            }
        }
    }
}

/// Axis indices named in a string such as "xy".
pub fn axes_of(s: &str) -> Vec<usize> {
    s.chars()
        .filter_map(|c| match c {
            'x' => Some(0),
            'y' => Some(1),
            'z' => Some(2),
            _ => None,
        })
        .collect()
}
