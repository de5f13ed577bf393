//! Bodies from a Gmsh file: the physical volumes of one MSH file become bodies whose
//! shared nodes are copied into each (`MshMesh::body_mesh`), so interface detection pairs them
//! on their common face as a perfect interface; a boundary condition holds on a physical surface
//! (`MshMesh::surface_selector`, `detect::boundary_interface_on`); and the model solves like a
//! built-in one.
//!
//! A column of two steel cubes (2 cm, 2 × 2 × 2 cells of six tetrahedra each, written as an MSH
//! 4.1 file in both encodings), clamped at the bottom and pushed down on top at 1 m/s (cosine
//! ramp over 2 µs):
//! * LATIN at η < 1e-9 against the monolithic reference of the same problem: within 1e-6;
//! * against the built-in box of the same column on tetrahedra (`elements = "tet4"`, split in
//!   two substructures along z), the same discrete problem: velocities and energies equal to
//!   1e-9 relative.

use lopin_core::elements::material::Material;
use lopin_core::interfaces::detect::{
    assemble_traces, boundary_interface, boundary_interface_on, detect_interfaces, PairRule,
};
use lopin_core::interfaces::interface::{BoundaryDof, BoundaryLoad, DofLaw};
use lopin_core::mesh::msh;
use lopin_core::problem::{NamedMaterial, Problem};
use lopin_core::scene;
use lopin_core::scene::spec::{ComponentSpec, ElementKind};
use lopin_core::substructure::Substructure;
use lopin_core::time::time_function::{Ramp, TimeFunction, TimeGrid};
use lopin_core::time::time_scheme::TimeScheme;
use lopin_core::{post, Solver};
use lopin_tests::msh_writer::{stacked_cubes, write};
use lopin_tests::{against_reference, solve_problem};

const SIZE: f64 = 0.02;

fn steel() -> Material {
    Material {
        young: 210e9,
        poisson: 0.3,
        density: 7800.0,
        damping: Default::default(),
    }
}

/// The problem of the column read from an MSH file.
fn problem_from_file(binary: bool) -> Problem {
    let m = msh::parse(&write(&stacked_cubes(2, SIZE), binary), "column.msh").expect("reads");
    let (lower, lower_nodes) = m.body("lower").expect("physical volume");
    let upper = m.body_mesh("upper").expect("physical volume");
    let mut subs: Vec<Substructure> = [("lower", lower), ("upper", upper)]
        .into_iter()
        .map(|(name, mesh)| {
            Substructure::assemble(name.into(), name.into(), 0, mesh, steel(), [0.0; 3])
        })
        .collect();
    // shared nodes are copied: each body has its own (3 × 3 × 3 nodes)
    assert!(subs.iter().all(|s| s.mesh.nodes.len() == 27));
    let mut interfaces = detect_interfaces(&subs, &|_, _| PairRule::Perfect).expect("detects");
    assert_eq!(
        interfaces.len(),
        1,
        "one perfect interface on the shared face"
    );
    assert_eq!(interfaces[0].sides[0].nodes.len(), 9);
    let clamp = BoundaryLoad::Components(
        (0..3)
            .map(|component| {
                BoundaryDof::new(component, DofLaw::Velocity(TimeFunction::constant(0.0)))
            })
            .collect(),
    );
    // the clamp on the physical surface `bottom`, found by its facets
    let bottom = m
        .surface_selector("bottom", &lower_nodes)
        .expect("physical surface");
    let clamped = boundary_interface_on(&subs, 0, &bottom, &clamp, "lower:bottom".into())
        .expect("the bottom surface");
    // the same nodes as the plane z = 0 selects, with the same lumped areas
    let plane = boundary_interface(&subs, 0, 2, -1.0, 0.0, &clamp, "plane".into()).expect("plane");
    assert_eq!(clamped.sides[0].nodes, plane.sides[0].nodes);
    assert_eq!(clamped.area, plane.area);
    assert_eq!(clamped.sides[0].nodes.len(), 3 * 9);
    interfaces.push(clamped);
    let push = BoundaryLoad::Components(vec![BoundaryDof::new(
        2,
        DofLaw::Velocity(TimeFunction::ramp(-1.0, Ramp::Cosine, 2e-6)),
    )]);
    interfaces.push(
        boundary_interface(&subs, 1, 2, 1.0, 2.0 * SIZE, &push, "upper:top".into())
            .expect("the top face"),
    );
    assemble_traces(&mut subs, &mut interfaces);
    let mut p = Problem {
        name: "column".into(),
        materials: vec![NamedMaterial {
            name: "steel".into(),
            material: steel(),
        }],
        subs,
        interfaces,
        time: TimeGrid {
            dt: 0.25e-6,
            steps: 40,
        },
        scheme: TimeScheme::new(1.0),
        load_signs: Vec::new(),
        zones: Vec::new(),
        statics: false,
    };
    p.record_load_signs();
    p
}

