//! The time-integration scheme of every substructure and of the monolithic reference: the
//! trapezoidal rule of METHOD §2 (ρ∞ = 1, undamped) and its second-order dissipative extension,
//! the Bossak–Newmark member of the generalized-α family (α_f = 0), with the spectral radius at
//! infinite frequency ρ∞ ∈ [0, 1] as its one setting (METHOD §10 "add numerical dissipation"):
//!
//!   M [(1 − α_m) a_m + α_m a_{m−1}] + K u_m = f_ext,m + Bᵀ A F_m
//!   v_m = v_{m−1} + Δt [(1 − γ) a_{m−1} + γ a_m]
//!   u_m = u_{m−1} + Δt v_{m−1} + Δt² [(½ − β) a_{m−1} + β a_m]
//!   α_m = (ρ∞ − 1)/(ρ∞ + 1),  γ = ½ − α_m,  β = ¼ (1 − α_m)²
//!
//! Forces stay point values at t_m (α_f = 0), so the interface laws of METHOD §5 pair F_m with
//! W_m exactly as before and ρ∞ = 1 is today's rule, bit for bit. Written on velocities, a step is
//!
//!   S v_m = f_ext,m + M (c_M v_{m−1} + c_A a_{m−1}) − K (u_{m−1} + d_V v_{m−1} + d_A a_{m−1})
//!           + Bᵀ A (F̂_m + k Ŵ_m),   S = c_M M + c_K K + k Bᵀ A B,
//!
//! with the coefficients of [`StepCoefficients`] (c_M = 2/Δt, c_K = d_V = Δt/2, c_A = 1, d_A = 0
//! for ρ∞ = 1). The contact gap and slip (METHOD §5) follow the same displacement update applied
//! to the velocity jump ([`StepCoefficients::closing_velocity`], [`StepCoefficients::advance`]),
//! in LATIN and in the reference alike, so a closed contact has no displacement jump and its
//! normal force does no work: the scheme's dissipation is the only energy change.
//! The undamped rule's discrete admittance vanishes at the Nyquist frequency (METHOD §10); with
//! ρ∞ < 1 it is Δt (−2α_m) / (2 M (1 − 2α_m)) per unit mass there, which is what lets LATIN
//! converge on that content.

use serde::{Deserialize, Serialize};

/// The scheme: ρ∞ = 1 is the trapezoidal rule (METHOD §2), ρ∞ < 1 damps the highest
/// frequencies (ρ∞ = 0: annihilated in one step).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeScheme {
    /// Spectral radius at infinite frequency, in [0, 1].
    pub rho_inf: f64,
}

impl Default for TimeScheme {
    fn default() -> Self {
        Self::TRAPEZOIDAL
    }
}

/// The coefficients of one step of the scheme for a time step Δt (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepCoefficients {
    /// Δt.
    pub dt: f64,
    /// c_M: coefficient of M in S and of M v_{m−1} in the right-hand side.
    pub mass: f64,
    /// c_K: coefficient of K in S (u_m = … + c_K v_m).
    pub stiffness: f64,
    /// c_A: coefficient of M a_{m−1} in the right-hand side.
    pub mass_a: f64,
    /// d_V: u_m = u_{m−1} + d_V v_{m−1} + d_A a_{m−1} + c_K v_m.
    pub u_from_v: f64,
    /// d_A (0 for the trapezoidal rule).
    pub u_from_a: f64,
    /// a_m = e_V (v_m − v_{m−1}) − e_A a_{m−1}: e_V.
    pub a_from_dv: f64,
    /// e_A.
    pub a_from_a: f64,
    /// True for ρ∞ = 1: the march uses the trapezoidal formulas of METHOD §2 as written.
    pub trapezoidal: bool,
    /// True for the static "step" of [`StepCoefficients::STATIC`] (no inertia, no damping).
    pub statics: bool,
}

impl TimeScheme {
    /// The undamped trapezoidal rule (ρ∞ = 1).
    pub const TRAPEZOIDAL: Self = Self { rho_inf: 1.0 };

    /// The scheme with spectral radius `rho_inf` at infinite frequency.
    pub fn new(rho_inf: f64) -> Self {
        Self { rho_inf }
    }

    /// Checks ρ∞ ∈ [0, 1]; the reason for a refusal.
    pub fn check(&self) -> Result<(), String> {
        if (0.0..=1.0).contains(&self.rho_inf) {
            Ok(())
        } else {
            Err(format!(
                "must lie in [0, 1] (1: undamped trapezoidal rule, smaller: more high-frequency dissipation), got {}",
                self.rho_inf
            ))
        }
    }

    /// True for the undamped rule.
    pub fn is_trapezoidal(&self) -> bool {
        self.rho_inf == 1.0
    }

