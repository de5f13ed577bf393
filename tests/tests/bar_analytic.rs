//! `bar` and `bar-bimaterial` at `--refine 4` against d'Alembert: behind the front
//! σ_xx = −ρ c V0 and v_x = V0; at the steel/aluminium change the transmitted stress is
//! 2 Z2 / (Z1 + Z2) times the incident one (SCENES.md). Tolerances: 0.5 % on plateau means
//! (discretization and ramp), converged to η < 1e-6.

use lopin_core::scene;
use lopin_tests::{plateau, solve};

fn refined(name: &str) -> scene::SceneSpec {
    let mut spec = scene::registry::builtin(name).expect("registry scene");
    spec.refine(4).expect("refine");
    spec
}

#[test]
fn bar_stress_and_velocity_plateaus_match_dalembert() {
    let (solver, sol) = solve(&refined("bar"), |s| s.tol = 1e-6);
    assert!(sol.converged);
    let steel = solver.problem().materials[0].material;
    let exact = -steel.density * steel.bar_speed() * 10.0;
    // t = 15 µs: front at c t = 0.078 m, ramp tail 0.0104 m behind it
    let (sigma, v) = plateau(&solver, &sol, 150, 0.005, 0.06);
    println!(
        "bar: sigma {sigma:.5e} (exact {exact:.5e}, rel {:.2e}), v {v:.5}",
        sigma / exact - 1.0
    );
    assert!((sigma / exact - 1.0).abs() < 5e-3);
    assert!((v / 10.0 - 1.0).abs() < 5e-3);
}

#[test]
fn bar_bimaterial_transmission_matches_impedance_ratio() {
    let (solver, sol) = solve(&refined("bar-bimaterial"), |s| s.tol = 1e-6);
    assert!(sol.converged);
    let m = &solver.problem().materials;
    let (z1, z2) = (
        m[0].material.density * m[0].material.bar_speed(),
        m[1].material.density * m[1].material.bar_speed(),
    );
    let incident_exact = -z1 * 10.0;
    // incident: t = 8 µs (front at 0.0415 m); transmitted: t = 15 µs (front at 0.077 m)
    let (incident, _) = plateau(&solver, &sol, 80, 0.005, 0.028);
    let (transmitted, _) = plateau(&solver, &sol, 150, 0.052, 0.065);
    let ratio = transmitted / incident;
    let exact = 2.0 * z2 / (z1 + z2);
    println!("bar-bimaterial: incident {incident:.5e} (exact {incident_exact:.5e}), ratio {ratio:.5} (exact {exact:.5})");
    assert!((incident / incident_exact - 1.0).abs() < 5e-3);
    assert!((ratio / exact - 1.0).abs() < 5e-3);
}

/// A prescribed traction P on the end of `bar` (instead of a velocity) sends σ = −P and
/// v = P/(ρc) behind the front (0.5 %).
#[test]
fn bar_under_prescribed_traction_matches_dalembert() {
    let mut spec = refined("bar");
    let steel = spec.materials[0].clone();
    let z = (steel.density * steel.young).sqrt();
    let p = z * 10.0;
    let x = spec.boundaries[0].x.as_mut().expect("x prescribed");
    x.velocity = None;
    x.traction = Some(p);
    let (solver, sol) = solve(&spec, |s| s.tol = 1e-6);
    assert!(sol.converged);
    let (sigma, v) = plateau(&solver, &sol, 150, 0.005, 0.06);
    println!(
        "bar under traction: sigma {sigma:.5e} (exact {:.5e}), v {v:.5} (exact 10)",
        -p
    );
    assert!((sigma / -p - 1.0).abs() < 5e-3);
    assert!((v / 10.0 - 1.0).abs() < 5e-3);
}
