//! The numerical stability stress suite (core `stress::quick`): every adverse case must end with
//! finite values, η below its tolerance (or, where the case allows it, a clear "not converged"),
//! energy within the bounds of the module doc, and no interpenetration beyond the law's bound.
//! The same suite runs again with Anderson acceleration of depth 5 (`[solver] anderson`, METHOD
//! §6 relaxation replaced by the mixing of `core/src/stages/acceleration.rs`): the acceleration must not
//! cost any case its stability. `lopin stress` runs the longer set.

use lopin_judge::stress::{self, StressCase};

fn run_all(cases: Vec<StressCase>) -> Vec<stress::StressOutcome> {
    let mut failures = Vec::new();
    let mut outcomes = Vec::new();
    for case in cases {
        let o = case.run().expect("case builds and solves");
        println!(
            "{:<46} {:>7} it  eta {:.2e}  E ratio {:.9}  ref {:?}  gap {:?}  {}",
            o.name,
            o.iterations,
            o.eta,
            o.max_energy_ratio,
            o.reference_energy_ratio,
            o.min_gap,
            o.verdict
        );
        assert!(o.eta.is_finite());
        if !o.ok {
            failures.push(format!("{}: {}", o.name, o.verdict));
        }
        outcomes.push(o);
    }
    assert!(failures.is_empty(), "{failures:#?}");
    outcomes
}

#[test]
fn every_quick_case_passes() {
    run_all(stress::quick());
}

#[test]
fn every_quick_case_passes_with_anderson() {
    let cases: Vec<StressCase> = stress::quick()
        .into_iter()
        .map(|mut c| {
            c.spec.solver.anderson = Some(5);
            c
        })
        .collect();
    let n = cases.len();
    let outcomes = run_all(cases);
    assert_eq!(outcomes.len(), n);
    let converged = outcomes.iter().filter(|o| o.converged).count();
    println!("with Anderson 5: {converged} of {n} cases converged");
}
