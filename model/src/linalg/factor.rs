//! Sparse Cholesky factorization of a substructure operator, computed once and reused for every
//! solve (METHOD §4: S is SPD and constant; §11: factorize once, one forward/back solve per step).
//! Symbolic analysis (in the order of [`super::ordering`]) and numeric factorization are faer's;
//! so are the solves of a simplicial factor and of several columns; a supernodal factor's
//! solves of one column are [`super::supernodal_solve`]'s; the solve scratch is allocated once.
//! The factor is computed and kept in double precision, or in single
//! ([`CholeskyFactor::try_new_single`]: half the memory, the factorization's own included, and
//! half the bytes each solve reads; the solution accurate to the rounding of single precision
//! times the conditioning of S, which the solver's linear stage refines against S in double),
//! or computed in double and rounded
//! ([`CholeskyFactor::into_single`]).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::SymmetricOrdering;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

use super::supernodal_solve::{solve_columns, Buffers};

/// Substructures with at least this many nodes (three dofs each) have factors large enough for
/// their solves to be bound by memory traffic: nested dissection orders them
/// ([`super::ordering`]) and [`crate::scene::settings::FactorPrecision::Auto`] keeps them in
/// single precision.
pub const LARGE_NODES: usize = 3000;

/// Up to this many right-hand sides, a supernodal factor is solved by
/// [`super::supernodal_solve`], whose vectorized substitutions beat faer's matrix–vector
/// products on one column; more columns go through faer's blocked solve, whose matrix products
/// (a copy of each supernode's block, then kernels that keep several columns in registers) are
/// faster from two columns on.
const STREAMED_COLUMNS: usize = 1;

/// A numeric LLᵀ factor of an SPD sparse matrix.
#[derive(Debug)]
pub struct CholeskyFactor {
    symbolic: SymbolicCholesky<usize>,
    values: Values,
    n: usize,
}

/// The stored entries of L, in double or single precision (half the memory and half the bytes
/// a solve reads; the right-hand side is rounded to single for the solve and the solution
/// widened back).
#[derive(Debug)]
enum Values {
    Double(Vec<f64>),
    #[cfg(not(target_arch = "wasm32"))]
    Single(Vec<f32>),
}

/// Scratch memory for [`CholeskyFactor::solve_in_place`], one per concurrent user.
pub struct SolveScratch {
    buffer: MemBuffer,
    /// The right-hand sides in single precision (a single-precision factor's solves).
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    single: Vec<f32>,
    /// The buffers of a supernodal factor's solves, in either precision.
    supernodal: Buffers<f64>,
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    supernodal_single: Buffers<f32>,
}

impl SolveScratch {
    /// No scratch: the buffers of a substructure held by another rank, never solved here.
    pub fn none() -> Self {
        Self::with_buffer(MemBuffer::new(faer::dyn_stack::StackReq::empty()))
    }

    fn with_buffer(buffer: MemBuffer) -> Self {
        Self {
            buffer,
            single: Vec::new(),
            supernodal: Buffers::default(),
            supernodal_single: Buffers::default(),
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
        let (symbolic, values) = factorize(n, lower)?;
        Ok(Self {
            symbolic,
            values: Values::Double(values),
            n,
        })
    }

    /// [`Self::try_new`] computed and kept in single precision (the matrix rounded first): half
    /// the memory at every moment, the factorization's own included; not in the browser build.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn try_new_single(
        n: usize,
        lower: &[Triplet<usize, usize, f64>],
    ) -> Result<Self, FactorFailure> {
        let rounded: Vec<Triplet<usize, usize, f32>> = lower
            .iter()
            .map(|t| Triplet::new(t.row, t.col, t.val as f32))
            .collect();
        let (symbolic, values) = factorize(n, &rounded)?;
        Ok(Self {
            symbolic,
            values: Values::Single(values),
            n,
        })
    }

    /// The factor with its entries rounded to single precision (see [`Values`]); in the
    /// browser build (wasm32) the factor stays in double precision, which the page's scenes
    /// need no less.
    pub fn into_single(self) -> Self {
        #[cfg(not(target_arch = "wasm32"))]
        {
            let values = match self.values {
                Values::Double(v) => Values::Single(v.iter().map(|&x| x as f32).collect()),
                single => single,
            };
            Self { values, ..self }
        }
        #[cfg(target_arch = "wasm32")]
        self
    }

    /// Whether the entries are kept in single precision.
    pub fn is_single(&self) -> bool {
        !matches!(self.values, Values::Double(_))
    }

