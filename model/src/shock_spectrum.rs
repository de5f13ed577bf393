//! The shock response spectrum (SRS) shock engineers read off an acceleration history: for each
//! natural frequency f of a band, the largest absolute acceleration (maximax: during the shock
//! and after it, the residual) of a single-degree-of-freedom oscillator of damping ratio ζ
//! (quality factor Q = 1/(2ζ)) whose base follows the history. The oscillator is marched by the
//! ramp-invariant recursive filter of Smallwood (ISO 18431-4), exact for a history that is linear
//! between its samples:
//!
//!   y_k = 2C y_{k−1} − E² y_{k−2} + (1 − S') x_k + 2(S' − C) x_{k−1} + (E² − S') x_{k−2},
//!   E = e^{−ζωΔt}, C = E cos(ω_d Δt), S' = E sin(ω_d Δt)/(ω_d Δt), ω_d = ω √(1 − ζ²),
//!
//! followed by zeros for one natural period so that the residual peak is seen. The history a
//! run gives is the step-averaged acceleration (v_m − v_{m−1})/Δt, which carries none of the
//! trapezoidal rule's alternating mode (METHOD §2, §10 "force ringing").

use std::f64::consts::PI;

/// The natural frequencies of a band: `per_octave` per octave (log-spaced) from `low` to `high`
/// (Hz), both ends included.
pub fn frequencies(low: f64, high: f64, per_octave: usize) -> Vec<f64> {
    let octaves = (high / low).log2();
    let n = (octaves * per_octave as f64).ceil().max(1.0) as usize;
    (0..=n)
        .map(|i| low * (high / low).powf(i as f64 / n as f64))
        .collect()
}

/// The maximax absolute acceleration of the oscillator of natural frequency `f` (Hz) and damping
/// ratio `zeta` under the base acceleration `history` sampled every `dt` s.
pub fn maximax(history: &[f64], dt: f64, f: f64, zeta: f64) -> f64 {
    let w = 2.0 * PI * f;
    let wd = w * (1.0 - zeta * zeta).sqrt();
    let e = (-zeta * w * dt).exp();
    let k = wd * dt;
    let c = e * k.cos();
    let sp = e * k.sin() / k;
    let (a1, a2) = (2.0 * c, e * e);
    let (b0, b1, b2) = (1.0 - sp, 2.0 * (sp - c), e * e - sp);
    let residual = (1.0 / (f * dt)).ceil() as usize + 2;
    let (mut x1, mut x2, mut y1, mut y2) = (0.0, 0.0, 0.0, 0.0);
    let mut peak: f64 = 0.0;
    let inputs = history
        .iter()
        .copied()
        .chain(std::iter::repeat_n(0.0, residual));
    for x in inputs {
        let y = a1 * y1 - a2 * y2 + b0 * x + b1 * x1 + b2 * x2;
        peak = peak.max(y.abs());
        (x2, x1, y2, y1) = (x1, x, y1, y);
    }
    peak
}

/// The maximax spectrum of `history` at the frequencies `freqs` (Hz), damping ratio `zeta`.
pub fn spectrum(history: &[f64], dt: f64, freqs: &[f64], zeta: f64) -> Vec<f64> {
    freqs
        .iter()
        .map(|&f| maximax(history, dt, f, zeta))
        .collect()
}

/// The maximax spectrum of each component of a three-component history, per frequency.
pub fn component_spectra(history: &[[f64; 3]], dt: f64, freqs: &[f64], zeta: f64) -> Vec<[f64; 3]> {
    let per_component: Vec<Vec<f64>> = (0..3)
        .map(|c| {
            let h: Vec<f64> = history.iter().map(|a| a[c]).collect();
            spectrum(&h, dt, freqs, zeta)
        })
        .collect();
    (0..freqs.len())
        .map(|i| std::array::from_fn(|c| per_component[c][i]))
        .collect()
}

/// The default band of natural frequencies (Hz) for a history of `duration` s sampled every
/// `dt` s: from 1/duration to a tenth of the sampling frequency.
pub fn default_band(dt: f64, duration: f64) -> (f64, f64) {
    (1.0 / duration, 0.1 / dt)
}

/// The step-averaged accelerations (v_m − v_{m−1})/Δt of a velocity history v_0..v_N, one per
/// step (at the mid-steps t_{m−½}).
pub fn step_accelerations(velocity: &[[f64; 3]], dt: f64) -> Vec<[f64; 3]> {
    velocity
        .windows(2)
        .map(|w| std::array::from_fn(|c| (w[1][c] - w[0][c]) / dt))
        .collect()
}

