//! `lopin bench`: setup time, time per iteration and the time of the triangular solves alone
//! on `two-blocks` at refine 1 and 2, so the overhead ratio (iteration / triangular solves) is
//! visible; with `--batch`, the study table of [`super::bench_batch`]; with `--background`, the
//! explorer's background study in lanes ([`super::bench_background`]); with `--accuracy`, the
//! time-to-accuracy table of [`super::bench_accuracy`]. Ratios are measured within one run; the table (comfy-table) is printed at the end.

use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::scene::spec::SolverSpec;
use lopin_core::window_choice::{Task, WindowRequest};

use super::report::column_table;
use super::setup::{prepare, SceneArgs};

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Scene to benchmark.
    #[arg(long, default_value = "two-blocks")]
    scene: String,
    /// Refinements to run.
    #[arg(long, value_delimiter = ',', default_value = "1,2")]
    refine: Vec<usize>,
    /// LATIN iterations timed per refinement.
    #[arg(long, default_value_t = 10)]
    iterations: usize,
    /// Disable the check for substructures whose inputs did not change (on by default).
    #[arg(long)]
    no_skip: bool,
    /// Instead of the iteration table: studies solved this many configurations at a time on one
    /// factorization, against one at a time and against the same chains on threads (e.g.
    /// 1,2,4,8).
    #[arg(long, value_delimiter = ',')]
    batch: Vec<usize>,
    /// The studies of --batch: `sweep` (f = 0:0.5:0.05, 11 values) and `grid` (that × gap =
    /// 0:20e-6:2e-6, 121 configurations).
    #[arg(long, value_delimiter = ',', default_value = "sweep,grid")]
    studies: Vec<String>,
    /// Instead of the iteration table: the explorer's background study (the friction grid
    /// around the scene's value) solved this many values at a time on lanes that share the
    /// factorizations, against one at a time (e.g. 1,4).
    #[arg(long, value_delimiter = ',', conflicts_with = "batch")]
    background: Vec<usize>,
    /// Also write the --batch, --background or --accuracy table's rows as JSON to this file.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// Instead of the iteration table: the time to a velocity error of 1e-3 and 1e-6 of each
    /// case (two-blocks, two-blocks-ramp, two-blocks --refine 2, granular-small, granular-poly)
    /// under the default settings, on two-step windows, with double-precision factors, on the
    /// whole interval and on the whole interval at ρ∞ = 0.5; and of the friction sweep f =
    /// 0:0.5:0.1, every value cold, warm one at a time and in four lanes.
    #[arg(long, conflicts_with_all = ["batch", "background"])]
    accuracy: bool,
    /// With --accuracy: only the cases of these scenes.
    #[arg(long, value_delimiter = ',')]
    cases: Vec<String>,
}

pub fn bench(args: &BenchArgs) -> anyhow::Result<ExitCode> {
    if args.accuracy {
        super::bench_accuracy::bench_accuracy(&args.cases, args.json.as_deref())?;
        return Ok(ExitCode::SUCCESS);
    }
    if !args.background.is_empty() {
        super::bench_background::bench_background(
            &args.scene,
            &args.refine,
            &args.background,
            args.json.as_deref(),
        )?;
        return Ok(ExitCode::SUCCESS);
    }
    if !args.batch.is_empty() {
        super::bench_batch::bench_batches(
            &args.scene,
            &args.refine,
            &args.studies,
            &args.batch,
            args.json.as_deref(),
        )?;
        return Ok(ExitCode::SUCCESS);
    }
    let mut table = column_table([
        "scene",
        "refine",
        "dofs",
        "subs",
        "setup_s",
        "iter_ms",
        "trisolve_ms",
        "overhead",
    ]);
    for &refine in &args.refine {
        let sargs = SceneArgs {
            scene: args.scene.clone(),
            friction: None,
            set: Vec::new(),
            solver: SolverSpec {
                tol: Some(1e-300),
                max_iter: Some(args.iterations),
                window: Some(WindowRequest::Whole),
                ..SolverSpec::default()
            },
            refine,
            split: 1,
            task: Task::Single,
        };
        let mut prepared = prepare(&sargs)?;
        let solver = &mut prepared.solver;
        let mut settings = *solver.settings();
        settings.skip_unchanged = !args.no_skip;
        solver.set_settings(settings)?;
        let setup = solver.counters().setup_s;
        let start = Instant::now();
        let sol = solver.solve(None)?;
        let iter_s = start.elapsed().as_secs_f64() / sol.iterations as f64;
        let tri_s = triangular_solves(solver);
        let p = solver.problem();
        table.add_row([
            p.name.clone(),
            refine.to_string(),
            p.dof_count().to_string(),
            p.subs.len().to_string(),
            format!("{setup:.3}"),
            format!("{:.2}", 1e3 * iter_s),
            format!("{:.2}", 1e3 * tri_s),
            format!("{:.2}", iter_s / tri_s),
        ]);
        eprintln!("refine {refine}: done");
    }
    println!("{}", table.trim_fmt());
    Ok(ExitCode::SUCCESS)
}

/// Wall time of the triangular solves of one iteration alone: N solves per substructure, the
/// substructures in parallel exactly as in the linear stage (median of 5 repetitions).
fn triangular_solves(solver: &lopin_core::Solver) -> f64 {
    let p = solver.problem();
    let n = p.time.steps;
    let mut times: Vec<f64> = (0..5)
        .map(|_| {
            let start = Instant::now();
            let threads = std::thread::available_parallelism().map_or(1, |t| t.get());
            std::thread::scope(|scope| {
                for t in 0..threads {
                    scope.spawn(move || {
                        for (i, sub) in p.subs.iter().enumerate().skip(t).step_by(threads) {
                            let factor = solver.factor(i);
                            let mut scratch = factor.scratch();
                            let mut x: Vec<f64> =
                                (0..sub.ndof()).map(|i| (i as f64).sin()).collect();
                            for _ in 0..n {
                                factor.solve_in_place(&mut x, &mut scratch);
                            }
                            std::hint::black_box(&x);
                        }
                    });
                }
            });
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[2]
}

/// Prints a benchmark's table and writes its rows as JSON to `json` if given.
pub(super) fn print_table(
    table: &comfy_table::Table,
    rows: &impl serde::Serialize,
    json: Option<&std::path::Path>,
) -> anyhow::Result<()> {
    println!("{}", table.trim_fmt());
    if let Some(path) = json {
        std::fs::write(path, serde_json::to_string_pretty(rows)?)
            .with_context(|| format!("{}: writing", path.display()))?;
    }
    Ok(())
}
