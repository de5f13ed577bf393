//! Lopin explorer: an egui/eframe application that shows the substructures of a scene in 3D
//! coloured by von Mises stress, velocity or contact quantities, with a section plane, a time
//! scrubber, probes, and parameter sliders whose every move launches a warm-started LATIN
//! re-solve (METHOD §8) in a background thread (a Web Worker in the browser), streamed live into the view with a live
//! convergence plot of η (METHOD §7); while the user is idle, a background study solves the
//! friction slider's range and keeps every converged configuration, so a slider move shows the
//! nearest stored picture at once, and a pinned value is compared with the current one as a
//! difference field or side by side. Shared by the desktop binary and the web build.

pub mod app;
mod background;
pub mod camera;
pub mod clock;
pub mod colormap;
pub mod field_cache;
pub mod fields;
pub mod geometry;
pub mod layout;
pub mod measure;
pub mod mesh_build;
pub mod page_report;
pub mod panels;
pub mod params;
pub mod picture;
pub mod plots;
pub mod protocol;
pub mod quantity;
pub mod recorder;
pub mod recording;
pub mod remote;
pub mod render;
pub mod result_folder;
pub mod results_panel;
mod schedule;
pub mod section;
mod service;
pub mod solve_view;
pub mod stored_run;
#[cfg(not(target_arch = "wasm32"))]
mod stored_side;
pub mod study;
pub mod study_panel;
pub mod study_view;
pub mod timeline;
pub mod view3d;
pub mod wire;
pub mod worker;

pub use app::{ExplorerApp, Loaded, Options};
pub use recorder::{RecordedSolve, RecorderFactory, SolveRecorder};
pub use remote::Connector;
pub use result_folder::{FolderOpener, OpenedFolder};

/// Opens the explorer in a native window (wgpu renderer) and returns when it is closed.
#[cfg(not(target_arch = "wasm32"))]
pub fn run_native(options: Options) -> anyhow::Result<()> {
    // fail before opening a window if the scene cannot be opened
    let started = lopin_core::counters::Instant::now();
    let loaded = app::load(&options).map_err(|e| anyhow::anyhow!(e))?;
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title(format!("Lopin — {}", options.scene))
            .with_inner_size([1400.0, 860.0]),
        renderer: eframe::Renderer::Wgpu,
        ..Default::default()
    };
    let result = eframe::run_native(
        "Lopin",
        native,
        Box::new(move |cc| {
            let mut app = ExplorerApp::opened(cc, options, loaded)?;
            app.measure_from(started);
            Ok(Box::new(app))
        }),
    );
    result.map_err(|e| anyhow::anyhow!("cannot open the explorer window: {e}"))
}
