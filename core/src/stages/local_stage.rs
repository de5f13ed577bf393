//! Local stage (E+): the closed forms of METHOD §5, per interface node and step — perfect
//! (vectorized), prescribed velocity/traction (per dof), and unilateral contact with Coulomb
//! friction (sequential in time, persistent normal law V_lim = min(V*, 0)).

use crate::interfaces::interface::{Contact, DofLaw, Interface, Law};
use crate::mesh::{dot, Vec3};
use crate::state::{InterfaceState, TraceHistory};
use crate::time::time_function::TimeGrid;
use crate::time::time_scheme::StepCoefficients;

/// Running contact state carried from step to step: gap ĝ, normal jump [Ŵ_n] and, for a
/// dissipative scheme, the normal acceleration jump its displacement update needs, per node.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactRunning {
    /// ĝ per node.
    pub gap: Vec<f64>,
    /// [Ŵ_n] per node.
    pub normal_jump: Vec<f64>,
    /// [â_n] per node (zero at t₀: no interface force, no body load).
    pub normal_accel: Vec<f64>,
}

impl ContactRunning {
    /// The state at t₀: ĝ₀ = g0 (after the preload, if any), [Ŵ_n]₀ = n·(W₂ − W₁) from the
    /// initial velocities.
    pub fn initial(iface: &Interface, contact: &Contact, s: &InterfaceState) -> Self {
        let (w1, w2) = side_values(iface, s, 0);
        let normal_jump: Vec<f64> = contact
            .normal
            .iter()
            .enumerate()
            .map(|(i, n)| dot(*n, sub3(node(w2.1, i), node(w1.1, i))))
            .collect();
        Self {
            gap: contact.gap_at_start().to_vec(),
            normal_accel: vec![0.0; normal_jump.len()],
            normal_jump,
        }
    }
}

/// Inputs of one local stage.
pub struct LocalInput<'a> {
    /// Current linear-stage fields s.
    pub s: &'a InterfaceState,
    /// Search direction k.
    pub k: f64,
    /// Time grid.
    pub time: TimeGrid,
    /// The scheme's step coefficients (the gap update of contact).
    pub step: StepCoefficients,
    /// Steps m0..=m1 to treat.
    pub steps: (usize, usize),
}

/// Computes ŝ on steps m0..=m1 of one interface into `hat` (one history per side). For a
/// contact interface, `start` is the running state at m0 − 1 and the state at m1 is returned.
pub fn local_stage(
    iface: &Interface,
    input: &LocalInput<'_>,
    hat: &mut [TraceHistory],
    start: Option<&ContactRunning>,
) -> Option<ContactRunning> {
    let (m0, m1) = input.steps;
    let k = input.k;
    match &iface.law {
        Law::Perfect => {
            for m in m0..=m1 {
                let (a, b) = side_values(iface, input.s, m);
                let r = hat[0].at(m);
                let (h1, h2) = hat.split_at_mut(1);
                let (h1, h2) = (&mut h1[0], &mut h2[0]);
                for j in 0..iface.len {
                    let (f1, w1, f2, w2) = (a.0[j], a.1[j], b.0[j], b.1[j]);
                    let kj = k * iface.k_scale[j];
                    let ft = 0.5 * (f1 - f2) + 0.5 * kj * (w2 - w1);
                    let half_sigma = 0.5 * (w1 + w2 - (f1 + f2) / kj);
                    h1.f[r.start + j] = ft;
                    h2.f[r.start + j] = -ft;
                    h1.w[r.start + j] = half_sigma;
                    h2.w[r.start + j] = half_sigma;
                }
            }
            None
        }
        Law::Boundary(dofs) => {
            for m in m0..=m1 {
                let t = input.time.time(m);
                let (f, w) = side_values(iface, input.s, m).0;
                let r = hat[0].at(m);
                for (j, d) in dofs.iter().enumerate() {
                    let k = k * iface.k_scale[j];
                    let (fh, wh) = match &d.law {
                        DofLaw::Velocity(g) => {
                            let wd = g.value(t);
                            (f[j] + k * (wd - w[j]), wd)
                        }
                        DofLaw::Traction(g) => {
                            let fd = d.scale * g.value(t);
                            (fd, w[j] + (fd - f[j]) / k)
                        }
                    };
                    hat[0].f[r.start + j] = fh;
                    hat[0].w[r.start + j] = wh;
                }
            }
            None
        }
        Law::Contact(c) => {
            let mut run = start
                .cloned()
                .unwrap_or_else(|| ContactRunning::initial(iface, c, input.s));
            let c_step = &input.step;
            for m in m0..=m1 {
                let (a, b) = side_values(iface, input.s, m);
                let r = hat[0].at(m);
                let (h1, h2) = hat.split_at_mut(1);
                let (h1, h2) = (&mut h1[0], &mut h2[0]);
                for (i, &n) in c.normal.iter().enumerate() {
                    let (f1, w1, f2, w2) = (node(a.0, i), node(a.1, i), node(b.0, i), node(b.1, i));
                    let ks: Vec3 = std::array::from_fn(|q| k * iface.k_scale[3 * i + q]);
                    let mut ft = [0.0; 3];
                    let mut sigma = [0.0; 3];
                    for q in 0..3 {
                        ft[q] = 0.5 * (f1[q] - f2[q]) + 0.5 * ks[q] * (w2[q] - w1[q]);
                        sigma[q] = w1[q] + w2[q] - (f1[q] + f2[q]) / ks[q];
                    }
                    let (gap, jn_prev, an_prev) =
                        (run.gap[i], run.normal_jump[i], run.normal_accel[i]);
                    let v_star = c_step.closing_velocity(gap, jn_prev, an_prev);
                    let v_lim = if c_step.statics {
                        v_star
                    } else {
                        v_star.min(0.0)
                    };
                    let (fh1, jump, jn) =
                        contact_node(ft, n, c.friction, v_lim, normal_tangential(ks, n));
                    (run.gap[i], run.normal_accel[i]) = c_step.advance(gap, jn_prev, an_prev, jn);
                    run.normal_jump[i] = jn;
                    for q in 0..3 {
                        let p = r.start + 3 * i + q;
                        h1.f[p] = fh1[q];
                        h2.f[p] = -fh1[q];
                        h1.w[p] = 0.5 * (sigma[q] - jump[q]);
                        h2.w[p] = 0.5 * (sigma[q] + jump[q]);
                    }
                }
            }
            Some(run)
        }
    }
}

