//! The polyhedral granular material (`[granular_poly]`), meshed by gmsh (the README's
//! test command installs it):
//!
//! * `granular-poly` builds as the table says: a matrix cut into 8 substructures by METIS and
//!   one substructure per grain, every grain in frictional contact with the matrix, at most
//!   30,000 dofs; it solves at its default settings with the energy balance kept
//!   (E ≤ E0 + input work within 1e-3) and contact gaps closed to the tolerance's scale.
//! * A small sample (3 grains, 15 mm tetrahedra, the matrix in 4 parts, ρ∞ = 0.5, 20 steps):
//!   LATIN at η < 1e-9 against the monolithic reference, within 1e-7 (measured: velocity
//!   7.9e-9, force 3.2e-9, in 910 whole-interval iterations).
//! * Where a cut between matrix parts meets a grain, the grain's nodes lie on two contacts or
//!   more: every one gives them the same normal, the same with the matrix in 8 or 16 parts;
//!   with it, `granular-poly` converges to η < 1e-6 on one-step windows at its default
//!   iteration limit (measured: 1,983 iterations; with a normal per contact, the window of step
//!   13 stopped at the limit).
//! * Bad tables are errors naming the field, before anything is meshed.

use lopin_core::interfaces::interface::Law;
use lopin_core::post;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::Problem;
use lopin_tests::{against_reference, solve, solve_problem};
use std::collections::BTreeMap;

fn granular_poly() -> SceneSpec {
    scene::registry::builtin("granular-poly").expect("registry scene")
}

#[test]
fn granular_poly_builds_as_its_table_says_and_solves() {
    let spec = granular_poly();
    let problem = scene::problem_of(&spec, &spec.name).unwrap_or_else(|e| panic!("{e}"));
    let subs_of = |body: &str| problem.subs.iter().filter(|s| s.body == body).count();
    assert_eq!(subs_of("matrix"), 8);
    for k in 1..=10 {
        assert_eq!(subs_of(&format!("grain{k}")), 1, "grain{k}");
    }
    let dofs: usize = problem.subs.iter().map(|s| s.ndof()).sum();
    assert!(dofs <= 30_000, "{dofs} dofs");
    // every grain touches the matrix through contact, and only through contact
    for k in 1..=10 {
        let grain = format!("grain{k}");
        let touching: Vec<_> = problem
            .interfaces
            .iter()
            .filter(|i| i.sides.iter().any(|s| problem.subs[s.sub].body == grain))
            .collect();
        assert!(!touching.is_empty(), "{grain} touches nothing");
        assert!(
            touching
                .iter()
                .all(|i| matches!(&i.law, Law::Contact(c) if (c.friction - 0.3).abs() < 1e-15)),
            "{grain}: every interface is a contact with f = 0.3"
        );
    }
    let contacts = problem.interfaces.iter().filter(|i| i.is_contact()).count();
    println!(
        "granular-poly: {dofs} dofs, {} substructures, {} interfaces ({contacts} contact)",
        problem.subs.len(),
        problem.interfaces.len()
    );
    let (solver, sol) = solve(&spec, |_| {});
    assert!(sol.converged, "eta {}", sol.eta);
    let s = post::summary(&solver, &sol);
    let min_gap = s.min_gap.expect("contacts report a gap");
    println!(
        "granular-poly: {} iterations, max E/(E0 + input) {:.6}, min gap {min_gap:.3e} m, peak \
         normal force {:.4e} N, max slip {:.3e} m",
        sol.iterations, s.max_total_over_input, s.peak_normal_force, s.max_slip
    );
    assert!(s.max_total_over_input < 1.0 + 1e-3);
    assert!(s.peak_normal_force > 0.0 && s.max_slip > 0.0);
    // penetration at η < 1e-3 stays a small fraction of the 6 mm elements
    assert!(min_gap > -1e-5, "min gap {min_gap}");
}

#[test]
fn a_small_polyhedral_sample_equals_the_reference() {
    let mut spec = granular_poly();
    let g = spec.granular_poly.as_mut().expect("table");
    g.grains = 3;
    g.mesh_size = 0.015;
    g.matrix_substructures = 4;
    spec.time.steps = 20;
    spec.solver.rho_inf = Some(0.5);
    let problem = scene::problem_of(&spec, &spec.name).unwrap_or_else(|e| panic!("{e}"));
    let dofs: usize = problem.subs.iter().map(|s| s.ndof()).sum();
    let (solver, sol) = solve_problem(problem, &spec.solver, |s| {
        s.tol = 1e-9;
        s.window = None;
        s.max_iter = 20_000;
    });
    assert!(sol.converged, "eta {}", sol.eta);
    let c = against_reference(&solver, &sol);
    println!(
        "3 polyhedral grains ({dofs} dofs, {} substructures): {} iterations, velocity {:.2e}, \
         force {:.2e}",
        solver.problem().subs.len(),
        sol.iterations,
        c.rel_diff_velocity,
        c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity < 1e-7 && c.rel_diff_force < 1e-7,
        "{c:?}"
    );
}

