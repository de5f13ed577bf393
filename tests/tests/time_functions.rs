//! Time functions on a boundary (METHOD §5 boundary data): `bar` driven at x = 0 by each
//! standard pulse against d'Alembert's v(x, t) = V(t − x/c) (space–time L2 error of the
//! x-velocities, η < 1e-7, one-step windows), converging under refinement in x and t at the
//! order the pulse's smoothness allows; a table that equals a pulse at every time point gives
//! that pulse's fields (to 1e-9 of the peak, in the same iterations); the velocity amplitude
//! `v0` scales a pulse (the bar is linear: twice the amplitude, twice the fields, to 1e-9).

use lopin_core::scene::spec::ComponentSpec;
use lopin_core::time::time_function::PulseKind;
use lopin_core::{post, scene, Parameter, Solution, Solver};
use lopin_judge::compare::compare;
use lopin_reference::exact::{l2_error, BarExact};
use lopin_reference::monolithic::Monolithic;
use lopin_tests::{bar_driven, largest_difference, solve};

/// Pulse duration (s): a fifth of the 15 µs run, about 20 elements of the refined bar.
const DURATION: f64 = 3e-6;

/// `bar` refined 4 times in x (and its step divided by 4), driven by `drive`.
fn bar(drive: ComponentSpec) -> scene::SceneSpec {
    bar_driven(drive, 4)
}

fn pulse(kind: PulseKind, rise: Option<f64>) -> ComponentSpec {
    ComponentSpec {
        velocity: Some(10.0),
        pulse: Some(kind),
        duration: Some(DURATION),
        rise,
        ..ComponentSpec::default()
    }
}

fn solved(spec: &scene::SceneSpec) -> (Solver, Solution) {
    let (solver, sol) = solve(spec, |s| {
        s.tol = 1e-7;
        s.window = Some(1);
    });
    assert!(sol.converged);
    (solver, sol)
}

/// The L2 error against d'Alembert of the bar refined `r` times under `drive`.
fn error(drive: ComponentSpec, r: usize) -> f64 {
    let (solver, sol) = solved(&bar_driven(drive, r));
    let p = solver.problem();
    let exact = BarExact::for_problem(p).expect("the front stays inside the bar");
    let history = post::velocity_history(&solver, &sol);
    l2_error(p, &exact, &mut |s, m| history[m][s].clone())
}

/// Refined 2, 4 and 8 times in x and t, each pulse's error falls at the order its smoothness
/// allows: near 2 for the haversine (C¹), near 1 for the half-sine and the trapezoid (kinks at
/// their corners), slowly for the sawtooth (a jump at its end).
#[test]
fn a_bar_driven_by_each_pulse_converges_to_dalembert() {
    // (name, drive, lowest order on the finest pair, largest error at refine 8)
    let cases = [
        ("half-sine", pulse(PulseKind::HalfSine, None), 0.9, 0.06),
        ("haversine", pulse(PulseKind::Haversine, None), 1.6, 0.04),
        ("sawtooth", pulse(PulseKind::Sawtooth, None), 0.2, 0.3),
        (
            "trapezoid",
            pulse(PulseKind::Trapezoid, Some(1e-6)),
            0.9,
            0.07,
        ),
    ];
    for (name, drive, order, largest) in cases {
        let e: Vec<f64> = [2, 4, 8].map(|r| error(drive.clone(), r)).to_vec();
        let orders: Vec<f64> = e.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!("{name}: L2 errors against d'Alembert {e:.3?}, orders {orders:.2?}");
        assert!(orders.iter().all(|&o| o > 0.0), "{name}: {e:?}");
        assert!(
            orders[1] > order && e[2] < largest,
            "{name}: {e:?}, orders {orders:?}"
        );
    }
}

/// A table through the trapezoid's corners equals it at every time point, and gives its
/// fields; through the haversine's values at the time points it gives the haversine's.
#[test]
fn a_table_equal_to_a_pulse_at_the_time_points_gives_its_fields() {
    let (r, d) = (1e-6, DURATION);
    let corners = ComponentSpec {
        velocity: Some(10.0),
        table: Some(vec![[0.0, 0.0], [r, 1.0], [d - r, 1.0], [d, 0.0]]),
        ..ComponentSpec::default()
    };
    let (a, sa) = solved(&bar(corners));
    let (b, sb) = solved(&bar(pulse(PulseKind::Trapezoid, Some(r))));
    let (diff, peak) = largest_difference((&a, &sa), (&b, &sb), 1.0);
    println!("table against trapezoid: largest difference {diff:.3e} of a peak {peak:.3e}");
    assert!(peak > 9.0 && diff <= 1e-9 * peak, "{diff:e} of {peak:e}");
    assert_eq!(sa.iterations, sb.iterations);
}

