//! Solving the values of a sweep: each value set through [`lopin_core::Parameter`], started cold
//! or from the predictor's state (METHOD §8), its cold solve with `--compare-cold`, its record
//! and state saved at once (the resume point), run.json updated, the recording fed; a resumed
//! sweep restarts after its last value that passed its checks, from the stored states: a
//! damaged value is reported on stderr (file and reason) and recomputed with all after it.

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use lopin_core::counters::Instant;
use lopin_core::{post, Control};

use super::outputs::RunJson;
use super::plan::{Mode, Plan};
use super::SweepArgs;
use crate::cli::outputs::{describe, FLUSH_TIMEOUT};
use crate::cli::setup::Prepared;
use crate::cli::sweep_store::{state_name, ColdRecord, Resumed, Store, ValueRecord};
use crate::record::Recorder;

/// Solves the values not in `resumed` yet and returns all the records.
pub fn solve(
    args: &SweepArgs,
    plan: &Plan,
    prepared: &mut Prepared,
    store: &Store,
    resumed: Resumed,
) -> anyhow::Result<Vec<ValueRecord>> {
    let (parameter, values, header) = (plan.parameter, &plan.values, &plan.header);
    let Resumed {
        mut records,
        mut chain,
        damage,
    } = resumed;
    let root = crate::ranks::is_root();
    if let Some(d) = damage.as_ref().filter(|_| root) {
        let last = values.len().saturating_sub(1);
        eprintln!(
            "{}: {}: recomputing {}",
            d.path.display(),
            d.reason,
            if d.from == last {
                format!("value {last}")
            } else {
                format!("values {} … {last}", d.from)
            }
        );
    }
    let mut run_json = RunJson::new(args, plan, prepared);
    let solver = &mut prepared.solver;
    run_json.write(&records, solver)?;
    let mut recorder = if !root {
        None
    } else {
        args.rerun.open(
        &prepared.spec.name,
        &describe(
            "sweep",
            &prepared.spec,
            solver,
            &format!(
                "Sweep of `{}` over {:?} ({}, predictor {}). Each value is one index of the \
                 `parameter` timeline: its fields per time step, and its quantities under `sweep/`.",
                header.parameter,
                header.values,
                plan.mode.name(),
                header.predictor
            ),
        ),
    )?
    };
    let recording = solver.distribution().any(recorder.is_some());
    if let Some(rec) = &recorder {
        // values finished before a resume: their quantities (their fields were not stored)
        for r in &records {
            log_value(rec, r)?;
        }
    }
    if root && (!records.is_empty() || damage.is_some()) {
        eprintln!(
            "resuming {}: {} of {} values finished",
            plan.dir.display(),
            records.len(),
            values.len()
        );
    }
    let bar = if root {
        ProgressBar::new(values.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_position(records.len() as u64);
    for index in records.len()..values.len() {
        let value = values[index];
        solver
            .set_parameter(parameter, value)
            .with_context(|| format!("{} = {value:?}", parameter.name()))?;
        let start_state = if plan.mode == Mode::Cold {
            None
        } else {
            // a sweep is a study of one parameter along one chain, in the order of its values
            chain.start(&[value], solver).state
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
        });
        let finished = records.len();
        let mut sol = sol.with_context(|| {
            format!(
                "{} = {value:?}: solving (the {finished} values before it are kept in {})",
                parameter.name(),
                plan.dir.display()
            )
        })?;
        if let Some(e) = record_error {
            return Err(e.context("recording the iterations"));
        }
        let wall_s = t.elapsed().as_secs_f64();
        let skipped_solves = solver.counters().skipped_solves();
        let s = post::summary(solver, &sol);
        let cold = if plan.mode == Mode::CompareCold {
            let t = Instant::now();
            let c = solver
                .solve(None)
                .with_context(|| format!("{} = {value:?}: the cold solve", parameter.name()))?;
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
        // distributed: rank 0 writes the whole state
        solver.gather_to_root(&mut sol);
        store.save(&record, &sol.state)?;
        let mut fields = Vec::new();
        if recording {
            fields = post::history(solver, &sol);
            post::gather_history(solver, &mut fields);
        }
        if let Some(rec) = recorder.as_mut() {
            rec.solution(
                solver,
                &sol,
                &fields,
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
        run_json.write(&records, solver)?;
        chain.converged(index, &[value], &sol.state);
        bar.inc(1);
    }
    bar.finish_and_clear();
    run_json.write(&records, solver)?;
    if let Some(rec) = recorder.take() {
        let target = rec.close(FLUSH_TIMEOUT)?;
        eprintln!("recording: {}", target.describe());
    }
    Ok(records)
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
