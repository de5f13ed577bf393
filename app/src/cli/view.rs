//! `lopin view` (and `lopin` alone): opens the desktop explorer.

use clap::Args;
use std::path::PathBuf;

/// Options of the explorer.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// Built-in scene name (see `lopin scenes`) or path to a .toml scene file.
    #[arg(default_value = "two-blocks")]
    pub scene: String,
    /// Measure: move the friction slider by 0.05 several times, write the re-solve latency and
    /// frame intervals to FILE (JSON), print them and close the window.
    #[arg(long, value_name = "FILE")]
    pub measure: Option<PathBuf>,
    /// Hide wall-clock figures (timings, frame rate) so screenshots are reproducible.
    #[arg(long)]
    pub reproducible: bool,
}

impl Default for ViewArgs {
    fn default() -> Self {
        ViewArgs {
            scene: "two-blocks".into(),
            measure: None,
            reproducible: false,
        }
    }
}

/// Opens the explorer and returns when its window is closed.
pub fn view(args: &ViewArgs) -> anyhow::Result<std::process::ExitCode> {
    lopin_explorer::run_native(lopin_explorer::Options {
        scene: args.scene.clone(),
        reproducible: args.reproducible,
        measure: args.measure.clone(),
    })?;
    Ok(std::process::ExitCode::SUCCESS)
}
