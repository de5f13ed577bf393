//! Factors of S kept in single precision (`model/src/linalg/factor.rs`, `solver.factors =
//! "single"`): half the memory of the values, the same iteration counts as double precision
//! (within 1 %), and LATIN at η < 1e-7 against the monolithic reference to a few parts in 10⁶
//! (the rounding of the factor, which η does not see: the linear stage solves a neighbouring
//! system), where double precision reaches a few parts in 10⁷; a lane of a batch keeps the
//! solver's precision.

use lopin_core::scene::settings::FactorPrecision;
use lopin_core::{scene, Solver};
use lopin_tests::{against_reference, solve};

#[test]
fn single_precision_factors_halve_the_memory_and_keep_a_few_parts_in_a_million() {
    let spec = scene::load("two-blocks").expect("scene");
    let mut runs = Vec::new();
    for precision in [FactorPrecision::Double, FactorPrecision::Single] {
        let (solver, sol) = solve(&spec, |s| {
            s.tol = 1e-7;
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
    }
    let (double, single) = (&runs[0], &runs[1]);
    assert!(double.1.rel_diff_velocity < 1e-6 && double.1.rel_diff_force < 2e-6);
    assert!(single.1.rel_diff_velocity < 1e-5, "{:?}", single.1);
    assert!(single.1.rel_diff_force < 1e-5, "{:?}", single.1);
    assert!(single.1.rel_diff_contact_force < 1e-6, "{:?}", single.1);
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

/// Changing the precision refactorizes; a lane made afterwards shares the new factors; records
/// name the precision only when it is single.
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
    assert_eq!(back.factors, FactorPrecision::Double);
    let err = FactorPrecision::parse("half").expect_err("refused");
    assert!(err.to_string().contains("factors"), "{err}");
}
