//! `lopin sweep`: a parametric study over one interface parameter with warm starts (METHOD §8),
//! records written per finished value, `--resume`, a cold baseline or comparison, a table or one
//! JSON object, and the two PNG figures; run.json in the sweep directory, and with `--rerun`
//! a recording with each value's fields and its quantities on the `parameter` timeline.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lopin_core::counters::Instant;
use lopin_core::sweep::{parse_values, Parameter, Predictor};
use lopin_core::{post, Control, InterfaceState};
use serde_json::json;

use super::outputs::{describe, RerunArgs, FLUSH_TIMEOUT};
use super::plot;
use super::setup::{prepare, SceneArgs};
use super::sweep_store::{state_name, ColdRecord, Header, Store, ValueRecord};
use crate::record::Recorder;
use crate::run_dir::run_json::RunRecord;

/// Options of `lopin sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The parameter and its values: NAME=START:STOP:STEP or NAME=V1,V2,… (NAME: f, gap, v0).
    #[arg(long)]
    pub param: String,
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
    /// Start state of each value: `previous` (the converged state of the previous value; measured
    /// best) or `linear` (extrapolate the two previous).
    #[arg(long, default_value = "previous")]
    pub predictor: String,
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
    let (name, values) = args.param.split_once('=').ok_or_else(|| {
        anyhow::anyhow!(
            "--param must look like f=0:0.5:0.05 or f=0.1,0.2 (got `{}`)",
            args.param
        )
    })?;
    let parameter = Parameter::parse(name)?;
    let values = parse_values(values)?;
    let predictor = Predictor::parse(&args.predictor)?;
    let mut prepared = prepare(&args.scene)?;
    let solver = &mut prepared.solver;
    let mut settings = *solver.settings();
    settings.skip_unchanged = !args.no_skip;
    solver.set_settings(settings)?;
    let mode = if args.cold {
        "cold"
    } else if args.compare_cold {
        "compare-cold"
    } else {
        "warm"
    };
    let header = Header {
        scene: prepared.spec.name.clone(),
        parameter: parameter.name().into(),
        values: values.clone(),
        mode: mode.into(),
        predictor: predictor.name().into(),
        tol: settings.tol,
        k: settings.k,
        mu: settings.mu,
        refine: args.scene.refine,
        split: args.scene.split,
        skip_unchanged: settings.skip_unchanged,
    };
    let dir = args.out.clone().unwrap_or_else(|| {
        PathBuf::from(format!("out/sweep-{}-{}", header.scene, header.parameter))
    });
    let (store, mut records) = Store::open(&dir, &header, args.resume)?;
    let sweep_start = Instant::now();
    let mut run_record = RunRecord::new("sweep", &args.scene.scene, &prepared.spec, solver);
    let write_run_json =
        |run_record: &mut RunRecord, records: &[ValueRecord], solver: &lopin_core::Solver| {
            run_record.sweep = Some(json!({
                "parameter": header.parameter,
                "values": header.values,
                "mode": header.mode,
                "predictor": header.predictor,
                "finished": records.len(),
                "total_iterations": records.iter().map(|r| r.iterations).sum::<usize>(),
            }));
            run_record.files = std::iter::once("sweep.json".to_string())
                .chain(records.iter().flat_map(|r| {
                    [
                        super::sweep_store::record_name(r.index),
                        r.state_file.clone(),
                    ]
                }))
                .collect();
            run_record.set_timings(solver, sweep_start.elapsed().as_secs_f64(), 0.0);
            run_record.write(&dir)
        };
    write_run_json(&mut run_record, &records, solver)?;
    let mut recorder = args.rerun.open(
        &prepared.spec.name,
        &describe(
            "sweep",
            &prepared.spec,
            solver,
            &format!(
                "Sweep of `{}` over {:?} ({mode}, predictor {}). Each value is one index of the \
                 `parameter` timeline: its fields per time step, and its quantities under `sweep/`.",
                header.parameter, header.values, header.predictor
            ),
        ),
    )?;
    if let Some(rec) = &recorder {
        // values finished before a resume: their quantities (their fields were not stored)
        for r in &records {
            log_value(rec, r)?;
        }
    }
    // the converged states the predictor extrapolates from (the last two)
    let mut history: Vec<(f64, InterfaceState)> = Vec::new();
    for r in records.iter().rev().take(2).rev() {
        history.push((r.value, store.load_state(r)?));
    }
    if !records.is_empty() {
        eprintln!(
            "resuming {}: {} of {} values finished",
            dir.display(),
            records.len(),
            values.len()
        );
    }
    let bar = ProgressBar::new(values.len() as u64);
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_position(records.len() as u64);
    for index in records.len()..values.len() {
        let value = values[index];
        parameter
            .apply(solver, value)
            .with_context(|| format!("{} = {value}", parameter.name()))?;
        let start_state = if args.cold {
            None
        } else {
            let refs: Vec<(f64, &InterfaceState)> = history.iter().map(|(v, s)| (*v, s)).collect();
            predictor.predict(&refs, value)
        };
        let t = Instant::now();
        let mut record_error = None;
        let sol = solver.solve_with(start_state.as_ref(), &mut |r| {
            bar.set_message(format!(
                "{} = {value:.4}: iteration {} eta {:.2e}",
                parameter.name(),
                r.iteration,
                r.eta
            ));
            if let (Some(rec), None) = (recorder.as_mut(), &record_error) {
                record_error = rec.iteration(r).err();
            }
            Control::Continue
        })?;
        if let Some(e) = record_error {
            return Err(e.context("recording the iterations"));
        }
        let wall_s = t.elapsed().as_secs_f64();
        let skipped_solves = solver.counters().skipped_solves();
        let s = post::summary(solver, &sol);
        let cold = if args.compare_cold {
            let t = Instant::now();
            let c = solver.solve(None)?;
            Some(ColdRecord {
                iterations: c.iterations,
                eta: c.eta,
                converged: c.converged,
                wall_s: t.elapsed().as_secs_f64(),
            })
        } else {
            None
        };
        let record = ValueRecord {
            index,
            parameter: parameter.name().into(),
            value,
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            wall_s,
            skipped_solves,
            peak_normal_force: s.peak_normal_force,
            max_slip: s.max_slip,
            energy_end: s.kinetic_end + s.strain_end,
            eta_history: sol.eta_history.clone(),
            cold,
            state_file: state_name(index),
        };
        store.save(&record, &sol.state)?;
        if let Some(rec) = recorder.as_mut() {
            rec.solution(
                solver,
                &sol,
                &post::history(solver, &sol),
                &[("parameter", index as i64)],
                args.rerun.rerun_deform,
            )?;
            log_value(rec, &record)?;
        }
        if !sol.converged {
            bar.println(format!(
                "warning: {} = {value}: not converged after {} iterations (eta {:.3e})",
                parameter.name(),
                sol.iterations,
                sol.eta
            ));
        }
        records.push(record);
        write_run_json(&mut run_record, &records, solver)?;
        history.push((value, sol.state));
        if history.len() > 2 {
            history.remove(0);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    write_run_json(&mut run_record, &records, solver)?;
    if let Some(rec) = recorder.take() {
        let target = rec.close(FLUSH_TIMEOUT)?;
        eprintln!("recording: {}", target.describe());
    }
    plot::convergence(&store.path("convergence.png"), &records, parameter.name())?;
    plot::quantities(&store.path("quantities.png"), &records, parameter.name())?;
    let total: usize = records.iter().map(|r| r.iterations).sum();
    let total_wall: f64 = records.iter().map(|r| r.wall_s).sum();
    let cold_total: Option<usize> = records
        .iter()
        .map(|r| r.cold.as_ref().map(|c| c.iterations))
        .sum();
    let cold_wall: Option<f64> = records
        .iter()
        .map(|r| r.cold.as_ref().map(|c| c.wall_s))
        .sum();
    let skipped: usize = records.iter().map(|r| r.skipped_solves).sum();
    if args.json {
        let mut out = json!({
            "scene": header.scene,
            "parameter": header.parameter,
            "mode": mode,
            "predictor": header.predictor,
            "tol": header.tol,
            "out": dir.display().to_string(),
            "values": records,
            "total_iterations": total,
            "total_wall_s": total_wall,
            "skipped_solves": skipped,
        });
        if let (Some(ct), Some(cw)) = (cold_total, cold_wall) {
            out["cold_total_iterations"] = json!(ct);
            out["cold_total_wall_s"] = json!(cw);
            out["gain"] = json!(ct as f64 / total as f64);
            out["gain_wall"] = json!(cw / total_wall);
        }
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "{:>9} {:>7} {:>7} {:>10} {:>9} {:>9} {:>12} {:>11} {:>11} {:>7}",
            parameter.name(),
            "it",
            "it_cold",
            "eta",
            "time_s",
            "cold_s",
            "peak_Fn_N",
            "max_slip_m",
            "E_end_J",
            "skipped"
        );
        for r in &records {
            let (ci, cw) = r.cold.as_ref().map_or(("-".into(), "-".into()), |c| {
                (c.iterations.to_string(), format!("{:.3}", c.wall_s))
            });
            println!(
                "{:>9} {:>7} {:>7} {:>10.3e} {:>9.3} {:>9} {:>12.4e} {:>11.4e} {:>11.4e} {:>7}",
                format_value(r.value),
                r.iterations,
                ci,
                r.eta,
                r.wall_s,
                cw,
                r.peak_normal_force,
                r.max_slip,
                r.energy_end,
                r.skipped_solves
            );
        }
        println!(
            "total: {total} iterations, {total_wall:.3} s, {skipped} substructure solves skipped"
        );
        if let (Some(ct), Some(cw)) = (cold_total, cold_wall) {
            println!(
                "cold:  {ct} iterations, {cw:.3} s; gain {:.2} in iterations, {:.2} in time",
                ct as f64 / total as f64,
                cw / total_wall
            );
        }
        println!("records and figures in {}", dir.display());
    }
    Ok(if records.iter().all(|r| r.converged) {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The quantities of one finished value on the `parameter` timeline.
fn log_value(rec: &Recorder, r: &ValueRecord) -> anyhow::Result<()> {
    rec.parameter(
        r.index,
        &[
            (r.parameter.as_str(), r.value),
            ("iterations", r.iterations as f64),
            ("eta", r.eta),
            ("peak_normal_force", r.peak_normal_force),
            ("max_slip", r.max_slip),
            ("energy_end", r.energy_end),
        ],
    )
}

/// A parameter value for the table: fixed point in the usual range, exponent otherwise.
fn format_value(v: f64) -> String {
    if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}
