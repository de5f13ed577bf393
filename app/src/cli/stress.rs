//! `lopin stress`: the numerical stability stress suite (core `stress`), one row per case
//! (iterations, η, max energy ratio, min gap against the law's bound, verdict); exit status 1 if
//! any case fails. Cases run one after the other; every finished case is told on stderr at once,
//! the table (comfy-table, text or Markdown) follows when all are done.

use std::process::ExitCode;

use clap::{Args, ValueEnum};
use comfy_table::CellAlignment;
use lopin_judge::stress::{self, StressOutcome};

use super::report::{column_table, markdown_table};

#[derive(Debug, Args)]
pub struct StressArgs {
    /// Run only the CI set (the default runs the longer full set).
    #[arg(long)]
    quick: bool,
    /// Run only the cases of this family.
    #[arg(long, value_enum)]
    group: Option<Group>,
    /// Print the table as Markdown (for the guide).
    #[arg(long)]
    markdown: bool,
}

/// A family of stress cases (`--group`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
enum Group {
    K,
    Mu,
    Contrast,
    Dt,
    Long,
    Friction,
    Gap,
    Impact,
    Degenerate,
}

impl Group {
    /// The family's name in the suite.
    fn name(self) -> String {
        self.to_possible_value()
            .map_or_else(String::new, |v| v.get_name().to_string())
    }
}

/// The columns of the table.
const HEADER: [&str; 10] = [
    "case",
    "dofs",
    "steps",
    "iterations",
    "eta",
    "max E/(E0+W)",
    "reference max E/(E0+W)",
    "min gap / bound (m)",
    "time s",
    "verdict",
];

pub fn stress(args: &StressArgs) -> anyhow::Result<ExitCode> {
    let mut cases = if args.quick {
        stress::quick()
    } else {
        stress::full()
    };
    if let Some(g) = args.group {
        let g = g.name();
        cases.retain(|c| c.group == g);
        anyhow::ensure!(!cases.is_empty(), "--group {g}: no such family of cases");
    }
    let mut table = if args.markdown {
        markdown_table(HEADER)
    } else {
        let mut t = column_table(HEADER);
        if let Some(c) = t.column_mut(9) {
            c.set_cell_alignment(CellAlignment::Left);
        }
        t
    };
    let mut failed = 0;
    for (i, case) in cases.iter().enumerate() {
        // the row at once on stderr, the table when all are done
        let cells = match case.run() {
            Ok(o) => {
                if !o.ok {
                    failed += 1;
                }
                cells(&o)
            }
            Err(e) => {
                failed += 1;
                let mut cells = vec![String::from("-"); 10];
                cells[0].clone_from(&case.name);
                cells[9] = format!("FAIL: {e}");
                cells
            }
        };
        eprintln!("[{}/{}] {}: {}", i + 1, cases.len(), cells[0], cells[9]);
        table.add_row(cells);
    }
    println!("{}", table.trim_fmt());
    println!("{} cases, {} failed", cases.len(), failed);
    Ok(if failed == 0 {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

/// The cells of one finished case.
fn cells(o: &StressOutcome) -> Vec<String> {
    vec![
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
    ]
}
