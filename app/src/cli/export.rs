//! `lopin export RUN_DIR`: VTU files, a Rerun recording and/or the stored step fields the
//! explorer opens large runs from (`RUN_DIR/fields.bin`), from a run saved with
//! `lopin run --out RUN_DIR`, without solving again: the solver is rebuilt from run.json and
//! the fields are replayed from the stored ŝ (METHOD §6 "at convergence"). `solution.bin` is
//! checked whole before anything is written: checksum, shapes, finite values, and that it
//! belongs to run.json's scene and settings ([`RunRecord::fingerprint`]); a damaged or
//! foreign file is an error naming it.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Args;
use lopin_core::counters::Instant;

use super::outputs::{describe, RerunArgs, FLUSH_TIMEOUT};
use crate::export;
use crate::run_dir::fields_file::{self, FIELDS_BIN};
use crate::run_dir::run_json::RunRecord;

/// Options of `lopin export`.
#[derive(Debug, Args)]
pub struct ExportArgs {
    /// A run directory (made by `lopin run --out DIR`).
    pub run: PathBuf,
    /// Write one VTU file per substructure and time step, and run.pvd, to DIR.
    #[arg(long, value_name = "DIR")]
    pub vtu: Option<PathBuf>,
    /// Store every step's fields in RUN_DIR/fields.bin, as `lopin run --out DIR --fields` does,
    /// so `lopin view RUN_DIR` opens the run without its scene.
    #[arg(long)]
    pub fields: bool,
    #[command(flatten)]
    pub rerun: RerunArgs,
}

pub fn export_cmd(args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let rerun_target = args.rerun.target()?;
    anyhow::ensure!(
        args.vtu.is_some() || rerun_target.is_some() || args.fields,
        "nothing to export: give --vtu DIR, --fields, --rerun FILE.rrd or --rerun-connect ADDR"
    );
    let start = Instant::now();
    let (record, solver, solution) = RunRecord::open_run(&args.run)?;
    let history = lopin_core::post::history(&solver, &solution);
    if let Some(dir) = &args.vtu {
        let e = export::write_vtu(dir, &solver, &history)?;
        let mut r = record.clone();
        r.files = vec![export::PVD_NAME.into()];
        r.write(dir)?;
        println!(
            "vtu: {} files, {} bytes, in {}",
            e.files,
            e.bytes,
            dir.display()
        );
    }
    if args.fields {
        let bytes = fields_file::write_for_run(&args.run, &record, &solver, &solution, &history)?;
        let mut r = record.clone();
        if !r.files.iter().any(|f| f == FIELDS_BIN) {
            r.files.push(FIELDS_BIN.into());
        }
        r.write(&args.run)?;
        println!(
            "fields: {bytes} bytes in {}",
            args.run.join(FIELDS_BIN).display()
        );
    }
    if rerun_target.is_some() {
        let extra = format!(
            "Exported from the run saved in `{}` (made by `{}`).",
            args.run.display(),
            record.command.join(" ")
        );
        if let Some(mut rec) = args.rerun.open(
            &record.scene.name,
            &describe("run", &record.scene, &solver, &extra),
        )? {
            for &eta in &solution.eta_history {
                rec.eta(eta, None)?;
            }
            let steps = rec.solution(&solver, &solution, &history, &[], args.rerun.rerun_deform)?;
            let target = rec.close(FLUSH_TIMEOUT)?;
            println!("rerun: {} steps to {}", steps.steps, target.describe());
        }
    }
    println!("exported in {:.2} s", start.elapsed().as_secs_f64());
    Ok(ExitCode::SUCCESS)
}
