//! The plain result types of a transient solve, shared by the LATIN post-processing
//! (`lopin_core::post`, which re-exports them) and the monolithic reference of `lopin-reference`:
//! the energy balance of the exact discrete identity of METHOD §2, contact histories (METHOD §5:
//! pressure, gap, slip, step-averaged normal force) and the headline numbers of a run. They hold
//! numbers only and depend on nothing of the LATIN iteration.

/// Energy balance over time (all substructures summed), m = 0..=N.
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyHistory {
    /// ½ vᵀ M v.
    pub kinetic: Vec<f64>,
    /// ½ uᵀ K u.
    pub strain: Vec<f64>,
    /// Cumulative work of the boundary interfaces (imposed velocities and tractions).
    pub input_work: Vec<f64>,
    /// Cumulative energy dissipated by the Rayleigh damping, the scheme's work of C v:
    /// Σ ((1 − γ) C v_{m−1} + γ C v_m)·(u_m − u_{m−1}) (all 0 without damping).
    pub damping: Vec<f64>,
}

impl EnergyHistory {
    /// Kinetic + strain energy at step m.
    pub fn total(&self, m: usize) -> f64 {
        self.kinetic[m] + self.strain[m]
    }

    /// max over m of E_m / (E_0 + W_in,m), over steps where the denominator is positive:
    /// ≤ 1 when no energy is created.
    pub fn max_total_over_input(&self) -> f64 {
        let e0 = self.total(0);
        (0..self.kinetic.len())
            .filter_map(|m| {
                let avail = e0 + self.input_work[m];
                (avail > 0.0).then(|| self.total(m) / avail)
            })
            .fold(0.0, f64::max)
    }
}

/// Contact quantities of one contact interface over time, from ŝ (METHOD §5).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactHistory {
    /// Interface index.
    pub interface: usize,
    /// Contact pressure p_m = −F̂₁·n per step and node (point values).
    pub pressure: Vec<Vec<f64>>,
    /// Gap ĝ_m per step and node.
    pub gap: Vec<Vec<f64>>,
    /// Magnitude of the accumulated tangential relative displacement per step and node.
    pub slip: Vec<Vec<f64>>,
    /// Step-averaged total normal force Σ A (p_m + p_{m−1})/2 per step.
    pub normal_force: Vec<f64>,
}

impl ContactHistory {
    /// Largest slip over nodes and steps.
    pub fn max_slip(&self) -> f64 {
        self.slip.iter().flatten().copied().fold(0.0, f64::max)
    }

    /// Smallest gap over nodes and steps.
    pub fn min_gap(&self) -> f64 {
        self.gap
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// Largest step-averaged normal force.
    pub fn peak_normal_force(&self) -> f64 {
        self.normal_force.iter().copied().fold(0.0, f64::max)
    }
}

/// The headline numbers of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Kinetic energy at the end.
    pub kinetic_end: f64,
    /// Strain energy at the end.
    pub strain_end: f64,
    /// Total input work of the boundary interfaces at the end.
    pub input_work: f64,
    /// Energy dissipated by the Rayleigh damping at the end.
    pub damping_work: f64,
    /// max_m E_m / (E_0 + W_in,m).
    pub max_total_over_input: f64,
    /// Largest slip on contact interfaces (0 without contact).
    pub max_slip: f64,
    /// Largest step-averaged total normal force on a contact interface (0 without contact).
    pub peak_normal_force: f64,
    /// Smallest gap on contact interfaces (None without contact).
    pub min_gap: Option<f64>,
}

impl Summary {
    /// The headline numbers of an energy balance and contact histories.
    pub fn from_histories(e: &EnergyHistory, c: &[ContactHistory]) -> Self {
        let n = e.kinetic.len() - 1;
        Summary {
            kinetic_end: e.kinetic[n],
            strain_end: e.strain[n],
            input_work: e.input_work[n],
            damping_work: e.damping[n],
            max_total_over_input: e.max_total_over_input(),
            max_slip: c.iter().map(ContactHistory::max_slip).fold(0.0, f64::max),
            peak_normal_force: c
                .iter()
                .map(ContactHistory::peak_normal_force)
                .fold(0.0, f64::max),
            min_gap: c.iter().map(ContactHistory::min_gap).reduce(f64::min),
        }
    }
}
