//! The state the web page exposes to scripts (`PageReport`, written into `#lopin-status` by the
//! web crate): converged solve, iterations, η, warm flag and latency, and the friction slider's
//! rail, which a click must hit: clicking at 3/4 of the reported rail moves f to about 3/4 of
//! its 0..1 range and launches a warm re-solve (what the browser test does with a real mouse).
//! The same with the solver behind the browser's byte link (`remote::thread_connector`): the
//! page reports its solver in its worker, and slider, section and time work as on a thread.

mod common;

use lopin_explorer::page_report::PageReport;
use lopin_explorer::remote::thread_connector;
use lopin_explorer::Options;

#[test]
fn the_page_report_follows_solves_and_locates_the_friction_slider() {
    follows_solves(common::harness("two-blocks"), "thread");
}

#[test]
fn the_page_report_follows_solves_over_the_worker_link() {
    let options = Options {
        reproducible: true,
        connector: Some(thread_connector()),
        ..Options::scene("two-blocks")
    };
    follows_solves(common::harness_with(options), "worker");
}

fn follows_solves(
    mut h: egui_kittest::Harness<'static, lopin_explorer::ExplorerApp>,
    solver: &str,
) {
    common::settle(&mut h);
    let r = PageReport::of(h.state());
    assert_eq!(r.solver, solver);
    assert!(
        r.solve_s.is_some_and(|s| s > 0.0) && r.engine_s.is_some_and(|s| s > 0.0),
        "{r:?}"
    );
    assert_eq!(r.state, "converged", "{r:?}");
    assert_eq!(r.scene, "two-blocks");
    assert_eq!(r.generation, 1);
    assert!(!r.warm);
    assert!(r.drawn);
    let tol = h.state().solve.params().settings.tol;
    assert!(r.iterations > 1 && r.eta < tol, "{r:?}");
    let f0 = r.friction.expect("two-blocks has contact");
    let latency = r.latency_s.expect("first solve timed");
    assert!(latency > 0.0);
    let rail = r.control("friction").expect("slider drawn");
    let time_rail = r.control("time").expect("time slider drawn");
    let section = r.control("section").expect("section checkbox drawn");
    assert!(r.control("exploded").is_some());
    // the controls object is what the browser test parses
    let parsed: serde_json::Value = serde_json::from_str(&r.controls_json()).expect("json");
    assert_eq!(parsed["friction"][2].as_f64(), Some(f64::from(rail[2])));
    let view = r.view.expect("view drawn");
    // the rail lies in the left panel, the view right of it, both inside the window
    assert!(
        rail[0] >= 0.0 && rail[0] + rail[2] <= view[0],
        "{rail:?} {view:?}"
    );
    assert!(rail[2] > 50.0 && rail[3] > 5.0, "{rail:?}");
    assert!(view[2] > 400.0 && view[3] > 300.0, "{view:?}");
    let attrs = r.attributes();
    let get = |k: &str| {
        attrs
            .iter()
            .find(|(n, _)| *n == k)
            .map(|(_, v)| v.clone())
            .expect("attribute")
    };
    assert_eq!(get("data-state"), "converged");
    assert_eq!(get("data-friction").parse::<f64>().ok(), Some(f0));
    assert_eq!(get("data-iterations"), r.iterations.to_string());
    assert!(r.title().starts_with("Lopin two-blocks: converged f="));

    // click at 3/4 of the rail, as the browser test does
    let at = egui::pos2(rail[0] + 0.75 * rail[2], rail[1] + rail[3] / 2.0);
    click(&mut h, at);
    common::settle(&mut h);
    let r2 = PageReport::of(h.state());
    let f1 = r2.friction.expect("friction");
    assert!(
        (f1 - 0.75).abs() < 0.06,
        "clicked 3/4 of the rail, f = {f1}"
    );
    assert!((f1 - f0).abs() > 0.05, "f moved from {f0} to {f1}");
    assert_eq!(r2.state, "converged", "{r2:?}");
    assert_eq!(r2.generation, 2);
    assert!(r2.warm && r2.eta < tol, "{r2:?}");
    assert!(r2.latency_s.is_some());
    assert_ne!(r2.title(), r.title());

    // the section checkbox and the time rail: the browser test clicks them too
    assert!(!r2.section);
    click(&mut h, rect_centre(section));
    let r3 = PageReport::of(h.state());
    assert!(r3.section, "the section checkbox was hit");
    let steps = h.state().info.steps;
    click(
        &mut h,
        egui::pos2(
            time_rail[0] + 0.2 * time_rail[2],
            time_rail[1] + time_rail[3] / 2.0,
        ),
    );
    common::settle(&mut h);
    let r4 = PageReport::of(h.state());
    let want = 0.2 * steps as f64;
    assert!(
        (r4.step as f64 - want).abs() <= 0.06 * steps as f64,
        "clicked 1/5 of the time rail: step {} of {steps}",
        r4.step
    );
    assert_eq!(r4.shown_step, Some((r4.step, false)));
    assert_eq!(r4.solver, solver);
    let attrs = r4.attributes();
    assert!(attrs.contains(&("data-solver", solver.to_string())));
    assert!(attrs.contains(&("data-step", r4.step.to_string())));
    assert!(attrs.contains(&("data-section", "true".to_string())));
}

fn rect_centre(r: [f32; 4]) -> egui::Pos2 {
    egui::pos2(r[0] + r[2] / 2.0, r[1] + r[3] / 2.0)
}

fn click(h: &mut egui_kittest::Harness<'static, lopin_explorer::ExplorerApp>, at: egui::Pos2) {
    let button = |pressed| egui::Event::PointerButton {
        pos: at,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: Default::default(),
    };
    h.input_mut().events.push(egui::Event::PointerMoved(at));
    h.step();
    h.input_mut().events.push(button(true));
    h.step();
    h.input_mut().events.push(button(false));
    h.step();
}
