//! The rows of a substructure's trace operator B that are not selections of one dof: on the
//! mortar side of a non-matching interface, the trace entry of interface node q and component c
//! is Σ_m P_qm v_{3m+c} ([`crate::interfaces::mortar`]; METHOD §1, §4: B and Bᵀ A in the linear
//! stage). They follow the selected entries in the trace.

use crate::interfaces::interface::Projection;

/// Trace rows as combinations of dofs.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MortarRows {
    starts: Vec<usize>,
    dofs: Vec<usize>,
    weights: Vec<f64>,
}

impl MortarRows {
    /// Number of rows.
    pub fn len(&self) -> usize {
        self.starts.len().saturating_sub(1)
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends the three rows (x, y, z) of every row of a projection, node-major.
    pub fn push_projection(&mut self, p: &Projection) {
        if self.starts.is_empty() {
            self.starts.push(0);
        }
        for q in 0..p.rows() {
            let (nodes, weights) = p.row_slices(q);
            for c in 0..3 {
                self.dofs.extend(nodes.iter().map(|&m| 3 * m + c));
                self.weights.extend_from_slice(weights);
                self.starts.push(self.dofs.len());
            }
        }
    }

    /// Row r: its dofs and weights.
    #[inline]
    pub fn row(&self, r: usize) -> (&[usize], &[f64]) {
        let range = self.starts[r]..self.starts[r + 1];
        (&self.dofs[range.clone()], &self.weights[range])
    }

    /// Σ_t w_t v[d_t] over row r.
    #[inline]
    pub fn value(&self, r: usize, v: &[f64]) -> f64 {
        let (dofs, weights) = self.row(r);
        dofs.iter().zip(weights).map(|(&d, &w)| w * v[d]).sum()
    }

    /// out[d_t] += w_t x over row r.
    #[inline]
    pub fn add(&self, r: usize, x: f64, out: &mut [f64]) {
        let (dofs, weights) = self.row(r);
        for (&d, &w) in dofs.iter().zip(weights) {
            out[d] += w * x;
        }
    }

    /// The component of row r (rows come in x, y, z triples).
    pub fn component(&self, r: usize) -> usize {
        r % 3
    }
}