fn tight(problem: Problem) -> (Solver, lopin_core::Solution) {
    let (solver, sol) = solve_problem(problem, &Default::default(), |s| {
        s.tol = 1e-9;
        s.window = None;
        s.max_iter = 20_000;
    });
    assert!(sol.converged, "eta {}", sol.eta);
    (solver, sol)
}

/// Largest difference of the total energy histories of two solves, relative to the largest
/// total energy of the second.
fn energy_difference(
    (sa, a): (&Solver, &lopin_core::Solution),
    (sb, b): (&Solver, &lopin_core::Solution),
) -> f64 {
    let (ea, eb) = (post::energy(sa, a), post::energy(sb, b));
    let steps = sb.problem().time.steps;
    let scale = (0..=steps)
        .map(|m| eb.total(m).abs())
        .fold(0.0f64, f64::max);
    assert!(scale > 0.0);
    (0..=steps)
        .map(|m| (ea.total(m) - eb.total(m)).abs() / scale)
        .fold(0.0f64, f64::max)
}

#[test]
fn bodies_from_a_gmsh_file_solve_against_the_reference() {
    let ascii = problem_from_file(false);
    assert_eq!(ascii.dof_count(), problem_from_file(true).dof_count());
    let (solver, sol) = tight(ascii);
    let c = against_reference(&solver, &sol);
    println!(
        "column from MSH: {} iterations; against the reference: velocity {:.2e}, force {:.2e}",
        sol.iterations, c.rel_diff_velocity, c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity < 1e-6 && c.rel_diff_force < 1e-6,
        "{c:?}"
    );
}

#[test]
fn bodies_from_a_gmsh_file_equal_the_built_in_box_on_tetrahedra() {
    let (file_solver, file_sol) = tight(problem_from_file(true));
    // the same column as a built-in box: one body split in two substructures along z
    let mut spec = scene::registry::builtin("mini-bar").expect("scene");
    spec.name = "column".into();
    spec.time = TimeGrid {
        dt: 0.25e-6,
        steps: 40,
    };
    spec.materials.truncate(1);
    spec.materials[0].name = "steel".into();
    (
        spec.materials[0].young,
        spec.materials[0].poisson,
        spec.materials[0].density,
    ) = (210e9, 0.3, 7800.0);
    let b = &mut spec.bodies[0];
    b.material = "steel".into();
    (b.min, b.max) = ([0.0; 3], [SIZE, SIZE, 2.0 * SIZE]);
    (b.divisions, b.split) = ([2, 2, 4], [1, 1, 2]);
    b.velocity = [0.0; 3];
    b.elements = Some(ElementKind::Tet4);
    spec.boundaries.truncate(1);
    let bc = &mut spec.boundaries[0];
    bc.face = "z-".into();
    (bc.x, bc.y, bc.z, bc.clamped) = (None, None, None, true);
    let mut top = bc.clone();
    top.face = "z+".into();
    top.clamped = false;
    top.z = Some(ComponentSpec::velocity(-1.0, 2e-6));
    spec.boundaries.push(top);
    let problem = scene::problem_of(&spec, "column").expect("builds");
    let (box_solver, box_sol) = tight(problem);
    let worst = energy_difference((&file_solver, &file_sol), (&box_solver, &box_sol));
    let (vf, vb) = (
        post::velocity_history(&file_solver, &file_sol),
        post::velocity_history(&box_solver, &box_sol),
    );
    // the peak speed of every substructure at every step
    let peak = |h: &Vec<Vec<Vec<f64>>>, m: usize, s: usize| {
        h[m][s].iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };
    let dv = (0..=40)
        .flat_map(|m| (0..2).map(move |s| (m, s)))
        .map(|(m, s)| (peak(&vf, m, s) - peak(&vb, m, s)).abs())
        .fold(0.0f64, f64::max);
    println!(
        "column from MSH against the built-in box: energy {worst:.2e}, peak speeds {dv:.2e} m/s"
    );
    assert!(worst < 1e-9, "energy histories differ by {worst:e}");
    assert!(dv < 1e-9, "peak speeds differ by {dv:e} m/s");
}

