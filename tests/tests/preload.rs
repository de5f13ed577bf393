//! The preload's static phase (`lopin_core::preload`): LATIN in statics brings `two-blocks`
//! (ν = 0, so the stack's static solution is uniaxial and exact on hexahedra) to the equilibrium
//! of a clamping pressure on A's top (B's bottom clamped), and of a press fit (a contact
//! interference δ between the blocks, both outer faces clamped), against the analytic contact
//! pressure and displacement (to 1e-6); the dynamics that start from that equilibrium with
//! nothing else moving stay at rest (the start is in equilibrium, to 1e-6 of the static
//! displacement per step); moving the interference re-solves the static phase.

use lopin_core::scene::spec::ComponentSpec;
use lopin_core::{post, scene, Parameter, Problem};
use lopin_tests::solve;

const P: f64 = 50e6;
const DELTA: f64 = 2e-6;
/// (height, Young's modulus) of A (steel) and B (aluminium).
const A: (f64, f64) = (0.02, 210e9);
const B: (f64, f64) = (0.02, 70e9);

/// `two-blocks` with ν = 0 and nothing moving: A's top and B's bottom as `top` and `bottom`
/// say, the contact with gap `gap`.
fn stack(top: ComponentSpec, top_clamped: bool, preload: bool, gap: f64) -> scene::SceneSpec {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.time.steps = 20;
    for m in &mut spec.materials {
        m.poisson = 0.0;
    }
    spec.interfaces[0].gap = Some(gap);
    let a = &mut spec.boundaries[0];
    a.z = None;
    a.clamped = top_clamped;
    a.preload = preload;
    if !top_clamped {
        a.normal = Some(top);
    }
    spec
}

/// The contact pressure of every contact node at t₀ (after the static phase).
fn start_pressures(solver: &lopin_core::Solver, sol: &lopin_core::Solution) -> Vec<f64> {
    post::gathered_contact(solver, sol)
        .iter()
        .flat_map(|h| h.pressure[0].clone())
        .collect()
}

/// The largest |u_z| and |v| of every node over the dynamic steps, and u_z at A's top at t₀.
fn motion(solver: &lopin_core::Solver, sol: &lopin_core::Solution) -> (f64, f64, f64) {
    let p: &Problem = solver.problem();
    let (mut drift, mut speed, mut top) = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..p.subs.len() {
        let sub = &p.subs[i];
        let u0 = sub
            .prestress
            .as_ref()
            .expect("prestressed")
            .displacement
            .clone();
        post::replay(solver, sol, i, p.time.steps, &mut |m, st, _, _| {
            for d in 0..sub.ndof() {
                drift = drift.max((st.u[d] - u0[d]).abs());
                speed = speed.max(st.v[d].abs());
            }
            if m == 0 {
                for (k, x) in sub.mesh.nodes.iter().enumerate() {
                    if x[2] > 0.04 - 1e-9 {
                        top = top.max(st.u[3 * k + 2].abs());
                    }
                }
            }
        });
    }
    (drift, speed, top)
}

/// A clamping pressure p on A's top: contact pressure p at every contact node, A's top lowered
/// by p (L_A/E_A + L_B/E_B); the dynamics stay at rest.
#[test]
fn a_clamping_pressure_gives_the_analytic_static_stack() {
    let pressure = ComponentSpec {
        pressure: Some(P),
        ..ComponentSpec::default()
    };
    let spec = stack(pressure, false, true, 0.0);
    let (solver, sol) = solve(&spec, |s| s.tol = 1e-8);
    assert!(sol.converged);
    let report = *solver.preload().expect("a static phase");
    let pressures = start_pressures(&solver, &sol);
    let worst = pressures
        .iter()
        .map(|x| (x / P - 1.0).abs())
        .fold(0.0, f64::max);
    let (drift, speed, top) = motion(&solver, &sol);
    let expected = P * (A.0 / A.1 + B.0 / B.1);
    println!(
        "clamped stack: static phase {} iterations (η {:.2e}, k {:.3e} Pa/m, {:.3} s); contact \
         pressure off p by {worst:.2e}; top {top:.6e} m against {expected:.6e}; then drift \
         {drift:.2e} m, speed {speed:.2e} m/s",
        report.iterations, report.eta, report.k, report.seconds
    );
    assert!(worst < 1e-6, "{worst:e}");
    assert!((top / expected - 1.0).abs() < 1e-6, "{top:e}");
    assert!(drift < 1e-6 * expected, "{drift:e}");
    assert!(speed < 1e-6 * expected / spec.time.dt, "{speed:e}");
}

