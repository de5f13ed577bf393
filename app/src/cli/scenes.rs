//! `lopin scenes` and `lopin export-scene`: the registry, and its scenes as TOML files.

use std::process::ExitCode;

use lopin_core::scene::{self, registry};

pub fn list() -> anyhow::Result<ExitCode> {
    for name in registry::SCENES {
        let spec =
            registry::builtin(name).ok_or_else(|| anyhow::anyhow!("registry lost {name}"))?;
        let large = if registry::is_large(name) {
            " [large: command line, see `lopin estimate`]"
        } else {
            ""
        };
        println!("{name:<16} {}{large}", spec.description);
    }
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
