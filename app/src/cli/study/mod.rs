//! `lopin study`: a parametric study over several interface parameters (METHOD §8):
//! a grid of value lists or samples of distributions ([`lopin_core::study::design`]), each
//! parameter everywhere or in one zone of the scene (`f@ZONE`), visited along a greedy
//! nearest-neighbour path cut into `--chains` chains that run at once, each configuration
//! warm-started from the nearest one its chain solved. A parameter is given once, and either
//! everywhere or per zone (`f` with `f@ZONE` is refused: one would overwrite the other). Every
//! finished configuration is one row of `study.csv` at once, with its checksum ([`rows`]), its
//! converged state written just before in `states/` (the sweep's [`SavedStates`]);
//! `--resume` keeps every row that passes its checks, says which rows it drops and why, and
//! solves the rest, each chain seeded with the states of its kept configurations, so the rest
//! start as they would have without the stop; `study.json` holds the plan (parameters, design,
//! order) and the totals, with the statistics of every quantity ([`stats`]: a quantity that is
//! not finite somewhere is counted and named, and a warning printed); at the end the rows are
//! also written typed to `study.parquet` ([`parquet_rows`]).
//!
//! Under `mpirun -np P` ([`crate::ranks`]) the chains are dealt to the ranks (chain c on rank
//! c mod P, one chain per rank by default), each rank solving its own on threads with solvers of
//! its own (nothing is exchanged while they run). Rank 0 writes `study.csv`; rank r > 0 appends
//! its rows, synced, to `rank-r/study.csv`, which rank 0 takes into `study.csv` when every rank
//! is done (and `--resume` after a kill), so a killed distributed study loses nothing either.

mod figures;
mod parquet_rows;
mod rows;
mod stats;

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Mutex;

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::study::runner::{self, Outcome, Resumed, RunOptions};
use lopin_core::study::Predictor;
use lopin_core::study::{Chains, Design, Path, Sampling, Spread, Target};
use lopin_core::window_choice::Task;
use lopin_core::{Solution, Solver};
use serde::Serialize;

use super::setup::{build, SceneArgs};
use crate::run_dir::fingerprint;
use crate::run_dir::saved_states::SavedStates;
use rows::Rows;

/// Options of `lopin study`.
#[derive(Debug, Args)]
pub struct StudyArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// A parameter and its spread, once per parameter: NAME=START:STOP:STEP, NAME=V1,V2,…,
    /// NAME=uniform(A,B), NAME=normal(MEAN,SD) or NAME=lognormal(MU,SIGMA) (ln x ~ N(MU, SIGMA));
    /// NAME is f, gap, v0, t0, a0, preload or duration, or NAME@ZONE for one zone of the scene.
    #[arg(long, required = true)]
    pub param: Vec<String>,
    /// Draw this many samples of the spreads instead of the grid of the value lists.
    #[arg(long, allow_negative_numbers = true)]
    pub samples: Option<i64>,
    /// How samples are drawn.
    #[arg(long, value_enum, default_value_t = SamplingArg::Lhs)]
    pub sampling: SamplingArg,
    /// Seed of the draws.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Chains of the path solved at once (each with its own factorization); under mpirun they
    /// are dealt to the ranks. Default: one per rank (one without mpirun).
    #[arg(long)]
    pub chains: Option<usize>,
    /// Configurations solved together: this many chains advance iteration by iteration on one
    /// shared factorization, each linear stage solving all their right-hand sides in one pass
    /// through each substructure's factor (then --chains defaults to this many per rank).
    #[arg(long, default_value_t = 1)]
    pub batch: usize,
    /// Solve every configuration cold (the baseline).
    #[arg(long, conflicts_with = "compare_cold")]
    pub cold: bool,
    /// Solve every configuration warm and cold, reporting both iteration counts.
    #[arg(long)]
    pub compare_cold: bool,
    /// Start of a warm configuration: the nearest solved one's state; on a grid the
    /// parallelogram s_j + s_k − s_l of three solved neighbours (the change of one parameter step
    /// on the neighbouring row carried over); the projection (the affine combination of the 8
    /// nearest states closest to the new configuration's contact and boundary laws, found by
    /// local stages only); or auto (the projection on the whole interval with a dissipative
    /// scheme, --rho-inf < 1, else the nearest; the report says which).
    #[arg(long, value_enum, default_value_t = PredictorArg::Auto)]
    pub predictor: PredictorArg,
    /// Directory of study.csv and study.json (default out/study-SCENE).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Keep the rows of the study in --out and solve the configurations it lacks, each chain
    /// starting from the converged states of its finished configurations.
    #[arg(long)]
    pub resume: bool,
    /// Keep no converged states in --out/states (by default one file per configuration, the
    /// size of its interface fields): a --resume then starts each chain's remaining
    /// configurations cold.
    #[arg(long)]
    pub no_states: bool,
    /// Print one JSON object on stdout instead of the summary.
    #[arg(long)]
    pub json: bool,
}

