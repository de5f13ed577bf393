//! `lopin stress`: the numerical stability stress suite (core `stress`), one row per case
//! (iterations, η, max energy ratio, min gap against the law's bound, verdict); exit status 1 if
//! any case fails. Cases run one after the other and every finished row is printed at once.

use std::process::ExitCode;

use clap::Args;
use lopin_core::stress::{self, StressOutcome};

#[derive(Debug, Args)]
pub struct StressArgs {
    /// Run only the CI set (the default runs the longer full set).
    #[arg(long)]
    quick: bool,
    /// Run only the cases of this family (k, mu, contrast, dt, long, friction, gap, impact,
    /// degenerate).
    #[arg(long)]
    group: Option<String>,
    /// Print the table as Markdown (for the README).
    #[arg(long)]
    markdown: bool,
}

pub fn stress(args: &StressArgs) -> anyhow::Result<ExitCode> {
    let mut cases = if args.quick {
        stress::quick()
    } else {
        stress::full()
    };
    if let Some(g) = &args.group {
        cases.retain(|c| c.group == g);
        anyhow::ensure!(!cases.is_empty(), "--group {g}: no such family of cases");
    }
    if args.markdown {
        println!("| case | dofs | steps | iterations | eta | max E/(E0+W) | reference max E/(E0+W) | min gap / bound (m) | time s | verdict |");
        println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|");
    } else {
        println!(
            "{:<46} {:>6} {:>6} {:>6} {:>9} {:>12} {:>12} {:>19} {:>7}  verdict",
            "case",
            "dofs",
            "steps",
            "iter",
            "eta",
            "max E ratio",
            "ref E ratio",
            "min gap / bound",
            "time s"
        );
    }
    let mut failed = 0;
    for case in &cases {
        let row = match case.run() {
            Ok(o) => {
                if !o.ok {
                    failed += 1;
                }
                format_row(&o, args.markdown)
            }
            Err(e) => {
                failed += 1;
                format!("{:<46} FAIL: {e}", case.name)
            }
        };
        println!("{row}");
    }
    println!("{} cases, {} failed", cases.len(), failed);
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

fn format_row(o: &StressOutcome, markdown: bool) -> String {
    let gap = o.min_gap.map_or("-".to_string(), |g| {
        format!("{g:.2e} / -{:.1e}", o.penetration_bound)
    });
    let reference = o
        .reference_energy_ratio
        .map_or("-".to_string(), |r| format!("{r:.9}"));
    if markdown {
        format!(
            "| {} | {} | {} | {} | {:.1e} | {:.9} | {} | {} | {:.2} | {} |",
            o.name,
            o.dofs,
            o.steps,
            o.iterations,
            o.eta,
            o.max_energy_ratio,
            reference,
            gap,
            o.wall_s,
            o.verdict
        )
    } else {
        format!(
            "{:<46} {:>6} {:>6} {:>6} {:>9.2e} {:>12.9} {:>12} {:>19} {:>7.2}  {}",
            o.name,
            o.dofs,
            o.steps,
            o.iterations,
            o.eta,
            o.max_energy_ratio,
            reference,
            gap,
            o.wall_s,
            o.verdict
        )
    }
}
