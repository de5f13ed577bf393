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
    #[error("substructures `{a}` and `{b}` share a face region near ({x:.6e}, {y:.6e}, {z:.6e}) but their nodes do not match (interfaces must be conforming)")]
    NonConforming {
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
    /// Reading a scene file failed.
    #[error("{path}: {reason}")]
    Io {
        /// File path.
        path: String,
        /// Reason.
        reason: String,
    },
}

impl LopinError {
    /// Shorthand for a [`LopinError::Scene`] error.
    pub fn scene(source_name: &str, field: impl Into<String>, reason: impl Into<String>) -> Self {
        LopinError::Scene {
            source_name: source_name.to_string(),
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// Shorthand for a [`LopinError::Setting`] error.
    pub fn setting(field: &str, reason: impl Into<String>) -> Self {
        LopinError::Setting {
            field: field.to_string(),
            reason: reason.into(),
        }
    }
}
