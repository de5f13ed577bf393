//! Convergence order (in the manner of fenris's convergence tests): the `bar` scene refined in
//! space and time together (h and Δt divided by r = 1, 2, 4, 8, so c Δt / h stays fixed), solved
//! by LATIN (one-step windows) to η < 1e-7, against d'Alembert's exact solution (`lopin_reference::exact`): the
//! relative space–time L2 error of v_x must fall at the order of the scheme (trapezoidal rule,
//! trilinear elements with lumped mass: second order for smooth data). The coarsest mesh puts
//! two elements in the ramp's front (c · 2 µs = 10 mm, h = 5 mm), so the first halving is
//! pre-asymptotic; measured: errors 1.18e-1, 6.24e-2, 2.07e-2, 6.21e-3, orders 0.92, 1.59, 1.74,
//! approaching 2.

use lopin_core::{post, scene};
use lopin_reference::exact::{l2_error, BarExact};
use lopin_tests::solve;

/// L2 error of the bar refined `r` times in x and in time.
fn bar_error(r: usize) -> f64 {
    let mut spec = scene::load("bar").expect("scene");
    spec.refine(r).expect("refine");
    spec.time.dt /= r as f64;
    spec.time.steps *= r;
    let (solver, sol) = solve(&spec, |s| {
        s.tol = 1e-7;
        s.window = Some(1);
    });
    assert!(sol.converged, "r = {r}");
    let p = solver.problem();
    let exact = BarExact::for_problem(p).expect("the front stays inside the bar");
    let history = post::velocity_history(&solver, &sol);
    l2_error(p, &exact, &mut |s, m| history[m][s].clone())
}

#[test]
fn bar_error_against_dalembert_falls_at_second_order() {
    let errors: Vec<f64> = [1, 2, 4, 8].into_iter().map(bar_error).collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("bar L2 errors {errors:?}, observed orders {orders:.2?}");
    // the order rises towards 2 as the front is resolved, and is above 1.6 on the finest pair
    assert!(
        orders.windows(2).all(|o| o[1] > o[0]),
        "orders {orders:.2?} (errors {errors:?})"
    );
    assert!(orders[2] > 1.6 && orders[2] < 2.2, "orders {orders:.2?}");
    assert!(orders[0] > 0.8, "orders {orders:.2?}");
    // the finest mesh is accurate to better than 1 %
    assert!(errors[3] < 1e-2, "{errors:?}");
}
