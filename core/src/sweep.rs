//! Multiresolution (METHOD §8): the interface parameters a parametric study can sweep without
//! refactorizing anything, and the predictors that build the start state of the next value from
//! the converged states of the previous ones. The smooth predictor extrapolates only the part of
//! the change that varies slowly in time: the change filtered by the binomial weights
//! (¼, ½, ¼) over steps m − 1, m, m + 1, which take the alternating content
//! x_m = (−1)^m c (the highest frequency of the time grid, METHOD §10) to zero and keep affine
//! content in time unchanged.

use crate::error::{LopinError, Result};
use crate::state::InterfaceState;

/// How the start state of the next value is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Predictor {
    /// The previous converged state (the seed paper's restart).
    Previous,
    /// Linear extrapolation from the two previous converged states, scaled to the parameter
    /// step: s = s₁ + (p − p₁)/(p₁ − p₀) (s₁ − s₀).
    Linear,
    /// The linear extrapolation of the time-filtered change only:
    /// s = s₁ + (p − p₁)/(p₁ − p₀) T(s₁ − s₀), T the (¼, ½, ¼) filter over steps.
    Smooth,
}

impl Predictor {
    /// Parses `previous`, `linear` or `smooth`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "previous" => Ok(Self::Previous),
            "linear" => Ok(Self::Linear),
            "smooth" => Ok(Self::Smooth),
            _ => Err(LopinError::setting(
                "predictor",
                format!("unknown predictor `{name}` (previous, linear, smooth)"),
            )),
        }
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Previous => "previous",
            Self::Linear => "linear",
            Self::Smooth => "smooth",
        }
    }

    /// The start state for parameter value `p` from the converged (value, state) pairs of the
    /// previous values, most recent last. None: cold start (no previous value).
    pub fn predict(&self, history: &[(f64, &InterfaceState)], p: f64) -> Option<InterfaceState> {
        let (p1, s1) = *history.last()?;
        if *self == Self::Previous || history.len() < 2 {
            return Some(s1.clone());
        }
        let (p0, s0) = history[history.len() - 2];
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

/// Values of a sweep: `a:b:step` (inclusive, rounded to the step) or a list `a,b,c`.
pub fn parse_values(text: &str) -> Result<Vec<f64>> {
    let bad = |why: String| LopinError::setting("param", why);
    let num = |s: &str| {
        s.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| bad(format!("`{s}` is not a number")))
    };
    let values = if text.contains(':') {
        let parts: Vec<&str> = text.split(':').collect();
        let [a, b, step] = parts.as_slice() else {
            return Err(bad(format!("a range is start:stop:step, got `{text}`")));
        };
        let (a, b, step) = (num(a)?, num(b)?, num(step)?);
        if step <= 0.0 || b < a {
            return Err(bad(format!(
                "range `{text}` needs step > 0 and stop ≥ start"
            )));
        }
        let n = ((b - a) / step + 1e-9).floor() as usize;
        if n > 100_000 {
            return Err(bad(format!("range `{text}` has too many values")));
        }
        (0..=n).map(|i| a + step * i as f64).collect()
    } else {
        text.split(',').map(num).collect::<Result<Vec<f64>>>()?
    };
    if values.is_empty() {
        return Err(bad("no values".into()));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::TraceHistory;

    #[test]
    fn ranges_and_lists() {
        let v = parse_values("0:0.5:0.05").expect("range");
        assert_eq!(v.len(), 11);
        assert!((v[10] - 0.5).abs() < 1e-12);
        assert_eq!(parse_values("0.1, 0.3").expect("list"), vec![0.1, 0.3]);
        assert!(parse_values("0:1").is_err());
        assert!(parse_values("a,b").is_err());
        assert!(parse_values("1:0:0.1").is_err());
    }

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
            .predict(&[(0.1, &a), (0.2, &b)], 0.35)
            .expect("state");
        let exact = state(0.35);
        assert!((p.subs[0].f[1] - exact.subs[0].f[1]).abs() < 1e-14);
        assert!((p.subs[0].w[1] - exact.subs[0].w[1]).abs() < 1e-14);
        let q = Predictor::Previous
            .predict(&[(0.1, &a), (0.2, &b)], 0.35)
            .expect("state");
        assert_eq!(q, b);
        assert!(Predictor::Linear.predict(&[], 0.3).is_none());
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
            .predict(&[(1.0, &a), (2.0, &b)], 3.0)
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
}