/// (k_n, k_t) of a node whose direction is diag(ks) in global axes: n·K n and the mean of the
/// other two axes (exact when n is a coordinate axis, the only case where ks is not k I:
/// [`crate::interfaces::search_direction`]).
fn normal_tangential(ks: Vec3, n: Vec3) -> (f64, f64) {
    if ks[0] == ks[1] && ks[1] == ks[2] {
        return (ks[0], ks[0]);
    }
    let kn: f64 = (0..3).map(|q| n[q] * n[q] * ks[q]).sum();
    let kt: f64 = (0..3).map(|q| (1.0 - n[q] * n[q]) * ks[q]).sum::<f64>() / 2.0;
    (kn, kt)
}

/// The contact closed form of METHOD §5 for one node and step, given the least admissible
/// normal jump V_lim and the search direction's normal and tangential parts (k_n, k_t)
/// (k_n = k_t = k for the scalar direction): returns (F̂₁, [Ŵ], [Ŵ_n]). In dynamics V_lim =
/// min(V*, 0), V* the normal velocity jump that closes the gap
/// ([`StepCoefficients::closing_velocity`]; the persistent law: a penetrated node is not pushed
/// apart); in statics V_lim = V* = −g0, so an interference is undone (Signorini's law).
pub fn contact_node(
    ft: Vec3,
    n: Vec3,
    friction: f64,
    v_lim: f64,
    (kn, kt): (f64, f64),
) -> (Vec3, Vec3, f64) {
    let ftn = dot(ft, n);
    let p = (0.5 * kn * v_lim - ftn).max(0.0);
    let jn = 2.0 / kn * (ftn + p);
    let ftt = [ft[0] - ftn * n[0], ft[1] - ftn * n[1], ft[2] - ftn * n[2]];
    let norm_t = dot(ftt, ftt).sqrt();
    let (fht, jt) = if norm_t <= friction * p {
        (ftt, [0.0; 3])
    } else {
        let s = friction * p / norm_t;
        let fht = [s * ftt[0], s * ftt[1], s * ftt[2]];
        let jt = std::array::from_fn(|q| 2.0 / kt * (ftt[q] - fht[q]));
        (fht, jt)
    };
    let fh1 = std::array::from_fn(|q| -p * n[q] + fht[q]);
    let jump = std::array::from_fn(|q| jn * n[q] + jt[q]);
    (fh1, jump, jn)
}

/// ((F, W) of side 1, (F, W) of side 2) at step m; side 2 equals side 1 on a boundary.
type SideSlices<'a> = ((&'a [f64], &'a [f64]), (&'a [f64], &'a [f64]));

fn side_values<'a>(iface: &Interface, s: &'a InterfaceState, m: usize) -> SideSlices<'a> {
    let get = |k: usize| {
        let side = &iface.sides[k];
        let h = &s.subs[side.sub];
        let start = m * h.len + side.offset;
        (
            &h.f[start..start + iface.len],
            &h.w[start..start + iface.len],
        )
    };
    let a = get(0);
    let b = if iface.sides.len() > 1 { get(1) } else { a };
    (a, b)
}

fn node(x: &[f64], i: usize) -> Vec3 {
    [x[3 * i], x[3 * i + 1], x[3 * i + 2]]
}

