//! Time grid and prescribed time functions: the smooth (1 − cos) ramp recommended by METHOD §10
//! (C¹ data converge fast) and the linear ramp kept to show why it is not the default.

use serde::{Deserialize, Serialize};

/// The uniform time grid t_m = m Δt, m = 0..=steps (METHOD §1).
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimeGrid {
    /// Time step Δt (s).
    pub dt: f64,
    /// Number of steps N.
    pub steps: usize,
}

impl TimeGrid {
    /// t_m.
    pub fn time(&self, m: usize) -> f64 {
        self.dt * m as f64
    }

    /// Final time N Δt.
    pub fn end(&self) -> f64 {
        self.time(self.steps)
    }
}

/// Shape of a ramp from 0 to the amplitude.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "lowercase")]
pub enum Ramp {
    /// V₀ ½ (1 − cos(π t / t_r)) for t < t_r (C¹; default).
    #[default]
    Cosine,
    /// V₀ t / t_r for t < t_r (C⁰: excites the slow Nyquist mode of METHOD §10).
    Linear,
    /// V₀ for all t ≥ 0 (a step).
    Step,
}

/// A scalar function of time: amplitude × ramp profile.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeFunction {
    /// Value after the ramp.
    pub amplitude: f64,
    /// Profile of the ramp.
    pub ramp: Ramp,
    /// Ramp duration t_r (s); 0 means a step.
    pub ramp_time: f64,
}

impl TimeFunction {
    /// A constant value from t = 0.
    pub fn constant(amplitude: f64) -> Self {
        Self {
            amplitude,
            ramp: Ramp::Step,
            ramp_time: 0.0,
        }
    }

    /// Value at time t.
    pub fn value(&self, t: f64) -> f64 {
        if self.ramp_time <= 0.0 || t >= self.ramp_time || self.ramp == Ramp::Step {
            return if t >= 0.0 { self.amplitude } else { 0.0 };
        }
        let s = (t / self.ramp_time).max(0.0);
        match self.ramp {
            Ramp::Cosine => self.amplitude * 0.5 * (1.0 - (std::f64::consts::PI * s).cos()),
            Ramp::Linear => self.amplitude * s,
            Ramp::Step => self.amplitude,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cosine_ramp_is_smooth_and_reaches_amplitude() {
        let f = TimeFunction {
            amplitude: 10.0,
            ramp: Ramp::Cosine,
            ramp_time: 2.0,
        };
        assert_eq!(f.value(0.0), 0.0);
        assert!((f.value(1.0) - 5.0).abs() < 1e-12);
        assert_eq!(f.value(2.0), 10.0);
        assert_eq!(f.value(3.0), 10.0);
        let l = TimeFunction {
            ramp: Ramp::Linear,
            ..f
        };
        assert!((l.value(0.5) - 2.5).abs() < 1e-12);
    }
}
