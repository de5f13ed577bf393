//! The time bar: play/pause, step buttons, a scrubber over the time steps and the physical
//! time of the displayed step in µs.

use crate::app::ExplorerApp;

/// Bottom panel with the time controls.
pub fn show(app: &mut ExplorerApp, ui: &mut egui::Ui) {
    egui::Panel::bottom("lopin-time").show(ui, |ui| {
        ui.horizontal(|ui| {
            let label = if app.playing { "pause" } else { "play" };
            if ui.button(label).clicked() {
                app.playing = !app.playing;
            }
            if ui.button("<").clicked() && app.step > 0 {
                app.set_step(app.step - 1);
            }
            if ui.button(">").clicked() {
                app.set_step(app.step + 1);
            }
            let mut step = app.step;
            let rail_width = (ui.available_width() - 260.0).max(100.0);
            ui.spacing_mut().slider_width = rail_width;
            let r = ui.add(egui::Slider::new(&mut step, 0..=app.info.steps).text("step"));
            app.controls
                .insert("time", crate::panels::slider_rail(r.rect, rail_width));
            if r.changed() {
                app.set_step(step);
            }
            ui.label(format!("t = {:.3} µs", app.time() * 1e6));
        });
    });
}
