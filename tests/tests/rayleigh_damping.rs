//! Rayleigh damping C = α M + β K per material (`lopin_core::elements::rayleigh`) end to end:
//! a single-mode free vibration decays at ζ(ω) = α/(2ω) + βω/2 (within 1 %; the scheme's own
//! error is O((ωΔt)²)); LATIN and the monolithic reference, which assembles C itself, solve the
//! same damped problem (velocities and step-averaged forces within 1e-6 at η < 1e-9); the energy
//! balance closes with the dissipated energy (E_m + D_m = E_0 + W_m to 1e-9 of the input on
//! perfect interfaces, for both); bad damping input is refused with the file and field.

use lopin_core::scene::{self, SceneSpec};
use lopin_core::{post, Settings, Solver};
use lopin_reference::monolithic::Monolithic;
use lopin_tests::{against_reference, assert_clear_errors, solve};

/// Rod length (m), Young's modulus (Pa) and density (kg/m³) of the one-element oscillator.
const L: f64 = 0.1;
const E: f64 = 210e9;
const RHO: f64 = 7800.0;
const DT: f64 = 1e-7;

/// A steel rod of one hexahedron (ν = 0) held along x at x = 0 and launched at 1 m/s: its free
/// end is one mass ρAL/2 on the spring EA/L (lumped mass, exact uniform stretch), a single mode
/// at ω = √(2E/ρ)/L, with the damping `extra` (TOML lines of the material).
fn oscillator(extra: &str, steps: usize) -> SceneSpec {
    let text = format!(
        "name = \"oscillator\"\n\
         [time]\ndt = {DT:e}\nsteps = {steps}\n\
         [[material]]\nname = \"steel\"\nyoung = {E:e}\npoisson = 0.0\ndensity = {RHO:e}\n{extra}\n\
         [[body]]\nname = \"rod\"\nmaterial = \"steel\"\nmin = [0.0, 0.0, 0.0]\n\
         max = [{L}, 0.01, 0.01]\ndivisions = [1, 1, 1]\nvelocity = [1.0, 0.0, 0.0]\n\
         [[boundary]]\nbody = \"rod\"\nface = \"x-\"\nx = {{ velocity = 0.0 }}\n"
    );
    scene::reading::parse(&text, "oscillator.toml").expect("oscillator scene")
}

