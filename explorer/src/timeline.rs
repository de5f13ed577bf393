//! The time bar: play/pause, step buttons, a scrubber over the time steps and the physical
//! time of the displayed step in µs.

use crate::clock::Clock;
use crate::layout::ControlRects;

/// Bottom panel with the time controls; the scrubber's rail goes into `controls`.
pub fn show(ui: &mut egui::Ui, clock: &mut Clock, controls: &mut ControlRects) {
    egui::Panel::bottom("lopin-time")
        .frame(crate::panels::panel_frame(ui))
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                let label = if clock.playing() { "pause" } else { "play" };
                if ui.button(label).clicked() {
                    clock.toggle_play();
                }
                if ui.button("<").clicked() && clock.step() > 0 {
                    clock.set_step(clock.step() - 1);
                }
                if ui.button(">").clicked() {
                    clock.set_step(clock.step() + 1);
                }
                let mut step = clock.step();
                let rail_width = (ui.available_width() - 260.0).max(100.0);
                ui.spacing_mut().slider_width = rail_width;
                let r = ui.add(egui::Slider::new(&mut step, 0..=clock.steps()).text("step"));
                controls.place("time", crate::panels::slider_rail(r.rect, rail_width));
                if r.changed() {
                    clock.set_step(step);
                }
                ui.label(format!("t = {:.3} µs", clock.time() * 1e6));
            });
        });
}
