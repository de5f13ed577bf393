//! `lopin reference`: the monolithic reference solve of a scene (core `monolithic`), reported in
//! the shape of `lopin run` with `solver: "monolithic"`.

use std::process::ExitCode;

use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::monolithic::{MonoSolution, Monolithic};
use lopin_core::post::Summary;
use lopin_core::Problem;
use serde_json::{json, Value};

use super::report::{contact_json, energy_json, row, summary_rows};
use super::setup::{build, SceneArgs};

/// Options of `lopin reference`.
#[derive(Debug, Args)]
pub struct ReferenceArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// A finished reference solve and its timings.
pub struct ReferenceRun {
    pub scene: String,
    pub reference: Monolithic,
    pub solution: MonoSolution,
    pub summary: Summary,
    /// Load/build seconds plus the reference's own setup.
    pub setup_s: f64,
    /// Seconds of the time march.
    pub solve_s: f64,
    /// Seconds of post-processing.
    pub post_s: f64,
}

impl ReferenceRun {
    /// Builds and solves.
    pub fn new(args: &SceneArgs) -> anyhow::Result<Self> {
        let built = build(args)?;
        Self::solve(built.spec.name, built.problem, built.build_s)
    }

    /// Solves a built problem (`build_s`: the seconds it took to build).
    pub fn solve(scene: String, problem: Problem, build_s: f64) -> anyhow::Result<Self> {
        let reference = Monolithic::new(problem)?;
        let clock = Instant::now();
        let solution = reference.solve()?;
        let solve_s = clock.elapsed().as_secs_f64();
        let clock = Instant::now();
        let summary = reference.summary(&solution);
        Ok(Self {
            scene,
            setup_s: build_s + reference.setup_s(),
            reference,
            solution,
            summary,
            solve_s,
            post_s: clock.elapsed().as_secs_f64(),
        })
    }

    /// Total wall time of setup and march.
    pub fn time_s(&self) -> f64 {
        self.setup_s + self.solve_s
    }

    pub fn to_json(&self) -> Value {
        let p = self.reference.problem();
        let (assembled, free) = self.reference.dofs();
        let sol = &self.solution;
        let c = self.reference.controls;
        json!({
            "scene": self.scene,
            "solver": "monolithic",
            "substructures": p.subs.len(),
            "interfaces": p.interfaces.len(),
            "contact_interfaces": p.contact_count(),
            "dofs": p.dof_count(),
            "assembled_dofs": assembled,
            "free_dofs": free,
            "contact_pairs": self.reference.assembled().pairs.len(),
            "steps": p.time.steps,
            "dt": p.time.dt,
            "settings": { "contact_tol": c.tol, "max_sweeps": c.max_sweeps },
            // one factorization of the assembled operator, no macro problem
            "factorizations": 1,
            "macro_dofs": null,
            "peak_memory_bytes": super::report::peak_memory_bytes(),
            "iterations": sol.sweeps,
            "max_sweeps_per_step": sol.max_sweeps,
            "eta": sol.contact_change,
            "converged": true,
            "wall_s": self.time_s() + self.post_s,
            "stages_s": {
                "setup": self.setup_s,
                "local": sol.contact_s,
                "linear": sol.solve_s,
                "post": self.post_s,
            },
            "energy": energy_json(&self.summary),
            "contact": contact_json(&self.summary),
        })
    }

    pub fn table(&self) -> String {
        let p = self.reference.problem();
        let (assembled, free) = self.reference.dofs();
        let sol = &self.solution;
        let mut out = String::new();
        out.push_str(&row(
            "scene",
            format!("{} (monolithic reference)", self.scene),
        ));
        out.push_str(&row(
            "dofs (assembled, free)",
            format!("{} ({assembled}, {free})", p.dof_count()),
        ));
        out.push_str(&row(
            "contact pairs",
            self.reference.assembled().pairs.len().to_string(),
        ));
        out.push_str(&row(
            "steps x dt",
            format!("{} x {:.3e} s", p.time.steps, p.time.dt),
        ));
        out.push_str(&row(
            "contact sweeps",
            format!(
                "{} (max {} per step, last change {:.1e})",
                sol.sweeps, sol.max_sweeps, sol.contact_change
            ),
        ));
        out.push_str(&row("time setup", format!("{:.3} s", self.setup_s)));
        out.push_str(&row("time solves", format!("{:.3} s", sol.solve_s)));
        out.push_str(&row("time contact", format!("{:.3} s", sol.contact_s)));
        out.push_str(&row("time post", format!("{:.3} s", self.post_s)));
        out.push_str(&summary_rows(&self.summary));
        out
    }
}

pub fn reference(args: &ReferenceArgs) -> anyhow::Result<ExitCode> {
    let run = ReferenceRun::new(&args.scene)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&run.to_json())?);
    } else {
        print!("{}", run.table());
    }
    Ok(ExitCode::SUCCESS)
}
