//! The exact solution of the `bar` scene (SCENES.md) before the wave reaches the free end:
//! d'Alembert's v(x, t) = V(t − x/c) behind the front, 0 ahead of it, with c = √(E/ρ) and V the
//! velocity prescribed at x = 0; used to show the discretization floor of the accuracy study.

use lopin_model::interfaces::interface::{DofLaw, Law};
use lopin_model::Problem;

/// The analytic x-velocity field of a 1D bar driven at x = 0.
pub struct BarExact {
    c: f64,
    drive: lopin_model::time::time_function::TimeFunction,
}

impl BarExact {
    /// Applies to single-material bars driven along x at x = 0 whose front stays inside the bar
    /// over the whole time grid; None otherwise.
    pub fn for_problem(p: &Problem) -> Option<Self> {
        let mats: Vec<usize> = p.subs.iter().map(|s| s.material_id).collect();
        if mats.iter().any(|&m| m != mats[0]) || p.materials[mats[0]].material.poisson != 0.0 {
            return None;
        }
        let mat = &p.materials[mats[0]].material;
        let c = mat.bar_speed();
        let length = p
            .subs
            .iter()
            .map(|s| s.mesh.bounding_box().1[0])
            .fold(0.0, f64::max);
        if c * p.time.end() >= length {
            return None;
        }
        let drive = p.interfaces.iter().find_map(|i| match &i.law {
            Law::Boundary(d) => d.iter().find_map(|b| match &b.law {
                DofLaw::Velocity(f) if b.component == 0 && f.amplitude != 0.0 => Some(f.clone()),
                _ => None,
            }),
            _ => None,
        })?;
        Some(Self { c, drive })
    }

    /// v_x(x, t).
    pub fn velocity(&self, x: f64, t: f64) -> f64 {
        let tau = t - x / self.c;
        if tau > 0.0 {
            self.drive.value(tau)
        } else {
            0.0
        }
    }
}

/// Relative space–time L2 error of the x-velocities: √(Σ (v − v_exact)²) / √(Σ v_exact²) over
/// every node of every substructure and every step; `velocity(sub, m)` gives nodal velocities.
pub fn l2_error(
    p: &Problem,
    exact: &BarExact,
    velocity: &mut dyn FnMut(usize, usize) -> Vec<f64>,
) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for m in 0..=p.time.steps {
        let t = p.time.time(m);
        for (s, sub) in p.subs.iter().enumerate() {
            let v = velocity(s, m);
            for (node, x) in sub.mesh.nodes.iter().enumerate() {
                let e = exact.velocity(x[0], t);
                num += (v[3 * node] - e).powi(2);
                den += e * e;
            }
        }
    }
    (num / den).sqrt()
}
