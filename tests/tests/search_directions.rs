//! Wave-matched search directions (`lopin_core::interfaces::search_direction`, ρc_p along the interface
//! normal, ρc_s across it): the direction changes the iteration, never the solution. LATIN with
//! the wave direction converges to the monolithic reference (velocities and step-averaged forces
//! within 1e-6 at η < 1e-9) on perfect interfaces between two materials (`bar-bimaterial`), on
//! frictional contact (`two-blocks`) and with the two-scale linear stage (`two-blocks` split 2,
//! whose macro operator L_E = k Êᵀ A s Ê − k² Êᵀ A s B Z_E reads the direction); switching the
//! direction on a solver gives the iterations of a solver built with it.

use lopin_core::interfaces::search_direction::Directions;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::{Settings, Solver};
use lopin_judge::compare::compare;
use lopin_reference::monolithic::Monolithic;

fn solver_for(spec: &SceneSpec, directions: Directions, two_scale: bool, tol: f64) -> Solver {
    let problem = scene::problem_of(spec, &spec.name).expect("scene builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    settings.max_iter = 20_000;
    settings.directions = directions;
    settings.two_scale = two_scale;
    Solver::new(problem, settings).expect("setup")
}

#[test]
fn the_wave_direction_converges_to_the_reference() {
    let mut split = scene::load("two-blocks").expect("scene");
    split.split(2).expect("split");
    for (label, spec, two_scale) in [
        (
            "bar-bimaterial",
            scene::load("bar-bimaterial").expect("scene"),
            false,
        ),
        (
            "two-blocks",
            scene::load("two-blocks").expect("scene"),
            false,
        ),
        ("two-blocks split 2, two-scale", split, true),
    ] {
        let mut solver = solver_for(&spec, Directions::Wave, two_scale, 1e-9);
        let sol = solver.solve(None).expect("latin");
        assert!(sol.converged, "{label}");
        let reference = Monolithic::new(solver.problem().clone()).expect("reference");
        let mono = reference.solve().expect("reference solve");
        let c = compare(&solver, &sol, &reference, &mono);
        println!(
            "{label}, wave direction: {} iterations, velocity {:.3e}, force {:.3e}",
            sol.iterations, c.rel_diff_velocity, c.rel_diff_force
        );
        assert!(c.rel_diff_velocity <= 1e-6, "{label}: {c:?}");
        assert!(c.rel_diff_force <= 1e-6, "{label}: {c:?}");
    }
}

/// A solver switched to the wave direction and back iterates exactly as solvers built with
/// each direction (the refactorization and the operator classes follow the switch), and the two
/// directions do iterate differently.
#[test]
fn switching_the_direction_equals_building_with_it() {
    let spec = scene::load("two-blocks").expect("scene");
    let tol = 1e-4;
    let iso = solver_for(&spec, Directions::Isotropic, false, tol)
        .solve(None)
        .expect("isotropic");
    let wave = solver_for(&spec, Directions::Wave, false, tol)
        .solve(None)
        .expect("wave");
    assert_ne!(iso.iterations, wave.iterations);
    let mut solver = solver_for(&spec, Directions::Isotropic, false, tol);
    let mut set = *solver.settings();
    set.directions = Directions::Wave;
    solver.set_settings(set).expect("to wave");
    let switched = solver.solve(None).expect("switched");
    assert_eq!(switched.iterations, wave.iterations);
    assert_eq!(switched.eta, wave.eta);
    set.directions = Directions::Isotropic;
    solver.set_settings(set).expect("back");
    let back = solver.solve(None).expect("back");
    assert_eq!(back.iterations, iso.iterations);
    assert_eq!(back.eta, iso.eta);
}