fn solver_for(spec: &SceneSpec, tol: f64, window: Option<usize>) -> Solver {
    let problem = scene::problem_of(spec, &spec.name).expect("scene builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    settings.window = window;
    settings.max_iter = 20_000;
    Solver::new(problem, settings).expect("setup")
}

/// The damping ratio of the free end's x-velocity history v_m (m ≥ 3): the least-squares
/// recurrence v_{m+1} = p v_m + q v_{m−1} of a linear two-state march gives its eigenvalues
/// r e^{±iθ}, hence σ = −ln r/Δt, ω_d = θ/Δt and ζ = σ/√(σ² + ω_d²); and ω = √(σ² + ω_d²).
fn measured_ratio(v: &[f64]) -> (f64, f64) {
    let (mut a11, mut a12, mut a22, mut b1, mut b2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for m in 3..v.len() - 1 {
        let (x1, x2, y) = (v[m], v[m - 1], v[m + 1]);
        a11 += x1 * x1;
        a12 += x1 * x2;
        a22 += x2 * x2;
        b1 += x1 * y;
        b2 += x2 * y;
    }
    let det = a11 * a22 - a12 * a12;
    let p = (b1 * a22 - b2 * a12) / det;
    let q = (a11 * b2 - a12 * b1) / det;
    let r = (-q).sqrt();
    let theta = (p / (2.0 * r)).acos();
    let (sigma, wd) = (-r.ln() / DT, theta / DT);
    let w = sigma.hypot(wd);
    (sigma / w, w)
}

/// The oscillator's free-end x-velocity at every step, converged to η < 1e-11 on one-step
/// windows.
fn free_end_velocity(extra: &str, steps: usize) -> Vec<f64> {
    let spec = oscillator(extra, steps);
    let mut solver = solver_for(&spec, 1e-11, Some(1));
    let sol = solver.solve(None).expect("solve");
    assert!(sol.converged, "{extra}");
    let sub = &solver.problem().subs[0];
    let tip = (0..sub.mesh.nodes.len())
        .find(|&k| sub.mesh.nodes[k][0] > 0.5 * L)
        .expect("a node at x = L");
    post::velocity_history(&solver, &sol)
        .iter()
        .map(|step| step[0][3 * tip])
        .collect()
}

/// Mass-proportional, stiffness-proportional and both (ζ = 2 % at half and twice the mode's
/// frequency): the free vibration decays at ζ(ω) = α/(2ω) + βω/2 within 1 %, and the undamped
/// rod does not decay (ζ < 1e-7, the resolution of the fit at η < 1e-11).
#[test]
fn a_single_mode_decays_at_the_rayleigh_ratio() {
    let omega = (2.0 * E / RHO).sqrt() / L;
    let f = omega / (2.0 * std::f64::consts::PI);
    // two periods
    let steps = (2.0 * 2.0 * std::f64::consts::PI / omega / DT) as usize;
    let zeta = 0.02;
    let both = lopin_core::elements::rayleigh::Rayleigh::from_ratio(zeta, [0.5 * f, 2.0 * f]);
    let cases = [
        ("alpha", 2.0 * zeta * omega, 0.0),
        ("beta", 0.0, 2.0 * zeta / omega),
        ("both", both.alpha, both.beta),
    ];
    for (name, alpha, beta) in cases {
        let expected = lopin_core::elements::rayleigh::Rayleigh { alpha, beta }.ratio(omega);
        let v = free_end_velocity(&format!("alpha = {alpha:e}\nbeta = {beta:e}"), steps);
        let (measured, w) = measured_ratio(&v);
        println!(
            "{name}: α = {alpha:.4e}, β = {beta:.4e}: ζ measured {measured:.6e}, expected \
             {expected:.6e} ({:+.2e}), ω {w:.6e} against {omega:.6e}",
            measured / expected - 1.0
        );
        assert!(
            (measured / expected - 1.0).abs() < 1e-2,
            "{name}: ζ = {measured:e}, expected {expected:e}"
        );
        assert!((w / omega - 1.0).abs() < 1e-3, "{name}: ω = {w:e}");
    }
    let (undamped, _) = measured_ratio(&free_end_velocity("", steps));
    println!("undamped: ζ measured {undamped:.3e}");
    assert!(
        undamped.abs() < 1e-7,
        "the undamped rod decays: ζ = {undamped:e}"
    );
}

/// `two-blocks` (frictional contact) and `bar-bimaterial` (perfect interfaces) with 5 % damping
/// over [20 kHz, 400 kHz] on every material: LATIN at η < 1e-9 against the reference (velocities
/// and step-averaged forces within 1e-6); the damping dissipates a share of the input that both
/// agree on (1e-6), and with perfect interfaces E_m + D_m = E_0 + W_m at every step to 1e-9 of
/// the input, for both.
#[test]
fn damped_latin_agrees_with_the_reference_and_the_energy_balance_closes() {
    for name in ["bar-bimaterial", "two-blocks"] {
        let mut spec = scene::load(name).expect("scene");
        for m in &mut spec.materials {
            m.damping_ratio = Some(0.05);
            m.damping_band = Some([2e4, 4e5]);
        }
        let mut solver = solver_for(&spec, 1e-9, None);
        let sol = solver.solve(None).expect("latin");
        assert!(sol.converged, "{name}");
        let reference = Monolithic::new(solver.problem().clone()).expect("reference");
        let mono = reference.solve().expect("reference solve");
        let c = lopin_judge::compare::compare(&solver, &sol, &reference, &mono);
        println!(
            "{name} damped: {} iterations, velocity {:.3e}, force {:.3e}, contact {:.3e}",
            sol.iterations, c.rel_diff_velocity, c.rel_diff_force, c.rel_diff_contact_force
        );
        assert!(c.rel_diff_velocity <= 1e-6, "{name}: {c:?}");
        assert!(c.rel_diff_force <= 1e-6, "{name}: {c:?}");
        let (e_latin, e_ref) = (post::energy(&solver, &sol), reference.energy(&mono));
        let n = e_latin.kinetic.len() - 1;
        let input = e_ref.input_work[n].abs();
        let (d_latin, d_ref) = (e_latin.damping[n], e_ref.damping[n]);
        println!(
            "{name}: input {input:.4e} J, dissipated LATIN {d_latin:.6e} J, reference \
             {d_ref:.6e} J"
        );
        assert!(
            d_ref > 1e-2 * input,
            "{name}: the damping dissipated {d_ref:e} J"
        );
        assert!((d_latin - d_ref).abs() <= 1e-6 * d_ref, "{name}");
        if name == "bar-bimaterial" {
            for (who, e) in [("LATIN", &e_latin), ("reference", &e_ref)] {
                let worst = (0..=n)
                    .map(|m| (e.total(m) + e.damping[m] - e.total(0) - e.input_work[m]).abs())
                    .fold(0.0, f64::max)
                    / input;
                println!("{name} {who}: |E + D − E0 − W| ≤ {worst:.3e} of the input");
                assert!(worst < 1e-9, "{name} {who}: balance off by {worst:e}");
            }
        }
    }
}

/// A damped material at every ρ∞: the dissipative scheme with damping still agrees with the
/// reference (`bar-bimaterial`, ρ∞ = 0.5, η < 1e-9, 1e-6).
#[test]
fn damping_with_the_dissipative_scheme_agrees_with_the_reference() {
    let mut spec = scene::load("bar-bimaterial").expect("scene");
    for m in &mut spec.materials {
        m.alpha = Some(2e4);
        m.beta = Some(2e-8);
    }
    let (solver, sol) = solve(&spec, |s| {
        s.tol = 1e-9;
        s.rho_inf = 0.5;
        s.max_iter = 20_000;
    });
    assert!(sol.converged);
    let c = against_reference(&solver, &sol);
    println!(
        "ρ∞ = 0.5 damped: {} iterations, velocity {:.3e}, force {:.3e}",
        sol.iterations, c.rel_diff_velocity, c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity <= 1e-6 && c.rel_diff_force <= 1e-6,
        "{c:?}"
    );
}

/// Bad damping is refused naming the file, the material's field and the reason.
#[test]
fn bad_damping_is_refused_naming_the_field() {
    let good = std::fs::read_to_string(lopin_tests::asset("bar")).expect("bar");
    let at = "density = 7800.0 # kg/m3\n";
    assert!(good.contains(at));
    let with = |lines: &str| good.replace(at, &format!("{at}{lines}\n"));
    let cases = [
        (
            "negative alpha",
            with("alpha = -1.0"),
            "material[0].alpha",
            "≥ 0",
        ),
        (
            "ratio without band",
            with("damping_ratio = 0.02"),
            "material[0].damping_ratio",
            "needs `damping_band",
        ),
        (
            "band without ratio",
            with("damping_band = [10.0, 100.0]"),
            "material[0].damping_band",
            "needs `damping_ratio`",
        ),
        (
            "both ways",
            with("alpha = 1.0\ndamping_ratio = 0.02\ndamping_band = [10.0, 100.0]"),
            "material[0].alpha",
            "not both",
        ),
        (
            "ratio out of range",
            with("damping_ratio = 1.5\ndamping_band = [10.0, 100.0]"),
            "material[0].damping_ratio",
            "(0, 1)",
        ),
        (
            "band in the wrong order",
            with("damping_ratio = 0.02\ndamping_band = [100.0, 10.0]"),
            "material[0].damping_band",
            "0 < f1 < f2",
        ),
    ];
    assert_clear_errors(&good, &cases, "lopin-bad-damping");
}
