//! The forward and back substitution through a supernodal LLᵀ factor for one or several
//! right-hand sides at once (METHOD §4, §11: one pass through the factor per step; the factor
//! solves single columns here, several with faer's blocked solve). Each entry
//! of L is read from memory once per solve whatever the number of columns, and used for every
//! column while it is in cache: the solve of a few columns is bound by the bytes of the factor,
//! as that of one column is, without the copies of L that a general matrix product makes of
//! each supernode's block. Each column's arithmetic is the same whatever the others (its result
//! does not depend on how many columns are solved with it).
//!
//! A supernode s holds the columns start..start + size of L as one dense column-major block of
//! size + m rows: its diagonal block (lower triangular), then the m rows of its pattern. The
//! right-hand sides are permuted into the factor's order and rounded to its precision on the
//! way in, and back on the way out.

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use pulp::Simd;
use std::ops::{Add, AddAssign, Div, Mul, Sub};

/// The precision of a factor's entries (f64 or f32), with the two kernels of the solve in the
/// vector registers of `S`.
pub(crate) trait Entry:
    Copy
    + Default
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + AddAssign
{
    fn from_f64(x: f64) -> Self;
    fn to_f64(self) -> f64;
    /// Σ a_i b_i (four vector partial sums, then the rest).
    fn dot<S: Simd>(simd: S, a: &[Self], b: &[Self]) -> Self;
    /// out_i += Σ_c l_c,i v_c for the four columns `l` (each as long as `out`).
    fn update4<S: Simd>(simd: S, out: &mut [Self], l: [&[Self]; 4], v: [Self; 4]);
    /// out_i += l_i v.
    fn update1<S: Simd>(simd: S, out: &mut [Self], l: &[Self], v: Self);
}

macro_rules! entry {
    ($t:ty, $split:ident, $split_mut:ident, $splat:ident, $fma:ident, $add:ident, $sum:ident) => {
        impl Entry for $t {
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn dot<S: Simd>(simd: S, a: &[Self], b: &[Self]) -> Self {
                let len = a.len().min(b.len());
                let ((a, ra), (b, rb)) = (S::$split(&a[..len]), S::$split(&b[..len]));
                let zero = simd.$splat(0.0);
                let mut acc = [zero; 4];
                let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
                let (a1, b1) = (a4.remainder(), b4.remainder());
                for (x, y) in a4.zip(b4) {
                    for k in 0..4 {
                        acc[k] = simd.$fma(x[k], y[k], acc[k]);
                    }
                }
                for (&x, &y) in a1.iter().zip(b1) {
                    acc[0] = simd.$fma(x, y, acc[0]);
                }
                let total = simd.$add(simd.$add(acc[0], acc[1]), simd.$add(acc[2], acc[3]));
                let mut sum = simd.$sum(total);
                for (&x, &y) in ra.iter().zip(rb) {
                    sum += x * y;
                }
                sum
            }
            #[inline(always)]
            fn update4<S: Simd>(simd: S, out: &mut [Self], l: [&[Self]; 4], v: [Self; 4]) {
                let n = out.len();
                let (o, ro) = S::$split_mut(out);
                let ((l0, r0), (l1, r1)) = (S::$split(&l[0][..n]), S::$split(&l[1][..n]));
                let ((l2, r2), (l3, r3)) = (S::$split(&l[2][..n]), S::$split(&l[3][..n]));
                let vs = v.map(|x| simd.$splat(x));
                for (i, o) in o.iter_mut().enumerate() {
                    let t = simd.$fma(l0[i], vs[0], *o);
                    let t = simd.$fma(l1[i], vs[1], t);
                    let t = simd.$fma(l2[i], vs[2], t);
                    *o = simd.$fma(l3[i], vs[3], t);
                }
                for (i, o) in ro.iter_mut().enumerate() {
                    *o += r0[i] * v[0] + r1[i] * v[1] + r2[i] * v[2] + r3[i] * v[3];
                }
            }
            #[inline(always)]
            fn update1<S: Simd>(simd: S, out: &mut [Self], l: &[Self], v: Self) {
                let n = out.len();
                let (o, ro) = S::$split_mut(out);
                let (l, rl) = S::$split(&l[..n]);
                let vs = simd.$splat(v);
                for (o, &l) in o.iter_mut().zip(l) {
                    *o = simd.$fma(l, vs, *o);
                }
                for (o, &l) in ro.iter_mut().zip(rl) {
                    *o += l * v;
                }
            }
        }
    };
}

