//! Helpers shared by the explorer's UI tests: a kittest harness on a scene (wgpu on the
//! software Vulkan driver) and a loop that steps frames until the newest solve converged.
//! Snapshot tests pause the background study, so what the study panel shows does not depend on
//! timing.

use egui_kittest::Harness;
use lopin_explorer::{ExplorerApp, Options};
use std::time::{Duration, Instant};

/// A harness on `scene` with reproducible labels.
pub fn harness(scene: &str) -> Harness<'static, ExplorerApp> {
    harness_with(Options {
        reproducible: true,
        ..Options::scene(scene)
    })
}

/// A harness with these options.
#[allow(dead_code)] // not every test file uses it
pub fn harness_with(options: Options) -> Harness<'static, ExplorerApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_eframe(move |cc| ExplorerApp::new(cc, options).expect("the scene loads"))
}

/// Steps frames until the newest solve converged, its configuration is stored by the study and
/// the displayed step's converged fields are on screen.
pub fn settle(h: &mut Harness<'static, ExplorerApp>) {
    let start = Instant::now();
    loop {
        h.step();
        let app = h.state();
        // the converged value is also stored by the study (the study panel shows it)
        let stored = app.solve.params().friction.is_none_or(|f| {
            app.study
                .points()
                .iter()
                .any(|p| (p.value - f).abs() < 1e-9)
        });
        let ready = app.solve.converged()
            && stored
            && app
                .cache
                .shown()
                .is_some_and(|f| !f.live && f.step == app.clock.step());
        if ready {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(180),
            "the explorer did not settle: {:?}",
            app.solve.status()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    // one more frame draws the rebuilt mesh
    h.step();
    h.step();
}
