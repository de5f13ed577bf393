//! `lopin estimate`: what a solve of a scene will hold and cost, without solving it: memory of
//! the interface fields (METHOD §11), operators, factorizations and homogenized operators, the
//! number of distinct factorizations, and the measured time of one iteration's triangular solves.

use clap::Args;
use lopin_core::estimate::Estimate;
use lopin_core::Solver;
use serde::Serialize;

use super::setup::{build, SceneArgs};

/// Options of `lopin estimate`.
#[derive(Debug, Args)]
pub struct EstimateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object instead of lines.
    #[arg(long)]
    pub json: bool,
}

pub fn estimate(args: &EstimateArgs) -> anyhow::Result<std::process::ExitCode> {
    let built = build(&args.scene)?;
    let solver = Solver::new(built.problem, built.settings)?;
    let e = Estimate::of_solver(&solver);
    if args.json {
        let json = EstimateReport {
            estimate: &e,
            total_bytes: e.total_bytes(),
            setup_s: solver.counters().setup_s + built.build_s,
            macro_dofs: solver.macro_problem().map(|mp| mp.size),
            homogenized_operators: solver.macro_problem().map(|mp| mp.classes.count()),
        };
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        println!("{} ({})", built.spec.name, args.scene.scene);
        for line in e.lines() {
            println!("  {line}");
        }
        if let Some(mp) = solver.macro_problem() {
            println!(
                "  macro problem: {} dofs, {} homogenized operators, factor of L {} values",
                mp.size,
                mp.classes.count(),
                mp.factor_nnz()
            );
        }
        println!(
            "  setup: build {:.2} s, factorizations{} {:.2} s",
            built.build_s,
            if solver.macro_problem().is_some() {
                " and macro problem"
            } else {
                ""
            },
            solver.counters().setup_s
        );
    }
    Ok(std::process::ExitCode::SUCCESS)
}

/// The `--json` object: the core's estimate and what only the solver knows.
#[derive(Serialize)]
struct EstimateReport<'a> {
    #[serde(flatten)]
    estimate: &'a Estimate,
    total_bytes: usize,
    setup_s: f64,
    /// Two-scale only.
    #[serde(skip_serializing_if = "Option::is_none")]
    macro_dofs: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    homogenized_operators: Option<usize>,
}
