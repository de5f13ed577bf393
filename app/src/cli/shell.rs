//! `lopin completions SHELL` and `lopin man`: the shell completion script and the man pages,
//! generated from the command line's own definition (clap), so that they list every subcommand
//! and flag there is.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::CommandFactory;

/// Options of `lopin completions`.
#[derive(Debug, clap::Args)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell (e.g. `lopin completions bash >
    /// ~/.local/share/bash-completion/completions/lopin`).
    pub shell: clap_complete::Shell,
}

/// Options of `lopin man`.
#[derive(Debug, clap::Args)]
pub struct ManArgs {
    /// Write `lopin.1` and one page per subcommand (`lopin-run.1`, …) into this folder instead
    /// of printing the main page.
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

/// Prints the completion script of `shell`.
pub fn completions(args: &CompletionsArgs) -> anyhow::Result<ExitCode> {
    let mut cmd = super::Cli::command();
    clap_complete::generate(args.shell, &mut cmd, "lopin", &mut std::io::stdout());
    Ok(ExitCode::SUCCESS)
}

/// Prints the main man page, or writes every page into `--dir`.
pub fn man(args: &ManArgs) -> anyhow::Result<ExitCode> {
    let cmd = super::Cli::command();
    match &args.dir {
        None => clap_mangen::Man::new(cmd)
            .render(&mut std::io::stdout())
            .context("writing the man page")?,
        Some(dir) => {
            std::fs::create_dir_all(dir)
                .with_context(|| format!("--dir {}: cannot create the folder", dir.display()))?;
            clap_mangen::generate_to(cmd, dir)
                .with_context(|| format!("--dir {}: writing the man pages", dir.display()))?;
        }
    }
    Ok(ExitCode::SUCCESS)
}
