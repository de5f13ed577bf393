//! Errors of the engine: every error says where (file, field, substructure, interface) and why.

use thiserror::Error;

/// Result alias used throughout `lopin-core`.
pub type Result<T, E = LopinError> = std::result::Result<T, E>;

/// Everything that can go wrong while building or solving a problem.
#[derive(Debug, Error)]
pub enum LopinError {
    /// A scene description (built-in or file) is malformed or inconsistent.
    #[error("{source_name}: field `{field}`: {reason}")]
    Scene {
        /// The scene file path, or `scene NAME` for a built-in scene.
        source_name: String,
        /// Path of the offending field, e.g. `body[1].divisions`.
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A scene name that is not in the registry and not a readable file.
    #[error("unknown scene `{name}` (built-in scenes: {known}); a path to a .toml scene file is also accepted")]
    UnknownScene {
        /// The requested name.
        name: String,
        /// Comma-separated list of the registry's names.
        known: String,
    },
    /// Two substructures touch on a face region but their nodes do not pair one to one.
    #[error("{}substructures `{a}` and `{b}` share a face region near ({x:.6e}, {y:.6e}, {z:.6e}) but their faces cannot be coupled: their nodes do not match, and no facet of either is wholly covered by the other's within 25.8° (a non-matching interface needs one side's facets covered)", source_prefix(.source_name))]
    NonConforming {
        /// The scene file path, or `scene NAME` (empty where no scene is known).
        source_name: String,
        /// First substructure.
        a: String,
        /// Second substructure.
        b: String,
        /// Location of the mismatch.
        x: f64,
        /// Location of the mismatch.
        y: f64,
        /// Location of the mismatch.
        z: f64,
    },
    /// A mesh element that cannot be used (inverted, degenerate, non-finite).
    #[error("{}element {element}: {reason}", source_prefix(.source_name))]
    BadElement {
        /// The mesh file path (empty where none is known).
        source_name: String,
        /// The element's id in the file.
        element: usize,
        /// What is wrong with it.
        reason: String,
    },
    /// The substructure operator S could not be factorized.
    #[error(
        "substructure `{sub}`: factorization of S = 2/dt M + dt/2 K + k B^T A B failed: {reason}"
    )]
    Factorization {
        /// Substructure name.
        sub: String,
        /// Reason given by the factorization.
        reason: String,
    },
    /// A solver setting is out of range.
    #[error("solver setting `{field}`: {reason}")]
    Setting {
        /// Setting name (`k`, `mu`, `tol`, `window`, ...).
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A warm-start state does not have the layout of this problem.
    #[error("warm-start state does not fit this problem: {0}")]
    StateMismatch(String),
    /// The monolithic reference cannot treat this problem, or its contact iteration failed.
    #[error("monolithic reference: {0}")]
    Reference(String),
    /// A solve that cannot fit this machine, refused before anything large is allocated.
    #[error("{source_name}: the solve needs about {needed}, more than this machine can give it: {available}. {detail}. What would fit: {remedy}")]
    TooLarge {
        /// The scene file path, or `scene NAME` for a built-in scene.
        source_name: String,
        /// Bytes needed, formatted.
        needed: String,
        /// Bytes available and where that figure comes from.
        available: String,
        /// The sizes and the memory breakdown.
        detail: String,
        /// What would make it fit.
        remedy: String,
    },
    /// A value became non-finite during a solve: where it appeared and the inputs that feed it.
    #[error("non-finite value during the solve: {0}")]
    NonFinite(String),
    /// Reading a scene file failed.
    #[error("{path}: {reason}")]
    Io {
        /// File path.
        path: String,
        /// Reason.
        reason: String,
    },
}

/// Longest field name and reason a scene or setting error carries: input quoted in a message
/// (a value, a line of the file) is cut there, however long the input.
const FIELD_CHARS: usize = 160;
const REASON_CHARS: usize = 1000;

/// `text` cut to its first `max` characters, with an ellipsis and the full length where it was
/// cut (error messages quote user input; a megabyte-long line must not come back whole).
pub fn clip(text: &str, max: usize) -> String {
    match text.char_indices().nth(max) {
        Some((end, _)) => format!("{}… ({} characters)", &text[..end], text.chars().count()),
        None => text.to_string(),
    }
}

/// `message` with every piece quoted between backticks or double quotes cut to `max`
/// characters ([`clip`]): a parser's message quotes the input, the rest of it is its own.
pub fn clip_quoted(message: &str, max: usize) -> String {
    let mut out = String::with_capacity(message.len().min(4 * max));
    let mut rest = message;
    while let Some(open) = rest.find(['`', '"']) {
        let quote = &rest[open..=open];
        out.push_str(&rest[..=open]);
        rest = &rest[open + 1..];
        match rest.find(quote) {
            Some(close) => {
                out.push_str(&clip(&rest[..close], max));
                out.push_str(quote);
                rest = &rest[close + 1..];
            }
            None => {
                out.push_str(&clip(rest, max));
                rest = "";
            }
        }
    }
    out.push_str(rest);
    out
}

/// "SOURCE: " before a message, or nothing when no source is known.
fn source_prefix(source: &str) -> String {
    if source.is_empty() {
        String::new()
    } else {
        format!("{source}: ")
    }
}

impl LopinError {
    /// Names the scene an error without a source came from (interface detection knows only
    /// substructures).
    pub fn in_source(self, source: &str) -> Self {
        match self {
            LopinError::NonConforming {
                source_name,
                a,
                b,
                x,
                y,
                z,
            } if source_name.is_empty() => LopinError::NonConforming {
                source_name: source.to_string(),
                a,
                b,
                x,
                y,
                z,
            },
            other => other,
        }
    }

    /// Shorthand for a [`LopinError::Scene`] error.
    pub fn scene(source_name: &str, field: impl Into<String>, reason: impl Into<String>) -> Self {
        LopinError::Scene {
            source_name: clip(source_name, FIELD_CHARS),
            field: clip(&field.into(), FIELD_CHARS),
            reason: clip(&reason.into(), REASON_CHARS),
        }
    }

    /// Shorthand for a [`LopinError::Setting`] error.
    pub fn setting(field: &str, reason: impl Into<String>) -> Self {
        LopinError::Setting {
            field: clip(field, FIELD_CHARS),
            reason: clip(&reason.into(), REASON_CHARS),
        }
    }
}
