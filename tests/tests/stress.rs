//! The numerical stability stress suite (core `stress::quick`): every adverse case must end with
//! finite values, η below its tolerance (or, where the case allows it, a clear "not converged"),
//! energy within the bounds of the module doc, and no interpenetration beyond the law's bound.
//! `lopin stress` runs the longer set.

use lopin_reference::stress;

#[test]
fn every_quick_case_passes() {
    let mut failures = Vec::new();
    for case in stress::quick() {
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
    }
    assert!(failures.is_empty(), "{failures:#?}");
}
