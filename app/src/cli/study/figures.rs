//! The PNG figures of a study (plotters, as the sweep's): each quantity of interest against each
//! parameter (`quantities.png`), a map over the first two parameters (`map.png`), for sampled
//! studies the histograms with their statistics (`histograms.png`), and the finite-difference
//! sensitivities along the path (`sensitivities.png`). The numbers behind the last two are
//! [`super::stats`]'s.

use std::path::Path as FsPath;

use lopin_core::study::runner::Outcome;
use lopin_core::study::{Design, Quantities};
use plotters::prelude::*;

use super::stats::{Sensitivity, Statistics};
use crate::cli::plot::{err, fonts, padded_range};

const PANEL: (u32, u32) = (420, 300);
/// Share of an axis' span added on each side.
const PAD: f64 = 0.06;

/// A drawing area of a figure.
type Area<'a> = DrawingArea<BitMapBackend<'a>, plotters::coord::Shift>;

/// The white picture of `path` cut into `rows` × `cols` panels of `panel` pixels: the whole
/// (to present) and its panels, row by row.
fn sheet(
    path: &FsPath,
    (rows, cols): (usize, usize),
    panel: (u32, u32),
) -> anyhow::Result<(Area<'_>, Vec<Area<'_>>)> {
    fonts();
    let size = (panel.0 * cols as u32, panel.1 * rows as u32);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let areas = root.split_evenly((rows, cols));
    Ok((root, areas))
}

/// A tick label: plain for moderate magnitudes, scientific otherwise.
fn tick(x: &f64) -> String {
    let a = x.abs();
    if a == 0.0 || (a.fract() == 0.0 && a < 1e4) {
        format!("{x:.0}")
    } else if (1e-2..1e4).contains(&a) {
        // three significant digits, no trailing zeros: 0.125, 2.5, 48
        let digits = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{x:.digits$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.2e}")
    }
}

/// Title of quantity k with its unit.
fn title(k: usize) -> String {
    let (name, unit) = Quantities::NAMES[k];
    format!("{} ({unit})", name.replace('_', " "))
}

/// A colour of the viridis-like scale for t in [0, 1].
fn scale(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 5] = [
        (68, 1, 84),
        (59, 82, 139),
        (33, 145, 140),
        (94, 201, 98),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    } * 4.0;
    let i = (t.floor() as usize).min(3);
    let u = t - i as f64;
    let mix = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * u).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

/// A chart on `area` with its caption, axes and ticks drawn.
type Chart<'a, 'b> = ChartContext<
    'a,
    BitMapBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

fn chart<'a, 'b>(
    area: &'a DrawingArea<BitMapBackend<'b>, plotters::coord::Shift>,
    caption: &str,
    (xr, yr): (std::ops::Range<f64>, std::ops::Range<f64>),
    (x_desc, y_desc): (&str, &str),
) -> anyhow::Result<Chart<'a, 'b>> {
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 14))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(68)
        .build_cartesian_2d(xr, yr)
        .map_err(err)?;
    chart
        .configure_mesh()
        .light_line_style(WHITE)
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_labels(5)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .label_style(("sans-serif", 11))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// Each quantity (rows) against each parameter (columns), one point per configuration,
/// coloured by the second parameter (the first for the second column) when there are two.
pub fn quantities(path: &FsPath, design: &Design, outcomes: &[Outcome]) -> anyhow::Result<()> {
    let d = design.targets.len();
    let nq = Quantities::NAMES.len();
    let (root, areas) = sheet(path, (nq, d), PANEL)?;
    for k in 0..nq {
        for p in 0..d {
            let area = &areas[k * d + p];
            let colour_by = (d > 1).then_some(usize::from(p == 0));
            let points: Vec<(f64, f64, f64)> = outcomes
                .iter()
                .map(|o| {
                    let x = &design.points[o.index];
                    (
                        x[p],
                        o.quantities.values()[k],
                        colour_by.map_or(0.0, |c| x[c]),
                    )
                })
                .filter(|(x, y, _)| x.is_finite() && y.is_finite())
                .collect();
            let (Some(xr), Some(yr)) = (
                padded_range(points.iter().map(|q| q.0), PAD),
                padded_range(points.iter().map(|q| q.1), PAD),
            ) else {
                area.titled(
                    &format!("{}: no finite values", title(k)),
                    ("sans-serif", 15),
                )
                .map_err(err)?;
                continue;
            };
            let (clo, chi) = points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), q| {
                    (a.min(q.2), b.max(q.2))
                });
            let mut chart = chart(
                area,
                &title(k),
                (xr, yr),
                (design.targets[p].label.as_str(), ""),
            )?;
            chart
                .draw_series(points.iter().map(|&(x, y, c)| {
                    let t = if chi > clo {
                        (c - clo) / (chi - clo)
                    } else {
                        0.5
                    };
                    Circle::new((x, y), 3, scale(t).filled())
                }))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}

