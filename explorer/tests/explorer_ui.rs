//! The explorer driven through its widgets with egui_kittest (rendered with wgpu on the software
//! Vulkan driver): the friction slider launches a converged warm re-solve, the time scrubber,
//! field choice and section change what is drawn, a click on the body picks a probe node (its
//! history, acceleration and shock response spectrum, the spectrum's tab drawn), and
//! a scene with non-matching contact faces shows contact fields on both, and snapshot images of
//! the main views are compared with the committed ones
//! (`tests/snapshots/`; regenerate with `UPDATE_SNAPSHOTS=1`).

use common::{harness, settle};
use egui::Role;
use egui_kittest::kittest::Queryable;
use lopin_explorer::quantity::Quantity;
use std::time::{Duration, Instant};

mod common;

#[test]
fn the_friction_slider_launches_a_converged_warm_re_solve() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    let first = h.state().solve.reports().len();
    let f0 = h
        .state()
        .solve
        .params()
        .friction
        .expect("two-blocks has a contact");
    // a slider move of 0.05, as in the latency benchmark
    let f1 = f0 + 0.05;
    h.get_by_role_and_label(Role::Slider, "friction f")
        .set_value_accesskit(f1);
    h.step();
    let moved = h.state().solve.params().friction.expect("friction");
    assert!((moved - f1).abs() < 1e-9, "{moved} vs {f1}");
    assert!(h.state().solve.busy(), "a re-solve starts at once");
    settle(&mut h);
    let app = h.state();
    let r = app.solve.reports().last().expect("a report");
    assert!(app.solve.reports().len() > first);
    assert!(
        r.converged && r.warm && r.eta < app.solve.params().settings.tol,
        "{r:?}"
    );
    assert_eq!(r.params.friction, Some(moved));
    // the convergence plot has a marker at the change and every η of both solves
    assert_eq!(app.solve.markers().len(), 2);
    assert!(
        app.solve.markers()[1].1.starts_with("f = "),
        "{:?}",
        app.solve.markers()
    );
    let total: usize = app.solve.reports().iter().map(|r| r.iterations).sum();
    assert_eq!(app.solve.convergence().len(), total);
}

#[test]
fn scrubbing_time_switching_field_and_moving_the_section_change_the_view() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    // time scrubber
    h.get_by_role_and_label(Role::Slider, "step")
        .set_value_accesskit(10.0);
    settle(&mut h);
    assert_eq!(h.state().clock.step(), 10);
    let vm_mesh = h.state().layout.mesh().clone();
    assert!(
        vm_mesh.extent.1 > 0.0,
        "stress is drawn: {:?}",
        vm_mesh.extent
    );
    // field: velocity magnitude, in m/s; nothing is re-solved
    let solves = h.state().solve.reports().len();
    h.state_mut().layout.view.quantity = Quantity::Velocity;
    h.step();
    let v_mesh = h.state().layout.mesh().clone();
    assert_ne!(v_mesh.extent, vm_mesh.extent);
    assert!(
        v_mesh.extent.1 > 0.1 && v_mesh.extent.1 < 100.0,
        "{:?}",
        v_mesh.extent
    );
    assert_eq!(h.state().solve.reports().len(), solves);
    // section: the cut faces add triangles; moving it changes them
    h.get_by_role_and_label(Role::CheckBox, "section").click();
    h.step();
    assert!(h.state().layout.view.section);
    let cut_mesh = h.state().layout.mesh().clone();
    let cut = cut_mesh.vertices.len();
    assert!(
        cut > v_mesh.vertices.len(),
        "{cut} vs {}",
        v_mesh.vertices.len()
    );
    h.get_by_role_and_label(Role::Slider, "cut position")
        .set_value_accesskit(0.25);
    h.step();
    assert!((h.state().layout.view.section_fraction - 0.25).abs() < 1e-6);
    assert_ne!(h.state().layout.mesh().vertices, cut_mesh.vertices);
    // a camera move alone rebuilds nothing
    let version = h.state().layout.mesh_version();
    h.state_mut().layout.camera.orbit(40.0, 10.0);
    h.step();
    assert_eq!(h.state().layout.mesh_version(), version);
}

