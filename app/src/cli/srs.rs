//! `lopin srs RUN_DIR --at X,Y,Z`: what shock engineers read off a run saved with `lopin run
//! --out`: the acceleration history at probe points (the node nearest each point, its
//! step-averaged acceleration) and its shock response spectrum, maximax at a quality factor Q
//! ([`lopin_core::shock_spectrum`]), as CSV files and a log–log figure.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use lopin_core::mesh::Vec3;
use lopin_core::post;
use lopin_core::shock_spectrum::{self, frequencies, ratio_of_quality};
use plotters::prelude::*;

use super::accuracy_plot::{extent, log_log_chart};
use super::plot::{err, fonts};
use crate::run_dir::run_json::RunRecord;
use crate::run_dir::write_atomic;

/// Options of `lopin srs`.
#[derive(Debug, Args)]
pub struct SrsArgs {
    /// A run directory (made by `lopin run --out DIR`).
    pub run: PathBuf,
    /// A probe point X,Y,Z in metres: the node nearest to it is read (repeatable).
    #[arg(long = "at", value_name = "X,Y,Z", required = true)]
    pub at: Vec<String>,
    /// Quality factor Q of the oscillators (damping ratio 1/(2Q)).
    #[arg(long, default_value_t = 10.0)]
    pub q: f64,
    /// The band of natural frequencies LOW:HIGH in Hz (default: from 1/(the run's duration) to
    /// a tenth of the sampling frequency 1/Δt).
    #[arg(long, value_name = "LOW:HIGH")]
    pub band: Option<String>,
    /// Natural frequencies per octave.
    #[arg(long, default_value_t = 12)]
    pub per_octave: usize,
    /// Folder for probe-N.csv (acceleration histories), srs-N.csv (spectra) and srs.png.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// One probe: where it was asked, the node read, and its histories.
struct Probe {
    at: Vec3,
    sub: usize,
    node: usize,
    distance: f64,
    /// Step-averaged acceleration of each step (at the mid-steps), m/s².
    acceleration: Vec<[f64; 3]>,
    /// Maximax per frequency and component, m/s².
    spectrum: Vec<[f64; 3]>,
}

pub fn srs(args: &SrsArgs) -> anyhow::Result<ExitCode> {
    let points = args
        .at
        .iter()
        .map(|s| parse_point(s))
        .collect::<anyhow::Result<Vec<Vec3>>>()?;
    anyhow::ensure!(
        args.q.is_finite() && args.q > 0.5,
        "--q: the quality factor must be a number above 0.5 (damping ratio below 1), got {}",
        args.q
    );
    anyhow::ensure!(
        args.per_octave > 0 && args.per_octave <= 96,
        "--per-octave: must lie in 1..=96, got {}",
        args.per_octave
    );
    let (_, solver, solution) = RunRecord::open_run(&args.run)?;
    let p = solver.problem();
    let dt = p.time.dt;
    let nyquist = 0.5 / dt;
    let (low, high) = match &args.band {
        Some(b) => parse_band(b)?,
        None => shock_spectrum::default_band(dt, p.time.end()),
    };
    anyhow::ensure!(
        high <= nyquist,
        "--band: {high:e} Hz is above the Nyquist frequency 1/(2Δt) = {nyquist:e} Hz of the run"
    );
    let freqs = frequencies(low, high, args.per_octave);
    let zeta = ratio_of_quality(args.q);
    let diameter = p.diameter();
    let mut probes = Vec::new();
    for (k, &at) in points.iter().enumerate() {
        let (sub, node, distance) = post::nearest_node(p, at).context("the model has no node")?;
        anyhow::ensure!(
            distance <= 0.1 * diameter,
            "--at {}: the nearest node is {distance:.3e} m away, outside the model (its size \
             is {diameter:.3e} m)",
            args.at[k]
        );
        let velocity = post::node_velocity(&solver, &solution, sub, node);
        let acceleration = shock_spectrum::step_accelerations(&velocity, dt);
        let spectrum = shock_spectrum::component_spectra(&acceleration, dt, &freqs, zeta);
        probes.push(Probe {
            at,
            sub,
            node,
            distance,
            acceleration,
            spectrum,
        });
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    for (k, probe) in probes.iter().enumerate() {
        write_csvs(&args.out, k + 1, probe, &freqs, dt)?;
    }
    let png = args.out.join("srs.png");
    figure(&png, &probes, &freqs, args.q)?;
    for (k, probe) in probes.iter().enumerate() {
        let node = p.subs[probe.sub].mesh.nodes[probe.node];
        println!(
            "probe {} at {:?}: node {} of {} at {:?} ({:.2e} m away)",
            k + 1,
            probe.at,
            probe.node,
            p.subs[probe.sub].name,
            node,
            probe.distance
        );
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            let peak = probe
                .acceleration
                .iter()
                .map(|a| a[c].abs())
                .fold(0.0, f64::max);
            let (i, top) = probe
                .spectrum
                .iter()
                .enumerate()
                .map(|(i, s)| (i, s[c]))
                .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
            println!(
                "  {axis}: peak acceleration {peak:.4e} m/s², SRS peak {top:.4e} m/s² at {:.4e} Hz",
                freqs[i]
            );
        }
    }
    println!(
        "SRS maximax at Q = {} over {:.3e}–{:.3e} Hz ({} frequencies): {}",
        args.q,
        low,
        high,
        freqs.len(),
        args.out.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// `probe-N.csv` (t at the mid-steps, ax, ay, az) and `srs-N.csv` (frequency, x, y, z).
fn write_csvs(dir: &Path, n: usize, probe: &Probe, freqs: &[f64], dt: f64) -> anyhow::Result<()> {
    let mut text = String::from("t_s,ax_m_s2,ay_m_s2,az_m_s2\n");
    for (m, a) in probe.acceleration.iter().enumerate() {
        let t = (m as f64 + 0.5) * dt;
        writeln!(text, "{t:e},{:e},{:e},{:e}", a[0], a[1], a[2])?;
    }
    write_atomic(&dir.join(format!("probe-{n}.csv")), text.as_bytes())?;
    let mut text = String::from("frequency_hz,srs_x_m_s2,srs_y_m_s2,srs_z_m_s2\n");
    for (f, s) in freqs.iter().zip(&probe.spectrum) {
        writeln!(text, "{f:e},{:e},{:e},{:e}", s[0], s[1], s[2])?;
    }
    write_atomic(&dir.join(format!("srs-{n}.csv")), text.as_bytes())
}

/// The spectra on a log–log figure: one curve per probe and component that carries any
/// acceleration (a component below 1e-6 of the largest is left out).
fn figure(path: &Path, probes: &[Probe], freqs: &[f64], q: f64) -> anyhow::Result<()> {
    fonts();
    let largest = probes
        .iter()
        .flat_map(|p| p.spectrum.iter().flatten())
        .fold(0.0f64, |a, &b| a.max(b));
    anyhow::ensure!(
        largest > 0.0,
        "every probe is at rest: there is no spectrum to draw"
    );
    let floor = 1e-6 * largest;
    let mut curves = Vec::new();
    for (k, p) in probes.iter().enumerate() {
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            let pts: Vec<(f64, f64)> = freqs
                .iter()
                .zip(&p.spectrum)
                .map(|(&f, s)| (f, s[c].max(floor)))
                .collect();
            if p.spectrum.iter().any(|s| s[c] > floor) {
                curves.push((format!("probe {} {axis}", k + 1), pts));
            }
        }
    }
    let all: Vec<(f64, f64)> = curves.iter().flat_map(|c| c.1.iter().copied()).collect();
    let ((fmin, fmax), (smin, smax)) = extent(&all);
    let root = BitMapBackend::new(path, (1000, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let mut chart = log_log_chart(
        &root,
        format!("shock response spectrum, maximax, Q = {q}"),
        fmin..fmax,
        smin / 2.0..smax * 2.0,
        ("natural frequency (Hz)", "peak acceleration (m/s²)"),
        &|x| format!("{x:.0e}"),
    )?;
    for (i, (label, pts)) in curves.into_iter().enumerate() {
        let colour = Palette99::pick(i).to_rgba();
        chart
            .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
            .map_err(err)?
            .label(label)
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// `X,Y,Z` in metres.
fn parse_point(s: &str) -> anyhow::Result<Vec3> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|e| anyhow::anyhow!("--at {s}: {e} (expected X,Y,Z in metres)"))?;
    match v[..] {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([x, y, z]),
        _ => anyhow::bail!("--at {s}: expected three finite numbers X,Y,Z in metres"),
    }
}

/// `LOW:HIGH` in Hz, 0 < LOW < HIGH.
fn parse_band(s: &str) -> anyhow::Result<(f64, f64)> {
    let parsed = s
        .split_once(':')
        .and_then(|(a, b)| Some((a.trim().parse::<f64>().ok()?, b.trim().parse::<f64>().ok()?)));
    match parsed {
        Some((low, high)) if low > 0.0 && high > low && high.is_finite() => Ok((low, high)),
        _ => anyhow::bail!("--band {s}: expected LOW:HIGH in Hz with 0 < LOW < HIGH"),
    }
}
