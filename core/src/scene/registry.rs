//! The built-in scenes of SCENES.md, in one registry shared by the command line, the explorer,
//! the web build, the tests and the benchmarks. Each has a TOML twin in `assets/scenes/`.

use crate::scene::granular::GranularSpec;
use crate::scene::spec::{
    BodySpec, BoundarySpec, ComponentSpec, InterfaceKind, InterfaceSpec, MaterialSpec, SceneSpec,
    SolverSpec,
};
use crate::time_function::TimeGrid;

/// Names of the built-in scenes, in display order.
pub const SCENES: [&str; 6] = [
    "bar",
    "bar-bimaterial",
    "two-blocks",
    "gap-impact",
    "granular-small",
    "granular-paper",
];

/// Built-in scenes too large for the test suite's solves and the explorer's scene picker
/// (`granular-paper`: 648 substructures, about 1 million dofs, about 1 GB to build).
pub const LARGE: [&str; 1] = ["granular-paper"];

/// Whether a built-in scene is too large to solve in the tests or to offer in the explorer.
pub fn is_large(name: &str) -> bool {
    LARGE.contains(&name)
}

/// The built-in scene of that name.
pub fn builtin(name: &str) -> Option<SceneSpec> {
    match name {
        "bar" => Some(bar()),
        "bar-bimaterial" => Some(bar_bimaterial()),
        "two-blocks" => Some(two_blocks()),
        "gap-impact" => Some(gap_impact()),
        "granular-small" => Some(granular_small()),
        "granular-paper" => Some(granular_paper()),
        _ => None,
    }
}

fn material(name: &str, young: f64, poisson: f64, density: f64) -> MaterialSpec {
    MaterialSpec {
        name: name.into(),
        young,
        poisson,
        density,
    }
}

fn body(
    name: &str,
    material: &str,
    min: [f64; 3],
    max: [f64; 3],
    divisions: [usize; 3],
) -> BodySpec {
    BodySpec {
        name: name.into(),
        material: material.into(),
        min,
        max,
        divisions,
        split: [1, 1, 1],
        velocity: [0.0; 3],
    }
}

fn clamped(body: &str, face: &str) -> BoundarySpec {
    BoundarySpec {
        body: body.into(),
        face: face.into(),
        clamped: true,
        x: None,
        y: None,
        z: None,
    }
}

fn pushed_x(body: &str) -> BoundarySpec {
    BoundarySpec {
        body: body.into(),
        face: "x-".into(),
        clamped: false,
        x: Some(ComponentSpec::velocity(10.0, 2e-6)),
        y: None,
        z: None,
    }
}

/// `bar`: steel bar 0.10 × 0.01 × 0.01 m, 5 substructures, pushed at x = 0.
fn bar() -> SceneSpec {
    let mut b = body("bar", "steel", [0.0; 3], [0.1, 0.01, 0.01], [20, 1, 1]);
    b.split = [5, 1, 1];
    SceneSpec {
        name: "bar".into(),
        description: "1D check: steel bar (nu = 0) pushed at x = 0, 5 substructures".into(),
        refine_axes: "x".into(),
        split_axes: "x".into(),
        time: TimeGrid {
            dt: 1e-7,
            steps: 150,
        },
        solver: SolverSpec::default(),
        materials: vec![material("steel", 210e9, 0.0, 7800.0)],
        granular: None,
        bodies: vec![b],
        interfaces: vec![],
        boundaries: vec![pushed_x("bar")],
    }
}

/// `bar-bimaterial`: steel for x < 0.05, aluminium beyond; the material change is an interface
/// (2 + 2 substructures of 0.025 m, so that no substructure holds two materials).
fn bar_bimaterial() -> SceneSpec {
    let mut steel = body("steel", "steel", [0.0; 3], [0.05, 0.01, 0.01], [10, 1, 1]);
    steel.split = [2, 1, 1];
    let mut al = body(
        "aluminium",
        "aluminium",
        [0.05, 0.0, 0.0],
        [0.1, 0.01, 0.01],
        [10, 1, 1],
    );
    al.split = [2, 1, 1];
    SceneSpec {
        name: "bar-bimaterial".into(),
        description: "1D check: steel then aluminium bar (nu = 0), wave transmission".into(),
        refine_axes: "x".into(),
        split_axes: "x".into(),
        time: TimeGrid {
            dt: 1e-7,
            steps: 150,
        },
        solver: SolverSpec::default(),
        materials: vec![
            material("steel", 210e9, 0.0, 7800.0),
            material("aluminium", 70e9, 0.0, 2700.0),
        ],
        granular: None,
        bodies: vec![steel, al],
        interfaces: vec![],
        boundaries: vec![pushed_x("steel")],
    }
}

