//! Non-matching interfaces (dual mortar: `model/src/interfaces/mortar.rs`, detected in
//! `model/src/interfaces/non_matching.rs`): parts meshed separately, in contact or bonded.
//!
//! * Patch tests: `two-blocks-nonmatching` (A at 10 × 10 × 5 hexahedra on B at 13 × 13 × 7, or
//!   on B's tetrahedra) with ν = 0 under a clamping pressure P (the preload's static phase, B's
//!   bottom clamped): the static solution is uniaxial, linear in z in each block, which both
//!   meshes represent; across the non-matching contact (stick) and the non-matching perfect
//!   interface the interface traction is P n at every interface node to 1e-8 and the
//!   displacement the analytic one at every node to 1e-10 of its largest value.
//! * LATIN against the monolithic reference of the same discrete problem (the mortar pairs,
//!   bonded for a perfect interface) at η < 1e-9: velocities and step-averaged forces within
//!   1e-6 on `two-blocks-nonmatching` (contact, f = 0.3 then warm at f = 0; and perfect), on
//!   `stack-mixed-msh` (hexahedra from one MSH file on tetrahedra from another), single- and
//!   two-scale, on `two-parts-assembly` (two parts gmsh meshes independently) and on
//!   `sleeve-and-core` (a curved interface faceted differently on each side).
//! * Zones on non-matching contacts: each zone moves its own friction, against the reference.
//! * Energy: `mini-impact` with B at 4 × 4 × 4 (non-matching contact) over 10⁴ steps creates no
//!   energy: max E/(E₀ + input) ≤ 1 + 1e-6.

use lopin_core::scene::spec::{ComponentSpec, ElementKind, InterfaceKind};
use lopin_core::scene::{self, SceneSpec};
use lopin_core::study::Target;
use lopin_core::{post, Parameter, Settings, Solver};
use lopin_judge::compare::compare;
use lopin_reference::monolithic::Monolithic;
use lopin_tests::solve;

const P: f64 = 50e6;
/// (height, Young's modulus) of A (steel) and B (aluminium).
const A: (f64, f64) = (0.02, 210e9);
const B: (f64, f64) = (0.02, 70e9);

/// `two-blocks-nonmatching` with ν = 0, a clamping pressure P on A's top as a preload, B's
/// bottom clamped, the blocks joined by `kind`, B on `elements`.
fn clamped_stack(kind: InterfaceKind, elements: ElementKind) -> SceneSpec {
    let mut spec = scene::load("two-blocks-nonmatching").expect("scene");
    spec.time.steps = 4;
    for m in &mut spec.materials {
        m.poisson = 0.0;
    }
    let i = &mut spec.interfaces[0];
    i.kind = kind;
    if kind != InterfaceKind::Contact {
        i.friction = None;
        i.gap = None;
    }
    spec.bodies[1].elements = Some(elements);
    let a = &mut spec.boundaries[0];
    a.z = None;
    a.preload = true;
    a.normal = Some(ComponentSpec {
        pressure: Some(P),
        ..ComponentSpec::default()
    });
    spec
}

/// The analytic displacement u_z of the stack at height z (B below 0.02 m, A above).
fn u_z(z: f64) -> f64 {
    if z <= B.0 {
        -P * z / B.1
    } else {
        -P * (B.0 / B.1 + (z - B.0) / A.1)
    }
}

