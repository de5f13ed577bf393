//! Isotropic linear elastic material (E, ν, ρ): Hooke matrix, wave speeds and impedance
//! (METHOD §1, §10: k0 = √(ρE)).

use serde::{Deserialize, Serialize};

/// An isotropic linear elastic material.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub young: f64,
    /// Poisson's ratio ν (−).
    pub poisson: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
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
