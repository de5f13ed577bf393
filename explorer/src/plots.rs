//! The right panel's plots (egui_plot): the live convergence of the LATIN error indicator η
//! against cumulative iterations on a log scale with a marker at each parameter change (the
//! seed paper's Figure 6, drawn live), the probe's velocity, von Mises and acceleration history
//! or the shock response spectrum of its acceleration, and the contact interfaces' total normal
//! force and maximum slip over time.

use crate::app::SceneInfo;
use crate::clock::Clock;
use crate::field_cache::FieldCache;
use crate::fields;
use crate::solve_view::SolveView;
use egui_plot::{Legend, Line, Plot, PlotPoints, VLine};

/// Right panel with the three plots.
pub fn show(
    ui: &mut egui::Ui,
    solve: &SolveView,
    cache: &FieldCache,
    clock: &Clock,
    info: &SceneInfo,
) {
    egui::Panel::right("lopin-plots")
        .frame(crate::panels::panel_frame(ui))
        .resizable(false)
        .exact_size(340.0)
        .show(ui, |ui| {
            // the plots draw no background of their own either: on a software rasterizer
            // their fills cost a tenth of an idle frame
            let h = ((ui.available_height() - 90.0) / 3.0).max(90.0);
            convergence(ui, solve, h);
            ui.separator();
            probe(ui, cache, clock, info, h);
            ui.separator();
            interface(ui, cache, clock, info, h);
        });
}

fn convergence(ui: &mut egui::Ui, solve: &SolveView, height: f32) {
    ui.strong("Convergence: log10 η against cumulative iterations");
    let points: PlotPoints = solve
        .convergence()
        .iter()
        .filter(|p| p[1] > 0.0 && p[1].is_finite())
        .map(|p| [p[0], p[1].log10()])
        .collect();
    let tol = solve.params().settings.tol.log10();
    Plot::new("convergence")
        .show_background(false)
        .height(height)
        .legend(Legend::default())
        .x_axis_label("iterations")
        .y_axis_label("log10 η")
        .show(ui, |plot| {
            plot.line(Line::new("η", points));
            plot.hline(
                egui_plot::HLine::new("tolerance", tol).style(egui_plot::LineStyle::dashed_loose()),
            );
            for (x, what) in solve.markers().iter().skip(1) {
                plot.vline(
                    VLine::new(what.clone(), *x).color(egui::Color32::from_rgb(230, 150, 40)),
                );
            }
        });
}

fn probe(ui: &mut egui::Ui, cache: &FieldCache, clock: &Clock, info: &SceneInfo, height: f32) {
    let Some((sub, node)) = cache.probe() else {
        ui.strong("Probe");
        ui.label("Click a point of the 3D view to plot its velocity and stress over time.");
        return;
    };
    let id = egui::Id::unique("lopin-probe-spectrum");
    let mut spectrum = ui.data(|d| d.get_temp::<bool>(id).unwrap_or(false));
    ui.horizontal(|ui| {
        ui.strong(format!("Probe: substructure {sub}, node {node}"));
        ui.selectable_value(&mut spectrum, false, "history");
        ui.selectable_value(&mut spectrum, true, format!("SRS, Q = {}", fields::PROBE_Q))
            .on_hover_text(
                "shock response spectrum of the probe's acceleration: the peak absolute \
                 acceleration (maximax) of an oscillator of each natural frequency on it",
            );
    });
    ui.data_mut(|d| d.insert_temp(id, spectrum));
    if spectrum {
        probe_spectrum(ui, cache, height);
        return;
    }
    let dt_us = info.dt * 1e6;
    let (speed, vm, accel) = match cache.probe_history() {
        Some(h) => (
            over_time(h.speed.iter().copied(), dt_us),
            over_time(h.von_mises.iter().map(|v| v * 1e-6), dt_us),
            // step-averaged: at the mid-steps
            h.acceleration
                .iter()
                .enumerate()
                .map(|(m, a)| [(m as f64 + 0.5) * dt_us, a * 1e-6])
                .collect::<PlotPoints>(),
        ),
        None => Default::default(),
    };
    Plot::new("probe")
        .show_background(false)
        .height(height)
        .legend(Legend::default())
        .x_axis_label("t (µs)")
        .show(ui, |plot| {
            plot.line(Line::new("|v| (m/s)", speed));
            plot.line(Line::new("von Mises (MPa)", vm));
            plot.line(Line::new("|a| (10⁶ m/s²)", accel));
            plot.vline(VLine::new("now", clock.time() * 1e6));
        });
}

/// The probe's shock response spectrum, log10 of the maximax (m/s²) against log10 of the
/// natural frequency (Hz), one line per component that moves.
fn probe_spectrum(ui: &mut egui::Ui, cache: &FieldCache, height: f32) {
    let lines: Vec<(&str, PlotPoints)> = match cache.probe_history() {
        Some(h) => {
            let largest = h
                .spectrum
                .iter()
                .flat_map(|(_, s)| s.iter().copied())
                .fold(0.0f64, f64::max);
            ["x", "y", "z"]
                .iter()
                .enumerate()
                .filter(|&(c, _)| h.spectrum.iter().any(|(_, s)| s[c] > 1e-6 * largest))
                .map(|(c, axis)| {
                    let points = h
                        .spectrum
                        .iter()
                        .filter(|(_, s)| s[c] > 0.0)
                        .map(|(f, s)| [f.log10(), s[c].log10()])
                        .collect();
                    (*axis, points)
                })
                .collect()
        }
        None => Vec::new(),
    };
    Plot::new("probe-spectrum")
        .show_background(false)
        .height(height)
        .legend(Legend::default())
        .x_axis_label("log10 f (Hz)")
        .y_axis_label("log10 peak a (m/s²)")
        .show(ui, |plot| {
            for (axis, points) in lines {
                plot.line(Line::new(axis, points));
            }
        });
}

fn interface(ui: &mut egui::Ui, cache: &FieldCache, clock: &Clock, info: &SceneInfo, height: f32) {
    ui.strong("Contact interfaces over time");
    let Some(c) = cache.contact() else {
        ui.label(if info.contacts == 0 {
            "This scene has no contact interface."
        } else {
            "waiting for the solver…"
        });
        return;
    };
    let dt_us = info.dt * 1e6;
    let steps = c.first().map_or(0, |h| h.normal_force.len());
    let force = over_time(
        (0..steps).map(|m| c.iter().map(|h| h.normal_force[m]).sum::<f64>() * 1e-3),
        dt_us,
    );
    let slip = over_time(
        (0..steps).map(|m| {
            c.iter()
                .flat_map(|h| h.slip[m].iter().copied())
                .fold(0.0, f64::max)
                * 1e6
        }),
        dt_us,
    );
    Plot::new("interface")
        .show_background(false)
        .height(height)
        .legend(Legend::default())
        .x_axis_label("t (µs)")
        .show(ui, |plot| {
            plot.line(Line::new("normal force (kN)", force));
            plot.line(Line::new("max slip (µm)", slip));
            plot.vline(VLine::new("now", clock.time() * 1e6));
        });
}

/// A per-step series as plot points against time in µs.
fn over_time(values: impl Iterator<Item = f64>, dt_us: f64) -> PlotPoints<'static> {
    values
        .enumerate()
        .map(|(m, v)| [m as f64 * dt_us, v])
        .collect()
}
