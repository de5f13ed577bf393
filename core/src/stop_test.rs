//! The stopping test's choice (METHOD §6): η on the fields themselves, or η̄ on their step
//! averages (see [`crate::indicator`]). It lives apart from the indicator so scene files, which the
//! monolithic reference reads without the LATIN solver, can name it.

use crate::error::{LopinError, Result};

/// Which indicator ends a window (METHOD §6 stopping test).
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StopTest {
    /// η on the fields themselves (METHOD §6 as written).
    #[default]
    Eta,
    /// η̄ on step-averaged fields: blind to the alternating mode.
    Smooth,
}

impl StopTest {
    /// Parses `eta` or `smooth`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "eta" => Ok(Self::Eta),
            "smooth" => Ok(Self::Smooth),
            _ => Err(LopinError::setting(
                "stop",
                format!("unknown stopping test `{name}` (eta, smooth)"),
            )),
        }
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Eta => "eta",
            Self::Smooth => "smooth",
        }
    }
}
