//! The numerical stability stress suite: small scenes under adverse settings — search direction
//! k far from the impedance, relaxation μ, stiffness and density contrasts, time steps far from
//! the element transit time, long runs, large friction coefficients, gaps from zero to never
//! closing, high-speed impacts, degenerate layouts — each solved and judged:
//!
//! * every η and every interface value finite;
//! * η below the tolerance, or a clear "not converged after N iterations" where the case allows
//!   it (never a hang: every solve is bounded by its iteration limit);
//! * energy (METHOD §2 identity), conservative cases (no contact, solved to η < 1e-9):
//!   |E_m / (E₀ + W_in,m) − 1| ≤ 1e-6 at every step — no growth and no numerical dissipation;
//! * energy, contact cases: the converged discrete solution (the monolithic reference of the
//!   same problem) never exceeds E₀ + W_in,m by more than 1e-6 relative, and the LATIN iterate at
//!   tolerance tol by no more than 10·tol (its interface fields are off by O(η));
//! * interpenetration (METHOD §5 persistent law): min gap ≥ −Δt·v/2 with v the fastest approach
//!   speed the scene can produce, for LATIN and for the reference.
//!
//! `quick()` is the CI test set; `full()` adds the longer cases run by `lopin stress`.

use lopin_core::counters::Instant;
use lopin_core::error::Result;
use lopin_core::post;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::solver::{Settings, Solver};

use lopin_reference::monolithic::Monolithic;

/// Relative energy bound of converged discrete solutions.
pub const ENERGY_BOUND: f64 = 1e-6;

/// Energy bound of a LATIN iterate at tolerance tol, as a multiple of tol.
pub const ITERATE_ENERGY_FACTOR: f64 = 10.0;

/// One adverse case.
#[derive(Debug, Clone)]
pub struct StressCase {
    /// Family (k, mu, contrast, dt, long, friction, gap, impact, degenerate).
    pub group: &'static str,
    /// Case name.
    pub name: String,
    /// The scene.
    pub spec: SceneSpec,
    /// k as a multiple of the default √(ρE) mean.
    pub k_factor: f64,
    /// Relaxation μ.
    pub mu: f64,
    /// Tolerance on η.
    pub tol: f64,
    /// Iteration limit per window.
    pub max_iter: usize,
    /// Time-window length (None: whole interval).
    pub window: Option<usize>,
    /// Whether "not converged after max_iter" is an acceptable, reported result.
    pub may_stall: bool,
    /// Whether the contact must stay open all along (no force at all).
    pub never_closes: bool,
}

/// What a case gave.
#[derive(Debug, Clone, PartialEq)]
pub struct StressOutcome {
    /// Family.
    pub group: &'static str,
    /// Case name.
    pub name: String,
    /// Dofs.
    pub dofs: usize,
    /// Steps.
    pub steps: usize,
    /// LATIN iterations.
    pub iterations: usize,
    /// Final η.
    pub eta: f64,
    /// Whether η < tol in every window.
    pub converged: bool,
    /// max_m E_m / (E₀ + W_in,m).
    pub max_energy_ratio: f64,
    /// Smallest gap (None without contact).
    pub min_gap: Option<f64>,
    /// The reference's max_m E_m / (E₀ + W_in,m) (contact cases).
    pub reference_energy_ratio: Option<f64>,
    /// The reference's smallest gap (contact cases).
    pub reference_min_gap: Option<f64>,
    /// The penetration the law allows.
    pub penetration_bound: f64,
    /// Largest step-averaged normal force.
    pub peak_normal_force: f64,
    /// Wall time of the solve and the checks (s).
    pub wall_s: f64,
    /// "pass", "not converged after N iterations" or "FAIL: reason".
    pub verdict: String,
    /// Whether the verdict is acceptable.
    pub ok: bool,
}

impl StressCase {
    fn new(group: &'static str, name: impl Into<String>, spec: SceneSpec) -> Self {
        Self {
            group,
            name: name.into(),
            spec,
            k_factor: 1.0,
            mu: 0.8,
            tol: 1e-3,
            max_iter: 3000,
            window: None,
            may_stall: false,
            never_closes: false,
        }
    }

    /// Fastest approach speed the scene can produce: its largest initial or prescribed speed.
    fn approach_speed(&self) -> f64 {
        let init = self
            .spec
            .bodies
            .iter()
            .flat_map(|b| b.velocity)
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let presc = self
            .spec
            .boundaries
            .iter()
            .flat_map(|b| [&b.x, &b.y, &b.z])
            .flatten()
            .filter_map(|c| c.velocity)
            .fold(0.0f64, |a, v| a.max(v.abs()));
        // two bodies can approach at the sum of their speeds
        2.0 * init.max(presc)
    }

