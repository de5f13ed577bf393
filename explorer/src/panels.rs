//! The explorer's top bar (scene picker, solver status) and left panel: the parameters that
//! launch a warm re-solve (friction, gap, impact velocity, k, μ, tolerance), the view options
//! (quantity, colour range, deformation, exploded view, section) and the scene's sizes and
//! per-stage timings. Each section borrows only the states it shows or edits.

use crate::app::SceneInfo;
use crate::clock::Clock;
use crate::geometry::SceneGeometry;
use crate::layout::{ControlRects, Layout};
use crate::params::{FrictionTargets, Params};
use crate::quantity::Quantity;
use crate::recording::Recording;
use crate::solve_view::{SolveStatus, SolveView};
use egui::{Color32, RichText};
use lopin_core::interfaces::search_direction::Directions;

/// Top bar: title, scene picker, status. Returns the scene picked, if another one was.
/// What the top bar asks to open.
#[derive(Debug, Clone, PartialEq)]
pub enum Picked {
    /// A scene from the picker.
    Scene(String),
    /// A result folder typed in the "open" field.
    Folder(std::path::PathBuf),
}

pub fn top_bar(
    ui: &mut egui::Ui,
    info: &SceneInfo,
    solve: &SolveView,
    reproducible: bool,
    mut folder: Option<&mut String>,
) -> Option<Picked> {
    let mut picked = None;
    egui::Panel::top("lopin-top")
        .frame(panel_frame(ui))
        .show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.heading("Lopin");
                ui.separator();
                let mut chosen = None;
                egui::ComboBox::from_label("scene")
                    .selected_text(info.name.clone())
                    .show_ui(ui, |ui| {
                        // scenes of a million dofs are for the command line (`lopin run`), not a
                        // live view; the web build meshes nothing with gmsh
                        // a build that reads no shock loads cannot parse a scene with them
                        let scenes = lopin_core::scene::registry::SCENES.into_iter().filter(|n| {
                            !lopin_core::scene::registry::is_large(n)
                                && (cfg!(feature = "meshes")
                                    || !lopin_core::scene::registry::needs_gmsh(n))
                                && lopin_core::scene::registry::parse(n).is_some_and(|r| r.is_ok())
                        });
                        for name in scenes {
                            if ui.selectable_label(info.name == name, name).clicked() {
                                chosen = Some(name.to_string());
                            }
                        }
                    });
                picked = chosen.filter(|n| *n != info.name).map(Picked::Scene);
                if let Some(text) = folder.take() {
                    let field = ui.add(
                        egui::TextEdit::singleline(text)
                            .hint_text("result folder")
                            .desired_width(180.0),
                    );
                    let enter = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if (ui.button("open").clicked() || enter) && !text.trim().is_empty() {
                        picked = Some(Picked::Folder(text.trim().into()));
                    }
                }
                ui.label(RichText::new(&info.description).weak());
                ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                    status_label(ui, solve, reproducible);
                });
            });
            if let Some(e) = solve.error() {
                ui.colored_label(Color32::from_rgb(220, 80, 60), format!("error: {e}"));
            }
        });
    picked
}

fn status_label(ui: &mut egui::Ui, solve: &SolveView, reproducible: bool) {
    let text = match solve.status() {
        SolveStatus::Starting => "factorizing…".to_string(),
        SolveStatus::Running {
            iterations, eta, ..
        } => format!("solving: iteration {iterations}, η = {eta:.2e}"),
        SolveStatus::Done(r) if r.from_store => match r.params.friction {
            Some(f) => format!("stored: f = {f:.3}, shown without solving"),
            None => "stored: shown without solving".to_string(),
        },
        SolveStatus::Done(r) if r.converged => {
            let mut t = format!(
                "converged: {} iterations{}, η = {:.2e}",
                r.iterations,
                if r.warm { " (warm)" } else { "" },
                r.eta
            );
            if !reproducible {
                if let Some(l) = solve.last_latency() {
                    t += &format!(", {:.0} ms", 1e3 * l);
                }
            }
            t
        }
        SolveStatus::Done(r) => format!(
            "not converged after {} iterations (η = {:.2e})",
            r.iterations, r.eta
        ),
        SolveStatus::Failed(e) => format!("failed: {e}"),
    };
    ui.label(text);
}

/// Records in the context's memory that the painter clears the window to the panels' colour:
/// called from [`crate::app::ExplorerApp`]'s `clear_color`, which eframe calls on the desktop
/// and in the browser (a test harness clears to its own colour and never calls it).
pub fn mark_cleared_to_panel_fill(ctx: &egui::Context) {
    ctx.data_mut(|d| d.insert_temp(cleared_id(), true));
}

