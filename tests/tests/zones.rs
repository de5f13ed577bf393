//! Zones (`model/src/interfaces/zone.rs`): contact interfaces grouped by body pairs or by a box in
//! the scene file, each zone's friction its own parameter. On a stack of three blocks (steel on
//! aluminium on aluminium, two contact interfaces that share no node, zones `upper` and
//! `lower`): the same value in both zones is the uniform setting bit for bit; f = 0.1 above and
//! 0.5 below agrees with the monolithic reference of the same problem to 1e-6 (LATIN at
//! η < 1e-9), and its friction work lies between the two uniform runs'. (Zones that meet along a
//! line, as the quadrants of `two-blocks --split 2`, share the nodes of that line: there the
//! split of the normal force between the two frictions is not unique, and the monolithic
//! reference cannot stand as a check.) Bad zone blocks are refused naming the field. The contact
//! work of `core/src/dissipation.rs` closes the energy balance: input work − final energy =
//! friction work + normal work.

use lopin_core::scene::{self, SceneSpec};
use lopin_core::study::Target;
use lopin_core::{dissipation, post, Parameter, Settings, Solver};
use lopin_tests::two_frictions_against_reference_and_uniform;

const STACK: &str = r#"
name = "stack"
description = "steel block on two aluminium blocks, two frictional contacts"
refine_axes = "xyz"
split_axes = "xy"

[time]
dt = 0.25e-6
steps = 40

[[material]]
name = "steel"
young = 210e9
poisson = 0.30
density = 7800.0

[[material]]
name = "aluminium"
young = 70e9
poisson = 0.33
density = 2700.0

[[body]]
name = "A"
material = "steel"
min = [0.0, 0.0, 0.04]
max = [0.03, 0.03, 0.06]
divisions = [5, 5, 3]

[[body]]
name = "B"
material = "aluminium"
min = [0.0, 0.0, 0.02]
max = [0.03, 0.03, 0.04]
divisions = [5, 5, 3]

[[body]]
name = "C"
material = "aluminium"
min = [0.0, 0.0, 0.0]
max = [0.03, 0.03, 0.02]
divisions = [5, 5, 3]

[[interface]]
bodies = ["A", "B"]
kind = "contact"
friction = 0.3
gap = 0.0

[[interface]]
bodies = ["B", "C"]
kind = "contact"
friction = 0.3
gap = 0.0

[[boundary]]
body = "A"
face = "z+"
z = { velocity = -10.0, ramp = "cosine", ramp_time = 2.5e-6 }

[[boundary]]
body = "C"
face = "z-"
clamped = true

[[zone]]
name = "upper"
bodies = [["A", "B"]]

[[zone]]
name = "lower"
max = [1.0, 1.0, 0.03]
"#;

fn stack() -> SceneSpec {
    scene::from_toml(STACK, "stack").expect("stack scene")
}

fn solver(spec: &SceneSpec, tol: f64) -> Solver {
    let problem = scene::problem_of(spec, &spec.name).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    settings.max_iter = 20_000;
    Solver::new(problem, settings).expect("solver")
}

#[test]
fn zones_select_their_interfaces_and_move_their_own_friction() {
    let spec = stack();
    let mut s = solver(&spec, 1e-9);
    let zones = s.problem().zones.clone();
    assert_eq!(zones.len(), 2);
    assert_eq!(zones[0].contacts.len(), 1, "{zones:?}");
    assert_eq!(zones[1].contacts.len(), 1, "{zones:?}");
    assert_ne!(zones[0].contacts, zones[1].contacts);
    // `upper` names bodies A and B: A's top face, where the velocity is prescribed, is its (v0);
    // `lower`'s box holds no prescribed velocity
    assert_eq!(zones[0].boundaries.len(), 1, "{zones:?}");
    assert!(zones[1].boundaries.is_empty(), "{zones:?}");
    let upper = Target::parse("f@upper", s.problem()).expect("f@upper");
    let lower = Target::parse("f@lower", s.problem()).expect("f@lower");
    assert_eq!(upper.label, "f@upper");

    // one value in both zones = the uniform setting, bit for bit
    s.set_parameter(Parameter::Friction, 0.3).expect("f");
    let uniform = s.solve(None).expect("uniform");
    s.set_parameter_in(upper.parameter, upper.zone, 0.3)
        .expect("upper");
    s.set_parameter_in(lower.parameter, lower.zone, 0.3)
        .expect("lower");
    let zoned = s.solve(None).expect("zoned");
    assert!(uniform.state == zoned.state && uniform.hats == zoned.hats);

    // different values: the reference agrees, and the friction work lies between the uniform
    // runs'
    two_frictions_against_reference_and_uniform(&mut s, [(&upper, 0.1), (&lower, 0.5)]);
}