    /// Solves the case and judges it.
    pub fn run(&self) -> Result<StressOutcome> {
        let clock = Instant::now();
        let problem = scene::problem_of(&self.spec, &self.name)?;
        let mut settings = Settings::for_problem(&problem, &self.spec.solver);
        settings.k *= self.k_factor;
        settings.mu = self.mu;
        settings.tol = self.tol;
        settings.max_iter = self.max_iter;
        settings.window = self.window;
        let dofs = problem.dof_count();
        let (steps, dt) = (problem.time.steps, problem.time.dt);
        let reference = if problem.contact_count() > 0 {
            let mono = Monolithic::new(problem.clone())?;
            let sol = mono.solve()?;
            Some(mono.summary(&sol))
        } else {
            None
        };
        let mut solver = Solver::new(problem, settings)?;
        let sol = solver.solve(None)?;
        let energy = post::energy(&solver, &sol);
        let contact = post::contact(&solver, &sol);
        let summary = post::Summary::from_histories(&energy, &contact);
        let e0 = energy.total(0);
        let min_ratio = (1..=steps)
            .filter_map(|m| {
                let avail = e0 + energy.input_work[m];
                (avail > 0.0).then(|| energy.total(m) / avail)
            })
            .fold(f64::INFINITY, f64::min);
        let penetration_bound = 0.5 * dt * self.approach_speed() * (1.0 + 1e-9) + 1e-15;
        let finite = sol.eta_history.iter().all(|e| e.is_finite())
            && sol
                .hats
                .iter()
                .flatten()
                .all(|h| h.f.iter().chain(&h.w).all(|x| x.is_finite()))
            && energy
                .kinetic
                .iter()
                .chain(&energy.strain)
                .all(|x| x.is_finite());
        let conservative = contact.is_empty();
        let mut failures = Vec::new();
        if !finite {
            failures.push("non-finite values".to_string());
        }
        let iterate_bound = if conservative {
            ENERGY_BOUND
        } else {
            ENERGY_BOUND.max(ITERATE_ENERGY_FACTOR * self.tol)
        };
        if summary.max_total_over_input > 1.0 + iterate_bound {
            failures.push(format!(
                "energy grows: max E/(E0+W) = {:.9}",
                summary.max_total_over_input
            ));
        }
        if conservative && sol.converged && min_ratio < 1.0 - ENERGY_BOUND {
            failures.push(format!(
                "energy lost in a conservative case: min E/(E0+W) = {min_ratio:.9}"
            ));
        }
        if let Some(r) = &reference {
            if r.max_total_over_input > 1.0 + ENERGY_BOUND {
                failures.push(format!(
                    "reference energy grows: max E/(E0+W) = {:.9}",
                    r.max_total_over_input
                ));
            }
        }
        for (who, g) in [
            ("", summary.min_gap),
            ("reference ", reference.as_ref().and_then(|r| r.min_gap)),
        ] {
            if let Some(g) = g {
                if g < -penetration_bound {
                    failures.push(format!(
                        "{who}interpenetration {g:.3e} m beyond the bound {penetration_bound:.3e} m"
                    ));
                }
            }
        }
        if self.never_closes && summary.peak_normal_force != 0.0 {
            failures.push(format!(
                "contact force {:.3e} N on a gap that never closes",
                summary.peak_normal_force
            ));
        }
        if !sol.converged && !self.may_stall {
            failures.push(format!(
                "not converged after {} iterations (eta {:.2e})",
                sol.iterations, sol.eta
            ));
        }
        let (verdict, ok) = if !failures.is_empty() {
            (format!("FAIL: {}", failures.join("; ")), false)
        } else if sol.converged {
            ("pass".to_string(), true)
        } else {
            (
                format!(
                    "not converged after {} iterations (eta {:.2e}), stable",
                    sol.iterations, sol.eta
                ),
                true,
            )
        };
        Ok(StressOutcome {
            group: self.group,
            name: self.name.clone(),
            dofs,
            steps,
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            max_energy_ratio: summary.max_total_over_input,
            min_gap: summary.min_gap,
            reference_energy_ratio: reference.as_ref().map(|r| r.max_total_over_input),
            reference_min_gap: reference.as_ref().and_then(|r| r.min_gap),
            penetration_bound,
            peak_normal_force: summary.peak_normal_force,
            wall_s: clock.elapsed().as_secs_f64(),
            verdict,
            ok,
        })
    }
}