/// Every grain node on a contact, by (grain, node): the normal out of the grain from each
/// contact interface that holds the node.
fn grain_normals(problem: &Problem) -> BTreeMap<(String, usize), Vec<[f64; 3]>> {
    let mut out: BTreeMap<(String, usize), Vec<[f64; 3]>> = BTreeMap::new();
    for iface in &problem.interfaces {
        let Law::Contact(c) = &iface.law else {
            continue;
        };
        for (j, side) in iface.sides.iter().enumerate() {
            let body = &problem.subs[side.sub].body;
            if !body.starts_with("grain") {
                continue;
            }
            // the normal points out of side 0
            let sign = if j == 0 { 1.0 } else { -1.0 };
            for (q, &node) in side.nodes.iter().enumerate() {
                out.entry((body.clone(), node))
                    .or_default()
                    .push(c.normal[q].map(|x| sign * x));
            }
        }
    }
    out
}

#[test]
fn a_grain_node_has_one_contact_normal_wherever_the_matrix_is_cut() {
    // where a cut between matrix parts meets a grain, its nodes lie on two contacts or more:
    // each gives them the same normal, that of all the contact faces around the node, so the
    // normals do not depend on the cut
    let normals = |parts| {
        let mut spec = granular_poly();
        spec.granular_poly
            .as_mut()
            .expect("table")
            .matrix_substructures = parts;
        let problem = scene::problem_of(&spec, &spec.name).unwrap_or_else(|e| panic!("{e}"));
        let normals = grain_normals(&problem);
        let shared = normals.values().filter(|n| n.len() > 1).count();
        println!(
            "matrix in {parts} parts: {} grain nodes on contact, {shared} on two contacts or more",
            normals.len()
        );
        assert!(shared > 0, "no grain node on two contacts");
        for (node, n) in &normals {
            assert!(n.iter().all(|x| *x == n[0]), "{node:?}: {n:?}");
        }
        normals
    };
    let (eight, sixteen) = (normals(8), normals(16));
    assert_eq!(
        eight.keys().collect::<Vec<_>>(),
        sixteen.keys().collect::<Vec<_>>()
    );
    let moved = eight
        .values()
        .zip(sixteen.values())
        .flat_map(|(a, b)| (0..3).map(move |c| (a[0][c] - b[0][c]).abs()))
        .fold(0.0, f64::max);
    println!("the normals of 8 and 16 matrix parts differ by {moved:.1e}");
    assert!(moved < 1e-12, "{moved}");
}

#[test]
fn granular_poly_converges_to_tight_tolerances_at_its_default_settings() {
    // one-step windows (the default of `lopin run` with contact) at η < 1e-6, each within the
    // default limit of 2,000 iterations
    let spec = granular_poly();
    let (_, sol) = solve(&spec, |s| {
        s.tol = 1e-6;
        s.window = Some(1);
    });
    println!("granular-poly at η < 1e-6: {} iterations", sol.iterations);
    assert!(sol.converged, "eta {}", sol.eta);
    assert!(sol.iterations < 3_000, "{} iterations", sol.iterations);
}

#[test]
fn bad_tables_are_errors_naming_the_field_before_meshing() {
    let text = scene::registry::source("granular-poly").expect("registry");
    for (from, to, field, says) in [
        (
            "grains = 10",
            "grains = 100000",
            "granular_poly.grains",
            "at most 500",
        ),
        (
            "grains = 10",
            "grains = 400",
            "granular_poly.grains",
            "cannot fit",
        ),
        (
            "grains = 10",
            "grains = 40",
            "granular_poly.grains",
            "placed only",
        ),
        (
            "vertices = 12",
            "vertices = 3",
            "granular_poly.grains",
            "at least 6",
        ),
        (
            "vertices = 12",
            "vertices = 1000",
            "granular_poly.vertices",
            "at most 24",
        ),
        (
            "mesh_size = 0.006",
            "mesh_size = 0.5",
            "granular_poly.mesh_size",
            "smaller",
        ),
        (
            "mesh_size = 0.006",
            "mesh_size = 1e-5",
            "mesh_size` about",
            "needs about",
        ),
        (
            "matrix = \"matrix\"",
            "matrix = \"clay\"",
            "granular_poly.matrix",
            "clay",
        ),
        (
            "friction = 0.3",
            "friction = -1.0",
            "granular_poly.friction",
            "lies in [0, 10]",
        ),
        (
            "matrix_substructures = 8",
            "matrix_substructures = 0",
            "granular_poly.matrix_substructures",
            "at least 1",
        ),
    ] {
        let edited = text.replacen(from, to, 1);
        assert_ne!(edited, text, "{from}");
        let e = scene::from_toml(&edited, "poly.toml")
            .expect_err(to)
            .to_string();
        assert!(
            e.contains("poly.toml") && e.contains(field) && e.contains(says),
            "{to}: {e}"
        );
    }
    let listed =
        format!("{text}\n[[boundary]]\nbody = \"matrix\"\nsurface = \"top\"\nclamped = true\n");
    let e = scene::from_toml(&listed, "poly.toml")
        .expect_err("listed boundary")
        .to_string();
    assert!(e.contains("generates its bodies"), "{e}");
}
