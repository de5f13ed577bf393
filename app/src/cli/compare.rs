//! `lopin compare`: LATIN and the monolithic reference on the same scene and options, and the
//! relative differences of nodal velocities and step-averaged interface forces, and of the
//! quantities the undamped rule's alternating mode cannot touch: displacements, step-averaged
//! velocities, total energy and contact normal forces (`lopin_judge::compare`).

use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::{post, Solver};
use lopin_judge::compare::compare;
use serde::Serialize;

use super::reference::{MonolithicReport, ReferenceRun};
use super::report::{Latin, Rows, RunReport, SolveReport};
use super::setup::{build, SceneArgs};

/// Options of `lopin compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn compare_cmd(args: &CompareArgs) -> anyhow::Result<ExitCode> {
    let built = build(&args.scene)?;
    let start = Instant::now();
    let mut solver =
        Solver::new(built.problem.clone(), built.settings).context("setting up the solver")?;
    solver.add_setup_time(built.build_s);
    let solution = solver.solve(None)?;
    let latin_s = built.build_s + start.elapsed().as_secs_f64();
    let summary = post::summary(&solver, &solution);
    let latin = RunReport::new(&built.spec, &solver, &solution, &summary, latin_s)
        .with_windows(&built.windows);
    let reference = ReferenceRun::solve(built.spec.name.clone(), built.problem, built.build_s)?;
    let c = compare(
        &solver,
        &solution,
        &reference.reference,
        &reference.solution,
    );
    if args.json {
        let out = CompareReport {
            scene: built.spec.name.clone(),
            rel_diff_velocity: c.rel_diff_velocity,
            rel_diff_force: c.rel_diff_force,
            max_velocity: c.max_velocity,
            max_force: c.max_force,
            rel_diff_displacement: c.rel_diff_displacement,
            rel_diff_velocity_avg: c.rel_diff_velocity_avg,
            rel_diff_energy: c.rel_diff_energy,
            rel_diff_contact_force: c.rel_diff_contact_force,
            worst_force_at: c.describe_worst_force(&solver),
            latin: latin.report(),
            reference: reference.report(),
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        let mut rows = Rows::default();
        rows.row(
            "LATIN",
            format!(
                "{} iterations, eta {:.2e}, eta smooth {}, {:.3} s",
                solution.iterations,
                solution.eta,
                solution
                    .eta_smooth
                    .map_or_else(|| "-".to_string(), |e| format!("{e:.2e}")),
                latin_s
            ),
        );
        rows.row(
            "reference",
            format!(
                "{} contact sweeps, {:.3} s",
                reference.solution.sweeps,
                reference.time_s()
            ),
        );
        rows.row(
            "rel_diff_velocity",
            format!(
                "{:.3e} (max |v| {:.4e} m/s)",
                c.rel_diff_velocity, c.max_velocity
            ),
        );
        rows.row(
            "rel_diff_force",
            format!("{:.3e} (max |F| {:.4e} N)", c.rel_diff_force, c.max_force),
        );
        rows.row("  largest at", c.describe_worst_force(&solver));
        rows.row(
            "rel_diff_displacement",
            format!("{:.3e}", c.rel_diff_displacement),
        );
        rows.row(
            "rel_diff_velocity_avg",
            format!("{:.3e}  (step-averaged)", c.rel_diff_velocity_avg),
        );
        rows.row(
            "rel_diff_energy",
            format!("{:.3e}  (kinetic + strain)", c.rel_diff_energy),
        );
        rows.row(
            "rel_diff_contact_force",
            format!(
                "{:.3e}  (step-averaged normal force)",
                c.rel_diff_contact_force
            ),
        );
        print!("{rows}");
    }
    Ok(if solution.converged {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The `--json` object of `lopin compare`: the differences, then both reports.
#[derive(Debug, Serialize)]
struct CompareReport {
    scene: String,
    rel_diff_velocity: f64,
    rel_diff_force: f64,
    max_velocity: f64,
    max_force: f64,
    rel_diff_displacement: f64,
    rel_diff_velocity_avg: f64,
    rel_diff_energy: f64,
    rel_diff_contact_force: f64,
    worst_force_at: String,
    latin: SolveReport<Latin>,
    reference: SolveReport<MonolithicReport>,
}
