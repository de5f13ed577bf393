//! PNG figures of a sweep (plotters, bitmap backend, embedded DejaVu Sans): η against cumulative
//! iterations over the whole sweep (log scale, a marker line at each parameter change: the seed
//! paper's figure), and the quantities of interest against the parameter.

use std::path::Path;

use anyhow::anyhow;
use lopin_core::Parameter;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

use super::sweep::records::ValueRecord;

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

pub(super) fn fonts() {
    // registering twice is harmless; the error type carries no information we can act on
    let _ = register_font("sans-serif", FontStyle::Normal, FONT);
}

pub(super) fn err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("plotting: {e:?}")
}

/// η against cumulative iterations, warm sweep (and the cold solves, if recorded, in grey).
pub fn convergence(path: &Path, records: &[ValueRecord], param: Parameter) -> anyhow::Result<()> {
    fonts();
    let param = param.name();
    let mut warm = Vec::new();
    let mut changes = Vec::new();
    let mut it = 0usize;
    for r in records {
        changes.push((it, r.value));
        for &e in &r.eta_history {
            it += 1;
            if e.is_finite() {
                warm.push((it as f64, e.max(1e-16)));
            }
        }
    }
    let total = it.max(1) as f64;
    let ymin = warm.iter().map(|p| p.1).fold(1.0f64, f64::min).max(1e-16) / 2.0;
    let ymax = warm.iter().map(|p| p.1).fold(1e-3f64, f64::max).min(1e300) * 2.0;
    let root = BitMapBackend::new(path, (1000, 560)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("LATIN error indicator over the sweep of {param} (warm starts)"),
            ("sans-serif", 22),
        )
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..total * 1.02, (ymin..ymax).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("cumulative LATIN iterations")
        .y_desc("eta")
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(err)?;
    for &(x, v) in &changes {
        chart
            .draw_series(LineSeries::new(
                [(x as f64, ymin), (x as f64, ymax)],
                BLUE.mix(0.25),
            ))
            .map_err(err)?;
        chart
            .draw_series([Text::new(
                format!("{v:.3}"),
                (x as f64 + 0.3, ymax / 1.6),
                ("sans-serif", 12),
            )])
            .map_err(err)?;
    }
    chart
        .draw_series(LineSeries::new(warm.iter().copied(), RED.stroke_width(2)))
        .map_err(err)?
        .label("eta (warm sweep)")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], RED.stroke_width(2)));
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// A panel: its title and the quantity it plots.
type Panel = (&'static str, fn(&ValueRecord) -> f64);

/// Peak normal force, max slip and end energy against the parameter (three panels).
pub fn quantities(path: &Path, records: &[ValueRecord], param: Parameter) -> anyhow::Result<()> {
    fonts();
    let param = param.name();
    let root = BitMapBackend::new(path, (1200, 400)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let panels = root.split_evenly((1, 3));
    let xs: Vec<f64> = records.iter().map(|r| r.value).collect();
    let series: [Panel; 3] = [
        ("peak normal force (N)", |r| r.peak_normal_force),
        ("max slip (m)", |r| r.max_slip),
        ("energy at the end (J)", |r| r.energy_end),
    ];
    for (area, (title, f)) in panels.iter().zip(series) {
        // only finite points are drawn; a panel with none says so instead of a broken axis
        let points: Vec<(f64, f64)> = xs
            .iter()
            .copied()
            .zip(records.iter().map(f))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        let (Some(xr), Some(yr)) = (
            padded_range(points.iter().map(|p| p.0), 0.05),
            padded_range(points.iter().map(|p| p.1), 0.1),
        ) else {
            area.titled(&format!("{title}: no finite values"), ("sans-serif", 18))
                .map_err(err)?;
            continue;
        };
        let mut chart = ChartBuilder::on(area)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(75)
            .build_cartesian_2d(xr, yr)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(param)
            .y_label_formatter(&|y| format!("{y:.3e}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                points.iter().copied(),
                BLUE.stroke_width(2),
            ))
            .map_err(err)?;
        chart
            .draw_series(
                points
                    .iter()
                    .map(|&(x, y)| Circle::new((x, y), 4, BLUE.filled())),
            )
            .map_err(err)?;
    }
    root.present().map_err(err)?;
    Ok(())
}

/// The range of finite values, padded by `share` of its width (or of its magnitude when all are
/// equal); None when there is no finite value or the padded range is not finite.
pub(super) fn padded_range(
    values: impl Iterator<Item = f64>,
    share: f64,
) -> Option<std::ops::Range<f64>> {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    let pad = ((hi - lo) * share)
        .max(hi.abs().max(lo.abs()) * 1e-3)
        .max(1e-30);
    let range = (lo - pad)..(hi + pad);
    (range.start.is_finite() && range.end.is_finite() && range.start < range.end).then_some(range)
}
