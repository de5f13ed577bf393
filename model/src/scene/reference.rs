//! The scene file's reference, generated from the code: every table and key the parser accepts,
//! read from the serde schema ([`schema`], through schemars: type, default, the field's doc
//! comment), each with the unit and allowed range of its rule (`RULES`) and the message a scene gets
//! outside that range: a probe sets the key to a value outside it in a valid scene and runs the
//! scene through reading, validation and building (METHOD §10 for the solver settings' ranges),
//! so the page quotes the validator itself. Where a range has an inside probe too, that value
//! must be accepted, which pins the documented bound from both sides.
//!
//! [`markdown`] writes the page (`lopin docs scene` prints it); it fails when a key of the
//! schema has no rule, a rule names no key, or a probe is not refused, so a key cannot be added
//! without being documented.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write;

use serde_json::Value;

use crate::scene::{from_toml, registry, to_toml};

/// What the page says of one key beyond the schema.
#[derive(Debug, Clone, Copy)]
struct Rule {
    /// `table.key` as in the page: `time.dt`, `body.divisions`, `boundary.x.velocity` (the
    /// three components share their rules), `name` for a top-level key.
    key: &'static str,
    /// Unit (empty: dimensionless or not a quantity).
    unit: &'static str,
    /// The values accepted, in words.
    range: &'static str,
    /// A value outside the range, in a valid scene.
    outside: Option<Probe>,
    /// A value at the edge of the range, which the scene must accept.
    inside: Option<Probe>,
}

/// One key of a valid scene set to a value (TOML).
#[derive(Debug, Clone, Copy)]
struct Probe {
    /// The scene the value is put into.
    base: Base,
    /// Where: `material[0].young`, `boundary[0].z.ramp`, `granular.side`.
    path: &'static str,
    /// The value, as TOML.
    value: &'static str,
}

/// The valid scenes probes start from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Base {
    /// `two-blocks`: two box bodies in contact, a velocity on top, the bottom clamped.
    Boxes,
    /// `two-blocks` with a zone holding the contact.
    Zoned,
    /// `granular-small`: the `[granular]` generator.
    Granular,
    /// `granular-poly`: the `[granular_poly]` generator (its table alone is probed: nothing
    /// is meshed).
    GranularPoly,
    /// A steel unit cube from a Gmsh file (six tetrahedra, its face `bottom` clamped) and a box
    /// body apart from it.
    Meshed,
    /// `two-blocks` shocked on top by a trapezoid pulse (10 µs, rise 2 µs) instead of a ramp.
    Pulsed,
    /// `two-blocks` driven on top by a table of points instead of a ramp.
    Tabled,
}

const fn out(base: Base, path: &'static str, value: &'static str) -> Option<Probe> {
    Some(Probe { base, path, value })
}

use Base::{Boxes, Granular, GranularPoly, Meshed, Pulsed, Tabled, Zoned};

