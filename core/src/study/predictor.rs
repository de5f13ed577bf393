//! Where a warm solve starts (METHOD §8 multiresolution): the one [`Predictor`] of every
//! parametric front end (`lopin study`, `lopin sweep`, the explorer's slider and background
//! study), and [`Predictor::start`], which builds the start of a configuration from what the
//! front end has solved: its chain's last converged states in full precision (the previous one,
//! or an extrapolation of the last two) and the store of converged states
//! ([`super::store::StateStore`]: the nearest, a parallelogram of three, the bracket of a
//! one-parameter study, or a projection on the nearest ones, [`super::projection`]).
//!
//! The extrapolations scale the change between the chain's last two values p₀, p₁ to the new
//! value p: s = s₁ + (p − p₁)/(p₁ − p₀) (s₁ − s₀) (`linear`), or the same with the change
//! filtered over time steps by the binomial weights (¼, ½, ¼) (`smooth`), which take the
//! alternating content x_m = (−1)^m c (the highest frequency of the time grid, METHOD §10) to
//! zero and keep affine content in time unchanged.

use crate::error::{LopinError, Result};
use crate::solver::Solver;
use crate::state::InterfaceState;
use crate::study::path::distance;
use crate::study::{projection, StateStore};

/// How the start state of the next configuration is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Predictor {
    /// The chain's previous converged state (the seed paper's restart).
    Previous,
    /// Linear extrapolation from the chain's last two converged states.
    Linear,
    /// The linear extrapolation of the time-filtered change only.
    Smooth,
    /// The converged state of the nearest solved configuration.
    #[default]
    Nearest,
    /// s_j + s_k − s_l from three solved configurations closing a parallelogram with the new
    /// one ([`StateStore::parallelogram`]: on a grid, the change one parameter step made on the
    /// neighbouring row carried over), else the nearest.
    Parallelogram,
    /// The affine combination of the [`projection::BASIS`] nearest stored states closest to
    /// the new configuration's interface behaviour ([`super::projection`]).
    Projection,
    /// In a one-parameter study, the states of the nearest solved values below and above
    /// interpolated linearly ([`StateStore::between`]), else the nearest.
    Bracket,
}

/// Two stored values closer than this are the same configuration (a bracket needs both ends
/// strictly apart from the value).
pub const SAME: f64 = 1e-9;

/// A start and where it came from.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Start {
    /// The state (None: cold).
    pub state: Option<InterfaceState>,
    /// The stored configuration it started from (a parallelogram's first corner, a bracket's
    /// nearer end).
    pub from: Option<usize>,
    /// The other two configurations of a parallelogram start (from + first − second).
    pub change: Option<(usize, usize)>,
    /// A bracket start's two ends, (index, value) each.
    pub between: Option<((usize, f64), (usize, f64))>,
    /// Scaled distance to `from`.
    pub distance: Option<f64>,
    /// A projected start's ρ_Γ: of the nearest state alone, and of the start.
    pub residual: Option<(f64, f64)>,
}

impl Predictor {
    /// Every predictor, in the order the help lists them.
    pub const ALL: [Self; 7] = [
        Self::Previous,
        Self::Linear,
        Self::Smooth,
        Self::Nearest,
        Self::Parallelogram,
        Self::Projection,
        Self::Bracket,
    ];