/// `--sampling`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SamplingArg {
    /// Latin hypercube.
    Lhs,
    /// Monte Carlo.
    Mc,
}

/// `--predictor`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PredictorArg {
    /// The nearest solved configuration.
    Nearest,
    /// Three solved neighbours closing a parallelogram (grids), else the nearest.
    Parallelogram,
    /// The combination of the nearest states closest to the new configuration's laws.
    Projection,
    /// The projection on the whole interval with a dissipative scheme, else the nearest.
    Auto,
}

/// `study.json`: what the study is (a resume must find the same) and, at the end, its totals.
#[derive(Debug, Clone, Serialize, serde::Deserialize, PartialEq)]
pub struct Plan {
    pub scene: String,
    /// Fingerprint of the resolved scene and settings.
    pub fingerprint: String,
    pub parameters: Vec<String>,
    pub spreads: Vec<String>,
    /// `grid`, `lhs` or `mc`.
    pub design: String,
    pub seed: Option<u64>,
    pub configurations: usize,
    pub chains: usize,
    pub mode: String,
    #[serde(default)]
    pub predictor: String,
    /// Why that predictor (`--predictor auto`).
    #[serde(default)]
    pub predictor_reason: String,
    /// Visiting order (configuration indices) and its length in scaled parameter space, against
    /// the given order's.
    pub order: Vec<usize>,
    pub path_length: f64,
    pub given_length: f64,
}

/// The totals of a study.
#[derive(Debug, Clone, Serialize)]
pub struct Totals {
    pub configurations: usize,
    pub converged: usize,
    pub iterations: usize,
    pub cold_iterations: Option<usize>,
    pub wall_s: f64,
    /// Configurations solved together (`--batch`).
    pub batch: usize,
    /// Bytes of the converged states kept per chain (f32).
    pub state_bytes: Vec<usize>,
    /// Statistics of every quantity over the configurations.
    pub statistics: Vec<stats::Statistics>,
    /// Standardized regression coefficients (sampled studies): one row per parameter, one
    /// column per quantity.
    pub regression: Option<Vec<[f64; 6]>>,
    /// The figures written.
    pub figures: Vec<String>,
}

/// What every rank knows of a study before it runs: the problem, the design, its path cut into
/// chains, the plan and the folder.
struct Setup {
    problem: lopin_core::Problem,
    settings: lopin_core::Settings,
    design: Design,
    chains: Chains,
    predictor: Predictor,
    plan: Plan,
    dir: PathBuf,
    /// run.json: the scene, its parameter values and the settings, as a run's (the explorer
    /// rebuilds the problem from it when it opens the folder).
    record: crate::run_dir::run_json::RunRecord,
}

