//! The numbers a study reports beside its rows: the statistics of every quantity of interest over
//! the configurations (mean, standard deviation, quantiles: what a sampled study is for), the
//! finite-difference sensitivities along the path (each warm step that moved one parameter), and
//! for sampled studies the standardized regression coefficients (how much of each quantity's
//! spread each parameter explains, linearly).
//!
//! A quantity that is not finite in some configuration (NaN or ±inf: a solve that broke down)
//! is left out of that quantity's statistics, and said so: each [`Statistics`] counts those
//! configurations and names them (`non_finite`, `non_finite_configurations` in `study.json`),
//! [`warnings`] gives the line the study prints for each such quantity, and the regression has
//! no coefficient (null) for it rather than one fitted to part of the rows.

use lopin_core::study::runner::Outcome;
use lopin_core::study::{Design, Quantities};
use serde::Serialize;

const NQ: usize = Quantities::NAMES.len();

/// Statistics of one quantity over the finished configurations.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Statistics {
    pub quantity: &'static str,
    /// Configurations whose value is finite (the ones these statistics are of).
    pub count: usize,
    /// Configurations whose value is NaN or infinite, left out.
    pub non_finite: usize,
    /// Their indices, in increasing order.
    pub non_finite_configurations: Vec<usize>,
    pub mean: f64,
    /// Sample standard deviation (n − 1).
    pub sd: f64,
    pub min: f64,
    pub p5: f64,
    pub p25: f64,
    pub p50: f64,
    pub p75: f64,
    pub p95: f64,
    pub max: f64,
}

/// The quantile q of sorted values, linear between order statistics (type 7).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        1 => sorted[0],
        n => {
            let h = q.clamp(0.0, 1.0) * (n - 1) as f64;
            let i = (h.floor() as usize).min(n - 2);
            sorted[i] + (h - i as f64) * (sorted[i + 1] - sorted[i])
        }
    }
}

/// The statistics of every quantity over the finite values, counting and naming the
/// configurations whose value is not finite.
pub fn statistics(outcomes: &[Outcome]) -> Vec<Statistics> {
    (0..NQ)
        .map(|k| {
            let mut v: Vec<f64> = outcomes
                .iter()
                .map(|o| o.quantities.values()[k])
                .filter(|x| x.is_finite())
                .collect();
            let mut non_finite_configurations: Vec<usize> = outcomes
                .iter()
                .filter(|o| !o.quantities.values()[k].is_finite())
                .map(|o| o.index)
                .collect();
            non_finite_configurations.sort_unstable();
            v.sort_by(f64::total_cmp);
            let n = v.len();
            let mean = v.iter().sum::<f64>() / n.max(1) as f64;
            let var =
                v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n.max(2) - 1) as f64;
            Statistics {
                quantity: Quantities::NAMES[k].0,
                count: n,
                non_finite: non_finite_configurations.len(),
                non_finite_configurations,
                mean: if n > 0 { mean } else { f64::NAN },
                sd: if n > 1 { var.sqrt() } else { f64::NAN },
                min: v.first().copied().unwrap_or(f64::NAN),
                p5: quantile(&v, 0.05),
                p25: quantile(&v, 0.25),
                p50: quantile(&v, 0.5),
                p75: quantile(&v, 0.75),
                p95: quantile(&v, 0.95),
                max: v.last().copied().unwrap_or(f64::NAN),
            }
        })
        .collect()
}

/// One line per quantity that is not finite in some configuration: which quantity, how many
/// configurations of how many, which (the first ten), and that they are left out of its
/// statistics.
pub fn warnings(statistics: &[Statistics]) -> Vec<String> {
    const NAMED: usize = 10;
    statistics
        .iter()
        .filter(|s| s.non_finite > 0)
        .map(|s| {
            let shown: Vec<String> = s
                .non_finite_configurations
                .iter()
                .take(NAMED)
                .map(usize::to_string)
                .collect();
            let more = s.non_finite.saturating_sub(NAMED);
            format!(
                "warning: {} is not finite in {} of {} configurations ({}{}): left out of its \
                 statistics (study.json: non_finite)",
                s.quantity,
                s.non_finite,
                s.count + s.non_finite,
                shown.join(", "),
                if more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                }
            )
        })
        .collect()
}

/// A finite difference along the path: the warm step from `from` to `to` moved only
/// `parameter`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    pub from: usize,
    pub to: usize,
    /// Which parameter moved (index into the study's parameters).
    pub parameter: usize,
    /// The parameter's value at the middle of the step.
    pub at: f64,
    /// ΔQ / Δp for every quantity.
    pub derivative: [f64; NQ],
    /// ΔQ / Δp times the parameter's span in the study.
    pub scaled: [f64; NQ],
}

