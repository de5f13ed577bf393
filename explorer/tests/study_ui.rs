//! The study in the explorer's window, driven with egui_kittest: once the background study has
//! stored values, a friction slider move puts the nearest stored picture on screen in the same
//! frame (marked as a stand-in), then the warm re-solve converges to the new value; a stored
//! value is shown without solving; the pinned configuration's difference field is zero (to f32
//! precision) against itself and, against another value, is drawn on a symmetric range; side by
//! side, the pinned configuration A and the current one B are drawn in two labelled viewports
//! with one camera and the colour range both share, A following the time step even while the
//! study is paused, and turning it off or unpinning gives one view back (with a snapshot); the
//! pin and compare controls stay where they are while the background study works.

use common::{harness, settle};
use egui::Role;
use egui_kittest::kittest::{NodeT, Queryable};
use lopin_core::post::ContactHistory;
use lopin_explorer::fields::StepFields;
use lopin_explorer::mesh_build;
use lopin_explorer::page_report::PageReport;
use lopin_explorer::quantity::Quantity;
use lopin_explorer::ExplorerApp;
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

/// Where the pin and compare controls are, for the frame just drawn.
fn pin_and_compare(h: &H) -> [egui::Rect; 3] {
    let c = &h.state().layout.controls;
    ["pin A", "side by side", "section"].map(|name| {
        c.get(name)
            .unwrap_or_else(|| panic!("no \"{name}\" control drawn"))
    })
}

#[test]
fn the_pin_and_compare_controls_stay_put_while_the_background_study_works() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    let at = pin_and_compare(&h);
    // from its wait through four values at once (the line saying which is the longest) to done
    let (mut idle, mut four) = (false, false);
    let start = Instant::now();
    while !h.state().study.complete() {
        h.step();
        let running = h.state().study.running().len();
        idle |= running == 0;
        four |= running >= 4;
        assert_eq!(
            pin_and_compare(&h),
            at,
            "the pin A, side by side and section controls moved with {running} value(s) solving"
        );
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the background study stored {} values",
            h.state().study.grid_stored()
        );
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(
        idle && four,
        "the study was seen idle ({idle}) and on four values ({four})"
    );
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

