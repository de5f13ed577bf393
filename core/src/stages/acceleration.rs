//! Anderson acceleration of the relaxed LATIN iteration (the relaxation of METHOD §6
//! generalized): the fixed-point map x ↦ G(x), x = s over the current window, G(x) = s_new the
//! linear stage's output after the local stage of x. With residuals r_i = G(x_i) − x_i and the
//! differences ΔX, ΔR of the last `depth` iterates and residuals, each iteration takes
//!
//!   γ = argmin ‖r − ΔR γ‖_η,   x ← x + μ r − (ΔX + μ ΔR) γ
//!
//! (type II, Walker & Ni 2011; μ the relaxation), the norm being the one η measures with
//! (METHOD §6: A/k on forces, A k on velocities), so that depth 0 is exactly the relaxation
//! s ← μ s_new + (1 − μ) s. The history restarts with each window.
//!
//! Safeguard: the LATIN map is only piecewise affine (contact statuses switch), and a mixing
//! built on differences from before a switch can push the iterate away. Whenever the residual's
//! η norm grows by more than [`RESTART_GROWTH`] over the previous iteration's, the history is
//! dropped and that iteration is a plain relaxation (a restarted Anderson, as in Walker & Ni's
//! recommendations and Fang & Saad's "restart on non-decrease"). The stress suite runs with depth 5
//! (`tests/tests/stress.rs`).

/// Growth of the residual norm from one iteration to the next above which the history restarts.
pub const RESTART_GROWTH: f64 = 1.0;

/// Iterations without a new best residual (by at least 1 %), in multiples of the depth, after
/// which the history restarts: the mixing can settle on a cycle of the piecewise affine map.
pub const STALL_DEPTHS: usize = 2;

/// Stalls after which the mixing is off for the rest of the window (plain relaxation, which
/// converges wherever the LATIN iteration does, METHOD §6).
pub const MAX_STALLS: usize = 2;

use std::collections::VecDeque;

use crate::linalg::dense::solve_spd;

/// The mixing history of one window.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Anderson {
    depth: usize,
    last: Option<(Vec<f64>, Vec<f64>)>,
    /// The η norm² of the previous residual.
    last_norm: Option<f64>,
    /// The smallest residual norm² of the window and how many iterations ago it was reached.
    best: Option<(f64, usize)>,
    /// How many times the safeguard restarted the history.
    restarts: usize,
    /// Stalls in this window.
    stalls: usize,
    dx: VecDeque<Vec<f64>>,
    dr: VecDeque<Vec<f64>>,
    /// The weighted Gram matrix ΔRᵀ W ΔR, rows in the order of `dr`, kept as the history moves
    /// (one new row of dot products per iteration instead of the whole matrix).
    gram: VecDeque<VecDeque<f64>>,
}

impl Anderson {
    /// An empty history keeping the last `depth` differences.
    pub fn new(depth: usize) -> Self {
        Self {
            depth,
            last: None,
            last_norm: None,
            best: None,
            restarts: 0,
            stalls: 0,
            dx: VecDeque::new(),
            dr: VecDeque::new(),
            gram: VecDeque::new(),
        }
    }

    /// Forgets the history (a new window starts).
    pub fn reset(&mut self) {
        self.last = None;
        self.last_norm = None;
        self.best = None;
        self.stalls = 0;
        self.dx.clear();
        self.dr.clear();
        self.gram.clear();
    }

    /// Replaces `x` by the next iterate from it and `g` = G(x), with relaxation `mu` and the
    /// norm's weight per entry.
    pub fn step(&mut self, x: &mut [f64], g: &[f64], weights: &[f64], mu: f64) {
        let r: Vec<f64> = g.iter().zip(x.iter()).map(|(a, b)| a - b).collect();
        if self.safeguard(dot(&r, &r, weights)) && !self.dr.is_empty() {
            self.restarts += 1;
            self.dx.clear();
            self.dr.clear();
            self.gram.clear();
            self.last = None;
        }
        if let Some((lx, lr)) = self.last.take() {
            if self.depth > 0 && !self.is_off() {
                if self.dx.len() == self.depth {
                    self.dx.pop_front();
                    self.dr.pop_front();
                    self.gram.pop_front();
                    self.gram.iter_mut().for_each(|row| {
                        row.pop_front();
                    });
                }
                self.dx
                    .push_back(x.iter().zip(&lx).map(|(a, b)| a - b).collect());
                let new: Vec<f64> = r.iter().zip(&lr).map(|(a, b)| a - b).collect();
                let mut row: VecDeque<f64> =
                    self.dr.iter().map(|d| dot(d, &new, weights)).collect();
                row.push_back(dot(&new, &new, weights));
                for (g, v) in self.gram.iter_mut().zip(&row) {
                    g.push_back(*v);
                }
                self.gram.push_back(row);
                self.dr.push_back(new);
            }
        }
        let gamma = self.coefficients(&r, weights);
        self.last = Some((x.to_vec(), r.clone()));
        for (i, xi) in x.iter_mut().enumerate() {
            let mut v = *xi + mu * r[i];
            for (c, (dx, dr)) in gamma.iter().zip(self.dx.iter().zip(&self.dr)) {
                v -= c * (dx[i] + mu * dr[i]);
            }
            *xi = v;
        }
    }