#[test]
fn a_click_on_the_body_picks_a_probe_with_a_history() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    // the view's centre looks at the scene's centre, on the body
    let centre = h.get_by_label("3D view").rect().center();
    h.hover_at(centre);
    h.step();
    h.drag_at(centre);
    h.step();
    h.drop_at(centre);
    h.step();
    let start = Instant::now();
    while h.state().cache.probe_history().is_none() {
        h.step();
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no probe history"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    let app = h.state();
    let p = app.cache.probe_history().expect("history");
    assert_eq!(p.speed.len(), app.info.steps + 1);
    assert_eq!(p.speed[0], 0.0, "at rest before the impact");
    assert!(p.speed.iter().copied().fold(0.0, f64::max) > 0.1);
    assert!(p.von_mises.iter().copied().fold(0.0, f64::max) > 0.0);
    // the step-averaged acceleration, one per step, and its spectrum over the default band
    assert_eq!(p.acceleration.len(), app.info.steps);
    assert!(p.acceleration.iter().copied().fold(0.0, f64::max) > 0.0);
    assert!(p.spectrum.len() > 10);
    assert!(p
        .spectrum
        .iter()
        .all(|(f, s)| *f > 0.0 && s.iter().all(|x| x.is_finite())));
    // the spectrum tab draws, and the history tab comes back
    h.get_by_label("SRS, Q = 10").click();
    h.step();
    h.step();
    h.get_by_label("history").click();
    h.step();
}

#[test]
fn snapshots_of_the_main_views() {
    let mut h = harness("two-blocks");
    h.state_mut().study.paused = true;
    settle(&mut h);
    h.snapshot("two_blocks_von_mises");
    h.state_mut().layout.view.quantity = Quantity::Velocity;
    h.state_mut().layout.view.section = true;
    h.state_mut().layout.view.section_axis = 1;
    h.step();
    h.step();
    h.snapshot("two_blocks_velocity_section");
    h.state_mut().layout.view.section = false;
    h.state_mut().layout.view.quantity = Quantity::Pressure;
    h.state_mut().layout.view.exploded = true;
    h.step();
    h.step();
    h.snapshot("two_blocks_contact_pressure_exploded");
}

#[test]
fn the_scene_picker_loads_another_scene() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    h.state_mut().pending_scene = Some("gap-impact".into());
    h.step();
    settle(&mut h);
    let app = h.state();
    assert_eq!(app.info.name, "gap-impact");
    assert_eq!(
        app.solve.reports().len(),
        1,
        "a fresh session: {:?}",
        app.solve.reports()
    );
    assert!(
        app.solve.params().gap.is_some_and(|g| g > 0.0),
        "{:?}",
        app.solve.params()
    );
    assert!(!app.layout.mesh().vertices.is_empty());
}

/// granular-small (the second demo): the exploded view pulls every cell apart, so the grains
/// stand out as blocks whose faces on the grain/matrix contacts carry the pressure colour while
/// every other face is grey; the macro checkbox re-solves warm with the two-scale stage.
#[test]
fn granular_small_exploded_shows_the_grains_and_the_macro_switch_re_solves() {
    let mut h = harness("granular-small");
    h.state_mut().study.paused = true;
    settle(&mut h);
    let contacts = h.state().info.contacts;
    assert!(contacts > 0);
    h.state_mut().layout.view.quantity = Quantity::Pressure;
    h.state_mut().layout.view.exploded = true;
    h.step();
    h.step();
    let app = h.state();
    let coloured: std::collections::BTreeSet<u32> = app
        .layout
        .mesh()
        .vertices
        .iter()
        .filter(|v| {
            (v.color[0] - v.color[1]).abs() > 0.02 || (v.color[1] - v.color[2]).abs() > 0.02
        })
        .map(|v| v.body as u32)
        .collect();
    let all: std::collections::BTreeSet<u32> = app
        .layout
        .mesh()
        .vertices
        .iter()
        .map(|v| v.body as u32)
        .collect();
    println!(
        "granular-small exploded: {} of {} cells show contact pressure ({contacts} contacts)",
        coloured.len(),
        all.len()
    );
    assert_eq!(all.len(), 64);
    assert!(coloured.len() >= 6 && coloured.len() < 64, "{coloured:?}");
    h.snapshot("granular_small_contact_pressure_exploded");
    let before = h.state().solve.reports().len();
    h.get_by_label("macro problem (two-scale)").click();
    h.step();
    assert!(h.state().solve.params().settings.two_scale);
    settle(&mut h);
    let app = h.state();
    let r = app.solve.reports().last().expect("a report");
    assert!(app.solve.reports().len() > before);
    assert!(
        r.converged && r.warm && r.params.settings.two_scale,
        "{r:?}"
    );
    assert!(
        app.solve
            .markers()
            .last()
            .is_some_and(|m| m.1.contains("macro on")),
        "{:?}",
        app.solve.markers()
    );
}