/// A press fit: an interference δ between the blocks, both outer faces clamped: contact
/// pressure δ/(L_A/E_A + L_B/E_B) at every node; the gap left is 0; the dynamics stay at rest;
/// twice the interference (the `gap` parameter) re-solves the static phase: twice the pressure.
#[test]
fn a_press_fit_gives_the_analytic_contact_pressure() {
    let mut spec = stack(ComponentSpec::default(), true, false, -DELTA);
    spec.boundaries[0].preload = false;
    let (mut solver, sol) = solve(&spec, |s| s.tol = 1e-8);
    assert!(sol.converged);
    let expected = DELTA / (A.0 / A.1 + B.0 / B.1);
    let worst = |pressures: Vec<f64>, expected: f64| {
        pressures
            .iter()
            .map(|x| (x / expected - 1.0).abs())
            .fold(0.0, f64::max)
    };
    let off = worst(start_pressures(&solver, &sol), expected);
    let (drift, speed, _) = motion(&solver, &sol);
    let report = *solver.preload().expect("a static phase");
    println!(
        "press fit: static phase {} iterations; pressure off {expected:.6e} Pa by {off:.2e}; \
         drift {drift:.2e} m, speed {speed:.2e} m/s",
        report.iterations
    );
    assert!(off < 1e-6, "{off:e}");
    assert!(drift < 1e-6 * DELTA && speed < 1e-6 * DELTA / spec.time.dt);
    solver
        .set_parameter(Parameter::Gap, -2.0 * DELTA)
        .expect("interference");
    let again = solver.solve(None).expect("solves");
    let off = worst(start_pressures(&solver, &again), 2.0 * expected);
    println!("press fit at 2δ: pressure off by {off:.2e}");
    assert!(off < 1e-6, "{off:e}");
}

/// A preload given a ramp, or on a velocity, is refused naming the field.
#[test]
fn bad_preloads_are_refused_naming_the_field() {
    let good = std::fs::read_to_string(lopin_tests::asset("two-blocks")).expect("scene");
    let top = "z = { velocity = -10.0, ramp = \"cosine\", ramp_time = 2.5e-6 }";
    assert!(good.contains(top));
    let cases = [
        (
            "ramped",
            good.replace(
                top,
                "preload = true\nnormal = { pressure = 1e6, ramp_time = 1e-6 }",
            ),
            "boundary[0].normal",
            "held constant",
        ),
        (
            "velocity",
            good.replace(top, "preload = true\nz = { velocity = -1.0 }"),
            "boundary[0].z",
            "static load",
        ),
    ];
    lopin_tests::assert_clear_errors(&good, &cases, "lopin-bad-preload");
}

