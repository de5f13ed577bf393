//! The page's start function: finds the canvas, starts eframe's web runner with WebGL2 through
//! wgpu, and shows a start failure on the page instead of a blank canvas.

use crate::page::PageApp;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The scene the page opens when its address names none (`?scene=NAME` picks another built-in).
const DEFAULT_SCENE: &str = "two-blocks";

/// Called by index.html once the module is loaded.
#[wasm_bindgen(start)]
pub fn start() {
    // the module also starts in the solver's worker, which has no page to draw
    if web_sys::window().is_none() {
        return;
    }
    wasm_bindgen_futures::spawn_local(async {
        if let Err(e) = run().await {
            crate::page::show_failure(&e);
        }
    });
}

async fn run() -> Result<(), String> {
    let window = web_sys::window().ok_or("no window")?;
    let document = window.document().ok_or("no document")?;
    let canvas = document
        .get_element_by_id("lopin_canvas")
        .ok_or("index.html has no canvas with id lopin_canvas")?
        .dyn_into::<web_sys::HtmlCanvasElement>()
        .map_err(|_| "#lopin_canvas is not a canvas")?;
    let scene = scene_from_address(&window);
    // the solver opens the scene and factorizes while the page starts drawing
    crate::solver_worker::start_early(&scene);
    let mut options = eframe::WebOptions::default();
    // WebGL2 everywhere: WebGPU is not in every browser yet, and the meshes are small
    if let eframe::egui_wgpu::WgpuSetup::CreateNew(create) = &mut options.wgpu_options.wgpu_setup {
        create.instance_descriptor.backends = eframe::wgpu::Backends::GL;
    }
    eframe::WebRunner::new()
        .start(
            canvas,
            options,
            Box::new(move |cc| {
                let app = PageApp::new(cc, &scene)?;
                Ok(Box::new(app))
            }),
        )
        .await
        .map_err(|e| {
            let reason = e.as_string().unwrap_or_else(|| format!("{e:?}"));
            format!("{reason} (the page opens built-in scenes only: ?scene=NAME)")
        })
}

/// `?scene=NAME` in the page address, else [`DEFAULT_SCENE`].
fn scene_from_address(window: &web_sys::Window) -> String {
    let search = window.location().search().unwrap_or_default();
    search
        .trim_start_matches('?')
        .split('&')
        .find_map(|kv| kv.strip_prefix("scene="))
        .filter(|s| !s.is_empty())
        .map_or_else(|| DEFAULT_SCENE.to_string(), str::to_string)
}
