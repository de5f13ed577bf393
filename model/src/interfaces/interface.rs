//! Interfaces between substructures and with the outside: their sides, nodal areas A, normals and
//! behaviour (METHOD §1 notation, §5 laws). An interface side owns a contiguous slice of its
//! substructure's trace vector (node-major, component-minor: METHOD §11 data layout).

use crate::mesh::Vec3;
use crate::time::time_function::{Integrated, Shape, TimeFunction};

/// One side of an interface: which substructure, where its dofs sit in that substructure's trace
/// vector, and which mesh nodes they belong to.
#[derive(Debug, Clone, PartialEq)]
pub struct Side {
    /// Substructure index.
    pub sub: usize,
    /// Offset of this side's first dof in the substructure's trace vector.
    pub offset: usize,
    /// Mesh node of each interface node (two-sided: one per node; boundary: one per dof). On
    /// the mortar side of a non-matching interface, the node of largest weight in the
    /// projection's row: what drawings and groupings use; the trace itself is the projection.
    pub nodes: Vec<usize>,
    /// The mortar side of a non-matching interface: its trace at interface node q is
    /// Σ_m P_qm v_m ([`crate::interfaces::mortar`]); None: the nodes' own values.
    pub projection: Option<std::sync::Arc<Projection>>,
}

/// The projection P of a non-matching interface's mortar side: one row per interface node, each
/// a few (mesh node, weight) terms ([`crate::interfaces::mortar`]).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Projection {
    /// Start of each row in `nodes` and `weights` (rows + 1 entries once a row is pushed).
    pub starts: Vec<usize>,
    /// Mesh node of each term.
    pub nodes: Vec<usize>,
    /// Weight of each term.
    pub weights: Vec<f64>,
}

impl Projection {
    /// Appends a row.
    pub fn push_row(&mut self, row: &[(usize, f64)]) {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        for &(m, w) in row {
            self.nodes.push(m);
            self.weights.push(w);
        }
        self.starts.push(self.nodes.len());
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// Row q as (mesh node, weight) terms.
    pub fn row(&self, q: usize) -> Vec<(usize, f64)> {
        let r = self.starts[q]..self.starts[q + 1];
        self.nodes[r.clone()]
            .iter()
            .copied()
            .zip(self.weights[r].iter().copied())
            .collect()
    }

    /// Row q's mesh nodes and weights as slices.
    pub fn row_slices(&self, q: usize) -> (&[usize], &[f64]) {
        let r = self.starts[q]..self.starts[q + 1];
        (&self.nodes[r.clone()], &self.weights[r])
    }
}

/// What a boundary dof prescribes (METHOD §5, per component in global axes).
#[derive(Debug, Clone, PartialEq)]
pub enum DofLaw {
    /// Prescribed velocity W_d(t).
    Velocity(TimeFunction),
    /// Prescribed traction F_d(t) (force per unit area on the substructure).
    Traction(TimeFunction),
}

/// A prescribed dof of a boundary interface.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryDof {
    /// Component 0, 1, 2 = x, y, z.
    pub component: usize,
    /// The prescription.
    pub law: DofLaw,
    /// True for a preload: a traction applied in the static phase and held from t₀.
    pub preload: bool,
    /// Factor on the law's value on this dof: 1, or for a traction along the faces' normal
    /// (a pressure) the component of the node's area-weighted normal,
    /// n_c = (Σ_f A_f n_f,c / k_f) / A_node over the node's faces f of k_f nodes, so the nodal
    /// forces add up to the traction times Σ_f A_f n_f.
    pub scale: f64,
}

impl BoundaryDof {
    /// A dof prescribed along `component` by `law` (scale 1).
    pub fn new(component: usize, law: DofLaw) -> Self {
        Self {
            component,
            law,
            preload: false,
            scale: 1.0,
        }
    }
}

/// What a boundary prescribes on every node of its faces, before the faces are known: laws per
/// component, or a traction along the faces' outward normal (a pressure p is −p), spread on
/// each node's x, y and z by its area-weighted normal ([`BoundaryDof::scale`]).
#[derive(Debug, Clone, PartialEq)]
pub enum BoundaryLoad {
    /// The same laws on every node.
    Components(Vec<BoundaryDof>),
    /// A traction along the outward normal (a preload when `preload`).
    Normal {
        /// The traction (Pa; a pressure p is −p).
        traction: TimeFunction,
        /// Applied in the static phase and held from t₀.
        preload: bool,
    },
}

impl BoundaryDof {
    /// Sets the amplitude of a non-zero prescribed velocity to `v` times the direction the
    /// scene gave it (zero velocities, e.g. clamps, and tractions are left alone).
    pub fn set_velocity_amplitude(&mut self, v: f64, nominal_sign: f64) {
        if let DofLaw::Velocity(f) = &mut self.law {
            if nominal_sign != 0.0 && f.acceleration().is_none() {
                f.amplitude = nominal_sign * v;
            }
        }
    }