entry!(
    f64,
    as_simd_f64s,
    as_mut_simd_f64s,
    splat_f64s,
    mul_add_e_f64s,
    add_f64s,
    reduce_sum_f64s
);
entry!(
    f32,
    as_simd_f32s,
    as_mut_simd_f32s,
    splat_f32s,
    mul_add_e_f32s,
    add_f32s,
    reduce_sum_f32s
);

/// Buffers of [`solve_columns`]: the permuted right-hand sides and one supernode's pattern rows.
#[derive(Debug, Default)]
pub(crate) struct Buffers<T> {
    x: Vec<T>,
    below: Vec<T>,
}

/// X ← (L Lᵀ)⁻¹ X for the `ncols` columns of `x` (column-major, n rows), L the supernodal factor
/// (`symbolic`, `values`) of the matrix permuted by `perm` (new → old, old → new).
pub(crate) fn solve_columns<T: Entry>(
    symbolic: &SymbolicSupernodalCholesky<usize>,
    perm: Option<(&[usize], &[usize])>,
    values: &[T],
    x: &mut [f64],
    ncols: usize,
    buffers: &mut Buffers<T>,
) {
    let n = symbolic.nrows();
    debug_assert_eq!(x.len(), n * ncols);
    let Buffers { x: y, below } = buffers;
    y.resize(n * ncols, T::default());
    for j in 0..ncols {
        let (src, dst) = (&x[j * n..(j + 1) * n], &mut y[j * n..(j + 1) * n]);
        match perm {
            Some((forward, _)) => dst
                .iter_mut()
                .zip(forward)
                .for_each(|(d, &f)| *d = T::from_f64(src[f])),
            None => dst
                .iter_mut()
                .zip(src)
                .for_each(|(d, &s)| *d = T::from_f64(s)),
        }
    }
    pulp::Arch::new().dispatch(Substitutions {
        symbolic,
        values,
        y,
        ncols,
        below,
    });
    for j in 0..ncols {
        let (src, dst) = (&y[j * n..(j + 1) * n], &mut x[j * n..(j + 1) * n]);
        match perm {
            Some((_, inverse)) => dst
                .iter_mut()
                .zip(inverse)
                .for_each(|(d, &i)| *d = src[i].to_f64()),
            None => dst.iter_mut().zip(src).for_each(|(d, &s)| *d = s.to_f64()),
        }
    }
}

/// The forward and back substitutions of [`solve_columns`] on the permuted columns `y`, as one
/// operation that [`pulp`] compiles for the vector instructions of the processor it runs on.
struct Substitutions<'a, T> {
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    values: &'a [T],
    y: &'a mut [T],
    ncols: usize,
    below: &'a mut Vec<T>,
}

impl<T: Entry> pulp::WithSimd for Substitutions<'_, T> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(mut self, simd: S) {
        for s in 0..self.symbolic.n_supernodes() {
            self.forward(simd, s);
        }
        for s in (0..self.symbolic.n_supernodes()).rev() {
            self.backward(simd, s);
        }
    }
}

