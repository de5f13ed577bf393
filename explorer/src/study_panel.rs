//! The study panel (collapsible, in the left panel): the chosen quantity of interest against the
//! friction coefficient, filling as configurations converge, with the current value and the
//! pinned one marked; the background study's progress (values stored out of the grid, what it
//! solves now, the memory of the stored configurations); the "pause background study" toggle;
//! and the comparison with a pinned configuration "A" (pin, unpin; the current configuration
//! alone, the difference field, or A and the current one side by side).

use crate::layout::ControlRects;
use crate::study_view::{Compare, StudyView};
use egui::{Color32, RichText};
use egui_plot::{Line, Plot, PlotPoints, Points, VLine};
use lopin_core::study::Quantities;

/// Mebibytes, for the memory line.
fn mib(bytes: usize) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

/// The study section; `current` is the friction value the controls show and `label` what the
/// slider moves (`f`, or `f@ZONE`). The "pin A" button and the "side by side" choice go into
/// `controls`.
pub fn show(
    ui: &mut egui::Ui,
    study: &mut StudyView,
    current: Option<f64>,
    label: &str,
    controls: &mut ControlRects,
) {
    egui::CollapsingHeader::new("Study: friction (background)")
        .default_open(true)
        .show(ui, |ui| {
            if study.grid().is_empty() || current.is_none() {
                ui.label("No contact interface: nothing to study.");
                return;
            }
            body(ui, study, current.unwrap_or(0.0), label, controls);
        });
}

/// A line of text that never wraps (cut short, whole on hover): the lines above the pin and
/// compare controls change as the background study works, and a line that wrapped or unwrapped
/// would move those controls under a pointer on its way to them.
fn one_line(ui: &mut egui::Ui, text: RichText) -> egui::Response {
    ui.add(egui::Label::new(text).truncate())
}

fn body(
    ui: &mut egui::Ui,
    study: &mut StudyView,
    current: f64,
    label: &str,
    controls: &mut ControlRects,
) {
    let grid = study.grid();
    let (lo, hi) = (grid[0], grid[grid.len() - 1]);
    let step = if grid.len() > 1 {
        grid[1] - grid[0]
    } else {
        0.0
    };
    one_line(
        ui,
        RichText::new(format!(
            "stored {} / {} ({label} {lo:.1}–{hi:.1}, step {step:.2})",
            study.grid_stored(),
            grid.len()
        )),
    );
    let (states, pictures) = study.memory();
    one_line(
        ui,
        RichText::new(format!(
            "{} kept: {:.1} MiB ({:.1} states, {:.1} pictures)",
            study.stored(),
            mib(states + pictures),
            mib(states),
            mib(pictures)
        )),
    )
    .on_hover_text(
        "Each converged configuration keeps its interface state s and solution ŝ in f32 (a warm \
         start and every time step) and a picture (fields at the displayed step, contact \
         histories, f32) shown at once when the slider lands near it.",
    );
    let activity = match (study.paused, study.running()) {
        (true, _) => "paused".to_string(),
        (false, []) if study.complete() => "every value stored".to_string(),
        (false, []) => "waits for 1 s without changes".to_string(),
        (false, values) => {
            let values: Vec<String> = values.iter().map(|v| format!("{v:.2}")).collect();
            format!("solving {label} = {} in the background", values.join(", "))
        }
    };
    one_line(ui, RichText::new(activity).weak());
    ui.checkbox(&mut study.paused, "pause background study");
    let names = Quantities::NAMES;
    let q = study.quantity.min(names.len() - 1);
    egui::ComboBox::from_label("quantity")
        .selected_text(format!("{} ({})", names[q].0, names[q].1))
        .show_ui(ui, |ui| {
            for (i, (name, unit)) in names.iter().enumerate() {
                ui.selectable_value(&mut study.quantity, i, format!("{name} ({unit})"));
            }
        });
    let curve = study.curve(study.quantity);
    let pinned = study.pinned;
    Plot::new("study")
        .show_background(false)
        .height(130.0)
        .x_axis_label(label)
        .include_x(lo)
        .include_x(hi)
        .allow_scroll(false)
        .allow_drag(false)
        .show(ui, |plot| {
            let points: PlotPoints = curve.iter().copied().collect();
            plot.line(Line::new(names[q].0, points));
            let dots: PlotPoints = curve.iter().copied().collect();
            plot.points(Points::new("stored", dots).radius(2.5));
            plot.vline(VLine::new("current", current).color(Color32::from_rgb(230, 150, 40)));
            if let Some(a) = pinned {
                plot.vline(VLine::new("A", a).color(Color32::from_rgb(90, 170, 240)));
            }
        });
    ui.horizontal(|ui| {
        let pin = ui
            .button("pin A")
            .on_hover_text("Pin the current friction value as A, to compare with");
        controls.place("pin A", pin.rect);
        if pin.clicked() {
            study.pinned = Some(current);
        }
        match study.pinned {
            Some(a) => {
                ui.label(format!("A: {label} = {a:.3}"));
                if ui.small_button("unpin").clicked() {
                    study.unpin();
                }
            }
            None => {
                ui.weak("nothing pinned");
            }
        };
    });
    ui.add_enabled_ui(study.pinned.is_some(), |ui| {
        ui.horizontal_wrapped(|ui| {
            ui.radio_value(&mut study.compare, Compare::Off, "current");
            ui.radio_value(&mut study.compare, Compare::Difference, "current − A");
            let beside = ui
                .radio_value(&mut study.compare, Compare::SideBySide, "side by side")
                .on_hover_text(
                    "A and the current value in two views with the same camera, field and \
                     colour range",
                );
            controls.place("side by side", beside.rect);
        });
    });
}