/// `v0` sets a pulse's peak: twice the amplitude, twice every velocity (the bar is linear).
#[test]
fn the_velocity_amplitude_scales_a_pulse() {
    let spec = bar(pulse(PulseKind::HalfSine, None));
    let (mut solver, one) = solved(&spec);
    assert_eq!(
        Parameter::VelocityAmplitude.current(solver.problem()),
        Some(10.0)
    );
    solver
        .set_parameter(Parameter::VelocityAmplitude, 20.0)
        .expect("v0");
    let two = solver.solve(None).expect("solves");
    let (off, peak) = largest_difference((&solver, &one), (&solver, &two), 2.0);
    let peak = peak / 2.0;
    assert!(off <= 1e-9 * peak, "{off:e} of {peak:e}");
}

/// `two-blocks` shocked on top by a haversine velocity pulse (5 µs) and by a table of a
/// measured-like pulse (its points in a CSV file beside the scene): LATIN at η < 1e-6 over the
/// whole interval agrees with the monolithic reference, which reads the same time function
/// independently of the solver (velocities and forces to 1e-4, contact forces to 1e-6).
#[test]
fn a_shock_pulse_through_contact_agrees_with_the_monolithic_reference() {
    let dir = std::env::temp_dir().join(format!("lopin-time-functions-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    std::fs::write(
        dir.join("pulse.csv"),
        "time_s,scale\n0,0\n1e-6,0.4\n2.5e-6,1.0\n4e-6,0.7\n6e-6,0\n",
    )
    .expect("csv");
    let text = scene::reading::to_toml(&scene::load("two-blocks").expect("scene"));
    let haversine = text.replace(
        "ramp = \"cosine\"\nramp_time = 0.0000025\n",
        "pulse = \"haversine\"\nduration = 0.000005\n",
    );
    let table = text.replace(
        "ramp = \"cosine\"\nramp_time = 0.0000025\n",
        "table_file = \"pulse.csv\"\n",
    );
    assert!(haversine != text && table != text, "the scene's top ramp");
    for (name, toml) in [("haversine", haversine), ("table", table)] {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, toml).expect("scene");
        let spec = scene::load(path.to_str().expect("utf-8")).expect("loads");
        let (solver, sol) = solve(&spec, |s| {
            s.tol = 1e-6;
            s.window = None;
        });
        assert!(sol.converged, "{name}");
        let reference = Monolithic::new(solver.problem().clone()).expect("reference");
        let mono = reference.solve().expect("reference solve");
        let c = compare(&solver, &sol, &reference, &mono);
        println!("{name}: {c:?}");
        assert!(
            c.rel_diff_velocity < 1e-4 && c.rel_diff_force < 1e-4,
            "{name}: {c:?}"
        );
        assert!(c.rel_diff_contact_force < 1e-6, "{name}: {c:?}");
    }
    std::fs::remove_dir_all(&dir).expect("cleans up");
}

