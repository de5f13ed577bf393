//! The assembled structure: global lumped mass, stiffness and Rayleigh damping (element matrices of
//! every substructure summed on the merged nodes, C with each substructure's α and β), the strongly
//! imposed velocities, the prescribed tractions as nodal loads A·F_d (METHOD §1, §5 boundary laws),
//! and the contact node pairs with their local frames (METHOD §5: normal n outward of side 1,
//! tangent plane).

use faer::sparse::Triplet;
use lopin_model::time::time_scheme::StepCoefficients;

use super::numbering::Numbering;
use lopin_model::error::{LopinError, Result};
use lopin_model::interfaces::interface::{DofLaw, Law};
use lopin_model::linalg::sparse::SymmetricMatrix;
use lopin_model::mesh::{cross, dot, norm, Vec3};
use lopin_model::problem::Problem;
use lopin_model::time::time_function::TimeFunction;

/// One copy of a contact pair: the interface node it comes from and its lumped area.
#[derive(Debug, Clone, PartialEq)]
pub struct PairCopy {
    /// Interface index.
    pub interface: usize,
    /// Node index within that interface.
    pub node: usize,
    /// Lumped area A of that interface node.
    pub area: f64,
}

/// A pair of global nodes in unilateral contact with Coulomb friction. Copies from several
/// interfaces that join the same two global nodes with the same law are one pair (their areas
/// add); the nodal force is shared among them in proportion to area. On a non-matching
/// interface side 2 is a combination of nodes (the mortar projection's row,
/// `lopin_model::interfaces::mortar`), and a non-matching perfect interface is a pair of
/// them that is bonded: its relative velocity is zero (the same discrete problem as LATIN's).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// Global node of side 1.
    pub a: usize,
    /// Side 2 as (global node, weight): its one node, weight 1, on a conforming interface.
    pub across: Vec<(usize, f64)>,
    /// Bonded (a non-matching perfect interface): no unilateral law, no friction.
    pub bonded: bool,
    /// Local frame: normal n (side 1 → side 2), then two unit tangents.
    pub frame: [Vec3; 3],
    /// Friction coefficient f.
    pub friction: f64,
    /// Initial gap g₀.
    pub gap: f64,
    /// The interface nodes this pair stands for.
    pub copies: Vec<PairCopy>,
}

impl ContactPair {
    /// Total lumped area.
    pub fn area(&self) -> f64 {
        self.copies.iter().map(|c| c.area).sum()
    }

    /// Relative value [x] = Σ w x_b − x_a of component q of a nodal field.
    #[inline]
    pub fn jump(&self, x: &[f64], q: usize) -> f64 {
        let mut terms = self.across.iter().map(|&(b, w)| w * x[3 * b + q]);
        let first = terms.next().unwrap_or(0.0);
        terms.fold(first, |s, t| s + t) - x[3 * self.a + q]
    }
}

/// The assembled, undecomposed discrete problem.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// Node numbering.
    pub numbering: Numbering,
    /// Global lumped mass per dof.
    pub mass: Vec<f64>,
    /// Global stiffness.
    pub stiffness: SymmetricMatrix,
    /// Global Rayleigh damping C = Σ_E (α_E M_E + β_E K_E) (None: undamped).
    pub damping: Option<SymmetricMatrix>,
    /// Initial velocity v₀.
    pub v0: Vec<f64>,
    /// Prescribed velocity per global dof (None: free).
    pub prescribed: Vec<Option<TimeFunction>>,
    /// Prescribed tractions: (global dof, area times the dof's scale, F_d(t)).
    pub tractions: Vec<(usize, f64, TimeFunction)>,
    /// Contact pairs.
    pub pairs: Vec<ContactPair>,
    /// Index among the free dofs of each global dof (usize::MAX if prescribed).
    pub free_index: Vec<usize>,
    /// Number of free dofs.
    pub free: usize,
}