/// Unit, range and probes of every key.
const RULES: &[Rule] = &[
    // top level
    Rule { key: "name", unit: "", range: "any text", outside: None, inside: None },
    Rule { key: "description", unit: "", range: "any text", outside: None, inside: None },
    Rule {
        key: "refine_axes",
        unit: "",
        range: "letters among `x`, `y`, `z`",
        outside: out(Boxes, "refine_axes", "\"xw\""),
        inside: out(Boxes, "refine_axes", "\"z\""),
    },
    Rule {
        key: "split_axes",
        unit: "",
        range: "letters among `x`, `y`, `z`",
        outside: out(Boxes, "split_axes", "\"q\""),
        inside: out(Boxes, "split_axes", "\"xyz\""),
    },
    // [time]
    Rule {
        key: "time.dt",
        unit: "s",
        range: "> 0, and 10⁻⁴ to 10⁴ times the time a P wave takes to cross the smallest element",
        outside: out(Boxes, "time.dt", "1.0"),
        inside: None,
    },
    Rule {
        key: "time.steps",
        unit: "",
        range: "≥ 1, and long enough for every ramp",
        outside: out(Boxes, "time.steps", "0"),
        inside: out(Boxes, "time.steps", "10"),
    },
    // [solver]
    Rule {
        key: "solver.tol",
        unit: "",
        range: "> 0",
        outside: out(Boxes, "solver.tol", "0.0"),
        inside: None,
    },
    Rule {
        key: "solver.mu",
        unit: "",
        range: "(0, 1]",
        outside: out(Boxes, "solver.mu", "1.5"),
        inside: out(Boxes, "solver.mu", "1.0"),
    },
    Rule {
        key: "solver.k",
        unit: "Pa·s/m",
        range: "> 0, and 10⁻⁶ to 10⁶ times the mean impedance √(ρE) of the materials",
        outside: out(Boxes, "solver.k", "1e-3"),
        inside: None,
    },
    Rule {
        key: "solver.max_iter",
        unit: "iterations",
        range: "≥ 1",
        outside: out(Boxes, "solver.max_iter", "0"),
        inside: out(Boxes, "solver.max_iter", "1"),
    },
    Rule {
        key: "solver.window",
        unit: "steps",
        range: "≥ 1, or `\"whole\"` (the whole interval) or `\"auto\"`",
        outside: out(Boxes, "solver.window", "0"),
        inside: out(Boxes, "solver.window", "1"),
    },
    Rule {
        key: "solver.rho_inf",
        unit: "",
        range: "[0, 1]",
        outside: out(Boxes, "solver.rho_inf", "1.5"),
        inside: out(Boxes, "solver.rho_inf", "0.0"),
    },
    Rule {
        key: "solver.directions",
        unit: "",
        range: "`isotropic` or `wave`",
        outside: out(Boxes, "solver.directions", "\"radial\""),
        inside: out(Boxes, "solver.directions", "\"wave\""),
    },
    Rule {
        key: "solver.stop",
        unit: "",
        range: "`eta` or `smooth`",
        outside: out(Boxes, "solver.stop", "\"energy\""),
        inside: out(Boxes, "solver.stop", "\"smooth\""),
    },
    Rule {
        key: "solver.window_start",
        unit: "",
        range: "`zero`, `hold`, `linear`, `smooth` or `auto`",
        outside: out(Boxes, "solver.window_start", "\"cubic\""),
        inside: out(Boxes, "solver.window_start", "\"hold\""),
    },
    Rule {
        key: "solver.anderson",
        unit: "",
        range: "≥ 0 (0: plain relaxation)",
        outside: out(Boxes, "solver.anderson", "-1"),
        inside: out(Boxes, "solver.anderson", "0"),
    },
    Rule {
        key: "solver.macro",
        unit: "",
        range: "`true` or `false`",
        outside: out(Boxes, "solver.macro", "\"yes\""),
        inside: out(Boxes, "solver.macro", "true"),
    },
    Rule {
        key: "solver.factors",
        unit: "",
        range: "`double` or `single`",
        outside: out(Boxes, "solver.factors", "\"half\""),
        inside: out(Boxes, "solver.factors", "\"single\""),
    },
    // [[material]]
    Rule {
        key: "material.name",
        unit: "",
        range: "unique among the materials",
        outside: out(Boxes, "material[1].name", "\"steel\""),
        inside: None,
    },
    Rule {
        key: "material.young",
        unit: "Pa",
        range: "10⁻³ to 10¹³",
        outside: out(Boxes, "material[0].young", "1e14"),
        inside: out(Boxes, "material[0].young", "1e13"),
    },
    Rule {
        key: "material.poisson",
        unit: "",
        range: "(−1, 0.5)",
        outside: out(Boxes, "material[0].poisson", "0.5"),
        inside: out(Boxes, "material[0].poisson", "0.0"),
    },
    Rule {
        key: "material.density",
        unit: "kg/m³",
        range: "10⁻³ to 10⁵",
        outside: out(Boxes, "material[0].density", "0.0"),
        inside: None,
    },
    Rule {
        key: "material.alpha",
        unit: "1/s",
        range: "≥ 0 (not with `damping_ratio`)",
        outside: out(Boxes, "material[0].alpha", "-1.0"),
        inside: out(Boxes, "material[0].alpha", "0.0"),
    },
    Rule {
        key: "material.beta",
        unit: "s",
        range: "≥ 0 (not with `damping_ratio`)",
        outside: out(Boxes, "material[0].beta", "-1e-9"),
        inside: out(Boxes, "material[0].beta", "0.0"),
    },
    Rule {
        key: "material.damping_ratio",
        unit: "",
        range: "(0, 1), with `damping_band`",
        outside: out(Boxes, "material[0].damping_ratio", "1.0"),
        inside: None,
    },
    Rule {
        key: "material.damping_band",
        unit: "Hz",
        range: "0 < f1 < f2, with `damping_ratio`",
        outside: out(Boxes, "material[0].damping_band", "[100.0, 10.0]"),
        inside: None,
    },
    // [[body]]
    Rule {
        key: "body.name",
        unit: "",
        range: "unique among the bodies",
        outside: out(Boxes, "body[1].name", "\"A\""),
        inside: None,
    },
    Rule {
        key: "body.material",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(Boxes, "body[0].material", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "body.min",
        unit: "m",
        range: "3 numbers, below `max` on every axis; edges 10⁻⁹ to 10⁵ m; bodies may touch, not overlap",
        outside: out(Boxes, "body[0].min", "[0.0, 0.0, 0.05]"),
        inside: None,
    },
    Rule {
        key: "body.max",
        unit: "m",
        range: "3 numbers, above `min` on every axis",
        outside: out(Boxes, "body[0].max", "[0.04, 0.04, 0.01]"),
        inside: None,
    },
    Rule {
        key: "body.divisions",
        unit: "elements",
        range: "3 counts ≥ 1; element edges within a ratio of 10³ of each other",
        outside: out(Boxes, "body[0].divisions", "[10, 10, 0]"),
        inside: None,
    },
    Rule {
        key: "body.split",
        unit: "substructures",
        range: "3 counts ≥ 1, each dividing `divisions`",
        outside: out(Boxes, "body[0].split", "[3, 1, 1]"),
        inside: out(Boxes, "body[0].split", "[2, 2, 1]"),
    },
    Rule {
        key: "body.velocity",
        unit: "m/s",
        range: "3 finite numbers, small against the slowest wave speed (small strains)",
        outside: out(Boxes, "body[0].velocity", "[0.0, 0.0, -1e5]"),
        inside: None,
    },
    Rule {
        key: "body.elements",
        unit: "",
        range: "`hex8` or `tet4`",
        outside: out(Boxes, "body[0].elements", "\"hex20\""),
        inside: None,
    },
    Rule {
        key: "body.substructures",
        unit: "",
        range: "1 to the number of elements; instead of `split`",
        outside: out(Boxes, "body[0].substructures", "0"),
        inside: out(Boxes, "body[0].substructures", "4"),
    },
    // [[mesh_body]]
    Rule {
        key: "mesh_body.name",
        unit: "",
        range: "unique among the bodies",
        outside: out(Meshed, "mesh_body[0].name", "\"plate\""),
        inside: None,
    },
    Rule {
        key: "mesh_body.material",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(Meshed, "mesh_body[0].material", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "mesh_body.mesh",
        unit: "",
        range: "a readable `.msh` (MSH 4.1) or `.geo` file",
        outside: out(Meshed, "mesh_body[0].mesh", "\"missing.msh\""),
        inside: None,
    },
    Rule {
        key: "mesh_body.volume",
        unit: "",
        range: "a physical volume of the file",
        outside: out(Meshed, "mesh_body[0].volume", "\"sphere\""),
        inside: out(Meshed, "mesh_body[0].volume", "\"cube\""),
    },
    Rule {
        key: "mesh_body.velocity",
        unit: "m/s",
        range: "3 finite numbers, small against the slowest wave speed",
        outside: out(Meshed, "mesh_body[0].velocity", "[0.0, 0.0, 1e5]"),
        inside: None,
    },
    Rule {
        key: "mesh_body.substructures",
        unit: "",
        range: "1 to the number of elements",
        outside: out(Meshed, "mesh_body[0].substructures", "0"),
        inside: out(Meshed, "mesh_body[0].substructures", "2"),
    },
    // [[interface]]
    Rule {
        key: "interface.bodies",
        unit: "",
        range: "two different body names, each pair listed once",
        outside: out(Boxes, "interface[0].bodies", "[\"A\", \"A\"]"),
        inside: None,
    },
    Rule {
        key: "interface.kind",
        unit: "",
        range: "`perfect`, `contact` or `free`",
        outside: out(Boxes, "interface[0].kind", "\"glued\""),
        inside: None,
    },
    Rule {
        key: "interface.friction",
        unit: "",
        range: "[0, 10]",
        outside: out(Boxes, "interface[0].friction", "11.0"),
        inside: out(Boxes, "interface[0].friction", "10.0"),
    },
    Rule {
        key: "interface.gap",
        unit: "m",
        range: "at most the size of the whole model; negative: an interference, closed by a static preload phase",
        outside: out(Boxes, "interface[0].gap", "1.0"),
        inside: out(Boxes, "interface[0].gap", "-1e-6"),
    },
    Rule {
        key: "interface.search",
        unit: "m",
        range: "≥ 0, at most the size of the whole model",
        outside: out(Boxes, "interface[0].search", "1e3"),
        inside: out(Boxes, "interface[0].search", "0.0"),
    },
    // [[boundary]]
    Rule {
        key: "boundary.body",
        unit: "",
        range: "a body name",
        outside: out(Boxes, "boundary[0].body", "\"C\""),
        inside: None,
    },
    Rule {
        key: "boundary.face",
        unit: "",
        range: "`x-`, `x+`, `y-`, `y+`, `z-` or `z+` (box bodies)",
        outside: out(Boxes, "boundary[0].face", "\"top\""),
        inside: None,
    },
    Rule {
        key: "boundary.surface",
        unit: "",
        range: "a physical surface of the body's mesh file (mesh bodies)",
        outside: out(Boxes, "boundary[0].surface", "\"top\""),
        inside: None,
    },
    Rule {
        key: "boundary.clamped",
        unit: "",
        range: "`true` or `false`; not with `x`, `y` or `z`",
        outside: out(Boxes, "boundary[0].clamped", "true"),
        inside: None,
    },
    Rule {
        key: "boundary.preload",
        unit: "",
        range: "`true` or `false`; tractions or a `normal` pressure only, constant",
        outside: out(Boxes, "boundary[0].preload", "true"),
        inside: None,
    },
    Rule {
        key: "boundary.x.velocity",
        unit: "m/s",
        range: "finite, small against the slowest wave speed; not with `traction`",
        outside: out(Boxes, "boundary[0].z.velocity", "-1e5"),
        inside: None,
    },
    Rule {
        key: "boundary.x.traction",
        unit: "Pa",
        range: "finite, small against E; not with `velocity`",
        outside: out(Boxes, "boundary[0].x.traction", "-1e12"),
        inside: None,
    },
    Rule {
        key: "boundary.x.acceleration",
        unit: "m/s²",
        range: "finite; the body at rest along that axis; not with `velocity` or `traction`",
        outside: out(Boxes, "boundary[0].z.acceleration", "-500.0"),
        inside: None,
    },
    Rule {
        key: "boundary.x.pressure",
        unit: "Pa",
        range: "`normal` only (along the outward normal, pushing in); small against E",
        outside: out(Boxes, "boundary[0].z.pressure", "1e6"),
        inside: None,
    },
    Rule {
        key: "boundary.x.ramp",
        unit: "",
        range: "`cosine`, `linear` or `step`",
        outside: out(Boxes, "boundary[0].z.ramp", "\"sine\""),
        inside: out(Boxes, "boundary[0].z.ramp", "\"linear\""),
    },
    Rule {
        key: "boundary.x.ramp_time",
        unit: "s",
        range: "≥ 0, at most the run's duration (`time.steps` × `time.dt`)",
        outside: out(Boxes, "boundary[0].z.ramp_time", "1.0"),
        inside: out(Boxes, "boundary[0].z.ramp_time", "1.5e-5"),
    },
    Rule {
        key: "boundary.x.pulse",
        unit: "",
        range: "`half-sine`, `haversine`, `sawtooth` or `trapezoid`; not with `ramp_time` or a table",
        outside: out(Pulsed, "boundary[0].z.pulse", "\"square\""),
        inside: out(Pulsed, "boundary[0].z.pulse", "\"trapezoid\""),
    },
    Rule {
        key: "boundary.x.duration",
        unit: "s",
        range: "> 0, at most the run's duration (`time.steps` × `time.dt`); with `pulse` only",
        outside: out(Pulsed, "boundary[0].z.duration", "1.0"),
        inside: out(Pulsed, "boundary[0].z.duration", "1.5e-5"),
    },
    Rule {
        key: "boundary.x.rise",
        unit: "s",
        range: "in (0, `duration` / 2]; a trapezoid pulse's only, and it needs one",
        outside: out(Pulsed, "boundary[0].z.rise", "6e-6"),
        inside: out(Pulsed, "boundary[0].z.rise", "5e-6"),
    },
    Rule {
        key: "boundary.x.table",
        unit: "[s, ×]",
        range: "at least one point; finite; times from 0, strictly increasing",
        outside: out(Tabled, "boundary[0].z.table", "[[0.0, 0.0], [2e-6, 1.0], [1e-6, 0.5]]"),
        inside: out(Tabled, "boundary[0].z.table", "[[0.0, 1.0]]"),
    },
    Rule {
        key: "boundary.x.table_file",
        unit: "",
        range: "a readable CSV file (relative to the scene file) of `t,value` lines, read into `table`",
        outside: None,
        inside: None,
    },
    // [[zone]]
    Rule {
        key: "zone.name",
        unit: "",
        range: "letters, digits, `-` and `_`; unique among the zones",
        outside: out(Zoned, "zone[0].name", "\"top zone\""),
        inside: None,
    },
    Rule {
        key: "zone.bodies",
        unit: "",
        range: "pairs of body names joined by a contact",
        outside: out(Zoned, "zone[0].bodies", "[[\"A\", \"C\"]]"),
        inside: None,
    },
    Rule {
        key: "zone.min",
        unit: "m",
        range: "3 numbers; the box must hold the centre of at least one interface",
        outside: out(Zoned, "zone[0].min", "[1.0, 1.0, 1.0]"),
        inside: None,
    },
    Rule {
        key: "zone.max",
        unit: "m",
        range: "3 numbers; the box must hold the centre of at least one interface",
        outside: out(Zoned, "zone[0].max", "[-1.0, -1.0, -1.0]"),
        inside: None,
    },
    Rule {
        key: "zone.surfaces",
        unit: "",
        range: "physical surfaces of the mesh bodies' files",
        outside: out(Zoned, "zone[0].surfaces", "[\"top\"]"),
        inside: None,
    },
    // [granular]
    Rule {
        key: "granular.side",
        unit: "m",
        range: "> 0",
        outside: out(Granular, "granular.side", "-1.0"),
        inside: None,
    },
    Rule {
        key: "granular.grid",
        unit: "cells",
        range: "3 counts ≥ 1",
        outside: out(Granular, "granular.grid", "[4, 0, 4]"),
        inside: None,
    },
    Rule {
        key: "granular.cell_elements",
        unit: "elements",
        range: "≥ 1",
        outside: out(Granular, "granular.cell_elements", "0"),
        inside: out(Granular, "granular.cell_elements", "1"),
    },
    Rule {
        key: "granular.grains",
        unit: "",
        range: "0 to the number of cells the grains can take",
        outside: out(Granular, "granular.grains", "65"),
        inside: None,
    },
    Rule {
        key: "granular.grain_cells",
        unit: "cells",
        range: "minimum ≥ 1, minimum ≤ maximum ≤ cells",
        outside: out(Granular, "granular.grain_cells", "[3, 2]"),
        inside: out(Granular, "granular.grain_cells", "[1, 1]"),
    },
    Rule { key: "granular.seed", unit: "", range: "any integer ≥ 0", outside: None, inside: None },
    Rule {
        key: "granular.matrix",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(Granular, "granular.matrix", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "granular.grain",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(Granular, "granular.grain", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "granular.friction",
        unit: "",
        range: "[0, 10]",
        outside: out(Granular, "granular.friction", "-0.1"),
        inside: out(Granular, "granular.friction", "0.0"),
    },
    Rule {
        key: "granular.velocity",
        unit: "m/s",
        range: "finite, small against the slowest wave speed",
        outside: out(Granular, "granular.velocity", "1e5"),
        inside: None,
    },
    Rule {
        key: "granular.ramp_steps",
        unit: "steps",
        range: "0 to `time.steps`",
        outside: out(Granular, "granular.ramp_steps", "100000"),
        inside: None,
    },
    // [granular_poly]
    Rule {
        key: "granular_poly.side",
        unit: "m",
        range: "10⁻⁴ to 100",
        outside: out(GranularPoly, "granular_poly.side", "1e3"),
        inside: None,
    },
    Rule {
        key: "granular_poly.grains",
        unit: "",
        range: "1 to 500",
        outside: out(GranularPoly, "granular_poly.grains", "501"),
        inside: None,
    },
    Rule {
        key: "granular_poly.radius",
        unit: "m",
        range: "minimum ≤ maximum; minimum ≥ 10⁻³ × side and ≥ mesh_size / 2",
        outside: out(GranularPoly, "granular_poly.radius", "[0.02, 0.01]"),
        inside: None,
    },
    Rule {
        key: "granular_poly.vertices",
        unit: "",
        range: "6 to 24",
        outside: out(GranularPoly, "granular_poly.vertices", "25"),
        inside: out(GranularPoly, "granular_poly.vertices", "24"),
    },
    Rule {
        key: "granular_poly.gap",
        unit: "m",
        range: "> 0, at least mesh_size / 4",
        outside: out(GranularPoly, "granular_poly.gap", "0.0"),
        inside: None,
    },
    Rule { key: "granular_poly.seed", unit: "", range: "any integer ≥ 0", outside: None, inside: None },
    Rule {
        key: "granular_poly.mesh_size",
        unit: "m",
        range: "> 0",
        outside: out(GranularPoly, "granular_poly.mesh_size", "0.0"),
        inside: None,
    },
    Rule {
        key: "granular_poly.matrix_substructures",
        unit: "",
        range: "≥ 1",
        outside: out(GranularPoly, "granular_poly.matrix_substructures", "0"),
        inside: None,
    },
    Rule {
        key: "granular_poly.matrix",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(GranularPoly, "granular_poly.matrix", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "granular_poly.grain",
        unit: "",
        range: "a `[[material]]` name",
        outside: out(GranularPoly, "granular_poly.grain", "\"wood\""),
        inside: None,
    },
    Rule {
        key: "granular_poly.friction",
        unit: "",
        range: "[0, 10]",
        outside: out(GranularPoly, "granular_poly.friction", "10.5"),
        inside: out(GranularPoly, "granular_poly.friction", "10.0"),
    },
    Rule {
        key: "granular_poly.velocity",
        unit: "m/s",
        range: "finite; small against the slowest wave speed (checked when the sample is built)",
        outside: None,
        inside: None,
    },
    Rule {
        key: "granular_poly.ramp_steps",
        unit: "steps",
        range: "0 to `time.steps`",
        outside: out(GranularPoly, "granular_poly.ramp_steps", "100000"),
        inside: None,
    },
];

/// The JSON schema of a scene file (draft 2020-12), as `lopin docs schema` prints it: editors
/// that read JSON schemas check and complete scene files with it.
pub fn schema() -> Value {
    schemars::schema_for!(crate::scene::SceneSpec).to_value()
}

/// One key of the schema.
#[derive(Debug, Clone, PartialEq)]
struct SchemaKey {
    /// `table.key`, as [`Rule::key`].
    key: String,
    /// The table header as written in a file: `[time]`, `[[body]]`, `[boundary.x]`.
    table: String,
    /// The key's name in its table.
    name: String,
    /// Its type, in words.
    kind: String,
    /// Its default (as TOML), or `required`.
    default: String,
    /// The field's doc comment.
    description: String,
}

/// Every key the parser accepts, table by table in the schema's order.
fn schema_keys() -> Vec<SchemaKey> {
    let schema = schema();
    let defs = schema.get("$defs").cloned().unwrap_or(Value::Null);
    let mut keys = Vec::new();
    walk(&schema, &defs, "", "(top level)", &mut keys);
    keys
}

fn walk(table: &Value, defs: &Value, prefix: &str, header: &str, keys: &mut Vec<SchemaKey>) {
    let required: Vec<&str> = table
        .get("required")
        .and_then(Value::as_array)
        .map(|r| r.iter().filter_map(Value::as_str).collect())
        .unwrap_or_default();
    let Some(props) = table.get("properties").and_then(Value::as_object) else {
        return;
    };
    let mut nested = Vec::new();
    for (name, prop) in props {
        let key = format!("{prefix}{name}");
        let (target, array) = resolve(prop, defs);
        if target.get("properties").is_some() {
            // a table: one level below, the three components of a boundary and its normal
            // load under one header
            if name == "y" || name == "z" || name == "normal" {
                continue;
            }
            let sub = if array {
                format!("[[{key}]]")
            } else if name == "x" && prefix.starts_with("boundary") {
                format!("[{key}], [{prefix}y], [{prefix}z], [{prefix}normal]")
            } else {
                format!("[{key}]")
            };
            nested.push((target.clone(), format!("{key}."), sub));
            continue;
        }
        let kind = kind(prop, defs);
        let default = if required.contains(&name.as_str()) {
            "required".to_string()
        } else {
            match prop.get("default") {
                Some(Value::Null) | None if kind == "boolean" => "`false`".into(),
                Some(Value::Null) | None => "absent".to_string(),
                Some(v) => format!("`{}`", toml_value(v)),
            }
        };
        keys.push(SchemaKey {
            key,
            table: header.to_string(),
            name: name.clone(),
            kind,
            default,
            description: description(prop, defs),
        });
    }
    for (target, prefix, header) in nested {
        walk(&target, defs, &prefix, &header, keys);
    }
}

/// The schema a property points at, and whether the property is an array of it.
fn resolve<'a>(prop: &'a Value, defs: &'a Value) -> (&'a Value, bool) {
    if let Some(r) = prop.get("$ref").and_then(Value::as_str) {
        let name = r.trim_start_matches("#/$defs/");
        return (defs.get(name).unwrap_or(prop), false);
    }
    if let Some(options) = prop.get("anyOf").and_then(Value::as_array) {
        if let Some(some) = options
            .iter()
            .find(|o| o.get("type").and_then(Value::as_str) != Some("null"))
        {
            return resolve(some, defs);
        }
    }
    if prop.get("type").and_then(Value::as_str) == Some("array") {
        if let Some(items) = prop.get("items") {
            let (target, _) = resolve(items, defs);
            if target.get("properties").is_some() {
                return (target, true);
            }
        }
    }
    (prop, false)
}

/// A property's type in words.
fn kind(prop: &Value, defs: &Value) -> String {
    let (target, _) = resolve(prop, defs);
    if let Some(variants) = target.get("oneOf").and_then(Value::as_array) {
        let names: Vec<String> = variants
            .iter()
            .filter_map(|v| v.get("const").and_then(Value::as_str))
            .map(|s| format!("`{s}`"))
            .collect();
        return format!("one of {}", names.join(", "));
    }
    if let Some(variants) = target.get("anyOf").and_then(Value::as_array) {
        let kinds: Vec<String> = variants
            .iter()
            .filter(|v| v.get("type").and_then(Value::as_str) != Some("null"))
            .map(|v| kind(v, defs))
            .collect();
        return kinds.join(" or ");
    }
    if let Some(names) = target.get("enum").and_then(Value::as_array) {
        let names: Vec<String> = names
            .iter()
            .filter_map(Value::as_str)
            .map(|s| format!("`{s}`"))
            .collect();
        return format!("one of {}", names.join(", "));
    }
    let types: Vec<&str> = match target.get("type") {
        Some(Value::String(t)) => vec![t.as_str()],
        Some(Value::Array(ts)) => ts.iter().filter_map(Value::as_str).collect(),
        _ => Vec::new(),
    };
    let t = types
        .iter()
        .find(|t| **t != "null")
        .copied()
        .unwrap_or("value");
    match t {
        "array" => {
            let item = target
                .get("items")
                .map(|i| kind(i, defs))
                .unwrap_or_default();
            match (target.get("minItems"), target.get("maxItems")) {
                (Some(a), Some(b)) if a == b => format!("{a} × {item}"),
                _ => format!("list of {item}"),
            }
        }
        "integer" => "integer".into(),
        "number" => "number".into(),
        "string" => "text".into(),
        "boolean" => "boolean".into(),
        other => other.into(),
    }
}

/// A property's doc comment, or its target's.
fn description(prop: &Value, defs: &Value) -> String {
    let text = prop
        .get("description")
        .or_else(|| resolve(prop, defs).0.get("description"))
        .and_then(Value::as_str)
        .unwrap_or("");
    // rustdoc links are not links on the page
    text.replace('\n', " ")
        .replace("[`", "`")
        .replace("`]", "`")
        .replace("`crate::", "`lopin_core::")
}

/// A JSON default as TOML.
fn toml_value(v: &Value) -> String {
    match v {
        Value::String(s) => format!("\"{s}\""),
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(toml_value).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// The unit cube of the meshed base: six tetrahedra, the physical volume `cube` and the
/// physical surface `bottom`.
const UNIT_CUBE_MSH: &str = include_str!("../../../assets/meshes/unit-cube.msh");

/// The meshed base: the cube clamped on `bottom`, a box body apart.
const MESHED_TOML: &str = r#"
name = "meshed"
[time]
dt = 1e-5
steps = 10
[[material]]
name = "steel"
young = 210e9
poisson = 0.3
density = 7800.0
[[mesh_body]]
name = "cube"
material = "steel"
mesh = "unit-cube.msh"
[[body]]
name = "plate"
material = "steel"
min = [0.0, 0.0, 2.0]
max = [1.0, 1.0, 2.5]
divisions = [2, 2, 1]
[[boundary]]
body = "cube"
surface = "bottom"
clamped = true
"#;

/// The base scene of a probe, as TOML.
fn base_toml(base: Base) -> Result<String, String> {
    let name = match base {
        Boxes | Zoned | Pulsed | Tabled => "two-blocks",
        Granular => "granular-small",
        GranularPoly => "granular-poly",
        Meshed => return Ok(MESHED_TOML.to_string()),
    };
    let mut spec = registry::parse(name)
        .ok_or_else(|| format!("no built-in scene {name}"))?
        .map_err(|e| e.to_string())?;
    if let Some(z) = spec
        .boundaries
        .first_mut()
        .and_then(|b| b.z.as_mut())
        .filter(|_| matches!(base, Pulsed | Tabled))
    {
        z.ramp_time = 0.0;
        if base == Pulsed {
            z.pulse = Some(crate::time::time_function::PulseKind::Trapezoid);
            z.duration = Some(1e-5);
            z.rise = Some(2e-6);
        } else {
            z.table = Some(vec![[0.0, 0.0], [2.5e-6, 1.0]]);
        }
    }
    let mut text = to_toml(&spec);
    if base == Zoned {
        text.push_str("\n[[zone]]\nname = \"joint\"\nbodies = [[\"A\", \"B\"]]\n");
    }
    Ok(text)
}

/// The message a scene with the probe's value gets (`None`: accepted).
fn probe(p: &Probe, bases: &mut HashMap<Base, String>) -> Result<Option<String>, String> {
    let text = match bases.get(&p.base) {
        Some(text) => text.clone(),
        None => {
            let text = base_toml(p.base)?;
            bases.insert(p.base, text.clone());
            text
        }
    };
    let mut doc: toml::Table = text.parse().map_err(|e| format!("base scene: {e}"))?;
    let value: toml::Value = toml::from_str::<toml::Table>(&format!("v = {}", p.value))
        .map_err(|e| format!("probe value {}: {e}", p.value))?
        .remove("v")
        .ok_or("probe value")?;
    set(&mut doc, p.path, value)?;
    let text = toml::to_string(&doc).map_err(|e| e.to_string())?;
    // a meshed scene's file lies beside it, in a folder of its own; messages name the scene
    // and its files as if they were in the current folder, so the page is the same everywhere
    let folder = (p.base == Meshed).then(|| {
        std::env::temp_dir().join(format!(
            "lopin-reference-{}-{}",
            std::process::id(),
            p.path.replace(['[', ']', '.'], "_")
        ))
    });
    let source = match &folder {
        Some(dir) => {
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            for (name, content) in [("unit-cube.msh", UNIT_CUBE_MSH), ("scene.toml", &text)] {
                std::fs::write(dir.join(name), content)
                    .map_err(|e| format!("{}: {e}", dir.display()))?;
            }
            dir.join("scene.toml").to_string_lossy().to_string()
        }
        None => "scene.toml".to_string(),
    };
    let outcome = match from_toml(&text, &source) {
        Err(e) => Some(e.to_string()),
        // the table alone: building a granular_poly sample meshes it with gmsh
        Ok(_) if p.base == GranularPoly => None,
        Ok(spec) => crate::scene::problem_of(&spec, &source)
            .err()
            .map(|e| e.to_string()),
    };
    let outcome = match &folder {
        Some(dir) => {
            let _ = std::fs::remove_dir_all(dir);
            let prefix = format!("{}{}", dir.display(), std::path::MAIN_SEPARATOR);
            outcome.map(|m| m.replace(&prefix, ""))
        }
        None => outcome,
    };
    Ok(outcome)
}

/// Sets `a[0].b.c` in a TOML document, creating the last tables as needed.
fn set(doc: &mut toml::Table, path: &str, value: toml::Value) -> Result<(), String> {
    let parts: Vec<&str> = path.split('.').collect();
    let mut table = doc;
    for (i, part) in parts.iter().enumerate() {
        let (name, index) = match part.split_once('[') {
            Some((n, rest)) => (
                n,
                Some(
                    rest.trim_end_matches(']')
                        .parse::<usize>()
                        .map_err(|e| format!("{path}: {e}"))?,
                ),
            ),
            None => (*part, None),
        };
        if i + 1 == parts.len() {
            table.insert(name.to_string(), value);
            return Ok(());
        }
        let entry = table
            .entry(name.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        let next = match (entry, index) {
            (toml::Value::Array(items), Some(k)) => items.get_mut(k),
            (v @ toml::Value::Table(_), None) => Some(v),
            _ => None,
        };
        table = match next {
            Some(toml::Value::Table(t)) => t,
            _ => return Err(format!("{path}: no table at `{part}` in the base scene")),
        };
    }
    Ok(())
}

/// The page: one section per table, one row per key; errors list every key without a rule,
/// rule without a key, and probe that does not do what it says.
pub fn markdown() -> Result<String, String> {
    let keys = schema_keys();
    let rules: BTreeMap<&str, &Rule> = RULES.iter().map(|r| (r.key, r)).collect();
    let mut problems = coverage_problems(&keys, &rules);
    let messages = probe_messages(&mut problems)?;
    if !problems.is_empty() {
        return Err(problems.join("\n"));
    }
    let mut page = String::new();
    page.push_str(HEADER);
    write_key_tables(&mut page, &keys, &rules);
    write_messages(&mut page, &messages);
    Ok(page)
}

/// The keys of the schema without a rule in [`RULES`], then the rules that name no key of the
/// schema, one problem each.
fn coverage_problems(keys: &[SchemaKey], rules: &BTreeMap<&str, &Rule>) -> Vec<String> {
    let mut problems = Vec::new();
    for k in keys {
        if !rules.contains_key(k.key.as_str()) {
            problems.push(format!(
                "key `{}` has no rule in scene::reference::RULES",
                k.key
            ));
        }
    }
    for r in RULES {
        if !keys.iter().any(|k| k.key == r.key) {
            problems.push(format!("rule `{}` names no key of the schema", r.key));
        }
    }
    problems
}

/// Runs the probes of every rule in order: each outside probe with its message (pushing a
/// problem when it is accepted, or when its message names neither the key nor its entry), and
/// each inside probe (pushing a problem when it is refused). An error when a probe cannot be
/// run.
fn probe_messages(problems: &mut Vec<String>) -> Result<Vec<(&'static Probe, String)>, String> {
    // each outside probe with its message, in the rules' order
    let mut messages: Vec<(&Probe, String)> = Vec::new();
    let mut bases = HashMap::new();
    for r in RULES {
        if let Some(p) = &r.outside {
            match probe(p, &mut bases)? {
                Some(m) => {
                    // the key, or its entry when two keys are judged together
                    let last = r.key.rsplit('.').next().unwrap_or(r.key);
                    let entry = p.path.split('.').next().unwrap_or(p.path);
                    if !m.contains(last) && !m.contains(&format!("field `{entry}")) {
                        problems.push(format!(
                            "`{}` = {} gives a message that does not name `{last}`: {m}",
                            p.path, p.value
                        ));
                    }
                    messages.push((p, m));
                }
                None => problems.push(format!(
                    "`{}` = {} is accepted, but the range of `{}` is {}",
                    p.path, p.value, r.key, r.range
                )),
            }
        }
        if let Some(p) = &r.inside {
            if let Some(m) = probe(p, &mut bases)? {
                problems.push(format!(
                    "`{}` = {} is in the range of `{}` ({}) but refused: {m}",
                    p.path, p.value, r.key, r.range
                ));
            }
        }
    }
    Ok(messages)
}

/// Writes one section per table of the schema (its heading, its introduction when it has one,
/// and a table header), one row per key with the unit and range of its rule.
fn write_key_tables(page: &mut String, keys: &[SchemaKey], rules: &BTreeMap<&str, &Rule>) {
    let mut table = "";
    for k in keys {
        if k.table != table {
            table = &k.table;
            let _ = write!(page, "\n## `{table}`\n\n");
            if let Some(intro) = TABLE_INTROS.iter().find(|t| t.0 == table) {
                let _ = write!(page, "{}\n\n", intro.1);
            }
            page.push_str("| key | type | unit | default | allowed | description |\n");
            page.push_str("|---|---|---|---|---|---|\n");
        }
        let rule = rules[k.key.as_str()];
        let _ = writeln!(
            page,
            "| `{}` | {} | {} | {} | {} | {} |",
            k.name,
            k.kind,
            if rule.unit.is_empty() {
                "—"
            } else {
                rule.unit
            },
            k.default,
            rule.range,
            k.description.replace('|', "\\|"),
        );
    }
}

/// Writes the section that quotes, for each outside probe, the value it sets and the message
/// Lopin answers.
fn write_messages(page: &mut String, messages: &[(&Probe, String)]) {
    page.push_str("\n## The message outside the range\n\n");
    page.push_str(
        "Each line sets one key of a valid scene (`two-blocks`, with a `[[zone]]` for the zone \
         keys; `granular-small`; `granular-poly`) to the value shown and quotes what Lopin \
         answers; the `[[mesh_body]]` keys start from a steel unit cube read from a Gmsh file, \
         `unit-cube.msh`, beside a box body `plate`.\n\n",
    );
    for (p, m) in messages {
        let _ = writeln!(
            page,
            "- `{}` = `{}`:\n  `{}`",
            p.path,
            p.value,
            m.replace('`', "'")
        );
    }
}

const HEADER: &str = "# Scene file reference\n\n\
This page is generated by `lopin docs scene` from the scene schema and the validator's ranges; \
a test fails when a key the parser accepts is missing from it or when a range it states is not \
the one the validator applies. `lopin docs schema` prints the same schema as JSON Schema for \
editors.\n\n\
A scene file is TOML. Every table refuses keys it does not know; an array of three numbers must \
have exactly three. Lengths are in metres, times in seconds, stresses in pascals: any consistent \
unit system works if every input uses it (the ranges below are wide enough for dimensionless \
models with E = ρ = 1).\n";

/// A sentence under some tables' headers.
const TABLE_INTROS: &[(&str, &str)] = &[
    (
        "(top level)",
        "The scene's name and the axes `--refine` and `--split` act on.",
    ),
    (
        "[time]",
        "The uniform time grid t_m = m Δt, m = 0 … steps (METHOD §1).",
    ),
    (
        "[solver]",
        "Every key optional; absent keys take the defaults of METHOD §10. The command line's \
         flags of the same names override them.",
    ),
    (
        "[[body]]",
        "A box meshed with hexahedra (or tetrahedra) and cut into substructures.",
    ),
    (
        "[[mesh_body]]",
        "A body taken from one physical volume of a Gmsh file (the tutorial *Bringing a part \
         from CAD* makes one).",
    ),
    (
        "[[interface]]",
        "How two bodies are joined where they touch (default: perfect).",
    ),
    (
        "[[boundary]]",
        "A condition on a face of a box body or a physical surface of a mesh body.",
    ),
    (
        "[boundary.x], [boundary.y], [boundary.z], [boundary.normal]",
        "The prescription on one component: a velocity or a traction, reached through a ramp.",
    ),
    (
        "[[zone]]",
        "Interfaces grouped under a name, whose parameters a study moves apart \
         (`--param f@NAME=…`).",
    ),
    (
        "[granular]",
        "A cube of cells with grains of cells in contact with the matrix; the bodies, interfaces \
         and boundaries are generated and must not be listed.",
    ),
    (
        "[granular_poly]",
        "Polyhedral grains in a cube of matrix, meshed with tetrahedra by gmsh; the bodies, \
         interfaces and boundaries are generated.",
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Every key of the schema has a rule and every probe does what its rule says.
    #[test]
    fn the_reference_covers_every_key_and_its_probes_hold() {
        let page = markdown().unwrap_or_else(|e| panic!("{e}"));
        assert!(page.contains("| `young` |"));
        let keys = schema_keys().len();
        assert!(keys >= 60, "{keys}");
    }
}
