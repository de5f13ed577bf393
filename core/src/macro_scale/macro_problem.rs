//! The macro problem of the two-scale linear stage (METHOD §9): the macro bases of all internal
//! interfaces (perfect and contact), the homogenized operators
//!
//!   Z_E = S⁻¹ Bᵀ A s Ê,   L_E = k Êᵀ A s Ê − k² Êᵀ A s B Z_E (s the direction factors of
//!   [`crate::interfaces::search_direction`]; s = 1 gives k I − k² Êᵀ A B Z_E),
//!
//! computed once per class of identical substructures ([`crate::macro_scale::operator_classes`]), and the
//! global macro operator L = Σ_E L_E over the macro dofs (9 per planar interface), assembled and
//! factorized once. Per time step: the macro right-hand side b = −Σ_E Êᵀ A F¹ (step 2), the
//! solve L α = b (step 3), and per substructure the correction data of step 4.
//!
//! In a distributed run ([`crate::distributed::distribution`]) a rank homogenizes the classes with a
//! substructure on it (from the class representative, as on one machine: every rank holds the
//! whole problem description); the L_E of every class comes from the rank of its
//! representative by an exact all-sum, and every rank assembles and factorizes the same L (the
//! macro problem is replicated: it is small, and one solve per step costs less than a
//! broadcast).

use crate::distributed::distribution::Distribution;
use crate::error::{LopinError, Result};
use crate::linalg::factor::{CholeskyFactor, SolveScratch};
use crate::macro_scale::macro_basis::MacroBasis;
use crate::macro_scale::operator_classes::{homogenized_classes, Classes};
use crate::par;
use crate::problem::Problem;
use crate::substructure::SideRef;
use faer::sparse::Triplet;

/// One macro side of a substructure: an internal interface on its trace.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MacroSide {
    /// Interface index.
    pub interface: usize,
    /// Offset of the side in the substructure's trace.
    pub trace_offset: usize,
    /// Offset of the interface's functions among the substructure's macro unknowns.
    pub local: usize,
}

/// The homogenized operator of a class of substructures.
#[derive(Debug, Clone)]
pub struct Homogenized {
    /// Macro unknowns n_M,E.
    pub count: usize,
    /// Z_E, dofs × n_M,E, column-major (empty on a rank without a substructure of the class).
    pub z: Vec<f64>,
    /// L_E, n_M,E × n_M,E, row-major (symmetric).
    pub l: Vec<f64>,
}

/// The assembled and factorized macro problem.
#[derive(Debug)]
pub struct MacroProblem {
    /// Macro basis of every interface (None: boundary interfaces carry no macro unknowns).
    pub bases: Vec<Option<MacroBasis>>,
    /// First global macro dof of every interface (meaningful where it has a basis).
    pub offsets: Vec<usize>,
    /// Number of global macro dofs.
    pub size: usize,
    /// Macro sides of every substructure, in trace order.
    pub sides: Vec<Vec<MacroSide>>,
    /// Global macro dof of each macro unknown of every substructure.
    pub global: Vec<Vec<usize>>,
    /// Homogenized class of every substructure and the class representatives.
    pub classes: Classes,
    /// Homogenized operator of every class.
    pub homogenized: Vec<Homogenized>,
    /// Cholesky factor of L.
    factor: CholeskyFactor,
    /// Non-zeros of the assembled L (lower triangle).
    pub operator_nnz: usize,
}