impl<T: Entry> Substitutions<'_, T> {
    /// Forward substitution through supernode `s`: its diagonal block solved, then the update
    /// of its pattern's rows (accumulated in `below`, m rows a column, and subtracted once).
    #[inline(always)]
    fn forward<S: Simd>(&mut self, simd: S, s: usize) {
        let (start, size, pattern, block) = supernode(self.symbolic, self.values, s);
        let (n, m, ncols) = (self.symbolic.nrows(), pattern.len(), self.ncols);
        let (rows, y, below) = (size + m, &mut *self.y, &mut *self.below);
        for j in 0..ncols {
            let top = &mut y[j * n + start..j * n + start + size];
            for c in 0..size {
                let col = &block[c * rows..c * rows + size];
                let v = top[c] / col[c];
                top[c] = v;
                for (t, &l) in top[c + 1..].iter_mut().zip(&col[c + 1..]) {
                    *t = *t - l * v;
                }
            }
        }
        if m == 0 {
            return;
        }
        below.clear();
        below.resize(m * ncols, T::default());
        // four columns of L at a time: each row of `below` read and written once per four
        let under = |c: usize| &block[c * rows + size..(c + 1) * rows];
        let mut c = 0;
        while c + 4 <= size {
            let l = [under(c), under(c + 1), under(c + 2), under(c + 3)];
            for j in 0..ncols {
                let top = &y[j * n + start + c..j * n + start + c + 4];
                let v = [top[0], top[1], top[2], top[3]];
                T::update4(simd, &mut below[j * m..(j + 1) * m], l, v);
            }
            c += 4;
        }
        while c < size {
            for j in 0..ncols {
                let v = y[j * n + start + c];
                T::update1(simd, &mut below[j * m..(j + 1) * m], under(c), v);
            }
            c += 1;
        }
        for j in 0..ncols {
            let (yj, out) = (&mut y[j * n..(j + 1) * n], &below[j * m..(j + 1) * m]);
            for (&r, &b) in pattern.iter().zip(out) {
                yj[r] = yj[r] - b;
            }
        }
    }

    /// Back substitution through supernode `s`: its pattern's rows gathered (m a column), the
    /// dot products of the block's columns below the diagonal with them subtracted, then the
    /// diagonal block's transpose solved.
    #[inline(always)]
    fn backward<S: Simd>(&mut self, simd: S, s: usize) {
        let (start, size, pattern, block) = supernode(self.symbolic, self.values, s);
        let (n, m, ncols) = (self.symbolic.nrows(), pattern.len(), self.ncols);
        let (rows, y, below) = (size + m, &mut *self.y, &mut *self.below);
        if m > 0 {
            below.clear();
            below.resize(m * ncols, T::default());
            for j in 0..ncols {
                let (yj, out) = (&y[j * n..(j + 1) * n], &mut below[j * m..(j + 1) * m]);
                for (o, &r) in out.iter_mut().zip(pattern) {
                    *o = yj[r];
                }
            }
            for c in 0..size {
                let l = &block[c * rows + size..(c + 1) * rows];
                for j in 0..ncols {
                    let d = T::dot(simd, l, &below[j * m..(j + 1) * m]);
                    let t = &mut y[j * n + start + c];
                    *t = *t - d;
                }
            }
        }
        for j in 0..ncols {
            let top = &mut y[j * n + start..j * n + start + size];
            for c in (0..size).rev() {
                let col = &block[c * rows..c * rows + size];
                let d = T::dot(simd, &col[c + 1..], &top[c + 1..]);
                top[c] = (top[c] - d) / col[c];
            }
        }
    }
}