/// Reads the options and the scene into a [`Setup`]; `ranks` is the number of ranks started.
fn setup(args: &StudyArgs, ranks: usize) -> anyhow::Result<Setup> {
    let built = build(&args.scene.for_task(Task::Study))?;
    let (problem, settings) = (built.problem, built.settings);
    let mut axes = Vec::new();
    for p in &args.param {
        let (name, spread) = p.split_once('=').with_context(|| {
            format!("--param must look like f=0:0.5:0.05 or f@ZONE=normal(0.3,0.05) (got `{p}`)")
        })?;
        let target = Target::parse(name, &problem).with_context(|| format!("--param {p}"))?;
        let spread = Spread::parse(spread).with_context(|| format!("--param {p}"))?;
        if axes
            .iter()
            .any(|(t, _): &(Target, Spread)| t.label == target.label)
        {
            anyhow::bail!("--param {p}: `{}` is given twice", target.label);
        }
        // the same parameter everywhere and in one zone: whichever is set later would overwrite
        // the other's value in that zone
        if let Some((other, _)) = axes.iter().find(|(t, _)| {
            t.parameter == target.parameter && t.zone.is_some() != target.zone.is_some()
        }) {
            let (zoned, global) = if target.zone.is_some() {
                (&target.label, &other.label)
            } else {
                (&other.label, &target.label)
            };
            anyhow::bail!(
                "--param {p}: `{global}` (every interface) and `{zoned}` (one zone) move the same \
                 parameter in that zone, one value overwriting the other: give `{global}` alone, \
                 or one `{}@ZONE` per zone",
                target.parameter.name()
            );
        }
        axes.push((target, spread));
    }
    let spreads: Vec<String> = axes.iter().map(|(_, s)| s.describe()).collect();
    let design = match args.samples {
        None => Design::grid(axes).context("--param")?,
        Some(n) if n <= 0 => anyhow::bail!("--samples: must be positive, got {n}"),
        Some(n) => {
            let sampling = match args.sampling {
                SamplingArg::Lhs => Sampling::LatinHypercube,
                SamplingArg::Mc => Sampling::MonteCarlo,
            };
            Design::sample(axes, n as usize, sampling, args.seed).context("--param")?
        }
    };
    // every configuration checked against the problem before anything is written
    {
        let mut p = problem.clone();
        for (i, point) in design.points.iter().enumerate() {
            for (t, &x) in design.targets.iter().zip(point) {
                t.apply(&mut p, x)
                    .with_context(|| format!("--param: configuration {i}, {} = {x:e}", t.label))?;
            }
        }
    }
    if args.batch == 0 {
        anyhow::bail!("--batch: must be at least 1");
    }
    let count = args.chains.unwrap_or(ranks * args.batch);
    if count == 0 {
        anyhow::bail!("--chains: must be at least 1");
    }
    if count < ranks {
        anyhow::bail!(
            "--chains: {count} chain(s) for {ranks} ranks would leave ranks idle: give at least \
             {ranks} (the default is one per rank)"
        );
    }
    let path = Path::greedy(&design.points);
    let chains = Chains::split(&path, count);
    // each chain on a rank holds a solve of its own at once: admitted together
    let per_rank = chains.0.len().div_ceil(ranks.max(1));
    let source = lopin_core::scene::source_label(&args.scene.scene);
    lopin_core::scene::admission::admit_copies(
        &built.spec,
        &source,
        args.scene.shape(&built.spec),
        per_rank,
    )
    .map_err(anyhow::Error::from)?;
    let whole = settings.window.is_none_or(|w| w >= problem.time.steps);
    let (predictor, predictor_reason) = match args.predictor {
        PredictorArg::Nearest => (Predictor::Nearest, "--predictor nearest"),
        PredictorArg::Parallelogram => (Predictor::Parallelogram, "--predictor parallelogram"),
        PredictorArg::Projection => (Predictor::Projection, "--predictor projection"),
        PredictorArg::Auto => Predictor::auto(whole, problem.scheme.rho_inf),
    };
    let plan = Plan {
        scene: built.spec.name.clone(),
        fingerprint: crate::run_dir::fingerprint::of_run(
            &built.spec,
            &built.assignments,
            &settings,
        )
        .to_string(),
        parameters: design.targets.iter().map(|t| t.label.clone()).collect(),
        spreads,
        design: match (args.samples, args.sampling) {
            (None, _) => "grid".into(),
            (Some(_), SamplingArg::Lhs) => "lhs".into(),
            (Some(_), SamplingArg::Mc) => "mc".into(),
        },
        seed: args.samples.map(|_| args.seed),
        configurations: design.points.len(),
        chains: chains.0.len(),
        mode: if args.cold {
            "cold"
        } else if args.compare_cold {
            "compare-cold"
        } else {
            "warm"
        }
        .into(),
        predictor: predictor.name().into(),
        predictor_reason: predictor_reason.into(),
        order: path.order.clone(),
        path_length: path.length,
        given_length: Path::given(&design.points).length,
    };
    let dir = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("out/study-{}", plan.scene)));
    let record = crate::run_dir::run_json::RunRecord::of_problem(
        "study",
        &args.scene.scene,
        &built.spec,
        &built.assignments,
        &problem,
        &settings,
    );
    Ok(Setup {
        problem,
        settings,
        design,
        chains,
        predictor,
        plan,
        dir,
        record,
    })
}

