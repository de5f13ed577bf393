//! `lopin`: the command line of Lopin (headless runs, benchmarks, scene files). The desktop
//! explorer will open when `lopin` is run without arguments.

mod cli;

use clap::Parser;

fn main() -> std::process::ExitCode {
    let args = cli::Cli::parse();
    match cli::dispatch(args) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::ExitCode::from(2)
        }
    }
}