/// Bad time functions are refused with the scene, the field and the reason: times that do not
/// increase, a non-finite value, a pulse longer than the run, a trapezoid without its rise, a
/// rise on another pulse, two time functions at once, a CSV line that is not two numbers and a
/// missing CSV file (each named with its path and line).
#[test]
fn bad_time_functions_are_refused_naming_the_file_and_field() {
    let text = scene::reading::to_toml(&scene::load("two-blocks").expect("scene"));
    let ramp = "ramp = \"cosine\"\nramp_time = 0.0000025\n";
    assert!(text.contains(ramp));
    let dir = std::env::temp_dir().join(format!("lopin-bad-time-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("tmp");
    std::fs::write(dir.join("bad.csv"), "t,v\n0,0\n1e-6,fast\n").expect("csv");
    let cases = [
        (
            "table = [[0.0, 0.0], [2e-6, 1.0], [2e-6, 0.5]]\n",
            "boundary[0].z.table",
            "table[2]: time 2e-6 s is not after the previous point's 2e-6 s",
        ),
        (
            "table = [[0.0, 0.0], [1e-6, nan]]\n",
            "boundary[0].z.table",
            "table[1] = [1e-6, NaN]: not a finite number",
        ),
        (
            "pulse = \"half-sine\"\nduration = 0.011\n",
            "boundary[0].z.duration",
            "a pulse of 0.011 s is longer than the run (1.5e-5 s",
        ),
        (
            "pulse = \"trapezoid\"\nduration = 0.00001\n",
            "boundary[0].z.rise",
            "a trapezoid pulse needs its rise",
        ),
        (
            "pulse = \"haversine\"\nduration = 0.00001\nrise = 0.000001\n",
            "boundary[0].z.rise",
            "a trapezoid pulse's, not a haversine's",
        ),
        (
            "ramp_time = 0.000001\ntable = [[0.0, 1.0]]\n",
            "boundary[0].z",
            "give one time function: `ramp_time` and `table` both describe it",
        ),
        (
            "table_file = \"bad.csv\"\n",
            "boundary[0].z.table_file",
            "bad.csv: line 3: expected two numbers `t,value`, got `1e-6,fast`",
        ),
        (
            "table_file = \"missing.csv\"\n",
            "boundary[0].z.table_file",
            "missing.csv: ",
        ),
    ];
    for (i, (law, field, reason)) in cases.into_iter().enumerate() {
        let path = dir.join(format!("case-{i}.toml"));
        std::fs::write(&path, text.replace(ramp, law)).expect("scene");
        let path = path.to_str().expect("utf-8").to_string();
        let e = scene::load(&path).expect_err(law).to_string();
        assert!(
            e.starts_with(&path) && e.contains(&format!("field `{field}`")) && e.contains(reason),
            "{law}: {e}"
        );
    }
    std::fs::remove_dir_all(&dir).expect("cleans up");
}

/// `duration` is a parameter: set on a solved problem it gives what a scene written with that
/// duration gives (the same iterations, the fields to 1e-12 of their peak), a trapezoid's rise
/// scaled with it; a duration longer than the run is refused, naming it.
#[test]
fn the_pulse_duration_is_a_parameter() {
    let (mut moved, _) = solved(&bar(pulse(PulseKind::Trapezoid, Some(1e-6))));
    assert_eq!(
        Parameter::PulseDuration.current(moved.problem()),
        Some(DURATION)
    );
    moved
        .set_parameter(Parameter::PulseDuration, 2.0 * DURATION)
        .expect("duration");
    let a = moved.solve(None).expect("solves");
    let written = ComponentSpec {
        duration: Some(2.0 * DURATION),
        ..pulse(PulseKind::Trapezoid, Some(2e-6))
    };
    let (direct, b) = solved(&bar(written));
    assert_eq!(a.iterations, b.iterations);
    let (diff, peak) = largest_difference((&moved, &a), (&direct, &b), 1.0);
    assert!(peak > 9.0 && diff <= 1e-12 * peak, "{diff:e} of {peak:e}");
    let e = moved
        .set_parameter(Parameter::PulseDuration, 1.0)
        .expect_err("longer than the run")
        .to_string();
    assert!(
        e.contains("duration") && e.contains("longer than the run"),
        "{e}"
    );
}

/// `t0` sets a traction's amplitude, here a half-sine pulse of traction on the end of `bar`:
/// twice the amplitude, twice every velocity (the bar is linear), to 1e-9 of the peak.
#[test]
fn the_traction_amplitude_scales_a_traction_pulse() {
    let drive = ComponentSpec {
        velocity: None,
        traction: Some(4e8),
        ..pulse(PulseKind::HalfSine, None)
    };
    let (mut solver, one) = solved(&bar(drive));
    assert_eq!(
        Parameter::TractionAmplitude.current(solver.problem()),
        Some(4e8)
    );
    assert_eq!(Parameter::VelocityAmplitude.current(solver.problem()), None);
    solver
        .set_parameter(Parameter::TractionAmplitude, 8e8)
        .expect("t0");
    let two = solver.solve(None).expect("solves");
    let (off, peak) = largest_difference((&solver, &one), (&solver, &two), 2.0);
    assert!(peak > 1.0 && off <= 1e-9 * peak, "{off:e} of {peak:e}");
}
