//! Sparse symmetric matrices assembled from element contributions (faer CSC storage) and the
//! matrix–vector product used by the linear stage (METHOD §4: r_m needs K(u + Δt/2 v)).

use faer::sparse::{SparseColMat, Triplet};

/// A symmetric sparse matrix, stored in full (both triangles) in CSC.
#[derive(Debug, Clone)]
pub struct SymmetricMatrix {
    mat: SparseColMat<usize, f64>,
}

impl SymmetricMatrix {
    /// Builds the matrix from triplets (duplicates summed). Both triangles must be given.
    pub fn from_triplets(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Self {
        let mat = SparseColMat::try_new_from_triplets(n, n, triplets).unwrap_or_else(|e| {
            unreachable!("assembly indices are in range by construction: {e:?}")
        });
        Self { mat }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.mat.nrows()
    }

    /// Number of stored non-zeros.
    pub fn nnz(&self) -> usize {
        self.mat.val().len()
    }

    /// The faer matrix.
    pub fn as_faer(&self) -> &SparseColMat<usize, f64> {
        &self.mat
    }

    /// y ← K x (symmetric, so the CSC columns are rows).
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let col_ptr = self.mat.symbolic().col_ptr();
        let row_idx = self.mat.symbolic().row_idx();
        let val = self.mat.val();
        for (j, yj) in y.iter_mut().enumerate() {
            let (start, end) = (col_ptr[j], col_ptr[j + 1]);
            let mut acc = 0.0;
            for p in start..end {
                acc += val[p] * x[row_idx[p]];
            }
            *yj = acc;
        }
    }

    /// xᵀ K x.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        let col_ptr = self.mat.symbolic().col_ptr();
        let row_idx = self.mat.symbolic().row_idx();
        let val = self.mat.val();
        let mut total = 0.0;
        for (j, xj) in x.iter().enumerate() {
            let mut acc = 0.0;
            for p in col_ptr[j]..col_ptr[j + 1] {
                acc += val[p] * x[row_idx[p]];
            }
            total += acc * xj;
        }
        total
    }

    /// Iterates the stored lower-triangle entries (row ≥ col) as (row, col, value).
    pub fn lower_entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        let col_ptr = self.mat.symbolic().col_ptr();
        let row_idx = self.mat.symbolic().row_idx();
        let val = self.mat.val();
        (0..self.n()).flat_map(move |j| {
            (col_ptr[j]..col_ptr[j + 1])
                .filter(move |&p| row_idx[p] >= j)
                .map(move |p| (row_idx[p], j, val[p]))
        })
    }
}