/// The sensitivities of every warm step of the study that moved exactly one parameter.
pub fn sensitivities(design: &Design, outcomes: &[Outcome]) -> Vec<Sensitivity> {
    let d = design.targets.len();
    let spans: Vec<f64> = (0..d)
        .map(|p| {
            let (lo, hi) = design
                .points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x[p]), b.max(x[p]))
                });
            hi - lo
        })
        .collect();
    let by_index = |i: usize| outcomes.iter().find(|o| o.index == i);
    let mut out = Vec::new();
    for o in outcomes {
        let Some(from) = o.start.and_then(by_index) else {
            continue;
        };
        let (a, b) = (&design.points[from.index], &design.points[o.index]);
        let moved: Vec<usize> = (0..d).filter(|&p| a[p] != b[p]).collect();
        let [p] = moved[..] else {
            continue;
        };
        let dp = b[p] - a[p];
        let (qa, qb) = (from.quantities.values(), o.quantities.values());
        let derivative: [f64; NQ] = std::array::from_fn(|k| (qb[k] - qa[k]) / dp);
        out.push(Sensitivity {
            from: from.index,
            to: o.index,
            parameter: p,
            at: 0.5 * (a[p] + b[p]),
            derivative,
            scaled: std::array::from_fn(|k| derivative[k] * spans[p]),
        });
    }
    out
}

/// Standardized regression coefficients of a sampled study: for each parameter (rows) and
/// quantity (columns), b·σ_p/σ_Q of the least-squares fit Q ≈ a + Σ b_p x_p (None when the fit
/// is singular, e.g. fewer configurations than parameters + 2).
pub fn regression(design: &Design, outcomes: &[Outcome]) -> Option<Vec<[f64; NQ]>> {
    let d = design.targets.len();
    let n = outcomes.len();
    if n < d + 2 {
        return None;
    }
    let x: Vec<&Vec<f64>> = outcomes.iter().map(|o| &design.points[o.index]).collect();
    let mean = |f: &dyn Fn(usize) -> f64| (0..n).map(f).sum::<f64>() / n as f64;
    let xm: Vec<f64> = (0..d).map(|p| mean(&|i| x[i][p])).collect();
    let xs: Vec<f64> = (0..d)
        .map(|p| mean(&|i| (x[i][p] - xm[p]).powi(2)).sqrt())
        .collect();
    if xs.iter().any(|&s| s <= 0.0) {
        return None;
    }
    // normal equations on the standardized parameters
    let z = |i: usize, p: usize| (x[i][p] - xm[p]) / xs[p];
    let gram: Vec<Vec<f64>> = (0..d)
        .map(|p| (0..d).map(|q| mean(&|i| z(i, p) * z(i, q))).collect())
        .collect();
    let mut out = vec![[0.0; NQ]; d];
    for k in 0..NQ {
        let y = |i: usize| outcomes[i].quantities.values()[k];
        let ym = mean(&|i| y(i));
        let ys = mean(&|i| (y(i) - ym).powi(2)).sqrt();
        if !ys.is_finite() {
            // a non-finite value in some configuration: no fit ([`warnings`] names them)
            for row in out.iter_mut() {
                row[k] = f64::NAN;
            }
            continue;
        }
        let rhs: Vec<f64> = (0..d).map(|p| mean(&|i| z(i, p) * (y(i) - ym))).collect();
        let b = solve(gram.clone(), rhs)?;
        for p in 0..d {
            out[p][k] = if ys > 0.0 { b[p] / ys } else { 0.0 };
        }
    }
    Some(out)
}