/// The damping ratio ζ = 1/(2Q) of a quality factor Q.
pub fn ratio_of_quality(q: f64) -> f64 {
    0.5 / q
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sin(πt/T) for t ≤ T, then 0, sampled every Δt at t = 0..=n Δt.
    fn half_sine(a: f64, t_pulse: f64, dt: f64, n: usize) -> Vec<f64> {
        (0..=n)
            .map(|i| {
                let t = i as f64 * dt;
                if t <= t_pulse {
                    a * (PI * t / t_pulse).sin()
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The undamped oscillator under a half-sine A sin(πt/T) of the base, in closed form: the
    /// relative displacement z = −A/(ω² − Ω²) (sin Ωt − (Ω/ω) sin ωt) during the pulse (Ω = π/T),
    /// a free vibration after it; the absolute acceleration is −ω² z. Its maximax on a grid of
    /// 200,000 points of the pulse and the exact residual amplitude.
    fn half_sine_exact(a: f64, t_pulse: f64, f: f64) -> f64 {
        let (w, big) = (2.0 * PI * f, PI / t_pulse);
        let z = |t: f64| -a / (w * w - big * big) * ((big * t).sin() - big / w * (w * t).sin());
        let zd = |t: f64| -a / (w * w - big * big) * big * ((big * t).cos() - (w * t).cos());
        let n = 200_000;
        let during = (0..=n)
            .map(|i| (w * w * z(t_pulse * i as f64 / n as f64)).abs())
            .fold(0.0, f64::max);
        let residual = w * w * z(t_pulse).hypot(zd(t_pulse) / w);
        during.max(residual)
    }

    /// Sampled at T/5000, the filter's spectrum of an undamped half-sine matches the closed form
    /// to 1e-4 from a fifth of the pulse's frequency to twenty times it (residual and primary
    /// regions both).
    #[test]
    fn the_undamped_half_sine_spectrum_matches_its_closed_form() {
        let (a, t_pulse) = (490.3, 0.011);
        let dt = t_pulse / 5000.0;
        let history = half_sine(a, t_pulse, dt, (1.5 * t_pulse / dt) as usize);
        for f in frequencies(0.2 / t_pulse, 20.0 / t_pulse, 6) {
            if ((2.0 * f * t_pulse) - 1.0).abs() < 1e-3 {
                continue; // ω = Ω: the closed form's resonant limit
            }
            let got = maximax(&history, dt, f, 0.0);
            let exact = half_sine_exact(a, t_pulse, f);
            assert!(
                (got / exact - 1.0).abs() < 1e-4,
                "f = {f} Hz: {got} against {exact}"
            );
        }
    }

    /// With damping, far above the pulse's frequencies the oscillator follows its base: the
    /// spectrum tends to the peak acceleration (Q = 10, within 1 % at 100/T); far below, it is
    /// small (the oscillator barely moves).
    #[test]
    fn the_damped_spectrum_tends_to_the_peak_at_high_frequency() {
        let (a, t_pulse) = (1000.0, 1e-3);
        let dt = t_pulse / 20000.0;
        let history = half_sine(a, t_pulse, dt, 20000);
        let zeta = ratio_of_quality(10.0);
        let high = maximax(&history, dt, 100.0 / t_pulse, zeta);
        assert!((high / a - 1.0).abs() < 1e-2, "{high}");
        let low = maximax(&history, dt, 0.01 / t_pulse, zeta);
        assert!(low < 0.1 * a, "{low}");
    }

    /// With damping (Q = 10), the filter's spectrum of a sampled half-sine equals the maximax of
    /// the oscillator marched independently: z'' + 2ζωz' + ω²z = −x(t), x linear between the
    /// samples, by RK4 at a hundredth of the sample step, the absolute acceleration
    /// −(2ζωz' + ω²z) read at the samples (to 1e-6, over the band 0.1/T to 10/T).
    #[test]
    fn the_damped_spectrum_matches_an_independent_march() {
        let (a, t_pulse, dt) = (1000.0, 1e-3, 1e-3 / 200.0);
        let history = half_sine(a, t_pulse, dt, 400);
        let zeta = ratio_of_quality(10.0);
        for f in frequencies(0.1 / t_pulse, 10.0 / t_pulse, 4) {
            let w = 2.0 * PI * f;
            let base = |t: f64| {
                let x = t / dt;
                let i = x.floor() as usize;
                let s = x - i as f64;
                let at = |k: usize| history.get(k).copied().unwrap_or(0.0);
                at(i) + s * (at(i + 1) - at(i))
            };
            let rhs = |t: f64, (z, v): (f64, f64)| (v, -base(t) - 2.0 * zeta * w * v - w * w * z);
            let sub = 100;
            let h = dt / sub as f64;
            let samples = history.len() + (1.0 / (f * dt)).ceil() as usize + 2;
            let (mut y, mut peak) = ((0.0, 0.0), 0.0f64);
            for k in 0..samples {
                for j in 0..sub {
                    let t = (k * sub + j) as f64 * h;
                    let k1 = rhs(t, y);
                    let k2 = rhs(t + h / 2.0, (y.0 + h / 2.0 * k1.0, y.1 + h / 2.0 * k1.1));
                    let k3 = rhs(t + h / 2.0, (y.0 + h / 2.0 * k2.0, y.1 + h / 2.0 * k2.1));
                    let k4 = rhs(t + h, (y.0 + h * k3.0, y.1 + h * k3.1));
                    y.0 += h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
                    y.1 += h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
                }
                peak = peak.max((2.0 * zeta * w * y.1 + w * w * y.0).abs());
            }
            let got = maximax(&history, dt, f, zeta);
            assert!(
                (got / peak - 1.0).abs() < 1e-6,
                "f = {f} Hz: {got} against {peak}"
            );
        }
    }

    #[test]
    fn the_band_has_its_ends_and_the_asked_density() {
        let f = frequencies(100.0, 1600.0, 3);
        assert_eq!(f.len(), 13);
        assert!((f[0] - 100.0).abs() < 1e-12 && (f[12] - 1600.0).abs() < 1e-9);
        let a = step_accelerations(&[[0.0; 3], [1.0, 2.0, 3.0]], 0.5);
        assert_eq!(a, vec![[2.0, 4.0, 6.0]]);
    }
}
