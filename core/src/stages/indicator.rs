//! The error indicator η of METHOD §6, with the window normalisation of METHOD §7, in one place:
//!
//!   η² = Σ_m Σ_j A_j [ (F_j − F̂_j)²/k + k (W_j − Ŵ_j)² ]
//!        / ( ½ Σ_m Σ_j A_j [ (F_j² + F̂_j²)/k + k (W_j² + Ŵ_j²) ] + D_prev ),
//!
//! where s_new = (F, W) is the unrelaxed linear-stage output and ŝ = (F̂, Ŵ) the local stage of
//! the same iteration, m runs over the current window [m0, m1] and j over every interface dof of
//! every side. D_prev is the denominator of the finished windows (METHOD §7: "η normalised by
//! the energy of steps 1..m1"), or, per step (the default, see
//! [`crate::Settings::per_step_window_norm`]), their mean energy per step times the window
//! length. [`IndicatorSums::add_dof`] is the one place a term is formed; the linear stage calls it
//! per trace dof and step; [`WindowNorm`] turns the sums into η.
//!
//! The smooth indicator η̄ ([`smooth_sums`]) is the same expression on step-averaged fields
//! x̄_m = (x_m + x_{m−1})/2 of s_new and ŝ. The averages are what moves the displacements
//! (u_m − u_{m−1} = Δt W̄_m for the trapezoidal rule, METHOD §2) and what the reported contact
//! forces are (METHOD §5, step-averaged normal force); the alternating mode of the undamped rule,
//! x_m = (−1)^m c, has x̄ = 0 and so leaves η̄ untouched while it keeps η up (METHOD §10). On
//! time windows, the first step of a window after a finished one is measured on its own fields
//! (the step before it is fixed), so a one-step window's η̄ is its η.
//! [`StopTest`] says which of the two the stopping test reads.

use crate::distributed::distribution::Distribution;
use crate::interfaces::interface::Interface;
pub use crate::scene::settings::StopTest;
use crate::state::{InterfaceState, TraceHistory};

/// The η̄ sums of steps m0..=m1: the terms of η on the step averages
/// ((x_m + x_{m−1})/2) of the linear-stage output `s_new` (per substructure trace) and ŝ (per
/// interface side), with each interface's areas and direction factors k·k_scale. On the whole
/// interval (m0 = 1) step 0 is the initial state, the same in both. After a finished window
/// (m0 > 1) step m0 − 1 is fixed with what residual its window converged to, which no iteration
/// of this window can reduce: averaged in, it would hold η̄ near the tolerance for ever (a
/// one-step window stopped on η̄ never converged), so step m0 is measured on its own fields, as
/// η measures it, and a one-step window's η̄ is its η. One sum per interface side, computed in
/// parallel on the rank holding the side's substructure and added in (interface, side) order
/// ([`Distribution::gathered_sums`]).
pub fn smooth_sums(
    interfaces: &[Interface],
    k: f64,
    s_new: &InterfaceState,
    hats: &[Vec<TraceHistory>],
    (m0, m1): (usize, usize),
    distribution: &Distribution,
) -> IndicatorSums {
    let sides: Vec<(usize, usize)> = interfaces
        .iter()
        .enumerate()
        .flat_map(|(i, iface)| (0..iface.sides.len()).map(move |j| (i, j)))
        .collect();
    let per_side = crate::par::map_range(sides.len(), |n| {
        let (i, j) = sides[n];
        let iface = &interfaces[i];
        let side = &iface.sides[j];
        if !distribution.holds_sub(side.sub) {
            return None;
        }
        let hat = &hats[i][j];
        let mut sums = IndicatorSums::default();
        let t = &s_new.subs[side.sub];
        for m in m0.max(1)..=m1 {
            let (now, prev) = (t.at(m).start + side.offset, t.at(m - 1).start + side.offset);
            let (hn, hp) = (hat.at(m).start, hat.at(m - 1).start);
            // a window's first step after a finished window: its own fields (doc above)
            let (prev, hp) = if m == m0 && m0 > 1 {
                (now, hn)
            } else {
                (prev, hp)
            };
            for j in 0..iface.len {
                let avg = |x: &[f64], a: usize, b: usize| 0.5 * (x[a + j] + x[b + j]);
                sums.add_dof(
                    iface.area[j],
                    k * iface.k_scale[j],
                    (avg(&t.f, now, prev), avg(&t.w, now, prev)),
                    (avg(&hat.f, hn, hp), avg(&hat.w, hn, hp)),
                );
            }
        }
        Some(sums)
    });
    distribution.gathered_sums(per_side.into_iter())
}

