//! `lopin bench --batch 1,2,4,8`: studies solved B configurations at a time on one
//! factorization ([`lopin_core::study::batched`]) against one configuration at a time. For each
//! refinement and study (the 11-value friction sweep f = 0:0.5:0.05, the 121-configuration grid
//! f × gap = 0:20 µm in 2 µm steps), at the study settings of the scene (one-step windows with
//! contact): the wall time of one chain solved one configuration at a time (B = 1, the sweep's
//! way), then for each B > 1 the wall time of B chains in lanes and of the same B chains on
//! threads with solvers of their own, and the largest difference of iterations between the two
//! (the same configurations from the same starts). Ratios are taken within one run; the table
//! (comfy-table) is printed at the end, and written as JSON with `--json`.

use anyhow::Context;
use lopin_core::counters::Instant;
use lopin_core::study::runner::{self, Outcome, RunOptions};
use lopin_core::study::{Design, Spread, Target};
use lopin_core::window_choice::Task;
use lopin_core::{Problem, Settings, Solver};

use super::report::column_table;
use super::setup::problem_for;

/// One row of the table.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BatchRow {
    pub scene: String,
    pub refine: usize,
    pub dofs: usize,
    pub study: String,
    pub configurations: usize,
    pub batch: usize,
    /// Iterations of all configurations (lanes).
    pub iterations: usize,
    /// Wall time of the study in lanes (B = 1: one chain, one configuration at a time).
    pub wall_s: f64,
    /// `wall_s` against B = 1.
    pub ratio: f64,
    /// Wall time of the same chains on threads, each with a solver of its own (B > 1).
    pub threads_s: Option<f64>,
    /// Largest difference of a configuration's iterations between lanes and threads.
    pub iteration_difference: Option<usize>,
}

/// The studies benchmarked, by name.
const STUDIES: [(&str, &str, Option<&str>); 2] = [
    ("sweep", "0:0.5:0.05", None),
    ("grid", "0:0.5:0.05", Some("0:20e-6:2e-6")),
];

/// Runs the table for `scene` at `refines`, for the studies named in `studies` and the batch
/// sizes `batches`; writes the rows as JSON to `json` if given.
pub fn bench_batches(
    scene: &str,
    refines: &[usize],
    studies: &[String],
    batches: &[usize],
    json: Option<&std::path::Path>,
) -> anyhow::Result<()> {
    if batches.contains(&0) {
        anyhow::bail!("--batch: batch sizes must be at least 1");
    }
    for s in studies {
        if !STUDIES.iter().any(|(name, _, _)| name == s) {
            anyhow::bail!("--studies: `{s}` is not one of sweep, grid");
        }
    }
    let mut table = column_table([
        "scene",
        "refine",
        "dofs",
        "study",
        "configs",
        "B",
        "iterations",
        "wall_s",
        "vs_B1",
        "threads_s",
        "d_iter",
    ]);
    let mut rows = Vec::new();
    for &refine in refines {
        let (problem, settings) = problem_for(scene, refine, Task::Study)?;
        for (name, f, gap) in STUDIES
            .iter()
            .filter(|(n, _, _)| studies.iter().any(|s| s == n))
        {
            let mut axes = vec![(Target::parse("f", &problem)?, Spread::parse(f)?)];
            if let Some(g) = gap {
                axes.push((Target::parse("gap", &problem)?, Spread::parse(g)?));
            }
            let design = Design::grid(axes).context("design")?;
            let one = timed(&problem, settings, &design, 1, 1)?;
            eprintln!("refine {refine}, {name}, one at a time: {:.2} s", one.1);
            for &batch in batches {
                let (lanes, threads) = if batch == 1 {
                    (one.clone(), None)
                } else {
                    let lanes = timed(&problem, settings, &design, batch, batch)?;
                    let threads = timed(&problem, settings, &design, batch, 1)?;
                    (lanes, Some(threads))
                };
                let difference = threads.as_ref().map(|(t, _)| {
                    t.iter()
                        .zip(&lanes.0)
                        .map(|(a, b)| a.iterations.abs_diff(b.iterations))
                        .max()
                        .unwrap_or(0)
                });
                let row = BatchRow {
                    scene: problem.name.clone(),
                    refine,
                    dofs: problem.dof_count(),
                    study: name.to_string(),
                    configurations: design.points.len(),
                    batch,
                    iterations: lanes.0.iter().map(|o| o.iterations).sum(),
                    wall_s: lanes.1,
                    ratio: lanes.1 / one.1,
                    threads_s: threads.as_ref().map(|t| t.1),
                    iteration_difference: difference,
                };
                eprintln!("refine {refine}, {name}, B = {batch}: {:.2} s", row.wall_s);
                table.add_row([
                    row.scene.clone(),
                    refine.to_string(),
                    row.dofs.to_string(),
                    row.study.clone(),
                    row.configurations.to_string(),
                    batch.to_string(),
                    row.iterations.to_string(),
                    format!("{:.2}", row.wall_s),
                    format!("{:.2}", row.ratio),
                    row.threads_s.map_or("-".into(), |t| format!("{t:.2}")),
                    row.iteration_difference
                        .map_or("-".into(), |d| d.to_string()),
                ]);
                rows.push(row);
            }
        }
    }
    super::bench::print_table(&table, &rows, json)
}

/// The outcomes (in configuration order) and the wall time of `design` cut into `chains` and
/// solved `batch` at a time.
fn timed(
    problem: &Problem,
    settings: Settings,
    design: &Design,
    chains: usize,
    batch: usize,
) -> anyhow::Result<(Vec<Outcome>, f64)> {
    let start = Instant::now();
    let out = runner::run_gathered(
        &|| Solver::new(problem.clone(), settings),
        design,
        chains,
        RunOptions::warm(batch),
    )?;
    let wall = start.elapsed().as_secs_f64();
    Ok((out, wall))
}
