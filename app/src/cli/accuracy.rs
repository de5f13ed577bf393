//! `lopin accuracy`: run time against error. LATIN (whole interval stopped on η, whole interval
//! stopped on η̄ — the indicator on step-averaged fields —, and incremental with window 1, once
//! with the run's window start (default: smooth extrapolation) and once with the held start) at
//! tolerances 1e-1 … 1e-8, each result compared with the monolithic reference (max relative
//! nodal-velocity difference over space–time, and the differences the alternating mode cannot
//! touch: displacements, step-averaged velocities, step-averaged interface forces, energy,
//! contact normal force) and, for the `bar` scenes, with the exact solution (relative
//! space–time L2 error: the discretization floor). Writes accuracy.csv, accuracy.png (log–log
//! velocity error against wall time, one curve per method, the reference's own time as a
//! vertical line) and accuracy-fields.png (each field's error against iterations, for both
//! stopping tests). The time scheme is the run's (`--rho-inf`; the reference uses the same).
//!
//! Timing: the whole-interval solves form one chain — each tolerance continues from the state of
//! the previous one, so the time of a row is the time of one solve stopped at that tolerance
//! (setup included). Incremental solves are cold, one per tolerance (a continued incremental
//! solve would redo every window), on one factorization whose setup time each row includes.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::scene::settings::WindowStart;
use lopin_core::stages::indicator::StopTest;
use lopin_core::{post, Settings, Solution, Solver};
use lopin_judge::compare::{compare, Comparison};
use lopin_reference::exact::{l2_error, BarExact};
use lopin_reference::monolithic::Monolithic;

use serde::Serialize;

use super::accuracy_plot;
use super::report::column_table;
use super::setup::{build, SceneArgs};

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Tolerances on η, loosest first.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1e-1,1e-2,1e-3,1e-4,1e-5,1e-6,1e-7,1e-8"
    )]
    pub tols: Vec<f64>,
    /// Skip the incremental (window 1) variant.
    #[arg(long)]
    pub no_incremental: bool,
    /// Output directory (default out/accuracy-SCENE-rREFINE).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// One point of the study.
#[derive(Debug, Clone, PartialEq)]
pub struct Point {
    pub method: &'static str,
    pub tol: Option<f64>,
    pub iterations: usize,
    pub eta: f64,
    pub time_s: f64,
    pub error_reference: f64,
    pub error_exact: Option<f64>,
    /// Every difference against the reference (None for the reference itself).
    pub fields: Option<Comparison>,
}

/// The differences of a comparison drawn and tabulated per field, named as in the figure.
pub fn field_errors(c: &Comparison) -> [(&'static str, f64); 6] {
    [
        ("displacement", c.rel_diff_displacement),
        ("velocity", c.rel_diff_velocity),
        ("velocity_avg", c.rel_diff_velocity_avg),
        ("force_avg", c.rel_diff_force),
        ("energy", c.rel_diff_energy),
        ("contact_force", c.rel_diff_contact_force),
    ]
}

pub fn accuracy(args: &AccuracyArgs) -> anyhow::Result<ExitCode> {
    anyhow::ensure!(
        args.scene.solver.tol.is_none() && args.scene.solver.window.is_none(),
        "lopin accuracy sets the tolerance and the window itself: remove --tol / --window"
    );
    anyhow::ensure!(!args.tols.is_empty(), "--tols: give at least one tolerance");
    for &t in &args.tols {
        anyhow::ensure!(
            t > 0.0 && t < 1.0,
            "--tols: every tolerance must lie in (0, 1), got {t}"
        );
    }
    let mut tols = args.tols.clone();
    tols.sort_by(|a, b| b.total_cmp(a));
    tols.dedup();
    let built = build(&args.scene)?;
    let out = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(format!(
            "out/accuracy-{}-r{}",
            built.spec.name, args.scene.refine
        ))
    });
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let exact = BarExact::for_problem(&built.problem);

    // the reference
    let clock = Instant::now();
    let reference = Monolithic::new(built.problem.clone())?;
    let mono = reference.solve()?;
    let reference_s = built.build_s + clock.elapsed().as_secs_f64();
    let p = reference.problem();
    let mut points = vec![Point {
        method: "reference",
        tol: None,
        iterations: mono.sweeps,
        eta: mono.contact_change,
        time_s: reference_s,
        error_reference: 0.0,
        error_exact: exact
            .as_ref()
            .map(|e| l2_error(p, e, &mut |s, m| reference.sub_velocity(&mono, m, s))),
        fields: None,
    }];
    eprintln!("reference: {reference_s:.3} s");

    let error_exact = |solver: &Solver, sol: &Solution| -> Option<f64> {
        let e = exact.as_ref()?;
        let hist = post::velocity_history(solver, sol);
        Some(l2_error(solver.problem(), e, &mut |s, m| {
            hist[m][s].clone()
        }))
    };

    let point = |method: &'static str,
                 tol: f64,
                 iterations: usize,
                 time_s: f64,
                 solver: &Solver,
                 sol: &Solution| {
        let c = compare(solver, sol, &reference, &mono);
        let point = Point {
            method,
            tol: Some(tol),
            iterations,
            eta: sol.eta,
            time_s,
            error_reference: c.rel_diff_velocity,
            error_exact: error_exact(solver, sol),
            fields: Some(c),
        };
        eprintln!(
            "{method} tol {tol:.0e}: {iterations} iterations, {time_s:.3} s, error {:.3e}",
            point.error_reference
        );
        point
    };

    // whole interval: one chain of solves per stopping test
    for (method, stop) in [("latin", StopTest::Eta), ("latin-smooth", StopTest::Smooth)] {
        let clock = Instant::now();
        let mut solver = Solver::new(built.problem.clone(), built.settings)?;
        let mut elapsed = built.build_s + clock.elapsed().as_secs_f64();
        let mut state = None;
        let mut iterations = 0;
        for &tol in &tols {
            let settings = Settings {
                tol,
                window: None,
                max_iter: 100_000,
                stop,
                ..built.settings
            };
            solver.set_settings(settings)?;
            let clock = Instant::now();
            let sol = solver.solve(state.as_ref())?;
            elapsed += clock.elapsed().as_secs_f64();
            iterations += sol.iterations;
            points.push(point(method, tol, iterations, elapsed, &solver, &sol));
            state = Some(sol.state);
        }
    }

    // incremental: cold per tolerance, with the run's window start (default smooth) and, beside
    // it, the held start it replaced
    let starts = [
        ("latin-incremental", built.settings.window_start),
        ("latin-incremental-hold", WindowStart::Hold),
    ];
    for (method, window_start) in starts.into_iter().filter(|_| !args.no_incremental) {
        if method != "latin-incremental" && window_start == built.settings.window_start {
            continue;
        }
        let clock = Instant::now();
        let mut solver = Solver::new(built.problem.clone(), built.settings)?;
        let setup_s = built.build_s + clock.elapsed().as_secs_f64();
        for &tol in &tols {
            solver.set_settings(Settings {
                tol,
                window: Some(1),
                max_iter: 100_000,
                window_start,
                ..built.settings
            })?;
            let clock = Instant::now();
            let sol = solver.solve(None)?;
            let time_s = setup_s + clock.elapsed().as_secs_f64();
            points.push(point(method, tol, sol.iterations, time_s, &solver, &sol));
        }
    }

    let csv = out.join("accuracy.csv");
    write_csv(&csv, &built.spec.name, args.scene.refine, &points)
        .with_context(|| format!("writing {}", csv.display()))?;
    let png = out.join("accuracy.png");
    let title = format!(
        "{} (refine {}, {} dofs)",
        built.spec.name,
        args.scene.refine,
        p.dof_count()
    );
    accuracy_plot::plot(&png, &title, &points)?;
    let fields_png = out.join("accuracy-fields.png");
    accuracy_plot::plot_fields(&fields_png, &title, &points)?;
    print!("{}", table(&points));
    println!(
        "wrote {}, {} and {}",
        csv.display(),
        png.display(),
        fields_png.display()
    );
    Ok(ExitCode::SUCCESS)
}

