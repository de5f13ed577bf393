//! A substructure: a mesh, one isotropic material (with its Rayleigh damping), its lumped mass M
//! and stiffness K (METHOD §1–§2), its initial velocity, and its trace: the interface dofs that B
//! selects, with their areas A (METHOD §11 layout: sides concatenated, node-major, component-minor).

use std::collections::HashMap;
use std::sync::Arc;

use faer::sparse::Triplet;

use crate::elements::hex8;
use crate::elements::material::Material;
use crate::elements::tet4;
pub use crate::interfaces::mortar_trace::MortarRows;
use crate::linalg::factor::FactorFailure;
use crate::linalg::sparse::SymmetricMatrix;
use crate::mesh::{Element, Mesh, Vec3};
use crate::time::time_scheme::StepCoefficients;

/// A substructure with its assembled mass and stiffness.
#[derive(Debug, Clone)]
pub struct Substructure {
    /// Name, e.g. `A` or `A[1,0,0]`.
    pub name: String,
    /// Name of the body it was cut from.
    pub body: String,
    /// Index of the material in the problem's material list.
    pub material_id: usize,
    /// Mesh.
    pub mesh: Mesh,
    /// Material.
    pub material: Material,
    /// Lumped mass per dof (diagonal of M).
    pub mass: Vec<f64>,
    /// Stiffness K (shared by substructures with the same mesh up to a translation and the
    /// same material, see [`StiffnessCache`]).
    pub stiffness: Arc<SymmetricMatrix>,
    /// Uniform initial velocity v0 (u0 = 0).
    pub initial_velocity: Vec3,
    /// Substructure dof of each trace entry (B).
    pub trace_dofs: Vec<usize>,
    /// The trace entries past `trace_dofs`: the mortar sides of non-matching interfaces, each
    /// entry a combination of dofs (the rows of B that are not selections).
    pub trace_mortar: MortarRows,
    /// Area A of each trace entry.
    pub trace_area: Vec<f64>,
    /// Search direction factor per trace dof (k_j = k · trace_k[j]; all 1 for the scalar k,
    /// [`crate::interfaces::search_direction`]).
    pub trace_k: Vec<f64>,
    /// The interface sides whose dofs make up the trace, in trace order.
    pub sides: Vec<SideRef>,
    /// The prestressed state the dynamics start from (None: unloaded, u₀ = 0, F₀ = 0).
    pub prestress: Option<Arc<Prestress>>,
}

/// A substructure's static equilibrium under preload ([`crate::problem::Problem::statics`]):
/// the dynamics start from it at rest.
#[derive(Debug, Clone, PartialEq)]
pub struct Prestress {
    /// Displacement u₀ per dof.
    pub displacement: Vec<f64>,
    /// Interface traction F₀ per trace dof (trace layout).
    pub traction: Vec<f64>,
}

/// One side of an interface, as a substructure's trace holds it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SideRef {
    /// Index of the interface in the problem.
    pub interface: usize,
    /// Which of its sides (0 or 1; boundaries have one).
    pub side: usize,
}

/// Stiffness matrices already assembled, by mesh up to a translation
/// ([`Mesh::translation_key`]) and material.
#[derive(Debug, Default)]
pub struct StiffnessCache(HashMap<Vec<i64>, Arc<SymmetricMatrix>>);

impl StiffnessCache {
    fn key(mesh: &Mesh, material_id: usize) -> Vec<i64> {
        let mut key = vec![material_id as i64];
        key.extend(mesh.translation_key());
        key
    }
}

