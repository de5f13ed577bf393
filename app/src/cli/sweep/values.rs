//! Solving the values of a sweep, a study of one parameter visited along one chain by the study
//! engine ([`Visit`]): each value set through [`lopin_core::Parameter`], started cold or from the
//! predictor's state (METHOD §8), its cold solve with `--compare-cold`, its record
//! and state saved at once (the resume point), run.json updated, the recording fed; a resumed
//! sweep restarts after its last value that passed its checks, from the stored states: a
//! damaged value is reported on stderr (file and reason) and recomputed with all after it.

use std::cell::RefCell;

use anyhow::Context;
use indicatif::{ProgressBar, ProgressStyle};
use lopin_core::counters::Instant;
use lopin_core::study::runner::{Solved, Visit};
use lopin_core::study::{Design, Target};
use lopin_core::{post, Control, Solver};

use super::outputs::RunJson;
use super::plan::{Mode, Plan};
use super::SweepArgs;
use crate::cli::outputs::{describe, FLUSH_TIMEOUT};
use crate::cli::setup::Prepared;
use crate::cli::sweep::records::{state_name, ColdRecord, Resumed, Store, ValueRecord};
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
    let recorder = if !root {
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
    // a sweep is a study of one parameter visited along one chain in the order of its values
    // (its points the values themselves, which the extrapolations scale)
    let design = Design {
        targets: vec![Target {
            parameter,
            zone: None,
            label: parameter.name().into(),
        }],
        points: values.iter().map(|&v| vec![v]).collect(),
        sampled: false,
    };
    let order: Vec<usize> = (0..values.len()).collect();
    let resumed = records.len();
    let visit = Visit {
        design: &design,
        points: &design.points,
        chain: &order,
        cold: plan.mode == Mode::Cold,
        done: &|i| i < resumed,
        go_on: &|| true,
    };
    let recorder = RefCell::new(recorder);
    let record_error = RefCell::new(None);
    let sink = Sink {
        args,
        plan,
        store,
        recorder: &recorder,
        recording,
        bar: &bar,
    };
    visit.solve(
        solver,
        &mut chain,
        &mut |i, r| {
            bar.set_message(format!(
                "{} = {:.4}: iteration {} eta {:.2e}",
                parameter.name(),
                values[i],
                r.iteration,
                r.eta
            ));
            let mut error = record_error.borrow_mut();
            if let (Some(rec), None) = (recorder.borrow_mut().as_mut(), &*error) {
                *error = rec.iteration(r).err();
            }
            Control::Continue
        },
        &mut |solver, solved| {
            if let Some(e) = record_error.borrow_mut().take() {
                return Err(e.context("recording the iterations"));
            }
            records.push(sink.finish(solver, solved)?);
            run_json.write(&records, solver)?;
            bar.inc(1);
            Ok(())
        },
        &|failure| {
            let value = values[failure.index];
            let what = format!("{} = {value:?}", parameter.name());
            if failure.setting {
                anyhow::Error::new(failure.error).context(what)
            } else {
                anyhow::Error::new(failure.error).context(format!(
                    "{what}: solving (the {} values before it are kept in {})",
                    failure.index,
                    plan.dir.display()
                ))
            }
        },
    )?;
    let mut recorder = recorder.into_inner();
    bar.finish_and_clear();
    run_json.write(&records, solver)?;
    if let Some(rec) = recorder.take() {
        let target = rec.close(FLUSH_TIMEOUT)?;
        eprintln!("recording: {}", target.describe());
    }
    Ok(records)
}

/// What a sweep does with each solved value: its record (the post-processed quantities, the
/// cold solve of `--compare-cold`), its state saved (gathered onto rank 0 when distributed),
/// the recording fed, a warning when it did not converge.
struct Sink<'a> {
    args: &'a SweepArgs,
    plan: &'a Plan,
    store: &'a Store,
    recorder: &'a RefCell<Option<Recorder>>,
    recording: bool,
    bar: &'a ProgressBar,
}

impl Sink<'_> {
    /// The record of a solved value, once its state is saved and recorded.
    fn finish(&self, solver: &mut Solver, solved: &mut Solved) -> anyhow::Result<ValueRecord> {
        let (parameter, index) = (self.plan.parameter, solved.index);
        let value = self.plan.values[index];
        let sol = &mut solved.solution;
        let s = post::summary(solver, sol);
        let cold = if self.plan.mode == Mode::CompareCold {
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
            wall_s: solved.wall_s,
            skipped_solves: solved.skipped_solves,
            peak_normal_force: s.peak_normal_force,
            max_slip: s.max_slip,
            energy_end: s.kinetic_end + s.strain_end,
            eta_history: sol.eta_history.clone(),
            cold,
            state_file: state_name(index),
        };
        // distributed: rank 0 writes the whole state
        solver.gather_to_root(sol);
        self.store.save(&record, &sol.state)?;
        let mut fields = Vec::new();
        if self.recording {
            fields = post::history(solver, sol);
            post::gather_history(solver, &mut fields);
        }
        if let Some(rec) = self.recorder.borrow_mut().as_mut() {
            rec.solution(
                solver,
                sol,
                &fields,
                &[("parameter", index as i64)],
                self.args.rerun.rerun_deform,
            )?;
            log_value(rec, &record)?;
        }
        if !sol.converged {
            self.bar.println(format!(
                "warning: {} = {value}: not converged after {} iterations (eta {:.3e})",
                parameter.name(),
                sol.iterations,
                sol.eta
            ));
        }
        Ok(record)
    }
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
