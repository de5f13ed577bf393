//! The order in which a study visits its configurations: a greedy nearest-neighbour path in
//! scaled parameter space (each parameter divided by its span, so f ∈ [0, 0.5] and a gap in
//! micrometres weigh alike), starting from the corner of smallest values, so that each solve
//! warm-starts from a close neighbour (METHOD §8); cut into chains of consecutive
//! configurations that run at once, each warm-starting along its own part of the path.
//!
//! Each step of the path asks for the nearest configuration not visited yet; a k-d tree of the
//! scaled configurations with visited ones removed ([`Remaining`]) answers it from the few
//! cells near the current configuration, so planning grows about as n log n rather than as n²,
//! and gives exactly the configuration an exhaustive search would (the same distances, the same
//! ties, the same tie rule).

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
    /// The greedy nearest-neighbour path from the configuration of smallest scaled coordinates.
    /// Ties go to the step along the earliest parameter, then to the lowest index: a grid is
    /// walked as a serpentine with the first parameter varying fastest, so the first parameter
    /// should be the one whose changes the warm start absorbs best (friction before a gap,
    /// which moves the impact time).
    pub fn greedy(points: &[Vec<f64>]) -> Self {
        let s = scaled(points);
        let n = s.len();
        let mut order = Vec::with_capacity(n);
        let Some(mut at) = (0..n).min_by(|&a, &b| {
            s[a].iter()
                .sum::<f64>()
                .total_cmp(&s[b].iter().sum::<f64>())
                .then(a.cmp(&b))
        }) else {
            return Self { order, length: 0.0 };
        };
        let mut left = Remaining::new(&s);
        let mut length = 0.0;
        let mut near = Vec::new();
        loop {
            order.push(at);
            left.remove(at);
            let Some(d) = left.nearest(&s[at]) else {
                break;
            };
            // among the nearest, the step along the earliest parameter (so a grid is walked
            // with the first parameter varying fastest), then the lowest index
            near.clear();
            left.within(&s[at], d + 1e-9, &mut near);
            let j = near
                .iter()
                .copied()
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

/// Most configurations in one leaf of [`Remaining`].
const LEAF: usize = 8;

/// One cell of [`Remaining`]: a box holding `perm[start..end]`.
#[derive(Debug, Clone)]
struct Cell {
    /// The box: the least and greatest coordinates of its configurations.
    lo: Vec<f64>,
    hi: Vec<f64>,
    start: usize,
    end: usize,
    /// The two halves, or None for a leaf.
    halves: Option<(usize, usize)>,
    parent: Option<usize>,
    /// Configurations in it not removed yet.
    alive: usize,
}

/// The configurations a greedy path has not visited yet: a k-d tree over their scaled
/// coordinates (each cell split at the median of its widest coordinate, leaves of at most
/// [`LEAF`]), each cell counting the configurations left in it, so that removed ones cost
/// nothing to skip.
struct Remaining<'a> {
    points: &'a [Vec<f64>],
    cells: Vec<Cell>,
    perm: Vec<usize>,
    leaf_of: Vec<usize>,
    left: Vec<bool>,
}

impl<'a> Remaining<'a> {
    fn new(points: &'a [Vec<f64>]) -> Self {
        let n = points.len();
        let mut tree = Self {
            points,
            cells: Vec::new(),
            perm: (0..n).collect(),
            leaf_of: vec![0; n],
            left: vec![true; n],
        };
        if n > 0 {
            tree.build(0, n, None);
        }
        tree
    }

    /// Builds the cell of `perm[start..end]` and its halves; returns its number.
    fn build(&mut self, start: usize, end: usize, parent: Option<usize>) -> usize {
        let dims = self.points[self.perm[start]].len();
        let (mut lo, mut hi) = (vec![f64::INFINITY; dims], vec![f64::NEG_INFINITY; dims]);
        for &i in &self.perm[start..end] {
            for (d, &x) in self.points[i].iter().enumerate() {
                lo[d] = lo[d].min(x);
                hi[d] = hi[d].max(x);
            }
        }
        let widest = (0..dims).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])));
        let id = self.cells.len();
        self.cells.push(Cell {
            lo,
            hi,
            start,
            end,
            halves: None,
            parent,
            alive: end - start,
        });
        let split =
            widest.filter(|&d| end - start > LEAF && self.cells[id].hi[d] > self.cells[id].lo[d]);
        match split {
            Some(d) => {
                let mid = start + (end - start) / 2;
                let points = self.points;
                self.perm[start..end].select_nth_unstable_by(mid - start, |&a, &b| {
                    points[a][d].total_cmp(&points[b][d])
                });
                let a = self.build(start, mid, Some(id));
                let b = self.build(mid, end, Some(id));
                self.cells[id].halves = Some((a, b));
            }
            None => {
                for k in start..end {
                    self.leaf_of[self.perm[k]] = id;
                }
            }
        }
        id
    }

    /// A lower bound of the distance from `p` to every configuration in cell `c`, computed
    /// as [`distance`] is, so that it never exceeds the distance it bounds (each term is the
    /// rounded difference to the box, no greater than the rounded difference to a point inside).
    fn bound(&self, c: usize, p: &[f64]) -> f64 {
        let cell = &self.cells[c];
        let nearest: Vec<f64> = p
            .iter()
            .zip(cell.lo.iter().zip(&cell.hi))
            .map(|(&x, (&lo, &hi))| x.clamp(lo, hi))
            .collect();
        distance(p, &nearest)
    }

    /// Takes configuration `i` out.
    fn remove(&mut self, i: usize) {
        if !std::mem::replace(&mut self.left[i], false) {
            return;
        }
        let mut at = Some(self.leaf_of[i]);
        while let Some(c) = at {
            self.cells[c].alive -= 1;
            at = self.cells[c].parent;
        }
    }

    /// The distance from `p` to the nearest configuration left (None: none is left).
    fn nearest(&self, p: &[f64]) -> Option<f64> {
        let mut best = f64::INFINITY;
        if !self.cells.is_empty() {
            self.search(0, p, &mut best);
        }
        best.is_finite().then_some(best)
    }

    fn search(&self, c: usize, p: &[f64], best: &mut f64) {
        let cell = &self.cells[c];
        if cell.alive == 0 || self.bound(c, p) > *best {
            return;
        }
        match cell.halves {
            None => {
                for &i in &self.perm[cell.start..cell.end] {
                    if self.left[i] {
                        *best = best.min(distance(p, &self.points[i]));
                    }
                }
            }
            Some((a, b)) => {
                // the nearer half first: its configurations prune the other's
                let (first, second) = if self.bound(a, p) <= self.bound(b, p) {
                    (a, b)
                } else {
                    (b, a)
                };
                self.search(first, p, best);
                self.search(second, p, best);
            }
        }
    }

    /// Appends to `out` every configuration left within `radius` of `p` (distance ≤ radius).
    fn within(&self, p: &[f64], radius: f64, out: &mut Vec<usize>) {
        let mut stack = Vec::new();
        if !self.cells.is_empty() {
            stack.push(0);
        }
        while let Some(c) = stack.pop() {
            let cell = &self.cells[c];
            if cell.alive == 0 || self.bound(c, p) > radius {
                continue;
            }
            match cell.halves {
                None => out.extend(
                    self.perm[cell.start..cell.end]
                        .iter()
                        .copied()
                        .filter(|&i| self.left[i] && distance(p, &self.points[i]) <= radius),
                ),
                Some((a, b)) => stack.extend([a, b]),
            }
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

/// The next value of a one-parameter study that grows around a moving value (the explorer's
/// background study around its slider): among `grid`, the value nearest `current` (ties: the
/// lower) that `open` still accepts (not solved, not given up); None once none is.
pub fn nearest_open(grid: &[f64], open: impl Fn(f64) -> bool, current: f64) -> Option<f64> {
    grid.iter()
        .copied()
        .filter(|&v| open(v))
        .min_by(|a, b| (a - current).abs().total_cmp(&(b - current).abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_nearest_open_value_prefers_the_lower_on_a_tie() {
        let grid = [0.0, 0.1, 0.2, 0.3];
        assert_eq!(nearest_open(&grid, |_| true, 0.15), Some(0.1));
        assert_eq!(nearest_open(&grid, |v| v != 0.1, 0.12), Some(0.2));
        assert_eq!(nearest_open(&grid, |_| false, 0.12), None);
    }

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

    /// The greedy path by exhaustive search: every step measures every configuration left.
    fn greedy_exhaustive(points: &[Vec<f64>]) -> Path {
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
            return Path { order, length: 0.0 };
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
            let j = (0..n)
                .filter(|&j| left[j] && distance(&s[at], &s[j]) <= d + 1e-9)
                .max_by(|&a, &b| {
                    along_earlier(&moves(&s[at], &s[a]), &moves(&s[at], &s[b]), 0.0).then(b.cmp(&a))
                })
                .unwrap_or(at);
            length += d;
            at = j;
        }
        Path { order, length }
    }

    #[test]
    fn the_tree_search_walks_the_same_path_as_the_exhaustive_search() {
        let mut rng = crate::splitmix::SplitMix64(7);
        // grids (many equal distances), grids with repeated points, and random clouds in one
        // to four dimensions
        let mut designs: Vec<Vec<Vec<f64>>> = vec![
            (0..7)
                .flat_map(|i| (0..5).map(move |j| vec![0.1 * f64::from(i), 1e-6 * f64::from(j)]))
                .collect(),
            (0..4)
                .flat_map(|i| {
                    (0..3).flat_map(move |j| {
                        (0..3).map(move |k| vec![f64::from(i), f64::from(j), f64::from(k)])
                    })
                })
                .collect(),
            (0..40).map(|i| vec![f64::from(i % 5), 0.5]).collect(),
        ];
        for dims in 1..=4 {
            for n in [1, 2, 9, 50, 300] {
                designs.push(
                    (0..n)
                        .map(|_| (0..dims).map(|_| rng.unit()).collect())
                        .collect(),
                );
            }
        }
        for points in &designs {
            let (tree, all) = (Path::greedy(points), greedy_exhaustive(points));
            assert_eq!(tree.order, all.order, "{} points", points.len());
            assert_eq!(tree.length.to_bits(), all.length.to_bits());
        }
        assert_eq!(Path::greedy(&[]).order, Vec::<usize>::new());
    }

    #[test]
    fn study_plans_100000_samples() {
        // a Latin hypercube of 100,000 samples in two parameters, planned whole
        let n = 100_000;
        let mut rng = crate::splitmix::SplitMix64(1);
        let mut points: Vec<Vec<f64>> = vec![Vec::new(); n];
        for _ in 0..2 {
            let mut strata: Vec<usize> = (0..n).collect();
            for i in (1..n).rev() {
                strata.swap(i, rng.below(i + 1));
            }
            for (p, &s) in points.iter_mut().zip(&strata) {
                p.push((s as f64 + rng.unit()) / n as f64);
            }
        }
        let path = Path::greedy(&points);
        let mut seen = path.order.clone();
        seen.sort_unstable();
        assert_eq!(seen, (0..n).collect::<Vec<_>>());
        // every step measured: the length is the sum of the steps
        let s = scaled(&points);
        let sum: f64 = path
            .order
            .windows(2)
            .map(|w| distance(&s[w[0]], &s[w[1]]))
            .sum();
        assert!(
            (path.length - sum).abs() <= 1e-9 * sum,
            "{} {sum}",
            path.length
        );
        // far shorter than the given order's walk across the square
        assert!(path.length < 0.02 * Path::given(&points).length);
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
