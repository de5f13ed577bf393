//! Which Lopin made a file: package version and the git commit of the build (see build.rs).

/// Package version.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Git commit of the build ("unknown" outside a git checkout).
pub const COMMIT: &str = env!("LOPIN_COMMIT");

/// "Lopin 0.1.0 (commit abcdef123456)".
pub fn line() -> String {
    format!("Lopin {VERSION} (commit {COMMIT})")
}
