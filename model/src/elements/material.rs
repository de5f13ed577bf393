//! Isotropic linear elastic material (E, ν, ρ): Hooke matrix, wave speeds and impedance
//! (METHOD §1, §10: k0 = √(ρE)), and its Rayleigh damping ([`Rayleigh`]).

use serde::{Deserialize, Serialize};

pub use super::rayleigh::Rayleigh;

/// An isotropic linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub young: f64,
    /// Poisson's ratio ν (−).
    pub poisson: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Rayleigh damping C = α M + β K (none by default).
    #[serde(default)]
    pub damping: Rayleigh,
}

impl Material {
    /// Lamé's first parameter λ.
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus G.
    pub fn shear_modulus(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// The 6×6 Hooke matrix in Voigt order (xx, yy, zz, xy, yz, zx), engineering shear strains.
    pub fn hooke(&self) -> [[f64; 6]; 6] {
        let (l, g) = (self.lambda(), self.shear_modulus());
        let mut d = [[0.0; 6]; 6];
        for (i, row) in d.iter_mut().enumerate().take(3) {
            for (j, v) in row.iter_mut().enumerate().take(3) {
                *v = if i == j { l + 2.0 * g } else { l };
            }
        }
        for (i, row) in d.iter_mut().enumerate().skip(3) {
            row[i] = g;
        }
        d
    }

    /// The stress D ε of a Voigt strain (xx, yy, zz, and engineering shears xy, yz, zx).
    pub fn stress_of(&self, eps: &[f64; 6]) -> [f64; 6] {
        let d = self.hooke();
        std::array::from_fn(|r| (0..6).map(|c| d[r][c] * eps[c]).sum())
    }

    /// Bar (1D) wave speed √(E/ρ).
    pub fn bar_speed(&self) -> f64 {
        (self.young / self.density).sqrt()
    }

    /// Dilatational (P) wave speed √((λ+2G)/ρ).
    pub fn p_wave_speed(&self) -> f64 {
        ((self.lambda() + 2.0 * self.shear_modulus()) / self.density).sqrt()
    }

    /// The search-direction scale √(ρE) of METHOD §10 (the bar impedance ρc).
    pub fn impedance(&self) -> f64 {
        (self.density * self.young).sqrt()
    }
}

/// The slowest bar wave speed √(E/ρ) among (speed, material name) pairs, with its material.
pub fn slowest<'a>(speeds: impl Iterator<Item = (f64, &'a str)>) -> (f64, &'a str) {
    speeds.fold((f64::INFINITY, ""), |a, b| if b.0 < a.0 { b } else { a })
}

/// A velocity against the slowest wave speed of a model ([`slowest`]): a faster one means
/// strains of order one, outside small-strain elasticity; the reason says so.
pub fn check_small_strain_speed(v: f64, (c, name): (f64, &str)) -> Result<(), String> {
    if v.abs() <= c {
        return Ok(());
    }
    Err(format!(
        "{v:?} m/s is faster than the slowest wave speed of the model ({c:.4e} m/s in \
         `{name}`): the strains would not be small"
    ))
}

/// The Voigt strain (xx, yy, zz, 2xy, 2yz, 2zx) of a displacement gradient g[i][j] = ∂u_i/∂x_j
/// (its symmetric part; the skew part is a rotation).
pub fn voigt_strain(g: &[[f64; 3]; 3]) -> [f64; 6] {
    [
        g[0][0],
        g[1][1],
        g[2][2],
        g[0][1] + g[1][0],
        g[1][2] + g[2][1],
        g[2][0] + g[0][2],
    ]
}