    /// (α_m, γ, β) of the Bossak–Newmark scheme.
    pub fn parameters(&self) -> (f64, f64, f64) {
        let r = self.rho_inf;
        let alpha_m = (r - 1.0) / (r + 1.0);
        let gamma = 0.5 - alpha_m;
        let beta = 0.25 * (1.0 - alpha_m) * (1.0 - alpha_m);
        (alpha_m, gamma, beta)
    }

    /// The step coefficients for Δt.
    pub fn coefficients(&self, dt: f64) -> StepCoefficients {
        if self.is_trapezoidal() {
            return StepCoefficients {
                dt,
                mass: 2.0 / dt,
                stiffness: 0.5 * dt,
                mass_a: 1.0,
                u_from_v: 0.5 * dt,
                u_from_a: 0.0,
                a_from_dv: 2.0 / dt,
                a_from_a: 1.0,
                trapezoidal: true,
                statics: false,
            };
        }
        let (am, g, b) = self.parameters();
        let e_v = 1.0 / (g * dt);
        let e_a = (1.0 - g) / g;
        StepCoefficients {
            dt,
            mass: (1.0 - am) * e_v,
            stiffness: b * dt / g,
            mass_a: (1.0 - am) * e_a - am,
            u_from_v: dt - b * dt / g,
            u_from_a: dt * dt * (0.5 - b) - b * dt * dt * e_a,
            a_from_dv: e_v,
            a_from_a: e_a,
            trapezoidal: false,
            statics: false,
        }
    }

    /// A short name for reports: "trapezoidal (ρ∞ = 1)" or "Bossak–Newmark ρ∞ = 0.8".
    pub fn describe(&self) -> String {
        if self.is_trapezoidal() {
            "trapezoidal rule (ρ∞ = 1, undamped)".into()
        } else {
            format!(
                "Bossak–Newmark (generalized-α, α_f = 0), ρ∞ = {}",
                self.rho_inf
            )
        }
    }
}

impl StepCoefficients {
    /// Statics as one step of a unit pseudo-time from rest: no mass, u₁ = v₁ (the "velocity"
    /// is the displacement), S = K + k Bᵀ A B, and the contact gap after the step is
    /// g₀ + [u_n] (METHOD §5 with the displacement jump in place of the velocity's update):
    /// the LATIN iteration of the scheme's step solves the static problem, floating
    /// substructures held by the search direction alone.
    pub const STATIC: Self = Self {
        dt: 1.0,
        mass: 0.0,
        stiffness: 1.0,
        mass_a: 0.0,
        u_from_v: 0.0,
        u_from_a: 0.0,
        a_from_dv: 0.0,
        a_from_a: 0.0,
        trapezoidal: false,
        statics: true,
    };

    /// The normal velocity jump at step m that closes the gap exactly (g_m = 0) from the gap,
    /// normal velocity jump and normal acceleration jump of step m − 1 (METHOD §5 V*:
    /// −2 g/Δt − [W_n] for the trapezoidal rule).
    #[inline]
    pub fn closing_velocity(&self, gap: f64, jn: f64, an: f64) -> f64 {
        if self.trapezoidal {
            -2.0 * gap / self.dt - jn
        } else {
            -(gap + self.u_from_v * jn + self.u_from_a * an) / self.stiffness
        }
    }

    /// Advances (u, v, a) of one dof from step m − 1 to m given v_m: returns (u_m, a_m).
    #[inline]
    pub fn advance(&self, u: f64, v: f64, a: f64, v_new: f64) -> (f64, f64) {
        if self.trapezoidal {
            self.advance_as::<true>(u, v, a, v_new)
        } else {
            self.advance_as::<false>(u, v, a, v_new)
        }
    }