impl MacroProblem {
    /// Builds the macro bases, the homogenized operators (one per class; `factors[c]` is the
    /// factorization of S of the substructures of `factor_classes` class c) and the factorized
    /// global operator. `factors[c]` is None for a class with no substructure on this rank of
    /// `distribution`.
    pub fn new(
        problem: &Problem,
        k: f64,
        factor_classes: &Classes,
        factors: &[Option<CholeskyFactor>],
        distribution: &Distribution,
    ) -> Result<Self> {
        let factor_of = |s: usize| factors[factor_classes.of[s]].as_ref();
        let mut offsets = vec![0; problem.interfaces.len()];
        let mut size = 0;
        let bases: Vec<Option<MacroBasis>> = problem
            .interfaces
            .iter()
            .enumerate()
            .map(|(i, iface)| {
                (iface.sides.len() == 2).then(|| {
                    let b = MacroBasis::of_interface(
                        iface,
                        &problem.subs[iface.sides[0].sub].mesh.nodes,
                    );
                    offsets[i] = size;
                    size += b.count;
                    b
                })
            })
            .collect();
        let sides: Vec<Vec<MacroSide>> = problem
            .subs
            .iter()
            .map(|sub| {
                let mut local = 0;
                sub.sides
                    .iter()
                    .filter_map(|&SideRef { interface: i, side }| {
                        let b = bases[i].as_ref()?;
                        let s = MacroSide {
                            interface: i,
                            trace_offset: problem.interfaces[i].sides[side].offset,
                            local,
                        };
                        local += b.count;
                        Some(s)
                    })
                    .collect()
            })
            .collect();
        let classes = homogenized_classes(&problem.subs, factor_classes, &bases, &|s| {
            sides[s]
                .iter()
                .map(|m| (m.interface, m.trace_offset))
                .collect()
        });
        let needed = distribution.holds_classes(&classes.of, classes.count());
        let mut homogenized = par::map_range(classes.count(), |c| {
            let s = classes.representatives[c];
            match factor_of(s) {
                Some(factor) if needed[c] => homogenize(problem, s, &sides[s], &bases, k, factor),
                _ => Homogenized {
                    count: macro_count(&sides[s], &bases),
                    z: Vec::new(),
                    l: Vec::new(),
                },
            }
        });
        share_operators(&mut homogenized, &classes, distribution);
        let global: Vec<Vec<usize>> = sides
            .iter()
            .map(|sub_sides| {
                sub_sides
                    .iter()
                    .flat_map(|m| {
                        let count = bases[m.interface].as_ref().map_or(0, |b| b.count);
                        offsets[m.interface]..offsets[m.interface] + count
                    })
                    .collect()
            })
            .collect();
        let mut triplets = Vec::new();
        for (s, global) in global.iter().enumerate() {
            let h = &homogenized[classes.of[s]];
            for (a, &ga) in global.iter().enumerate() {
                for (b, &gb) in global.iter().enumerate() {
                    if ga >= gb {
                        triplets.push(Triplet::new(ga, gb, h.l[a * h.count + b]));
                    }
                }
            }
        }
        let operator_nnz = {
            let mut keys: Vec<(usize, usize)> = triplets.iter().map(|t| (t.row, t.col)).collect();
            keys.sort_unstable();
            keys.dedup();
            keys.len()
        };
        let factor = if size == 0 {
            CholeskyFactor::new(1, &[Triplet::new(0, 0, 1.0)])
        } else {
            CholeskyFactor::new(size, &triplets)
        }
        .map_err(|reason| LopinError::Factorization {
            sub: "macro problem".into(),
            reason,
        })?;
        Ok(Self {
            bases,
            offsets,
            size,
            sides,
            global,
            classes,
            homogenized,
            factor,
            operator_nnz,
        })
    }

    /// Scratch for [`MacroProblem::solve_in_place`].
    pub fn scratch(&self) -> SolveScratch {
        self.factor.scratch()
    }

    /// α ← L⁻¹ b (METHOD §9 step 3).
    pub fn solve_in_place(&self, b: &mut [f64], scratch: &mut SolveScratch) {
        if self.size > 0 {
            self.factor.solve_in_place(b, scratch);
        }
    }

    /// Stored values of the Cholesky factor of L.
    pub fn factor_nnz(&self) -> usize {
        self.factor.factor_nnz()
    }

    /// The homogenized operator of substructure `s`.
    pub fn homogenized_of(&self, s: usize) -> &Homogenized {
        &self.homogenized[self.classes.of[s]]
    }

    /// Macro forces Êᵀ A F of substructure `s`'s trace field `f` (its macro unknowns' order),
    /// added into `out`.
    pub fn project(&self, s: usize, area: &[f64], f: &[f64], out: &mut [f64]) {
        for m in &self.sides[s] {
            let Some(b) = &self.bases[m.interface] else {
                continue;
            };
            let r = m.trace_offset..m.trace_offset + b.len;
            b.project_add(
                &area[r.clone()],
                &f[r],
                1.0,
                &mut out[m.local..m.local + b.count],
            );
        }
    }

