//! The iteration settings a scene file or the command line names besides numbers (a
//! [`super::spec::SolverSpec`] layer): the stopping test, the start of a cold time window, the
//! precision the factors of S keep and the on/off switches.
//!
//! The stopping test (METHOD §6): η on the fields themselves, or η̄ on their step averages,
//! which the undamped rule's alternating mode (METHOD §10) does not enter.
//!
//! Where a cold time window's iteration starts (METHOD §7): the linear-stage input s = (F, W)
//! on the window's steps m0..=m1, predicted from the converged steps before it. With
//! n = m − m0 + 1 the step's distance from the last converged step m0 − 1:
//!
//! * `zero`:   s_m = 0 (METHOD §7 as written);
//! * `hold`:   s_m = s_{m0−1} (the last converged step held constant);
//! * `linear`: s_m = s_{m0−1} + n (s_{m0−1} − s_{m0−2}) (extrapolated along the last step);
//! * `smooth`: s_m = s_{m0−1} + n (s_{m0−1} − s_{m0−3}) / 2 (extrapolated along the mean slope of
//!   the last two steps);
//! * `auto` (the default): `smooth` when the tolerance is at most [`EXTRAPOLATE_BELOW`], `hold`
//!   above it: an extrapolation also carries forward the iteration error of the steps it reads,
//!   about tol each, which outweighs its gain at loose tolerances (the guide,
//!   docs/src/iterations.md, "Window start", gives the measurements).
//!
//! The smooth slope is the difference of the step averages s̄_{m0−1} − s̄_{m0−2} with
//! s̄_j = (s_j + s_{j−1})/2, so the alternating mode (−1)^m c does not enter it, where `linear`
//! carries it forward doubled. `linear` and `smooth` need three converged steps before m0
//! (m0 ≥ 3, step 0 being the initial state); before that they hold. The LATIN solver applies
//! them (`lopin_core::solver`).

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

    /// Parses a command-line value ([`Self::parse`], the error as text).
    pub fn from_arg(name: &str) -> std::result::Result<Self, String> {
        Self::parse(name).map_err(|e| e.to_string())
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Eta => "eta",
            Self::Smooth => "smooth",
        }
    }
}

/// The precision the factors of S are computed and kept in
/// ([`crate::linalg::factor::CholeskyFactor`]).
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FactorPrecision {
    /// Single precision for the substructures of at least
    /// [`crate::linalg::factor::LARGE_NODES`] nodes, whose solves are bound by memory traffic;
    /// double below, where single precision would be slower.
    #[default]
    Auto,
    /// Kept in double precision.
    Double,
    /// Computed and kept in single precision: half the memory, faster solves; each solve is
    /// refined in double by the linear stage, which converges to the double-precision solution.
    Single,
}

impl FactorPrecision {
    /// Parses `auto`, `double` or `single`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "auto" => Ok(Self::Auto),
            "double" => Ok(Self::Double),
            "single" => Ok(Self::Single),
            _ => Err(LopinError::setting(
                "factors",
                format!("unknown precision `{name}` (auto, double, single)"),
            )),
        }
    }

    /// Parses a command-line value ([`Self::parse`], the error as text).
    pub fn from_arg(name: &str) -> std::result::Result<Self, String> {
        Self::parse(name).map_err(|e| e.to_string())
    }

    /// Whether it is the default, [`Self::Auto`].
    pub fn is_auto(&self) -> bool {
        *self == Self::Auto
    }

    /// Whether a substructure of `ndof` dofs keeps its factor in single precision (never in
    /// the browser build, which keeps double precision).
    pub fn single_for(&self, ndof: usize) -> bool {
        if cfg!(target_arch = "wasm32") {
            return false;
        }
        match self {
            Self::Auto => ndof / 3 >= crate::linalg::factor::LARGE_NODES,
            Self::Double => false,
            Self::Single => true,
        }
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::Double => "double",
            Self::Single => "single",
        }
    }
}

/// Parses an on/off switch of the command line (`--macro on`).
pub fn switch_from_arg(value: &str) -> std::result::Result<bool, String> {
    match value {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("expected `on` or `off`, got `{value}`")),
    }
}

/// The loosest tolerance at which `auto` extrapolates.
pub const EXTRAPOLATE_BELOW: f64 = 1e-3;

/// How a cold window's input is predicted.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum WindowStart {
    /// F = W = 0.
    Zero,
    /// The last converged step held constant.
    Hold,
    /// Linear extrapolation of the last step's change.
    Linear,
    /// Extrapolation of the mean change of the last two steps (blind to the alternating mode).
    Smooth,
    /// `Smooth` at tolerances up to [`EXTRAPOLATE_BELOW`], `Hold` above.
    #[default]
    Auto,
}

impl WindowStart {
    /// Every start, in the order the help lists them.
    pub const ALL: [Self; 5] = [
        Self::Zero,
        Self::Hold,
        Self::Linear,
        Self::Smooth,
        Self::Auto,
    ];

