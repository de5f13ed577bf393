//! The time march of the assembled structure: the scheme of METHOD §2 (the trapezoidal rule, or
//! its dissipative Bossak–Newmark extension of `lopin_model::time::time_scheme`, the same discrete
//! problem LATIN solves) on all dofs at once, prescribed velocities imposed strongly, prescribed
//! tractions as nodal loads, and at each step the contact problem of the pairs solved on the
//! Delassus operator (contact_solve.rs).
//!
//!   (c_M M + C + c_K K) v_m = f_ext,m + M(c_M v_{m−1} + c_A a_{m−1}) − K(u_{m−1} + d_V v_{m−1} + d_A a_{m−1}) + Gᵀ y_m
//!   u_m = u_{m−1} + d_V v_{m−1} + d_A a_{m−1} + c_K v_m,  a_m = e_V (v_m − v_{m−1}) − e_A a_{m−1}
//!   (trapezoidal: c_M = 2/Δt, c_K = d_V = Δt/2, c_A = e_A = 1, d_A = 0; C the Rayleigh damping,
//!   a₀ = −M⁻¹ C v₀)
//!   g_m = g_{m−1} + Δt/2 ([v_n]_{m−1} + [v_n]_m)   (METHOD §5 gap update, for every scheme)

use super::assembly::Assembled;
use super::contact_solve::{solve_step, ContactControls};
use super::delassus::{scatter, Delassus};
use lopin_model::counters::Instant;
use lopin_model::error::Result;
use lopin_model::linalg::factor::CholeskyFactor;
use lopin_model::mesh::{dot, Vec3};
use lopin_model::time::time_function::TimeGrid;
use lopin_model::time::time_scheme::StepCoefficients;

/// The reference solution: global fields at every step m = 0..=N and the contact history of
/// every pair.
#[derive(Debug, Clone, PartialEq)]
pub struct MonoSolution {
    /// Displacements per step (global dofs).
    pub u: Vec<Vec<f64>>,
    /// Velocities per step.
    pub v: Vec<Vec<f64>>,
    /// Accelerations per step.
    pub a: Vec<Vec<f64>>,
    /// Pair forces (P, T₁, T₂) per step and pair: force on side 1 = −P n + T₁ t₁ + T₂ t₂.
    pub pair_forces: Vec<Vec<[f64; 3]>>,
    /// Gap per step and pair.
    pub gaps: Vec<Vec<f64>>,
    /// Accumulated tangential relative displacement per step and pair.
    pub slips: Vec<Vec<Vec3>>,
    /// Total contact sweeps over all steps.
    pub sweeps: usize,
    /// Largest number of sweeps in one step.
    pub max_sweeps: usize,
    /// Largest final relative change of the contact iteration over the steps.
    pub contact_change: f64,
    /// Seconds in the sparse solves and vector updates.
    pub solve_s: f64,
    /// Seconds in the contact iteration.
    pub contact_s: f64,
}