/// Numerator and denominator sums of η² (METHOD §6) over some dofs and steps.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct IndicatorSums {
    /// Σ A [(F − F̂)²/k + k (W − Ŵ)²].
    pub num: f64,
    /// ½ Σ A [(F² + F̂²)/k + k (W² + Ŵ²)].
    pub den: f64,
}

impl IndicatorSums {
    /// Adds another set of sums.
    pub fn add(&mut self, o: IndicatorSums) {
        self.num += o.num;
        self.den += o.den;
    }

    /// Adds the terms of one trace dof at one step: area `a`, search direction `k`, the
    /// linear-stage output (f, w) and the local-stage fields (f̂, ŵ).
    #[inline]
    pub fn add_dof(&mut self, a: f64, k: f64, (f, w): (f64, f64), (fhat, what): (f64, f64)) {
        let (df, dw) = (f - fhat, w - what);
        self.num += a * (df * df / k + k * dw * dw);
        self.den += 0.5 * a * ((f * f + fhat * fhat) / k + k * (w * w + what * what));
    }

    /// η = √(num / den) (0 when the numerator vanishes).
    pub fn eta(&self) -> f64 {
        if self.num == 0.0 {
            0.0
        } else {
            (self.num / self.den).sqrt()
        }
    }
}

/// The denominator carried from the finished windows of a solve (METHOD §7).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WindowNorm {
    /// Scale the finished windows' energy to the current window's length (true) or add it whole
    /// (false, METHOD §7 as written).
    per_step: bool,
    /// Σ of the denominators of the finished windows, steps 1..m0 − 1.
    finished_den: f64,
}

impl WindowNorm {
    /// The norm at the start of a solve (no finished window).
    pub fn new(per_step: bool) -> Self {
        Self {
            per_step,
            finished_den: 0.0,
        }
    }

    /// η of the window [m0, m1] from its sums.
    pub fn eta(&self, window: IndicatorSums, (m0, m1): (usize, usize)) -> f64 {
        let carried = if self.per_step && m0 > 1 {
            self.finished_den * (m1 + 1 - m0) as f64 / (m0 - 1) as f64
        } else {
            self.finished_den
        };
        IndicatorSums {
            num: window.num,
            den: window.den + carried,
        }
        .eta()
    }