/// Each quantity over the plane of the first two parameters: the configurations as coloured
/// cells (a grid) or dots (samples), the colour scale from the smallest to the largest value.
pub fn map(path: &FsPath, design: &Design, outcomes: &[Outcome]) -> anyhow::Result<()> {
    if design.targets.len() < 2 {
        return Ok(());
    }
    let nq = Quantities::NAMES.len();
    let (root, areas) = sheet(path, (2, 3), (PANEL.0, PANEL.1 + 40))?;
    let xy: Vec<(f64, f64)> = outcomes
        .iter()
        .map(|o| (design.points[o.index][0], design.points[o.index][1]))
        .collect();
    let distinct = |v: Vec<f64>| {
        let mut v: Vec<f64> = v.into_iter().filter(|x| x.is_finite()).collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    };
    let xs = distinct(xy.iter().map(|p| p.0).collect());
    let ys = distinct(xy.iter().map(|p| p.1).collect());
    // a grid's cells span half-way to the neighbours; samples are dots
    let grid = !design.sampled && xs.len() * ys.len() >= outcomes.len();
    let half = |v: &[f64], x: f64| -> (f64, f64) {
        let i = v.iter().position(|&a| a == x).unwrap_or(0);
        let lo = if i > 0 {
            (v[i - 1] + x) / 2.0
        } else {
            x - span(v) / 2.0
        };
        let hi = if i + 1 < v.len() {
            (v[i + 1] + x) / 2.0
        } else {
            x + span(v) / 2.0
        };
        (lo, hi)
    };
    for (k, area) in areas.iter().enumerate().take(nq) {
        let values: Vec<f64> = outcomes.iter().map(|o| o.quantities.values()[k]).collect();
        let (lo, hi) = values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let (Some(xr), Some(yr)) = (
            padded_range(xs.iter().copied(), PAD),
            padded_range(ys.iter().copied(), PAD),
        ) else {
            continue;
        };
        let mut chart = chart(
            area,
            &format!(
                "{}: {} (dark) to {} (light)",
                title(k),
                tick(&lo),
                tick(&hi)
            ),
            (xr, yr),
            (
                design.targets[0].label.as_str(),
                design.targets[1].label.as_str(),
            ),
        )?;
        let t = |v: f64| if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
        if grid {
            chart
                .draw_series(xy.iter().zip(&values).map(|(&(x, y), &v)| {
                    let (x0, x1) = half(&xs, x);
                    let (y0, y1) = half(&ys, y);
                    Rectangle::new([(x0, y0), (x1, y1)], scale(t(v)).filled())
                }))
                .map_err(err)?;
        } else {
            chart
                .draw_series(
                    xy.iter()
                        .zip(&values)
                        .map(|(&(x, y), &v)| Circle::new((x, y), 5, scale(t(v)).filled())),
                )
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}

fn span(v: &[f64]) -> f64 {
    match (v.first(), v.last()) {
        (Some(a), Some(b)) if b > a => (b - a) / (v.len() - 1) as f64,
        (Some(a), _) => a.abs().max(1e-30) * 0.1,
        _ => 1.0,
    }
}

/// Histograms of every quantity over a sampled study, with its statistics in the title and
/// lines at the mean and the 5 % and 95 % quantiles.
pub fn histograms(path: &FsPath, outcomes: &[Outcome], stats: &[Statistics]) -> anyhow::Result<()> {
    let nq = Quantities::NAMES.len();
    let (root, areas) = sheet(path, (2, 3), (PANEL.0, PANEL.1 + 40))?;
    let bins = ((outcomes.len() as f64).sqrt().ceil() as usize).clamp(5, 30);
    for (k, area) in areas.iter().enumerate().take(nq) {
        let s = &stats[k];
        let values: Vec<f64> = outcomes
            .iter()
            .map(|o| o.quantities.values()[k])
            .filter(|v| v.is_finite())
            .collect();
        let Some(xr) = padded_range(values.iter().copied(), PAD) else {
            area.titled(
                &format!("{}: no finite values", title(k)),
                ("sans-serif", 15),
            )
            .map_err(err)?;
            continue;
        };
        let width = (xr.end - xr.start) / bins as f64;
        let mut counts = vec![0usize; bins];
        for v in &values {
            let b = (((v - xr.start) / width) as usize).min(bins - 1);
            counts[b] += 1;
        }
        let top = counts.iter().copied().max().unwrap_or(1) as f64 * 1.35;
        let mut chart = chart(
            area,
            &title(k),
            (xr.clone(), 0.0..top),
            ("", "configurations"),
        )?;
        chart
            .draw_series(counts.iter().enumerate().map(|(b, &c)| {
                let x0 = xr.start + b as f64 * width;
                Rectangle::new([(x0, 0.0), (x0 + width, c as f64)], BLUE.mix(0.6).filled())
            }))
            .map_err(err)?;
        let note = [
            format!(
                "n {}{}  mean {:.4e}  sd {:.3e}",
                s.count,
                if s.non_finite > 0 {
                    format!(" (+{} not finite)", s.non_finite)
                } else {
                    String::new()
                },
                s.mean,
                s.sd
            ),
            format!("p5 {:.4e}  p50 {:.4e}  p95 {:.4e}", s.p5, s.p50, s.p95),
        ];
        for (line, text) in note.iter().enumerate() {
            chart
                .plotting_area()
                .draw(&Text::new(
                    text.clone(),
                    (xr.start, top * (0.99 - 0.06 * line as f64)),
                    ("sans-serif", 12),
                ))
                .map_err(err)?;
        }
        // the lines stop below the statistics' text (the bars reach 1/1.35 of the top)
        for (x, colour) in [(s.mean, RED), (s.p5, BLACK), (s.p95, BLACK)] {
            chart
                .draw_series(LineSeries::new(
                    [(x, 0.0), (x, 0.85 * top)],
                    colour.stroke_width(2),
                ))
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}

/// The finite-difference sensitivities along the path: for each quantity, dQ/dp times the
/// parameter's span (the change of Q over the parameter's whole range at that rate), against the
/// parameter's value at the middle of the step, one colour per parameter.
pub fn sensitivities(path: &FsPath, design: &Design, sens: &[Sensitivity]) -> anyhow::Result<()> {
    if sens.is_empty() {
        return Ok(());
    }
    let nq = Quantities::NAMES.len();
    let d = design.targets.len();
    let (root, areas) = sheet(path, (nq, d), PANEL)?;
    for k in 0..nq {
        for p in 0..d {
            let area = &areas[k * d + p];
            let points: Vec<(f64, f64)> = sens
                .iter()
                .filter(|s| s.parameter == p)
                .map(|s| (s.at, s.scaled[k]))
                .filter(|(x, y)| x.is_finite() && y.is_finite())
                .collect();
            let (Some(xr), Some(yr)) = (
                padded_range(points.iter().map(|q| q.0), PAD),
                padded_range(points.iter().map(|q| q.1).chain([0.0]), PAD),
            ) else {
                continue;
            };
            let mut chart = chart(
                area,
                &format!(
                    "d {} / d {} × span",
                    Quantities::NAMES[k].0,
                    design.targets[p].label
                ),
                (xr, yr),
                (design.targets[p].label.as_str(), ""),
            )?;
            chart
                .draw_series(
                    points
                        .iter()
                        .map(|&(x, y)| Circle::new((x, y), 3, Palette99::pick(p).filled())),
                )
                .map_err(err)?;
        }
    }
    root.present().map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks_are_short() {
        let t = |x: f64| super::tick(&x);
        assert_eq!(
            [
                t(0.0),
                t(25.0),
                t(48.0),
                t(0.125),
                t(2.5),
                t(0.333),
                t(1234.6)
            ],
            ["0", "25", "48", "0.125", "2.5", "0.333", "1235"]
        );
        assert_eq!([t(6.2e5), t(1e-5)], ["6.20e5", "1.00e-5"]);
    }
}
