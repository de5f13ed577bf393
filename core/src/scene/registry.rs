//! The built-in scenes of SCENES.md, in one registry shared by the command line, the explorer,
//! the web build, the tests and the benchmarks. Each has a TOML twin in `assets/scenes/`.

use crate::scene::spec::{
    BodySpec, BoundarySpec, ComponentSpec, InterfaceKind, InterfaceSpec, MaterialSpec, SceneSpec,
    SolverSpec,
};
use crate::time_function::TimeGrid;

/// Names of the built-in scenes, in display order.
pub const SCENES: [&str; 4] = ["bar", "bar-bimaterial", "two-blocks", "gap-impact"];

/// The built-in scene of that name.
pub fn builtin(name: &str) -> Option<SceneSpec> {
    match name {
        "bar" => Some(bar()),
        "bar-bimaterial" => Some(bar_bimaterial()),
        "two-blocks" => Some(two_blocks()),
        "gap-impact" => Some(gap_impact()),
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
