//! Scenes meshed by gmsh: `.geo` scripts of `assets/meshes/` meshed on first use
//! (cached by their content, [`lopin_core::mesh::gmsh`]) and named by scene files of
//! `assets/scenes/gmsh/`. These tests need the `gmsh` program (the README's test command
//! installs it); without it they fail with the message saying how to install it.
//!
//! * `bar-gmsh`: the steel bar (ν = 0) on gmsh's tetrahedra (2.5 mm), cut into 5 substructures
//!   by METIS (3,567 dofs), against d'Alembert: the stress and velocity plateaus within 1 %
//!   (measured −0.27 % and −0.27 %).
//! * `two-blocks-gmsh-hex`: gmsh's transfinite hexahedra are the box scene's 10 × 10 × 5 per
//!   block, so peak normal force and maximum slip equal the box `two-blocks` to 1e-6 (η < 1e-6;
//!   measured 4e-16 and 2e-12).
//! * `two-blocks-gmsh`: gmsh's tetrahedra (4 mm) against the box `two-blocks` on hexahedra:
//!   peak normal force within 3 %, maximum slip within a factor [0.8, 2] (measured 675,123 N
//!   against 663,429 N, +1.8 %; slip 3.67 µm against 3.15 µm, ×1.17).
//! * LATIN on `two-blocks-gmsh` (tetrahedra, contact) against the monolithic reference at
//!   η < 1e-9: within 1e-6 (measured velocity 3.8e-8, force 2.9e-7).
//! * `two-blocks-pads-gmsh`: the contact face as two physical surfaces (`centre`, `rim`), each a
//!   zone: the contact is split in two interfaces that partition the unsplit one, the centre's
//!   lumped area within one node's area of its 4 cm² (measured 4.019 cm², 34 of 149 node
//!   pairs); the slip is the rim's friction's doing (Poisson's mismatch pushes the rim out):
//!   with no friction on the rim and 0.5 at the centre the slip is over 5 times that with 0.5 on
//!   the rim and none at the centre (measured 6.38e-5 m against 7.87e-6 m).

use lopin_core::post;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::study::Target;
use lopin_core::{Settings, Solver};
use lopin_tests::{
    against_reference, assert_same_contact_pairs, contact_pairs, plateau, solve_problem,
};

