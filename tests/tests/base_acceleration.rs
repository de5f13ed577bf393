//! Prescribed accelerations (base excitation, `lopin_core::time::time_function::Integrated`): the
//! velocity of a driven dof integrates the acceleration by the time scheme's own rule, so the
//! march gives the driven nodes the prescribed acceleration A(t_m) at every step (to 1e-7 of its
//! peak, for the trapezoidal rule and for ρ∞ = 0.5); `bar` driven by a haversine acceleration
//! converges to d'Alembert's v(x, t) = V(t − x/c), V = ∫A, at order near 2; through contact LATIN
//! agrees with the monolithic reference; `a0` and `duration` are parameters; a body that does not
//! start at rest along the driven axis is refused.

use lopin_core::scene::spec::ComponentSpec;
use lopin_core::time::time_function::PulseKind;
use lopin_core::{post, scene, Parameter, Settings, Solution, Solver};
use lopin_reference::exact::{l2_error, BarExact};
use lopin_tests::{against_reference, bar_driven, largest_difference, solve};

/// Pulse duration (s) and the acceleration peak (m/s²) that brings the end of `bar` to 10 m/s.
const DURATION: f64 = 3e-6;
const PEAK: f64 = 20.0 / DURATION;

/// A haversine acceleration pulse that brings the end of `bar` to 10 m/s.
fn haversine() -> ComponentSpec {
    ComponentSpec {
        acceleration: Some(PEAK),
        pulse: Some(PulseKind::Haversine),
        duration: Some(DURATION),
        ..ComponentSpec::default()
    }
}

fn solved(spec: &scene::SceneSpec, rho_inf: f64, tol: f64) -> (Solver, Solution) {
    let problem = scene::problem_of(spec, &spec.name).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    settings.rho_inf = rho_inf;
    settings.window = Some(1);
    let mut solver = Solver::new(problem, settings).expect("setup");
    let sol = solver.solve(None).expect("solves");
    assert!(sol.converged);
    (solver, sol)
}

/// The haversine acceleration's velocity from rest, V(t) = A (t/2 − T/(4π) sin(2πt/T)), then
/// held at A T/2.
fn exact_velocity(t: f64) -> f64 {
    let t = t.min(DURATION);
    PEAK * (0.5 * t
        - DURATION / (4.0 * std::f64::consts::PI)
            * (2.0 * std::f64::consts::PI * t / DURATION).sin())
}

/// On `bar` (refine 4), the nodes at x = 0 have the prescribed acceleration A(t_m) at every step
/// of the converged march (to 1e-7 of the peak: η < 1e-11 on the velocities, times 2/Δt), for the trapezoidal rule and for the Bossak scheme at ρ∞ = 0.5 (each
/// integrating V with its own γ); their velocity is the exact integral ∫A to 3.6e-5 of its end
/// value with the trapezoidal rule (second order), to 5.6e-3 with ρ∞ = 0.5 (γ = 5/6: first
/// order).
#[test]
fn the_driven_nodes_have_the_prescribed_acceleration_at_every_step() {
    let spec = bar_driven(haversine(), 4);
    for rho_inf in [1.0, 0.5] {
        let (solver, sol) = solved(&spec, rho_inf, 1e-11);
        let p = solver.problem();
        let sub = &p.subs[0];
        let driven: Vec<usize> = (0..sub.mesh.nodes.len())
            .filter(|&k| sub.mesh.nodes[k][0] == 0.0)
            .collect();
        assert_eq!(driven.len(), 4);
        let (mut worst_a, mut worst_v) = (0.0f64, 0.0f64);
        post::replay(&solver, &sol, 0, p.time.steps, &mut |m, st, _, _| {
            let t = p.time.time(m);
            let a = PEAK * 0.5 * (1.0 - (2.0 * std::f64::consts::PI * t / DURATION).cos());
            let a = if t <= DURATION { a } else { 0.0 };
            for &k in &driven {
                worst_a = worst_a.max((st.a[3 * k] - a).abs());
                worst_v = worst_v.max((st.v[3 * k] - exact_velocity(t)).abs());
            }
        });
        let (worst_a, worst_v) = (worst_a / PEAK, worst_v / exact_velocity(DURATION));
        println!(
            "ρ∞ = {rho_inf}: acceleration of the driven nodes off A(t_m) by {worst_a:.3e} of the \
             peak, velocity off ∫A by {worst_v:.3e} of its end value"
        );
        assert!(worst_a < 1e-7, "ρ∞ = {rho_inf}: {worst_a:e}");
        // the trapezoidal rule integrates at second order, Bossak's γ > ½ at first
        let bound = if rho_inf == 1.0 { 1e-4 } else { 1e-2 };
        assert!(worst_v < bound, "ρ∞ = {rho_inf}: {worst_v:e}");
    }
}

