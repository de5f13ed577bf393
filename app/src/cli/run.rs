//! `lopin run`: one solve with a progress bar, then a summary table or one JSON object; with
//! `--out`, `--vtu`, `--rerun`/`--rerun-connect`, the run directory, the ParaView files and the
//! Rerun recording (see [`super::outputs`]). Under `mpirun` every rank solves its part; rank 0
//! prints, records and writes the run directory, every rank writes the ParaView files of its
//! substructures.

use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use lopin_core::counters::Instant;
use lopin_core::{post, scene, Control};
use serde::Serialize;

use super::checkpoint::{self, CheckpointArgs};
use super::outputs::{describe, OutputArgs, FLUSH_TIMEOUT};
use super::report::{Latin, RunReport, SolveReport};
use super::setup::{prepare, SceneArgs};
use crate::export;
use crate::run_dir::fields_file::{self, FIELDS_BIN};
use crate::run_dir::run_json::{Outcome, RunRecord};

/// Options of `lopin run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    #[command(flatten)]
    pub outputs: OutputArgs,
    #[command(flatten)]
    pub checkpoints: CheckpointArgs,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

pub fn run(args: &RunArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    crate::ranks::agree(args.outputs.check_paths())?;
    let mut prepared = prepare(&args.scene)?;
    let spec = &prepared.spec;
    let assignments = &prepared.assignments;
    let solver = &mut prepared.solver;
    let root = crate::ranks::is_root();
    let mut recorder = crate::ranks::agree(if root {
        args.outputs
            .rerun
            .open(&spec.name, &describe("run", spec, solver, ""))
    } else {
        Ok(None)
    })?;
    let recording = solver.distribution().any(recorder.is_some());
    let max_iter = solver.settings().max_iter as u64;
    let bar = if root {
        ProgressBar::new(max_iter)
    } else {
        ProgressBar::hidden()
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} iteration {pos} [{elapsed_precise}] {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let tol = solver.settings().tol;
    let mut record_error = None;
    let print = checkpoint::fingerprint_of(
        solver,
        crate::run_dir::fingerprint::of_scene(spec, assignments),
    );
    let cp = &args.checkpoints;
    let mut run = crate::ranks::agree(match &cp.restart {
        Some(dir) => checkpoint::load(dir, solver, print),
        None => solver.begin(None).map_err(anyhow::Error::from),
    })?;
    let mut observer = |it: &lopin_core::Iterate<'_>| {
        let r = it.record;
        bar.set_position(r.iteration as u64);
        bar.set_message(format!(
            "eta = {:.3e} (tol {tol:.0e}), steps {}..{}",
            r.eta, r.window_start, r.window_end
        ));
        if let (Some(rec), None) = (recorder.as_mut(), &record_error) {
            record_error = rec.iteration(r).err();
        }
        Control::Continue
    };
    while !solver.step(&mut run, &mut observer) {
        if let Some(dir) = &cp.checkpoint {
            if (run.iterations() as u64).is_multiple_of(cp.checkpoint_every) {
                checkpoint::save(dir, solver, &run, print)?;
            }
        }
        if cp.halt_after.is_some_and(|h| run.iterations() >= h) {
            bar.finish_and_clear();
            return Ok(ExitCode::from(3));
        }
    }
    bar.finish_and_clear();
    let mut solution = solver
        .conclude(run)
        .with_context(|| format!("{}: solving", scene::source_label(&args.scene.scene)))?;
    if let Some(e) = record_error {
        return Err(e.context("recording the iterations"));
    }
    let solve_wall = start.elapsed().as_secs_f64();
    let summary = post::summary(solver, &solution);

    // outputs: fields replayed once for VTU and the recording
    let t_out = Instant::now();
    let mut written = Written::default();
    let fields = args.outputs.fields;
    let mut history = if args.outputs.vtu.is_some() || recording || fields {
        post::history(solver, &solution)
    } else {
        Vec::new()
    };
    if let Some(dir) = &args.outputs.vtu {
        let e = export::write_vtu(dir, solver, &history)?;
        written.vtu = Some(VtuWritten {
            dir: dir.display().to_string(),
            files: e.files,
            bytes: e.bytes,
        });
    }
    if recording || fields {
        // distributed: the recording and the stored fields are written on rank 0 from every
        // rank's fields
        post::gather_history(solver, &mut history);
    }
    if recording || args.outputs.out.is_some() {
        // distributed: rank 0 needs the whole solution for solution.bin and the recording
        solver.gather_to_root(&mut solution);
    }
    if let Some(mut rec) = recorder.take() {
        let steps = rec.solution(
            solver,
            &solution,
            &history,
            &[],
            args.outputs.rerun.rerun_deform,
        )?;
        // closing the recording writes the file's footer: measure its size after that
        let target = rec.close(FLUSH_TIMEOUT)?;
        written.rerun = Some(RerunWritten {
            target: target.describe(),
            steps: steps.steps,
            von_mises_range_pa: [steps.von_mises.0, steps.von_mises.1],
            deform_scale: steps.deform,
            bytes: match &target {
                crate::record::Target::File(f) => Some(std::fs::metadata(f).map_or(0, |m| m.len())),
                _ => None,
            },
        });
    }
    let outputs_s = t_out.elapsed().as_secs_f64();

    let mut record = RunRecord::new("run", &args.scene.scene, spec, assignments, solver);
    record.result = Some(Outcome {
        iterations: solution.iterations,
        eta: solution.eta,
        converged: solution.converged,
        eta_history: solution.eta_history.clone(),
    });
    record.set_timings(solver, start.elapsed().as_secs_f64(), outputs_s);
    let ranks = RankFacts::gather(solver);
    if !root {
        return Ok(exit_code(solution.converged));
    }
    if let Some(dir) = &args.outputs.out {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("--out {}: creating the folder", dir.display()))?;
        let mut others = Vec::new();
        if fields {
            let t = Instant::now();
            let bytes = fields_file::write_for_run(dir, &record, solver, &solution, &history)?;
            written.fields = Some(FieldsWritten {
                file: dir.join(FIELDS_BIN).display().to_string(),
                bytes,
                seconds: t.elapsed().as_secs_f64(),
            });
            others.push(FIELDS_BIN);
        }
        record.write_with_solution(dir, &solution, &others)?;
        written.out = Some(dir.display().to_string());
    }
    if let Some(dir) = &args.outputs.vtu {
        let mut r = record.clone();
        r.files = vec![export::PVD_NAME.into()];
        r.write(dir)?;
    }

    let report = RunReport::new(spec, solver, &solution, &summary, solve_wall)
        .with_windows(&prepared.windows);
    if args.json {
        let json = RunJson {
            report: report.report(),
            outputs: written,
            ranks,
        };
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        let mut rows = report.rows();
        for r in &ranks {
            rows.row(
                format!("rank {}", r.rank),
                format!(
                    "{} substructures, {:.3} s of {:.3} s iterating in communication, peak \
                     memory {}",
                    r.substructures,
                    r.communication_s,
                    r.iterations_s,
                    lopin_core::estimate::bytes(r.peak_memory_bytes as usize)
                ),
            );
        }
        // each output as its JSON object, in the order of the keys
        if let serde_json::Value::Object(outputs) = serde_json::to_value(&written)? {
            for (what, v) in outputs {
                rows.row(format!("output {what}"), v);
            }
        }
        print!("{rows}");
    }
    Ok(exit_code(solution.converged))
}

