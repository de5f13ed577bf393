//! The page side of the web explorer: [`PageApp`] runs the shared [`ExplorerApp`] frame by
//! frame and, whenever the explorer's [`PageReport`] changes, writes it into the page title and
//! the `data-*` attributes of `#lopin-status`; it also stamps the time of the first frame and of
//! the first frame with fields (`data-first-frame-ms`, `data-first-fields-ms`, milliseconds
//! since navigation start) for the page-load benchmark. The page address names the scene on
//! screen (`?scene=NAME`, replaced when the picker opens another), so it is a link to it.

use lopin_explorer::page_report::PageReport;
use lopin_explorer::{ExplorerApp, Options};

/// egui's proportional font and its icons for every text, monospace included: the page draws
/// no code, and a second font would add its size to the download.
fn fonts() -> egui::FontDefinitions {
    use egui::{FontData, FontFamily, FontTweak};
    use std::sync::Arc;
    let mut fonts = egui::FontDefinitions::empty();
    fonts.font_data.insert(
        "Ubuntu-Light".into(),
        Arc::new(FontData::from_static(epaint_default_fonts::UBUNTU_LIGHT)),
    );
    fonts.font_data.insert(
        "egui-icons".into(),
        Arc::new(
            FontData::from_static(epaint_default_fonts::EGUI_ICONS).tweak(FontTweak {
                scale: 0.90,
                ..Default::default()
            }),
        ),
    );
    for family in [FontFamily::Proportional, FontFamily::Monospace] {
        fonts
            .families
            .insert(family, vec!["Ubuntu-Light".into(), "egui-icons".into()]);
    }
    fonts
}

/// The explorer plus what the page was last told.
pub struct PageApp {
    app: ExplorerApp,
    last: Option<PageReport>,
    first_frame: bool,
    first_fields: bool,
    /// The scene the page address names.
    addressed: String,
}

impl PageApp {
    /// The explorer on a built-in scene; the first solve starts at once.
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        scene: &str,
    ) -> Result<Self, Box<dyn std::error::Error + Send + Sync>> {
        // the desktop explorer's look, whatever the browser's colour scheme
        cc.egui_ctx.set_theme(egui::Theme::Dark);
        cc.egui_ctx.set_fonts(fonts());
        let options = Options {
            connector: Some(crate::solver_worker::connector()),
            ..Options::scene(scene)
        };
        let app = ExplorerApp::new(cc, options)?;
        Ok(PageApp {
            app,
            last: None,
            first_frame: false,
            first_fields: false,
            addressed: String::new(),
        })
    }

    fn publish(&mut self) {
        if self.addressed != self.app.info.name {
            self.addressed.clone_from(&self.app.info.name);
            address_scene(&self.addressed);
        }
        let report = PageReport::of(&self.app);
        if !self.first_frame {
            self.first_frame = true;
            set_status_attribute("data-first-frame-ms", &format!("{:.1}", now_ms()));
        }
        if report.drawn && !self.first_fields {
            self.first_fields = true;
            set_status_attribute("data-first-fields-ms", &format!("{:.1}", now_ms()));
        }
        if self.last.as_ref() == Some(&report) {
            return;
        }
        if let Some(document) = web_sys::window().and_then(|w| w.document()) {
            document.set_title(&report.title());
            if let Some(el) = document.get_element_by_id("lopin-status") {
                for (name, value) in report.attributes() {
                    let _ = el.set_attribute(name, &value);
                }
                el.set_text_content(Some(&report.title()));
            }
        }
        self.last = Some(report);
    }
}

impl eframe::App for PageApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.app.frame(ui);
        self.publish();
    }
}

/// Replaces the page address's query by `?scene=NAME` (history unchanged: the back button
/// leaves the page as before).
fn address_scene(name: &str) {
    if let Some(history) = web_sys::window().and_then(|w| w.history().ok()) {
        let _ = history.replace_state_with_url(
            &wasm_bindgen::JsValue::NULL,
            "",
            Some(&format!("?scene={name}")),
        );
    }
}

/// Milliseconds since navigation start.
fn now_ms() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(f64::NAN, |p| p.now())
}

fn set_status_attribute(name: &str, value: &str) {
    if let Some(el) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("lopin-status"))
    {
        let _ = el.set_attribute(name, value);
    }
}

/// Shows why the explorer could not start (the canvas would otherwise stay blank).
pub fn show_failure(message: &str) {
    if let Some(el) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("lopin-status"))
    {
        let _ = el.set_attribute("data-state", "failed");
        let _ = el.set_attribute("data-error", message);
        let _ = el.set_attribute("class", "failed");
        el.set_text_content(Some(&format!("Lopin could not start: {message}")));
    }
}
