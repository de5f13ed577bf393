//! The frictional contact problem of one time step on the assembled system, solved by projected
//! Gauss–Seidel over the contact pairs with the Delassus operator (nonsmooth contact dynamics).
//!
//! Unknowns per pair, in the local frame: the normal force P ≥ 0 (compression) and the tangential
//! force T (2-vector) on side 1; the nodal force on side 1 is −P n + T, on side 2 the opposite.
//! Relative velocities w = [v] = q + D y with y = (P, −T). The conditions are those of METHOD §5
//! written on the converged fields: persistent normal law w_n ≥ V_lim = min(V*, 0),
//! V* = −2 g_{m−1}/Δt − w_{n,m−1}, P ≥ 0, P (w_n − V_lim) = 0; Coulomb |T| ≤ f P, stick w_t = 0
//! or slip w_t = λ T with λ ≥ 0 (side 2 drags side 1). Each pair update solves the normal
//! condition exactly, then the tangential one exactly for fixed P (a secular equation in λ).

use super::delassus::Delassus;
use lopin_model::error::{LopinError, Result};

/// Iteration controls of the contact solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactControls {
    /// Stop when a sweep changes no force by more than `tol` × the largest force.
    pub tol: f64,
    /// Sweep limit per step (an error beyond it).
    pub max_sweeps: usize,
}

impl Default for ContactControls {
    fn default() -> Self {
        Self {
            tol: 1e-12,
            max_sweeps: 200_000,
        }
    }
}

/// Solves one step. `q`: relative velocities of the free solution (local frames); `v_lim`:
/// normal bound per pair; `friction`: f per pair, and whether the pair is bonded (w = 0, the
/// force free: its 3 × 3 block solved exactly; an empty list: none); `y`: forces
/// (P, −T₁, −T₂) per pair, used as the starting guess and overwritten. Returns (sweeps, last
/// relative change) and leaves w = q + D y in `w`.
pub fn solve_step(
    d: &Delassus,
    q: &[f64],
    v_lim: &[f64],
    (friction, bonded): (&[f64], &[bool]),
    y: &mut [f64],
    w: &mut [f64],
    controls: ContactControls,
) -> Result<(usize, f64)> {
    let n = d.n;
    // w = q + D y
    w.copy_from_slice(q);
    for j in 0..n {
        if y[j] != 0.0 {
            let col = d.column(j);
            let yj = y[j];
            w.iter_mut().zip(col).for_each(|(wi, c)| *wi += c * yj);
        }
    }
    let mut change = 0.0;
    for sweep in 1..=controls.max_sweeps {
        change = 0.0f64;
        let mut scale = 0.0f64;
        for p in 0..n / 3 {
            let i = 3 * p;
            let old = [y[i], y[i + 1], y[i + 2]];
            let new = if bonded.get(p).copied().unwrap_or(false) {
                // w = 0 on the pair: its 3 × 3 block solved exactly
                let block: [[f64; 3]; 3] =
                    std::array::from_fn(|r| std::array::from_fn(|c| d.at(i + r, i + c)));
                let step = solve3(block, [w[i], w[i + 1], w[i + 2]]);
                [old[0] - step[0], old[1] - step[1], old[2] - step[2]]
            } else {
                // normal: exact scalar solve with the tangential forces fixed
                let dnn = d.at(i, i);
                let pn = (old[0] + (v_lim[p] - w[i]) / dnn).max(0.0);
                // tangential: w_t = q̃ − D_tt T with T = −(y₁, y₂)
                let dtt = [
                    [d.at(i + 1, i + 1), d.at(i + 1, i + 2)],
                    [d.at(i + 2, i + 1), d.at(i + 2, i + 2)],
                ];
                let dtn = [d.at(i + 1, i), d.at(i + 2, i)];
                let t_old = [-old[1], -old[2]];
                let qt = [
                    w[i + 1] + dtn[0] * (pn - old[0]) + dtt[0][0] * t_old[0] + dtt[0][1] * t_old[1],
                    w[i + 2] + dtn[1] * (pn - old[0]) + dtt[1][0] * t_old[0] + dtt[1][1] * t_old[1],
                ];
                let t = coulomb_disc(dtt, qt, friction[p] * pn);
                [pn, -t[0], -t[1]]
            };
            let delta = [new[0] - old[0], new[1] - old[1], new[2] - old[2]];
            for (k, &dk) in delta.iter().enumerate() {
                if dk != 0.0 {
                    let col = d.column(i + k);
                    w.iter_mut().zip(col).for_each(|(wi, c)| *wi += c * dk);
                }
                change = change.max(dk.abs());
            }
            y[i..i + 3].copy_from_slice(&new);
            scale = scale.max(new[0].abs()).max(new[1].abs()).max(new[2].abs());
        }
        if !change.is_finite() {
            return Err(LopinError::Reference(
                "contact forces became non-finite".to_string(),
            ));
        }
        if change <= controls.tol * scale || scale == 0.0 {
            return Ok((sweep, if scale > 0.0 { change / scale } else { 0.0 }));
        }
    }
    Err(LopinError::Reference(format!(
        "contact iteration not converged after {} sweeps (last change {change:.3e})",
        controls.max_sweeps
    )))
}

