//! `lopin view` (and `lopin` alone): opens the desktop explorer on a scene or a result folder
//! ([`crate::result_folder`]). Its "record to Rerun" toggle
//! saves to `--rerun FILE` or streams to `--rerun-connect ADDR` (default: a file
//! `lopin-SCENE-UNIXTIME.rrd` in the current folder).

use clap::Args;
use std::path::PathBuf;

/// Options of the explorer.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// Built-in scene name (see `lopin scenes`), path to a .toml scene file, or a result
    /// folder made by `lopin run --out`, `lopin sweep --out` or `lopin study --out` (shown
    /// from its stored states, then re-solved warm as its parameters move).
    #[arg(default_value = "two-blocks", value_name = "SCENE|FOLDER")]
    pub scene: String,
    /// Measure: move the friction slider by 0.05 several times, write the re-solve latency and
    /// frame intervals to FILE (JSON), print them and close the window.
    #[arg(long, value_name = "FILE")]
    pub measure: Option<PathBuf>,
    /// Hide wall-clock figures (timings, frame rate) so screenshots are reproducible.
    #[arg(long)]
    pub reproducible: bool,
    /// Where "record to Rerun" saves: FILE.rrd.
    #[arg(long, value_name = "FILE.rrd")]
    pub rerun: Option<PathBuf>,
    /// Where "record to Rerun" streams: a running Rerun viewer at ADDR (HOST:PORT).
    #[arg(long, value_name = "ADDR", conflicts_with = "rerun")]
    pub rerun_connect: Option<String>,
    /// Start with "record to Rerun" switched on.
    #[arg(long)]
    pub record: bool,
    /// Two-scale linear stage with the macro problem of METHOD §9 (default: the scene's
    /// `solver.macro`, else off); also a checkbox in the explorer.
    #[arg(long = "macro", value_enum)]
    pub two_scale: Option<super::setup::Switch>,
}

impl Default for ViewArgs {
    fn default() -> Self {
        ViewArgs {
            scene: "two-blocks".into(),
            measure: None,
            reproducible: false,
            rerun: None,
            rerun_connect: None,
            record: false,
            two_scale: None,
        }
    }
}

/// The recorder factory of this build (none without the `rerun` feature).
fn recorder(args: &ViewArgs) -> anyhow::Result<Option<lopin_explorer::RecorderFactory>> {
    let connect = args
        .rerun_connect
        .as_deref()
        .map(crate::record::Target::connect)
        .transpose()?;
    if cfg!(feature = "rerun") {
        Ok(Some(crate::record::explorer::factory(
            args.rerun.clone(),
            connect,
        )))
    } else {
        anyhow::ensure!(
            args.rerun.is_none() && connect.is_none() && !args.record,
            "recording needs a lopin built with the `rerun` feature"
        );
        Ok(None)
    }
}

/// Opens the explorer and returns when its window is closed.
pub fn view(args: &ViewArgs) -> anyhow::Result<std::process::ExitCode> {
    lopin_explorer::run_native(lopin_explorer::Options {
        scene: args.scene.clone(),
        reproducible: args.reproducible,
        measure: args.measure.clone(),
        recorder: recorder(args)?,
        record: args.record,
        two_scale: args.two_scale.map(|s| s == super::setup::Switch::On),
        opener: Some(crate::result_folder::opener()),
        connector: None,
    })?;
    Ok(std::process::ExitCode::SUCCESS)
}