const COLUMN_SCENE: &str = r#"
name = "column"

[time]
dt = 0.25e-6
steps = 40

[[material]]
name = "steel"
young = 210e9
poisson = 0.3
density = 7800.0

[[mesh_body]]
name = "lower"
material = "steel"
mesh = "column.msh"

[[mesh_body]]
name = "upper"
material = "steel"
mesh = "column.msh"

[[boundary]]
body = "lower"
surface = "bottom"
clamped = true

[[boundary]]
body = "upper"
surface = "top"
z = { velocity = -1.0, ramp = "cosine", ramp_time = 2e-6 }
"#;

/// A scene file naming the physical volumes of an MSH file beside it (`[[mesh_body]]`, the
/// boundary conditions on its physical surfaces) builds the same problem as the library calls
/// above: the same solution to 1e-12.
#[test]
fn a_scene_file_takes_bodies_and_surfaces_from_a_gmsh_file() {
    let dir = std::env::temp_dir().join(format!("lopin-msh-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(dir.join("column.msh"), write(&stacked_cubes(2, SIZE), true)).expect("msh");
    let scene_path = dir.join("column.toml");
    std::fs::write(&scene_path, COLUMN_SCENE).expect("scene");
    let path = scene_path.display().to_string();
    let spec = scene::load(&path).expect("loads");
    let problem = scene::problem_of(&spec, &path).expect("builds");
    assert_eq!(problem.subs.len(), 2);
    assert_eq!(
        problem.interfaces.len(),
        3,
        "the shared face and two boundaries"
    );
    let (scene_solver, scene_sol) = tight(problem);
    let (lib_solver, lib_sol) = tight(problem_from_file(true));
    let worst = energy_difference((&scene_solver, &scene_sol), (&lib_solver, &lib_sol));
    println!("column scene file against the library calls: energy {worst:.2e}");
    assert!(worst < 1e-12, "{worst:e}");
    assert_eq!(scene_sol.iterations, lib_sol.iterations);

    // bad input names the scene file, the field and the reason
    let bad = |text: String| {
        std::fs::write(&scene_path, text).expect("scene");
        let e = scene::load(&path)
            .and_then(|s| scene::problem_of(&s, &path))
            .expect_err("refused")
            .to_string();
        println!("{e}");
        assert!(e.starts_with(&path), "{e}");
        e
    };
    let e = bad(COLUMN_SCENE.replacen("mesh = \"column.msh\"", "mesh = \"nothere.msh\"", 1));
    assert!(
        e.contains("mesh_body[0].mesh") && e.contains("nothere.msh"),
        "{e}"
    );
    let e = bad(COLUMN_SCENE.replacen(
        "name = \"upper\"\nmaterial = \"steel\"\nmesh = \"column.msh\"",
        "name = \"upper\"\nmaterial = \"steel\"\nmesh = \"column.msh\"\nvolume = \"matrix\"",
        1,
    ));
    assert!(
        e.contains("mesh_body[1].volume") && e.contains("`matrix`") && e.contains("lower"),
        "{e}"
    );
    let e = bad(COLUMN_SCENE.replacen("surface = \"top\"", "surface = \"lid\"", 1));
    assert!(
        e.contains("boundary[1].surface") && e.contains("`lid`"),
        "{e}"
    );
    let e = bad(COLUMN_SCENE.replacen("surface = \"bottom\"", "face = \"z-\"", 1));
    assert!(
        e.contains("boundary[0].surface") && e.contains("mesh body"),
        "{e}"
    );
    // the physical surface `top` lies on `upper`, not on `lower`
    let e = bad(COLUMN_SCENE.replacen(
        "body = \"upper\"\nsurface = \"top\"",
        "body = \"lower\"\nsurface = \"top\"",
        1,
    ));
    assert!(
        e.contains("boundary[1].surface") && e.contains("no face"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
