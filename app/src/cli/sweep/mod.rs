//! `lopin sweep`: a parametric study over one interface parameter with warm starts (METHOD §8),
//! records written per finished value, `--resume`, a cold baseline or comparison, a table or one
//! JSON object, and the two PNG figures; run.json in the sweep directory, and with `--rerun`
//! a recording with each value's fields and its quantities on the `parameter` timeline.
//!
//! The driver is three steps: [`plan`] (the options checked into a plan: parameter, values,
//! predictor, mode, directory, the header with the fingerprints of the resolved scene and
//! settings), [`values`] (solving each value warm or cold, resuming from the values that pass
//! [`records::Store::verify`], saving each record) and [`outputs`] (run.json, table,
//! JSON, figures).

mod outputs;
mod plan;
pub mod records;
mod values;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use lopin_core::window_choice::Task;

use super::outputs::RerunArgs;
use super::setup::{prepare, SceneArgs};
use plan::{ParamValues, Plan, PredictorArg};
use records::Store;

/// Options of `lopin sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The parameter and its values: NAME=START:STOP:STEP or NAME=V1,V2,… (NAME: f, gap, v0, t0, a0, preload, duration).
    #[arg(long, value_parser = plan::parse_param)]
    pub param: ParamValues,
    /// Directory for the per-value records, the state files and the figures
    /// (default out/sweep-SCENE-PARAM).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Solve every value from scratch (the baseline).
    #[arg(long, conflicts_with = "compare_cold")]
    pub cold: bool,
    /// Run the warm sweep and, for each value, the cold solve too.
    #[arg(long)]
    pub compare_cold: bool,
    /// Start state of each value: `previous` (the converged state of the previous value), `linear`
    /// (extrapolate the two previous) or `smooth` (extrapolate their time-filtered change).
    #[arg(long, value_enum, default_value_t = PredictorArg::Previous)]
    pub predictor: PredictorArg,
    /// Continue the sweep stored in --out from its last finished value.
    #[arg(long)]
    pub resume: bool,
    /// Re-solve every substructure at every iteration (disable skipping unchanged ones).
    #[arg(long)]
    pub no_skip: bool,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub rerun: RerunArgs,
}

pub fn sweep(args: &SweepArgs) -> anyhow::Result<ExitCode> {
    let mut prepared = prepare(&args.scene.for_task(Task::Study))?;
    let plan = Plan::new(args, &mut prepared)?;
    // distributed: rank 0 opens (and writes) the folder, then every rank reads what it holds
    let store = crate::ranks::agree(if crate::ranks::is_root() {
        Store::open(&plan.dir, &plan.header, &args.scene.scene, args.resume)
    } else {
        Ok(Store::follow(&plan.dir, &plan.header))
    })?;
    let resumed = store.verify(plan.values.len(), prepared.solver.problem(), plan.predictor);
    let finished = resumed.records.len() as f64;
    let mut seen = [
        finished,
        if crate::ranks::is_root() {
            finished
        } else {
            0.0
        },
    ];
    prepared.solver.distribution().all_sum(&mut seen);
    let ranks = prepared.solver.distribution().size() as f64;
    crate::ranks::agree(if seen[0] == ranks * seen[1] {
        Ok(())
    } else {
        Err(anyhow::anyhow!(
            "{}: the ranks see different sweep folders (rank 0 finds {} finished values): --out \
             must be on a file system every rank shares",
            plan.dir.display(),
            seen[1]
        ))
    })?;
    let records = values::solve(args, &plan, &mut prepared, &store, resumed)?;
    outputs::finish(args, &plan, &store, &records)?;
    Ok(if records.iter().all(|r| r.converged) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}
