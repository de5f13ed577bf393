//! Zones by physical surface (`model/src/interfaces/zone.rs`, `model/src/interfaces/surface_groups.rs`): a
//! zone naming physical surfaces of a Gmsh mesh holds the contact interfaces on them, the
//! contact between two bodies being split by surface. A column of two steel cubes (2 cm, 4 × 4
//! × 4 cells of six tetrahedra each, an MSH 4.1 file), in frictional contact on the face between
//! them, whose two halves are the physical surfaces `left` (x < 1 cm) and `right`; clamped at
//! the bottom, the top pushed down and sideways:
//! * the split contact is a partition of the unsplit one: the same node pairs, each with the
//!   same lumped area, normal and gap; the 5 nodes of the line x = 1 cm are dealt so that each
//!   zone's area is within one node's area of its half of the face (`left` 10 + 3 nodes,
//!   `right` 10 + 2);
//! * the same friction in both zones is the unsplit contact's solution (to 1e-9 at η < 1e-10);
//! * f = 0.1 on `left` and 0.5 on `right` agrees with the monolithic reference of the same
//!   problem to 1e-6 (LATIN at η < 1e-9), and its friction work lies between the uniform runs';
//! * a surface no mesh file defines, or one that holds no contact, is refused naming the field.

use lopin_core::interfaces::interface::Law;
use lopin_core::problem::Problem;
use lopin_core::scene;
use lopin_core::study::Target;
use lopin_core::{dissipation, post, Settings, Solver};
use lopin_tests::msh_writer::{stacked_cubes, write};
use lopin_tests::{
    assert_same_contact_pairs, contact_pairs, two_frictions_against_reference_and_uniform,
};

const SIZE: f64 = 0.02;
const CELLS: usize = 4;

const SCENE: &str = r#"
name = "pads"

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
mesh = "pads.msh"

[[mesh_body]]
name = "upper"
material = "steel"
mesh = "pads.msh"

[[interface]]
bodies = ["lower", "upper"]
kind = "contact"
friction = 0.3
gap = 0.0

[[boundary]]
body = "lower"
surface = "bottom"
clamped = true

[[boundary]]
body = "upper"
surface = "top"
z = { velocity = -2.0, ramp = "cosine", ramp_time = 2e-6 }
x = { velocity = 1.5, ramp = "cosine", ramp_time = 2e-6 }

[[zone]]
name = "left"
surfaces = ["left"]

[[zone]]
name = "right"
surfaces = ["right"]
"#;

/// The column of [`stacked_cubes`] with the face between the cubes as two physical surfaces,
/// `left` (x < SIZE / 2, tag 5) and `right` (tag 6), in triangles of the tetrahedra's faces.
fn pads_msh() -> Vec<u8> {
    let mut d = stacked_cubes(CELLS, SIZE);
    let nx = CELLS + 1;
    let tag = |i: usize, j: usize| (1 + i + nx * (j + nx * CELLS)) as u64;
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for j in 0..CELLS {
        for i in 0..CELLS {
            let (a, b, c, e) = (tag(i, j), tag(i + 1, j), tag(i + 1, j + 1), tag(i, j + 1));
            let half = if 2 * i < CELLS { &mut left } else { &mut right };
            half.push(vec![a, b, c]);
            half.push(vec![a, c, e]);
        }
    }
    d.physical_names.push((2, 5, "left".into()));
    d.physical_names.push((2, 6, "right".into()));
    d.surfaces.push((3, vec![5]));
    d.surfaces.push((4, vec![6]));
    d.blocks.insert(0, (2, 3, 2, left));
    d.blocks.insert(1, (2, 4, 2, right));
    write(&d, true)
}

