//! The order in which a study visits its configurations: a greedy nearest-neighbour path in
//! scaled parameter space (each parameter divided by its span, so f ∈ [0, 0.5] and a gap in
//! micrometres weigh alike), starting from the corner of smallest values, so that each solve
//! warm-starts from a close neighbour (METHOD §8); cut into chains of consecutive
//! configurations that run at once, each warm-starting along its own part of the path.

/// Configurations scaled to [0, 1] per parameter (a parameter that does not vary scales to 0).
pub fn scaled(points: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let dims = points.first().map_or(0, Vec::len);
    let spans: Vec<(f64, f64)> = (0..dims)
        .map(|d| {
            points
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p[d]), b.max(p[d]))
                })
        })
        .collect();
    points
        .iter()
        .map(|p| {
            p.iter()
                .zip(&spans)
                .map(|(&x, &(lo, hi))| if hi > lo { (x - lo) / (hi - lo) } else { 0.0 })
                .collect()
        })
        .collect()
}

/// Euclidean distance of two scaled configurations.
pub fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

/// The move from `a` to `b`: |Δ| per parameter.
pub fn moves(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).collect()
}

/// Compares two moves ([`moves`]) lexicographically, entries within `tol` counting as equal:
/// the greater is the step along the earlier parameter.
pub fn along_earlier(a: &[f64], b: &[f64], tol: f64) -> std::cmp::Ordering {
    a.iter()
        .zip(b)
        .map(|(x, y)| {
            if (x - y).abs() <= tol {
                std::cmp::Ordering::Equal
            } else {
                x.total_cmp(y)
            }
        })
        .find(|o| o.is_ne())
        .unwrap_or(std::cmp::Ordering::Equal)
}

/// A visiting order and its length in scaled space.
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    /// Configuration indices in visiting order (each once).
    pub order: Vec<usize>,
    /// Sum of the scaled distances between consecutive configurations.
    pub length: f64,
}

impl Path {
    /// The greedy nearest-neighbour path from the configuration of smallest scaled coordinates,
    /// O(n²). Ties go to the step along the earliest parameter, then to the lowest index: a
    /// grid is walked as a serpentine with the first parameter varying fastest, so the first
    /// parameter should be the one whose changes the warm start absorbs best (friction before a
    /// gap, which moves the impact time).
    pub fn greedy(points: &[Vec<f64>]) -> Self {
        let s = scaled(points);
        let n = s.len();
        let mut order = Vec::with_capacity(n);
        let mut left = vec![true; n];
        let Some(mut at) = (0..n).min_by(|&a, &b| {
            s[a].iter()
                .sum::<f64>()
                .total_cmp(&s[b].iter().sum::<f64>())
                .then(a.cmp(&b))
        }) else {
            return Self { order, length: 0.0 };
        };
        let mut length = 0.0;
        loop {
            order.push(at);
            left[at] = false;
            let Some(d) = (0..n)
                .filter(|&j| left[j])
                .map(|j| distance(&s[at], &s[j]))
                .min_by(f64::total_cmp)
            else {
                break;
            };
            // among the nearest, the step along the earliest parameter (so a grid is walked
            // with the first parameter varying fastest), then the lowest index
            let j = (0..n)
                .filter(|&j| left[j] && distance(&s[at], &s[j]) <= d + 1e-9)
                .max_by(|&a, &b| {
                    along_earlier(&moves(&s[at], &s[a]), &moves(&s[at], &s[b]), 0.0).then(b.cmp(&a))
                })
                .unwrap_or(at);
            length += d;
            at = j;
        }
        Self { order, length }
    }

    /// The configurations in their given order (the baseline the greedy path is measured
    /// against).
    pub fn given(points: &[Vec<f64>]) -> Self {
        let s = scaled(points);
        let length = s.windows(2).map(|w| distance(&w[0], &w[1])).sum();
        Self {
            order: (0..points.len()).collect(),
            length,
        }
    }
}

/// A path cut into chains of consecutive configurations, as equal in length as counts allow.
#[derive(Debug, Clone, PartialEq)]
pub struct Chains(pub Vec<Vec<usize>>);

impl Chains {
    /// `count` chains (at least one, at most one per configuration).
    pub fn split(path: &Path, count: usize) -> Self {
        let n = path.order.len();
        let count = count.clamp(1, n.max(1));
        Self(
            (0..count)
                .map(|c| path.order[c * n / count..(c + 1) * n / count].to_vec())
                .collect(),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_greedy_path_on_a_grid_snakes_with_unit_steps() {
        // 11 × 11 grid of (f, gap): every step of the path moves to a grid neighbour
        let points: Vec<Vec<f64>> = (0..11)
            .flat_map(|i| (0..11).map(move |j| vec![0.05 * i as f64, 2e-6 * j as f64]))
            .collect();
        let path = Path::greedy(&points);
        let mut seen = path.order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..121).collect::<Vec<_>>());
        assert_eq!(path.order[0], 0);
        assert!(
            (path.length - 120.0 * 0.1).abs() < 1e-9,
            "length {}",
            path.length
        );
        // a serpentine with f varying fastest: gap moves only at the ten row ends
        let gap_steps = path
            .order
            .windows(2)
            .filter(|w| points[w[0]][1] != points[w[1]][1])
            .count();
        assert_eq!(gap_steps, 10);
        assert_eq!(&path.order[..3], &[0, 11, 22]);
        // the given (row-major) order jumps back at every row's end
        assert!(Path::given(&points).length > path.length + 9.0);
    }

    #[test]
    fn chains_cover_the_path_once_in_order() {
        let points: Vec<Vec<f64>> = (0..10).map(|i| vec![f64::from(i)]).collect();
        let path = Path::greedy(&points);
        let chains = Chains::split(&path, 3);
        assert_eq!(chains.0.len(), 3);
        assert_eq!(chains.0.concat(), path.order);
        assert!(chains.0.iter().all(|c| (3..=4).contains(&c.len())));
        assert_eq!(Chains::split(&path, 50).0.len(), 10);
    }
}