    /// Ê α on substructure `s`'s trace (zero off its macro sides), for its macro unknowns α.
    pub fn expand(&self, s: usize, alpha: &[f64], trace: &mut [f64]) {
        trace.iter_mut().for_each(|x| *x = 0.0);
        for m in &self.sides[s] {
            let Some(b) = &self.bases[m.interface] else {
                continue;
            };
            b.expand_add(
                &alpha[m.local..m.local + b.count],
                &mut trace[m.trace_offset..m.trace_offset + b.len],
            );
        }
    }
}

/// Macro unknowns of a substructure with these macro sides.
fn macro_count(sides: &[MacroSide], bases: &[Option<MacroBasis>]) -> usize {
    sides
        .iter()
        .filter_map(|m| bases[m.interface].as_ref().map(|b| b.count))
        .sum()
}

/// Gives every rank the L_E of every class, from the rank of the class representative.
fn share_operators(
    homogenized: &mut [Homogenized],
    classes: &Classes,
    distribution: &Distribution,
) {
    if distribution.is_single() {
        return;
    }
    let mut flat = Vec::new();
    for (c, h) in homogenized.iter().enumerate() {
        let from_here = distribution.holds_sub(classes.representatives[c]);
        let n = h.count * h.count;
        if from_here {
            flat.extend_from_slice(&h.l);
        } else {
            flat.extend(std::iter::repeat_n(-0.0, n));
        }
    }
    distribution.all_sum(&mut flat);
    let mut at = 0;
    for h in homogenized.iter_mut() {
        let n = h.count * h.count;
        h.l.clear();
        h.l.extend_from_slice(&flat[at..at + n]);
        at += n;
    }
}

/// Z_E and L_E of substructure `s` (METHOD §9 "Homogenised operator").
fn homogenize(
    problem: &Problem,
    s: usize,
    sides: &[MacroSide],
    bases: &[Option<MacroBasis>],
    k: f64,
    factor: &CholeskyFactor,
) -> Homogenized {
    let sub = &problem.subs[s];
    let n = sub.ndof();
    let count = macro_count(sides, bases);
    // Bᵀ A Ê, column by column
    let mut z = vec![0.0; n * count];
    for m in sides {
        let Some(b) = &bases[m.interface] else {
            continue;
        };
        for c in 0..b.count {
            let col = &mut z[(m.local + c) * n..(m.local + c + 1) * n];
            for (j, e) in b.column(c).iter().enumerate() {
                let t = m.trace_offset + j;
                sub.add_trace(t, sub.trace_area[t] * sub.trace_k[t] * e, col);
            }
        }
    }
    if count > 0 {
        factor.solve_many_in_place(&mut z, count);
    }
    // L_E = k Êᵀ A s Ê − k² Êᵀ A s B Z_E (= k I − k² Êᵀ A B Z_E for the scalar direction:
    // Ê is A-orthonormal per interface)
    let mut l = vec![0.0; count * count];
    let scalar = sub.trace_k.iter().all(|&s| s == 1.0);
    for a in 0..count {
        l[a * count + a] = k;
    }
    if !scalar {
        for m in sides {
            let Some(b) = &bases[m.interface] else {
                continue;
            };
            for c in 0..b.count {
                for d in 0..b.count {
                    let s: f64 = b
                        .column(c)
                        .iter()
                        .zip(b.column(d))
                        .enumerate()
                        .map(|(j, (ec, ed))| {
                            let t = m.trace_offset + j;
                            ec * sub.trace_area[t] * sub.trace_k[t] * ed
                        })
                        .sum();
                    l[(m.local + c) * count + m.local + d] = k * s;
                }
            }
        }
    }
    for m in sides {
        let Some(b) = &bases[m.interface] else {
            continue;
        };
        for c in 0..b.count {
            let e = b.column(c);
            for col in 0..count {
                let zc = &z[col * n..(col + 1) * n];
                let s: f64 = e
                    .iter()
                    .enumerate()
                    .map(|(j, ej)| {
                        let t = m.trace_offset + j;
                        ej * sub.trace_area[t] * sub.trace_k[t] * sub.trace_value(t, zc)
                    })
                    .sum();
                l[(m.local + c) * count + col] -= k * k * s;
            }
        }
    }
    // symmetric in exact arithmetic: remove the rounding asymmetry
    for a in 0..count {
        for b in 0..a {
            let mean = 0.5 * (l[a * count + b] + l[b * count + a]);
            l[a * count + b] = mean;
            l[b * count + a] = mean;
        }
    }
    Homogenized { count, z, l }
}