    /// Adds the sums of a window that ends (converged or not).
    pub fn close_window(&mut self, window: IndicatorSums) {
        self.finished_den += window.den;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eta_of_a_single_dof_is_the_relative_distance() {
        // k = 1, A = 1: η² = ((F − F̂)² + (W − Ŵ)²) / (½ (F² + F̂² + W² + Ŵ²))
        let mut s = IndicatorSums::default();
        s.add_dof(1.0, 1.0, (1.0, 0.0), (0.0, 0.0));
        assert_eq!(s.num, 1.0);
        assert_eq!(s.den, 0.5);
        assert!((s.eta() - 2f64.sqrt()).abs() < 1e-15);
        // identical fields: η = 0 whatever the scale
        let mut z = IndicatorSums::default();
        z.add_dof(3.0, 7.0, (2.0, -1.0), (2.0, -1.0));
        assert_eq!(z.eta(), 0.0);
        assert!(z.den > 0.0);
    }

    #[test]
    fn eta_is_dimensionless_in_k_and_area() {
        // (F, W) and (F̂, Ŵ) on the search direction F = k W: η does not depend on k or A
        let eta = |k: f64, a: f64| {
            let mut s = IndicatorSums::default();
            s.add_dof(a, k, (k * 2.0, 2.0), (k * 1.5, 1.5));
            s.add_dof(a, k, (-k * 0.5, -0.5), (k * 0.25, 0.25));
            s.eta()
        };
        let base = eta(1.0, 1.0);
        for (k, a) in [(4.1e7, 1.0), (2.0, 1e-6), (1e-3, 3.0)] {
            assert!((eta(k, a) - base).abs() < 1e-14 * base, "k {k} a {a}");
        }
    }

    /// One boundary interface of one dof on one substructure, over `steps` steps.
    fn one_dof(steps: usize) -> (Vec<Interface>, InterfaceState, Vec<Vec<TraceHistory>>) {
        let iface = Interface {
            name: "A:x+".into(),
            sides: vec![crate::interfaces::interface::Side {
                sub: 0,
                offset: 0,
                nodes: vec![0],
                projection: None,
            }],
            len: 1,
            area: vec![2.0],
            k_scale: vec![1.0],
            law: crate::interfaces::interface::Law::Perfect,
        };
        let state = InterfaceState {
            steps,
            subs: vec![TraceHistory::zeros(1, steps)],
        };
        let hats = vec![vec![TraceHistory::zeros(1, steps)]];
        (vec![iface], state, hats)
    }

    #[test]
    fn the_smooth_indicator_is_blind_to_the_alternating_mode() {
        let steps = 6;
        let (ifaces, mut s_new, mut hats) = one_dof(steps);
        // ŝ: a ramp; s_new: the same ramp plus the alternating mode (−1)^m c from m = 1 on
        // (W₀ is the given initial state, never iterated)
        for m in 0..=steps {
            let ramp = m as f64;
            hats[0][0].w[m] = ramp;
            hats[0][0].f[m] = 3.0 * ramp;
            let mode = if m == 0 {
                0.0
            } else {
                0.25 * (-1f64).powi(m as i32)
            };
            s_new.subs[0].w[m] = ramp + mode;
            s_new.subs[0].f[m] = 3.0 * ramp - 3.0 * mode;
        }
        // steps 2..=6: every average of the mode vanishes, so η̄ sees only step 1, whose average
        // with the initial state keeps half the mode (W̄ 0.375 against 0.5, F̄ 1.875 against
        // 1.5), while η sees every step
        let one = Distribution::single_for(1, &ifaces);
        let sm = smooth_sums(&ifaces, 3.0, &s_new, &hats, (1, steps), &one);
        let mut first = IndicatorSums::default();
        first.add_dof(2.0, 3.0, (1.875, 0.375), (1.5, 0.5));
        assert!((sm.num - first.num).abs() <= 1e-14 * first.num, "{sm:?}");
        assert!(sm.den > 0.0);
        let mut plain = IndicatorSums::default();
        for m in 2..=steps {
            plain.add_dof(
                2.0,
                3.0,
                (s_new.subs[0].f[m], s_new.subs[0].w[m]),
                (hats[0][0].f[m], hats[0][0].w[m]),
            );
        }
        assert!(plain.eta() > 0.05, "η {}", plain.eta());
        // a smooth difference is seen by both: s_new = 2 ŝ gives η̄ = η = √(2/5)·… exactly the
        // expression of add_dof on the averages
        for m in 0..=steps {
            s_new.subs[0].w[m] = 2.0 * hats[0][0].w[m];
            s_new.subs[0].f[m] = 2.0 * hats[0][0].f[m];
        }
        let sm = smooth_sums(&ifaces, 3.0, &s_new, &hats, (1, steps), &one);
        let mut expected = IndicatorSums::default();
        for m in 1..=steps {
            let (w, f) = (m as f64 - 0.5, 3.0 * (m as f64 - 0.5));
            expected.add_dof(2.0, 3.0, (2.0 * f, 2.0 * w), (f, w));
        }
        assert!((sm.num - expected.num).abs() <= 1e-12 * expected.num);
        assert!((sm.den - expected.den).abs() <= 1e-12 * expected.den);
        // (W − Ŵ)² k + (F − F̂)²/k over ½ (…): for x = 2y, η² = 1 / (½ (1 + 4)/1) → η = √(2/5)
        assert!((sm.eta() - (0.4f64).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn after_a_finished_window_the_first_step_is_measured_on_its_own_fields() {
        // step 2 was left by its window with a residual (s_new ≠ ŝ there); step 3 is exact
        let steps = 4;
        let (ifaces, mut s_new, mut hats) = one_dof(steps);
        for m in 0..=steps {
            hats[0][0].w[m] = 1.0 + m as f64;
            hats[0][0].f[m] = 2.0 * m as f64;
            s_new.subs[0].w[m] = hats[0][0].w[m];
            s_new.subs[0].f[m] = hats[0][0].f[m];
        }
        s_new.subs[0].w[2] += 0.1;
        let one = Distribution::single_for(1, &ifaces);
        // the one-step window [3, 3] and the window [3, 4] see no residual: step 2's is not theirs
        assert_eq!(
            smooth_sums(&ifaces, 1.0, &s_new, &hats, (3, 3), &one).num,
            0.0
        );
        assert_eq!(
            smooth_sums(&ifaces, 1.0, &s_new, &hats, (3, 4), &one).num,
            0.0
        );
        // and a one-step window's η̄ is its η: a residual at step 3 counts in full, not halved
        s_new.subs[0].w[3] += 0.2;
        let sm = smooth_sums(&ifaces, 1.0, &s_new, &hats, (3, 3), &one);
        let mut plain = IndicatorSums::default();
        plain.add_dof(2.0, 1.0, (6.0, 4.2), (6.0, 4.0));
        assert!((sm.num - plain.num).abs() <= 1e-14 * plain.num);
        assert!((sm.den - plain.den).abs() <= 1e-14 * plain.den);
        // within a window, and on the whole interval from the initial state, steps are averaged:
        // step 2's residual enters [2, 3] through steps 2 and 3
        let both = smooth_sums(&ifaces, 1.0, &s_new, &hats, (1, 3), &one);
        assert!(both.num > 0.0);
    }

    #[test]
    fn stop_tests_parse_and_name_themselves() {
        for t in [StopTest::Eta, StopTest::Smooth] {
            assert_eq!(StopTest::parse(t.name()).ok(), Some(t));
        }
        let e = StopTest::parse("fast").expect_err("unknown");
        assert!(e.to_string().contains("eta, smooth"), "{e}");
    }

    #[test]
    fn window_norm_carries_finished_energy() {
        let w = IndicatorSums { num: 4.0, den: 1.0 };
        let mut norm = WindowNorm::new(false);
        assert!((norm.eta(w, (1, 10)) - 2.0).abs() < 1e-15);
        norm.close_window(IndicatorSums { num: 0.0, den: 3.0 });
        // whole: den = 1 + 3
        assert!((norm.eta(w, (11, 20)) - 1.0).abs() < 1e-15);
        let mut per_step = WindowNorm::new(true);
        per_step.close_window(IndicatorSums { num: 0.0, den: 3.0 });
        // per step: 3 over steps 1..10, scaled to the 5-step window [11, 15]: 1.5; den = 2.5
        assert!((per_step.eta(w, (11, 15)) - (4.0f64 / 2.5).sqrt()).abs() < 1e-15);
        // the first window has nothing carried in either mode
        assert_eq!(WindowNorm::new(true).eta(w, (1, 5)), 2.0);
    }
}