#[test]
fn the_contact_work_closes_the_energy_balance() {
    let spec = scene::load("two-blocks").expect("scene");
    let mut s = solver(&spec, 1e-9);
    for f in [0.0, 0.1, 0.3, 0.5] {
        s.set_parameter(Parameter::Friction, f).expect("f");
        let sol = s.solve(None).expect("solve");
        let e = post::energy(&s, &sol);
        let n = e.kinetic.len() - 1;
        let lost = e.input_work[n] - e.total(n);
        let w = dissipation::contact_work(&s, &sol);
        let off = (lost - w.friction - w.normal).abs() / e.input_work[n];
        println!(
            "f = {f}: input {:.5e} J, lost {lost:.5e} J, friction {:.5e} J, normal {:.3e} J, \
             balance off by {off:.2e} of the input",
            e.input_work[n], w.friction, w.normal
        );
        assert!(off < 1e-6, "f = {f}: the balance is off by {off:e}");
        assert!(w.friction >= 0.0);
        if f == 0.0 {
            assert!(w.friction.abs() < 1e-9 * e.input_work[n], "{w:?}");
        } else if f < 0.45 {
            assert!(w.friction > 1e-4 * e.input_work[n], "{w:?}");
        } else {
            // full stick from f = 0.45 (the sweep's table): no slip, no friction work
            assert!(w.friction.abs() < 1e-6 * e.input_work[n], "{w:?}");
        }
    }
}

#[test]
fn bad_zones_are_refused_naming_the_field() {
    let text = std::fs::read_to_string(lopin_tests::asset("two-blocks")).expect("scene file");
    for (block, field, reason) in [
        (
            "[[zone]]\nname = \"a\"\nbodies = [[\"A\", \"C\"]]",
            "zone[0].bodies[0]",
            "no body is named `C`",
        ),
        (
            "[[zone]]\nname = \"a\"\nmin = [1.0, 1.0, 1.0]",
            "zone[0].min",
            "holds no contact",
        ),
        (
            "[[zone]]\nname = \"a b\"",
            "zone[0].name",
            "not a zone name",
        ),
        (
            "[[zone]]\nname = \"a\"\n[[zone]]\nname = \"a\"",
            "zone[1].name",
            "defined twice",
        ),
        (
            "[[zone]]\nname = \"a\"\nmin = [0.1, 0, 0]\nmax = [0.0, 1, 1]",
            "zone[0].min",
            "not below",
        ),
        (
            "[[zone]]\nname = \"a\"\nsurfaces = [\"pad\"]",
            "zone[0].surfaces[0]",
            "physical surfaces come from Gmsh meshes",
        ),
    ] {
        let spec = scene::from_toml(&format!("{text}\n{block}"), "bad").expect("parses");
        let e = scene::problem_of(&spec, "bad")
            .expect_err(block)
            .to_string();
        assert!(e.contains(field) && e.contains(reason), "{block}: {e}");
    }
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let e = Target::parse("f@left", &problem)
        .expect_err("no zones")
        .to_string();
    assert!(
        e.contains("unknown zone `left`") && e.contains("no [[zone]]"),
        "{e}"
    );
    let e = Target::parse("mu", &problem)
        .expect_err("unknown")
        .to_string();
    assert!(e.contains("unknown parameter `mu`"), "{e}");
}
