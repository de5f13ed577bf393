//! Sparse Cholesky factorization of a substructure operator, computed once and reused for every
//! solve (METHOD §4: S is SPD and constant; §11: factorize once, one forward/back solve per step).
//! Symbolic analysis and numeric factorization are faer's; the solve scratch is allocated once.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::SymmetricOrdering;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

/// A numeric LLᵀ factor of an SPD sparse matrix.
#[derive(Debug)]
pub struct CholeskyFactor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    n: usize,
}

/// Scratch memory for [`CholeskyFactor::solve_in_place`], one per concurrent user.
pub struct SolveScratch {
    buffer: MemBuffer,
}

impl SolveScratch {
    /// No scratch: the buffers of a substructure held by another rank, never solved here.
    pub fn none() -> Self {
        Self {
            buffer: MemBuffer::new(faer::dyn_stack::StackReq::empty()),
        }
    }
}

impl std::fmt::Debug for SolveScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("SolveScratch")
    }
}

/// Why a factorization failed, and at which unknown where the matrix is not positive definite.
#[derive(Debug, Clone, PartialEq)]
pub struct FactorFailure {
    /// What failed (not positive definite, out of memory, a bad matrix).
    pub reason: String,
    /// The unknown (row of the matrix as given) whose pivot was not positive, where known.
    pub dof: Option<usize>,
}

impl std::fmt::Display for FactorFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.dof {
            Some(dof) => write!(f, "{} at unknown {dof}", self.reason),
            None => f.write_str(&self.reason),
        }
    }
}

impl CholeskyFactor {
    /// Factorizes the SPD matrix given by its lower-triangle triplets (duplicates summed).
    /// Returns a readable reason on failure (not positive definite, out of memory).
    pub fn new(n: usize, lower: &[Triplet<usize, usize, f64>]) -> Result<Self, String> {
        Self::try_new(n, lower).map_err(|f| f.to_string())
    }