/// Marches the whole time grid.
pub fn march(
    asm: &Assembled,
    factor: &CholeskyFactor,
    delassus: &Delassus,
    time: TimeGrid,
    c: StepCoefficients,
    controls: ContactControls,
    start: Option<&super::Start>,
) -> Result<MonoSolution> {
    let (dt, steps) = (time.dt, time.steps);
    let n = asm.numbering.dofs();
    let np = asm.pairs.len();
    let mut scratch = factor.scratch();
    // u₀ = 0, or the static equilibrium of a preload (at rest: its forces balance, a₀ = 0)
    let mut u = start.map_or_else(|| vec![0.0; n], |s| s.displacement.clone());
    let mut v = asm.v0.clone();
    // a₀ = −M⁻¹ C v₀: no force at t₀ but the damping of the initial velocity
    let mut a = vec![0.0; n];
    let mut cv = vec![0.0; if asm.damping.is_some() { n } else { 0 }];
    if let Some(c) = &asm.damping {
        c.mul_into(&v, &mut cv);
        for g in 0..n {
            a[g] = -cv[g] / asm.mass[g];
        }
    }
    let mut sol = MonoSolution {
        u: vec![u.clone()],
        v: vec![v.clone()],
        a: vec![a.clone()],
        pair_forces: vec![start.map_or_else(|| vec![[0.0; 3]; np], |s| s.pair_forces.clone())],
        gaps: vec![start.map_or_else(
            || asm.pairs.iter().map(|p| p.gap).collect(),
            |s| s.gaps.clone(),
        )],
        slips: vec![vec![[0.0; 3]; np]],
        sweeps: 0,
        max_sweeps: 0,
        contact_change: 0.0,
        solve_s: 0.0,
        contact_s: 0.0,
    };
    let jump = |v: &[f64], p: usize| -> Vec3 { std::array::from_fn(|q| asm.pairs[p].jump(v, q)) };
    let mut jn: Vec<f64> = (0..np)
        .map(|p| dot(asm.pairs[p].frame[0], jump(&v, p)))
        .collect();
    let mut gap: Vec<f64> = sol.gaps[0].clone();
    let mut slip = vec![[0.0; 3]; np];
    let tangential = |j: Vec3, nrm: Vec3| -> Vec3 {
        let jn = dot(j, nrm);
        std::array::from_fn(|q| j[q] - jn * nrm[q])
    };
    let mut jt_prev: Vec<Vec3> = (0..np)
        .map(|p| tangential(jump(&v, p), asm.pairs[p].frame[0]))
        .collect();
    let mut y = vec![0.0; 3 * np];
    let mut w = vec![0.0; 3 * np];
    let mut q = vec![0.0; 3 * np];
    let mut v_lim = vec![0.0; np];
    let friction: Vec<f64> = asm.pairs.iter().map(|p| p.friction).collect();
    let bonded: Vec<bool> = asm.pairs.iter().map(|p| p.bonded).collect();
    let mut tmp = vec![0.0; n];
    let mut ktmp = vec![0.0; n];
    let mut rhs = vec![0.0; asm.free];
    let mut v_new = vec![0.0; n];
    let any_prescribed = asm.free < n;
    // displacements of the previous step (the gap update of a dissipative scheme)
    let mut u_prev = if c.trapezoidal {
        Vec::new()
    } else {
        vec![0.0; n]
    };
    let mut kp = vec![0.0; if any_prescribed { n } else { 0 }];

    for m in 1..=steps {
        let clock = Instant::now();
        let t = time.time(m);
        for g in 0..n {
            tmp[g] = u[g] + c.u_from_v * v[g] + c.u_from_a * a[g];
        }
        asm.stiffness.mul_into(&tmp, &mut ktmp);
        // v_new holds the prescribed values (zero on free dofs) to form S_fp v_p
        for g in 0..n {
            v_new[g] = asm.prescribed[g].as_ref().map_or(0.0, |f| f.value(t));
        }
        if any_prescribed {
            asm.stiffness.mul_into(&v_new, &mut kp);
            if let Some(damping) = &asm.damping {
                damping.mul_into(&v_new, &mut cv);
            }
        }
        for g in 0..n {
            let fi = asm.free_index[g];
            if fi != usize::MAX {
                let coupling = if any_prescribed {
                    c.stiffness * kp[g] + cv.get(g).copied().unwrap_or(0.0)
                } else {
                    0.0
                };
                rhs[fi] = asm.mass[g] * (c.mass * v[g] + c.mass_a * a[g]) - ktmp[g] - coupling;
            }
        }
        for &(g, area, ref f) in &asm.tractions {
            let fi = asm.free_index[g];
            if fi != usize::MAX {
                rhs[fi] += area * f.value(t);
            }
        }
        factor.solve_in_place(&mut rhs, &mut scratch);
        for g in 0..n {
            let fi = asm.free_index[g];
            if fi != usize::MAX {
                v_new[g] = rhs[fi];
            }
        }
        sol.solve_s += clock.elapsed().as_secs_f64();

        let mut forces = vec![[0.0; 3]; np];
        if np > 0 {
            let clock = Instant::now();
            for p in 0..np {
                let j = jump(&v_new, p);
                for k in 0..3 {
                    q[3 * p + k] = dot(asm.pairs[p].frame[k], j);
                }
                let an = dot(asm.pairs[p].frame[0], jump(&a, p));
                let v_star = c.closing_velocity(gap[p], jn[p], an);
                // statics: Signorini's law (an interference is undone); dynamics: the
                // persistent law (a penetrated pair is not pushed apart)
                v_lim[p] = if c.statics { v_star } else { v_star.min(0.0) };
            }
            let (sweeps, change) = solve_step(
                delassus,
                &q,
                &v_lim,
                (&friction, &bonded),
                &mut y,
                &mut w,
                controls,
            )?;
            sol.sweeps += sweeps;
            sol.max_sweeps = sol.max_sweeps.max(sweeps);
            sol.contact_change = sol.contact_change.max(change);
            sol.contact_s += clock.elapsed().as_secs_f64();

            let clock = Instant::now();
            if y.iter().any(|&x| x != 0.0) {
                let mut corr = vec![0.0; asm.free];
                for (p, pair) in asm.pairs.iter().enumerate() {
                    let yg: Vec3 = std::array::from_fn(|c| {
                        (0..3).map(|k| y[3 * p + k] * pair.frame[k][c]).sum()
                    });
                    scatter(asm, pair, yg, &mut corr);
                }
                factor.solve_in_place(&mut corr, &mut scratch);
                for g in 0..n {
                    let fi = asm.free_index[g];
                    if fi != usize::MAX {
                        v_new[g] += corr[fi];
                    }
                }
            }
            for (p, pair) in asm.pairs.iter().enumerate() {
                let j = jump(&v_new, p);
                let jn_new = dot(pair.frame[0], j);
                let jt = tangential(j, pair.frame[0]);
                if c.trapezoidal {
                    gap[p] += 0.5 * dt * (jn[p] + jn_new);
                    for q in 0..3 {
                        slip[p][q] += 0.5 * dt * (jt_prev[p][q] + jt[q]);
                    }
                }
                jn[p] = jn_new;
                jt_prev[p] = jt;
                forces[p] = [y[3 * p], -y[3 * p + 1], -y[3 * p + 2]];
            }
            sol.solve_s += clock.elapsed().as_secs_f64();
        }

        let clock = Instant::now();
        if !c.trapezoidal {
            u_prev.copy_from_slice(&u);
        }
        for g in 0..n {
            (u[g], a[g]) = c.advance(u[g], v[g], a[g], v_new[g]);
        }
        if !c.trapezoidal {
            // gap and slip from the displacement jump of the scheme's update
            for (p, pair) in asm.pairs.iter().enumerate() {
                let du: Vec3 = std::array::from_fn(|q| pair.jump(&u, q) - pair.jump(&u_prev, q));
                gap[p] += dot(pair.frame[0], du);
                let dt_slip = tangential(du, pair.frame[0]);
                for q in 0..3 {
                    slip[p][q] += dt_slip[q];
                }
            }
        }
        std::mem::swap(&mut v, &mut v_new);
        sol.u.push(u.clone());
        sol.v.push(v.clone());
        sol.a.push(a.clone());
        sol.pair_forces.push(forces);
        sol.gaps.push(gap.clone());
        sol.slips.push(slip.clone());
        sol.solve_s += clock.elapsed().as_secs_f64();
    }
    Ok(sol)
}