/// `two-blocks` with a press fit (interference 2 µm) and its shock on top (A's top held in x
/// and y): LATIN (its static
/// phase, then the dynamics at η < 1e-9) against the monolithic reference, started from its own
/// static solve (a monolithic contact solve on K): velocities and step-averaged forces within
/// 1e-6, contact forces too.
#[test]
fn preload_then_shock_agrees_with_the_reference_from_its_own_static_solve() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.interfaces[0].gap = Some(-DELTA);
    // A's top held across too: in statics every part of the reference is held
    spec.boundaries[0].x = Some(ComponentSpec::velocity(0.0, 0.0));
    spec.boundaries[0].y = Some(ComponentSpec::velocity(0.0, 0.0));
    let (solver, sol) = solve(&spec, |s| {
        s.tol = 1e-9;
        s.max_iter = 20_000;
    });
    assert!(sol.converged);
    let c = lopin_tests::against_reference(&solver, &sol);
    println!(
        "press fit then shock: static {} + dynamic {} iterations; velocity {:.3e}, force {:.3e}, \
         contact force {:.3e}",
        solver.preload().expect("static phase").iterations,
        sol.iterations,
        c.rel_diff_velocity,
        c.rel_diff_force,
        c.rel_diff_contact_force
    );
    assert!(
        c.rel_diff_velocity <= 1e-6 && c.rel_diff_force <= 1e-6,
        "{c:?}"
    );
    assert!(c.rel_diff_contact_force <= 1e-6, "{c:?}");
}

/// `bolted-lap` (a preload on washer areas, frictional lap, whole interval): moving the preload
/// (`preload`, 50 to 100 MPa; `t0` leaves it alone) and starting from the neighbour's converged state, shifted by the change
/// of the static state, takes under half the cold iterations (measured at η < 1e-4: 81 against
/// 245), and lands where the cold solve does (peak contact force to 1e-2 of it, the
/// tolerance's order).
#[test]
fn a_new_preload_warm_starts_from_its_neighbour() {
    let spec = scene::load("bolted-lap").expect("scene");
    let problem = scene::problem_of(&spec, "bolted-lap").expect("builds");
    let (mut solver, first) = lopin_tests::solve_problem(problem.clone(), &spec.solver, |s| {
        s.tol = 1e-4;
    });
    solver.set_parameter(Parameter::Preload, 50e6).expect("t0");
    let near = solver.solve(Some(&first.state)).expect("solves");
    solver.set_parameter(Parameter::Preload, 100e6).expect("t0");
    let warm = solver.solve(Some(&near.state)).expect("warm");
    assert_eq!(Parameter::Preload.current(solver.problem()), Some(100e6));
    assert_eq!(
        Parameter::TractionAmplitude.current(solver.problem()),
        None,
        "a preload is not one of the tractions t0 moves"
    );
    let (mut cold_solver, _) = lopin_tests::solve_problem(problem, &spec.solver, |s| s.tol = 1e-4);
    cold_solver
        .set_parameter(Parameter::Preload, 100e6)
        .expect("t0");
    let cold = cold_solver.solve(None).expect("cold");
    let peak = |s: &lopin_core::Solver, sol: &lopin_core::Solution| {
        post::summary(s, sol).peak_normal_force
    };
    let (pw, pc) = (peak(&solver, &warm), peak(&cold_solver, &cold));
    println!(
        "bolted-lap t0 50 → 100 MPa: warm {} iterations, cold {}; peak normal force {pw:.6e} \
         against {pc:.6e}",
        warm.iterations, cold.iterations
    );
    assert!(warm.converged && cold.converged);
    assert!(
        3 * warm.iterations < cold.iterations,
        "{} {}",
        warm.iterations,
        cold.iterations
    );
    assert!((pw / pc - 1.0).abs() < 1e-2, "{pw} {pc}");
}

/// A preload that pulls the washers outward opens the lap instead of clamping it: refused,
/// naming the contact and how far it opened.
#[test]
fn a_preload_that_opens_the_joint_is_refused() {
    let mut spec = scene::load("bolted-lap").expect("scene");
    for b in &mut spec.boundaries {
        if let Some(n) = &mut b.normal {
            n.pressure = Some(-200e6);
        }
    }
    let problem = scene::problem_of(&spec, "bolted-lap").expect("builds");
    let settings = lopin_core::Settings::for_problem(&problem, &spec.solver);
    let Err(e) = lopin_core::Solver::new(problem, settings) else {
        panic!("a preload that opens the joint was accepted");
    };
    let e = e.to_string();
    println!("{e}");
    assert!(
        e.contains("preload") && e.contains("opens contact `A|B`") && e.contains("sign"),
        "{e}"
    );
}
