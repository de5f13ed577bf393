//! `lopin scenes` and `lopin export-scene`: the registry (a table of names and descriptions), and
//! its scenes as TOML files.

use std::process::ExitCode;

use lopin_core::scene::{self, registry};

use super::report::plain_table;

pub fn list() -> anyhow::Result<ExitCode> {
    let mut table = plain_table();
    for name in registry::SCENES {
        let spec =
            registry::builtin(name).ok_or_else(|| anyhow::anyhow!("registry lost {name}"))?;
        let large = if registry::is_large(name) {
            " [large: command line, see `lopin estimate`]"
        } else {
            ""
        };
        table.add_row([name.to_string(), format!("{}{large}", spec.description)]);
    }
    println!("{}", table.trim_fmt());
    Ok(ExitCode::SUCCESS)
}

pub fn export(name: &str) -> anyhow::Result<ExitCode> {
    let spec = registry::builtin(name).ok_or_else(|| {
        anyhow::anyhow!(
            "unknown scene `{name}` (built-in: {})",
            registry::SCENES.join(", ")
        )
    })?;
    print!("{}", scene::to_toml(&spec));
    Ok(ExitCode::SUCCESS)
}
