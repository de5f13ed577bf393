//! The explorer's "record to Rerun" toggle with the real recorder of the `lopin` binary: two
//! converged solves (the first, then a friction move) are recorded to a .rrd file, which the
//! `rerun` tool verifies; the recording holds both solves on the `solve` timeline with their
//! parameters, every iteration, and every time step of each solve.

mod readers;

use egui::Role;
use egui_kittest::kittest::Queryable;
use egui_kittest::Harness;
use lopin_explorer::{ExplorerApp, Options};
use readers::{read_rrd, scratch};
use std::time::{Duration, Instant};

fn step_until(
    h: &mut Harness<'static, ExplorerApp>,
    what: &str,
    done: impl Fn(&ExplorerApp) -> bool,
) {
    let start = Instant::now();
    while !done(h.state()) {
        h.step();
        assert!(
            start.elapsed() < Duration::from_secs(180),
            "{what}: status {:?}, error {:?}",
            h.state().solve.status(),
            h.state().solve.error()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn the_toggle_records_converged_solves_to_a_file_the_rerun_tool_reads() {
    let dir = scratch("explorer-record");
    let file = dir.join("session.rrd");
    let factory = lopin_app::record::explorer::factory(Some(file.clone()), None);
    let options = Options {
        reproducible: true,
        recorder: Some(factory),
        ..Options::scene("two-blocks")
    };
    let mut h = Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_eframe(move |cc| ExplorerApp::new(cc, options).expect("the scene loads"));
    step_until(&mut h, "first solve", |a| a.solve.converged());
    h.get_by_label("record to Rerun").click();
    h.step();
    step_until(&mut h, "first recorded", |a| a.recording.solves() == 1);
    let f0 = h.state().solve.params().friction.expect("contact");
    h.get_by_role_and_label(Role::Slider, "friction f")
        .set_value_accesskit(f0 + 0.05);
    h.step();
    step_until(&mut h, "second recorded", |a| a.recording.solves() == 2);
    let iterations: usize = h.state().solve.reports().iter().map(|r| r.iterations).sum();
    assert_eq!(
        h.state().recording.target(),
        Some(file.display().to_string().as_str())
    );
    // off: the file is complete
    h.get_by_label("record to Rerun").click();
    h.step();
    assert!(!h.state().recording.is_on());
    let steps = h.state().info.steps + 1;
    drop(h);

    let e = readers::entities(&read_rrd(&file));
    assert_eq!(e["/scene"].static_rows(), 1);
    for q in [
        "f",
        "iterations",
        "eta",
        "warm",
        "k",
        "mu",
        "tol",
        "gap",
        "v0",
    ] {
        let path = format!("/parameters/{q}");
        if let Some(c) = e.get(&path) {
            assert_eq!(c.rows_on("solve"), 2, "{path}");
        } else {
            assert!(q == "gap" || q == "v0", "missing {path}");
        }
    }
    assert_eq!(e["/parameters/f"].rows_on("solve"), 2);
    assert_eq!(e["/convergence/eta"].rows_on("iteration"), iterations);
    for body in ["A", "B"] {
        let s = &e[&format!("/bodies/{body}/surface")];
        assert_eq!(s.static_rows(), 1);
        assert_eq!(s.rows_on("time"), 2 * steps);
        assert_eq!(s.rows_on("solve"), 2 * steps);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
