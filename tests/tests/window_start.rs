//! Where a cold window starts (`lopin_core::window_start`) changes the iteration, never the
//! solution. On `two-blocks` with one-step windows (the default of one cold solve with contact),
//! measured on this code: to η < 1e-3 the smooth extrapolation (the default) takes 295
//! iterations, `linear` 276, the held step (the previous default) 412 and F = W = 0 768; to η < 1e-6 smooth 1494 and hold 1664, and both agree with the monolithic
//! reference to the same accuracy.

use lopin_core::scene;
use lopin_core::scene::settings::WindowStart;
use lopin_core::{Settings, Solver};
use lopin_judge::compare::compare;
use lopin_reference::monolithic::Monolithic;

fn solve(start: WindowStart, tol: f64) -> (Solver, lopin_core::Solution) {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, &spec.name).expect("scene builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    assert_eq!(settings.window_start, WindowStart::Auto, "the default");
    assert_eq!(
        settings.window_start.resolve(tol.min(1e-3)),
        WindowStart::Smooth
    );
    settings.tol = tol;
    settings.window = Some(1);
    settings.window_start = start;
    let mut solver = Solver::new(problem, settings).expect("setup");
    let sol = solver.solve(None).expect("latin");
    assert!(sol.converged, "{start:?}: eta {}", sol.eta);
    (solver, sol)
}

#[test]
fn extrapolated_starts_cut_the_one_step_iterations() {
    let its = WindowStart::ALL.map(|s| solve(s, 1e-3).1.iterations);
    let [zero, hold, linear, smooth, auto] = its;
    assert_eq!(auto, smooth, "auto extrapolates at 1e-3");
    eprintln!("η < 1e-3: zero {zero}, hold {hold}, linear {linear}, smooth {smooth}");
    assert!(2 * zero > 3 * hold, "zero {zero} vs hold {hold}");
    assert!(
        10 * smooth <= 8 * hold,
        "smooth {smooth} vs hold {hold}: the extrapolation gains less than 20 %"
    );
    assert!(10 * linear <= 8 * hold, "linear {linear} vs hold {hold}");
}

#[test]
fn the_start_does_not_change_the_solution() {
    let (hold_solver, hold) = solve(WindowStart::Hold, 1e-6);
    let (smooth_solver, smooth) = solve(WindowStart::Smooth, 1e-6);
    eprintln!(
        "η < 1e-6: hold {} iterations, smooth {}",
        hold.iterations, smooth.iterations
    );
    assert!(smooth.iterations < hold.iterations);
    let reference = Monolithic::new(hold_solver.problem().clone()).expect("reference");
    let mono = reference.solve().expect("reference solve");
    let c_hold = compare(&hold_solver, &hold, &reference, &mono);
    let c_smooth = compare(&smooth_solver, &smooth, &reference, &mono);
    eprintln!("hold {c_hold:?}\nsmooth {c_smooth:?}");
    for (name, s, h) in [
        ("v", c_smooth.rel_diff_velocity, c_hold.rel_diff_velocity),
        ("F avg", c_smooth.rel_diff_force, c_hold.rel_diff_force),
        (
            "u",
            c_smooth.rel_diff_displacement,
            c_hold.rel_diff_displacement,
        ),
        (
            "contact",
            c_smooth.rel_diff_contact_force,
            c_hold.rel_diff_contact_force,
        ),
        ("energy", c_smooth.rel_diff_energy, c_hold.rel_diff_energy),
    ] {
        // both converged to η < 1e-6: the same solution within the tolerance's reach
        assert!(s < 1e-4 && h < 1e-4, "{name}: smooth {s:.2e}, hold {h:.2e}");
    }
}