/// A built-in or test scene of the registry (`assets/scenes/`, `assets/scenes/test/`: the
/// registry's unit tests parse every one). The test scenes are the small sizes the cases vary:
/// `mini-blocks` (two-blocks with 4 × 4 × 2 hexahedra per block), `mini-impact` (gap-impact with
/// 3 × 3 × 3 per cube) and `mini-bar` (bar with 4 hexahedra in 2 substructures).
fn builtin(name: &str) -> SceneSpec {
    scene::registry::builtin(name).unwrap_or_else(|| unreachable!("{name} is in the registry"))
}

/// Element transit time h/c (P-wave) of the stiffest material of a scene's first body.
fn transit_time(s: &SceneSpec) -> f64 {
    let b = &s.bodies[0];
    let h = (0..3)
        .map(|a| (b.max[a] - b.min[a]) / b.divisions[a] as f64)
        .fold(f64::INFINITY, f64::min);
    let c = s
        .materials
        .iter()
        .map(|m| m.material().p_wave_speed())
        .fold(0.0, f64::max);
    h / c
}

/// The CI set: every family of the issue at a size that runs in well under a minute.
pub fn quick() -> Vec<StressCase> {
    let mut cases = Vec::new();
    for kf in [1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3] {
        let mut c = StressCase::new(
            "k",
            format!("mini-blocks k = {kf:.0e} Z"),
            builtin("mini-blocks"),
        );
        c.k_factor = kf;
        c.may_stall = !(1e-1..=1e1).contains(&kf);
        cases.push(c);
    }
    for mu in [0.3, 0.5, 0.8, 1.0] {
        let mut c = StressCase::new(
            "mu",
            format!("mini-blocks mu = {mu}"),
            builtin("mini-blocks"),
        );
        c.mu = mu;
        cases.push(c);
    }
    // contrasts on the bimaterial bar (conservative: tight tolerance for the energy check)
    for (label, young, density) in [
        ("stiffness contrast 1e4", 1e-4, 1.0),
        ("density contrast 1e3", 1.0, 1e-3),
        ("both contrasts", 1e-4, 1e-3),
    ] {
        let mut s = builtin("bar-bimaterial");
        s.materials[1].young = s.materials[0].young * young;
        s.materials[1].density = s.materials[0].density * density;
        let mut c = StressCase::new("contrast", format!("bar-bimaterial {label}"), s);
        c.tol = 1e-9;
        c.max_iter = 20_000;
        cases.push(c);
    }
    {
        let mut s = builtin("mini-blocks");
        s.materials[1].young = s.materials[0].young * 1e-4;
        let mut c = StressCase::new("contrast", "mini-blocks stiffness contrast 1e4", s);
        c.max_iter = 5000;
        cases.push(c);
    }
    for factor in [0.01, 0.1, 1.0, 10.0] {
        let mut s = builtin("mini-impact");
        let dt = factor * transit_time(&s);
        let total = 40e-6;
        s.time.dt = dt;
        s.time.steps = ((total / dt).ceil() as usize).max(4);
        let mut c = StressCase::new("dt", format!("mini-impact dt = {factor} h/c"), s);
        c.window = (factor < 0.1).then_some(50);
        cases.push(c);
    }
    {
        // bar of 2 substructures pushed at x = 0 for 10⁴ steps of Δt ≈ h/c: ~250 wave round trips
        let mut s = builtin("mini-bar");
        s.time.dt = 4.8e-6;
        s.time.steps = 10_000;
        if let Some(x) = &mut s.boundaries[0].x {
            x.ramp_time = 10.0 * s.time.dt;
        }
        let mut c = StressCase::new("long", "bar 10^4 steps, 250 round trips", s);
        c.window = Some(100);
        c.tol = 1e-10;
        c.max_iter = 20_000;
        cases.push(c);
    }
    {
        // a clamped body that starts moving: the velocity jump at t₀ excites the Nyquist mode
        // (METHOD §10); η stalls, and the suite asks only for a clear result
        let mut s = builtin("mini-bar");
        s.bodies[0].velocity = [1.0, 0.0, 0.0];
        s.boundaries[0].x = None;
        s.boundaries[0].clamped = true;
        s.time.steps = 1000;
        let mut c = StressCase::new("long", "bar clamped with v0 = 1 m/s (velocity jump)", s);
        c.window = Some(100);
        c.max_iter = 1000;
        c.may_stall = true;
        cases.push(c);
    }
    for f in [0.0, 0.5, 2.0, 10.0] {
        let mut s = builtin("mini-blocks");
        s.set_friction(f);
        cases.push(StressCase::new(
            "friction",
            format!("mini-blocks f = {f}"),
            s,
        ));
    }
    for (label, g0, search) in [
        ("0", 0.0, None),
        ("1e-6", 1e-6, None),
        ("1e-4", 1e-4, None),
        ("1e-2 (never closes)", 1e-2, Some(2e-2)),
    ] {
        let mut s = builtin("mini-impact");
        if g0 > 0.0 {
            // move A up so that the geometric gap is g0
            let dz = 0.02 + g0 - s.bodies[0].min[2];
            s.bodies[0].min[2] += dz;
            s.bodies[0].max[2] += dz;
        } else {
            s.bodies[0].min[2] = 0.02;
            s.bodies[0].max[2] = 0.04;
        }
        if let Some(sr) = search {
            s.interfaces[0].search = Some(sr);
        }
        let mut c = StressCase::new("gap", format!("mini-impact gap {label}"), s);
        c.never_closes = g0 >= 1e-2;
        cases.push(c);
    }
    for v in [50.0, 500.0] {
        let mut s = builtin("mini-impact");
        s.bodies[0].velocity = [0.0, 0.0, -v];
        cases.push(StressCase::new(
            "impact",
            format!("mini-impact at {v} m/s"),
            s,
        ));
    }
    {
        let mut s = builtin("bar");
        s.bodies[0].split = [1, 1, 1];
        cases.push(StressCase::new(
            "degenerate",
            "bar, a single substructure",
            s,
        ));
    }
    {
        // both cubes floating: no boundary condition at all, B at rest, A falls on it
        let mut s = builtin("mini-impact");
        s.boundaries.clear();
        cases.push(StressCase::new(
            "degenerate",
            "mini-impact, both cubes floating",
            s,
        ));
    }
    {
        let mut s = builtin("bar");
        s.boundaries.clear();
        s.bodies[0].velocity = [2.0, 0.0, 0.0];
        let mut c = StressCase::new("degenerate", "bar floating, no contact, no BC", s);
        c.tol = 1e-9;
        cases.push(c);
    }
    cases
}

