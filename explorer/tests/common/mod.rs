//! Helpers shared by the explorer's UI tests: a kittest harness on a scene (wgpu on the
//! software Vulkan driver) and a loop that steps frames until the newest solve converged.

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
#[allow(dead_code)] // used by the recording tests only
pub fn harness_with(options: Options) -> Harness<'static, ExplorerApp> {
    Harness::builder()
        .with_size(egui::vec2(1400.0, 860.0))
        .wgpu()
        .build_eframe(move |cc| ExplorerApp::new(cc, options).expect("the scene loads"))
}

/// Steps frames until the newest solve converged and the displayed step's converged fields are
/// on screen.
pub fn settle(h: &mut Harness<'static, ExplorerApp>) {
    let start = Instant::now();
    loop {
        h.step();
        let app = h.state();
        let ready = app.solve.converged()
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