/// Min and max of the displayed quantity over one configuration's nodal values, computed here
/// from its fields and contact histories.
fn min_max(app: &ExplorerApp, fields: &StepFields, contact: &[ContactHistory]) -> (f64, f64) {
    let q = app.layout.view.quantity;
    mesh_build::nodal_values(&app.geometry, fields, Some(contact), q)
        .into_iter()
        .flatten()
        .flatten()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// The extents of A's stored picture and of the current fields on screen, computed from them.
fn extents(app: &ExplorerApp) -> ((f64, f64), (f64, f64)) {
    let a = app.study.pinned.expect("A is pinned");
    let p = app
        .study
        .points()
        .iter()
        .find(|p| (p.value - a).abs() < 1e-9)
        .expect("A is stored");
    let a_fields = p.picture.fields(0, false);
    let a_extent = min_max(app, &a_fields, &p.picture.contact());
    let b_fields = app.cache.shown().expect("fields on screen");
    let b_contact = app.cache.contact().expect("contact histories");
    (a_extent, min_max(app, b_fields, b_contact))
}

/// The viewports' names, left to right.
fn viewports(h: &H) -> Vec<(String, egui::Rect)> {
    let mut v: Vec<(String, egui::Rect)> = h
        .query_all_by(|n| n.label().is_some_and(|l| l.starts_with("3D view")))
        .map(|n| (n.accesskit_node().label().unwrap_or_default(), n.rect()))
        .collect();
    v.sort_by(|a, b| a.1.left().total_cmp(&b.1.left()));
    v
}

/// Pins A at the scene's f = 0.3 (study paused: nothing else is stored) and re-solves at f = 0.6.
fn pinned_then_moved() -> H {
    let mut h = harness("two-blocks");
    h.state_mut().study.paused = true;
    settle(&mut h);
    h.get_by_label("pin A").click();
    h.step();
    assert_eq!(h.state().study.pinned, Some(0.3));
    move_friction(&mut h, 0.6);
    settle(&mut h);
    h
}

#[test]
fn side_by_side_shows_a_and_b_labelled_on_one_colour_range_and_one_camera() {
    let mut h = pinned_then_moved();
    assert_eq!(viewports(&h).len(), 1, "{:?}", viewports(&h));
    h.get_by_role_and_label(Role::RadioButton, "side by side")
        .click();
    h.step();
    h.step();
    // two viewports, A on the left, B on the right, equal and apart, each named by its value
    let v = viewports(&h);
    let names: Vec<&str> = v.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["3D view A: f = 0.300", "3D view B: f = 0.600"]);
    let (a_rect, b_rect) = (v[0].1, v[1].1);
    assert_eq!(a_rect.size(), b_rect.size());
    assert!(a_rect.right() < b_rect.left(), "{a_rect:?} {b_rect:?}");
    assert!(a_rect.width() > 300.0, "{a_rect:?}");
    let app = h.state();
    assert_eq!(app.layout.beside_rect(), Some(a_rect));
    assert_eq!(app.layout.view_rect(), Some(b_rect));
    // what the browser test reads and clicks
    let report = PageReport::of(app);
    assert!(report.beside.is_some() && report.beside_drawn, "{report:?}");
    assert_eq!(report.pinned, Some(0.3));
    let radio = report.control("side by side").expect("radio drawn");
    assert!(report.control("pin A").is_some(), "{report:?}");
    assert!(radio[0] < a_rect.left(), "in the left panel: {radio:?}");
    // A is drawn from its stored picture, B from the fields on screen, both on the range
    // spanning the min and max over the two
    let (a_mesh, _) = app.layout.beside().expect("A's picture is drawn");
    let b_mesh = app.layout.mesh();
    let (a, b) = extents(app);
    assert_ne!(a, b, "f = 0.3 and 0.6 differ");
    assert_eq!(a_mesh.extent, a);
    assert_eq!(b_mesh.extent, b);
    let shared = (a.0.min(b.0), a.1.max(b.1));
    assert_eq!(a_mesh.range, shared);
    assert_eq!(b_mesh.range, shared);
    assert!(!a_mesh.difference && !b_mesh.difference);
    assert_eq!(a_mesh.vertices.len(), b_mesh.vertices.len());
    assert_ne!(a_mesh.vertices, b_mesh.vertices);
    // one camera: a drag in A's viewport turns both, and rebuilds nothing
    let (camera, versions) = (
        app.layout.camera,
        (app.layout.mesh_version(), app.layout.beside().map(|b| b.1)),
    );
    let centre = a_rect.center();
    h.drag_at(centre);
    h.step();
    for dx in [20.0, 40.0, 60.0] {
        h.hover_at(centre + egui::vec2(dx, 0.0));
        h.step();
    }
    h.drop_at(centre + egui::vec2(60.0, 0.0));
    h.step();
    let app = h.state();
    assert_ne!(app.layout.camera.yaw, camera.yaw);
    assert_eq!(
        (app.layout.mesh_version(), app.layout.beside().map(|b| b.1)),
        versions
    );
    // off: one view, on its own range again
    h.get_by_role_and_label(Role::RadioButton, "current")
        .click();
    h.step();
    h.step();
    let app = h.state();
    assert_eq!(viewports(&h)[0].0, "3D view");
    assert_eq!(viewports(&h).len(), 1);
    assert!(app.layout.beside().is_none() && app.layout.beside_rect().is_none());
    assert_eq!(app.layout.mesh().range, b);
    assert_eq!(PageReport::of(app).beside, None);
    // on again, then unpinned: one view
    h.get_by_role_and_label(Role::RadioButton, "side by side")
        .click();
    h.step();
    h.step();
    assert_eq!(viewports(&h).len(), 2);
    h.get_by_label("unpin").click();
    h.step();
    h.step();
    let app = h.state();
    assert_eq!(app.study.pinned, None);
    assert_eq!(viewports(&h).len(), 1);
    assert!(app.layout.beside().is_none() && app.layout.beside_rect().is_none());
    assert_eq!(app.layout.mesh().range, b);
}

#[test]
fn side_by_side_a_follows_the_time_step_while_the_study_is_paused() {
    let mut h = pinned_then_moved();
    h.get_by_role_and_label(Role::RadioButton, "side by side")
        .click();
    h.step();
    let before = h.state().layout.beside().expect("A drawn").0.extent;
    h.get_by_role_and_label(Role::Slider, "step")
        .set_value_accesskit(10.0);
    settle(&mut h);
    // A's picture at step 10 is made at once, though the background study is paused
    let start = Instant::now();
    while h.state().layout.beside().is_none()
        || h.state()
            .study
            .points()
            .iter()
            .any(|p| (p.value - 0.3).abs() < 1e-9 && p.picture.step != 10)
    {
        h.step();
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no picture of A at step 10"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    h.step();
    let app = h.state();
    assert_eq!(app.clock.step(), 10);
    assert!(app.study.paused);
    let (a, b) = extents(app);
    let (a_mesh, _) = app.layout.beside().expect("A drawn");
    assert_eq!(a_mesh.extent, a);
    assert_ne!(a, before, "A at step 10, not at the step it was pinned at");
    assert_eq!(a_mesh.range, (a.0.min(b.0), a.1.max(b.1)));
    assert_eq!(app.layout.mesh().range, a_mesh.range);
    // only A was pictured: the paused study solved nothing
    assert_eq!(app.study.points().len(), 2);
}

/// Side by side on the slip of the exploded contact faces, where the friction coefficient
/// shows.
#[test]
fn snapshot_of_the_side_by_side_view() {
    let mut h = pinned_then_moved();
    h.get_by_role_and_label(Role::RadioButton, "side by side")
        .click();
    h.state_mut().layout.view.quantity = Quantity::Slip;
    h.state_mut().layout.view.exploded = true;
    h.step();
    h.step();
    assert!(h.state().layout.beside().is_some());
    h.snapshot("two_blocks_side_by_side");
}
