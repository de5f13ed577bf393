//! Which configurations a study solves: the Cartesian grid of value lists (`f=0:0.5:0.05`), or
//! `n` samples of per-parameter distributions (`uniform(a,b)`, `normal(mean,sd)`,
//! `lognormal(mu,sigma)` with ln x ~ N(mu, sigma); a range or list counts as uniform over its
//! span) drawn by Latin hypercube (one draw in each of n equal-probability strata per
//! parameter, strata paired at random) or plain Monte Carlo, from a seed (splitmix64: the same
//! seed draws the same configurations on every machine and version). Every value is checked
//! against its parameter before anything is solved: a distribution that draws a negative
//! friction coefficient or gap is an error naming the sample, the parameter and the draw.

use crate::error::{LopinError, Result};
use crate::splitmix::SplitMix64;
use crate::target::Target;

/// The most configurations a study may hold.
pub const MAX_CONFIGURATIONS: usize = 1_000_000;

/// How one parameter spreads.
#[derive(Debug, Clone, PartialEq)]
pub enum Spread {
    /// Given values (`a:b:step` or `a,b,c`).
    Values(Vec<f64>),
    /// Uniform on [lo, hi].
    Uniform { lo: f64, hi: f64 },
    /// Normal with this mean and standard deviation.
    Normal { mean: f64, sd: f64 },
    /// ln x normal with mean mu and standard deviation sigma.
    LogNormal { mu: f64, sigma: f64 },
}

impl Spread {
    /// Parses `uniform(a,b)`, `normal(mean,sd)`, `lognormal(mu,sigma)`, or values as
    /// [`parse_values`] reads them.
    pub fn parse(text: &str) -> Result<Self> {
        let text = text.trim();
        let bad = |why: String| LopinError::setting("param", why);
        let Some((name, rest)) = text.split_once('(') else {
            // a range's values to 12 significant digits (0.15, not 0.15000000000000002)
            let round = |x: f64| format!("{x:.11e}").parse::<f64>().unwrap_or(x);
            return parse_values(text).map(|v| Self::Values(v.into_iter().map(round).collect()));
        };
        let args: Vec<f64> = rest
            .strip_suffix(')')
            .ok_or_else(|| bad(format!("`{text}` lacks its closing parenthesis")))?
            .split(',')
            .map(|a| {
                a.trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad(format!("`{}` in `{text}` is not a number", a.trim())))
            })
            .collect::<Result<_>>()?;
        let [a, b] = args[..] else {
            return Err(bad(format!("`{text}` takes two numbers")));
        };
        match name.trim() {
            "uniform" if a < b => Ok(Self::Uniform { lo: a, hi: b }),
            "uniform" => Err(bad(format!(
                "`{text}`: the lower bound must be below the upper"
            ))),
            "normal" if b > 0.0 => Ok(Self::Normal { mean: a, sd: b }),
            "lognormal" if b > 0.0 => Ok(Self::LogNormal { mu: a, sigma: b }),
            "normal" | "lognormal" => Err(bad(format!(
                "`{text}`: the standard deviation must be positive"
            ))),
            other => Err(bad(format!(
                "unknown distribution `{other}` (uniform, normal, lognormal)"
            ))),
        }
    }

    /// The value of probability u ∈ (0, 1) (the inverse distribution function; values: uniform
    /// over their span).
    pub fn quantile(&self, u: f64) -> f64 {
        match self {
            Self::Values(v) => {
                let (lo, hi) = span(v);
                lo + u * (hi - lo)
            }
            Self::Uniform { lo, hi } => lo + u * (hi - lo),
            Self::Normal { mean, sd } => mean + sd * normal_quantile(u),
            Self::LogNormal { mu, sigma } => (mu + sigma * normal_quantile(u)).exp(),
        }
    }

    /// How it reads in files and messages.
    pub fn describe(&self) -> String {
        match self {
            Self::Values(v) => format!("{} values in [{}, {}]", v.len(), span(v).0, span(v).1),
            Self::Uniform { lo, hi } => format!("uniform({lo}, {hi})"),
            Self::Normal { mean, sd } => format!("normal({mean}, {sd})"),
            Self::LogNormal { mu, sigma } => format!("lognormal({mu}, {sigma})"),
        }
    }
}

fn span(v: &[f64]) -> (f64, f64) {
    v.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

/// How samples are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// Latin hypercube: each parameter's n strata of equal probability hit once.
    LatinHypercube,
    /// Independent draws.
    MonteCarlo,
}

/// The configurations of a study: one row of values per configuration, in the targets' order.
#[derive(Debug, Clone, PartialEq)]
pub struct Design {
    pub targets: Vec<Target>,
    pub points: Vec<Vec<f64>>,
    /// Whether the points were drawn (statistics apply) or form a grid.
    pub sampled: bool,
}