    /// Sets the amplitude of a non-zero prescribed acceleration to `a` times the direction the
    /// scene gave it (other laws are left alone).
    pub fn set_acceleration_amplitude(&mut self, a: f64, nominal_sign: f64) {
        if let DofLaw::Velocity(f) = &mut self.law {
            if nominal_sign != 0.0 && f.acceleration().is_some() {
                f.amplitude = nominal_sign * a;
            }
        }
    }

    /// Sets the amplitude of a non-zero prescribed traction to `t` times the direction the
    /// scene gave it (velocities are left alone).
    pub fn set_traction_amplitude(&mut self, t: f64, nominal_sign: f64) {
        if let DofLaw::Traction(f) = &mut self.law {
            if nominal_sign != 0.0 {
                f.amplitude = nominal_sign * t;
            }
        }
    }

    /// Sets the duration of a pulse (a trapezoid's rise scaled with it; other shapes are left
    /// alone).
    pub fn set_pulse_duration(&mut self, t: f64) {
        let (DofLaw::Velocity(f) | DofLaw::Traction(f)) = &mut self.law;
        let rescale = |shape: &mut Shape| {
            if let Shape::Pulse { duration, rise, .. } = shape {
                *rise *= t / *duration;
                *duration = t;
            }
        };
        match &mut f.shape {
            // an acceleration pulse: its velocity integrated again on the same grid
            Shape::Integrated(i) => {
                let mut again = Integrated::new(i.acceleration.clone());
                rescale(&mut again.acceleration);
                if again.acceleration == i.acceleration {
                    return;
                }
                let (rule, steps) = (i.rule, i.velocity.len().saturating_sub(1));
                f.shape = Shape::Integrated(std::sync::Arc::new(again));
                if let Some((dt, gamma)) = rule {
                    f.integrate(dt, gamma, steps);
                }
            }
            shape => rescale(shape),
        }
    }

    /// The pulse duration of the law's time function (of its acceleration, for a velocity
    /// integrated from one), if it is a pulse.
    pub fn pulse_duration(&self) -> Option<f64> {
        let (DofLaw::Velocity(f) | DofLaw::Traction(f)) = &self.law;
        match f.acceleration().unwrap_or(&f.shape) {
            Shape::Pulse { duration, .. } => Some(*duration),
            _ => None,
        }
    }

    /// Sign of the prescribed velocity's or traction's amplitude (0 where it is zero).
    pub fn load_sign(&self) -> f64 {
        let (DofLaw::Velocity(f) | DofLaw::Traction(f)) = &self.law;
        if f.amplitude != 0.0 {
            f.amplitude.signum()
        } else {
            0.0
        }
    }
}

/// Unilateral contact with Coulomb friction (METHOD §5).
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// Friction coefficient f.
    pub friction: f64,
    /// Initial gap g0 per interface node (negative: an interference, closed by the preload's
    /// static phase).
    pub gap: Vec<f64>,
    /// Unit normal per node, outward of side 1 (from side 1 to side 2).
    pub normal: Vec<Vec3>,
    /// The gap per node when the dynamics start, after the preload's static phase
    /// (g0 + [u_n]; None without preload: g0).
    pub start_gap: Option<Vec<f64>>,
}

impl Contact {
    /// The gap per node at t₀ of the dynamics.
    pub fn gap_at_start(&self) -> &[f64] {
        self.start_gap.as_deref().unwrap_or(&self.gap)
    }
}

/// The behaviour of an interface.
#[derive(Debug, Clone, PartialEq)]
pub enum Law {
    /// Perfect bond: [Ŵ] = 0, F̂₁ + F̂₂ = 0.
    Perfect,
    /// Unilateral contact with Coulomb friction.
    Contact(Contact),
    /// One-sided boundary condition, one law per dof of the side.
    Boundary(Vec<BoundaryDof>),
}

/// An interface: one side (boundary) or two (perfect, contact).
#[derive(Debug, Clone, PartialEq)]
pub struct Interface {
    /// Readable name, e.g. `A|B` or `A:z+`.
    pub name: String,
    /// The sides (1 or 2).
    pub sides: Vec<Side>,
    /// Number of trace dofs on each side.
    pub len: usize,
    /// Lumped area A per trace dof (the same on both sides).
    pub area: Vec<f64>,
    /// Search direction factor per trace dof, the same on both sides: k_j = k · k_scale[j]
    /// (all 1 for the scalar k of METHOD §3, [`crate::interfaces::search_direction`]).
    pub k_scale: Vec<f64>,
    /// Behaviour.
    pub law: Law,
}

impl Interface {
    /// Number of interface nodes of a two-sided interface (len / 3).
    pub fn node_count(&self) -> usize {
        self.len / 3
    }

    /// Whether this is a contact interface.
    pub fn is_contact(&self) -> bool {
        matches!(self.law, Law::Contact(_))
    }

    /// Whether this is a boundary (one-sided) interface.
    pub fn is_boundary(&self) -> bool {
        matches!(self.law, Law::Boundary(_))
    }
}
