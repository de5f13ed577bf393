//! `lopin run`: one solve with a progress bar, then a summary table or one JSON object.

use std::process::ExitCode;

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lopin_core::counters::Instant;
use lopin_core::{post, Control};

use super::report::RunReport;
use super::setup::{prepare, SceneArgs};

/// Options of `lopin run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &RunArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    let mut prepared = prepare(&args.scene)?;
    let solver = &mut prepared.solver;
    let max_iter = solver.settings().max_iter as u64;
    let bar = ProgressBar::new(max_iter);
    bar.set_style(
        ProgressStyle::with_template("{spinner} iteration {pos} [{elapsed_precise}] {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let tol = solver.settings().tol;
    let solution = solver.solve_with(None, &mut |r| {
        bar.set_position(r.iteration as u64);
        bar.set_message(format!(
            "eta = {:.3e} (tol {tol:.0e}), steps {}..{}",
            r.eta, r.window_start, r.window_end
        ));
        Control::Continue
    })?;
    bar.finish_and_clear();
    let summary = post::summary(solver, &solution);
    let report = RunReport::new(
        &prepared.spec,
        solver,
        &solution,
        &summary,
        start.elapsed().as_secs_f64(),
    );
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report.to_json())?);
    } else {
        print!("{}", report.table());
    }
    Ok(if solution.converged {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
