//! The discrete problem: substructures, interfaces, materials and the time grid, with the
//! interface parameters that can change without refactorizing anything (friction, gap;
//! METHOD §8).

use crate::interface::{Interface, Law};
use crate::material::Material;
use crate::substructure::Substructure;
use crate::time_function::TimeGrid;

/// A decomposed structure ready to be solved.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Scene name.
    pub name: String,
    /// Materials (index = `Substructure::material_id`).
    pub materials: Vec<(String, Material)>,
    /// Substructures.
    pub subs: Vec<Substructure>,
    /// Interfaces.
    pub interfaces: Vec<Interface>,
    /// Time grid.
    pub time: TimeGrid,
}

impl Problem {
    /// Total number of dofs.
    pub fn dof_count(&self) -> usize {
        self.subs.iter().map(Substructure::ndof).sum()
    }

    /// Baseline search direction k0 = mean of √(ρE) over the materials in use (METHOD §10).
    pub fn default_k(&self) -> f64 {
        let mut used: Vec<usize> = self.subs.iter().map(|s| s.material_id).collect();
        used.sort_unstable();
        used.dedup();
        used.iter()
            .map(|&i| self.materials[i].1.impedance())
            .sum::<f64>()
            / used.len() as f64
    }

    /// Number of contact interfaces.
    pub fn contact_count(&self) -> usize {
        self.interfaces.iter().filter(|i| i.is_contact()).count()
    }

    /// Sets the friction coefficient of every contact interface.
    pub fn set_friction(&mut self, f: f64) {
        for i in &mut self.interfaces {
            if let Law::Contact(c) = &mut i.law {
                c.friction = f;
            }
        }
    }

    /// Sets the initial gap g0 of every node of every contact interface.
    pub fn set_gap(&mut self, g0: f64) {
        for i in &mut self.interfaces {
            if let Law::Contact(c) = &mut i.law {
                c.gap.iter_mut().for_each(|g| *g = g0);
            }
        }
    }
}