    /// Parses a predictor's name.
    pub fn parse(name: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| {
                LopinError::setting(
                    "predictor",
                    format!(
                        "unknown predictor `{name}` ({})",
                        Self::ALL.map(|p| p.name()).join(", ")
                    ),
                )
            })
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Previous => "previous",
            Self::Linear => "linear",
            Self::Smooth => "smooth",
            Self::Nearest => "nearest",
            Self::Parallelogram => "parallelogram",
            Self::Projection => "projection",
            Self::Bracket => "bracket",
        }
    }

    /// Whether it reads the chain's last converged states (rather than the store).
    pub fn follows_the_chain(&self) -> bool {
        matches!(self, Self::Previous | Self::Linear | Self::Smooth)
    }

    /// The predictor of a study that asks for none, and why: the projection on the whole
    /// interval with a dissipative scheme, where it saves iterations, else the nearest state
    /// (module doc of [`super::projection`]).
    pub fn auto(whole_interval: bool, rho_inf: f64) -> (Self, &'static str) {
        match (whole_interval, rho_inf < 1.0) {
            (true, true) => (
                Self::Projection,
                "auto: the whole interval with a dissipative scheme, where the projection on the \
                 nearest states saves iterations",
            ),
            (true, false) => (
                Self::Nearest,
                "auto: the undamped rule, whose alternating mode makes a projected start no \
                 better than the nearest state",
            ),
            (false, _) => (
                Self::Nearest,
                "auto: time windows, each started from the nearest state's converged step",
            ),
        }
    }

    /// The start of the configuration at scaled point `point`: from `chain`, the (value,
    /// state) pairs the chain converged to, most recent last, for the predictors that follow
    /// the chain (a value is the point's first coordinate); from `store` for the others. A
    /// projection runs local stages on `solver`, which holds the new configuration's
    /// parameters. Cold (an empty start) when nothing is solved yet.
    pub fn start(
        &self,
        chain: &[(f64, &InterfaceState)],
        store: &StateStore,
        point: &[f64],
        solver: &Solver,
    ) -> Start {
        if self.follows_the_chain() {
            return Start {
                state: self.extrapolate(chain, point.first().copied().unwrap_or(0.0)),
                ..Start::default()
            };
        }
        match self {
            Self::Parallelogram => {
                if let Some((j, k, l)) = store.parallelogram(point, 8) {
                    return Start {
                        state: store.combined(j, k, l),
                        from: Some(j),
                        change: Some((k, l)),
                        distance: store.distance_to(j, point),
                        ..Start::default()
                    };
                }
            }
            Self::Bracket => return Self::bracket_start(store, point),
            _ => {}
        }
        let mut start = Self::nearest_start(store, point);
        if let (Self::Projection, Some(s0), Some(j0)) = (self, &start.state, start.from) {
            // (a study's solvers hold everything: chains, not substructures, go to the ranks)
            let others: Vec<_> = store
                .nearest_k(point, projection::BASIS)
                .into_iter()
                .filter(|&j| j != j0)
                .filter_map(|j| store.state(j))
                .collect();
            let p = projection::project(solver, s0, &others, projection::GAUSS_NEWTON_STEPS);
            start.residual = Some((p.residual_nearest, p.residual));
            start.state = Some(p.state);
        }
        start
    }

    /// The start of [`Predictor::Bracket`]: inside a bracket of stored values the
    /// interpolation of its two ends, else the nearest stored state (no local stage runs, so
    /// no solver is needed).
    pub fn bracket_start(store: &StateStore, point: &[f64]) -> Start {
        let Some(((j, lo), (k, hi))) = store.bracket(point, SAME) else {
            return Self::nearest_start(store, point);
        };
        let value = point[0];
        let from = if value - lo <= hi - value { j } else { k };
        Start {
            state: store.between(j, k, (value - lo) / (hi - lo)),
            from: Some(from),
            between: Some(((j, lo), (k, hi))),
            distance: store.distance_to(from, point),
            ..Start::default()
        }
    }

    /// The start of [`Predictor::Bracket`] beside a converged state the caller holds outside
    /// the store, at `held` (the explorer's newest solve): the bracket's interpolation where its
    /// nearer end is at least as near `point` as `held`, else the nearest stored state where it
    /// is strictly nearer; None where the held state is the nearest start (or nothing is
    /// stored).
    pub fn bracket_start_beside(
        store: &StateStore,
        point: &[f64],
        held: Option<&[f64]>,
    ) -> Option<Start> {
        let held_gap = held.map_or(f64::INFINITY, |h| distance(h, point));
        if let Some(((_, lo), (_, hi))) = store.bracket(point, SAME) {
            let value = point[0];
            if (value - lo).min(hi - value) <= held_gap {
                return Some(Self::bracket_start(store, point));
            }
        }
        let (_, gap) = store.nearest(point)?;
        (gap < held_gap).then(|| Self::nearest_start(store, point))
    }

    /// The state of the nearest stored configuration (none when nothing is stored).
    fn nearest_start(store: &StateStore, point: &[f64]) -> Start {
        let near = store.nearest(point);
        Start {
            state: near.and_then(|(j, _)| store.state(j)),
            from: near.map(|n| n.0),
            distance: near.map(|n| n.1),
            ..Start::default()
        }
    }

    /// The start for parameter value `p` from the chain's converged (value, state) pairs, most
    /// recent last: the previous state, or its extrapolation along the last two (the previous
    /// state when there is one value only or both are equal). None: nothing solved yet.
    pub fn extrapolate(&self, chain: &[(f64, &InterfaceState)], p: f64) -> Option<InterfaceState> {
        let (p1, s1) = *chain.last()?;
        if !matches!(self, Self::Linear | Self::Smooth) || chain.len() < 2 {
            return Some(s1.clone());
        }
        let (p0, s0) = chain[chain.len() - 2];
        if p1 == p0 {
            return Some(s1.clone());
        }
        let r = (p - p1) / (p1 - p0);
        let mut s = s1.clone();
        for (h, h0) in s.subs.iter_mut().zip(&s0.subs) {
            let len = h.len;
            for (x, x0) in [(&mut h.f, &h0.f), (&mut h.w, &h0.w)] {
                let mut change: Vec<f64> = x.iter().zip(x0).map(|(a, b)| a - b).collect();
                if *self == Self::Smooth {
                    change = filter_in_time(&change, len);
                }
                for (a, d) in x.iter_mut().zip(&change) {
                    *a += r * d;
                }
            }
        }
        Some(s)
    }
}

