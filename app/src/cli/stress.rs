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

/// Column widths of the text table (the last column, the verdict, is not padded).
const WIDTHS: [usize; 9] = [46, 6, 6, 6, 9, 12, 12, 19, 7];

fn format_row(o: &StressOutcome, markdown: bool) -> String {
    let cells = [
        o.name.clone(),
        o.dofs.to_string(),
        o.steps.to_string(),
        o.iterations.to_string(),
        format!("{:.1e}", o.eta),
        format!("{:.9}", o.max_energy_ratio),
        o.reference_energy_ratio
            .map_or("-".to_string(), |r| format!("{r:.9}")),
        o.min_gap.map_or("-".to_string(), |g| {
            format!("{g:.2e} / -{:.1e}", o.penetration_bound)
        }),
        format!("{:.2}", o.wall_s),
        o.verdict.clone(),
    ];
    if markdown {
        format!("| {} |", cells.join(" | "))
    } else {
        let mut line = format!("{:<w$}", cells[0], w = WIDTHS[0]);
        for (cell, w) in cells[1..9].iter().zip(&WIDTHS[1..]) {
            line.push_str(&format!(" {cell:>w$}"));
        }
        line.push_str("  ");
        line.push_str(&cells[9]);
        line
    }
}
