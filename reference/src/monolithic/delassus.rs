//! The Delassus operator of the contact pairs: D = G S_ff⁻¹ Gᵀ in the pairs' local frames, where
//! G maps the free velocities to the relative velocities [v] = v_b − v_a (side 2 minus side 1,
//! METHOD §1 jump convention) projected on (n, t₁, t₂). It is dense (3 × pairs square), SPD, and
//! computed once from blocked solves with the global factorization; a time step then needs only
//! the free solution and D to state the contact problem on the pairs.

use super::assembly::{Assembled, ContactPair};
use lopin_model::linalg::factor::CholeskyFactor;
use lopin_model::mesh::Vec3;

/// Columns per blocked solve.
const BLOCK: usize = 48;

/// Dense Delassus operator, column-major, size 3·pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct Delassus {
    /// Dimension (3 × number of pairs).
    pub n: usize,
    /// Entries, column-major.
    pub d: Vec<f64>,
}

impl Delassus {
    /// Builds D with one blocked solve per `BLOCK` columns.
    pub fn new(asm: &Assembled, factor: &CholeskyFactor) -> Self {
        let n = 3 * asm.pairs.len();
        let nf = asm.free;
        let mut d = vec![0.0; n * n];
        let mut col = 0;
        while col < n {
            let cols = BLOCK.min(n - col);
            let mut x = vec![0.0; nf * cols];
            for c in 0..cols {
                let (p, q) = ((col + c) / 3, (col + c) % 3);
                let pair = &asm.pairs[p];
                scatter(asm, pair, pair.frame[q], &mut x[c * nf..(c + 1) * nf]);
            }
            factor.solve_many_in_place(&mut x, cols);
            for c in 0..cols {
                let xc = &x[c * nf..(c + 1) * nf];
                let out = &mut d[(col + c) * n..(col + c + 1) * n];
                for (p, pair) in asm.pairs.iter().enumerate() {
                    for q in 0..3 {
                        out[3 * p + q] = gather(asm, pair, pair.frame[q], xc);
                    }
                }
            }
            col += cols;
        }
        // symmetrize the rounding
        for i in 0..n {
            for j in 0..i {
                let m = 0.5 * (d[i * n + j] + d[j * n + i]);
                d[i * n + j] = m;
                d[j * n + i] = m;
            }
        }
        Self { n, d }
    }

    /// Entry D[i, j].
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.d[j * self.n + i]
    }

    /// Column j.
    pub fn column(&self, j: usize) -> &[f64] {
        &self.d[j * self.n..(j + 1) * self.n]
    }
}

/// x += Gᵀ e for one pair and direction: −e on node a, +w e on each node b of side 2 (free
/// dofs only).
pub fn scatter(asm: &Assembled, pair: &ContactPair, e: Vec3, x: &mut [f64]) {
    for q in 0..3 {
        let fa = asm.free_index[3 * pair.a + q];
        if fa != usize::MAX {
            x[fa] -= e[q];
        }
        for &(b, w) in &pair.across {
            let fb = asm.free_index[3 * b + q];
            if fb != usize::MAX {
                x[fb] += w * e[q];
            }
        }
    }
}

/// e · (Σ w x_b − x_a) over the free dofs of the pair's nodes.
fn gather(asm: &Assembled, pair: &ContactPair, e: Vec3, x: &[f64]) -> f64 {
    let mut s = 0.0;
    for q in 0..3 {
        let fa = asm.free_index[3 * pair.a + q];
        if fa != usize::MAX {
            s -= e[q] * x[fa];
        }
        for &(b, w) in &pair.across {
            let fb = asm.free_index[3 * b + q];
            if fb != usize::MAX {
                s += w * e[q] * x[fb];
            }
        }
    }
    s
}