/// The tangential force T for fixed normal force: w_t = q − D T with D SPD 2×2, |T| ≤ r;
/// stick (w_t = 0) if D⁻¹q lies in the disc, else slip: T = (D + λI)⁻¹ q with λ ≥ 0 and |T| = r.
pub fn coulomb_disc(d: [[f64; 2]; 2], q: [f64; 2], r: f64) -> [f64; 2] {
    if r <= 0.0 {
        return [0.0, 0.0];
    }
    let solve = |lam: f64| shifted_solve(d, lam, q);
    let len = |t: [f64; 2]| t[0].hypot(t[1]);
    let stick = solve(0.0);
    if len(stick) <= r {
        return stick;
    }
    // |T(λ)| decreases from |stick| > r to 0: bracket and solve |T(λ)| = r.
    // Newton on φ(λ) = 1/|T(λ)| − 1/r (nearly linear in λ), safeguarded by bisection.
    let (mut lo, mut hi) = (0.0, q[0].hypot(q[1]) / r);
    let mut lam = 0.0;
    for _ in 0..200 {
        let t = solve(lam);
        let l = len(t);
        let phi = 1.0 / l - 1.0 / r;
        if phi < 0.0 {
            lo = lam;
        } else {
            hi = lam;
        }
        // dφ/dλ = (Tᵀ (D + λI)⁻¹ T) / |T|³
        let s = shifted_solve(d, lam, t);
        let dphi = (t[0] * s[0] + t[1] * s[1]) / (l * l * l);
        let mut next = lam - phi / dphi;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - lam).abs() <= 1e-15 * next.abs().max(f64::MIN_POSITIVE) {
            lam = next;
            break;
        }
        lam = next;
    }
    let t = solve(lam);
    // land exactly on the circle
    let l = len(t);
    [t[0] * r / l, t[1] * r / l]
}

/// x with a x = b for a 3 × 3 matrix (Cramer's rule).
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> [f64; 3] {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    std::array::from_fn(|c| {
        let mut m = a;
        for (r, row) in m.iter_mut().enumerate() {
            row[c] = b[r];
        }
        det(m) / d
    })
}

/// (D + λI)⁻¹ q for a symmetric 2×2 D.
fn shifted_solve(d: [[f64; 2]; 2], lam: f64, q: [f64; 2]) -> [f64; 2] {
    let (a, b, c) = (d[0][0] + lam, d[0][1], d[1][1] + lam);
    let det = a * c - b * b;
    [(c * q[0] - b * q[1]) / det, (a * q[1] - b * q[0]) / det]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stick_inside_the_disc_and_slip_on_its_rim() {
        let d = [[2.0, 0.5], [0.5, 1.0]];
        // stick: D⁻¹ q small
        let t = coulomb_disc(d, [0.1, 0.05], 1.0);
        let w = [0.1 - (2.0 * t[0] + 0.5 * t[1]), 0.05 - (0.5 * t[0] + t[1])];
        assert!(w[0].abs() < 1e-15 && w[1].abs() < 1e-15);
        // slip: |T| = r and w_t = λ T with λ > 0
        let q = [3.0, -2.0];
        let t = coulomb_disc(d, q, 0.7);
        assert!((t[0].hypot(t[1]) - 0.7).abs() < 1e-14);
        let w = [q[0] - (2.0 * t[0] + 0.5 * t[1]), q[1] - (0.5 * t[0] + t[1])];
        let cross = w[0] * t[1] - w[1] * t[0];
        let along = w[0] * t[0] + w[1] * t[1];
        assert!(cross.abs() < 1e-12 && along > 0.0, "{w:?} {t:?}");
    }

    #[test]
    fn single_pair_closes_the_gap_exactly() {
        // one pair, isotropic D: approaching at −2 with V_lim = −0.5 ⇒ P = 1.5 / D_nn
        let d = Delassus {
            n: 3,
            d: vec![2.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 2.0],
        };
        let ctl = ContactControls::default();
        let solve = |q: [f64; 3], y: &mut [f64; 3], w: &mut [f64; 3]| {
            solve_step(&d, &q, &[-0.5], (&[0.1], &[]), y, w, ctl).expect("solve");
        };
        let (mut y, mut w) = ([0.0; 3], [0.0; 3]);
        solve([-2.0, 1.0, 0.0], &mut y, &mut w);
        assert!((y[0] - 0.75).abs() < 1e-15 && (w[0] + 0.5).abs() < 1e-15);
        // slip: |T| = f P = 0.075 against w_t = 1 − 2 T
        assert!((y[1].abs() - 0.075).abs() < 1e-15);
        assert!(w[1] > 0.0 && -y[1] > 0.0);
        // separating: no force
        let mut y = [0.0; 3];
        solve([1.0, 1.0, 0.0], &mut y, &mut w);
        assert_eq!(y, [0.0; 3]);
    }

    /// A bonded pair (non-matching perfect interface) ends at w = 0 whatever its approach,
    /// its force −D⁻¹ q, here with a coupled 3 × 3 block.
    #[test]
    fn a_bonded_pair_ends_at_rest_relative_to_its_other_side() {
        let d = Delassus {
            n: 3,
            d: vec![2.0, 0.5, 0.0, 0.5, 1.5, 0.2, 0.0, 0.2, 1.0],
        };
        let q = [1.0, -2.0, 0.5];
        let (mut y, mut w) = ([0.0; 3], [0.0; 3]);
        let ctl = ContactControls::default();
        solve_step(&d, &q, &[-0.5], (&[0.0], &[true]), &mut y, &mut w, ctl).expect("solve");
        assert!(w.iter().all(|x| x.abs() < 1e-14), "{w:?}");
        for (r, &qr) in q.iter().enumerate() {
            let dy: f64 = (0..3).map(|c| d.at(r, c) * y[c]).sum();
            assert!((qr + dy).abs() < 1e-14);
        }
    }
}
