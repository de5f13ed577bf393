//! An independent monolithic solver of the 1D discretization of METHOD §12: chains of lumped
//! masses and springs, trapezoidal rule in velocity form (METHOD §2), a prescribed velocity
//! imposed strongly (eliminated), and at most one node-to-node unilateral contact solved exactly
//! at each step with the persistent normal law of METHOD §5 (a scalar complementarity problem,
//! since each chain's response to the contact force is linear). Tridiagonal solves by Thomas.

use lopin_core::time::time_function::TimeFunction;

/// A chain of nodes joined by springs.
#[derive(Debug, Clone)]
pub struct Chain {
    /// Lumped nodal masses.
    pub mass: Vec<f64>,
    /// Spring stiffness of each element (EA/h).
    pub stiffness: Vec<f64>,
    /// Initial nodal velocities.
    pub velocity: Vec<f64>,
}

impl Chain {
    /// A chain of elements (E, ρ, length h each), section area `area`.
    pub fn of_elements(elements: &[(f64, f64)], h: f64, area: f64, v0: f64) -> Self {
        let n = elements.len();
        let mut mass = vec![0.0; n + 1];
        let mut stiffness = Vec::with_capacity(n);
        for (e, &(young, rho)) in elements.iter().enumerate() {
            mass[e] += 0.5 * rho * area * h;
            mass[e + 1] += 0.5 * rho * area * h;
            stiffness.push(young * area / h);
        }
        Self {
            mass,
            stiffness,
            velocity: vec![v0; n + 1],
        }
    }
}

/// Node-to-node contact: node `a.1` of chain `a.0` (side 1) against node `b.1` of chain `b.0`,
/// normal +x from side 1 to side 2, initial gap `gap`, contact area `area`.
#[derive(Debug, Clone, Copy)]
pub struct Contact {
    /// Side 1 (chain, node).
    pub a: (usize, usize),
    /// Side 2 (chain, node).
    pub b: (usize, usize),
    /// Initial gap.
    pub gap: f64,
}

/// The computed history.
#[derive(Debug, Clone)]
pub struct History {
    /// Velocities `[m][chain][node]`.
    pub v: Vec<Vec<Vec<f64>>>,
    /// Total energy per step.
    pub energy: Vec<f64>,
    /// Gap per step (with contact).
    pub gap: Vec<f64>,
}

/// Marches all chains over `steps` steps of `dt`.
pub fn march(
    chains: &[Chain],
    dt: f64,
    steps: usize,
    push: Option<TimeFunction>,
    contact: Option<Contact>,
) -> History {
    let nc = chains.len();
    // tridiagonal S = 2/Δt M + Δt/2 K per chain (with node 0 of chain 0 eliminated under push)
    let ops: Vec<Tridiag> = chains.iter().map(|c| Tridiag::operator(c, dt)).collect();
    let mut u: Vec<Vec<f64>> = chains.iter().map(|c| vec![0.0; c.mass.len()]).collect();
    let mut v: Vec<Vec<f64>> = chains.iter().map(|c| c.velocity.clone()).collect();
    let mut a: Vec<Vec<f64>> = chains.iter().map(|c| vec![0.0; c.mass.len()]).collect();
    let fixed = |ci: usize| push.is_some() && ci == 0;
    // responses of the contact nodes to a unit pair of contact forces
    let g = contact.map(|c| {
        let resp = |(ci, node): (usize, usize)| {
            let mut e = vec![0.0; chains[ci].mass.len()];
            e[node] = 1.0;
            ops[ci].solve(&e, fixed(ci).then_some(0.0))[node]
        };
        resp(c.a) + resp(c.b)
    });
    let mut gap = contact.map_or(0.0, |c| c.gap);
    let mut jn_prev = contact.map_or(0.0, |c| v[c.b.0][c.b.1] - v[c.a.0][c.a.1]);
    let mut hist = History {
        v: vec![v.clone()],
        energy: vec![energy(chains, &u, &v)],
        gap: vec![gap],
    };
    for m in 1..=steps {
        let t = dt * m as f64;
        let mut vn: Vec<Vec<f64>> = (0..nc)
            .map(|ci| {
                let r = residual(&chains[ci], dt, &u[ci], &v[ci], &a[ci]);
                let fixed_v = fixed(ci).then(|| push.as_ref().map_or(0.0, |f| f.value(t)));
                ops[ci].solve(&r, fixed_v)
            })
            .collect();
        if let (Some(c), Some(g)) = (contact, g) {
            let jn_free = vn[c.b.0][c.b.1] - vn[c.a.0][c.a.1];
            let v_lim = (-2.0 * gap / dt - jn_prev).min(0.0);
            if jn_free < v_lim {
                let p = (v_lim - jn_free) / g;
                for (side, sign) in [(c.a, -1.0), (c.b, 1.0)] {
                    let mut e = vec![0.0; chains[side.0].mass.len()];
                    e[side.1] = sign * p;
                    let dv = ops[side.0].solve(&e, fixed(side.0).then_some(0.0));
                    vn[side.0].iter_mut().zip(dv).for_each(|(x, d)| *x += d);
                }
            }
            let jn = vn[c.b.0][c.b.1] - vn[c.a.0][c.a.1];
            gap += 0.5 * dt * (jn_prev + jn);
            jn_prev = jn;
        }
        for ci in 0..nc {
            for i in 0..vn[ci].len() {
                let an = 2.0 / dt * (vn[ci][i] - v[ci][i]) - a[ci][i];
                u[ci][i] += 0.5 * dt * (v[ci][i] + vn[ci][i]);
                a[ci][i] = an;
            }
        }
        v = vn;
        hist.v.push(v.clone());
        hist.energy.push(energy(chains, &u, &v));
        hist.gap.push(gap);
    }
    hist
}

