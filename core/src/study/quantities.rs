//! What a study reports of each configuration: the peak step-averaged normal force and the
//! largest slip of the contact interfaces (METHOD §5), the energy at the end, the input work and
//! the work dissipated by friction and by the normal contact law
//! ([`crate::dissipation`]); in a distributed run every rank calls [`Quantities::of`].

use crate::dissipation::contact_work;
use crate::post::{self, ContactHistory};
use crate::solver::end_energy::EndEnergy;
use crate::solver::{Solution, Solver};

/// The quantities of interest of one solved configuration.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct Quantities {
    /// Largest step-averaged total normal force on a contact interface (N).
    pub peak_normal_force: f64,
    /// Largest accumulated slip (m).
    pub max_slip: f64,
    /// Kinetic + strain energy at the end (J).
    pub energy_end: f64,
    /// Work of the boundary interfaces (J).
    pub input_work: f64,
    /// Work dissipated by friction (J).
    pub friction_work: f64,
    /// Work of the normal contact forces (J).
    pub normal_work: f64,
}

impl Quantities {
    /// Names (as CSV columns and figure titles) and units, in [`Self::values`] order.
    pub const NAMES: [(&'static str, &'static str); 6] = [
        ("peak_normal_force", "N"),
        ("max_slip", "m"),
        ("energy_end", "J"),
        ("input_work", "J"),
        ("friction_work", "J"),
        ("normal_work", "J"),
    ];

    /// The quantities of a solution.
    /// The energies at the end come from the solve's last linear stages where it kept them
    /// ([`Solution::end`]), else from a replay of the interval ([`post::energy`]).
    pub fn of(solver: &Solver, sol: &Solution) -> Self {
        let contact = post::gathered_contact(solver, sol);
        let end = sol.end.unwrap_or_else(|| {
            let e = post::energy(solver, sol);
            let n = e.kinetic.len() - 1;
            EndEnergy {
                kinetic: e.kinetic[n],
                strain: e.strain[n],
                input_work: e.input_work[n],
            }
        });
        let w = contact_work(solver, sol);
        Self {
            peak_normal_force: contact
                .iter()
                .map(ContactHistory::peak_normal_force)
                .fold(0.0, f64::max),
            max_slip: contact
                .iter()
                .map(ContactHistory::max_slip)
                .fold(0.0, f64::max),
            energy_end: end.kinetic + end.strain,
            input_work: end.input_work,
            friction_work: w.friction,
            normal_work: w.normal,
        }
    }

    /// The values in [`Self::NAMES`] order.
    pub fn values(&self) -> [f64; 6] {
        [
            self.peak_normal_force,
            self.max_slip,
            self.energy_end,
            self.input_work,
            self.friction_work,
            self.normal_work,
        ]
    }
}
