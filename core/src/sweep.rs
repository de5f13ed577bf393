//! Multiresolution (METHOD §8): the interface parameters a parametric study can sweep without
//! refactorizing anything, and the predictors that build the start state of the next value from
//! the converged states of the previous ones.

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
}

impl Predictor {
    /// Parses `previous` or `linear`.
    pub fn parse(name: &str) -> Result<Self> {
        match name {
            "previous" => Ok(Self::Previous),
            "linear" => Ok(Self::Linear),
            _ => Err(LopinError::setting(
                "predictor",
                format!("unknown predictor `{name}` (previous, linear)"),
            )),
        }
    }

    /// Name.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Previous => "previous",
            Self::Linear => "linear",
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
            for (x, y) in h.f.iter_mut().zip(&h0.f) {
                *x += r * (*x - y);
            }
            for (x, y) in h.w.iter_mut().zip(&h0.w) {
                *x += r * (*x - y);
            }
        }
        Some(s)
    }
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
}
