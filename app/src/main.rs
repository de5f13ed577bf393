//! `lopin`: the desktop explorer (`lopin` alone, or `lopin view SCENE`) and the command line of
//! Lopin (headless runs, sweeps, exports, benchmarks, scene files). Built with the `mpi`
//! feature and started by `mpirun -np P`, `run`, `sweep` and `estimate` run distributed over the
//! P ranks ([`lopin_app::ranks`]) and `study` deals its chains to them; an error is printed
//! once, by the lowest rank that met it.

use clap::Parser;
use lopin_app::{cli, ranks};

fn main() -> std::process::ExitCode {
    #[cfg(feature = "mpi")]
    let _universe = ranks::mpi_world::init();
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(e) => {
            if ranks::is_root() {
                let _ = e.print();
            }
            return std::process::ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
    };
    match cli::dispatch(args) {
        Ok(code) => code,
        Err(e) if e.downcast_ref::<ranks::Silent>().is_some() => std::process::ExitCode::from(2),
        Err(e) => {
            match ranks::current() {
                None => eprintln!("error: {e:#}"),
                Some(r) if r.rank() > 0 => {
                    eprintln!("error (rank {} of {}): {e:#}", r.rank(), r.size())
                }
                Some(_) => eprintln!("error: {e:#}"),
            }
            std::process::ExitCode::from(2)
        }
    }
}