impl Substructure {
    /// What a failed factorization of S means for this substructure: the body, the node and
    /// component of the unknown whose pivot was not positive, where it lies and the elements
    /// around it (numbered from 0 in the substructure's mesh), and the mass and stiffness on it.
    pub fn describe_failure(&self, failure: &FactorFailure) -> String {
        let Some(dof) = failure.dof.filter(|&d| d < self.ndof()) else {
            return format!("{} (body `{}`)", failure.reason, self.body);
        };
        let (node, component) = (dof / 3, ["x", "y", "z"][dof % 3]);
        let elements: Vec<String> = self
            .mesh
            .elements
            .iter()
            .enumerate()
            .filter(|(_, e)| e.nodes().contains(&node))
            .take(8)
            .map(|(i, _)| i.to_string())
            .collect();
        let x = self.mesh.nodes.get(node).copied().unwrap_or([f64::NAN; 3]);
        format!(
            "{} at node {node} ({:.6e}, {:.6e}, {:.6e}) of body `{}`, component {component}, in \
             element{} {} (lumped mass {:e} kg): check the material and the shape of the \
             elements there",
            failure.reason,
            x[0],
            x[1],
            x[2],
            self.body,
            if elements.len() == 1 { "" } else { "s" },
            elements.join(", "),
            self.mass.get(dof).copied().unwrap_or(f64::NAN),
        )
    }

    /// Assembles M (lumped) and K of a mesh made of one material.
    pub fn assemble(
        name: String,
        body: String,
        material_id: usize,
        mesh: Mesh,
        material: Material,
        initial_velocity: Vec3,
    ) -> Self {
        Self::assemble_cached(
            name,
            body,
            material_id,
            mesh,
            material,
            initial_velocity,
            &mut StiffnessCache::default(),
        )
    }

    /// Like [`Substructure::assemble`], reusing the stiffness of an earlier substructure of the
    /// cache with the same mesh up to a translation and the same material (a granular cube of
    /// 648 cells assembles a handful of matrices, not 648).
    pub fn assemble_cached(
        name: String,
        body: String,
        material_id: usize,
        mesh: Mesh,
        material: Material,
        initial_velocity: Vec3,
        cache: &mut StiffnessCache,
    ) -> Self {
        let key = StiffnessCache::key(&mesh, material_id);
        let shared = cache.0.get(&key).cloned();
        let n = mesh.ndof();
        let mut mass = vec![0.0; n];
        let mut triplets = Vec::with_capacity(mesh.elements.len() * 576);
        for element in &mesh.elements {
            match element {
                Element::Hex8(nodes) => {
                    let x: [Vec3; 8] = std::array::from_fn(|a| mesh.nodes[nodes[a]]);
                    scatter_mass(&mut mass, nodes, &hex8::lumped_mass(&x, &material));
                    if shared.is_none() {
                        scatter(&mut triplets, nodes, hex8::stiffness(&x, &material).iter());
                    }
                }
                Element::Tet4(nodes) => {
                    let x: [Vec3; 4] = std::array::from_fn(|a| mesh.nodes[nodes[a]]);
                    scatter_mass(&mut mass, nodes, &tet4::lumped_mass(&x, &material));
                    if shared.is_none() {
                        scatter(&mut triplets, nodes, tet4::stiffness(&x, &material).iter());
                    }
                }
            }
        }
        let stiffness = shared.unwrap_or_else(|| {
            let k = Arc::new(SymmetricMatrix::from_triplets(n, &triplets));
            cache.0.insert(key, Arc::clone(&k));
            k
        });
        Self {
            name,
            body,
            material_id,
            mesh,
            material,
            mass,
            stiffness,
            initial_velocity,
            trace_dofs: Vec::new(),
            trace_mortar: MortarRows::default(),
            trace_area: Vec::new(),
            trace_k: Vec::new(),
            sides: Vec::new(),
            prestress: None,
        }
    }

    /// Number of dofs.
    pub fn ndof(&self) -> usize {
        self.mass.len()
    }

    /// Length of the trace vector.
    pub fn trace_len(&self) -> usize {
        self.trace_dofs.len() + self.trace_mortar.len()
    }

    /// (B v)_j: trace entry j of the dof vector v.
    #[inline]
    pub fn trace_value(&self, j: usize, v: &[f64]) -> f64 {
        match self.trace_dofs.get(j) {
            Some(&d) => v[d],
            None => self.trace_mortar.value(j - self.trace_dofs.len(), v),
        }
    }