/// Supernode `s`: its first column, its number of columns, the rows of its pattern (below the
/// diagonal block) and its block of values (column-major, size + m rows).
#[inline(always)]
fn supernode<'a, T>(
    symbolic: &'a SymbolicSupernodalCholesky<usize>,
    values: &'a [T],
    s: usize,
) -> (usize, usize, &'a [usize], &'a [T]) {
    let start = symbolic.supernode_begin()[s];
    let ptr = symbolic.col_ptr_for_val();
    (
        start,
        symbolic.supernode_end()[s] - start,
        symbolic.supernode(s).pattern(),
        &values[ptr[s]..ptr[s + 1]],
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, LltRef, SymbolicCholeskyRaw, SymmetricOrdering,
    };
    use faer::sparse::{SparseColMat, Triplet};
    use faer::{Conj, MatMut, Par, Side};

    /// A 3-dof-a-node operator on an nx × ny × nz grid (mass plus stiffness-like coupling of
    /// neighbours, SPD), lower triangle.
    fn grid(nx: usize, ny: usize, nz: usize) -> (usize, Vec<Triplet<usize, usize, f64>>) {
        let node = |i: usize, j: usize, k: usize| (k * ny + j) * nx + i;
        let n = 3 * nx * ny * nz;
        let mut t = Vec::new();
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    let a = node(i, j, k);
                    for d in 0..3 {
                        t.push(Triplet::new(3 * a + d, 3 * a + d, 7.0 + 0.01 * d as f64));
                        if d > 0 {
                            t.push(Triplet::new(3 * a + d, 3 * a, 0.3));
                        }
                    }
                    let mut near = Vec::new();
                    if i + 1 < nx {
                        near.push(node(i + 1, j, k));
                    }
                    if j + 1 < ny {
                        near.push(node(i, j + 1, k));
                    }
                    if k + 1 < nz {
                        near.push(node(i, j, k + 1));
                    }
                    for b in near {
                        for d in 0..3 {
                            t.push(Triplet::new(3 * b + d, 3 * a + d, -1.0));
                        }
                    }
                }
            }
        }
        (n, t)
    }

    fn noise(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    fn product(n: usize, lower: &[Triplet<usize, usize, f64>], x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; n];
        for t in lower {
            y[t.row] += t.val * x[t.col];
            if t.row != t.col {
                y[t.col] += t.val * x[t.row];
            }
        }
        y
    }

    #[test]
    fn several_columns_solve_as_faer_does_and_each_column_alone() {
        let (n, lower) = grid(9, 8, 7);
        let mat = SparseColMat::try_new_from_triplets(n, n, &lower).expect("matrix");
        let symbolic = factorize_symbolic_cholesky(
            mat.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .expect("symbolic");
        let SymbolicCholeskyRaw::Supernodal(supernodal) = symbolic.raw() else {
            panic!("a 3-d grid's factor is supernodal");
        };
        assert!(supernodal.n_supernodes() > 10);
        let mut values = vec![0.0f64; symbolic.len_val()];
        let mut mem = MemBuffer::new(
            symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()),
        );
        symbolic
            .factorize_numeric_llt::<f64>(
                &mut values,
                mat.as_ref(),
                Side::Lower,
                Default::default(),
                Par::Seq,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .expect("SPD");
        let perm = symbolic.perm().map(|p| p.arrays());
        let ncols = 5;
        let mut seed = 7;
        let b: Vec<f64> = (0..n * ncols).map(|_| noise(&mut seed)).collect();

        // several columns in one pass: each solves S x = b to rounding
        let mut x = b.clone();
        let mut buffers = Buffers::default();
        solve_columns(supernodal, perm, &values, &mut x, ncols, &mut buffers);
        for j in 0..ncols {
            let r = product(n, &lower, &x[j * n..(j + 1) * n]);
            let err = r
                .iter()
                .zip(&b[j * n..(j + 1) * n])
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(err < 1e-12, "column {j}: residual {err:e}");
        }

        // faer's own solve of the same factor agrees to rounding
        let mut reference = b.clone();
        let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(ncols, Par::Seq));
        LltRef::new(&symbolic, &values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut reference, n, ncols),
            Par::Seq,
            MemStack::new(&mut mem),
        );
        let apart = x
            .iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(apart < 1e-13, "against faer: {apart:e}");

        // a column's result does not depend on the columns solved with it, bit for bit
        for j in [0, 3] {
            let mut one = b[j * n..(j + 1) * n].to_vec();
            solve_columns(supernodal, perm, &values, &mut one, 1, &mut buffers);
            assert_eq!(one, x[j * n..(j + 1) * n], "column {j}");
        }

        // in single precision: the factor's rounding times the conditioning, no more
        let single: Vec<f32> = values.iter().map(|&v| v as f32).collect();
        let mut xs = b.clone();
        solve_columns(
            supernodal,
            perm,
            &single,
            &mut xs,
            ncols,
            &mut Buffers::default(),
        );
        let scale = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let err = xs
            .iter()
            .zip(&x)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / scale;
        assert!(err < 1e-5 && err > 1e-9, "single against double: {err:e}");
    }
}