fn cleared_id() -> egui::Id {
    egui::Id::unique("lopin-cleared-to-panel-fill")
}

/// The frame of the side, top and bottom panels: egui's, without its fill where the window is
/// cleared to the panels' colour ([`mark_cleared_to_panel_fill`]), so they look the same. A
/// fill is shaded pixel by pixel, and on a software rasterizer (lavapipe) the panels' fills
/// were over half the pixels egui shaded in an idle frame.
pub fn panel_frame(ui: &egui::Ui) -> egui::Frame {
    let frame = egui::Frame::side_top_panel(ui.style());
    let cleared = ui
        .ctx()
        .data(|d| d.get_temp::<bool>(cleared_id()))
        .unwrap_or(false);
    if cleared {
        frame.fill(egui::Color32::TRANSPARENT)
    } else {
        frame
    }
}

/// Left panel, scrolling: `sections` lays out its content (parameters, view options,
/// recording, sizes and timings, separated).
pub fn left(ui: &mut egui::Ui, sections: impl FnOnce(&mut egui::Ui)) {
    egui::Panel::left("lopin-controls")
        .frame(panel_frame(ui))
        .resizable(false)
        .exact_size(280.0)
        .show(ui, |ui| {
            ui.spacing_mut().slider_width = 110.0;
            egui::ScrollArea::vertical().show(ui, sections);
        });
}

/// The parameters that launch a warm re-solve (the controls' values in `p`); the friction
/// slider's rail goes into `controls`. On a scene with zones, the friction slider moves every
/// contact or the zone picked beside it (`targets` keeps each one's value).
pub fn parameters(
    ui: &mut egui::Ui,
    p: &mut Params,
    targets: &mut FrictionTargets,
    controls: &mut ControlRects,
) {
    ui.strong("Parameters (each change re-solves warm)");
    if p.friction.is_some() && targets.zones().next().is_some() {
        let mut to = p.friction_zone;
        let name = |z: Option<usize>| match z.and_then(|z| p.zones.get(z)) {
            Some(n) => format!("zone {n}"),
            None => "every contact".to_string(),
        };
        ui.horizontal_wrapped(|ui| {
            ui.label("f moves:").on_hover_text(
                "The contact interfaces the friction slider moves: every one, or one zone of \
                 the scene ([[zone]]); the background study then covers that zone's values.",
            );
            ui.selectable_value(&mut to, None, name(None));
            for z in targets.zones() {
                ui.selectable_value(&mut to, Some(z), name(Some(z)));
            }
        });
        targets.switch(p, to);
    }
    let label = format!("friction {}", p.friction_label());
    if let Some(f) = &mut p.friction {
        let rail_width = ui.spacing().slider_width;
        let r = ui.add(
            egui::Slider::new(f, 0.0..=1.0)
                .clamping(egui::SliderClamping::Never)
                .text(label),
        );
        controls.place("friction", slider_rail(r.rect, rail_width));
        if r.changed() {
            targets.moved(p);
        }
    }
    if let Some(g) = &mut p.gap {
        // negative: an interference, closed by the preload's static phase
        if let Some(v) = scaled_slider(ui, *g, 1e6, -50.0..=500.0, "gap g0 (µm)") {
            *g = v;
        }
    }
    if let Some(v) = &mut p.velocity {
        ui.add(
            egui::Slider::new(v, 0.0..=50.0)
                .clamping(egui::SliderClamping::Never)
                .text("impact v0 (m/s)"),
        );
    }
    if let Some(t) = &mut p.traction {
        if let Some(v) = scaled_slider(ui, *t, 1e-6, 0.0..=1000.0, "traction t0 (MPa)") {
            *t = v;
        }
    }
    if let Some(t) = &mut p.preload {
        if let Some(v) = scaled_slider(ui, *t, 1e-6, 0.0..=1000.0, "preload (MPa)") {
            *t = v;
        }
    }
    if let Some(a) = &mut p.acceleration {
        let g = 1.0 / STANDARD_GRAVITY;
        if let Some(v) = scaled_slider(ui, *a, g, 0.0..=1000.0, "base acceleration a0 (g)") {
            *a = v;
        }
    }
    if let Some(d) = &mut p.duration {
        let range = 0.1..=1000.0;
        if let Some(v) =
            scaled_slider(ui, *d, 1e6, range, "pulse duration (µs)").filter(|&v| v > 0.0)
        {
            *d = v;
        }
    }
    ui.add(
        egui::Slider::new(&mut p.settings.k, 1e5..=1e9)
            .logarithmic(true)
            .clamping(egui::SliderClamping::Never)
            .text("k (Pa s/m)"),
    );
    ui.add(egui::Slider::new(&mut p.settings.mu, 0.1..=1.0).text("relaxation μ"));
    ui.checkbox(&mut p.settings.two_scale, "macro problem (two-scale)")
        .on_hover_text(
            "Two-scale linear stage (METHOD §9): 9 macro unknowns per internal interface, one \
             global macro solve per time step. Same converged solution; fewer iterations when \
             many substructures are crossed.",
        );
    ui.add(egui::Slider::new(&mut p.settings.rho_inf, 0.0..=1.0).text("ρ∞ damping"))
        .on_hover_text(
            "Spectral radius at infinite frequency of the time scheme (Bossak–Newmark): 1 is the \
             undamped trapezoidal rule; smaller damps the highest mesh frequencies, which stall \
             the iteration (0.5: about 7× fewer iterations to η < 1e-6 on two-blocks). Changes \
             the discrete problem slightly (guide: Fewer iterations).",
        );
    let mut wave = p.settings.directions == Directions::Wave;
    if ui
        .checkbox(&mut wave, "wave-matched search direction")
        .on_hover_text(
            "Search direction ρc_p along each interface normal and ρc_s across it instead of \
             the scalar k: fewer iterations per step in incremental granular runs, more at \
             η < 1e-3 on two-blocks (guide: Fewer iterations). Same converged solution.",
        )
        .changed()
    {
        p.settings.directions = if wave {
            Directions::Wave
        } else {
            Directions::Isotropic
        };
    }
    let mut exponent = p.settings.tol.log10().round() as i32;
    if ui
        .add(egui::Slider::new(&mut exponent, -8..=-1).text("tolerance 10^"))
        .changed()
    {
        p.settings.tol = 10f64.powi(exponent);
    }
}