fn sub3(a: Vec3, b: Vec3) -> Vec3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: Vec3 = [0.0, 0.0, 1.0];

    /// V_lim = min(V*, 0) of the trapezoidal rule with Δt = 1e-3.
    fn v_star(gap: f64, jn: f64) -> f64 {
        crate::time::time_scheme::TimeScheme::TRAPEZOIDAL
            .coefficients(1e-3)
            .closing_velocity(gap, jn, 0.0)
            .min(0.0)
    }

    /// With dissipation (ρ∞ = 0.5), a gap closed at V* leaves the Newmark gap update at zero:
    /// g_m = g + d_V [W_n]_{m−1} + d_A [a_n]_{m−1} + c_K V* = 0 to 1e-15.
    #[test]
    fn closing_velocity_closes_the_gap_of_a_dissipative_scheme() {
        let c = crate::time::time_scheme::TimeScheme::new(0.5).coefficients(1e-3);
        let (gap, jn, an) = (1e-3, -0.7, 30.0);
        let v = c.closing_velocity(gap, jn, an);
        let (g, _) = c.advance(gap, jn, an, v);
        assert!(g.abs() < 1e-15, "{g}");
        let (_, _, jn_new) = contact_node([0.0, 0.0, -10.0], N, 0.0, v.min(0.0), (2.0, 2.0));
        assert!(c.advance(gap, jn, an, jn_new).0 >= -1e-15);
    }

    #[test]
    fn separation_gives_zero_force() {
        // pulling apart (F̃_n > 0) with an open gap: p = 0, F̂ = 0
        let (f, jump, jn) = contact_node([0.3, 0.0, 2.0], N, 0.5, v_star(1e-3, 0.0), (2.0, 2.0));
        assert_eq!(f, [0.0; 3]);
        assert!((jn - 2.0).abs() < 1e-15 && (jump[0] - 0.3).abs() < 1e-15);
    }

    #[test]
    fn closed_contact_sticks_then_slips_on_the_coulomb_cone() {
        // pushing together from a closed gap: V* = 0, p = −F̃_n
        let (f, jump, jn) = contact_node([0.1, 0.0, -1.0], N, 0.5, v_star(0.0, 0.0), (2.0, 2.0));
        assert!((f[2] + 1.0).abs() < 1e-15 && (f[0] - 0.1).abs() < 1e-15 && jn == 0.0);
        assert_eq!(jump, [0.0; 3]);
        // |F̃_t| = 0.8 > f p = 0.5: slip, |F̂_t| = f p, jump along F̃_t
        let (f, jump, _) = contact_node([0.8, 0.0, -1.0], N, 0.5, v_star(0.0, 0.0), (2.0, 2.0));
        assert!((f[0] - 0.5).abs() < 1e-15);
        assert!((jump[0] - 2.0 / 2.0 * 0.3).abs() < 1e-15);
    }

    /// A direction with k_n = 3 and k_t = 0.5 (the wave-matched shape): the normal jump reads
    /// k_n, the tangential slip reads k_t, the forces follow the Signorini–Coulomb cone as before.
    #[test]
    fn normal_and_tangential_parts_of_the_direction_enter_their_own_jumps() {
        // closed and pushed: p = 1, no normal jump; slip [Ŵ_t] = 2/k_t (0.8 − 0.5) = 1.2
        let (f, jump, jn) = contact_node([0.8, 0.0, -1.0], N, 0.5, v_star(0.0, 0.0), (3.0, 0.5));
        assert!((f[2] + 1.0).abs() < 1e-15 && (f[0] - 0.5).abs() < 1e-15 && jn == 0.0);
        assert!((jump[0] - 1.2).abs() < 1e-14, "{jump:?}");
        // open and pulled: no force, [Ŵ_n] = 2/k_n · 2 = 4/3, [Ŵ_t] = 2/k_t · 0.3 = 1.2
        let (f, jump, jn) = contact_node([0.3, 0.0, 2.0], N, 0.5, v_star(1e-3, 0.0), (3.0, 0.5));
        assert_eq!(f, [0.0; 3]);
        assert!((jn - 4.0 / 3.0).abs() < 1e-14 && (jump[0] - 1.2).abs() < 1e-14);
        // diag(ks) along a coordinate normal splits into (k_n, k_t); equal entries give k
        assert_eq!(normal_tangential([0.5, 0.5, 3.0], N), (3.0, 0.5));
        assert_eq!(normal_tangential([2.0; 3], [0.6, 0.0, 0.8]), (2.0, 2.0));
    }

    #[test]
    fn approaching_gap_is_closed_exactly_by_the_persistent_law() {
        // gap 1e-3 closing at relative speed −3 over dt = 1e-3: V* = −2 + 3 = 1 > 0 → V_lim = 0
        let (_, _, jn) = contact_node([0.0, 0.0, -10.0], N, 0.0, v_star(1e-3, -3.0), (2.0, 2.0));
        assert!(jn >= 0.0);
        // gap 1e-3 with no relative speed: V* = −2: the gap may close but not more
        let (_, _, jn) = contact_node([0.0, 0.0, -10.0], N, 0.0, v_star(1e-3, 0.0), (2.0, 2.0));
        assert!((jn + 2.0).abs() < 1e-12);
        let gap = 1e-3 + 0.5 * 1e-3 * (0.0 + jn);
        assert!(gap.abs() < 1e-15);
    }
}
