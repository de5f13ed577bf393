//! Rayleigh damping of a material: the damping matrix C = α M + β K of a substructure, mass- and
//! stiffness-proportional, whose modal damping ratio at the angular frequency ω is
//! ζ(ω) = α/(2ω) + βω/2. It enters the step operator of the time scheme as
//! S = (c_M + α) M + (c_K + β) K + k Bᵀ A B ([`crate::time::time_scheme`]), a constant matrix
//! factorized once like the undamped one.

use serde::{Deserialize, Serialize};

/// The two Rayleigh coefficients of a material (both 0: undamped).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Rayleigh {
    /// α, on the mass (1/s).
    pub alpha: f64,
    /// β, on the stiffness (s).
    pub beta: f64,
}

impl Rayleigh {
    /// No damping.
    pub const NONE: Self = Self {
        alpha: 0.0,
        beta: 0.0,
    };

    /// True when C = 0.
    pub fn is_none(&self) -> bool {
        self.alpha == 0.0 && self.beta == 0.0
    }

    /// The modal damping ratio ζ(ω) = α/(2ω) + βω/2 at the angular frequency ω (rad/s).
    pub fn ratio(&self, omega: f64) -> f64 {
        self.alpha / (2.0 * omega) + 0.5 * self.beta * omega
    }

    /// The coefficients that give the damping ratio ζ at the two frequencies f₁ < f₂ (Hz):
    /// α = 2ζ ω₁ω₂/(ω₁ + ω₂), β = 2ζ/(ω₁ + ω₂) (ζ(ω) is below ζ between them, above outside).
    pub fn from_ratio(zeta: f64, band: [f64; 2]) -> Self {
        let (w1, w2) = (
            2.0 * std::f64::consts::PI * band[0],
            2.0 * std::f64::consts::PI * band[1],
        );
        Self {
            alpha: 2.0 * zeta * w1 * w2 / (w1 + w2),
            beta: 2.0 * zeta / (w1 + w2),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The pair built for ζ at two frequencies gives ζ at both.
    #[test]
    fn the_ratio_at_the_band_ends_is_the_one_asked() {
        let r = Rayleigh::from_ratio(0.02, [50.0, 2000.0]);
        for f in [50.0, 2000.0] {
            let w = 2.0 * std::f64::consts::PI * f;
            assert!((r.ratio(w) - 0.02).abs() < 1e-15, "{}", r.ratio(w));
        }
        let mid = 2.0 * std::f64::consts::PI * 300.0;
        assert!(r.ratio(mid) < 0.02);
        assert!(Rayleigh::NONE.is_none());
    }
}
