//! Command-line definitions (clap) and dispatch to one module per subcommand.

mod accuracy;
mod accuracy_plot;
mod bench;
mod bench_accuracy;
mod bench_accuracy_study;
mod bench_background;
mod bench_batch;
mod checkpoint;
mod compare;
mod docs;
mod estimate;
mod export;
mod mesh;
mod mesh_granular;
mod outputs;
mod plot;
mod reference;
mod report;
mod run;
mod scaling;
mod scenes;
mod setup;
mod shell;
mod srs;
mod stress;
pub(crate) mod study;
pub(crate) mod sweep;
mod view;

use clap::{Parser, Subcommand};

/// Lopin: LATIN domain decomposition for frictional contact under shock.
#[derive(Debug, Parser)]
#[command(name = "lopin", version, about)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Open the explorer on a scene (built-in name or .toml file); `lopin` alone opens it on
    /// two-blocks.
    View(view::ViewArgs),
    /// Solve a scene (built-in name or .toml file) and print a summary.
    Run(run::RunArgs),
    /// Memory and time a solve of a scene will need, without solving it.
    Estimate(estimate::EstimateArgs),
    /// Solve a scene with the monolithic reference (no decomposition).
    Reference(reference::ReferenceArgs),
    /// Solve with LATIN and with the reference, and print their relative differences.
    Compare(compare::CompareArgs),
    /// Run time against error: LATIN at tolerances 1e-1 … 1e-8 against the reference (CSV, PNG).
    Accuracy(accuracy::AccuracyArgs),
    /// Numerical stability stress suite (adverse settings on small scenes).
    Stress(stress::StressArgs),
    /// Write VTU files or a Rerun recording from a run saved with `lopin run --out DIR`.
    Export(export::ExportArgs),
    /// Acceleration histories at probe points and their shock response spectrum (CSV, PNG),
    /// from a run saved with `lopin run --out DIR`.
    Srs(srs::SrsArgs),
    /// Parametric study with warm starts (multiresolution), resumable.
    Sweep(sweep::SweepArgs),
    /// Study over several parameters (grid or samples, per zone), chains at once, resumable.
    Study(study::StudyArgs),
    /// Time setup, iterations and triangular solves on `two-blocks` (refine 1 and 2).
    Bench(bench::BenchArgs),
    /// Iterations against the number of substructures, with and without the macro problem.
    Scaling(scaling::ScalingArgs),
    /// Gmsh meshes: read an MSH 4.1 file and report what Lopin sees in it.
    #[command(subcommand)]
    Mesh(mesh::MeshCommand),
    /// List the built-in scenes.
    Scenes,
    /// Print a built-in scene as a TOML scene file.
    ExportScene {
        /// Scene name.
        name: String,
    },
    /// Print the shell completion script of `lopin` (bash, zsh, fish, elvish, powershell).
    Completions(shell::CompletionsArgs),
    /// Print the man page of `lopin`, or write one page per command into a folder.
    Man(shell::ManArgs),
    /// Print a reference of the user guide: the scene file's keys (`scene`), its JSON schema
    /// (`schema`) or the command line (`cli`).
    Docs(docs::DocsArgs),
}

/// Runs the chosen subcommand.
pub fn dispatch(cli: Cli) -> anyhow::Result<std::process::ExitCode> {
    if let Some(r) = crate::ranks::current() {
        let distributed = matches!(
            cli.command,
            Some(Command::Run(_) | Command::Sweep(_) | Command::Study(_) | Command::Estimate(_))
        );
        if !distributed {
            crate::ranks::agree::<()>(Err(anyhow::anyhow!(
                "this command runs on one rank ({} ranks started): under mpirun, use `lopin \
                 run`, `lopin sweep`, `lopin study` or `lopin estimate`",
                r.size()
            )))?;
        }
    }
    match cli.command {
        Some(Command::View(args)) => view::view(&args),
        Some(Command::Run(args)) => run::run(&args),
        Some(Command::Estimate(args)) => estimate::estimate(&args),
        Some(Command::Reference(args)) => reference::reference(&args),
        Some(Command::Compare(args)) => compare::compare_cmd(&args),
        Some(Command::Accuracy(args)) => accuracy::accuracy(&args),
        Some(Command::Stress(args)) => stress::stress(&args),
        Some(Command::Sweep(args)) => sweep::sweep(&args),
        Some(Command::Study(args)) => study::study(&args),
        Some(Command::Export(args)) => export::export_cmd(&args),
        Some(Command::Srs(args)) => srs::srs(&args),
        Some(Command::Bench(args)) => bench::bench(&args),
        Some(Command::Scaling(args)) => scaling::scaling(&args),
        Some(Command::Mesh(cmd)) => mesh::mesh(&cmd),
        Some(Command::Scenes) => scenes::list(),
        Some(Command::ExportScene { name }) => scenes::export(&name),
        Some(Command::Completions(args)) => shell::completions(&args),
        Some(Command::Man(args)) => shell::man(&args),
        Some(Command::Docs(args)) => docs::docs(&args),
        None => view::view(&view::ViewArgs::default()),
    }
}
