//! The generator tables of a scene, `[granular]` and `[granular_poly]`, as the file writes
//! them (their fields and defaults, SCENES.md `granular`): the schema's part of the generators,
//! apart from their checks and expansions ([`super::granular`], [`super::granular_poly`]).

use serde::{Deserialize, Serialize};

/// The `[granular]` table: the generator's parameters.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GranularSpec {
    /// Side L of the cube (m); its lower corner is the origin.
    pub side: f64,
    /// Cells along x, y, z.
    #[serde(deserialize_with = "crate::scene::exact::exactly")]
    pub grid: [usize; 3],
    /// Hexahedra m along each edge of a cell (a cell has m × m × m).
    pub cell_elements: usize,
    /// Number of grains.
    pub grains: usize,
    /// Smallest and largest number of cells of a grain (each grain's size is drawn in between).
    #[serde(
        default = "default_grain_cells",
        deserialize_with = "crate::scene::exact::exactly"
    )]
    pub grain_cells: [usize; 2],
    /// Seed of the grain placement (the same seed always gives the same layout).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Material of the matrix (a `[[material]]` name).
    pub matrix: String,
    /// Material of the grains (a `[[material]]` name).
    pub grain: String,
    /// Friction coefficient f of the grain/matrix contacts.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Velocity V₀ (m/s) imposed along −z on the top face.
    #[serde(default = "default_velocity")]
    pub velocity: f64,
    /// Duration of the (1 − cos) ramp of V₀, in time steps.
    #[serde(default = "default_ramp_steps")]
    pub ramp_steps: usize,
    /// The factor of `--split n` applied to this scene ([`SceneSpec::split`]); not part of the
    /// file. Every cell is one substructure, so validation rejects any value but 1.
    #[serde(skip, default = "default_split")]
    pub requested_split: usize,
}

pub(crate) fn default_grain_cells() -> [usize; 2] {
    [1, 3]
}

/// Default of the granular tables (SCENES.md `granular`).
pub(crate) fn default_seed() -> u64 {
    1
}

/// Default of the granular tables (SCENES.md `granular`).
pub(crate) fn default_friction() -> f64 {
    0.3
}

/// Default of the granular tables (SCENES.md `granular`).
pub(crate) fn default_velocity() -> f64 {
    10.0
}

/// Default of the granular tables (SCENES.md `granular`).
pub(crate) fn default_ramp_steps() -> usize {
    10
}

pub(crate) fn default_split() -> usize {
    1
}

/// The `[granular_poly]` table: the generator's parameters.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GranularPolySpec {
    /// Side L of the cube (m); its lower corner is the origin.
    pub side: f64,
    /// Number of grains.
    pub grains: usize,
    /// Smallest and largest circumscribed radius of a grain (m).
    #[serde(deserialize_with = "crate::scene::exact::exactly")]
    pub radius: [f64; 2],
    /// Points drawn on a grain's sphere, whose convex hull is the grain (at least 6).
    #[serde(default = "default_vertices")]
    pub vertices: usize,
    /// Smallest distance between two grains' circumscribed spheres, and from a sphere to the
    /// cube's faces (m).
    pub gap: f64,
    /// Seed of the grain shapes and placement (the same seed always gives the same sample).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Target tetrahedron size (m).
    pub mesh_size: f64,
    /// Substructures the matrix is cut into by the graph partitioner (each grain is one).
    #[serde(default = "default_one")]
    pub matrix_substructures: usize,
    /// Material of the matrix (a `[[material]]` name).
    pub matrix: String,
    /// Material of the grains (a `[[material]]` name).
    pub grain: String,
    /// Friction coefficient f of the grain/matrix contacts.
    #[serde(default = "default_friction")]
    pub friction: f64,
    /// Velocity V₀ (m/s) imposed along −z on the top face.
    #[serde(default = "default_velocity")]
    pub velocity: f64,
    /// Duration of the (1 − cos) ramp of V₀, in time steps.
    #[serde(default = "default_ramp_steps")]
    pub ramp_steps: usize,
}

pub(crate) fn default_vertices() -> usize {
    12
}

pub(crate) fn default_one() -> usize {
    1
}
