//! Rerun recordings of runs, sweeps and explorer sessions: where they go ([`target`]), the
//! surfaces they draw ([`surface`]), what is logged per step and per iteration (`steps`,
//! `stream`, with the `rerun` feature) and the explorer's recorder ([`explorer`]). Without the
//! feature, [`Recorder::open`] explains how to get it.

#[cfg(not(feature = "rerun"))]
mod disabled;
pub mod explorer;
#[cfg(feature = "rerun")]
mod steps;
#[cfg(feature = "rerun")]
mod stream;
pub mod surface;
pub mod target;

#[cfg(not(feature = "rerun"))]
pub use disabled::Recorder;
#[cfg(feature = "rerun")]
pub use stream::Recorder;
pub use target::Target;

/// At most this many velocity arrows per step over the whole scene (nodes are subsampled).
pub const MAX_ARROWS: usize = 1500;

/// What the steps were drawn with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepsSummary {
    /// Steps logged (N + 1).
    pub steps: usize,
    /// Colour range of the von Mises stress, Pa.
    pub von_mises: (f64, f64),
    /// Displacement scale of the drawn surfaces.
    pub deform: f64,
    /// Arrow length per m/s, m.
    pub arrow_scale: f64,
    /// Largest contact pressure (top of its colour range), Pa.
    pub pressure_max: f64,
}

/// Readable, path-safe entity name.
pub fn entity_name(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