    /// Bytes of the stored entries of L (values only).
    pub fn value_bytes(&self) -> usize {
        match &self.values {
            Values::Double(v) => 8 * v.len(),
            #[cfg(not(target_arch = "wasm32"))]
            Values::Single(v) => 4 * v.len(),
        }
    }

    /// Bytes of the factor: its values and the row indices of its structure (per column
    /// of a simplicial factor, per supernode of a supernodal one).
    pub fn bytes(&self) -> usize {
        let indices = match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => s.row_idx().len(),
            SymbolicCholeskyRaw::Supernodal(s) => s.row_idx().len(),
        };
        self.value_bytes() + indices * std::mem::size_of::<usize>()
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored values of L (a measure of the solve cost).
    pub fn factor_nnz(&self) -> usize {
        match &self.values {
            Values::Double(v) => v.len(),
            #[cfg(not(target_arch = "wasm32"))]
            Values::Single(v) => v.len(),
        }
    }

    /// Scratch sized for single right-hand-side solves with this factor.
    pub fn scratch(&self) -> SolveScratch {
        self.scratch_for(1)
    }

    /// Scratch sized for solves of up to `ncols` right-hand sides at once
    /// ([`Self::solve_columns_in_place`]).
    pub fn scratch_for(&self, ncols: usize) -> SolveScratch {
        let ncols = ncols.max(1);
        if ncols <= STREAMED_COLUMNS
            && matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
        {
            // the streamed solve's buffers grow on first use
            return SolveScratch::none();
        }
        match &self.values {
            Values::Double(_) => SolveScratch::with_buffer(MemBuffer::new(
                self.symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq),
            )),
            #[cfg(not(target_arch = "wasm32"))]
            Values::Single(_) => SolveScratch {
                single: vec![0.0; self.n * ncols],
                ..SolveScratch::with_buffer(MemBuffer::new(
                    self.symbolic.solve_in_place_scratch::<f32>(ncols, Par::Seq),
                ))
            },
        }
    }

    /// X ← S⁻¹ X for `ncols` right-hand sides stored column-major in `x` (blocked solves; the
    /// scratch is allocated for the call).
    pub fn solve_many_in_place(&self, x: &mut [f64], ncols: usize) {
        let mut scratch = self.scratch_for(ncols);
        self.solve_columns_in_place(x, ncols, &mut scratch);
    }

    /// X ← S⁻¹ X for `ncols` right-hand sides stored column-major in `x`, in one pass through
    /// the factor (the factor is read once for all columns), with scratch from
    /// [`Self::scratch_for`] of at least `ncols` columns.
    pub fn solve_columns_in_place(&self, x: &mut [f64], ncols: usize, scratch: &mut SolveScratch) {
        if let (SymbolicCholeskyRaw::Supernodal(symbolic), true) =
            (self.symbolic.raw(), ncols <= STREAMED_COLUMNS)
        {
            let perm = self.symbolic.perm().map(|p| p.arrays());
            match &self.values {
                Values::Double(values) => {
                    solve_columns(symbolic, perm, values, x, ncols, &mut scratch.supernodal)
                }
                #[cfg(not(target_arch = "wasm32"))]
                Values::Single(values) => solve_columns(
                    symbolic,
                    perm,
                    values,
                    x,
                    ncols,
                    &mut scratch.supernodal_single,
                ),
            }
            return;
        }
        match &self.values {
            Values::Double(values) => {
                let rhs = MatMut::from_column_major_slice_mut(x, self.n, ncols);
                LltRef::new(&self.symbolic, values).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    Par::Seq,
                    MemStack::new(&mut scratch.buffer),
                );
            }
            #[cfg(not(target_arch = "wasm32"))]
            Values::Single(values) => {
                let y = &mut scratch.single[..self.n * ncols];
                y.iter_mut().zip(x.iter()).for_each(|(s, d)| *s = *d as f32);
                let rhs = MatMut::from_column_major_slice_mut(y, self.n, ncols);
                LltRef::new(&self.symbolic, values).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    Par::Seq,
                    MemStack::new(&mut scratch.buffer),
                );
                x.iter_mut()
                    .zip(y.iter())
                    .for_each(|(d, s)| *d = f64::from(*s));
            }
        }
    }

    /// x ← S⁻¹ x (forward and back substitution).
    pub fn solve_in_place(&self, x: &mut [f64], scratch: &mut SolveScratch) {
        self.solve_columns_in_place(x, 1, scratch);
    }
}