    /// [`Self::new`], with the unknown where the matrix is found not positive definite.
    pub fn try_new(n: usize, lower: &[Triplet<usize, usize, f64>]) -> Result<Self, FactorFailure> {
        let failed = |reason: String| FactorFailure { reason, dof: None };
        let mat = SparseColMat::try_new_from_triplets(n, n, lower)
            .map_err(|e| failed(format!("{e:?}")))?;
        let symbolic = factorize_symbolic_cholesky(
            mat.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| failed(format!("symbolic analysis: {e:?}")))?;
        let mut values = vec![0.0; symbolic.len_val()];
        let par = Par::Seq;
        let mut mem = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|e| failed(format!("{e:?}")))?;
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                mat.as_ref(),
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| {
                let faer::linalg::solvers::LltError::NonPositivePivot { index } = e;
                // faer counts the failed pivot from 1 in its simplicial factorization, from 0
                // in its supernodal one
                let pivot = Some(match symbolic.raw() {
                    SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                    SymbolicCholeskyRaw::Supernodal(_) => index,
                });
                // the pivot counts in the fill-reducing order: back to the rows as given
                let dof = pivot.map(|k| match symbolic.perm() {
                    Some(p) => p.arrays().0.get(k).copied().unwrap_or(k),
                    None => k,
                });
                FactorFailure {
                    reason: "not positive definite".into(),
                    dof,
                }
            })?;
        Ok(Self {
            symbolic,
            values,
            n,
        })
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored values of L (a measure of the solve cost).
    pub fn factor_nnz(&self) -> usize {
        self.values.len()
    }

    /// Scratch sized for single right-hand-side solves with this factor.
    pub fn scratch(&self) -> SolveScratch {
        SolveScratch {
            buffer: MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(1, Par::Seq)),
        }
    }

    /// X ← S⁻¹ X for `ncols` right-hand sides stored column-major in `x` (blocked solves; the
    /// scratch is allocated for the call).
    pub fn solve_many_in_place(&self, x: &mut [f64], ncols: usize) {
        let mut buffer =
            MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq));
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, ncols);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut buffer),
        );
    }

    /// x ← S⁻¹ x (forward and back substitution).
    pub fn solve_in_place(&self, x: &mut [f64], scratch: &mut SolveScratch) {
        let rhs = MatMut::from_column_major_slice_mut(x, self.n, 1);
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut scratch.buffer),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_a_tridiagonal_system() {
        let n = 50;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 4.0));
            if i + 1 < n {
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        let f = CholeskyFactor::new(n, &t).expect("SPD");
        let x_true: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut b: Vec<f64> = (0..n)
            .map(|i| {
                4.0 * x_true[i]
                    - if i > 0 { x_true[i - 1] } else { 0.0 }
                    - if i + 1 < n { x_true[i + 1] } else { 0.0 }
            })
            .collect();
        let mut s = f.scratch();
        f.solve_in_place(&mut b, &mut s);
        for i in 0..n {
            assert!((b[i] - x_true[i]).abs() < 1e-13);
        }
    }

    #[test]
    fn many_right_hand_sides_match_single_solves() {
        let n = 30;
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 3.0 + i as f64 * 0.1));
            if i + 2 < n {
                t.push(Triplet::new(i + 2, i, -1.0));
            }
        }
        let f = CholeskyFactor::new(n, &t).expect("SPD");
        let x: Vec<f64> = (0..3 * n).map(|i| ((i * 7) as f64).cos()).collect();
        let mut many = x.clone();
        f.solve_many_in_place(&mut many, 3);
        let mut s = f.scratch();
        for c in 0..3 {
            let mut one = x[c * n..(c + 1) * n].to_vec();
            f.solve_in_place(&mut one, &mut s);
            for i in 0..n {
                assert!((one[i] - many[c * n + i]).abs() < 1e-14);
            }
        }
    }

    /// A banded SPD matrix but for one negative diagonal entry: the failure names that row,
    /// whatever order the factorization visits the rows in.
    #[test]
    fn names_the_unknown_where_the_matrix_is_not_positive_definite() {
        for (n, bad) in [(40usize, 17usize), (40, 0), (40, 39), (300, 123)] {
            let mut t = Vec::new();
            for i in 0..n {
                t.push(Triplet::new(i, i, if i == bad { -5.0 } else { 4.0 }));
                for d in [1, 7] {
                    if i + d < n {
                        t.push(Triplet::new(i + d, i, -0.5));
                    }
                }
            }
            let failure = CholeskyFactor::try_new(n, &t).expect_err("indefinite");
            assert_eq!(failure.dof, Some(bad), "{failure}");
            assert!(failure.to_string().ends_with(&format!("at unknown {bad}")));
        }
        // a 3D grid Laplacian, large enough for faer's supernodal factorization
        let m = 14;
        let n = m * m * m;
        let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
        for bad in [0, 1234, n - 1] {
            let mut t = Vec::new();
            for k in 0..m {
                for j in 0..m {
                    for i in 0..m {
                        let r = id(i, j, k);
                        t.push(Triplet::new(r, r, if r == bad { -1.0 } else { 6.5 }));
                        if i + 1 < m {
                            t.push(Triplet::new(id(i + 1, j, k), r, -1.0));
                        }
                        if j + 1 < m {
                            t.push(Triplet::new(id(i, j + 1, k), r, -1.0));
                        }
                        if k + 1 < m {
                            t.push(Triplet::new(id(i, j, k + 1), r, -1.0));
                        }
                    }
                }
            }
            let failure = CholeskyFactor::try_new(n, &t).expect_err("indefinite");
            assert_eq!(failure.dof, Some(bad), "{failure}");
        }
    }

    #[test]
    fn rejects_an_indefinite_matrix() {
        let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, -1.0)];
        assert!(CholeskyFactor::new(2, &t).is_err());
    }
}
