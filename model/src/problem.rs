//! The discrete problem: substructures, interfaces, materials and the time grid, with the
//! interface parameters that can change without refactorizing anything (friction, gap;
//! METHOD §8).

use crate::elements::material::Material;
use crate::interfaces::interface::{BoundaryDof, DofLaw, Interface, Law};
use crate::substructure::{Prestress, Substructure};
use crate::time::time_function::{TimeFunction, TimeGrid};
use crate::time::time_scheme::{StepCoefficients, TimeScheme};

/// A material of the scene, with the name its bodies refer to it by.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedMaterial {
    /// Name in the scene file.
    pub name: String,
    /// Elastic constants and density.
    pub material: Material,
}

/// A static equilibrium the dynamics start from: per substructure its displacement and
/// interface tractions ([`Prestress`]), and per interface (contact ones) the gaps it leaves,
/// g0 + [u_n].
#[derive(Debug, Clone, PartialEq)]
pub struct StaticState {
    /// One per substructure.
    pub subs: Vec<Prestress>,
    /// One per interface: Some for a contact interface, one gap per node.
    pub gaps: Vec<Option<Vec<f64>>>,
}

/// A decomposed structure ready to be solved.
#[derive(Debug, Clone)]
pub struct Problem {
    /// Scene name.
    pub name: String,
    /// Materials (index = `Substructure::material_id`).
    pub materials: Vec<NamedMaterial>,
    /// Substructures.
    pub subs: Vec<Substructure>,
    /// Interfaces.
    pub interfaces: Vec<Interface>,
    /// Time grid.
    pub time: TimeGrid,
    /// Time-integration scheme of every substructure (METHOD §2; ρ∞ = 1: trapezoidal).
    pub scheme: TimeScheme,
    /// Sign of every boundary dof's prescribed velocity or traction as built (per interface,
    /// per dof), so that an amplitude can be swept through zero.
    pub load_signs: Vec<Vec<f64>>,
    /// Named groups of interfaces with parameters of their own ([`crate::interfaces::zone`]).
    pub zones: Vec<crate::interfaces::zone::Zone>,
    /// True for the static problem of a preload ([`Self::statics`]): one step of
    /// [`StepCoefficients::STATIC`].
    pub statics: bool,
}

impl Problem {
    /// Sets the time scheme, and integrates every velocity prescribed as an acceleration with
    /// its rule ([`crate::time::time_function::Integrated`]).
    pub fn set_scheme(&mut self, scheme: TimeScheme) {
        self.scheme = scheme;
        self.integrate_accelerations();
    }

    /// Integrates every velocity prescribed as an acceleration on the time grid with the
    /// scheme's rule (those already integrated with it are kept).
    pub fn integrate_accelerations(&mut self) {
        let (dt, steps) = (self.time.dt, self.time.steps);
        let gamma = self.scheme.parameters().1;
        for iface in &mut self.interfaces {
            if let Law::Boundary(dofs) = &mut iface.law {
                for d in dofs {
                    if let DofLaw::Velocity(f) = &mut d.law {
                        f.integrate(dt, gamma, steps);
                    }
                }
            }
        }
    }

    /// The coefficients of one step of the scheme on the time grid (of statics, for the static
    /// problem of a preload).
    pub fn step_coefficients(&self) -> StepCoefficients {
        if self.statics {
            return StepCoefficients::STATIC;
        }
        self.scheme.coefficients(self.time.dt)
    }

    /// True when the dynamics start from a preload: a boundary traction marked `preload`, or a
    /// contact interference (a negative gap).
    pub fn needs_preload(&self) -> bool {
        !self.statics
            && self.interfaces.iter().any(|i| match &i.law {
                Law::Boundary(dofs) => dofs.iter().any(|d| d.preload),
                Law::Contact(c) => c.gap.iter().any(|&g| g < 0.0),
                Law::Perfect => false,
            })
    }

    /// True once the preload's static equilibrium is held by the substructures.
    pub fn is_prestressed(&self) -> bool {
        self.subs.iter().any(|s| s.prestress.is_some())
    }

    /// The static problem of the preload: one step of statics from rest, prescribed velocities
    /// held at zero displacement, the preload tractions at their value, every other load off,
    /// contact with its gaps g0 (an interference closes) and friction; no inertia, no damping.
    pub fn statics(&self) -> Problem {
        let mut p = self.clone();
        p.statics = true;
        p.time = TimeGrid { dt: 1.0, steps: 1 };
        for s in &mut p.subs {
            s.initial_velocity = [0.0; 3];
            s.prestress = None;
            s.material.damping = crate::elements::rayleigh::Rayleigh::NONE;
        }
        for iface in &mut p.interfaces {
            match &mut iface.law {
                Law::Boundary(dofs) => {
                    for d in dofs {
                        d.law = match &d.law {
                            DofLaw::Velocity(_) => DofLaw::Velocity(TimeFunction::constant(0.0)),
                            DofLaw::Traction(f) if d.preload => {
                                DofLaw::Traction(TimeFunction::constant(f.amplitude))
                            }
                            DofLaw::Traction(_) => DofLaw::Traction(TimeFunction::constant(0.0)),
                        };
                    }
                }
                Law::Contact(c) => c.start_gap = None,
                Law::Perfect => {}
            }
        }
        p
    }