fn residual(c: &Chain, dt: f64, u: &[f64], v: &[f64], a: &[f64]) -> Vec<f64> {
    // r = M(2/Δt v + a) − K(u + Δt/2 v)
    let y: Vec<f64> = u.iter().zip(v).map(|(u, v)| u + 0.5 * dt * v).collect();
    let mut r: Vec<f64> = (0..u.len())
        .map(|i| c.mass[i] * (2.0 / dt * v[i] + a[i]))
        .collect();
    for (e, &k) in c.stiffness.iter().enumerate() {
        let f = k * (y[e + 1] - y[e]);
        r[e] += f;
        r[e + 1] -= f;
    }
    r
}

fn energy(chains: &[Chain], u: &[Vec<f64>], v: &[Vec<f64>]) -> f64 {
    let mut e = 0.0;
    for (ci, c) in chains.iter().enumerate() {
        e += 0.5
            * c.mass
                .iter()
                .zip(&v[ci])
                .map(|(m, v)| m * v * v)
                .sum::<f64>();
        e += 0.5
            * c.stiffness
                .iter()
                .enumerate()
                .map(|(i, k)| k * (u[ci][i + 1] - u[ci][i]).powi(2))
                .sum::<f64>();
    }
    e
}

/// Symmetric tridiagonal matrix (diagonal, off-diagonal).
struct Tridiag {
    diag: Vec<f64>,
    off: Vec<f64>,
}

impl Tridiag {
    fn operator(c: &Chain, dt: f64) -> Self {
        let mut diag: Vec<f64> = c.mass.iter().map(|m| 2.0 / dt * m).collect();
        let mut off = vec![0.0; c.stiffness.len()];
        for (e, &k) in c.stiffness.iter().enumerate() {
            diag[e] += 0.5 * dt * k;
            diag[e + 1] += 0.5 * dt * k;
            off[e] = -0.5 * dt * k;
        }
        Self { diag, off }
    }

    /// Solves S x = r; with `fixed = Some(x0)` node 0 is prescribed (row 0 dropped).
    fn solve(&self, r: &[f64], fixed: Option<f64>) -> Vec<f64> {
        let n = self.diag.len();
        let start = usize::from(fixed.is_some());
        let mut rhs = r.to_vec();
        if let Some(x0) = fixed {
            rhs[1] -= self.off[0] * x0;
        }
        // Thomas on rows start..n
        let mut c = vec![0.0; n];
        let mut d = vec![0.0; n];
        for i in start..n {
            let lower = if i > start { self.off[i - 1] } else { 0.0 };
            let denom = self.diag[i] - lower * if i > start { c[i - 1] } else { 0.0 };
            c[i] = if i + 1 < n { self.off[i] / denom } else { 0.0 };
            d[i] = (rhs[i] - lower * if i > start { d[i - 1] } else { 0.0 }) / denom;
        }
        let mut x = vec![0.0; n];
        for i in (start..n).rev() {
            x[i] = d[i] - if i + 1 < n { c[i] * x[i + 1] } else { 0.0 };
        }
        if let Some(x0) = fixed {
            x[0] = x0;
        }
        x
    }
}