    /// out += x Bᵀ e_j: a value x of trace entry j spread on its dofs.
    #[inline]
    pub fn add_trace(&self, j: usize, x: f64, out: &mut [f64]) {
        match self.trace_dofs.get(j) {
            Some(&d) => out[d] += x,
            None => self.trace_mortar.add(j - self.trace_dofs.len(), x, out),
        }
    }

    /// The component (0, 1, 2 for x, y, z) of trace entry j.
    pub fn trace_component(&self, j: usize) -> usize {
        match self.trace_dofs.get(j) {
            Some(&d) => d % 3,
            None => self.trace_mortar.component(j - self.trace_dofs.len()),
        }
    }

    /// Initial velocity field v0.
    pub fn initial_velocity_field(&self) -> Vec<f64> {
        let mut v = vec![0.0; self.ndof()];
        for (i, x) in v.iter_mut().enumerate() {
            *x = self.initial_velocity[i % 3];
        }
        v
    }

    /// The coefficients (c_M + α, c_K + β) of M and K in the step operator S: the scheme's, plus
    /// the material's Rayleigh damping C = α M + β K ([`crate::elements::rayleigh`]).
    pub fn operator_coefficients(&self, time: &StepCoefficients) -> (f64, f64) {
        if time.statics {
            return (time.mass, time.stiffness);
        }
        let d = self.material.damping;
        (time.mass + d.alpha, time.stiffness + d.beta)
    }

    /// Lower-triangle triplets of S = (c_M + α) M + (c_K + β) K + Bᵀ A K B, K = k diag(trace_k)
    /// (a mortar row b adds k s A b bᵀ, coupling the dofs of its row)
    /// (METHOD §4; 2/Δt M + Δt/2 K for the trapezoidal rule without damping,
    /// [`crate::time::time_scheme`]).
    pub fn operator_triplets(
        &self,
        time: &StepCoefficients,
        k: f64,
    ) -> Vec<Triplet<usize, usize, f64>> {
        let (cm, ck) = self.operator_coefficients(time);
        let mut t: Vec<Triplet<usize, usize, f64>> = self
            .stiffness
            .lower_entries()
            .map(|(r, c, v)| Triplet::new(r, c, ck * v))
            .collect();
        for (i, &m) in self.mass.iter().enumerate() {
            t.push(Triplet::new(i, i, cm * m));
        }
        for ((&d, &a), &s) in self
            .trace_dofs
            .iter()
            .zip(&self.trace_area)
            .zip(&self.trace_k)
        {
            t.push(Triplet::new(d, d, k * s * a));
        }
        let first = self.trace_dofs.len();
        for r in 0..self.trace_mortar.len() {
            let j = first + r;
            let c = k * self.trace_k[j] * self.trace_area[j];
            let (dofs, weights) = self.trace_mortar.row(r);
            for (p, (&dp, &wp)) in dofs.iter().zip(weights).enumerate() {
                for (&dq, &wq) in dofs[..=p].iter().zip(weights) {
                    let (row, col) = if dp >= dq { (dp, dq) } else { (dq, dp) };
                    t.push(Triplet::new(row, col, c * wp * wq));
                }
            }
        }
        t
    }
}

/// Adds an element's lumped nodal masses to every component of its nodes.
fn scatter_mass(mass: &mut [f64], nodes: &[usize], me: &[f64]) {
    for (&n, &m) in nodes.iter().zip(me) {
        for c in 0..3 {
            mass[3 * n + c] += m;
        }
    }
}

/// Adds an element stiffness (rows of 3·nodes entries, dof = 3·local node + component) to the
/// triplets of the substructure.
fn scatter<'a, const D: usize>(
    triplets: &mut Vec<Triplet<usize, usize, f64>>,
    nodes: &[usize],
    rows: impl Iterator<Item = &'a [f64; D]>,
) {
    for (i, row) in rows.enumerate() {
        let gi = 3 * nodes[i / 3] + i % 3;
        for (j, &v) in row.iter().enumerate() {
            let gj = 3 * nodes[j / 3] + j % 3;
            triplets.push(Triplet::new(gi, gj, v));
        }
    }
}