    /// The safeguard's verdict on this iteration's residual norm² `norm`: whether the history
    /// restarts, because the norm grew over the previous one ([`RESTART_GROWTH`]) or no new best
    /// came for [`STALL_DEPTHS`] × depth iterations (a stall; after [`MAX_STALLS`] of them the
    /// mixing is off until the window ends).
    fn safeguard(&mut self, norm: f64) -> bool {
        let grew = self
            .last_norm
            .is_some_and(|n| norm > RESTART_GROWTH * RESTART_GROWTH * n);
        self.last_norm = Some(norm);
        let stalled = match &mut self.best {
            Some((b, age)) if norm < 0.99 * 0.99 * *b => {
                (*b, *age) = (norm, 0);
                false
            }
            Some((_, age)) => {
                *age += 1;
                *age >= STALL_DEPTHS * self.depth.max(1)
            }
            None => {
                self.best = Some((norm, 0));
                false
            }
        };
        if stalled {
            self.best = Some((norm, 0));
            self.stalls += 1;
        }
        grew || stalled
    }

    /// Whether the safeguard has switched the mixing off for the rest of the window.
    pub fn is_off(&self) -> bool {
        self.stalls >= MAX_STALLS
    }

    /// How many times the safeguard restarted the history.
    pub fn restarts(&self) -> usize {
        self.restarts
    }

    /// γ of the weighted least-squares problem, through its normal equations (a few unknowns)
    /// with a relative regularization 1e-12 of the diagonal; empty when the history is.
    fn coefficients(&self, r: &[f64], weights: &[f64]) -> Vec<f64> {
        let n = self.dr.len();
        if n == 0 {
            return Vec::new();
        }
        let mut a: Vec<f64> = self.gram.iter().flatten().copied().collect();
        let b: Vec<f64> = self.dr.iter().map(|d| dot(d, r, weights)).collect();
        let scale = (0..n).map(|i| a[i * n + i]).fold(0.0, f64::max);
        for i in 0..n {
            a[i * n + i] += 1e-12 * scale + f64::MIN_POSITIVE;
        }
        solve_spd(a, b)
    }
}

