//! The scene description: the serde schema shared by the registry and TOML scene files
//! (materials, boxes with mesh divisions and substructure splits, interface overrides, boundary
//! conditions, time grid, solver settings, or a `[granular]` generator table), plus `--refine`
//! and `--split`.

use serde::{Deserialize, Serialize};

use crate::error::{LopinError, Result};
use crate::scene::exact::exactly;
use crate::scene::tables::GranularPolySpec;
use crate::scene::tables::GranularSpec;
use crate::time::time_function::{PulseKind, Ramp, TimeGrid};

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

/// One layer of solver settings, every field optional: the scene's `[solver]` table, or the
/// command line's options (the same fields, `--tol`, `--rho-inf`, …), or the explorer's
/// controls. Layers stack with [`SolverSpec::over`] (the command line over the scene) and
/// resolve into [`crate::Settings`] over the defaults of METHOD §10.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Stopping tolerance on the error indicator η (default 1e-3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub tol: Option<f64>,
    /// Relaxation μ in (0, 1] (default 0.8).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub mu: Option<f64>,
    /// Search direction k in Pa·s/m (default: mean of √(ρE) over the materials in use).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, allow_hyphen_values = true))]
    pub k: Option<f64>,
    /// Iteration limit, per time window (default 2000).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub max_iter: Option<usize>,
    /// Time windows: a length in steps (1 = incremental), `whole` (the whole interval) or
    /// `auto` (the default: the scene's `solver.window`, else chosen for what the run is for:
    /// one-step windows for one solve or a study of a scene with contact, the whole interval
    /// without contact and in the explorer; the report says which).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(
        feature = "schema",
        schemars(with = "Option<crate::window_choice::WindowValue>")
    )]
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true, value_parser = crate::window_choice::WindowRequest::parse))]
    pub window: Option<crate::window_choice::WindowRequest>,
    /// Spectral radius at infinite frequency of the time scheme in [0, 1]: 1 is the undamped
    /// trapezoidal rule, smaller damps the highest frequencies (METHOD §2; default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long = "rho-inf", allow_hyphen_values = true))]
    pub rho_inf: Option<f64>,
    /// Shape of the search direction: `isotropic` (the scalar k on every dof) or `wave` (the
    /// P-wave impedance ρc_p along the interface normal, the S-wave impedance ρc_s across it;
    /// default isotropic).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::interfaces::search_direction::Directions::parse))]
    pub directions: Option<crate::interfaces::search_direction::Directions>,
    /// Which indicator ends a window: `eta` (the fields themselves, METHOD §6) or `smooth` (η̄,
    /// the same measure on step-averaged fields, blind to the undamped rule's alternating mode;
    /// default eta).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::scene::settings::StopTest::from_arg))]
    pub stop: Option<crate::scene::settings::StopTest>,
    /// Where a cold time window's iteration starts: `smooth` (extrapolate the mean change of the
    /// last two converged steps), `linear` (the last step's change), `hold` (the last step held
    /// constant), `zero`, or `auto` (smooth at a tolerance of 1e-3 and tighter, hold above;
    /// default auto).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long = "window-start", value_parser = crate::scene::settings::WindowStart::from_arg))]
    pub window_start: Option<crate::scene::settings::WindowStart>,
    /// Depth of the Anderson acceleration of the relaxation (0: plain relaxation; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, allow_negative_numbers = true))]
    pub anderson: Option<usize>,
    /// Two-scale linear stage with the macro problem of METHOD §9 (default off).
    #[serde(default, rename = "macro", skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long = "macro", value_name = "on|off", value_parser = crate::scene::settings::switch_from_arg))]
    pub two_scale: Option<bool>,
    /// Precision the factors of S are kept in: `single` (half their memory and faster
    /// triangular solves where the factors are large, each solve refined in double so that
    /// LATIN converges to the double-precision solution), `double`, or `auto` (single for
    /// substructures of 3,000 nodes and more, double below; the default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "cli", arg(long, value_parser = crate::scene::settings::FactorPrecision::from_arg))]
    pub factors: Option<crate::scene::settings::FactorPrecision>,
}

impl SolverSpec {
    /// This layer over `lower`: each setting this layer gives, else `lower`'s.
    pub fn over(&self, lower: &SolverSpec) -> SolverSpec {
        SolverSpec {
            tol: self.tol.or(lower.tol),
            mu: self.mu.or(lower.mu),
            k: self.k.or(lower.k),
            max_iter: self.max_iter.or(lower.max_iter),
            window: match self.window {
                None | Some(crate::window_choice::WindowRequest::Auto) => lower.window,
                asked => asked,
            },
            rho_inf: self.rho_inf.or(lower.rho_inf),
            directions: self.directions.or(lower.directions),
            stop: self.stop.or(lower.stop),
            window_start: self.window_start.or(lower.window_start),
            anderson: self.anderson.or(lower.anderson),
            two_scale: self.two_scale.or(lower.two_scale),
            factors: self.factors.or(lower.factors),
        }
    }
}

