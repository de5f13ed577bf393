//! A warm solve on one-step windows carries on the difference its converged steps show between
//! the solution and the given state (METHOD §8): a given state off the solution by a constant
//! costs the first window its iterations and most later windows one (`two-blocks-ramp`, η <
//! 1e-6: 128 iterations over 60 steps against 1,562 cold), where a start taken as given would
//! pay the offset again at every step; and the solution does not depend on the start.

use lopin_core::scene;
use lopin_core::state::InterfaceState;
use lopin_core::{Parameter, Solution, Solver};

/// `two-blocks-ramp` with friction `f` on one-step windows, solved cold to η < 1e-6.
fn solved_cold(f: f64) -> (Solver, Solution) {
    let mut spec = scene::load("two-blocks-ramp").expect("scene");
    for i in spec.interfaces.iter_mut().filter(|i| i.friction.is_some()) {
        i.friction = Some(f);
    }
    lopin_tests::solve(&spec, |s| {
        s.tol = 1e-6;
        s.window = Some(1);
    })
}

/// The largest |x| over every substructure's F, and over every W.
fn scales(s: &InterfaceState) -> (f64, f64) {
    let max = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    s.subs
        .iter()
        .fold((0.0, 0.0), |(f, w), h| (f.max(max(&h.f)), w.max(max(&h.w))))
}

/// Both solves converged to η < 1e-6: the same F and W within 1e-4 of each field's largest value.
fn assert_same_solution(warm: &InterfaceState, cold: &InterfaceState) {
    let (f_scale, w_scale) = scales(cold);
    for (a, b) in warm.subs.iter().zip(&cold.subs) {
        for (x, y) in a.f.iter().zip(&b.f) {
            assert!((x - y).abs() <= 1e-4 * f_scale, "F {x} vs {y}");
        }
        for (x, y) in a.w.iter().zip(&b.w) {
            assert!((x - y).abs() <= 1e-4 * w_scale, "W {x} vs {y}");
        }
    }
}

#[test]
fn a_given_state_off_by_a_constant_costs_the_first_window_and_little_after() {
    // the scene's friction
    let (mut solver, cold) = solved_cold(0.3);
    let steps = solver.problem().time.steps;
    assert!(cold.converged);
    let (f_scale, w_scale) = scales(&cold.state);
    // every entry after step 0 moved by 1 % of its field's largest value, its sign alternating
    // over the entries
    let mut given = cold.state.clone();
    for h in &mut given.subs {
        let len = h.len;
        for (k, x) in h.f.iter_mut().enumerate().skip(len) {
            *x += 0.01 * f_scale * if k % 2 == 0 { 1.0 } else { -1.0 };
        }
        for (k, x) in h.w.iter_mut().enumerate().skip(len) {
            *x += 0.01 * w_scale * if k % 2 == 0 { 1.0 } else { -1.0 };
        }
    }
    let warm = solver.solve(Some(&given)).expect("warm");
    assert!(warm.converged);
    let mut per_window = vec![0usize; steps + 1];
    for r in &solver.counters().iterations {
        per_window[r.window_start] += 1;
    }
    let one = per_window[2..].iter().filter(|&&n| n == 1).count();
    eprintln!(
        "{steps} steps: cold {} iterations, warm from the offset state {}; per window {:?}",
        cold.iterations,
        warm.iterations,
        &per_window[1..]
    );
    // most windows after the first converge at their first iteration
    assert!(
        2 * one > steps,
        "{one} of {} windows at one iteration",
        steps - 1
    );
    assert!(8 * warm.iterations < cold.iterations);
    assert_same_solution(&warm.state, &cold.state);
}

#[test]
fn a_warm_friction_step_agrees_with_its_cold_solve() {
    let (mut solver, neighbour) = solved_cold(0.2);
    solver.set_parameter(Parameter::Friction, 0.25).expect("f");
    let warm = solver.solve(Some(&neighbour.state)).expect("warm");
    let cold = solver.solve(None).expect("cold");
    assert!(warm.converged && cold.converged);
    eprintln!(
        "f = 0.25 from f = 0.2: warm {} iterations, cold {}",
        warm.iterations, cold.iterations
    );
    assert!(
        2 * warm.iterations < cold.iterations,
        "warm {} vs cold {}",
        warm.iterations,
        cold.iterations
    );
    assert_same_solution(&warm.state, &cold.state);
}
