//! Sparse symmetric matrices assembled from element contributions and the matrix–vector
//! product used by the linear stage (METHOD §4: r_m needs K(u + Δt/2 v); a single-precision
//! factor's linear stage forms c_K K v_m, METHOD §11). Only the lower triangle is stored, in
//! compressed columns with 32-bit row indices: the product reads 12 bytes an entry of the lower
//! triangle instead of 16 bytes an entry of both, which is what it is bound by.

use faer::sparse::{SparseColMat, Triplet};

/// A symmetric sparse matrix: its lower triangle (row ≥ col) in compressed sparse columns,
/// rows ascending within a column.
#[derive(Debug, Clone)]
pub struct SymmetricMatrix {
    n: usize,
    /// Start of each column in `row` and `val` (n + 1 entries).
    col_ptr: Vec<usize>,
    /// Row of each stored entry.
    row: Vec<u32>,
    /// Value of each stored entry.
    val: Vec<f64>,
}

impl SymmetricMatrix {
    /// Builds the matrix from triplets (duplicates summed). Both triangles must be given; the
    /// lower one is kept.
    pub fn from_triplets(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Self {
        let mat: SparseColMat<usize, f64> = SparseColMat::try_new_from_triplets(n, n, triplets)
            .unwrap_or_else(|e| {
                unreachable!("assembly indices are in range by construction: {e:?}")
            });
        let (cp, ri, values) = (
            mat.symbolic().col_ptr(),
            mat.symbolic().row_idx(),
            mat.val(),
        );
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row = Vec::with_capacity(values.len() / 2 + n);
        let mut val = Vec::with_capacity(values.len() / 2 + n);
        col_ptr.push(0);
        for j in 0..n {
            for p in cp[j]..cp[j + 1] {
                if ri[p] >= j {
                    row.push(u32::try_from(ri[p]).unwrap_or_else(|_| {
                        unreachable!("a substructure or assembly has fewer than 2³² dofs")
                    }));
                    val.push(values[p]);
                }
            }
            col_ptr.push(row.len());
        }
        Self {
            n,
            col_ptr,
            row,
            val,
        }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored non-zeros (the lower triangle's).
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// Bytes the matrix holds.
    pub fn bytes(&self) -> usize {
        let word = std::mem::size_of::<usize>();
        self.val.len() * (std::mem::size_of::<f64>() + std::mem::size_of::<u32>())
            + self.col_ptr.len() * word
    }

    /// y ← K x: each stored entry a_ij (i > j) adds a_ij x_i to y_j and a_ij x_j to y_i.
    pub fn mul_into(&self, x: &[f64], y: &mut [f64]) {
        let n = self.n;
        let (x, y) = (&x[..n], &mut y[..n]);
        y.fill(0.0);
        for j in 0..n {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            let (rows, vals) = (&self.row[range.clone()], &self.val[range]);
            let xj = x[j];
            let mut acc = 0.0;
            for (&i, &a) in rows.iter().zip(vals) {
                let i = i as usize;
                if i == j {
                    acc += a * xj;
                } else {
                    acc += a * x[i];
                    y[i] += a * xj;
                }
            }
            y[j] += acc;
        }
    }

    /// xᵀ K x.
    pub fn quadratic_form(&self, x: &[f64]) -> f64 {
        let mut total = 0.0;
        for (j, &xj) in x[..self.n].iter().enumerate() {
            let range = self.col_ptr[j]..self.col_ptr[j + 1];
            let mut acc = 0.0;
            for (&i, &a) in self.row[range.clone()].iter().zip(&self.val[range]) {
                let i = i as usize;
                acc += if i == j { a * xj } else { 2.0 * a * x[i] };
            }
            total += acc * xj;
        }
        total
    }

    /// Iterates the stored lower-triangle entries (row ≥ col) as (row, col, value), column by
    /// column, rows ascending.
    pub fn lower_entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.n).flat_map(move |j| {
            (self.col_ptr[j]..self.col_ptr[j + 1])
                .map(move |p| (self.row[p] as usize, j, self.val[p]))
        })
    }

    /// Iterates every entry of both triangles as (row, col, value): the lower triangle's in
    /// the order of [`Self::lower_entries`], each off-diagonal one followed by its mirror.
    pub fn entries(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        self.lower_entries()
            .flat_map(|(i, j, v)| std::iter::once((i, j, v)).chain((i != j).then_some((j, i, v))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A dense symmetric matrix with a reproducible pattern of zeros, its triplets (both
    /// triangles, some entries split in two duplicates).
    fn example(n: usize) -> (Vec<f64>, Vec<Triplet<usize, usize, f64>>) {
        let mut dense = vec![0.0; n * n];
        let mut triplets = Vec::new();
        for j in 0..n {
            for i in j..n {
                let v = if i == j {
                    10.0 + i as f64
                } else {
                    ((i * 13 + j * 5) % 11) as f64 - 5.0
                };
                if i != j && ((i * 7 + j * 3) % 4 == 0 || v == 0.0) {
                    continue;
                }
                dense[i * n + j] = v;
                dense[j * n + i] = v;
                triplets.push(Triplet::new(i, j, 0.25 * v));
                triplets.push(Triplet::new(i, j, 0.75 * v));
                if i != j {
                    triplets.push(Triplet::new(j, i, v));
                }
            }
        }
        (dense, triplets)
    }

    /// The product, the quadratic form and both entry iterators against the dense matrix.
    #[test]
    fn the_lower_triangle_gives_the_whole_matrix() {
        let n = 23;
        let (dense, triplets) = example(n);
        let k = SymmetricMatrix::from_triplets(n, &triplets);
        let x: Vec<f64> = (0..n).map(|i| ((i * 17) % 7) as f64 - 2.5).collect();
        let mut y = vec![1e9; n];
        k.mul_into(&x, &mut y);
        let mut xkx = 0.0;
        for i in 0..n {
            let yi: f64 = (0..n).map(|j| dense[i * n + j] * x[j]).sum();
            assert!((y[i] - yi).abs() <= 1e-12 * yi.abs().max(1.0), "row {i}");
            xkx += x[i] * yi;
        }
        assert!((k.quadratic_form(&x) - xkx).abs() <= 1e-12 * xkx.abs());
        let mut rebuilt = vec![0.0; n * n];
        for (i, j, v) in k.entries() {
            rebuilt[i * n + j] += v;
        }
        assert_eq!(rebuilt, dense);
        assert!(k.lower_entries().all(|(i, j, _)| i >= j));
        assert_eq!(k.nnz(), k.lower_entries().count());
        assert_eq!(
            k.entries().count(),
            dense.iter().filter(|v| **v != 0.0).count()
        );
    }
}