/// The longer set of `lopin stress`: the quick set on the full-size scenes plus extremes.
pub fn full() -> Vec<StressCase> {
    let mut cases = quick();
    for kf in [1e-3, 1e-1, 1.0, 1e1, 1e3] {
        let mut c = StressCase::new(
            "k",
            format!("two-blocks k = {kf:.0e} Z"),
            builtin("two-blocks"),
        );
        c.k_factor = kf;
        c.may_stall = !(1e-1..=1e1).contains(&kf);
        cases.push(c);
    }
    for f in [0.0, 1.0, 10.0] {
        let mut s = builtin("two-blocks");
        s.set_friction(f);
        cases.push(StressCase::new(
            "friction",
            format!("two-blocks f = {f}"),
            s,
        ));
    }
    for v in [5.0, 100.0, 1000.0] {
        let mut s = builtin("gap-impact");
        s.bodies[0].velocity = [0.0, 0.0, -v];
        cases.push(StressCase::new(
            "impact",
            format!("gap-impact at {v} m/s"),
            s,
        ));
    }
    {
        let mut s = builtin("mini-impact");
        s.time.steps = 10_000;
        s.time.dt = 0.25e-6;
        let mut c = StressCase::new("long", "mini-impact 10^4 steps", s);
        c.window = Some(100);
        cases.push(c);
    }
    cases
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stalled_solve_fails_unless_the_case_allows_it() {
        let mut c = quick()
            .into_iter()
            .find(|c| c.name == "mini-blocks mu = 0.8")
            .expect("case");
        c.max_iter = 3;
        let o = c.run().expect("runs");
        assert!(
            !o.ok && o.verdict.contains("not converged after 3 iterations"),
            "{o:?}"
        );
        c.may_stall = true;
        let o = c.run().expect("runs");
        assert!(o.ok && o.verdict.starts_with("not converged"), "{o:?}");
    }

    #[test]
    fn energy_growth_is_caught() {
        // a conservative case stopped early: the iterate's energy error exceeds 1e-6
        let mut c = quick()
            .into_iter()
            .find(|c| c.name == "bar floating, no contact, no BC")
            .expect("case");
        c.tol = 0.5;
        c.may_stall = true;
        let o = c.run().expect("runs");
        println!("{o:?}");
        assert!(!o.ok && o.verdict.contains("energy"), "{o:?}");
    }
}
