//! The right panel's plots (egui_plot): the live convergence of the LATIN error indicator η
//! against cumulative iterations on a log scale with a marker at each parameter change (the
//! seed paper's Figure 6, drawn live), the probe's velocity and von Mises history, and the
//! contact interfaces' total normal force and maximum slip over time.

use crate::app::SceneInfo;
use crate::clock::Clock;
use crate::field_cache::FieldCache;
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
    ui.strong(format!("Probe: substructure {sub}, node {node}"));
    let dt_us = info.dt * 1e6;
    let (speed, vm) = match cache.probe_history() {
        Some(h) => (
            over_time(h.speed.iter().copied(), dt_us),
            over_time(h.von_mises.iter().map(|v| v * 1e-6), dt_us),
        ),
        None => (PlotPoints::default(), PlotPoints::default()),
    };
    Plot::new("probe")
        .show_background(false)
        .height(height)
        .legend(Legend::default())
        .x_axis_label("t (µs)")
        .show(ui, |plot| {
            plot.line(Line::new("|v| (m/s)", speed));
            plot.line(Line::new("von Mises (MPa)", vm));
            plot.vline(VLine::new("now", clock.time() * 1e6));
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
