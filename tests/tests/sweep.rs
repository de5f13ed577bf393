//! Multiresolution (METHOD §8): a warm-started solution agrees with the cold solution of the same
//! parameter value within the accuracy the tolerance implies. Bound: both solutions are within
//! C·η of the converged one, where η measures interface fields in an energy norm and the test
//! compares nodal velocities in the max norm over space-time; C ≈ 10 on `two-blocks`, so the
//! bound is 30 · tol relative to max |v| (measured up to 18 · tol).

use lopin_core::study::Predictor;
use lopin_core::{scene, Parameter, Settings, Solver};
use lopin_tests::{rel_diff, velocity_history};

fn warm_vs_cold(tol: f64) -> Vec<(f64, usize, usize, f64)> {
    let spec = scene::registry::builtin("two-blocks").expect("registry");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    // the first value of the study, solved cold, seeds the warm chain
    solver.set_parameter(Parameter::Friction, 0.0).expect("f");
    let mut history = vec![(0.0, solver.solve(None).expect("cold").state)];
    let mut out = Vec::new();
    for f in [0.1, 0.2, 0.3] {
        solver.set_parameter(Parameter::Friction, f).expect("f");
        let refs: Vec<(f64, &lopin_core::InterfaceState)> =
            history.iter().map(|(v, s)| (*v, s)).collect();
        let start = Predictor::Previous.extrapolate(&refs, f);
        let warm = solver.solve(start.as_ref()).expect("warm");
        let vw = velocity_history(&solver, &warm);
        let cold = solver.solve(None).expect("cold");
        let vc = velocity_history(&solver, &cold);
        assert!(warm.converged && cold.converged);
        out.push((f, warm.iterations, cold.iterations, rel_diff(&vw, &vc)));
        history.push((f, warm.state));
    }
    out
}

#[test]
fn warm_started_solutions_agree_with_cold_ones() {
    for tol in [1e-3, 1e-6] {
        for (f, warm, cold, d) in warm_vs_cold(tol) {
            println!("tol {tol:.0e}, f {f}: warm {warm} / cold {cold} iterations, difference {d:.2e} (bound {:.0e})", 30.0 * tol);
            assert!(d <= 30.0 * tol, "f {f}, tol {tol}: {d}");
            assert!(
                warm <= cold + 10,
                "f {f}: warm start should not cost much more than cold"
            );
        }
    }
}

/// Sweeping the imposed velocity amplitude: with zero initial gap the problem is positively
/// homogeneous in V0 (linear elasticity, contact and Coulomb laws all are), so the solution at
/// 2 V0 is twice the solution at V0 (to 1e-5 at η < 1e-7).
#[test]
fn velocity_amplitude_sweep_is_homogeneous() {
    let spec = scene::registry::builtin("two-blocks").expect("registry");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = 1e-7;
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    solver
        .set_parameter(Parameter::VelocityAmplitude, 5.0)
        .expect("v0");
    let a = solver.solve(None).expect("solve");
    let va = velocity_history(&solver, &a);
    solver
        .set_parameter(Parameter::VelocityAmplitude, 10.0)
        .expect("v0");
    let b = solver.solve(Some(&a.state)).expect("solve");
    let vb: Vec<Vec<Vec<f64>>> = velocity_history(&solver, &b)
        .into_iter()
        .map(|m| {
            m.into_iter()
                .map(|s| s.into_iter().map(|x| 0.5 * x).collect())
                .collect()
        })
        .collect();
    let d = rel_diff(&vb, &va);
    println!(
        "v0 5 -> 10: {} iterations warm, homogeneity error {d:.2e}",
        b.iterations
    );
    assert!(d < 1e-5, "{d}");
}
