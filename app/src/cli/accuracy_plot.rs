//! The run-time-against-error figure of `lopin accuracy`: log–log, error against wall time, one
//! curve per method (LATIN whole interval, LATIN incremental) and per yardstick (reference solid,
//! exact solution dashed when there is one), the reference's own time as a vertical line and its
//! own error against the exact solution (the discretization floor) as a horizontal one.

use std::path::Path;

use plotters::prelude::*;

use super::accuracy::Point;
use super::plot::{err, fonts};

const FLOOR: f64 = 1e-14;

pub fn plot(path: &Path, title: &str, points: &[Point]) -> anyhow::Result<()> {
    fonts();
    let reference = points.iter().find(|p| p.method == "reference");
    let series = |method: &str, exact: bool| -> Vec<(f64, f64, Option<f64>)> {
        points
            .iter()
            .filter(|p| p.method == method)
            .filter_map(|p| {
                let e = if exact {
                    p.error_exact?
                } else {
                    p.error_reference
                };
                Some((p.time_s, e.max(FLOOR), p.tol))
            })
            .collect()
    };
    let all: Vec<(f64, f64)> = ["latin", "latin-incremental"]
        .iter()
        .flat_map(|m| {
            let mut v = series(m, false);
            v.extend(series(m, true));
            v
        })
        .map(|(t, e, _)| (t, e))
        .chain(reference.map(|r| (r.time_s, r.error_exact.unwrap_or(1.0).max(FLOOR))))
        .collect();
    let (tmin, tmax) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    let (emin, emax) = all.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    let root = BitMapBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("run time against error: {title}"),
            ("sans-serif", 22),
        )
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (tmin / 1.5..tmax * 1.5).log_scale(),
            (emin / 3.0..emax * 3.0).log_scale(),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("wall time (s), setup included")
        .y_desc("relative error")
        .x_label_formatter(&|x| {
            if *x < 0.1 {
                format!("{x:.3}")
            } else {
                format!("{x:.2}")
            }
        })
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(err)?;
    if let Some(r) = reference {
        chart
            .draw_series(DashedLineSeries::new(
                [(r.time_s, emin / 3.0), (r.time_s, emax * 3.0)],
                6,
                4,
                BLACK.stroke_width(2),
            ))
            .map_err(err)?
            .label(format!("monolithic reference: {:.3} s", r.time_s))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 20, y)], BLACK.stroke_width(2)));
        if let Some(floor) = r.error_exact {
            chart
                .draw_series(DashedLineSeries::new(
                    [(tmin / 1.5, floor), (tmax * 1.5, floor)],
                    6,
                    4,
                    RGBColor(120, 120, 120).stroke_width(2),
                ))
                .map_err(err)?
                .label(format!(
                    "discretization floor (reference vs exact): {floor:.2e}"
                ))
                .legend(|(x, y)| {
                    PathElement::new(
                        [(x, y), (x + 20, y)],
                        RGBColor(120, 120, 120).stroke_width(2),
                    )
                });
        }
    }
    let curves: [(&str, bool, RGBColor, &str); 4] = [
        ("latin", false, RED, "LATIN, whole interval: vs reference"),
        (
            "latin-incremental",
            false,
            BLUE,
            "LATIN, incremental: vs reference",
        ),
        (
            "latin",
            true,
            RGBColor(230, 120, 0),
            "LATIN, whole interval: vs exact",
        ),
        (
            "latin-incremental",
            true,
            RGBColor(0, 150, 150),
            "LATIN, incremental: vs exact",
        ),
    ];
    for (method, exact, colour, label) in curves {
        let s = series(method, exact);
        if s.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(
                s.iter().map(|p| (p.0, p.1)),
                colour.stroke_width(2),
            ))
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
        chart
            .draw_series(
                s.iter()
                    .map(|p| Circle::new((p.0, p.1), 4, colour.filled())),
            )
            .map_err(err)?;
        if !exact {
            chart
                .draw_series(s.iter().filter_map(|p| {
                    p.2.map(|t| {
                        Text::new(
                            format!("{t:.0e}"),
                            (p.0 * 1.04, p.1 * 1.3),
                            ("sans-serif", 12),
                        )
                    })
                }))
                .map_err(err)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
