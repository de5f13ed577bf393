//! Factors of S kept in single precision (`model/src/linalg/factor.rs`, `solver.factors =
//! "single"`): half the memory of the values, and, since every single-precision solve is
//! refined against S in double (`core/src/stages/linear_stage.rs`), LATIN converges to the
//! solution of the double-precision linear stage: at η < 1e-9 the same iterations as double
//! precision (within 1 %), against the monolithic reference as close as double precision gets
//! (without the refinement a few parts in 10⁶, and η stalls above 1e-9), and against the
//! double-precision LATIN solution within 1e-10 (the replay of the fields refines its solves
//! too); a lane of a batch keeps the solver's precision.

use lopin_core::scene::settings::FactorPrecision;
use lopin_core::{scene, Solver};
use lopin_tests::{against_reference, largest_difference, solve, solve_in_lanes, state_difference};

#[test]
fn single_precision_factors_halve_the_memory_and_converge_to_the_double_precision_solution() {
    let spec = scene::load("two-blocks").expect("scene");
    let mut runs = Vec::new();
    let mut solutions = Vec::new();
    for precision in [FactorPrecision::Double, FactorPrecision::Single] {
        let (solver, sol) = solve(&spec, |s| {
            s.tol = 1e-9;
            s.window = Some(1);
            s.factors = precision;
        });
        assert!(sol.converged);
        let c = against_reference(&solver, &sol);
        let values: usize = solver.factors().iter().map(|f| f.value_bytes()).sum();
        let bytes: usize = solver.factors().iter().map(|f| f.bytes()).sum();
        println!(
            "{}: {} iterations, velocity {:.3e}, force {:.3e}, contact {:.3e}, factors {} \
             bytes ({values} of values)",
            precision.name(),
            sol.iterations,
            c.rel_diff_velocity,
            c.rel_diff_force,
            c.rel_diff_contact_force,
            bytes
        );
        assert!(solver
            .factors()
            .iter()
            .all(|f| f.is_single() == (precision == FactorPrecision::Single)));
        runs.push((sol.iterations, c, values, bytes));
        solutions.push((solver, sol));
    }
    let (double, single) = (&runs[0], &runs[1]);
    assert!(double.1.rel_diff_velocity < 1e-8 && double.1.rel_diff_force < 2e-8);
    assert!(single.1.rel_diff_velocity < 1e-8, "{:?}", single.1);
    assert!(single.1.rel_diff_force < 2e-8, "{:?}", single.1);
    assert!(single.1.rel_diff_contact_force < 2e-9, "{:?}", single.1);
    let (d, largest) = largest_difference(
        (&solutions[1].0, &solutions[1].1),
        (&solutions[0].0, &solutions[0].1),
        1.0,
    );
    println!("single against double: velocity {:.3e}", d / largest);
    assert!(d < 1e-10 * largest, "{:.3e} of {largest:.3e}", d);
    assert!(
        single.0.abs_diff(double.0) * 100 <= double.0,
        "{} iterations against {}",
        single.0,
        double.0
    );
    assert_eq!(2 * single.2, double.2, "values halved");
    assert!(
        single.3 < double.3 * 6 / 10,
        "{} bytes against {}",
        single.3,
        double.3
    );
}

/// Over the whole interval (every iteration marches all 60 steps, each refined from the same
/// step of the iteration before), with the dissipative scheme ρ∞ = 0.5: at η < 1e-9 single
/// precision takes the iterations of double precision (within 1 %) and its velocities are
/// double precision's to 1e-10 of the largest.
#[test]
fn single_precision_over_the_whole_interval_converges_to_the_double_precision_solution() {
    let spec = scene::load("two-blocks").expect("scene");
    let runs: Vec<_> = [FactorPrecision::Double, FactorPrecision::Single]
        .into_iter()
        .map(|precision| {
            solve(&spec, |s| {
                s.tol = 1e-9;
                s.window = None;
                s.rho_inf = 0.5;
                s.factors = precision;
            })
        })
        .collect();
    let (double, single) = (&runs[0], &runs[1]);
    assert!(double.1.converged && single.1.converged);
    let (d, largest) = largest_difference((&single.0, &single.1), (&double.0, &double.1), 1.0);
    println!(
        "whole interval: {} iterations against {}, velocities {:.3e} apart",
        single.1.iterations,
        double.1.iterations,
        d / largest
    );
    assert!(
        single.1.iterations.abs_diff(double.1.iterations) * 100 <= double.1.iterations,
        "{} against {}",
        single.1.iterations,
        double.1.iterations
    );
    assert!(d < 1e-10 * largest, "{:.3e}", d / largest);
}