/// The (¼, ½, ¼) filter over steps of a step-major history with `len` entries per step, m = 0..=N.
/// Step 0 (the given initial state) is kept as it is; the last step, with one neighbour, takes
/// x̃_N = (x_{N−1} + x_N)/2. Histories of fewer than 3 steps are returned unfiltered.
fn filter_in_time(x: &[f64], len: usize) -> Vec<f64> {
    let count = x.len().checked_div(len).unwrap_or(0);
    let mut out = x.to_vec();
    if count < 3 {
        return out;
    }
    for m in 1..count {
        for j in 0..len {
            let at = |k: usize| x[k * len + j];
            out[m * len + j] = if m + 1 < count {
                0.25 * at(m - 1) + 0.5 * at(m) + 0.25 * at(m + 1)
            } else {
                0.5 * (at(m - 1) + at(m))
            };
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::TraceHistory;

    #[test]
    fn linear_predictor_extrapolates_affine_data_exactly() {
        let state = |x: f64| InterfaceState {
            steps: 1,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![0.0, 1.0 + 2.0 * x],
                w: vec![0.0, -x],
            }],
        };
        let (a, b) = (state(0.1), state(0.2));
        let p = Predictor::Linear
            .extrapolate(&[(0.1, &a), (0.2, &b)], 0.35)
            .expect("state");
        let exact = state(0.35);
        assert!((p.subs[0].f[1] - exact.subs[0].f[1]).abs() < 1e-14);
        assert!((p.subs[0].w[1] - exact.subs[0].w[1]).abs() < 1e-14);
        let q = Predictor::Previous
            .extrapolate(&[(0.1, &a), (0.2, &b)], 0.35)
            .expect("state");
        assert_eq!(q, b);
        assert!(Predictor::Linear.extrapolate(&[], 0.3).is_none());
    }

    #[test]
    fn the_smooth_predictor_drops_the_alternating_part_of_the_change() {
        // change between the two values: a ramp in time plus the alternating mode (−1)^m
        let steps = 8;
        let state = |x: f64| InterfaceState {
            steps,
            subs: vec![TraceHistory {
                len: 1,
                f: (0..=steps).map(|m| x * m as f64).collect(),
                w: (0..=steps)
                    .map(|m| {
                        if m == 0 {
                            0.0
                        } else {
                            x * (m as f64 + (-1f64).powi(m as i32))
                        }
                    })
                    .collect(),
            }],
        };
        let (a, b) = (state(1.0), state(2.0));
        let p = Predictor::Smooth
            .extrapolate(&[(1.0, &a), (2.0, &b)], 3.0)
            .expect("state");
        let h = &p.subs[0];
        // F: affine in time, extrapolated exactly inside (the last step's one-sided average
        // lags half a step)
        for m in 0..steps {
            assert!(
                (h.f[m] - 3.0 * m as f64).abs() < 1e-12,
                "F at {m}: {}",
                h.f[m]
            );
        }
        // W: the ramp part extrapolated, the alternating part of the change not (it stays at
        // the last value's): 2(m + (−1)^m) + (m) for 2 ≤ m ≤ N − 2
        for m in 2..steps - 1 {
            let alt = (-1f64).powi(m as i32);
            let expected = 2.0 * (m as f64 + alt) + m as f64;
            assert!(
                (h.w[m] - expected).abs() < 1e-12,
                "W at {m}: {} vs {expected}",
                h.w[m]
            );
        }
        assert_eq!(Predictor::parse("smooth").ok(), Some(Predictor::Smooth));
        assert_eq!(Predictor::Smooth.name(), "smooth");
    }

    /// The store's predictors: nothing stored is a cold start; inside a bracket the two ends
    /// interpolated (to the f32 the store keeps), outside it the nearest; every name parses
    /// back.
    #[test]
    fn the_bracket_interpolates_inside_and_the_nearest_serves_outside() {
        let opened =
            crate::scene::open("mini-blocks", &crate::scene::Overrides::default()).expect("scene");
        let solver = Solver::new(opened.problem, opened.settings).expect("solver");
        let state = |x: f64| InterfaceState {
            steps: 2,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![0.0, x, 2.0 * x],
                w: vec![0.0, -x, 0.5],
            }],
        };
        let mut store = StateStore::default();
        assert_eq!(
            Predictor::Bracket.start(&[], &store, &[0.2], &solver),
            Start::default()
        );
        store.insert(0, &[0.1], &state(0.1));
        store.insert(1, &[0.3], &state(0.3));
        let inside = Predictor::Bracket.start(&[], &store, &[0.15], &solver);
        assert_eq!(inside.between, Some(((0, 0.1), (1, 0.3))));
        assert_eq!(inside.from, Some(0));
        let got = inside.state.expect("a state");
        let want = state(0.15);
        for (a, b) in got.subs[0].f.iter().zip(&want.subs[0].f) {
            assert!((a - b).abs() < 1e-7, "{a} vs {b}");
        }
        let outside = Predictor::Bracket.start(&[], &store, &[0.5], &solver);
        assert_eq!((outside.between, outside.from), (None, Some(1)));
        let nearest = Predictor::Nearest.start(&[], &store, &[0.5], &solver);
        assert_eq!(nearest.state, outside.state);
        for p in Predictor::ALL {
            assert_eq!(Predictor::parse(p.name()).ok(), Some(p));
        }
        assert!(Predictor::parse("cubic").is_err());
        let chain = [(0.1, &want)];
        let previous = Predictor::Previous.start(&chain, &store, &[0.5], &solver);
        assert_eq!(previous.state.as_ref(), Some(&want));
    }

    /// Beside a held state: the bracket wins a tie with it, the nearest stored state only when
    /// strictly nearer, and the held state otherwise.
    #[test]
    fn beside_a_held_state_the_store_starts_only_where_it_is_nearer() {
        let state = |x: f64| InterfaceState {
            steps: 1,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![0.0, x],
                w: vec![0.0, x],
            }],
        };
        let mut store = StateStore::default();
        assert_eq!(Predictor::bracket_start_beside(&store, &[0.2], None), None);
        store.insert(0, &[0.1], &state(0.1));
        store.insert(1, &[0.3], &state(0.3));
        let beside = |point: f64, held: Option<f64>| {
            let h = held.map(|h| [h]);
            Predictor::bracket_start_beside(&store, &[point], h.as_ref().map(|h| &h[..]))
        };
        // inside the bracket, its nearer end (0.1, 0.05 away) against a held state 0.05 away
        let tie = beside(0.15, Some(0.2)).expect("the bracket");
        assert_eq!(tie.between, Some(((0, 0.1), (1, 0.3))));
        assert_eq!(beside(0.15, Some(0.16)), None);
        // outside: the nearest stored (0.3, 0.1 away) only when strictly nearer than the held
        let outside = beside(0.4, Some(0.6)).expect("the nearest");
        assert_eq!((outside.from, outside.between), (Some(1), None));
        assert_eq!(beside(0.4, Some(0.5)), None);
        assert_eq!(beside(0.4, None).and_then(|s| s.from), Some(1));
    }
}
