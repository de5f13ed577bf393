//! Time grid and prescribed time functions: the smooth (1 − cos) ramp recommended by METHOD §10
//! (C¹ data converge fast) and the linear ramp kept to show why it is not the default; the
//! standard shock pulses (half-sine, haversine, terminal-peak sawtooth, trapezoid) of shock test
//! specifications; tables of (time, value) points, linearly interpolated and held after the
//! last point; and velocities integrated from a prescribed acceleration by the time scheme's own
//! rule (METHOD §2), for base excitation.

use std::sync::Arc;

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

/// A standard shock pulse of unit peak, zero before t = 0 and after its duration.
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PulseKind {
    /// sin(π t / T).
    HalfSine,
    /// ½ (1 − cos(2π t / T)).
    Haversine,
    /// t / T, then back to 0 at T (terminal-peak sawtooth).
    Sawtooth,
    /// t / r over the rise r, 1, then (T − t) / r over the last r.
    Trapezoid,
}

impl PulseKind {
    /// The name scenes use.
    pub fn name(&self) -> &'static str {
        match self {
            Self::HalfSine => "half-sine",
            Self::Haversine => "haversine",
            Self::Sawtooth => "sawtooth",
            Self::Trapezoid => "trapezoid",
        }
    }
}

/// How a time function goes from 0 to its amplitude.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A ramp of `time` seconds to the amplitude, held after (0 s: a step).
    Ramp { profile: Ramp, time: f64 },
    /// A pulse of `duration` seconds (`rise`: the trapezoid's rise and fall time).
    Pulse {
        kind: PulseKind,
        duration: f64,
        rise: f64,
    },
    /// Points (t, value) with increasing t, interpolated linearly from (0, 0) (or from the first
    /// point when it is at t = 0), the last value held.
    Table(Arc<[[f64; 2]]>),
    /// A velocity that integrates a prescribed acceleration of this shape on the time grid
    /// ([`Integrated`]).
    Integrated(Arc<Integrated>),
}

/// A velocity from rest integrated from a prescribed acceleration A(t) (unit amplitude) by the
/// time scheme's own rule, V_m = V_{m−1} + Δt [(1 − γ) A(t_{m−1}) + γ A(t_m)], V_0 = 0 (METHOD §2:
/// Δt/2 (A_{m−1} + A_m) for the trapezoidal rule), so that a dof driven by V has the
/// acceleration A(t_m) at every step of the march (from rest, A(0) = 0); linear between steps,
/// the last value held. [`TimeFunction::integrate`] fills it for a grid and a scheme.
#[derive(Debug, Clone, PartialEq)]
pub struct Integrated {
    /// The acceleration's shape.
    pub acceleration: Shape,
    /// (Δt, γ) of the integration; None until integrated (the velocity is then 0).
    pub rule: Option<(f64, f64)>,
    /// V_m at t_m, m = 0..=N.
    pub velocity: Arc<[f64]>,
}

impl Integrated {
    /// The acceleration `acceleration`, not yet integrated.
    pub fn new(acceleration: Shape) -> Self {
        Self {
            acceleration,
            rule: None,
            velocity: Arc::new([]),
        }
    }

    /// Integrated on `steps` steps of Δt with the scheme's γ.
    fn integrated(&self, dt: f64, gamma: f64, steps: usize) -> Self {
        let mut velocity = Vec::with_capacity(steps + 1);
        let (mut v, mut a_prev) = (0.0, self.acceleration.unit_value(0.0));
        velocity.push(v);
        for m in 1..=steps {
            let a = self.acceleration.unit_value(dt * m as f64);
            v += dt * ((1.0 - gamma) * a_prev + gamma * a);
            velocity.push(v);
            a_prev = a;
        }
        Self {
            acceleration: self.acceleration.clone(),
            rule: Some((dt, gamma)),
            velocity: velocity.into(),
        }
    }

    /// V(t): V_m at the steps, linear between them, held after the last.
    fn value(&self, t: f64) -> f64 {
        let Some((dt, _)) = self.rule else {
            return 0.0;
        };
        let Some(&last) = self.velocity.last() else {
            return 0.0;
        };
        if t <= 0.0 {
            return 0.0;
        }
        let x = t / dt;
        let m = x.floor();
        let i = m as usize;
        if i + 1 >= self.velocity.len() {
            return last;
        }
        let s = x - m;
        if s == 0.0 {
            self.velocity[i]
        } else {
            self.velocity[i] + s * (self.velocity[i + 1] - self.velocity[i])
        }
    }
}