/// The weighted inner product Σ w a b.
fn dot(a: &[f64], b: &[f64], weights: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .zip(weights)
        .map(|((x, y), w)| w * x * y)
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// G(x) = M x + c with M = diag(0.99, 0.9, 0.5, −0.95, 0.2) rotated by a fixed orthogonal
    /// matrix: plain relaxation crawls along the 0.99 and −0.95 modes.
    fn map(x: &[f64]) -> Vec<f64> {
        let lambda = [0.99, 0.9, 0.5, -0.95, 0.2];
        let n = lambda.len();
        // Householder reflector Q = I − 2 v vᵀ / vᵀv, v = (1, 2, 3, 4, 5)
        let v: Vec<f64> = (1..=n).map(|i| i as f64).collect();
        let vv: f64 = v.iter().map(|a| a * a).sum();
        let q = |y: &[f64]| -> Vec<f64> {
            let p: f64 = v.iter().zip(y).map(|(a, b)| a * b).sum::<f64>() * 2.0 / vv;
            y.iter().zip(&v).map(|(a, b)| a - p * b).collect()
        };
        let z: Vec<f64> = q(x).iter().zip(&lambda).map(|(a, l)| a * l).collect();
        q(&z)
            .iter()
            .enumerate()
            .map(|(i, a)| a + 1.0 + i as f64)
            .collect()
    }

    fn iterations(depth: usize, mu: f64) -> usize {
        let mut acc = Anderson::new(depth);
        let mut x = vec![0.0; 5];
        let w = vec![1.0; 5];
        for it in 1..=10_000 {
            let g = map(&x);
            let r: f64 = g
                .iter()
                .zip(&x)
                .map(|(a, b)| (a - b).powi(2))
                .sum::<f64>()
                .sqrt();
            if r < 1e-10 {
                return it;
            }
            acc.step(&mut x, &g, &w, mu);
        }
        usize::MAX
    }

    #[test]
    fn depth_zero_is_the_relaxation() {
        let mut acc = Anderson::new(0);
        let mut x = vec![1.0, -2.0, 0.5];
        let g = vec![3.0, 4.0, -1.0];
        acc.step(&mut x, &g, &[1.0; 3], 0.8);
        acc.step(&mut x, &g, &[1.0; 3], 0.8);
        // two relaxations towards a fixed g: x = g + 0.2² (x0 − g)
        for (xi, (x0, gi)) in x.iter().zip([1.0, -2.0, 0.5].iter().zip(&g)) {
            assert!((xi - (gi + 0.04 * (x0 - gi))).abs() < 1e-14);
        }
    }

    #[test]
    fn anderson_solves_a_linear_map_in_about_its_dimension() {
        let plain = iterations(0, 0.8);
        let accelerated = iterations(5, 0.8);
        // plain relaxation: the 0.99 mode contracts by 1 − 0.8·0.01 per iteration
        assert!(plain > 1000, "plain {plain}");
        // type II Anderson on an affine map is GMRES: exact after dimension + 1 residuals,
        // up to rounding
        assert!(accelerated <= 9, "accelerated {accelerated}");
        // a short history (the Gram matrix drops its oldest row and column every iteration)
        // still beats plain relaxation by far
        let short = iterations(2, 0.8);
        assert!(short < plain / 10, "depth 2: {short}, plain {plain}");
    }

    #[test]
    fn a_stall_restarts_the_history_and_two_switch_the_mixing_off() {
        // residuals turning in the plane, shrinking by 0.1 % per iteration: never growing, and
        // never a new best by 1 % within 2 × depth iterations
        let depth = 3;
        let mut acc = Anderson::new(depth);
        let w = [1.0; 2];
        let mut x = vec![0.0; 2];
        let mut k = 0.0f64;
        let mut next = |x: &[f64]| {
            k += 1.0;
            let a = 0.999f64.powf(k);
            vec![x[0] + a * k.cos(), x[1] + a * k.sin()]
        };
        // the first call sets the best; 2 × depth calls later the stall is seen
        for _ in 0..=STALL_DEPTHS * depth {
            let g = next(&x);
            acc.step(&mut x, &g, &w, 0.8);
        }
        assert_eq!(acc.restarts(), 1);
        assert!(!acc.is_off());
        for _ in 0..STALL_DEPTHS * depth {
            let g = next(&x);
            acc.step(&mut x, &g, &w, 0.8);
        }
        assert_eq!(acc.restarts(), 2);
        assert!(acc.is_off());
        // off: every step is the plain relaxation x + μ (g − x)
        for _ in 0..10 {
            let g = next(&x);
            let want: Vec<f64> = x.iter().zip(&g).map(|(a, b)| a + 0.8 * (b - a)).collect();
            acc.step(&mut x, &g, &w, 0.8);
            assert_eq!(x, want);
        }
        // a new window turns it back on
        acc.reset();
        assert!(!acc.is_off());
    }

    #[test]
    fn a_growing_residual_restarts_the_history() {
        let mut acc = Anderson::new(5);
        let w = [1.0; 3];
        let mut x = vec![1.0, 0.0, 0.0];
        // contraction by ½ for three iterations builds a history ...
        for _ in 0..3 {
            let g: Vec<f64> = x.iter().map(|a| 0.5 * a).collect();
            acc.step(&mut x, &g, &w, 0.8);
        }
        assert_eq!(acc.restarts(), 0);
        // ... then a residual ten times larger restarts it
        let g: Vec<f64> = x.iter().map(|a| a + 10.0).collect();
        acc.step(&mut x, &g, &w, 0.8);
        assert_eq!(acc.restarts(), 1);
    }
}
