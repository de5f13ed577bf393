//! What a sweep leaves besides its records: run.json (rewritten after every value), the two PNG
//! figures, and the table (comfy-table) or the `--json` object ([`SweepReport`]).

use lopin_core::Solver;
use serde::Serialize;

use super::plan::Plan;
use super::SweepArgs;
use crate::cli::plot;
use crate::cli::report::column_table;
use crate::cli::setup::Prepared;
use crate::cli::sweep::records::{record_name, Store, ValueRecord};
use crate::run_dir::run_json::{RunRecord, SweepFacts};
use lopin_core::counters::Instant;

/// run.json of the sweep directory.
pub struct RunJson<'a> {
    plan: &'a Plan,
    record: RunRecord,
    start: Instant,
}

impl<'a> RunJson<'a> {
    pub fn new(args: &SweepArgs, plan: &'a Plan, prepared: &Prepared) -> Self {
        RunJson {
            plan,
            record: RunRecord::new(
                "sweep",
                &args.scene.scene,
                &prepared.spec,
                &prepared.assignments,
                &prepared.solver,
            ),
            start: Instant::now(),
        }
    }

    /// Writes run.json for the finished `records`.
    pub fn write(&mut self, records: &[ValueRecord], solver: &Solver) -> anyhow::Result<()> {
        if !crate::ranks::is_root() {
            return Ok(());
        }
        let h = &self.plan.header;
        self.record.sweep = Some(SweepFacts {
            parameter: h.parameter.clone(),
            values: h.values.clone(),
            mode: h.mode.clone(),
            predictor: h.predictor.clone(),
            finished: records.len(),
            total_iterations: records.iter().map(|r| r.iterations).sum(),
        });
        self.record.files = std::iter::once("sweep.json".to_string())
            .chain(
                records
                    .iter()
                    .flat_map(|r| [record_name(r.index), r.state_file.clone()]),
            )
            .collect();
        self.record
            .set_timings(solver, self.start.elapsed().as_secs_f64(), 0.0);
        self.record.write(&self.plan.dir)
    }
}

/// The `--json` object of `lopin sweep`.
#[derive(Debug, Serialize)]
pub struct SweepReport<'a> {
    pub scene: &'a str,
    pub parameter: &'a str,
    pub mode: &'a str,
    pub predictor: &'a str,
    pub tol: f64,
    pub out: String,
    pub values: &'a [ValueRecord],
    pub total_iterations: usize,
    pub total_wall_s: f64,
    pub skipped_solves: usize,
    /// With `--compare-cold`.
    #[serde(flatten)]
    pub cold: Option<ColdTotals>,
}

/// Totals of the cold solves, and the gains of the warm sweep over them.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ColdTotals {
    pub cold_total_iterations: usize,
    pub cold_total_wall_s: f64,
    pub gain: f64,
    pub gain_wall: f64,
}

impl<'a> SweepReport<'a> {
    pub fn new(plan: &'a Plan, records: &'a [ValueRecord]) -> Self {
        let total_iterations: usize = records.iter().map(|r| r.iterations).sum();
        let total_wall_s: f64 = records.iter().map(|r| r.wall_s).sum();
        let cold_total: Option<usize> = records
            .iter()
            .map(|r| r.cold.as_ref().map(|c| c.iterations))
            .sum();
        let cold_wall: Option<f64> = records
            .iter()
            .map(|r| r.cold.as_ref().map(|c| c.wall_s))
            .sum();
        let h = &plan.header;
        SweepReport {
            scene: &h.scene,
            parameter: &h.parameter,
            mode: plan.mode.name(),
            predictor: &h.predictor,
            tol: h.tol,
            out: plan.dir.display().to_string(),
            values: records,
            total_iterations,
            total_wall_s,
            skipped_solves: records.iter().map(|r| r.skipped_solves).sum(),
            cold: cold_total.zip(cold_wall).map(|(ct, cw)| ColdTotals {
                cold_total_iterations: ct,
                cold_total_wall_s: cw,
                gain: ct as f64 / total_iterations as f64,
                gain_wall: cw / total_wall_s,
            }),
        }
    }

    /// The table of values, then the totals.
    pub fn text(&self) -> String {
        let mut t = column_table([
            self.parameter,
            "it",
            "it_cold",
            "eta",
            "time_s",
            "cold_s",
            "peak_Fn_N",
            "max_slip_m",
            "E_end_J",
            "skipped",
        ]);
        for r in self.values {
            let (ci, cw) = r.cold.as_ref().map_or(("-".into(), "-".into()), |c| {
                (c.iterations.to_string(), format!("{:.3}", c.wall_s))
            });
            t.add_row([
                format_value(r.value),
                r.iterations.to_string(),
                ci,
                format!("{:.3e}", r.eta),
                format!("{:.3}", r.wall_s),
                cw,
                format!("{:.4e}", r.peak_normal_force),
                format!("{:.4e}", r.max_slip),
                format!("{:.4e}", r.energy_end),
                r.skipped_solves.to_string(),
            ]);
        }
        let mut out = format!("{}\n", t.trim_fmt());
        out.push_str(&format!(
            "total: {} iterations, {:.3} s, {} substructure solves skipped\n",
            self.total_iterations, self.total_wall_s, self.skipped_solves
        ));
        if let Some(c) = &self.cold {
            out.push_str(&format!(
                "cold:  {} iterations, {:.3} s; gain {:.2} in iterations, {:.2} in time\n",
                c.cold_total_iterations, c.cold_total_wall_s, c.gain, c.gain_wall
            ));
        }
        out.push_str(&format!("records and figures in {}\n", self.out));
        out
    }
}

/// The figures, then the table or the JSON object on stdout (rank 0 of a distributed sweep).
pub fn finish(
    args: &SweepArgs,
    plan: &Plan,
    store: &Store,
    records: &[ValueRecord],
) -> anyhow::Result<()> {
    if !crate::ranks::is_root() {
        return Ok(());
    }
    plot::convergence(&store.path("convergence.png"), records, plan.parameter)?;
    plot::quantities(&store.path("quantities.png"), records, plan.parameter)?;
    let report = SweepReport::new(plan, records);
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", report.text());
    }
    Ok(())
}

/// A parameter value for the table: fixed point in the usual range, exponent otherwise.
fn format_value(v: f64) -> String {
    if v == 0.0 || (1e-2..1e4).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}