/// Gaussian elimination with partial pivoting (tiny systems).
fn solve(mut a: Vec<Vec<f64>>, mut b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    for c in 0..n {
        let p = (c..n).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c].abs() < 1e-12 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..n {
            let m = a[r][c] / a[c][c];
            for k in c..n {
                a[r][k] -= m * a[c][k];
            }
            b[r] -= m * b[c];
        }
    }
    let mut x = vec![0.0; n];
    for r in (0..n).rev() {
        let s: f64 = (r + 1..n).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    Some(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lopin_core::study::{Spread, Target};

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert_eq!(quantile(&v, 0.25), 2.0);
        assert!((quantile(&v, 0.05) - 1.2).abs() < 1e-12);
        assert_eq!(quantile(&v, 1.0), 5.0);
        assert!(quantile(&[], 0.5).is_nan());
    }

    fn outcome(index: usize, start: Option<usize>, q0: f64) -> Outcome {
        Outcome {
            index,
            chain: 0,
            position: index,
            start,
            start_change: None,
            start_residual: None,
            start_distance: None,
            iterations: 1,
            eta: 0.0,
            converged: true,
            wall_s: 0.0,
            quantities: Quantities {
                peak_normal_force: q0,
                ..Quantities::default()
            },
            cold_iterations: None,
        }
    }

    #[test]
    fn finite_differences_and_regression_recover_a_linear_response() {
        // Q = 3 f − 2e5 gap + 1 on a 3 × 2 grid visited with one-parameter steps
        let problem = lopin_core::scene::problem_of(
            &lopin_core::scene::load("two-blocks").expect("scene"),
            "two-blocks",
        )
        .expect("builds");
        let design = Design::grid(vec![
            (
                Target::parse("f", &problem).expect("test value"),
                Spread::parse("0:0.2:0.1").expect("test value"),
            ),
            (
                Target::parse("gap", &problem).expect("test value"),
                Spread::parse("0,1e-5").expect("test value"),
            ),
        ])
        .expect("grid");
        let q = |i: usize| 3.0 * design.points[i][0] - 2e5 * design.points[i][1] + 1.0;
        let order = [0usize, 2, 4, 5, 3, 1];
        let outcomes: Vec<Outcome> = order
            .iter()
            .enumerate()
            .map(|(k, &i)| outcome(i, (k > 0).then(|| order[k - 1]), q(i)))
            .collect();
        let sens = sensitivities(&design, &outcomes);
        assert_eq!(sens.len(), 5);
        for s in &sens {
            let want = if s.parameter == 0 { 3.0 } else { -2e5 };
            assert!((s.derivative[0] - want).abs() < 1e-6 * want.abs(), "{s:?}");
        }
        let src = regression(&design, &outcomes).expect("fit");
        // σ_f = 0.0816…, σ_gap = 5e-6: b_f σ_f = 0.2449, b_gap σ_gap = −1, σ_Q = sqrt(0.06 + 1)
        let sq = (0.06f64 + 1.0).sqrt();
        assert!((src[0][0] - 3.0 * (0.02f64 / 3.0).sqrt() / sq).abs() < 1e-9);
        assert!((src[1][0] + 1.0 / sq).abs() < 1e-9);
        let st = statistics(&outcomes);
        assert!((st[0].mean - 0.3).abs() < 1e-12);
        assert!(st.iter().all(|s| s.non_finite == 0));
        assert!(warnings(&st).is_empty());
        // a non-finite value: no coefficients for that quantity (null in study.json)
        let mut broken = outcomes.clone();
        broken[2].quantities.peak_normal_force = f64::NAN;
        let src = regression(&design, &broken).expect("fit");
        assert!(src[0][0].is_nan() && src[1][0].is_nan());
        assert_eq!(src[0][1], 0.0);
    }

    #[test]
    fn study_statistics_report_non_finite_rows() {
        // peak_normal_force 1 … 6 on configurations 0 … 5, NaN on 6, +inf on 7, −inf on 8
        let mut outcomes: Vec<Outcome> = (0..6)
            .map(|i| outcome(i, None, f64::from(i as u8) + 1.0))
            .collect();
        outcomes.push(outcome(8, None, f64::NEG_INFINITY));
        outcomes.push(outcome(6, None, f64::NAN));
        outcomes.push(outcome(7, None, f64::INFINITY));
        let st = statistics(&outcomes);
        let peak = &st[0];
        assert_eq!(peak.count, 6);
        assert_eq!(peak.non_finite, 3);
        assert_eq!(peak.non_finite_configurations, [6, 7, 8]);
        assert_eq!(
            (peak.mean, peak.min, peak.max, peak.p50),
            (3.5, 1.0, 6.0, 3.5)
        );
        assert!((peak.sd - 3.5f64.sqrt()).abs() < 1e-12);
        // the other quantities are 0 everywhere: all counted
        assert_eq!((st[1].count, st[1].non_finite), (9, 0));
        assert_eq!(
            warnings(&st),
            [
                "warning: peak_normal_force is not finite in 3 of 9 configurations (6, 7, 8): \
                 left out of its statistics (study.json: non_finite)"
            ]
        );
        let json = serde_json::to_value(peak).expect("serializes");
        assert_eq!(json["non_finite"], 3);
        assert_eq!(
            json["non_finite_configurations"],
            serde_json::json!([6, 7, 8])
        );
        // only the first ten configurations are named
        let many: Vec<Outcome> = (0..13).map(|i| outcome(i, None, f64::NAN)).collect();
        assert_eq!(
            warnings(&statistics(&many))[0],
            "warning: peak_normal_force is not finite in 13 of 13 configurations (0, 1, 2, 3, \
             4, 5, 6, 7, 8, 9 and 3 more): left out of its statistics (study.json: non_finite)"
        );
    }
}
