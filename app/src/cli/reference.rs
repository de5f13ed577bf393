//! `lopin reference`: the monolithic reference solve of a scene (core `monolithic`), reported in
//! the shape of `lopin run` with `solver: "monolithic"`.

use std::process::ExitCode;

use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::post::Summary;
use lopin_core::Problem;
use lopin_reference::monolithic::{MonoSolution, Monolithic};
use serde::Serialize;

use super::report::{Rows, SolveReport, Stages};
use super::setup::{build, SceneArgs};
use crate::run_dir::run_json::ProblemFacts;

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

    /// The `--json` object, in the shape of `lopin run`'s.
    pub fn report(&self) -> SolveReport<MonolithicReport> {
        let p = self.reference.problem();
        let (assembled, free) = self.reference.dofs();
        let sol = &self.solution;
        let c = self.reference.controls;
        SolveReport {
            scene: self.scene.clone(),
            solver: "monolithic",
            sizes: ProblemFacts::of(p),
            method: MonolithicReport {
                assembled_dofs: assembled,
                free_dofs: free,
                contact_pairs: self.reference.assembled().pairs.len(),
                settings: MonolithicSettings {
                    contact_tol: c.tol,
                    max_sweeps: c.max_sweeps,
                },
                max_sweeps_per_step: sol.max_sweeps,
            },
            // one factorization of the assembled operator, no macro problem
            factorizations: 1,
            macro_dofs: None,
            peak_memory_bytes: super::report::peak_memory_bytes(),
            preload: None,
            iterations: sol.sweeps,
            eta: sol.contact_change,
            // no LATIN indicator: both carry the contact iteration's last relative change
            eta_smooth: Some(sol.contact_change),
            converged: true,
            wall_s: self.time_s() + self.post_s,
            stages_s: Stages {
                setup: self.setup_s,
                local: sol.contact_s,
                linear: sol.solve_s,
                macro_s: None,
                post: self.post_s,
            },
            energy: (&self.summary).into(),
            contact: (&self.summary).into(),
        }
    }

    /// The summary rows.
    pub fn rows(&self) -> Rows {
        let p = self.reference.problem();
        let (assembled, free) = self.reference.dofs();
        let sol = &self.solution;
        let mut rows = Rows::default();
        rows.row("scene", format!("{} (monolithic reference)", self.scene));
        rows.row(
            "dofs (assembled, free)",
            format!("{} ({assembled}, {free})", p.dof_count()),
        );
        rows.row("contact pairs", self.reference.assembled().pairs.len());
        rows.row(
            "steps x dt",
            format!("{} x {:.3e} s", p.time.steps, p.time.dt),
        );
        rows.row(
            "contact sweeps",
            format!(
                "{} (max {} per step, last change {:.1e})",
                sol.sweeps, sol.max_sweeps, sol.contact_change
            ),
        );
        rows.row("time setup", format!("{:.3} s", self.setup_s));
        rows.row("time solves", format!("{:.3} s", sol.solve_s));
        rows.row("time contact", format!("{:.3} s", sol.contact_s));
        rows.row("time post", format!("{:.3} s", self.post_s));
        rows.summary(&self.summary);
        rows
    }
}

/// What only a reference report holds: the assembled sizes and the contact solver's controls.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MonolithicReport {
    pub assembled_dofs: usize,
    pub free_dofs: usize,
    pub contact_pairs: usize,
    pub settings: MonolithicSettings,
    pub max_sweeps_per_step: usize,
}

/// The contact solver's controls of a reference report.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct MonolithicSettings {
    pub contact_tol: f64,
    pub max_sweeps: usize,
}

pub fn reference(args: &ReferenceArgs) -> anyhow::Result<ExitCode> {
    let run = ReferenceRun::new(&args.scene)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&run.report())?);
    } else {
        print!("{}", run.rows());
    }
    Ok(ExitCode::SUCCESS)
}