/// Changing the precision refactorizes; a lane made afterwards shares the new factors; records
/// name the precision only when it is not the default `auto`.
#[test]
fn the_precision_is_a_setting_that_refactorizes() {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let settings = lopin_core::Settings::for_problem(&problem, &spec.solver);
    let mut solver = Solver::new(problem, settings).expect("solver");
    assert!(!solver.factor(0).is_single());
    let before = solver.lane().expect("lane");
    solver
        .set_settings(lopin_core::Settings {
            factors: FactorPrecision::Single,
            ..settings
        })
        .expect("single");
    assert!(solver.factor(0).is_single());
    assert!(!solver.shares_factors(&before), "refactorized");
    let lane = solver.lane().expect("lane");
    assert!(lane.factor(0).is_single() && lane.shares_factors(&solver));
    assert_eq!(
        FactorPrecision::parse("single").expect("parses"),
        FactorPrecision::Single
    );
    // records (and the fingerprints hashed from them) name the precision only when it is not
    // the default, so runs that never asked read as before
    let double = serde_json::to_string(&settings).expect("json");
    assert!(!double.contains("factors"), "{double}");
    let single = serde_json::to_string(solver.settings()).expect("json");
    assert!(single.contains(r#""factors":"single""#), "{single}");
    let back: lopin_core::Settings = serde_json::from_str(&double).expect("reads back");
    assert_eq!(back.factors, FactorPrecision::Auto);
    let err = FactorPrecision::parse("half").expect_err("refused");
    assert!(err.to_string().contains("factors"), "{err}");
}

/// The default precision, `auto`, keeps the factors of substructures of 3,000 nodes and more in
/// single precision and the smaller ones in double: `two-blocks` (726 nodes a block) in double,
/// `two-blocks --refine 2` (4,851) in single.
#[test]
fn the_default_precision_is_single_for_large_substructures_only() {
    for (refine, single) in [(1, false), (2, true)] {
        let mut spec = scene::load("two-blocks").expect("scene");
        spec.refine(refine).expect("refines");
        let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
        let nodes = problem.subs[0].ndof() / 3;
        assert_eq!(
            nodes >= lopin_core::linalg::factor::LARGE_NODES,
            single,
            "{nodes} nodes"
        );
        let settings = lopin_core::Settings::for_problem(&problem, &spec.solver);
        assert_eq!(settings.factors, FactorPrecision::Auto);
        let solver = Solver::new(problem, settings).expect("solver");
        assert!(
            solver.factors().iter().all(|f| f.is_single() == single),
            "refine {refine}"
        );
    }
}

/// Lanes of a batch on single-precision factors refine their solves too: two friction
/// coefficients solved together at η < 1e-9 reach the iterations and interface states of the
/// same configurations solved alone in double precision (to 1e-11 of each field's largest value).
#[test]
fn lanes_on_single_precision_factors_reach_the_double_precision_solutions() {
    use lopin_core::{Parameter, Settings};
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = 1e-9;
    settings.window = Some(1);
    let double = Solver::new(problem.clone(), settings).expect("solver");
    let single = Solver::new(
        problem,
        Settings {
            factors: FactorPrecision::Single,
            ..settings
        },
    )
    .expect("solver");
    let frictions = [0.1, 0.6];
    let solutions = solve_in_lanes(&single, &frictions, &[None, None]);
    for (sol, &f) in solutions.iter().zip(&frictions) {
        let mut alone = double.lane().expect("lane");
        alone
            .set_parameter(Parameter::Friction, f)
            .expect("friction");
        let reference = alone.solve(None).expect("solve");
        assert!(sol.converged && reference.converged);
        assert!(
            sol.iterations.abs_diff(reference.iterations) * 100 <= reference.iterations,
            "f = {f}: {} iterations against {}",
            sol.iterations,
            reference.iterations
        );
        let worst = state_difference(sol, &reference);
        println!(
            "f = {f}: {} iterations against {}, states {worst:.3e} apart",
            sol.iterations, reference.iterations
        );
        assert!(worst < 1e-11, "f = {f}: {worst:.3e}");
    }
}