    /// [`Self::advance`] for a scheme known to be the trapezoidal rule (`TRAPEZOIDAL`) or not,
    /// so that a loop over dofs carries no branch.
    #[inline(always)]
    pub fn advance_as<const TRAPEZOIDAL: bool>(
        &self,
        u: f64,
        v: f64,
        a: f64,
        v_new: f64,
    ) -> (f64, f64) {
        if TRAPEZOIDAL {
            (
                u + 0.5 * self.dt * (v + v_new),
                self.a_from_dv * (v_new - v) - a,
            )
        } else {
            (
                u + self.u_from_v * v + self.u_from_a * a + self.stiffness * v_new,
                self.a_from_dv * (v_new - v) - self.a_from_a * a,
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One dof, m = 1, stiffness ω²: the amplification matrix of (u, v, a) over one step,
    /// formed from the step coefficients (the velocity form the march uses).
    fn amplification(c: &StepCoefficients, omega: f64) -> [[f64; 3]; 3] {
        let k = omega * omega;
        let mut cols = [[0.0; 3]; 3];
        for (j, col) in cols.iter_mut().enumerate() {
            let mut x = [0.0; 3];
            x[j] = 1.0;
            let (u, v, a) = (x[0], x[1], x[2]);
            let rhs = c.mass * v + c.mass_a * a - k * (u + c.u_from_v * v + c.u_from_a * a);
            let v_new = rhs / (c.mass + c.stiffness * k);
            let (u_new, a_new) = c.advance(u, v, a, v_new);
            *col = [u_new, v_new, a_new];
        }
        // rows = outputs
        std::array::from_fn(|i| std::array::from_fn(|j| cols[j][i]))
    }

    /// Spectral radius of a 3×3 matrix as ‖A^n‖^{1/n} with n = 2²⁰ (by repeated squaring, each
    /// square normalized): transient growth and Jordan blocks weigh at most C^{1/n} ≈ 1 + 1e-5.
    fn spectral_radius(a: [[f64; 3]; 3]) -> f64 {
        let mul = |x: [[f64; 3]; 3], y: [[f64; 3]; 3]| -> [[f64; 3]; 3] {
            std::array::from_fn(|i| {
                std::array::from_fn(|j| (0..3).map(|k| x[i][k] * y[k][j]).sum())
            })
        };
        let (mut p, mut log_norm) = (a, 0.0);
        let squarings = 20;
        for _ in 0..squarings {
            p = mul(p, p);
            log_norm *= 2.0;
            let norm = p.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
            if norm == 0.0 {
                return 0.0;
            }
            p.iter_mut().flatten().for_each(|x| *x /= norm);
            log_norm += norm.ln();
        }
        (log_norm / f64::from(1u32 << squarings)).exp()
    }

    /// ρ∞ is what the scheme's name says: the spectral radius at ωΔt = 10⁶ equals ρ∞ to 1e-3
    /// for ρ∞ ∈ {0.5, 0.8, 0.9}, the trapezoidal rule keeps 1 at every frequency, and no
    /// frequency is amplified (unconditional stability, ωΔt from 10⁻² to 10⁶).
    #[test]
    fn spectral_radius_at_infinity_is_rho_inf() {
        for r in [0.5, 0.8, 0.9] {
            let c = TimeScheme::new(r).coefficients(1.0);
            let rho = spectral_radius(amplification(&c, 1e6));
            assert!((rho - r).abs() < 1e-3, "ρ∞ = {r}: {rho}");
            for w in [1e-2, 0.1, 1.0, 3.0, 10.0, 1e3] {
                let rho = spectral_radius(amplification(&c, w));
                assert!(rho <= 1.0 + 1e-4, "ρ∞ = {r}, ωΔt = {w}: {rho}");
            }
        }
        let c = TimeScheme::TRAPEZOIDAL.coefficients(1.0);
        for w in [0.1, 1.0, 10.0, 1e6] {
            let rho = spectral_radius(amplification(&c, w));
            assert!((rho - 1.0).abs() < 1e-4, "trapezoidal, ωΔt = {w}: {rho}");
        }
    }

    /// Second order: on u'' + u = 0 from u = 1 over t ∈ [0, 1], halving Δt divides the error by
    /// 4 (ratio between 3.6 and 4.4) for ρ∞ = 0.6, and the general formulas at ρ∞ = 1 − 1e-12
    /// agree with the trapezoidal ones to 1e-9.
    #[test]
    fn second_order_accurate() {
        let error = |scheme: TimeScheme, steps: usize| {
            let dt = 1.0 / steps as f64;
            let c = scheme.coefficients(dt);
            let (mut u, mut v, mut a) = (1.0, 0.0, -1.0);
            for _ in 0..steps {
                let rhs = c.mass * v + c.mass_a * a - (u + c.u_from_v * v + c.u_from_a * a);
                let v_new = rhs / (c.mass + c.stiffness);
                (u, a) = c.advance(u, v, a, v_new);
                v = v_new;
            }
            (u - 1f64.cos()).abs()
        };
        let s = TimeScheme::new(0.6);
        let ratio = error(s, 50) / error(s, 100);
        assert!((3.6..4.4).contains(&ratio), "ratio {ratio}");
        let near = error(TimeScheme::new(1.0 - 1e-12), 50);
        let trap = error(TimeScheme::TRAPEZOIDAL, 50);
        assert!((near - trap).abs() < 1e-9, "{near} vs {trap}");
    }

    #[test]
    fn rho_inf_outside_the_unit_interval_is_refused() {
        assert!(TimeScheme::new(1.5).check().is_err());
        assert!(TimeScheme::new(-0.1).check().is_err());
        assert!(TimeScheme::new(f64::NAN).check().is_err());
        assert!(TimeScheme::new(0.0).check().is_ok());
    }
}