#[test]
fn the_uniaxial_state_passes_non_matching_interfaces_exactly() {
    for (kind, elements) in [
        (InterfaceKind::Contact, ElementKind::Hex8),
        (InterfaceKind::Perfect, ElementKind::Hex8),
        (InterfaceKind::Contact, ElementKind::Tet4),
        (InterfaceKind::Perfect, ElementKind::Tet4),
    ] {
        let spec = clamped_stack(kind, elements);
        let (solver, sol) = solve(&spec, |s| {
            s.tol = 1e-9;
            s.max_iter = 50_000;
        });
        let p = solver.problem();
        let report = *solver.preload().expect("a static phase");
        // the interface: side 1's traction F₀ at every interface node is P n (n outward of
        // side 1), read from its substructure's prestress
        let (k, iface) = p
            .interfaces
            .iter()
            .enumerate()
            .find(|(_, i)| !i.is_boundary())
            .expect("the interface");
        assert!(iface.sides[1].projection.is_some(), "non-matching");
        let side = &iface.sides[0];
        let sub = &p.subs[side.sub];
        let traction = &sub.prestress.as_ref().expect("prestressed").traction;
        let up = if sub.body == "A" { 1.0 } else { -1.0 };
        let mut traction_error = 0.0f64;
        for q in 0..iface.node_count() {
            for c in 0..3 {
                let want = if c == 2 { up * P } else { 0.0 };
                let f = traction[side.offset + 3 * q + c];
                traction_error = traction_error.max((f - want).abs() / P);
            }
        }
        // the displacement of every node of both blocks
        let umax = u_z(2.0 * B.0).abs();
        let mut u_error = 0.0f64;
        for sub in &p.subs {
            let u = &sub.prestress.as_ref().expect("prestressed").displacement;
            for (n, x) in sub.mesh.nodes.iter().enumerate() {
                for c in 0..3 {
                    let want = if c == 2 { u_z(x[2]) } else { 0.0 };
                    u_error = u_error.max((u[3 * n + c] - want).abs() / umax);
                }
            }
        }
        let pressures: Vec<f64> = post::gathered_contact(&solver, &sol)
            .iter()
            .filter(|h| h.interface == k)
            .flat_map(|h| h.pressure[0].clone())
            .collect();
        let pressure_error = pressures
            .iter()
            .map(|x| (x / P - 1.0).abs())
            .fold(0.0, f64::max);
        println!(
            "{kind:?} on {elements:?}: {} interface nodes, static phase {} iterations (η {:.1e}): \
             traction off P n by {traction_error:.2e}, contact pressure by {pressure_error:.2e}, \
             displacement by {u_error:.2e} of its largest",
            iface.node_count(),
            report.iterations,
            report.eta,
        );
        assert!(
            traction_error < 1e-8,
            "{kind:?} {elements:?}: {traction_error:e}"
        );
        assert!(u_error < 1e-10, "{kind:?} {elements:?}: {u_error:e}");
        if kind == InterfaceKind::Contact {
            assert_eq!(pressures.len(), iface.node_count());
            assert!(pressure_error < 1e-8, "{pressure_error:e}");
        }
    }
}

/// LATIN at η < 1e-9 against the reference on `spec`, for each friction value in turn (None:
/// the scene's), each solve warm from the previous one; single- or two-scale.
fn against_reference(spec: &SceneSpec, frictions: &[Option<f64>], two_scale: bool) {
    let problem = scene::problem_of(spec, &spec.name).expect("scene builds");
    assert!(
        problem
            .interfaces
            .iter()
            .any(|i| i.sides.len() == 2 && i.sides[1].projection.is_some()),
        "{}: a non-matching interface",
        spec.name
    );
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = 1e-9;
    settings.max_iter = 30_000;
    settings.two_scale = two_scale;
    let mut reference = Monolithic::new(problem.clone()).expect("reference setup");
    let mut solver = Solver::new(problem, settings).expect("latin setup");
    let mut previous = None;
    for f in frictions {
        if let Some(f) = *f {
            solver.set_parameter(Parameter::Friction, f).expect("f");
            reference.set_parameter(Parameter::Friction, f).expect("f");
        }
        let sol = solver.solve(previous.as_ref()).expect("latin");
        assert!(sol.converged, "{}: LATIN did not converge", spec.name);
        let mono = reference.solve().expect("reference");
        let c = compare(&solver, &sol, &reference, &mono);
        println!(
            "{} f={f:?} two-scale {two_scale}, window {:?}, {} contacts: {} iterations; velocity \
             {:.2e}, force {:.2e}, contact force {:.2e}, energy {:.2e}",
            spec.name,
            solver.settings().window,
            solver
                .problem()
                .interfaces
                .iter()
                .filter(|i| i.is_contact())
                .count(),
            sol.iterations,
            c.rel_diff_velocity,
            c.rel_diff_force,
            c.rel_diff_contact_force,
            c.rel_diff_energy
        );
        assert!(c.rel_diff_velocity <= 1e-6, "{c:?}");
        assert!(c.rel_diff_force <= 1e-6, "{c:?}");
        assert!(c.rel_diff_contact_force <= 1e-6, "{c:?}");
        previous = Some(sol.state);
    }
}

#[test]
fn a_non_matching_contact_agrees_with_the_reference() {
    let spec = scene::load("two-blocks-nonmatching").expect("scene");
    against_reference(&spec, &[Some(0.3), Some(0.0)], false);
}

#[test]
fn a_non_matching_perfect_interface_agrees_with_the_reference() {
    let mut spec = scene::load("two-blocks-nonmatching").expect("scene");
    let i = &mut spec.interfaces[0];
    i.kind = InterfaceKind::Perfect;
    i.friction = None;
    i.gap = None;
    against_reference(&spec, &[None], false);
}