impl Shape {
    /// The shape's value at time t for a unit amplitude.
    pub fn unit_value(&self, t: f64) -> f64 {
        match self {
            Shape::Ramp { profile, time } => ramp_value(1.0, *profile, *time, t),
            Shape::Pulse {
                kind,
                duration,
                rise,
            } => pulse_value(*kind, *duration, *rise, t),
            Shape::Table(points) => table_value(points, t),
            Shape::Integrated(i) => i.value(t),
        }
    }
}

/// A scalar function of time: amplitude × shape.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeFunction {
    /// Scale of the shape (the value after a ramp, a pulse's peak, the factor on a table).
    pub amplitude: f64,
    /// The shape.
    pub shape: Shape,
}

impl TimeFunction {
    /// A constant value from t = 0.
    pub fn constant(amplitude: f64) -> Self {
        Self::ramp(amplitude, Ramp::Step, 0.0)
    }

    /// `amplitude` reached through `profile` in `time` seconds.
    pub fn ramp(amplitude: f64, profile: Ramp, time: f64) -> Self {
        Self {
            amplitude,
            shape: Shape::Ramp { profile, time },
        }
    }

    /// Value at time t.
    pub fn value(&self, t: f64) -> f64 {
        match &self.shape {
            Shape::Ramp { profile, time } => ramp_value(self.amplitude, *profile, *time, t),
            shape => self.amplitude * shape.unit_value(t),
        }
    }

    /// A velocity from rest whose acceleration is `amplitude` × `acceleration` (m/s²), to be
    /// integrated on the time grid ([`Self::integrate`]).
    pub fn from_acceleration(amplitude: f64, acceleration: Shape) -> Self {
        Self {
            amplitude,
            shape: Shape::Integrated(Arc::new(Integrated::new(acceleration))),
        }
    }

    /// The prescribed acceleration's shape, for a velocity integrated from one.
    pub fn acceleration(&self) -> Option<&Shape> {
        match &self.shape {
            Shape::Integrated(i) => Some(&i.acceleration),
            _ => None,
        }
    }

    /// Integrates a velocity from its acceleration ([`Integrated`]) for `steps` steps of Δt
    /// and the scheme's γ, unless it already is; other shapes are left alone.
    pub fn integrate(&mut self, dt: f64, gamma: f64, steps: usize) {
        if let Shape::Integrated(i) = &self.shape {
            if i.rule != Some((dt, gamma)) || i.velocity.len() != steps + 1 {
                self.shape = Shape::Integrated(Arc::new(i.integrated(dt, gamma, steps)));
            }
        }
    }

    /// The shape in words, for reports.
    pub fn describe(&self) -> String {
        match &self.shape {
            Shape::Ramp { profile, time } => format!("ramp {profile:?} over {time:e} s"),
            Shape::Pulse {
                kind: PulseKind::Trapezoid,
                duration,
                rise,
            } => format!("trapezoid pulse of {duration:e} s, rise {rise:e} s"),
            Shape::Pulse { kind, duration, .. } => {
                format!("{} pulse of {duration:e} s", kind.name())
            }
            Shape::Table(points) => format!("table of {} points", points.len()),
            Shape::Integrated(i) => {
                let of = TimeFunction {
                    amplitude: 1.0,
                    shape: i.acceleration.clone(),
                };
                format!("velocity from an acceleration ({})", of.describe())
            }
        }
    }
}

fn ramp_value(amplitude: f64, profile: Ramp, time: f64, t: f64) -> f64 {
    if time <= 0.0 || t >= time || profile == Ramp::Step {
        return if t >= 0.0 { amplitude } else { 0.0 };
    }
    let s = (t / time).max(0.0);
    match profile {
        Ramp::Cosine => amplitude * 0.5 * (1.0 - (std::f64::consts::PI * s).cos()),
        Ramp::Linear => amplitude * s,
        Ramp::Step => amplitude,
    }
}

/// A unit pulse at time t.
fn pulse_value(kind: PulseKind, duration: f64, rise: f64, t: f64) -> f64 {
    if !(0.0..=duration).contains(&t) || duration <= 0.0 {
        return 0.0;
    }
    let s = t / duration;
    match kind {
        PulseKind::HalfSine => (std::f64::consts::PI * s).sin(),
        PulseKind::Haversine => 0.5 * (1.0 - (2.0 * std::f64::consts::PI * s).cos()),
        PulseKind::Sawtooth if t < duration => s,
        PulseKind::Sawtooth => 0.0,
        PulseKind::Trapezoid => (t / rise).min((duration - t) / rise).min(1.0),
    }
}