/// `bar` driven by a haversine acceleration, refined 2, 4 and 8 times in x and t: the
/// space–time L2 error of the velocities against d'Alembert falls at an order above 1.6 (the
/// velocity is C², the same order as a haversine velocity pulse).
#[test]
fn a_bar_driven_by_an_acceleration_converges_to_dalembert() {
    let e: Vec<f64> = [2, 4, 8]
        .map(|r| {
            let (solver, sol) = solved(&bar_driven(haversine(), r), 1.0, 1e-7);
            let p = solver.problem();
            let exact = BarExact::for_problem(p).expect("the front stays inside the bar");
            let history = post::velocity_history(&solver, &sol);
            l2_error(p, &exact, &mut |s, m| history[m][s].clone())
        })
        .to_vec();
    let orders: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("acceleration-driven bar: L2 errors {e:.4?}, orders {orders:.2?}");
    assert!(orders.iter().all(|&o| o > 1.0), "{e:?}");
    assert!(orders[1] > 1.6 && e[2] < 0.05, "{e:?}, orders {orders:?}");
}

/// `two-blocks` standing on a base that moves up with a 5 µs half-sine acceleration (B's bottom
/// face driven along z instead of clamped, A's top face free): LATIN at η < 1e-9 agrees with
/// the monolithic reference to 1e-6 in velocity and force.
#[test]
fn base_excitation_through_contact_agrees_with_the_reference() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.boundaries.retain(|b| b.body == "B");
    let base = &mut spec.boundaries[0];
    base.clamped = false;
    base.z = Some(ComponentSpec {
        acceleration: Some(2e6),
        pulse: Some(PulseKind::HalfSine),
        duration: Some(5e-6),
        ..ComponentSpec::default()
    });
    let (solver, sol) = solve(&spec, |s| {
        s.tol = 1e-9;
        s.max_iter = 20_000;
    });
    assert!(sol.converged);
    let c = against_reference(&solver, &sol);
    println!(
        "base excitation: {} iterations, velocity {:.3e}, force {:.3e}, peak velocity {:.3e} m/s",
        sol.iterations, c.rel_diff_velocity, c.rel_diff_force, c.max_velocity
    );
    assert!(c.max_velocity > 5.0, "{c:?}");
    assert!(
        c.rel_diff_velocity <= 1e-6 && c.rel_diff_force <= 1e-6,
        "{c:?}"
    );
}

/// `a0` scales the acceleration (twice a0, twice every velocity, to 1e-9 of the peak) and leaves
/// `v0` to prescribed velocities (the scene has none); `duration` re-integrates the velocity:
/// set on a solved problem it gives what the scene written with that duration gives (1e-12).
#[test]
fn the_acceleration_amplitude_and_duration_are_parameters() {
    let spec = bar_driven(haversine(), 2);
    let (mut solver, one) = solved(&spec, 1.0, 1e-9);
    assert_eq!(
        Parameter::AccelerationAmplitude.current(solver.problem()),
        Some(PEAK)
    );
    assert_eq!(Parameter::VelocityAmplitude.current(solver.problem()), None);
    solver
        .set_parameter(Parameter::AccelerationAmplitude, 2.0 * PEAK)
        .expect("a0");
    let two = solver.solve(None).expect("solves");
    let (off, peak) = largest_difference((&solver, &one), (&solver, &two), 2.0);
    println!("a0 doubled: off by {off:.3e} of {peak:.3e}");
    assert!(peak > 15.0 && off <= 1e-9 * peak, "{off:e} of {peak:e}");

    solver
        .set_parameter(Parameter::AccelerationAmplitude, PEAK)
        .expect("a0");
    solver
        .set_parameter(Parameter::PulseDuration, 2.0 * DURATION)
        .expect("duration");
    let moved = solver.solve(None).expect("solves");
    let written = bar_driven(
        ComponentSpec {
            duration: Some(2.0 * DURATION),
            ..haversine()
        },
        2,
    );
    let (direct, sol) = solved(&written, 1.0, 1e-9);
    let (off, peak) = largest_difference((&solver, &moved), (&direct, &sol), 1.0);
    println!("duration doubled: off by {off:.3e} of {peak:.3e}");
    assert!(peak > 15.0 && off <= 1e-12 * peak, "{off:e} of {peak:e}");
}

/// An acceleration on a body that moves at t = 0 along that axis, or given with a velocity, is
/// refused naming the file and field.
#[test]
fn bad_accelerations_are_refused_naming_the_field() {
    let good = std::fs::read_to_string(lopin_tests::asset("bar")).expect("bar");
    let drive = "x = { velocity = 10.0, ramp = \"cosine\", ramp_time = 2e-6 }";
    assert!(good.contains(drive));
    let moving = good
        .replace(
            drive,
            "x = { acceleration = 1e6, pulse = \"half-sine\", duration = 2e-6 }",
        )
        .replace(
            "split = [5, 1, 1]",
            "split = [5, 1, 1]\nvelocity = [1.0, 0.0, 0.0]",
        );
    let both = good.replace(
        drive,
        "x = { velocity = 1.0, acceleration = 1e6, pulse = \"half-sine\", duration = 2e-6 }",
    );
    let cases = [
        (
            "moving body",
            moving,
            "boundary[0].x.acceleration",
            "starts from rest",
        ),
        ("with a velocity", both, "boundary[0].x", "not several"),
    ];
    lopin_tests::assert_clear_errors(&good, &cases, "lopin-bad-acceleration");
}
