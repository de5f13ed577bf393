//! Scene text: TOML parsed into a [`SceneSpec`] with errors that quote the line and column, and
//! written back; unchecked (the front door [`super::open`] reads files and registry names,
//! checks and builds).

use crate::error::{LopinError, Result};
use crate::scene::spec::SceneSpec;

/// Parses a scene from TOML text, unchecked ([`super::open::from_toml`] checks it); `source`
/// (usually the file path) names it in errors.
pub fn parse(text: &str, source: &str) -> Result<SceneSpec> {
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
    Ok(spec)
}

/// Writes a scene as TOML.
pub fn to_toml(spec: &SceneSpec) -> String {
    toml::to_string_pretty(spec)
        .unwrap_or_else(|e| unreachable!("scene specs always serialize: {e}"))
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
