//! Which substructures can share one operator. S = 2/Δt M + Δt/2 K + k Bᵀ A B (METHOD §4) depends
//! only on the mesh up to a translation, the material and the areas on the trace; the
//! homogenized operator Z_E, L_E (METHOD §9) also on the layout of the trace and the macro bases
//! of its interfaces. Substructures equal in these share ONE factorization (METHOD §11 "factorize
//! once") and ONE homogenized operator: a granular material cut into identical cells needs only
//! a handful.
//!
//! Equality is judged on the mesh up to a translation ([`crate::mesh::Mesh::translation_key`]) and
//! on areas rounded to 1e-9 of the largest one, so that translated copies match although their
//! coordinates differ in the last bits.

use std::collections::HashMap;

use crate::macro_scale::macro_basis::MacroBasis;
use crate::substructure::Substructure;

/// Relative resolution of the comparison.
const QUANTUM: f64 = 1e-9;

/// A partition of the substructures into classes sharing an operator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Classes {
    /// Class of every substructure.
    pub of: Vec<usize>,
    /// The first substructure of every class (its operator is the one computed).
    pub representatives: Vec<usize>,
}

impl Classes {
    /// Number of distinct classes.
    pub fn count(&self) -> usize {
        self.representatives.len()
    }

    /// Every substructure its own class.
    pub fn distinct(n: usize) -> Self {
        Self {
            of: (0..n).collect(),
            representatives: (0..n).collect(),
        }
    }

    fn from_keys(keys: impl Iterator<Item = Vec<i64>>) -> Self {
        let mut seen: HashMap<Vec<i64>, usize> = HashMap::new();
        let mut of = Vec::new();
        let mut representatives = Vec::new();
        for (i, key) in keys.enumerate() {
            let next = representatives.len();
            let class = *seen.entry(key).or_insert(next);
            if class == next {
                representatives.push(i);
            }
            of.push(class);
        }
        Self {
            of,
            representatives,
        }
    }
}

fn quantize(x: f64, scale: f64) -> i64 {
    (x / (QUANTUM * scale)).round() as i64
}

/// The key of S: material, mesh up to translation, and the diagonal of Bᵀ A B.
fn operator_key(sub: &Substructure) -> Vec<i64> {
    let m = &sub.material;
    let mut key: Vec<i64> = [m.young, m.poisson, m.density]
        .iter()
        .map(|x| x.to_bits() as i64)
        .collect();
    key.extend(sub.mesh.translation_key());
    let mut diag: Vec<(usize, f64)> = Vec::with_capacity(sub.trace_len());
    let mut sums: HashMap<usize, f64> = HashMap::new();
    for ((&d, &a), &s) in sub.trace_dofs.iter().zip(&sub.trace_area).zip(&sub.trace_k) {
        *sums.entry(d).or_default() += a * s;
    }
    diag.extend(sums);
    diag.sort_unstable_by_key(|x| x.0);
    let amax = sub
        .trace_area
        .iter()
        .fold(0.0f64, |m, &a| m.max(a))
        .max(f64::MIN_POSITIVE);
    key.push(diag.len() as i64);
    for (d, a) in diag {
        key.push(d as i64);
        key.push(quantize(a, amax));
    }
    // mortar rows k s A b bᵀ: their dofs and weighted entries
    let first = sub.trace_dofs.len();
    for r in 0..sub.trace_mortar.len() {
        let j = first + r;
        let (dofs, weights) = sub.trace_mortar.row(r);
        key.push(-(dofs.len() as i64) - 1);
        for (&d, &w) in dofs.iter().zip(weights) {
            key.push(d as i64);
            key.push(quantize(sub.trace_area[j] * sub.trace_k[j] * w, amax));
        }
    }
    key
}

/// Classes of substructures with the same operator S (one factorization each).
pub fn factor_classes(subs: &[Substructure]) -> Classes {
    Classes::from_keys(subs.iter().map(operator_key))
}

/// Classes of substructures with the same homogenized operator: same S, same trace layout and
/// areas, same macro bases on the same trace slices. `bases[i]` is the macro basis of interface
/// i (None for boundary interfaces), `sides_of(sub)` the (interface, trace offset) of each of its
/// sides in trace order.
pub fn homogenized_classes(
    subs: &[Substructure],
    factors: &Classes,
    bases: &[Option<MacroBasis>],
    offsets: &dyn Fn(usize) -> Vec<(usize, usize)>,
) -> Classes {
    Classes::from_keys(subs.iter().enumerate().map(|(s, sub)| {
        let mut key = vec![factors.of[s] as i64, sub.trace_len() as i64];
        key.extend(sub.trace_dofs.iter().map(|&d| d as i64));
        for r in 0..sub.trace_mortar.len() {
            key.extend(sub.trace_mortar.row(r).0.iter().map(|&d| -(d as i64) - 1));
        }
        let amax = sub
            .trace_area
            .iter()
            .fold(0.0f64, |m, &a| m.max(a))
            .max(f64::MIN_POSITIVE);
        key.extend(sub.trace_area.iter().map(|&a| quantize(a, amax)));
        key.extend(sub.trace_k.iter().map(|&s| quantize(s, 1.0)));
        for (i, offset) in offsets(s) {
            let Some(b) = &bases[i] else { continue };
            key.extend([-1, offset as i64, b.count as i64]);
            key.extend(b.e.iter().map(|&x| quantize(x, 1.0 / amax.sqrt())));
        }
        key
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_keys_share_a_class_in_order_of_first_appearance() {
        let c = Classes::from_keys([vec![1], vec![2], vec![1], vec![3], vec![2]].into_iter());
        assert_eq!(c.of, vec![0, 1, 0, 2, 1]);
        assert_eq!(c.representatives, vec![0, 1, 3]);
        assert_eq!(c.count(), 3);
    }
}