/// Folder of a study's converged states, one file per configuration.
pub const STATES_DIR: &str = "states";

/// The file of configuration `i`'s converged state in [`STATES_DIR`].
pub fn state_name(i: usize) -> String {
    format!("{STATES_DIR}/config-{i:04}.state")
}

/// The converged states of the study `plan` in `dir` (every rank writes its own chains').
fn saved_states(dir: &std::path::Path, plan: &Plan) -> anyhow::Result<SavedStates> {
    let states = dir.join(STATES_DIR);
    std::fs::create_dir_all(&states).with_context(|| format!("creating {}", states.display()))?;
    Ok(SavedStates::new(
        dir,
        fingerprint::of_json("study plan", plan),
    ))
}

pub fn study(args: &StudyArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    let world = crate::ranks::current();
    let (rank, size) = world.as_ref().map_or((0, 1), |r| (r.rank(), r.size()));
    let Setup {
        problem,
        settings,
        design,
        chains,
        predictor,
        plan,
        dir,
        record,
    } = crate::ranks::agree(setup(args, size))?;
    // rank 0 opens study.csv (taking in the rows of ranks a killed run left), then says which
    // configurations are finished; every other rank opens its own rows
    let opened = if rank == 0 {
        Rows::open(&dir, &plan, &design, args.resume).and_then(|mut rows| {
            rows::absorb_ranks(&dir, &mut rows, &plan, &design, args.resume)?;
            record.write(&dir)?;
            Ok(Some(rows))
        })
    } else {
        Ok(None)
    };
    let mut opened = crate::ranks::agree(opened)?;
    // what the resume found wrong with the rows (whatever --json says: on stderr)
    for line in opened.iter_mut().flat_map(Rows::take_report) {
        eprintln!("{line}");
    }
    let mut done: Vec<f64> = (0..design.points.len())
        .map(|i| f64::from(u8::from(opened.as_ref().is_some_and(|r| r.has(i)))))
        .collect();
    if let Some(w) = &world {
        w.all_sum(&mut done);
    }
    let done: Vec<bool> = done.iter().map(|&x| x > 0.0).collect();
    let kept = done.iter().filter(|&&d| d).count();
    let rows = match opened {
        Some(rows) => Ok(rows),
        None => Rows::open(&rows::rank_dir(&dir, rank), &plan, &design, false),
    };
    let rows = Mutex::new(crate::ranks::agree(rows)?);
    let mine: Vec<usize> = (0..chains.0.len()).filter(|c| c % size == rank).collect();
    let my_chains = Chains(mine.iter().map(|&c| chains.0[c].clone()).collect());
    if !args.json && rank == 0 {
        eprintln!(
            "study of {} configurations ({}), {} chain(s){}{}; path {:.3} against {:.3} in the given order; start: {} ({})",
            design.points.len(),
            plan.design,
            plan.chains,
            if size > 1 {
                format!(" on {size} ranks")
            } else {
                String::new()
            },
            if kept > 0 {
                format!(", {kept} kept from {}", dir.display())
            } else {
                String::new()
            },
            plan.path_length,
            plan.given_length,
            plan.predictor,
            plan.predictor_reason
        );
    }
    let make = || Solver::new(problem.clone(), settings);
    // None: --no-states
    let states = (!args.no_states)
        .then(|| saved_states(&dir, &plan))
        .transpose()?;
    let write_error: Mutex<Option<anyhow::Error>> = Mutex::new(None);
    let finished = |mut o: Outcome, solution: &Solution| -> lopin_core::Result<()> {
        let state = &solution.state;
        o.chain = mine[o.chain];
        // the state first: a row is the configuration's commit point
        let saved = states
            .as_ref()
            .map_or(Ok(()), |s| s.save(&state_name(o.index), state).map(drop));
        let mut r = rows.lock().unwrap_or_else(|p| p.into_inner());
        if let Err(e) = saved.and_then(|()| r.append(&design, &o)) {
            let msg = format!("{e:#}");
            *write_error.lock().unwrap_or_else(|p| p.into_inner()) = Some(e);
            return Err(lopin_core::LopinError::setting("out", msg));
        }
        if !args.json {
            eprintln!(
                "  [{}{}/{}] {} → {} iterations{}",
                if size > 1 {
                    format!("rank {rank}: ")
                } else {
                    String::new()
                },
                if rank == 0 {
                    r.done().len()
                } else {
                    r.done().len() + kept
                },
                design.points.len(),
                describe_point(&design, o.index),
                o.iterations,
                o.start
                    .map(|s| format!(" from {}", describe_point(&design, s)))
                    .unwrap_or_else(|| " (cold)".into())
                    + &o.start_residual
                        .map(|(a, b)| format!(", projected (start residual {a:.1e} → {b:.1e})"))
                        .unwrap_or_default()
            );
        }
        Ok(())
    };
    let options = RunOptions {
        cold: args.cold,
        compare_cold: args.compare_cold,
        predictor,
        batch: args.batch,
    };
    let resumed_state = |i: usize| match states.as_ref()?.load(&state_name(i), None, &problem) {
        Ok(state) => Some(state),
        Err(u) => {
            eprintln!(
                "{}: {}: configuration {i} is kept, the configurations after it start from \
                     another",
                u.path.display(),
                u.reason
            );
            None
        }
    };
    let resumed = Resumed {
        done: &|i| done[i],
        state: &resumed_state,
    };
    let result = runner::run(&make, &design, &my_chains, options, resumed, &finished);
    let mut rows = rows.into_inner().unwrap_or_else(|p| p.into_inner());
    let ran = match write_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some(e) => Err(e.context(format!("{}: writing the study", dir.display()))),
        None => result.map_err(anyhow::Error::from).with_context(|| {
            format!(
                "{}: the study stopped (every configuration finished is kept in {}; --resume \
                 continues)",
                plan.scene,
                dir.display()
            )
        }),
    };
    // every rank is done (or failed): rank 0 takes the other ranks' rows in
    let ran = crate::ranks::agree(ran);
    let mut state_bytes = vec![0.0; chains.0.len()];
    for (&c, &b) in mine.iter().zip(ran.as_deref().unwrap_or(&[])) {
        state_bytes[c] = b as f64;
    }
    if let Some(w) = &world {
        w.all_sum(&mut state_bytes);
    }
    if rank != 0 {
        return ran.map(|_| ExitCode::SUCCESS);
    }
    rows::absorb_ranks(&dir, &mut rows, &plan, &design, true)?;
    for line in rows.take_report() {
        eprintln!("{line}");
    }
    ran?;
    let state_bytes: Vec<usize> = state_bytes.iter().map(|&b| b as usize).collect();
    let outcomes = rows.done();
    let totals = Totals {
        configurations: outcomes.len(),
        converged: outcomes.iter().filter(|o| o.converged).count(),
        iterations: outcomes.iter().map(|o| o.iterations).sum(),
        cold_iterations: outcomes
            .iter()
            .map(|o| o.cold_iterations)
            .sum::<Option<usize>>(),
        wall_s: start.elapsed().as_secs_f64(),
        batch: args.batch,
        state_bytes,
        statistics: stats::statistics(outcomes),
        regression: design
            .sampled
            .then(|| stats::regression(&design, outcomes))
            .flatten(),
        figures: Vec::new(),
    };
    for line in stats::warnings(&totals.statistics) {
        eprintln!("{line}");
    }
    let mut totals = totals;
    let mut by_index = outcomes.to_vec();
    by_index.sort_by_key(|o| o.index);
    totals.figures = write_figures(&dir, &design, &by_index, &totals.statistics)?;
    let table = dir.join("study.parquet");
    parquet_rows::write(&table, &design, &by_index)
        .with_context(|| format!("{}: writing", table.display()))?;
    rows.finish(&plan, &totals)?;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&serde_json::json!({
                "plan": plan, "totals": totals, "dir": dir.display().to_string()
            }))?
        );
    } else {
        println!(
            "{} configurations, {} converged, {} iterations{}, {:.1} s; states kept: {} per chain; \
             {}",
            totals.configurations,
            totals.converged,
            totals.iterations,
            totals
                .cold_iterations
                .map(|c| format!(" (cold: {c}, ratio {:.3})", totals.iterations as f64 / c.max(1) as f64))
                .unwrap_or_default(),
            totals.wall_s,
            totals
                .state_bytes
                .iter()
                .map(|&b| lopin_core::estimate::bytes(b))
                .collect::<Vec<_>>()
                .join(", "),
            dir.join("study.csv").display()
        );
    }
    Ok(if totals.converged == totals.configurations {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// `(f = 0.3, gap = 2e-6)`.
fn describe_point(design: &Design, i: usize) -> String {
    let parts: Vec<String> = design
        .targets
        .iter()
        .zip(&design.points[i])
        .map(|(t, x)| format!("{} = {x:.4e}", t.label))
        .collect();
    format!("({})", parts.join(", "))
}

/// The study's figures and `sensitivities.csv` from its rows in index order; returns the file
/// names written.
fn write_figures(
    dir: &std::path::Path,
    design: &Design,
    sorted: &[Outcome],
    statistics: &[stats::Statistics],
) -> anyhow::Result<Vec<String>> {
    let mut written = Vec::new();
    let mut put = |name: &str, r: anyhow::Result<()>| -> anyhow::Result<()> {
        r.with_context(|| format!("{}: writing", dir.join(name).display()))?;
        written.push(name.to_string());
        Ok(())
    };
    put(
        "quantities.png",
        figures::quantities(&dir.join("quantities.png"), design, sorted),
    )?;
    if design.targets.len() >= 2 {
        put(
            "map.png",
            figures::map(&dir.join("map.png"), design, sorted),
        )?;
    }
    if design.sampled {
        put(
            "histograms.png",
            figures::histograms(&dir.join("histograms.png"), sorted, statistics),
        )?;
    }
    let sens = stats::sensitivities(design, sorted);
    if !sens.is_empty() {
        put(
            "sensitivities.png",
            figures::sensitivities(&dir.join("sensitivities.png"), design, &sens),
        )?;
        let mut w = csv::Writer::from_path(dir.join("sensitivities.csv"))
            .with_context(|| format!("{}: writing", dir.join("sensitivities.csv").display()))?;
        let mut head = vec![
            "from".to_string(),
            "to".into(),
            "parameter".into(),
            "at".into(),
        ];
        head.extend(
            lopin_core::study::Quantities::NAMES
                .iter()
                .map(|(n, _)| format!("d_{n}")),
        );
        w.write_record(&head)?;
        for s in &sens {
            let mut r = vec![
                s.from.to_string(),
                s.to.to_string(),
                design.targets[s.parameter].label.clone(),
                s.at.to_string(),
            ];
            r.extend(s.derivative.iter().map(f64::to_string));
            w.write_record(&r)?;
        }
        w.flush()?;
        written.push("sensitivities.csv".into());
    }
    Ok(written)
}