/// A table at time t: 0 at t = 0 unless the table starts there, linear between points, the
/// last value held.
fn table_value(points: &[[f64; 2]], t: f64) -> f64 {
    let Some(first) = points.first() else {
        return 0.0;
    };
    if t < 0.0 {
        return 0.0;
    }
    if t <= first[0] {
        // from (0, 0) to the first point (its value at once when it is at t = 0)
        return if first[0] <= 0.0 {
            first[1]
        } else {
            first[1] * t / first[0]
        };
    }
    let k = points.partition_point(|p| p[0] <= t);
    let Some(b) = points.get(k) else {
        return points[points.len() - 1][1];
    };
    let a = points[k - 1];
    a[1] + (b[1] - a[1]) * (t - a[0]) / (b[0] - a[0])
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn cosine_ramp_is_smooth_and_reaches_amplitude() {
        let f = TimeFunction::ramp(10.0, Ramp::Cosine, 2.0);
        assert_eq!(f.value(0.0), 0.0);
        assert!((f.value(1.0) - 5.0).abs() < 1e-12);
        assert_eq!(f.value(2.0), 10.0);
        assert_eq!(f.value(3.0), 10.0);
        let l = TimeFunction::ramp(10.0, Ramp::Linear, 2.0);
        assert!((l.value(0.5) - 2.5).abs() < 1e-12);
    }

    fn pulse(kind: PulseKind, rise: f64) -> TimeFunction {
        TimeFunction {
            amplitude: 490.5,
            shape: Shape::Pulse {
                kind,
                duration: 11e-3,
                rise,
            },
        }
    }

    /// Each pulse against its closed form at the points of a time grid of Δt = 0.1 ms over
    /// 20 ms (past the pulse's end, where it is 0), to 1e-12 of the peak.
    #[test]
    fn pulses_match_their_closed_forms_on_a_time_grid() {
        let (a, d, r) = (490.5, 11e-3, 2e-3);
        let closed: [(PulseKind, &dyn Fn(f64) -> f64); 4] = [
            (PulseKind::HalfSine, &|t| a * (PI * t / d).sin()),
            (PulseKind::Haversine, &|t| a * (PI * t / d).sin().powi(2)),
            (PulseKind::Sawtooth, &|t| {
                if t < d {
                    a * t / d
                } else {
                    0.0
                }
            }),
            (PulseKind::Trapezoid, &|t| {
                a * if t < r {
                    t / r
                } else if t > d - r {
                    (d - t) / r
                } else {
                    1.0
                }
            }),
        ];
        for (kind, exact) in closed {
            let f = pulse(kind, r);
            for m in 0..=200 {
                let t = m as f64 * 1e-4;
                let want = if t <= d { exact(t) } else { 0.0 };
                assert!(
                    (f.value(t) - want).abs() <= 1e-12 * a,
                    "{} at t = {t}: {} vs {want}",
                    kind.name(),
                    f.value(t)
                );
            }
            assert_eq!(f.value(-1e-6), 0.0);
        }
        // the half-sine and haversine peak mid-pulse, the sawtooth at its end
        assert!((pulse(PulseKind::HalfSine, 0.0).value(d / 2.0) - a).abs() < 1e-12 * a);
        assert!((pulse(PulseKind::Haversine, 0.0).value(d / 2.0) - a).abs() < 1e-12 * a);
        assert!((pulse(PulseKind::Sawtooth, 0.0).value(d * (1.0 - 1e-12)) - a).abs() < 1e-9 * a);
    }

    /// A table: linear between its points, from (0, 0) to a first point after t = 0, its last
    /// value held, scaled by the amplitude.
    #[test]
    fn tables_interpolate_linearly_and_hold_their_last_value() {
        let points: Arc<[[f64; 2]]> = vec![[1e-3, 2.0], [3e-3, -1.0], [4e-3, 0.5]].into();
        let f = TimeFunction {
            amplitude: 3.0,
            shape: Shape::Table(points),
        };
        let exact = |t: f64| -> f64 {
            3.0 * if t <= 1e-3 {
                2.0 * t / 1e-3
            } else if t <= 3e-3 {
                2.0 - 3.0 * (t - 1e-3) / 2e-3
            } else if t <= 4e-3 {
                -1.0 + 1.5 * (t - 3e-3) / 1e-3
            } else {
                0.5
            }
        };
        for m in 0..=60 {
            let t = m as f64 * 1e-4;
            assert!((f.value(t) - exact(t)).abs() < 1e-12, "t = {t}");
        }
        assert_eq!(f.value(-1.0), 0.0);
        let at_zero = TimeFunction {
            amplitude: 1.0,
            shape: Shape::Table(vec![[0.0, 5.0], [1.0, 7.0]].into()),
        };
        assert_eq!(at_zero.value(0.0), 5.0);
        assert!((at_zero.value(0.25) - 5.5).abs() < 1e-12);
    }
}