impl Assembled {
    /// Assembles a problem.
    pub fn new(problem: &Problem) -> Result<Self> {
        let numbering = Numbering::new(problem)?;
        let n = numbering.dofs();
        let mut mass = vec![0.0; n];
        let mut triplets = Vec::new();
        // C = Σ_E (α_E M_E + β_E K_E), each substructure's own coefficients
        let mut damping_triplets = Vec::new();
        for (s, sub) in problem.subs.iter().enumerate() {
            let d = sub.material.damping;
            for (dof, &m) in sub.mass.iter().enumerate() {
                let g = numbering.dof(s, dof);
                mass[g] += m;
                if d.alpha != 0.0 {
                    damping_triplets.push(Triplet::new(g, g, d.alpha * m));
                }
            }
            for (i, j, v) in sub.stiffness.entries() {
                let (gi, gj) = (numbering.dof(s, i), numbering.dof(s, j));
                triplets.push(Triplet::new(gi, gj, v));
                if d.beta != 0.0 {
                    damping_triplets.push(Triplet::new(gi, gj, d.beta * v));
                }
            }
        }
        let stiffness = SymmetricMatrix::from_triplets(n, &triplets);
        let damping = (!damping_triplets.is_empty())
            .then(|| SymmetricMatrix::from_triplets(n, &damping_triplets));
        let v0 = numbering.initial_velocity(problem);

        let mut prescribed: Vec<Option<TimeFunction>> = vec![None; n];
        let mut tractions = Vec::new();
        let mut pairs: Vec<ContactPair> = Vec::new();
        for (k, iface) in problem.interfaces.iter().enumerate() {
            match &iface.law {
                Law::Perfect if iface.sides[1].projection.is_some() => {
                    for i in 0..iface.node_count() {
                        pairs.push(ContactPair {
                            a: numbering.node_of[iface.sides[0].sub][iface.sides[0].nodes[i]],
                            across: across(&numbering, &iface.sides[1], i),
                            bonded: true,
                            frame: frame([0.0, 0.0, 1.0]),
                            friction: 0.0,
                            gap: 0.0,
                            copies: vec![PairCopy {
                                interface: k,
                                node: i,
                                area: iface.area[3 * i],
                            }],
                        });
                    }
                }
                Law::Perfect => {}
                Law::Boundary(dofs) => {
                    let side = &iface.sides[0];
                    for (j, d) in dofs.iter().enumerate() {
                        let g = 3 * numbering.node_of[side.sub][side.nodes[j]] + d.component;
                        match &d.law {
                            DofLaw::Velocity(f) => match &prescribed[g] {
                                Some(old) if old != f => {
                                    return Err(LopinError::Reference(format!(
                                        "interface `{}` prescribes a velocity on a dof that another boundary prescribes differently (node at {:?})",
                                        iface.name,
                                        problem.subs[side.sub].mesh.nodes[side.nodes[j]]
                                    )));
                                }
                                _ => prescribed[g] = Some(f.clone()),
                            },
                            DofLaw::Traction(f) => {
                                tractions.push((g, d.scale * iface.area[j], f.clone()))
                            }
                        }
                    }
                }
                Law::Contact(c) => {
                    let (s1, s2) = (&iface.sides[0], &iface.sides[1]);
                    for i in 0..iface.node_count() {
                        let a = numbering.node_of[s1.sub][s1.nodes[i]];
                        let across = across(&numbering, s2, i);
                        let copy = PairCopy {
                            interface: k,
                            node: i,
                            area: iface.area[3 * i],
                        };
                        let nrm = c.normal[i];
                        let mortar = s2.projection.is_some();
                        let same = pairs.iter_mut().find(|p| {
                            !mortar
                                && !p.bonded
                                && p.a == a
                                && p.across == across
                                && p.friction == c.friction
                                && p.gap == c.gap[i]
                                && dot(p.frame[0], nrm) > 1.0 - 1e-12
                        });
                        match same {
                            Some(p) => p.copies.push(copy),
                            None => pairs.push(ContactPair {
                                a,
                                across,
                                bonded: false,
                                frame: frame(nrm),
                                friction: c.friction,
                                gap: c.gap[i],
                                copies: vec![copy],
                            }),
                        }
                    }
                }
            }
        }
        let mut free_index = vec![usize::MAX; n];
        let mut free = 0;
        for (g, p) in prescribed.iter().enumerate() {
            if p.is_none() {
                free_index[g] = free;
                free += 1;
            }
        }
        Ok(Self {
            numbering,
            mass,
            stiffness,
            damping,
            v0,
            prescribed,
            tractions,
            pairs,
            free_index,
            free,
        })
    }

    /// Lower-triangle triplets of S_ff = (c_M M + C + c_K K) restricted to the free dofs (2/Δt M +
    /// Δt/2 K for the trapezoidal rule without damping; the coefficients of
    /// `lopin_model::time::time_scheme`).
    pub fn free_operator(&self, time: &StepCoefficients) -> Vec<Triplet<usize, usize, f64>> {
        let free = |(r, c, v): (usize, usize, f64), scale: f64| {
            let (fr, fc) = (self.free_index[r], self.free_index[c]);
            // free numbering preserves order, so row ≥ col stays lower
            (fr != usize::MAX && fc != usize::MAX).then(|| Triplet::new(fr, fc, scale * v))
        };
        let mut t: Vec<Triplet<usize, usize, f64>> = self
            .stiffness
            .lower_entries()
            .filter_map(|e| free(e, time.stiffness))
            .collect();
        if let Some(c) = &self.damping {
            t.extend(c.lower_entries().filter_map(|e| free(e, 1.0)));
        }
        for (g, &m) in self.mass.iter().enumerate() {
            let f = self.free_index[g];
            if f != usize::MAX {
                t.push(Triplet::new(f, f, time.mass * m));
            }
        }
        t
    }

    /// Sets the friction coefficient of every contact pair.
    pub fn set_friction(&mut self, f: f64) {
        self.pairs.iter_mut().for_each(|p| p.friction = f);
    }
}

/// Side 2 of interface node i as (global node, weight): the mortar projection's row, or the
/// paired node.
fn across(
    numbering: &Numbering,
    side: &lopin_model::interfaces::interface::Side,
    i: usize,
) -> Vec<(usize, f64)> {
    match &side.projection {
        Some(p) => p
            .row(i)
            .into_iter()
            .map(|(m, w)| (numbering.node_of[side.sub][m], w))
            .collect(),
        None => vec![(numbering.node_of[side.sub][side.nodes[i]], 1.0)],
    }
}

/// Orthonormal frame (n, t₁, t₂) with t₁ ⟂ n built from the axis least aligned with n.
fn frame(n: Vec3) -> [Vec3; 3] {
    let axis = (0..3)
        .min_by(|&i, &j| n[i].abs().total_cmp(&n[j].abs()))
        .unwrap_or(0);
    let mut e = [0.0; 3];
    e[axis] = 1.0;
    let t1 = cross(n, e);
    let l = norm(t1);
    let t1 = [t1[0] / l, t1[1] / l, t1[2] / l];
    [n, t1, cross(n, t1)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal() {
        for n in [[0.0, 0.0, 1.0], [0.6, 0.0, -0.8], [1.0, 0.0, 0.0]] {
            let f = frame(n);
            for i in 0..3 {
                for j in 0..3 {
                    let d = dot(f[i], f[j]);
                    let want = if i == j { 1.0 } else { 0.0 };
                    assert!((d - want).abs() < 1e-14, "{n:?} {i} {j} {d}");
                }
            }
        }
    }
}
