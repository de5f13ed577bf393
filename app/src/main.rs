//! `lopin`: the desktop explorer (`lopin` alone, or `lopin view SCENE`) and the command line of
//! Lopin (headless runs, sweeps, exports, benchmarks, scene files).

use clap::Parser;
use lopin_app::cli;

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
