//! `lopin estimate`: what a solve of a scene will hold and cost, without solving it. First,
//! always and at once for any size, the footprint counted from the scene alone (sizes, memory of
//! the interface fields of METHOD §11, operators, estimated factorizations) against this
//! machine's memory (a request that cannot fit is refused with the numbers); then, for problems
//! of at most [`MEASURED_DOFS`] dofs or with `--measure`, the problem is built and factorized for
//! the exact memory, the number of distinct factorizations and the measured time of one
//! iteration's triangular solves.

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::estimate::Estimate;
use lopin_core::Solver;
use serde::Serialize;

use super::setup::{admitted, build_admitted, SceneArgs};

/// Largest problem measured (built and factorized) without `--measure`.
pub const MEASURED_DOFS: usize = 200_000;

/// Options of `lopin estimate`.
#[derive(Debug, Args)]
pub struct EstimateArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// Print one JSON object instead of lines.
    #[arg(long)]
    pub json: bool,
    /// Also build and factorize a problem of more than 200,000 dofs for the exact memory and
    /// the measured iteration time (smaller problems always are).
    #[arg(long)]
    pub measure: bool,
    /// Also deal the built problem to P ranks of a distributed run (METIS on the substructure
    /// graph) and print what each rank holds and sends per iteration.
    #[arg(long, value_name = "P")]
    pub ranks: Option<usize>,
}

pub fn estimate(args: &EstimateArgs) -> anyhow::Result<std::process::ExitCode> {
    // under mpirun: rank 0 answers for the ranks started (as `--ranks P`), the others wait
    let world = crate::ranks::current();
    if world.as_ref().is_some_and(|r| r.rank() > 0) {
        return Ok(std::process::ExitCode::SUCCESS);
    }
    let wanted_ranks = args.ranks.or(world.map(|r| r.size()));
    // counted from the scene alone: answers at once however large, refuses what cannot fit
    let start = Instant::now();
    let counted = admitted(&args.scene)?;
    let fp = counted.footprint;
    if !args.json {
        println!("{} ({})", counted.spec.name, args.scene.scene);
        for line in fp.lines() {
            println!("  counted from the scene: {line}");
        }
        println!("  fits this machine's memory");
    }
    if fp.dofs > MEASURED_DOFS && !args.measure {
        if args.json {
            let json = EstimateReport {
                footprint: &fp,
                measured: None,
                ranks: None,
                window_steps: None,
            };
            println!("{}", serde_json::to_string_pretty(&json)?);
        } else {
            println!(
                "  (more than {MEASURED_DOFS} dofs: add --measure to build and factorize it for \
                 the exact memory and the time per iteration)"
            );
        }
        return Ok(std::process::ExitCode::SUCCESS);
    }
    let source = counted.source.clone();
    let built = build_admitted(counted, start)?;
    let solver = Solver::new(built.problem, built.settings)
        .with_context(|| format!("{source}: setting up the solver"))?;
    let e = Estimate::of_solver(&solver);
    let window = built.windows.window.unwrap_or(solver.problem().time.steps);
    let ranks = wanted_ranks
        .map(|p| {
            lopin_core::distributed::rank_assignment::assign(
                solver.problem(),
                &solver.classes().of,
                p,
            )
            .map_err(|r| anyhow::anyhow!("{source}: --ranks {p}: {r}"))
        })
        .transpose()?;
    if args.json {
        let json = EstimateReport {
            footprint: &fp,
            measured: Some(Measured {
                estimate: &e,
                total_bytes: e.total_bytes(),
                setup_s: solver.counters().setup_s + built.build_s,
                macro_dofs: solver.macro_problem().map(|mp| mp.size),
                homogenized_operators: solver.macro_problem().map(|mp| mp.classes.count()),
            }),
            ranks: ranks.as_ref(),
            window_steps: Some(window),
        };
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        for line in e.lines() {
            println!("  built and measured: {line}");
        }
        if let Some(mp) = solver.macro_problem() {
            println!(
                "  macro problem: {} dofs, {} homogenized operators, factor of L {} values",
                mp.size,
                mp.classes.count(),
                mp.factor_nnz()
            );
        }
        println!(
            "  setup: build {:.2} s, factorizations{} {:.2} s",
            built.build_s,
            if solver.macro_problem().is_some() {
                " and macro problem"
            } else {
                ""
            },
            solver.counters().setup_s
        );
        if let Some(a) = &ranks {
            print_ranks(a, window);
        }
    }
    Ok(std::process::ExitCode::SUCCESS)
}

/// The table of `--ranks P`: per rank its substructures, dofs, factorizations, cut interfaces
/// and the bytes it sends per iteration over a window of `window` steps.
fn print_ranks(a: &lopin_core::distributed::rank_assignment::RankAssignment, window: usize) {
    println!(
        "  {} ranks (METIS on the substructure graph): largest rank {:.3}x the mean dofs, {} \
         interfaces cut between ranks",
        a.ranks,
        a.dof_imbalance(),
        a.cut_interfaces()
    );
    let mut t = super::report::column_table([
        "rank",
        "substructures",
        "dofs",
        "factorizations",
        "cut interfaces",
        "sent per iteration",
    ]);
    for (r, l) in a.loads.iter().enumerate() {
        t.add_row([
            r.to_string(),
            l.substructures.to_string(),
            l.dofs.to_string(),
            l.factorizations.to_string(),
            l.cut_interfaces.to_string(),
            lopin_core::scene::admission::bytes(l.bytes_sent(window) as u64),
        ]);
    }
    println!("{t}");
}

/// The `--json` object: the footprint counted from the scene, and what building and
/// factorizing measured (absent for problems over [`MEASURED_DOFS`] without `--measure`).
#[derive(Serialize)]
struct EstimateReport<'a> {
    footprint: &'a lopin_core::scene::admission::Footprint,
    #[serde(skip_serializing_if = "Option::is_none")]
    measured: Option<Measured<'a>>,
    /// `--ranks P`: the substructures dealt to ranks.
    #[serde(skip_serializing_if = "Option::is_none")]
    ranks: Option<&'a lopin_core::distributed::rank_assignment::RankAssignment>,
    /// Steps of the window the bytes sent per iteration are counted over.
    #[serde(skip_serializing_if = "Option::is_none")]
    window_steps: Option<usize>,
}

/// The core's estimate of a factorized solver and what only the solver knows.
#[derive(Serialize)]
struct Measured<'a> {
    #[serde(flatten)]
    estimate: &'a Estimate,
    total_bytes: usize,
    setup_s: f64,
    /// Two-scale only.
    #[serde(skip_serializing_if = "Option::is_none")]
    macro_dofs: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    homogenized_operators: Option<usize>,
}