/// The scene file (with `text` as its content) beside the mesh, in a folder of its own (the
/// tests run at once), and its path.
fn scene_file(text: &str, name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("lopin-pads-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(dir.join("pads.msh"), pads_msh()).expect("msh");
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("scene");
    path.display().to_string()
}

fn build(text: &str, name: &str) -> std::result::Result<Problem, String> {
    let path = scene_file(text, name);
    scene::load(&path)
        .and_then(|s| scene::problem_of(&s, &path))
        .map_err(|e| e.to_string())
}

fn solver(problem: Problem, tol: f64) -> Solver {
    let mut settings = Settings::for_problem(&problem, &Default::default());
    settings.tol = tol;
    settings.max_iter = 20_000;
    Solver::new(problem, settings).expect("solver")
}

#[test]
fn zones_on_physical_surfaces_split_the_contact_and_move_their_own_friction() {
    let unzoned = SCENE[..SCENE.find("[[zone]]").expect("zones")].to_string();
    let whole = build(&unzoned, "whole").expect("builds without zones");
    let split = build(SCENE, "split").expect("builds with zones");
    let contacts = |p: &Problem| -> Vec<(String, usize)> {
        p.interfaces
            .iter()
            .filter(|i| matches!(i.law, Law::Contact(_)))
            .map(|i| (i.name.clone(), i.sides[0].nodes.len()))
            .collect()
    };
    println!(
        "unsplit {:?}, split {:?}",
        contacts(&whole),
        contacts(&split)
    );
    assert_eq!(contacts(&whole), vec![("lower|upper".to_string(), 25)]);
    assert_eq!(
        contacts(&split),
        vec![
            ("lower|upper@left".to_string(), 13),
            ("lower|upper@right".to_string(), 12)
        ]
    );
    // a partition of the unsplit contact: the same pairs, areas, normals and gaps
    assert_same_contact_pairs(&whole, &split);
    let pairs = contact_pairs(&split);
    let area: f64 = pairs.iter().map(|p| p.area).sum();
    assert!((area - SIZE * SIZE).abs() < 1e-12 * SIZE * SIZE, "{area}");
    let node = pairs.iter().fold(0.0f64, |m, p| m.max(p.area));
    for iface in split
        .interfaces
        .iter()
        .filter(|i| matches!(i.law, Law::Contact(_)))
    {
        let a: f64 = iface.area.iter().step_by(3).sum();
        println!(
            "{}: {a:.4e} m² (half the face: {:.4e} m²)",
            iface.name,
            SIZE * SIZE / 2.0
        );
        assert!(
            (a - SIZE * SIZE / 2.0).abs() <= node,
            "{a} (a node: {node})"
        );
    }
    let zones = &split.zones;
    assert_eq!(zones.len(), 2);
    assert_eq!(zones[0].contacts.len(), 1, "{zones:?}");
    assert_eq!(zones[1].contacts.len(), 1, "{zones:?}");
    assert_ne!(zones[0].contacts, zones[1].contacts);
    assert!(zones.iter().all(|z| z.boundaries.is_empty()), "{zones:?}");

    // one friction in both zones: the unsplit contact's solution
    let mut w = solver(whole, 1e-10);
    let ws = w.solve(None).expect("unsplit");
    let mut s = solver(split, 1e-10);
    let left = Target::parse("f@left", s.problem()).expect("f@left");
    let right = Target::parse("f@right", s.problem()).expect("f@right");
    let ss = s.solve(None).expect("split");
    assert!(ws.converged && ss.converged);
    let (ew, es) = (post::energy(&w, &ws), post::energy(&s, &ss));
    let worst = (0..ew.kinetic.len())
        .map(|m| (ew.total(m) - es.total(m)).abs() / ew.input_work[ew.kinetic.len() - 1])
        .fold(0.0f64, f64::max);
    let (fw, fs) = (
        dissipation::contact_work(&w, &ws).friction,
        dissipation::contact_work(&s, &ss).friction,
    );
    println!(
        "f = 0.3 everywhere: {} iterations unsplit, {} split; energies differ by {worst:.2e} of \
         the input work, friction work {fw:.6e} J against {fs:.6e} J",
        ws.iterations, ss.iterations
    );
    assert!(worst < 1e-9, "{worst:e}");
    assert!((fw - fs).abs() < 1e-9 * fw.abs(), "{fw} {fs}");

    // its own friction per zone: the reference agrees
    let mut settings = *s.settings();
    settings.tol = 1e-9;
    s.set_settings(settings).expect("settings");
    two_frictions_against_reference_and_uniform(&mut s, [(&left, 0.1), (&right, 0.5)]);
}

#[test]
fn a_zone_on_an_unknown_surface_or_one_without_contact_is_refused() {
    // the scene with the zone `right` on `surfaces` instead
    let right_on = |surfaces: &str, name: &str| {
        build(
            &SCENE.replacen(
                "surfaces = [\"right\"]",
                &format!("surfaces = {surfaces}"),
                1,
            ),
            name,
        )
    };
    let e = right_on(r#"["middle"]"#, "unknown").expect_err("unknown surface");
    println!("{e}");
    assert!(
        e.contains("zone[1].surfaces[0]")
            && e.contains("`middle`")
            && e.contains("left")
            && e.contains("bottom"),
        "{e}"
    );
    let e = right_on(r#"["bottom"]"#, "empty").expect_err("no contact on the surface");
    println!("{e}");
    assert!(
        e.contains("zone[1].surfaces") && e.contains("holds no contact interface"),
        "{e}"
    );
    // the prescribed velocity of the surface `top` is a zone's v0
    let p = right_on(r#"["right", "top"]"#, "top").expect("builds");
    assert_eq!(p.zones[1].contacts.len(), 1, "{:?}", p.zones);
    assert_eq!(p.zones[1].boundaries.len(), 1, "{:?}", p.zones);
}