/// In the browser the "record to Rerun" toggle is hidden, with the reason: a page has no
/// filesystem and cannot reach a viewer.
#[cfg(target_arch = "wasm32")]
pub fn recording(ui: &mut egui::Ui, _recording: &mut Recording, _solve: &mut SolveView) {
    ui.strong("Recording");
    ui.weak("Rerun recording: desktop only (hover for why)")
        .on_hover_text(
        "Recording writes a Rerun file or streams to a Rerun viewer, which a web page cannot do: \
         use the desktop explorer (`lopin view --record`) or `lopin run SCENE --rerun FILE.rrd`.",
    );
}

/// The "record to Rerun" toggle, its target and how many solves went there; a failure to
/// switch it on is shown as `solve`'s error.
#[cfg(not(target_arch = "wasm32"))]
pub fn recording(ui: &mut egui::Ui, recording: &mut Recording, solve: &mut SolveView) {
    ui.strong("Recording");
    if !recording.available() {
        ui.add_enabled(
            false,
            egui::Checkbox::new(&mut false, "record to Rerun"),
        )
        .on_disabled_hover_text(
            "Recording writes a Rerun file or streams to a Rerun viewer: it needs the desktop build with the `rerun` feature.",
        );
        return;
    }
    let mut on = recording.is_on();
    if ui
        .checkbox(&mut on, "record to Rerun")
        .on_hover_text("Record every converged solve (fields per time step, η per iteration, parameters) to Rerun")
        .changed()
    {
        if let Err(e) = recording.set(on, solve.worker()) {
            solve.set_error(e);
        }
    }
    if let Some(t) = recording.target() {
        ui.label(format!("{} solve(s) to {t}", recording.solves()));
    }
}