/// A scene on tetrahedra (`mini-impact-tet`) loads, solves and is drawn: its boundary triangles
/// become the mesh, and the section cuts its tetrahedra.
#[test]
fn a_scene_on_tetrahedra_loads_and_draws() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    h.state_mut().pending_scene = Some("mini-impact-tet".into());
    h.step();
    settle(&mut h);
    let app = h.state();
    assert_eq!(app.info.name, "mini-impact-tet");
    assert!(!app.layout.mesh().vertices.is_empty());
    let reports = app.solve.reports();
    assert_eq!(reports.len(), 1, "{reports:?}");
}

/// A scene whose contact faces do not match (`two-blocks-nonmatching`: 10 × 10 on 13 × 13) loads,
/// solves and is drawn, and both faces carry the contact fields: every node of B's top face
/// (side 1) and of A's bottom face (the mortar side) shows an interface node.
#[test]
fn a_non_matching_scene_loads_solves_and_shows_contact_on_both_faces() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    h.state_mut().pending_scene = Some("two-blocks-nonmatching".into());
    h.step();
    settle(&mut h);
    let app = h.state();
    assert_eq!(app.info.name, "two-blocks-nonmatching");
    assert!(app.solve.error().is_none(), "{:?}", app.solve.error());
    let reports = app.solve.reports();
    assert_eq!(reports.len(), 1, "{reports:?}");
    assert!(reports[0].converged, "{reports:?}");
    let on_face = |s: usize, z: f32| {
        let g = &app.geometry.subs[s];
        let face: Vec<usize> = (0..g.nodes.len())
            .filter(|&n| (g.nodes[n].z - z).abs() < 1e-6)
            .collect();
        let shown = face.iter().filter(|&&n| g.contact[n].is_some()).count();
        (face.len(), shown)
    };
    // substructure 0 is A (11 × 11 nodes on its bottom), 1 is B (14 × 14 on its top)
    assert_eq!(on_face(0, 0.02), (121, 121));
    assert_eq!(on_face(1, 0.02), (196, 196));
}

/// The polyhedral granular material (`granular-poly`: ten grains meshed by gmsh, the matrix cut
/// into 8 substructures by METIS) loads, solves and is drawn: every substructure's boundary
/// triangles are in the view, and the exploded view moves them apart.
#[test]
fn the_polyhedral_granular_scene_loads_solves_and_draws() {
    let mut h = harness("two-blocks");
    settle(&mut h);
    h.state_mut().pending_scene = Some("granular-poly".into());
    h.step();
    settle(&mut h);
    let app = h.state();
    assert_eq!(app.info.name, "granular-poly");
    assert!(app.solve.error().is_none(), "{:?}", app.solve.error());
    assert_eq!(app.info.subs, 18);
    let vertices = app.layout.mesh().vertices.len();
    assert!(vertices > 10_000, "{vertices} vertices drawn");
    let reports = app.solve.reports();
    assert_eq!(reports.len(), 1, "{reports:?}");
    assert!(reports[0].converged, "{reports:?}");
}

/// On a scene with zones, the "f moves" buttons point the friction slider at one zone: its
/// label names the zone, a move re-solves warm with that zone's friction alone, and the
/// convergence plot's marker names it.
#[test]
fn the_friction_slider_can_move_one_zone() {
    let path = format!(
        "{}/../assets/scenes/test/mini-stack-zones.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut h = harness(&path);
    settle(&mut h);
    h.get_by_label("zone upper").click();
    h.step();
    h.step();
    assert_eq!(h.state().solve.params().friction_zone, Some(0));
    h.get_by_role_and_label(Role::Slider, "friction f@upper")
        .set_value_accesskit(0.1);
    h.step();
    settle(&mut h);
    let app = h.state();
    let r = app.solve.reports().last().expect("a report");
    assert!(r.converged && r.warm, "{r:?}");
    assert_eq!(
        (r.params.friction_zone, r.params.friction),
        (Some(0), Some(0.1))
    );
    let marker = &app.solve.markers().last().expect("a marker").1;
    assert!(marker.starts_with("f@upper = 0.1"), "{marker}");
}