    /// Starts the dynamics from a static equilibrium ([`StaticState`]); `None` back to the
    /// unloaded start.
    pub fn set_prestress(&mut self, state: Option<StaticState>) {
        match state {
            Some(StaticState { subs, gaps }) => {
                for (s, p) in self.subs.iter_mut().zip(subs) {
                    s.prestress = Some(std::sync::Arc::new(p));
                }
                for (iface, g) in self.interfaces.iter_mut().zip(gaps) {
                    if let Law::Contact(c) = &mut iface.law {
                        c.start_gap = g;
                    }
                }
            }
            None => {
                for s in &mut self.subs {
                    s.prestress = None;
                }
                for iface in &mut self.interfaces {
                    if let Law::Contact(c) = &mut iface.law {
                        c.start_gap = None;
                    }
                }
            }
        }
    }

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
            .map(|&i| self.materials[i].material.impedance())
            .sum::<f64>()
            / used.len() as f64
    }

    /// Length of the diagonal of the box holding every substructure (m).
    pub fn diameter(&self) -> f64 {
        let boxes: Vec<_> = self.subs.iter().map(|s| s.mesh.bounding_box()).collect();
        crate::interfaces::detect::model_diameter(&boxes)
    }

    /// Number of contact interfaces.
    pub fn contact_count(&self) -> usize {
        self.interfaces.iter().filter(|i| i.is_contact()).count()
    }

    /// Which interfaces a parameter set in `zone` reaches (None: all of them).
    fn reached(&self, zone: Option<usize>) -> Vec<bool> {
        (0..self.interfaces.len())
            .map(|i| zone.is_none_or(|z| self.zones[z].holds(i)))
            .collect()
    }

    /// Sets the friction coefficient of every contact interface (of `zone` only, if given).
    pub(crate) fn set_friction(&mut self, f: f64, zone: Option<usize>) {
        let reached = self.reached(zone);
        for (i, _) in self.interfaces.iter_mut().zip(reached).filter(|x| x.1) {
            if let Law::Contact(c) = &mut i.law {
                c.friction = f;
            }
        }
    }

    /// Records the direction of every prescribed velocity and traction (call once after
    /// building).
    pub fn record_load_signs(&mut self) {
        self.load_signs = self
            .interfaces
            .iter()
            .map(|i| match &i.law {
                Law::Boundary(d) => d.iter().map(BoundaryDof::load_sign).collect(),
                _ => Vec::new(),
            })
            .collect();
    }

    /// Sets the amplitude of every non-zero prescribed velocity (of `zone` only, if given) to
    /// `v` (m/s), keeping the directions of the scene.
    pub(crate) fn set_velocity_amplitude(&mut self, v: f64, zone: Option<usize>) {
        self.each_boundary_dof(zone, |dof, sign| dof.set_velocity_amplitude(v, sign));
    }

    /// Sets the amplitude of every non-zero prescribed traction but the preloads (of `zone`
    /// only, if given) to `t` (Pa), keeping the directions of the scene.
    pub(crate) fn set_traction_amplitude(&mut self, t: f64, zone: Option<usize>) {
        self.each_boundary_dof(zone, |dof, sign| {
            if !dof.preload {
                dof.set_traction_amplitude(t, sign);
            }
        });
    }

    /// Sets the amplitude of every preload traction (of `zone` only, if given) to `p` (Pa),
    /// keeping the directions of the scene.
    pub(crate) fn set_preload(&mut self, p: f64, zone: Option<usize>) {
        self.each_boundary_dof(zone, |dof, sign| {
            if dof.preload {
                dof.set_traction_amplitude(p, sign);
            }
        });
    }

    /// Sets the amplitude of every non-zero prescribed acceleration (of `zone` only, if given)
    /// to `a` (m/s²), keeping the directions of the scene.
    pub(crate) fn set_acceleration_amplitude(&mut self, a: f64, zone: Option<usize>) {
        self.each_boundary_dof(zone, |dof, sign| dof.set_acceleration_amplitude(a, sign));
    }

    /// Sets the duration of every pulse a boundary prescribes (of `zone` only, if given),
    /// scaling a trapezoid's rise with it.
    pub(crate) fn set_pulse_duration(&mut self, t: f64, zone: Option<usize>) {
        self.each_boundary_dof(zone, |dof, _| dof.set_pulse_duration(t));
    }

    /// Calls `change` on every boundary dof (of `zone` only, if given) with the sign of its
    /// amplitude as built.
    fn each_boundary_dof(
        &mut self,
        zone: Option<usize>,
        mut change: impl FnMut(&mut BoundaryDof, f64),
    ) {
        let reached = self.reached(zone);
        for ((i, signs), _) in self
            .interfaces
            .iter_mut()
            .zip(&self.load_signs)
            .zip(reached)
            .filter(|x| x.1)
        {
            if let Law::Boundary(d) = &mut i.law {
                for (dof, &sign) in d.iter_mut().zip(signs) {
                    change(dof, sign);
                }
            }
        }
    }

    /// Sets the initial gap g0 of every node of every contact interface (of `zone` only, if
    /// given).
    pub(crate) fn set_gap(&mut self, g0: f64, zone: Option<usize>) {
        let reached = self.reached(zone);
        for (i, _) in self.interfaces.iter_mut().zip(reached).filter(|x| x.1) {
            if let Law::Contact(c) = &mut i.law {
                c.gap.iter_mut().for_each(|g| *g = g0);
            }
        }
    }
}