/// The view options: quantity, colour range, deformation, exploded view, section, camera reset;
/// interface quantities are offered when the scene (`info`) has contacts.
pub fn view_options(ui: &mut egui::Ui, layout: &mut Layout, info: &SceneInfo) {
    ui.strong("View");
    let extent = layout.mesh().extent;
    let (v, controls) = (&mut layout.view, &mut layout.controls);
    let before = v.quantity;
    egui::ComboBox::from_label("field")
        .selected_text(v.quantity.label())
        .show_ui(ui, |ui| {
            for q in Quantity::ALL {
                let enabled = !q.on_interfaces() || info.contacts > 0;
                ui.add_enabled_ui(enabled, |ui| {
                    ui.selectable_value(&mut v.quantity, q, q.label());
                });
            }
        });
    if v.quantity != before {
        // interface fields sit between bodies: pull them apart so they can be seen
        if v.quantity.on_interfaces() {
            v.exploded = true;
        }
        v.fixed_range = false;
    }
    ui.horizontal(|ui| {
        ui.radio_value(&mut v.fixed_range, false, "auto range");
        if ui.radio_value(&mut v.fixed_range, true, "fixed").clicked() {
            let (lo, hi) = extent;
            v.range_min = lo;
            v.range_max = hi;
        }
    });
    if v.fixed_range {
        ui.horizontal(|ui| {
            let min = ui.label("min").id;
            ui.add(egui::DragValue::new(&mut v.range_min).speed(0.01))
                .labelled_by(min);
            let max = ui.label("max").id;
            ui.add(egui::DragValue::new(&mut v.range_max).speed(0.01))
                .labelled_by(max);
        });
        if v.range_max <= v.range_min {
            v.range_max = v.range_min + 1e-6;
        }
    }
    ui.horizontal(|ui| {
        let label = ui.checkbox(&mut v.deformed, "deformed ×").id;
        ui.add_enabled(
            v.deformed,
            egui::DragValue::new(&mut v.deform_scale)
                .range(1.0..=1e6)
                .speed(10.0),
        )
        .labelled_by(label);
    });
    ui.horizontal(|ui| {
        let r = ui.checkbox(&mut v.exploded, "exploded");
        controls.place("exploded", r.rect);
        ui.add_enabled(
            v.exploded,
            egui::Slider::new(&mut v.explode_amount, 0.05..=1.0)
                .show_value(false)
                .text("amount"),
        );
    });
    let r = ui.checkbox(&mut v.section, "section");
    controls.place("section", r.rect);
    ui.add_enabled_ui(v.section, |ui| {
        ui.horizontal(|ui| {
            for (a, name) in ["x", "y", "z"].iter().enumerate() {
                ui.radio_value(&mut v.section_axis, a, *name);
            }
        });
        ui.add(egui::Slider::new(&mut v.section_fraction, 0.0..=1.0).text("cut position"));
    });
    if ui.button("reset view").clicked() {
        layout.reset_camera();
    }
}

/// The scene's sizes and the session's per-stage timings (hidden when `reproducible`), with the
/// frame rate.
pub fn sizes(
    ui: &mut egui::Ui,
    i: &SceneInfo,
    geometry: &SceneGeometry,
    solve: &SolveView,
    clock: &Clock,
    reproducible: bool,
) {
    ui.strong("Scene");
    egui::Grid::new("sizes").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: String| {
            ui.label(k);
            ui.label(v);
            ui.end_row();
        };
        row("substructures", i.subs.to_string());
        row(
            "interfaces",
            format!("{} ({} contact)", i.interfaces, i.contacts),
        );
        row("dofs", i.dofs.to_string());
        row("time steps", format!("{} × {:.3} µs", i.steps, i.dt * 1e6));
        row(
            "triangles",
            format!(
                "{} ({} assembled)",
                geometry.triangle_count(),
                geometry.assembled_triangle_count()
            ),
        );
    });
    ui.strong("Timings (s, whole session)");
    let Some(r) = solve.reports().last() else {
        ui.label("—");
        return;
    };
    if reproducible {
        ui.label("(hidden for reproducible screenshots)");
        return;
    }
    egui::Grid::new("timings").num_columns(2).show(ui, |ui| {
        let mut row = |k: &str, v: f64| {
            ui.label(k);
            ui.label(format!("{v:.3}"));
            ui.end_row();
        };
        row("setup (factorizations)", r.stages.setup);
        row("local stages", r.stages.local);
        row("linear stages", r.stages.linear);
        row("post-processing", r.stages.post);
        row("last solve (wall)", r.solve_s);
    });
    if let Some(fps) = clock.fps() {
        ui.label(format!("{fps:.0} frames/s"));
    }
}

/// The rail of a slider whose response covers `rect` (rail then value box and label).
pub(crate) fn slider_rail(rect: egui::Rect, rail_width: f32) -> egui::Rect {
    egui::Rect::from_min_size(rect.min, egui::vec2(rail_width, rect.height()))
}

/// A slider showing `value` × `scale` (a unit of its own: µm, MPa, µs; logarithmic when its
/// range starts above 0), unclamped; the new value in SI units when the user really moved it
/// Standard gravity (m/s²): the base acceleration slider reads in g.
const STANDARD_GRAVITY: f64 = 9.80665;

/// (not the unit's round trip).
fn scaled_slider(
    ui: &mut egui::Ui,
    value: f64,
    scale: f64,
    range: std::ops::RangeInclusive<f64>,
    text: &str,
) -> Option<f64> {
    let mut shown = value * scale;
    let logarithmic = *range.start() > 0.0;
    let moved = ui
        .add(
            egui::Slider::new(&mut shown, range)
                .logarithmic(logarithmic)
                .clamping(egui::SliderClamping::Never)
                .text(text),
        )
        .changed();
    (moved && (shown - value * scale).abs() > 1e-9 * (1.0 + shown.abs())).then(|| shown / scale)
}