    /// Parses `zero`, `hold`, `linear`, `smooth` or `auto`.
    pub fn parse(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| {
                LopinError::setting(
                    "window_start",
                    format!("unknown window start `{name}` (zero, hold, linear, smooth, auto)"),
                )
            })
    }

    /// Parses a command-line value ([`Self::parse`], the error as text).
    pub fn from_arg(name: &str) -> std::result::Result<Self, String> {
        Self::parse(name).map_err(|e| e.to_string())
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Zero => "zero",
            Self::Hold => "hold",
            Self::Linear => "linear",
            Self::Smooth => "smooth",
            Self::Auto => "auto",
        }
    }

    /// The start a solve at tolerance `tol` uses: `Auto` resolved, any other itself.
    pub fn resolve(self, tol: f64) -> Self {
        match self {
            Self::Auto if tol <= EXTRAPOLATE_BELOW => Self::Smooth,
            Self::Auto => Self::Hold,
            other => other,
        }
    }

    /// Fills steps m0..=m1 of one step-major history (`len` entries per step) from the steps
    /// before m0 (m0 ≥ 1); `Auto` must be resolved first ([`Self::resolve`]), and holds here.
    pub fn fill(&self, data: &mut [f64], len: usize, (m0, m1): (usize, usize)) {
        let at = |m: usize| m * len;
        // (the step the slope is taken from, the divisor of the slope)
        let slope = match self {
            Self::Linear if m0 >= 3 => Some((m0 - 2, 1.0)),
            Self::Smooth if m0 >= 3 => Some((m0 - 3, 2.0)),
            _ => None,
        };
        for m in m0..=m1 {
            let n = (m - m0 + 1) as f64;
            for j in 0..len {
                let last = data[at(m0 - 1) + j];
                data[at(m) + j] = match (self, slope) {
                    (Self::Zero, _) => 0.0,
                    (_, Some((from, div))) => last + n * (last - data[at(from) + j]) / div,
                    (_, None) => last,
                };
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two entries per step over 8 steps: x_m = a + b m plus the alternating mode c (−1)^m on
    /// the second entry.
    fn history(c: f64) -> Vec<f64> {
        (0..8)
            .flat_map(|m| {
                let t = m as f64;
                [1.0 + 2.0 * t, -3.0 + 0.5 * t + c * (-1f64).powi(m)]
            })
            .collect()
    }

    #[test]
    fn extrapolations_are_exact_on_linear_histories() {
        let exact = history(0.0);
        for start in [WindowStart::Linear, WindowStart::Smooth] {
            let mut h = exact.clone();
            h[8..].fill(f64::NAN);
            start.fill(&mut h, 2, (4, 7));
            for (a, b) in h.iter().zip(&exact) {
                assert!((a - b).abs() < 1e-12, "{start:?}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn smooth_ignores_the_alternating_mode_and_linear_carries_it() {
        let (clean, noisy) = (history(0.0), history(1.0));
        let mut s = noisy.clone();
        WindowStart::Smooth.fill(&mut s, 2, (4, 4));
        // the mode's value at step 3 (−1) stays as it was; no slope is added by it
        assert!((s[9] - (clean[9] + (noisy[7] - clean[7]))).abs() < 1e-12);
        let mut l = noisy.clone();
        WindowStart::Linear.fill(&mut l, 2, (4, 4));
        // linear: s_3 + (s_3 − s_2) = clean + (−1) + (−1 − 1)
        assert!((l[9] - (clean[9] - 3.0)).abs() < 1e-12, "{}", l[9]);
    }

    #[test]
    fn hold_zero_and_the_first_steps() {
        let h0 = history(0.0);
        let mut h = h0.clone();
        WindowStart::Hold.fill(&mut h, 2, (3, 5));
        assert_eq!(&h[6..12], &[h0[4], h0[5], h0[4], h0[5], h0[4], h0[5]]);
        let mut z = h0.clone();
        WindowStart::Zero.fill(&mut z, 2, (3, 5));
        assert!(z[6..12].iter().all(|x| *x == 0.0));
        // before three converged steps an extrapolation holds
        for start in [WindowStart::Linear, WindowStart::Smooth] {
            let mut e = h0.clone();
            start.fill(&mut e, 2, (2, 2));
            assert_eq!(&e[4..6], &h0[2..4]);
        }
        for s in WindowStart::ALL {
            assert_eq!(WindowStart::parse(s.name()).ok(), Some(s));
        }
        assert_eq!(WindowStart::Auto.resolve(1e-3), WindowStart::Smooth);
        assert_eq!(WindowStart::Auto.resolve(1e-2), WindowStart::Hold);
        assert_eq!(WindowStart::Linear.resolve(1e-1), WindowStart::Linear);
        let e = WindowStart::parse("cubic").expect_err("unknown");
        assert!(e.to_string().contains("cubic"), "{e}");
    }
}