/// `two-blocks`: the seed paper's study, steel on aluminium with frictional contact.
fn two_blocks() -> SceneSpec {
    SceneSpec {
        name: "two-blocks".into(),
        description: "steel block on aluminium block, frictional contact, shock on top".into(),
        refine_axes: "xyz".into(),
        split_axes: "xy".into(),
        time: TimeGrid {
            dt: 0.25e-6,
            steps: 60,
        },
        solver: SolverSpec::default(),
        materials: vec![
            material("steel", 210e9, 0.30, 7800.0),
            material("aluminium", 70e9, 0.33, 2700.0),
        ],
        granular: None,
        bodies: vec![
            body(
                "A",
                "steel",
                [0.0, 0.0, 0.02],
                [0.04, 0.04, 0.04],
                [10, 10, 5],
            ),
            body("B", "aluminium", [0.0; 3], [0.04, 0.04, 0.02], [10, 10, 5]),
        ],
        interfaces: vec![InterfaceSpec {
            bodies: ["A".into(), "B".into()],
            kind: InterfaceKind::Contact,
            friction: Some(0.3),
            gap: Some(0.0),
            search: None,
        }],
        boundaries: vec![
            BoundarySpec {
                body: "A".into(),
                face: "z+".into(),
                clamped: false,
                x: None,
                y: None,
                z: Some(ComponentSpec::velocity(-10.0, 2.5e-6)),
            },
            clamped("B", "z-"),
        ],
    }
}

/// `gap-impact`: a steel cube falls across a 0.1 mm gap onto a clamped aluminium cube.
fn gap_impact() -> SceneSpec {
    let mut a = body(
        "A",
        "steel",
        [0.0, 0.0, 0.0201],
        [0.02, 0.02, 0.0401],
        [5, 5, 5],
    );
    a.velocity = [0.0, 0.0, -5.0];
    SceneSpec {
        name: "gap-impact".into(),
        description: "steel cube falls 0.1 mm onto an aluminium cube: contact closes and opens"
            .into(),
        refine_axes: "xyz".into(),
        split_axes: "xy".into(),
        time: TimeGrid {
            dt: 0.25e-6,
            steps: 200,
        },
        solver: SolverSpec::default(),
        materials: vec![
            material("steel", 210e9, 0.30, 7800.0),
            material("aluminium", 70e9, 0.33, 2700.0),
        ],
        granular: None,
        bodies: vec![
            a,
            body("B", "aluminium", [0.0; 3], [0.02, 0.02, 0.02], [5, 5, 5]),
        ],
        interfaces: vec![InterfaceSpec {
            bodies: ["A".into(), "B".into()],
            kind: InterfaceKind::Contact,
            friction: Some(0.2),
            gap: None,
            search: Some(2e-4),
        }],
        boundaries: vec![clamped("B", "z-")],
    }
}

/// The materials of the `granular` scenes: a concrete-like matrix and stiffer grains.
fn granular_materials() -> Vec<MaterialSpec> {
    vec![
        material("matrix", 30e9, 0.2, 2400.0),
        material("grain", 70e9, 0.25, 2700.0),
    ]
}

/// A `granular` scene (SCENES.md): the bodies, interfaces and boundaries come from the table.
fn granular(name: &str, description: &str, time: TimeGrid, table: GranularSpec) -> SceneSpec {
    SceneSpec {
        name: name.into(),
        description: description.into(),
        refine_axes: "xyz".into(),
        split_axes: "xy".into(),
        time,
        solver: SolverSpec::default(),
        materials: granular_materials(),
        granular: Some(table),
        bodies: vec![],
        interfaces: vec![],
        boundaries: vec![],
    }
}

/// `granular-small`: a 0.1 m cube of 4 × 4 × 4 cells (3 × 3 × 3 hexahedra each) with 6 grains
/// of 1 to 3 cells, pressed at 10 m/s on top.
fn granular_small() -> SceneSpec {
    granular(
        "granular-small",
        "cube of 4 x 4 x 4 cells, 6 stiff grains in contact (f = 0.3) with the matrix, pressed on top",
        TimeGrid {
            dt: 1e-6,
            steps: 40,
        },
        GranularSpec::new(0.1, [4, 4, 4], 3, 6, "matrix", "grain"),
    )
}

/// `granular-paper`: the seed paper's size, a 0.5 m cube of 9 × 9 × 8 cells (648 substructures of
/// 7 × 7 × 7 hexahedra, about 1 million dofs) with 50 grains of 2 cells.
fn granular_paper() -> SceneSpec {
    let mut table = GranularSpec::new(0.5, [9, 9, 8], 7, 50, "matrix", "grain");
    table.grain_cells = [2, 2];
    granular(
        "granular-paper",
        "the seed paper's size: 648 cells, 50 grains of 2 cells, about 1 million dofs",
        TimeGrid {
            dt: 2.5e-6,
            steps: 100,
        },
        table,
    )
}
