//! Regression tests of the defects the stress suite (`lopin_judge::stress`, guide "Numerical
//! stability stress suite") found in the engine, one per defect, each named after what broke and
//! small enough to run in a few seconds. Each asserts the fixed default against a bound that the
//! variant the fix replaced (still selectable in `Settings`) breaks, with both measured numbers in
//! its doc; where that is cheap, the test also runs the old variant to show the defect.

use lopin_core::post;
use lopin_core::scene::settings::WindowStart;
use lopin_core::scene::{self, SceneSpec};
use lopin_tests::solve;

fn test_scene(name: &str) -> SceneSpec {
    scene::registry::builtin(name).expect("test scene of the registry")
}

/// Defect: each cold time window started from F = W = 0 (the plain METHOD §7 variant) and paid
/// for it in iterations: 2× in incremental runs. Fix: `Settings::window_start` starts a window
/// from the last converged step held constant (`Hold`; the default now extrapolates from it,
/// `tests/tests/window_start.rs`). `mini-blocks` incremental (window 1, η < 1e-3): 667
/// iterations held, 1361 from zero (measured).
#[test]
fn incremental_cold_window_starts_held_not_zero() {
    let spec = test_scene("mini-blocks");
    let run = |hold: bool| {
        let (_, sol) = solve(&spec, |s| {
            s.window = Some(1);
            s.window_start = if hold {
                WindowStart::Hold
            } else {
                WindowStart::Zero
            };
        });
        assert!(sol.converged, "hold {hold}: eta {}", sol.eta);
        sol.iterations
    };
    let held = run(true);
    let zero = run(false);
    println!("mini-blocks window 1: {held} iterations held, {zero} from zero");
    assert!(held <= 700, "held start: {held} iterations (measured 667)");
    assert!(
        zero as f64 >= 1.8 * held as f64,
        "zero start {zero} vs held {held}: the defect no longer shows"
    );
}

/// Defect: a window's η was normalized by the energy of all steps 1..m1 (METHOD §7), so the
/// criterion loosened as windows went by and late windows stopped early: `mini-impact 10^4
/// steps` (window 100, η < 1e-3) gained 20 % energy. Fix: `Settings::per_step_window_norm`
/// (default on) normalizes by the window's own energy plus the mean energy per step of the
/// earlier windows times its length. Here `mini-impact` over 4000 steps in 200 windows of 20:
/// max E/(E0 + W) = 1.000263 with the per-step norm, 1.215 with the cumulative one (measured; the
/// cumulative variant is not run here, to keep the test short).
#[test]
fn long_impact_energy_does_not_grow_with_cumulative_window_norm() {
    let mut spec = test_scene("mini-impact");
    spec.time.steps = 4000;
    let (solver, sol) = solve(&spec, |s| {
        s.window = Some(20);
        s.max_iter = 3000;
    });
    assert!(sol.converged, "eta {}", sol.eta);
    let ratio = post::energy(&solver, &sol).max_total_over_input();
    println!(
        "mini-impact 4000 steps, window 20: {} iterations, max E/(E0+W) {ratio:.9}",
        sol.iterations
    );
    assert!(
        ratio <= 1.0 + 1e-3,
        "max E/(E0+W) = {ratio} (measured 1.000263)"
    );
}

/// Defect (a limit of the method, reported, not fixed): a clamped body given an initial velocity
/// has a velocity jump at t₀ that excites the Nyquist mode (METHOD §10), and η stalls (3.6e-3
/// after 1000 iterations in the suite's case "bar clamped with v0 = 1 m/s (velocity jump)"). The
/// solve must end at its iteration limit, not converged, never hang or blow up: here 300
/// iterations, η = 8.8e-3, max E/(E0 + W) = 1 + 1.7e-7 (measured; bound 1e-6).
#[test]
fn velocity_jump_at_t0_stalls_but_stays_finite_and_bounded() {
    let mut spec = test_scene("mini-bar");
    spec.bodies[0].velocity = [1.0, 0.0, 0.0];
    spec.boundaries[0].x = None;
    spec.boundaries[0].clamped = true;
    spec.time.steps = 300;
    let (solver, sol) = solve(&spec, |s| {
        s.window = Some(100);
        s.max_iter = 300;
    });
    let e = post::energy(&solver, &sol);
    let ratio = e.max_total_over_input();
    println!(
        "velocity jump: {} iterations, eta {:.3e}, max E/(E0+W) {ratio:.9}",
        sol.iterations, sol.eta
    );
    assert!(!sol.converged && sol.iterations == 300);
    assert!(sol.eta.is_finite() && sol.eta > 1e-3, "eta {}", sol.eta);
    assert!(sol.eta_history.iter().all(|e| e.is_finite()));
    assert!(
        ratio.is_finite() && ratio <= 1.0 + 1e-6,
        "max E/(E0+W) = {ratio}"
    );
}