impl Design {
    /// The Cartesian product of each target's values (the first target varies slowest).
    pub fn grid(axes: Vec<(Target, Spread)>) -> Result<Self> {
        let mut lists = Vec::new();
        let mut count: usize = 1;
        for (t, s) in &axes {
            let Spread::Values(v) = s else {
                return Err(LopinError::setting(
                    "param",
                    format!(
                        "`{}` is a distribution ({}): give --samples N to draw from it",
                        t.label,
                        s.describe()
                    ),
                ));
            };
            count = count
                .checked_mul(v.len())
                .filter(|&c| c <= MAX_CONFIGURATIONS)
                .ok_or_else(|| {
                    LopinError::setting(
                        "param",
                        format!("the grid has more than {MAX_CONFIGURATIONS} configurations"),
                    )
                })?;
            lists.push(v.clone());
        }
        let mut points: Vec<Vec<f64>> = vec![Vec::new()];
        for list in &lists {
            points = points
                .into_iter()
                .flat_map(|p| {
                    list.iter().map(move |&x| {
                        let mut q = p.clone();
                        q.push(x);
                        q
                    })
                })
                .collect();
        }
        let targets = axes.into_iter().map(|(t, _)| t).collect();
        let design = Self {
            targets,
            points,
            sampled: false,
        };
        design.check()?;
        Ok(design)
    }

    /// `n` samples of the targets' spreads.
    pub fn sample(
        axes: Vec<(Target, Spread)>,
        n: usize,
        sampling: Sampling,
        seed: u64,
    ) -> Result<Self> {
        if n == 0 || n > MAX_CONFIGURATIONS {
            return Err(LopinError::setting(
                "samples",
                format!("must be between 1 and {MAX_CONFIGURATIONS}, got {n}"),
            ));
        }
        let mut rng = SplitMix64(seed);
        let mut points = vec![Vec::with_capacity(axes.len()); n];
        for (_, spread) in &axes {
            let strata: Vec<usize> = match sampling {
                Sampling::LatinHypercube => {
                    // Fisher–Yates shuffle of the strata
                    let mut s: Vec<usize> = (0..n).collect();
                    for i in (1..n).rev() {
                        s.swap(i, rng.below(i + 1));
                    }
                    s
                }
                Sampling::MonteCarlo => Vec::new(),
            };
            for (i, p) in points.iter_mut().enumerate() {
                let u = match sampling {
                    Sampling::LatinHypercube => (strata[i] as f64 + rng.unit()) / n as f64,
                    Sampling::MonteCarlo => rng.unit(),
                };
                // keep u inside (0, 1): the normal quantile is infinite at the ends
                p.push(spread.quantile(u.clamp(1e-12, 1.0 - 1e-12)));
            }
        }
        let targets = axes.iter().map(|(t, _)| t.clone()).collect();
        let design = Self {
            targets,
            points,
            sampled: true,
        };
        design.check().map_err(|e| with_spreads(e, &axes))?;
        Ok(design)
    }