fn gmsh_scene(name: &str) -> (SceneSpec, String) {
    let path = format!(
        "{}/../assets/scenes/gmsh/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    (scene::load(&path).expect("scene file"), path)
}

fn build(name: &str) -> lopin_core::problem::Problem {
    let (spec, path) = gmsh_scene(name);
    scene::problem_of(&spec, &path).unwrap_or_else(|e| panic!("{e}"))
}

/// Solves at the default settings changed by `tweak`, and checks it converged.
fn solve_converged(
    problem: lopin_core::problem::Problem,
    tweak: impl FnOnce(&mut Settings),
) -> (Solver, lopin_core::Solution) {
    let (solver, sol) = solve_problem(problem, &Default::default(), tweak);
    assert!(sol.converged, "eta {}", sol.eta);
    (solver, sol)
}

/// Peak normal force and maximum slip at η < 1e-6 (one-step windows).
fn contact_quantities(problem: lopin_core::problem::Problem) -> (f64, f64) {
    let (solver, sol) = solve_converged(problem, |s| {
        s.tol = 1e-6;
        s.window = Some(1);
    });
    let contact = post::contact(&solver, &sol);
    let energy = post::energy(&solver, &sol);
    let s = post::Summary::from_histories(&energy, &contact);
    (s.peak_normal_force, s.max_slip)
}

#[test]
fn bar_meshed_by_gmsh_matches_dalembert() {
    let problem = build("bar-gmsh");
    assert_eq!(problem.subs.len(), 5);
    assert!(problem
        .subs
        .iter()
        .all(|s| s.mesh.elements.iter().all(|e| e.nodes().len() == 4)));
    let (solver, sol) = solve_converged(problem, |s| s.tol = 1e-6);
    let steel = solver.problem().materials[0].material;
    let exact = -steel.density * steel.bar_speed() * 10.0;
    let (sigma, v) = plateau(&solver, &sol, 150, 0.005, 0.06);
    let dofs: usize = solver.problem().subs.iter().map(|s| s.ndof()).sum();
    println!(
        "bar-gmsh ({dofs} dofs): sigma {sigma:.5e} (exact {exact:.5e}, rel {:.2e}), v {v:.5} \
         (rel {:.2e}), {} iterations",
        sigma / exact - 1.0,
        v / 10.0 - 1.0,
        sol.iterations
    );
    assert!((sigma / exact - 1.0).abs() < 0.01);
    assert!((v / 10.0 - 1.0).abs() < 0.01);
}

#[test]
fn two_blocks_meshed_by_gmsh_against_the_box_scene() {
    let boxed = scene::registry::builtin("two-blocks").expect("scene");
    let (f_box, slip_box) =
        contact_quantities(scene::problem_of(&boxed, &boxed.name).expect("box scene builds"));
    let (f_hex, slip_hex) = contact_quantities(build("two-blocks-gmsh-hex"));
    let (f_tet, slip_tet) = contact_quantities(build("two-blocks-gmsh"));
    println!(
        "two-blocks peak normal force: box {f_box:.1} N, gmsh hexahedra {f_hex:.1} N ({:+.2e}), \
         gmsh tetrahedra {f_tet:.1} N ({:+.2e}); max slip: box {slip_box:.4e} m, hexahedra \
         {slip_hex:.4e} m ({:+.2e}), tetrahedra {slip_tet:.4e} m (x{:.3})",
        f_hex / f_box - 1.0,
        f_tet / f_box - 1.0,
        slip_hex / slip_box - 1.0,
        slip_tet / slip_box
    );
    assert!((f_hex / f_box - 1.0).abs() < 1e-6);
    assert!((slip_hex / slip_box - 1.0).abs() < 1e-6);
    assert!((f_tet / f_box - 1.0).abs() < 0.03);
    assert!((0.8..2.0).contains(&(slip_tet / slip_box)));
}

#[test]
fn latin_on_gmsh_tetrahedra_equals_the_reference() {
    let (solver, sol) = solve_converged(build("two-blocks-gmsh"), |s| {
        s.tol = 1e-9;
        s.window = None;
        s.max_iter = 20_000;
        s.anderson = 5;
    });
    let c = against_reference(&solver, &sol);
    println!(
        "two-blocks-gmsh vs reference: {} iterations, velocity {:.2e}, force {:.2e}",
        sol.iterations, c.rel_diff_velocity, c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity < 1e-6 && c.rel_diff_force < 1e-6,
        "{c:?}"
    );
}

#[test]
fn zones_on_gmsh_surfaces_split_the_contact_and_the_rim_holds_the_slip() {
    let (mut spec, path) = gmsh_scene("two-blocks-pads-gmsh");
    let split = scene::problem_of(&spec, &path).unwrap_or_else(|e| panic!("{e}"));
    spec.zones.clear();
    let whole = scene::problem_of(&spec, &path).unwrap_or_else(|e| panic!("{e}"));
    let (ps, pw) = (contact_pairs(&split), contact_pairs(&whole));
    let zone = |name: &str| -> Vec<f64> {
        ps.iter()
            .filter(|p| p.interface.ends_with(name))
            .map(|p| p.area)
            .collect()
    };
    let area = |name: &str| -> f64 { zone(name).iter().sum() };
    let (centre, rim) = (area("@centre"), area("@rim"));
    println!(
        "two-blocks-pads-gmsh: {} contact node pairs, centre {} ({centre:.4e} m²), rim {} \
         ({rim:.4e} m²)",
        pw.len(),
        zone("@centre").len(),
        zone("@rim").len()
    );
    assert_same_contact_pairs(&whole, &split);
    assert!((centre + rim - 0.04 * 0.04).abs() < 1e-9 * 0.04 * 0.04);
    let node = ps.iter().fold(0.0f64, |m, p| m.max(p.area));
    assert!(
        (centre - 0.02 * 0.02).abs() <= node,
        "{centre} (a node: {node})"
    );

    let mut settings = Settings::for_problem(&split, &spec.solver);
    settings.window = None;
    let mut solver = Solver::new(split, settings).expect("solver");
    let (c, r) = (
        Target::parse("f@centre", solver.problem()).expect("f@centre"),
        Target::parse("f@rim", solver.problem()).expect("f@rim"),
    );
    let mut slip = |fc: f64, fr: f64| {
        solver.set_parameter_in(c.parameter, c.zone, fc).expect("c");
        solver.set_parameter_in(r.parameter, r.zone, fr).expect("r");
        let sol = solver.solve(None).expect("solve");
        assert!(sol.converged);
        let s = post::Summary::from_histories(
            &post::energy(&solver, &sol),
            &post::contact(&solver, &sol),
        );
        s.max_slip
    };
    let (free_rim, held_rim) = (slip(0.5, 0.0), slip(0.0, 0.5));
    println!(
        "max slip: f@centre 0.5, f@rim 0: {free_rim:.3e} m; f@centre 0, f@rim 0.5: \
         {held_rim:.3e} m"
    );
    assert!(free_rim > 5.0 * held_rim, "{free_rim:e} {held_rim:e}");
}

#[test]
fn a_missing_physical_surface_and_a_broken_script_are_clear_errors() {
    let (mut spec, path) = gmsh_scene("two-blocks-gmsh");
    spec.boundaries[0].surface = Some("lid".into());
    let e = scene::problem_of(&spec, &path)
        .expect_err("unknown surface")
        .to_string();
    assert!(
        e.contains("two-blocks-gmsh.toml")
            && e.contains("boundary[0].surface")
            && e.contains("lid"),
        "{e}"
    );
    let dir = std::env::temp_dir().join(format!("lopin-gmsh-broken-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let geo = dir.join("broken.geo");
    std::fs::write(&geo, "Box(1) = {0, 0, 0, 1, 1;\n").expect("write");
    let e = lopin_core::mesh::gmsh::mesh_geo_file(&geo)
        .expect_err("a broken script does not mesh")
        .to_string();
    assert!(e.contains("broken.geo") && e.contains("gmsh failed"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two boxes meshed apart (not fragmented) and shifted by half a block: their faces overlap
/// without sharing nodes and are joined by a non-matching interface over the overlap (less the
/// side-1 triangles that straddle its edge, left out); and a time step far too large for gmsh's
/// elements is an error naming `time.dt` and the body.
#[test]
fn non_matching_faces_are_joined_and_an_absurd_time_step_is_a_clear_error() {
    let dir = std::env::temp_dir().join(format!("lopin-gmsh-nonmatching-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let geo = std::fs::read_to_string(format!(
        "{}/../assets/meshes/two-blocks-tet.geo",
        env!("CARGO_MANIFEST_DIR")
    ))
    .expect("geo");
    let shifted = geo
        .replace(
            "Box(2) = {0, 0, 0.02, 0.04, 0.04, 0.02};",
            "Box(2) = {0.02, 0, 0.02, 0.04, 0.04, 0.02};",
        )
        .replace(
            "BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }",
            "",
        )
        .replace(
            "0.04 + e, 0.04 + e, 0.04 + e",
            "0.06 + e, 0.04 + e, 0.04 + e",
        )
        .replace(
            "Volume In BoundingBox{-e, -e, 0.02 - e",
            "Volume In BoundingBox{0.02 - e, -e, 0.02 - e",
        );
    std::fs::write(dir.join("apart.geo"), shifted).expect("write geo");
    let (scene_text, _) = gmsh_scene("two-blocks-gmsh");
    let mut spec = scene_text;
    for b in &mut spec.mesh_bodies {
        b.mesh = "apart.geo".into();
    }
    spec.interfaces.clear();
    let path = dir.join("apart.toml");
    std::fs::write(&path, scene::to_toml(&spec)).expect("write scene");
    let path = path.display().to_string();
    let loaded = scene::load(&path).expect("loads");
    let problem = match scene::problem_of(&loaded, &path) {
        Ok(p) => p,
        Err(e) => panic!("a non-matching interface: {e}"),
    };
    let joined: Vec<_> = problem
        .interfaces
        .iter()
        .filter(|i| !i.is_boundary())
        .collect();
    assert_eq!(joined.len(), 1);
    assert!(joined[0].sides[1].projection.is_some());
    let overlap = 0.02 * 0.04;
    let area: f64 = joined[0].area.iter().step_by(3).sum();
    println!("apart: interface area {area:.4e} m² of the {overlap:.4e} m² overlap");
    assert!(
        area <= overlap * (1.0 + 1e-9) && area > 0.8 * overlap,
        "{area}"
    );
    let (mut spec, path) = gmsh_scene("two-blocks-gmsh");
    spec.time.dt = 1.0;
    let e = scene::problem_of(&spec, &path)
        .expect_err("absurd dt")
        .to_string();
    assert!(e.contains("time.dt") && e.contains("mesh body"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
