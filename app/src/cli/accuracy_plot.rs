//! The run-time-against-error figure of `lopin accuracy`: log–log, error against wall time, one
//! curve per method (LATIN whole interval, LATIN incremental with the run's window start and with
//! the held start) and per yardstick (reference solid,
//! exact solution dashed when there is one), the reference's own time as a vertical line and its
//! own error against the exact solution (the discretization floor) as a horizontal one; and the
//! iterations-against-error figure of every field ([`plot_fields`]).

use std::ops::Range;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::accuracy::{field_errors, Point};
use super::plot::{err, fonts};

const FLOOR: f64 = 1e-14;

/// The LATIN curves `lopin accuracy` draws, by method name.
const LATIN_METHODS: [&str; 4] = [
    "latin",
    "latin-smooth",
    "latin-incremental",
    "latin-incremental-hold",
];

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
    let all: Vec<(f64, f64)> = LATIN_METHODS
        .iter()
        .flat_map(|m| {
            let mut v = series(m, false);
            v.extend(series(m, true));
            v
        })
        .map(|(t, e, _)| (t, e))
        .chain(reference.map(|r| (r.time_s, r.error_exact.unwrap_or(1.0).max(FLOOR))))
        .collect();
    let ((tmin, tmax), (emin, emax)) = extent(&all);
    let root = BitMapBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let x_label = |x: &f64| {
        if *x < 0.1 {
            format!("{x:.3}")
        } else {
            format!("{x:.2}")
        }
    };
    let mut chart = log_log_chart(
        &root,
        format!("run time against error: {title}"),
        tmin / 1.5..tmax * 1.5,
        emin / 3.0..emax * 3.0,
        ("wall time (s), setup included", "relative error"),
        &x_label,
    )?;
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
    // (method, what it is, colour against the reference, colour against the exact solution)
    let methods: [(&str, &str, RGBColor, RGBColor); 4] = [
        ("latin", "whole interval", RED, RGBColor(230, 120, 0)),
        (
            "latin-smooth",
            "whole interval, stop on η̄",
            RGBColor(140, 60, 170),
            RGBColor(200, 120, 200),
        ),
        (
            "latin-incremental",
            "incremental",
            BLUE,
            RGBColor(0, 150, 150),
        ),
        (
            "latin-incremental-hold",
            "incremental, held window start",
            RGBColor(90, 160, 255),
            RGBColor(120, 200, 120),
        ),
    ];
    let curves = [false, true].into_iter().flat_map(|exact| {
        methods
            .iter()
            .map(move |&(method, what, vs_ref, vs_exact)| {
                let (colour, yardstick) = if exact {
                    (vs_exact, "exact")
                } else {
                    (vs_ref, "reference")
                };
                (
                    method,
                    exact,
                    colour,
                    format!("LATIN, {what}: vs {yardstick}"),
                )
            })
    });
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

/// The iterations-against-error figure: for the whole-interval chains stopped on η (solid) and
/// on η̄ (dashed), each field's difference from the reference against the iterations spent,
/// one colour per field, so that how many iterations each field needs for a given error reads
/// off directly. Fields that are exactly zero (no contact) are left out.
pub fn plot_fields(path: &Path, title: &str, points: &[Point]) -> anyhow::Result<()> {
    fonts();
    let colours = [
        RGBColor(0, 90, 200),
        RED,
        RGBColor(230, 120, 0),
        RGBColor(0, 150, 80),
        RGBColor(140, 60, 170),
        RGBColor(90, 90, 90),
    ];
    let series = |method: &str, field: usize| -> Vec<(f64, f64)> {
        points
            .iter()
            .filter(|p| p.method == method)
            .filter_map(|p| {
                let e = field_errors(p.fields.as_ref()?)[field].1;
                (e > 0.0).then_some((p.iterations.max(1) as f64, e.max(FLOOR)))
            })
            .collect()
    };
    let methods = [("latin", "stop on η"), ("latin-smooth", "stop on η̄")];
    let all: Vec<(f64, f64)> = methods
        .iter()
        .flat_map(|(m, _)| (0..colours.len()).flat_map(move |f| series(m, f)))
        .collect();
    if all.is_empty() {
        anyhow::bail!("no whole-interval points to draw in {}", path.display());
    }
    let ((xmin, xmax), (emin, emax)) = extent(&all);
    let root = BitMapBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let mut chart = log_log_chart(
        &root,
        format!("error of each field against iterations: {title}"),
        xmin / 1.3..xmax * 1.3,
        emin / 3.0..emax * 3.0,
        (
            "LATIN iterations (whole interval, cumulative over the tolerances)",
            "relative difference from the reference",
        ),
        &|x: &f64| format!("{x:.0}"),
    )?;
    for (mi, (method, how)) in methods.iter().enumerate() {
        for (f, colour) in colours.iter().copied().enumerate() {
            let s = series(method, f);
            if s.is_empty() {
                continue;
            }
            let style = colour.stroke_width(2);
            let label = format!("{} ({how})", FIELD_LABELS[f]);
            if mi == 0 {
                chart
                    .draw_series(LineSeries::new(s.iter().copied(), style))
                    .map_err(err)?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], style));
            } else {
                chart
                    .draw_series(DashedLineSeries::new(s.iter().copied(), 6, 4, style))
                    .map_err(err)?
                    .label(label)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 8, y)], style));
            }
            chart
                .draw_series(s.iter().map(|p| Circle::new(*p, 3, colour.filled())))
                .map_err(err)?;
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font(("sans-serif", 13))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// A chart with logarithmic axes drawn into a bitmap.
pub(super) type LogLogChart<'r, 'p> =
    ChartContext<'r, BitMapBackend<'p>, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// A log–log chart of both figures on `root`: caption, margins, the mesh with axis descriptions
/// (x, y), x labels by `x_label` and y labels as powers of ten.
pub(super) fn log_log_chart<'r, 'p>(
    root: &'r DrawingArea<BitMapBackend<'p>, Shift>,
    caption: String,
    x: Range<f64>,
    y: Range<f64>,
    (x_desc, y_desc): (&str, &str),
    x_label: &dyn Fn(&f64) -> String,
) -> anyhow::Result<LogLogChart<'r, 'p>> {
    let mut chart = ChartBuilder::on(root)
        .caption(caption, ("sans-serif", 22))
        .margin(14)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d(x.log_scale(), y.log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(x_label)
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// The ranges (min, max) of the x and of the y values of `points`.
pub(super) fn extent(points: &[(f64, f64)]) -> ((f64, f64), (f64, f64)) {
    points.iter().fold(
        ((f64::INFINITY, 0.0f64), (f64::INFINITY, 0.0f64)),
        |((x0, x1), (y0, y1)), p| ((x0.min(p.0), x1.max(p.0)), (y0.min(p.1), y1.max(p.1))),
    )
}

/// Readable names of [`super::accuracy::field_errors`], in its order.
const FIELD_LABELS: [&str; 6] = [
    "displacement",
    "velocity",
    "step-averaged velocity",
    "step-averaged interface force",
    "energy",
    "contact normal force",
];