/// 0 for a converged run, 1 otherwise.
fn exit_code(converged: bool) -> ExitCode {
    if converged {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    }
}

/// `lopin run --json`: the run's report and, when any was written, its outputs.
#[derive(Debug, Serialize)]
struct RunJson {
    #[serde(flatten)]
    report: SolveReport<Latin>,
    #[serde(skip_serializing_if = "Written::is_empty")]
    outputs: Written,
    /// Under mpirun: what each rank held and spent.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    ranks: Vec<RankFacts>,
}

/// One rank of a distributed run, as rank 0 reports it.
#[derive(Debug, Serialize)]
struct RankFacts {
    rank: usize,
    substructures: usize,
    /// Seconds of the iterations (local and linear stages).
    iterations_s: f64,
    /// Of which in exchanges and sums between ranks, waiting included.
    communication_s: f64,
    /// Peak resident memory of the rank's process.
    peak_memory_bytes: u64,
}

impl RankFacts {
    /// Every rank's facts on every rank (empty on one machine); every rank calls it.
    fn gather(solver: &lopin_core::Solver) -> Vec<Self> {
        let dist = solver.distribution();
        if dist.is_single() {
            return Vec::new();
        }
        let (p, me) = (dist.size(), dist.rank());
        let its = &solver.counters().iterations;
        // −0: the neutral element of the sum over the ranks
        let mut v = vec![-0.0; 4 * p];
        v[4 * me] = dist.sub_ranks().iter().filter(|&&r| r == me).count() as f64;
        v[4 * me + 1] = its.iter().map(|r| r.local_s + r.linear_s).sum();
        v[4 * me + 2] = its.iter().map(|r| r.comm_s).sum();
        v[4 * me + 3] = super::report::peak_memory_bytes().unwrap_or(0) as f64;
        dist.all_sum(&mut v);
        v.chunks_exact(4)
            .enumerate()
            .map(|(rank, x)| Self {
                rank,
                substructures: x[0] as usize,
                iterations_s: x[1],
                communication_s: x[2],
                peak_memory_bytes: x[3] as u64,
            })
            .collect()
    }
}

/// The outputs a run wrote (the `outputs` object).
#[derive(Debug, Default, Serialize)]
struct Written {
    #[serde(skip_serializing_if = "Option::is_none")]
    out: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    rerun: Option<RerunWritten>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vtu: Option<VtuWritten>,
    #[serde(skip_serializing_if = "Option::is_none")]
    fields: Option<FieldsWritten>,
}

impl Written {
    fn is_empty(&self) -> bool {
        self.out.is_none() && self.rerun.is_none() && self.vtu.is_none() && self.fields.is_none()
    }
}

/// The stored step fields a run wrote.
#[derive(Debug, Serialize)]
struct FieldsWritten {
    file: String,
    bytes: u64,
    /// Time to compute the stresses and write the file, s.
    seconds: f64,
}

/// The recording a run wrote.
#[derive(Debug, Serialize)]
struct RerunWritten {
    target: String,
    steps: usize,
    von_mises_range_pa: [f64; 2],
    deform_scale: f64,
    /// Size of the file (a file target only).
    #[serde(skip_serializing_if = "Option::is_none")]
    bytes: Option<u64>,
}

/// The ParaView files a run wrote.
#[derive(Debug, Serialize)]
struct VtuWritten {
    dir: String,
    files: usize,
    bytes: u64,
}
