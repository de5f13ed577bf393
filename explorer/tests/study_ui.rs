//! The study in the explorer's window, driven with egui_kittest: once the background study has
//! stored values, a friction slider move puts the nearest stored picture on screen in the same
//! frame (marked as a stand-in), then the warm re-solve converges to the new value; a stored
//! value is shown without solving; the pinned configuration's difference field is zero (to f32
//! precision) against itself and, against another value, is drawn on a symmetric range.

use common::{harness, settle};
use egui::Role;
use egui_kittest::kittest::Queryable;
use std::time::{Duration, Instant};

mod common;

type H = egui_kittest::Harness<'static, lopin_explorer::ExplorerApp>;

/// Steps frames until `n` grid values are stored.
fn wait_for_study(h: &mut H, n: usize) {
    let start = Instant::now();
    while h.state().study.grid_stored() < n {
        h.step();
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the background study stored {} values",
            h.state().study.grid_stored()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn move_friction(h: &mut H, f: f64) {
    h.get_by_role_and_label(Role::Slider, "friction f")
        .set_value_accesskit(f);
    h.step();
}

#[test]
fn a_slider_move_shows_the_nearest_stored_picture_at_once_then_converges() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    wait_for_study(&mut h, 5);
    h.state_mut().study.paused = true;
    h.step();
    // between the stored 0.35 and 0.40, nearer 0.35
    move_friction(&mut h, 0.36);
    let app = h.state();
    let stand_in = app.study.stand_in.expect("a stand-in in the move's frame");
    assert!((stand_in.value - 0.35).abs() < 1e-9 && !stand_in.exact);
    let shown = app.cache.shown().expect("a picture");
    assert_eq!(shown.generation, app.solve.generation());
    assert!(shown.live);
    assert!(app.solve.busy(), "and the re-solve runs");
    settle(&mut h);
    let app = h.state();
    let r = app.solve.reports().last().expect("a report");
    assert!(r.converged && r.warm && !r.from_store, "{r:?}");
    assert_eq!(r.start.map(|s| (s * 100.0).round()), Some(35.0));
    assert!(app.study.stand_in.is_none());
    // a stored value: shown without solving
    move_friction(&mut h, 0.25);
    assert!(h.state().study.stand_in.is_some_and(|s| s.exact));
    let shown = h.state().cache.shown().expect("a picture").clone();
    assert!(
        !shown.live,
        "the stored picture of the value itself is converged"
    );
    settle(&mut h);
    let r = h.state().solve.reports().last().expect("a report").clone();
    assert!(r.from_store && r.iterations == 0, "{r:?}");
}

#[test]
fn the_difference_field_is_zero_against_itself_and_symmetric_against_another_value() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    wait_for_study(&mut h, 3);
    h.state_mut().study.paused = true;
    h.get_by_label("pin A").click();
    h.step();
    assert_eq!(h.state().study.pinned, h.state().solve.params().friction);
    h.get_by_label("current − A").click();
    h.step();
    h.step();
    let mesh = h.state().layout.mesh().clone();
    assert!(mesh.difference);
    // the current fields (f64) minus A's stored picture (f32) of the same value: zero to f32
    // precision, against von Mises stresses of about 500 MPa
    let (lo, hi) = mesh.extent;
    assert!(
        lo.abs().max(hi.abs()) < 1e-3,
        "a value minus itself: {:?}",
        mesh.extent
    );
    move_friction(&mut h, 0.25);
    settle(&mut h);
    let mesh = h.state().layout.mesh().clone();
    assert!(mesh.difference);
    let (lo, hi) = mesh.range;
    assert!(
        lo < 0.0 && (lo + hi).abs() < 1e-12 * hi.abs(),
        "{:?}",
        mesh.range
    );
    assert!(mesh.extent.0 < mesh.extent.1, "{:?}", mesh.extent);
}