    /// Every value checked against its parameter (finite; f non-negative).
    fn check(&self) -> Result<()> {
        for (i, p) in self.points.iter().enumerate() {
            for (t, &x) in self.targets.iter().zip(p) {
                if let Err(e) = t.parameter.check(x) {
                    return Err(LopinError::setting(
                        "param",
                        format!(
                            "{} {i} has {} = {x:e}: {e}",
                            if self.sampled {
                                "sample"
                            } else {
                                "configuration"
                            },
                            t.label
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Adds the spreads to an error about a drawn value, with what to do about it.
fn with_spreads(e: LopinError, axes: &[(Target, Spread)]) -> LopinError {
    let e = match e {
        LopinError::Setting { field, reason } if field == "param" => reason,
        other => other.to_string(),
    };
    let spreads: Vec<String> = axes
        .iter()
        .map(|(t, s)| format!("{} ~ {}", t.label, s.describe()))
        .collect();
    LopinError::setting(
        "param",
        format!(
            "{e} (drawn from {}; a friction coefficient must stay non-negative: use \
             lognormal or uniform, or a narrower normal)",
            spreads.join(", ")
        ),
    )
}

/// The standard normal quantile Φ⁻¹(u), u ∈ (0, 1): Acklam's rational approximation (relative
/// error below 1.2e-9).
pub fn normal_quantile(u: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.38357751867269e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    const LOW: f64 = 0.02425;
    if u < LOW {
        tail((-2.0 * u.ln()).sqrt())
    } else if u > 1.0 - LOW {
        -tail((-2.0 * (1.0 - u).ln()).sqrt())
    } else {
        let q = u - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    }
}

/// Values of one parameter: `a:b:step` (inclusive, rounded to the step) or a list `a,b,c`.
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

    use crate::parameter::Parameter;

    fn target(p: Parameter) -> Target {
        Target {
            parameter: p,
            zone: None,
            label: p.name().into(),
        }
    }

    #[test]
    fn the_normal_quantile_matches_tabulated_values() {
        // Φ⁻¹ at 0.5, 0.975, 0.999, 1e-6 (tables), to 1e-8 relative
        for (u, z) in [
            (0.975, 1.959_963_984_540_054),
            (0.999, 3.090_232_306_167_813),
            (1e-6, -4.753_424_308_822_899),
            (0.841_344_746_068_542_9, 1.0),
        ] {
            let got = normal_quantile(u);
            assert!(
                (got - z).abs() < 1e-8 * z.abs(),
                "Φ⁻¹({u}) = {got}, not {z}"
            );
        }
        assert_eq!(normal_quantile(0.5), 0.0);
    }

    #[test]
    fn a_grid_is_the_cartesian_product_in_order() {
        let d = Design::grid(vec![
            (
                target(Parameter::Friction),
                Spread::parse("0:0.5:0.05").expect("test value"),
            ),
            (
                target(Parameter::Gap),
                Spread::parse("0:20e-6:2e-6").expect("test value"),
            ),
        ])
        .expect("test value");
        assert_eq!(d.points.len(), 121);
        assert_eq!(d.points[0], vec![0.0, 0.0]);
        assert!((d.points[12][0] - 0.05).abs() < 1e-15 && (d.points[12][1] - 2e-6).abs() < 1e-18);
        assert!(!d.sampled);
    }

    #[test]
    fn latin_hypercube_hits_every_stratum_once_and_is_seeded() {
        let n = 50;
        let axes = || {
            vec![
                (
                    target(Parameter::Friction),
                    Spread::parse("uniform(0.1, 0.5)").expect("test value"),
                ),
                (
                    target(Parameter::Gap),
                    Spread::parse("uniform(0, 1e-5)").expect("test value"),
                ),
            ]
        };
        let d = Design::sample(axes(), n, Sampling::LatinHypercube, 7).expect("test value");
        for (k, (lo, hi)) in [(0.1, 0.5), (0.0, 1e-5)].into_iter().enumerate() {
            let mut hit = vec![0; n];
            for p in &d.points {
                let stratum = ((p[k] - lo) / (hi - lo) * n as f64).floor() as usize;
                hit[stratum.min(n - 1)] += 1;
            }
            assert!(hit.iter().all(|&h| h == 1), "parameter {k}: strata {hit:?}");
        }
        assert_eq!(
            d,
            Design::sample(axes(), n, Sampling::LatinHypercube, 7).expect("test value")
        );
        assert_ne!(
            d,
            Design::sample(axes(), n, Sampling::LatinHypercube, 8).expect("test value")
        );
    }

    #[test]
    fn samples_have_the_moments_of_their_distributions() {
        // 4000 draws: the mean within 4 standard errors, the sd within 5 %
        let n = 4000;
        for (text, mean, sd) in [
            ("normal(0.3, 0.05)", 0.3, 0.05),
            // lognormal(mu, s): mean e^(mu + s²/2), var (e^(s²) − 1) e^(2mu + s²)
            (
                "lognormal(-1.5, 0.3)",
                (-1.5f64 + 0.045).exp(),
                ((0.09f64).exp_m1() * (-3.0f64 + 0.09).exp()).sqrt(),
            ),
        ] {
            for sampling in [Sampling::LatinHypercube, Sampling::MonteCarlo] {
                let d = Design::sample(
                    vec![(
                        target(Parameter::Friction),
                        Spread::parse(text).expect("test value"),
                    )],
                    n,
                    sampling,
                    3,
                )
                .expect("test value");
                let x: Vec<f64> = d.points.iter().map(|p| p[0]).collect();
                let m = x.iter().sum::<f64>() / n as f64;
                let s = (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt();
                assert!(
                    (m - mean).abs() < 4.0 * sd / (n as f64).sqrt(),
                    "{text} {sampling:?}: mean {m}"
                );
                assert!((s / sd - 1.0).abs() < 0.05, "{text} {sampling:?}: sd {s}");
            }
        }
    }

    #[test]
    fn bad_spreads_and_draws_are_refused_with_their_reason() {
        let msg = |r: Result<Spread>| r.expect_err("an error").to_string();
        assert!(msg(Spread::parse("normal(0.3)")).contains("two numbers"));
        assert!(msg(Spread::parse("normal(0.3, 0)")).contains("standard deviation"));
        assert!(msg(Spread::parse("uniform(1, 0)")).contains("lower bound"));
        assert!(msg(Spread::parse("weibull(1, 2)")).contains("unknown distribution"));
        assert!(msg(Spread::parse("1:0:0.1")).contains("stop ≥ start"));
        let e = Design::sample(
            vec![(
                target(Parameter::Friction),
                Spread::parse("normal(0.1, 0.1)").expect("test value"),
            )],
            100,
            Sampling::LatinHypercube,
            1,
        )
        .expect_err("an error")
        .to_string();
        assert!(
            e.contains("sample") && e.contains("f = -") && e.contains("lognormal"),
            "{e}"
        );
        let e = Design::sample(Vec::new(), 0, Sampling::MonteCarlo, 1)
            .expect_err("an error")
            .to_string();
        assert!(e.contains("samples"), "{e}");
        let e = Design::grid(vec![(
            target(Parameter::Friction),
            Spread::parse("normal(0.3, 0.1)").expect("test value"),
        )])
        .expect_err("an error")
        .to_string();
        assert!(e.contains("--samples"), "{e}");
    }
}