/// The symbolic analysis (the ordering of [`super::ordering`]) and the numeric LLᵀ factorization
/// of the SPD matrix given by its lower-triangle triplets, in the precision of its entries.
fn factorize<T: faer::traits::ComplexField>(
    n: usize,
    lower: &[Triplet<usize, usize, T>],
) -> Result<(SymbolicCholesky<usize>, Vec<T>), FactorFailure> {
    factorize_ordered(n, lower, super::ordering::dof_permutation(n, lower))
}

/// [`factorize`] with the permutation (new → old, old → new) given, or faer's minimum degree.
pub(crate) fn factorize_ordered<T: faer::traits::ComplexField>(
    n: usize,
    lower: &[Triplet<usize, usize, T>],
    permutation: Option<(Vec<usize>, Vec<usize>)>,
) -> Result<(SymbolicCholesky<usize>, Vec<T>), FactorFailure> {
    let failed = |reason: String| FactorFailure { reason, dof: None };
    let mat =
        SparseColMat::try_new_from_triplets(n, n, lower).map_err(|e| failed(format!("{e:?}")))?;
    let ordering = match &permutation {
        Some((forward, inverse)) => {
            SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(forward, inverse, n))
        }
        None => SymmetricOrdering::Amd,
    };
    let symbolic =
        factorize_symbolic_cholesky(mat.symbolic(), Side::Lower, ordering, Default::default())
            .map_err(|e| failed(format!("symbolic analysis: {e:?}")))?;
    let mut values = vec![T::zero_impl(); symbolic.len_val()];
    let par = Par::Seq;
    let mut mem =
        MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<T>(par, Default::default()))
            .map_err(|e| failed(format!("{e:?}")))?;
    symbolic
        .factorize_numeric_llt::<T>(
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
    Ok((symbolic, values))
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

    /// The factor computed in single precision, or computed in double and rounded, solves to its
    /// rounding (1e-5 on a 3D grid
    /// Laplacian of 2,744 unknowns, whose conditioning is a few tens), in one column or several
    /// (the blocked solve rounds apart from the single one), and keeps half the bytes of values.
    #[test]
    fn a_single_precision_factor_solves_to_its_rounding() {
        let m = 14;
        let n = m * m * m;
        let id = |i: usize, j: usize, k: usize| i + m * (j + m * k);
        let mut t = Vec::new();
        for k in 0..m {
            for j in 0..m {
                for i in 0..m {
                    let r = id(i, j, k);
                    t.push(Triplet::new(r, r, 6.5));
                    for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        if i + di < m && j + dj < m && k + dk < m {
                            t.push(Triplet::new(id(i + di, j + dj, k + dk), r, -1.0));
                        }
                    }
                }
            }
        }
        let double = CholeskyFactor::new(n, &t).expect("SPD");
        let bytes = double.value_bytes();
        let rounded = CholeskyFactor::new(n, &t).expect("SPD").into_single();
        let single = CholeskyFactor::try_new_single(n, &t).expect("SPD");
        assert!(single.is_single() && rounded.is_single() && !double.is_single());
        assert_eq!(2 * single.value_bytes(), bytes);
        assert_eq!(2 * rounded.value_bytes(), bytes);
        let mut c = (0..2 * n)
            .map(|i| ((i * 13) as f64).sin())
            .collect::<Vec<f64>>();
        let mut d = c.clone();
        double.solve_many_in_place(&mut d, 2);
        rounded.solve_many_in_place(&mut c, 2);
        let apart = c
            .iter()
            .zip(&d)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
            / d.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        assert!(
            apart < 1e-5 && apart > 1e-9,
            "rounded against double: {apart:e}"
        );
        assert!(single.bytes() < double.bytes());
        let x: Vec<f64> = (0..2 * n).map(|i| ((i * 13) as f64).sin()).collect();
        let (mut a, mut b) = (x.clone(), x.clone());
        double.solve_many_in_place(&mut a, 2);
        single.solve_many_in_place(&mut b, 2);
        let scale = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = a
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
            / scale;
        assert!(err < 1e-5 && err > 1e-9, "single against double: {err:e}");
        let mut one = x[..n].to_vec();
        single.solve_in_place(&mut one, &mut single.scratch());
        let apart = one
            .iter()
            .zip(&b)
            .fold(0.0f64, |m, (p, q)| m.max((p - q).abs()))
            / scale;
        assert!(apart < 1e-6, "one column against a block: {apart:e}");
    }

    #[test]
    fn rejects_an_indefinite_matrix() {
        let t = vec![Triplet::new(0, 0, 1.0), Triplet::new(1, 1, -1.0)];
        assert!(CholeskyFactor::new(2, &t).is_err());
    }
}