/// A named material.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
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
    /// Rayleigh damping on the mass, α (1/s): C = α M + β K.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// Rayleigh damping on the stiffness, β (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub beta: Option<f64>,
    /// Damping ratio ζ reached at both ends of `damping_band` (α and β computed from them:
    /// α = 2ζ ω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂)); instead of `alpha` and `beta`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_ratio: Option<f64>,
    /// The two frequencies (Hz) where the damping ratio is `damping_ratio`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping_band: Option<[f64; 2]>,
}

impl MaterialSpec {
    /// The material (its damping from `alpha`/`beta`, or from `damping_ratio` over
    /// `damping_band`; none when neither is given).
    pub fn material(&self) -> crate::elements::material::Material {
        use crate::elements::rayleigh::Rayleigh;
        let damping = match (self.damping_ratio, self.damping_band) {
            (Some(z), Some(band)) => Rayleigh::from_ratio(z, band),
            _ => Rayleigh {
                alpha: self.alpha.unwrap_or(0.0),
                beta: self.beta.unwrap_or(0.0),
            },
        };
        crate::elements::material::Material {
            young: self.young,
            poisson: self.poisson,
            density: self.density,
            damping,
        }
    }
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
    /// A preload: the tractions (or the `normal` pressure) of this boundary are applied in a
    /// static phase before the dynamics, which start from that equilibrium with the load held
    /// (a clamping force, a pressure on washer areas); constant, no ramp, pulse or table.
    #[serde(default, skip_serializing_if = "is_false")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub preload: bool,
    /// Prescription on the x component (absent: free).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<ComponentSpec>,
    /// Prescription on the y component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<ComponentSpec>,
    /// Prescription on the z component.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub z: Option<ComponentSpec>,
    /// A load along the faces' local outward normal instead of x, y and z: `pressure` (Pa,
    /// pushing into the body) or `traction` (Pa, pulling outward), with its time function; on a
    /// curved surface every node takes its area-weighted normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub normal: Option<ComponentSpec>,
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

/// A prescribed velocity, traction or acceleration on one component, with its time function: a
/// ramp (the default), a standard pulse, or a table of points (accelerations, pulses and tables
/// are read from scene text with the `shock` feature; the web build's built-in scenes use none).
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComponentSpec {
    /// Velocity amplitude V₀ (m/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity: Option<f64>,
    /// Traction amplitude (Pa, force per area on the body).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traction: Option<f64>,
    /// Pressure (Pa) of a `normal` load: the traction −pressure along the outward normal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub pressure: Option<f64>,
    /// Acceleration amplitude (m/s²), for base excitation: the dofs move from rest with this
    /// acceleration times the time function, its velocity integrated by the time scheme's
    /// own rule (the body's initial velocity along the component must be 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub acceleration: Option<f64>,
    /// Ramp profile ("cosine" default, "linear", "step").
    #[serde(default)]
    pub ramp: Ramp,
    /// Ramp duration t_r (s).
    #[serde(default)]
    pub ramp_time: f64,
    /// A standard shock pulse instead of a ramp, whose peak is the velocity or traction:
    /// `half-sine`, `haversine`, `sawtooth` (terminal peak) or `trapezoid`; 0 after `duration`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub pulse: Option<PulseKind>,
    /// Duration T of the pulse (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub duration: Option<f64>,
    /// Rise (and fall) time of a trapezoid pulse (s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub rise: Option<f64>,
    /// A table of `[t, value]` points instead of a ramp (t increasing, from 0 s), interpolated
    /// linearly, from 0 at t = 0 to the first point, the last value held; the velocity or
    /// traction multiplies its values (1: the values as written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub table: Option<Vec<[f64; 2]>>,
    /// A CSV file of `t,value` lines (relative to the scene file; a header line and `#`
    /// comments are skipped), read as `table` when the scene file is read.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(not(feature = "shock"), serde(skip))]
    pub table_file: Option<String>,
}

impl ComponentSpec {
    /// A velocity with the default (1 − cos) ramp.
    pub fn velocity(v: f64, ramp_time: f64) -> Self {
        Self {
            velocity: Some(v),
            traction: None,
            ramp: Ramp::Cosine,
            ramp_time,
            ..Self::default()
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

/// Faces of a box by name: (axis, sign).
pub fn face_of(name: &str) -> Option<(usize, f64)> {
    match name {
        "x-" => Some((0, -1.0)),
        "x+" => Some((0, 1.0)),
        "y-" => Some((1, -1.0)),
        "y+" => Some((1, 1.0)),
        "z-" => Some((2, -1.0)),
        "z+" => Some((2, 1.0)),
        _ => None,
    }
}
