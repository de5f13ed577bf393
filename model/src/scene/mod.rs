//! Scenes: the description schema ([`spec`]), the built-in registry ([`registry`]), TOML
//! reading, the generator of granular materials ([`granular`]), validation ([`validate`]), the
//! admission of a solve's size ([`admission`]) and the builder that turns a description into a
//! [`crate::Problem`] ([`build`]).

pub mod admission;
pub mod build;
mod cell_set;
mod exact;
mod face_index;
pub mod granular;
pub mod granular_poly;
pub mod mesh_bodies;
#[cfg(feature = "schema")]
pub mod reference;
pub mod registry;
pub mod settings;
pub mod spec;
pub mod validate;

use crate::error::{LopinError, Result};
pub use spec::SceneSpec;

/// Parses a scene from TOML text; `source` (usually the file path) names it in errors.
pub fn from_toml(text: &str, source: &str) -> Result<SceneSpec> {
    let spec: SceneSpec = toml::from_str(text).map_err(|e| {
        let field = e
            .span()
            .map(|s| field_at(text, s.start))
            .unwrap_or_else(|| "(document)".into());
        LopinError::scene(
            source,
            field,
            crate::error::clip_quoted(e.message(), QUOTED_CHARS),
        )
    })?;
    build::validate(&spec, source)?;
    Ok(spec)
}

/// Writes a scene as TOML.
pub fn to_toml(spec: &SceneSpec) -> String {
    toml::to_string_pretty(spec)
        .unwrap_or_else(|e| unreachable!("scene specs always serialize: {e}"))
}

/// How errors name a scene given to [`load`]: `scene NAME` for a built-in, else the path.
pub fn source_label(name_or_path: &str) -> String {
    if registry::contains(name_or_path) {
        format!("scene {name_or_path}")
    } else {
        name_or_path.to_string()
    }
}

/// Reads a scene: a registry name (built-in or test scene), or a path to a TOML file (not on
/// wasm32, which has no files).
pub fn load(name_or_path: &str) -> Result<SceneSpec> {
    if let Some(spec) = registry::parse(name_or_path) {
        return spec;
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        let path = std::path::Path::new(name_or_path);
        if path.exists() {
            let text = std::fs::read_to_string(path).map_err(|e| LopinError::Io {
                path: name_or_path.to_string(),
                reason: e.to_string(),
            })?;
            return from_toml(&text, name_or_path);
        }
    }
    Err(LopinError::UnknownScene {
        name: name_or_path.to_string(),
        known: registry::SCENES.join(", "),
    })
}

/// Characters of a TOML line an error quotes, from the error's column on.
const QUOTED_CHARS: usize = 60;

/// "line L, column C (`text`)" for a byte offset of a TOML document: the line as written from
/// the column on (all of it when short), cut to [`QUOTED_CHARS`].
fn field_at(text: &str, offset: usize) -> String {
    let before = text.get(..offset).unwrap_or(text);
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |p| p + 1);
    let col = before.chars().count() - text[..start].chars().count() + 1;
    let line_text = text[start..].lines().next().unwrap_or("");
    let from_col = if line_text.chars().count() <= QUOTED_CHARS {
        line_text.trim().to_string()
    } else {
        let skip = line_text
            .chars()
            .take(col - 1)
            .map(char::len_utf8)
            .sum::<usize>();
        let rest = line_text.get(skip..).unwrap_or(line_text);
        let mark = if skip > 0 { "…" } else { "" };
        format!("{mark}{}", crate::error::clip(rest, QUOTED_CHARS))
    };
    format!("line {line}, column {col} (`{from_col}`)")
}