/// One row of accuracy.csv (numbers formatted as they always were: `{:e}`, time `{:.6}`).
#[derive(Serialize)]
struct CsvRow<'a> {
    scene: &'a str,
    refine: usize,
    method: &'a str,
    tol: String,
    iterations: usize,
    eta: String,
    time_s: String,
    error_reference: String,
    error_exact: String,
    error_displacement: String,
    error_velocity_avg: String,
    error_force_avg: String,
    error_energy: String,
    error_contact_force: String,
}

fn write_csv(
    path: &std::path::Path,
    scene: &str,
    refine: usize,
    points: &[Point],
) -> anyhow::Result<()> {
    let mut w = csv::Writer::from_path(path)?;
    for p in points {
        w.serialize(CsvRow {
            scene,
            refine,
            method: p.method,
            tol: p.tol.map_or(String::new(), |t| format!("{t:e}")),
            iterations: p.iterations,
            eta: format!("{:e}", p.eta),
            time_s: format!("{:.6}", p.time_s),
            error_reference: format!("{:e}", p.error_reference),
            error_exact: p.error_exact.map_or(String::new(), |e| format!("{e:e}")),
            error_displacement: field(p, |c| c.rel_diff_displacement),
            error_velocity_avg: field(p, |c| c.rel_diff_velocity_avg),
            error_force_avg: field(p, |c| c.rel_diff_force),
            error_energy: field(p, |c| c.rel_diff_energy),
            error_contact_force: field(p, |c| c.rel_diff_contact_force),
        })?;
    }
    w.flush()?;
    Ok(())
}

/// One field's error of a point, `{:e}`, empty for the reference.
fn field(p: &Point, pick: impl Fn(&Comparison) -> f64) -> String {
    p.fields
        .as_ref()
        .map_or(String::new(), |f| format!("{:e}", pick(f)))
}

fn table(points: &[Point]) -> String {
    let mut t = column_table([
        "method",
        "tol",
        "iterations",
        "eta",
        "time_s",
        "err_ref",
        "err_exact",
        "err_u",
        "err_v_avg",
        "err_F_avg",
        "err_E",
        "err_contact",
    ]);
    for p in points {
        t.add_row(
            [
                p.method.to_string(),
                p.tol.map_or("-".to_string(), |t| format!("{t:.0e}")),
                p.iterations.to_string(),
                format!("{:.2e}", p.eta),
                format!("{:.3}", p.time_s),
                format!("{:.3e}", p.error_reference),
                p.error_exact
                    .map_or("-".to_string(), |e| format!("{e:.3e}")),
            ]
            .into_iter()
            .chain(p.fields.as_ref().map_or_else(
                || vec!["-".to_string(); 5],
                |f| {
                    [
                        f.rel_diff_displacement,
                        f.rel_diff_velocity_avg,
                        f.rel_diff_force,
                        f.rel_diff_energy,
                        f.rel_diff_contact_force,
                    ]
                    .map(|e| format!("{e:.2e}"))
                    .to_vec()
                },
            )),
        );
    }
    format!("{}\n", t.trim_fmt())
}