/// The scene file `assets/scenes/NAME.toml`, named by its path (so that its meshes are found).
fn file_scene(name: &str) -> SceneSpec {
    let path = lopin_tests::asset(name);
    let mut spec = scene::load(&path).expect("scene");
    spec.name = path;
    spec
}

/// The area of a scene's one two-sided interface (an error if it has another number of them).
fn the_interface_area(spec: &SceneSpec) -> f64 {
    let problem = scene::problem_of(spec, &spec.name).expect("builds");
    let two_sided: Vec<_> = problem
        .interfaces
        .iter()
        .filter(|i| !i.is_boundary())
        .collect();
    assert_eq!(two_sided.len(), 1, "{}: one interface", spec.name);
    assert!(two_sided[0].sides[1].projection.is_some(), "non-matching");
    two_sided[0].area.iter().step_by(3).sum()
}

#[test]
fn hexahedra_on_tetrahedra_from_two_msh_files_agree_with_the_reference() {
    let spec = file_scene("gmsh/stack-mixed-msh");
    against_reference(&spec, &[None], false);
    against_reference(&spec, &[None], true);
}

/// Two parts meshed independently by gmsh from one `.geo` (no fragments): where a few
/// triangles of the two meshes happen to coincide they join the one non-matching interface.
#[test]
fn an_assembly_meshed_part_by_part_agrees_with_the_reference() {
    let spec = file_scene("gmsh/two-parts-assembly");
    let area = the_interface_area(&spec);
    assert!(
        (area / 0.04f64.powi(2) - 1.0).abs() < 1e-9,
        "the whole face: {area}"
    );
    against_reference(&spec, &[None], false);
}

/// A curved interface faceted differently on each side (`sleeve-and-core`: a core bonded in a
/// sleeve, tetrahedra of 3 and 4 mm): the non-matching interface covers the cylindrical face
/// (its area within 1 % of 2πrh, the facets' chords making it smaller) and LATIN agrees with
/// the reference.
#[test]
fn a_curved_interface_faceted_differently_on_each_side_agrees_with_the_reference() {
    let spec = file_scene("gmsh/sleeve-and-core");
    let area = the_interface_area(&spec);
    let cylinder = 2.0 * std::f64::consts::PI * 0.015 * 0.03;
    println!("sleeve-and-core: interface area {area:.6e} m², 2πrh = {cylinder:.6e} m²");
    assert!(
        (area / cylinder - 1.0).abs() < 0.01,
        "{area} against {cylinder}"
    );
    against_reference(&spec, &[None], false);
}

/// Zones on non-matching contacts: the three-block stack of `mini-stack-zones` with B at
/// 4 × 4 × 3 against A's and C's 3 × 3 × 2, both contacts non-matching, each its own zone: each
/// zone selects its mortar contact, and two frictions agree with the reference (η < 1e-9) with
/// a friction work between the uniform runs'.
#[test]
fn zones_on_non_matching_contacts_move_their_own_friction() {
    let mut spec = file_scene("test/mini-stack-zones");
    spec.bodies[1].divisions = [4, 4, 3];
    let problem = scene::problem_of(&spec, &spec.name).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = 1e-9;
    settings.max_iter = 20_000;
    let mut s = Solver::new(problem, settings).expect("solver");
    let zones = s.problem().zones.clone();
    assert_eq!(zones.len(), 2);
    for z in &zones {
        assert_eq!(z.contacts.len(), 1, "{z:?}");
        let i = &s.problem().interfaces[z.contacts[0]];
        assert!(i.sides[1].projection.is_some(), "{}: non-matching", i.name);
    }
    let upper = Target::parse("f@upper", s.problem()).expect("f@upper");
    let lower = Target::parse("f@lower", s.problem()).expect("f@lower");
    lopin_tests::two_frictions_against_reference_and_uniform(
        &mut s,
        [(&upper, 0.1), (&lower, 0.5)],
    );
}

#[test]
fn a_long_impact_on_a_non_matching_contact_creates_no_energy() {
    let mut spec = scene::load("mini-impact").expect("scene");
    spec.bodies[1].divisions = [4, 4, 4];
    spec.time.steps = 10_000;
    let (solver, sol) = solve(&spec, |s| s.window = Some(100));
    assert!(sol.converged);
    let e = post::energy(&solver, &sol);
    let ratio = e.max_total_over_input();
    let summary = post::summary(&solver, &sol);
    println!(
        "mini-impact, B at 4 x 4 x 4, 10^4 steps: {} iterations, max E/(E0 + input) {ratio:.9}, \
         min gap {:?}",
        sol.iterations, summary.min_gap
    );
    assert!(ratio <= 1.0 + 1e-6, "{ratio}");
}
