//! Converged interface states of a study kept compactly (s in f32: half the memory of f64, and
//! a warm start needs only a close start, METHOD §8), keyed by their scaled configuration: the
//! nearest solved configuration, a parallelogram of three, the bracket of a one-parameter study
//! and the states combined from them, which [`super::predictor`] starts from.

use crate::state::{InterfaceState, TraceHistory};
use crate::study::path::{along_earlier, distance, moves};

/// One stored state.
#[derive(Debug, Clone)]
struct Compact {
    /// Scaled configuration.
    point: Vec<f64>,
    /// Which configuration it is.
    index: usize,
    steps: usize,
    /// Entries per step of each substructure trace, and whether it was stored here.
    lens: Vec<(usize, bool)>,
    /// F then W of every stored trace, f32.
    values: Vec<f32>,
}

/// The converged states of a study.
#[derive(Debug, Clone, Default)]
pub struct StateStore {
    entries: Vec<Compact>,
}

impl StateStore {
    /// Keeps the state of configuration `index` at scaled point `point`.
    pub fn insert(&mut self, index: usize, point: &[f64], state: &InterfaceState) {
        let mut values = Vec::with_capacity(state.size());
        for h in &state.subs {
            values.extend(h.f.iter().chain(&h.w).map(|&x| x as f32));
        }
        self.entries.push(Compact {
            point: point.to_vec(),
            index,
            steps: state.steps,
            lens: state
                .subs
                .iter()
                .map(|h| (h.len, !h.f.is_empty()))
                .collect(),
            values,
        });
    }

    /// The stored configuration nearest `point`: (its index, the distance). Among equally near
    /// ones (to 1e-9), the one reached by a step along the earliest parameter, then the latest
    /// stored: on a grid walked with the first parameter fastest ([`super::Path::greedy`]),
    /// each configuration starts from its neighbour along that parameter (a friction step)
    /// rather than from the previous row (a gap step, which moves the impact time and costs
    /// nearly a cold solve), and the path's own predecessor wins the remaining ties.
    pub fn nearest(&self, point: &[f64]) -> Option<(usize, f64)> {
        let near: Vec<(usize, f64)> = self
            .entries
            .iter()
            .enumerate()
            .map(|(k, e)| (k, distance(&e.point, point)))
            .collect();
        let d = near.iter().map(|n| n.1).min_by(f64::total_cmp)?;
        let step = |k: usize| moves(&self.entries[k].point, point);
        let (k, dk) = near
            .into_iter()
            .filter(|n| n.1 <= d + 1e-9)
            .max_by(|a, b| along_earlier(&step(a.0), &step(b.0), 1e-9).then(a.0.cmp(&b.0)))?;
        Some((self.entries[k].index, dk))
    }

    /// The `count` stored configurations nearest `point`, nearest first.
    pub fn nearest_k(&self, point: &[f64], count: usize) -> Vec<usize> {
        self.closest(point, count)
            .into_iter()
            .map(|(_, e)| e.index)
            .collect()
    }

    /// The `count` stored entries nearest `point` with their distances, nearest first.
    fn closest(&self, point: &[f64], count: usize) -> Vec<(f64, &Compact)> {
        let mut close: Vec<(f64, &Compact)> = self
            .entries
            .iter()
            .map(|e| (distance(&e.point, point), e))
            .collect();
        close.sort_by(|a, b| a.0.total_cmp(&b.0));
        close.truncate(count);
        close
    }

    /// The state of configuration `index`, in f64.
    pub fn state(&self, index: usize) -> Option<InterfaceState> {
        let e = self.entries.iter().find(|e| e.index == index)?;
        let mut at = 0;
        let subs = e
            .lens
            .iter()
            .map(|&(len, stored)| {
                if !stored {
                    return TraceHistory::absent(len);
                }
                let n = len * (e.steps + 1);
                let take = |at: &mut usize| {
                    let v: Vec<f64> = e.values[*at..*at + n]
                        .iter()
                        .map(|&x| f64::from(x))
                        .collect();
                    *at += n;
                    v
                };
                let f = take(&mut at);
                let w = take(&mut at);
                TraceHistory { len, f, w }
            })
            .collect();
        Some(InterfaceState {
            steps: e.steps,
            subs,
        })
    }

    /// A first-order start for `point` from three stored configurations j, k, l whose scaled
    /// points close a parallelogram with it (point − q_j = q_k − q_l, k ≠ j): the change that
    /// moving from l to k made, carried over to j. Searched among the `near` stored
    /// configurations nearest `point`; the one with the shortest sides wins. Returns (j, k, l).
    pub fn parallelogram(&self, point: &[f64], near: usize) -> Option<(usize, usize, usize)> {
        let close = self.closest(point, near);
        let mut best: Option<(f64, (usize, usize, usize))> = None;
        for &(dj, j) in &close {
            for &(dk, k) in &close {
                if k.index == j.index {
                    continue;
                }
                for &(_, l) in &close {
                    if l.index == j.index || l.index == k.index {
                        continue;
                    }
                    let closes = point
                        .iter()
                        .zip(&j.point)
                        .zip(k.point.iter().zip(&l.point))
                        .all(|((p, qj), (qk, ql))| ((p - qj) - (qk - ql)).abs() < 1e-9);
                    let size = dj + dk;
                    if closes && best.is_none_or(|(b, _)| size < b) {
                        best = Some((size, (j.index, k.index, l.index)));
                    }
                }
            }
        }
        best.map(|(_, t)| t)
    }

    /// s_j + s_k − s_l in f64 (the start of [`Self::parallelogram`]).
    pub fn combined(&self, j: usize, k: usize, l: usize) -> Option<InterfaceState> {
        let mut out = self.state(j)?;
        let (sk, sl) = (self.state(k)?, self.state(l)?);
        for ((o, a), b) in out.subs.iter_mut().zip(&sk.subs).zip(&sl.subs) {
            for (x, (y, z)) in o.f.iter_mut().zip(a.f.iter().zip(&b.f)) {
                *x += y - z;
            }
            for (x, (y, z)) in o.w.iter_mut().zip(a.w.iter().zip(&b.w)) {
                *x += y - z;
            }
        }
        Some(out)
    }

    /// (1 − t) s_j + t s_k in f64: on the segment between two stored configurations, the
    /// point a fraction t of the way from j to k. Stored states are admissible and admissibility
    /// is affine (the linear stage's loads and initial state are shared, METHOD §4), so the
    /// interpolation is admissible too; between two values of a parameter that enters only the
    /// interface laws it is a start of second order in the bracket's width.
    pub fn between(&self, j: usize, k: usize, t: f64) -> Option<InterfaceState> {
        let mut out = self.state(j)?;
        let sk = self.state(k)?;
        for (o, a) in out.subs.iter_mut().zip(&sk.subs) {
            for (x, y) in o.f.iter_mut().zip(&a.f).chain(o.w.iter_mut().zip(&a.w)) {
                *x += t * (y - *x);
            }
        }
        Some(out)
    }

    /// The stored configurations nearest `point` below and above it along its first coordinate
    /// (a one-parameter study), (index, coordinate) each: None unless the point lies strictly
    /// (by more than `same`) between two stored ones.
    pub fn bracket(&self, point: &[f64], same: f64) -> Option<((usize, f64), (usize, f64))> {
        let value = *point.first()?;
        let side = |below: bool| {
            self.entries
                .iter()
                .filter_map(|e| Some((e.index, *e.point.first()?)))
                .filter(|&(_, x)| {
                    if below {
                        x < value - same
                    } else {
                        x > value + same
                    }
                })
                .min_by(|a, b| (a.1 - value).abs().total_cmp(&(b.1 - value).abs()))
        };
        Some((side(true)?, side(false)?))
    }

    /// Scaled distance from stored configuration `index` to `point`.
    pub fn distance_to(&self, index: usize, point: &[f64]) -> Option<f64> {
        let e = self.entries.iter().find(|e| e.index == index)?;
        Some(distance(&e.point, point))
    }

    /// Number of stored states.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether nothing is stored.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Bytes of stored values.
    pub fn bytes(&self) -> usize {
        self.entries
            .iter()
            .map(|e| e.values.len() * 4 + e.point.len() * 8 + e.lens.len() * 16)
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_come_back_to_f32_precision_and_the_nearest_is_found() {
        let state = |x: f64| InterfaceState {
            steps: 2,
            subs: vec![
                TraceHistory {
                    len: 2,
                    f: vec![x, 1.0, 2.0, 3.0, 4.0, 5.0],
                    w: vec![0.1; 6],
                },
                TraceHistory::absent(3),
            ],
        };
        let mut store = StateStore::default();
        store.insert(4, &[0.0, 0.0], &state(1.0 / 3.0));
        store.insert(9, &[1.0, 0.5], &state(2.0));
        let (j, d) = store.nearest(&[0.9, 0.4]).expect("nearest");
        assert_eq!(j, 9);
        assert!((d - 0.02f64.sqrt()).abs() < 1e-15);
        let back = store.state(4).expect("stored");
        assert!((back.subs[0].f[0] - 1.0 / 3.0).abs() < 1e-7);
        assert_eq!(back.subs[0].f[1..], state(0.0).subs[0].f[1..]);
        assert!(!back.subs[1].is_present() && back.subs[1].len == 3);
        assert_eq!(store.bytes(), 2 * (12 * 4 + 16 + 32));
        assert!(store.state(5).is_none());
    }

    #[test]
    fn between_interpolates_every_stored_trace_and_keeps_absent_ones_absent() {
        let state = |x: f64| InterfaceState {
            steps: 1,
            subs: vec![
                TraceHistory {
                    len: 1,
                    f: vec![x, 2.0 * x],
                    w: vec![-x, 0.5],
                },
                TraceHistory::absent(2),
            ],
        };
        let mut store = StateStore::default();
        store.insert(0, &[0.1], &state(1.0));
        store.insert(1, &[0.2], &state(3.0));
        let s = store.between(0, 1, 0.25).expect("both stored");
        assert_eq!(s.subs[0].f, vec![1.5, 3.0]);
        assert_eq!(s.subs[0].w, vec![-1.5, 0.5]);
        assert!(!s.subs[1].is_present());
        assert_eq!(
            store.between(1, 0, 0.0).expect("stored").subs[0].f,
            vec![3.0, 6.0]
        );
        assert!(store.between(0, 7, 0.5).is_none());
    }

    #[test]
    fn equally_near_configurations_go_to_the_step_along_the_first_parameter() {
        let state = InterfaceState {
            steps: 0,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![0.0],
                w: vec![0.0],
            }],
        };
        let mut store = StateStore::default();
        // a grid row (gap 0.0) then the start of the next row (gap 0.1), walked f fastest
        store.insert(0, &[0.0, 0.0], &state);
        store.insert(1, &[0.1, 0.0], &state);
        store.insert(2, &[0.1, 0.1], &state);
        // (0, 0.1) is 0.1 from both (0, 0) (a step along the second parameter) and (0.1, 0.1)
        // (along the first): the first parameter's step wins, whatever was stored first
        assert_eq!(store.nearest(&[0.0, 0.1]).map(|n| n.0), Some(2));
        // (0, 0) nearer by a rounding difference only: still a tie
        assert_eq!(store.nearest(&[0.0, 0.1 - 1e-12]).map(|n| n.0), Some(2));
        // two equal steps along the same parameter (to rounding): the latest stored
        store.insert(3, &[0.2, 0.1], &state);
        assert_eq!(store.nearest(&[0.15, 0.1]).map(|n| n.0), Some(3));
        // a strictly nearer configuration wins over any tie rule
        assert_eq!(store.nearest(&[0.0, 0.04]).map(|n| n.0), Some(0));
    }

    #[test]
    fn a_parallelogram_carries_a_change_over() {
        let state = |x: f64| InterfaceState {
            steps: 0,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![x],
                w: vec![2.0 * x],
            }],
        };
        let mut store = StateStore::default();
        store.insert(0, &[0.0, 0.0], &state(1.0));
        store.insert(1, &[0.1, 0.0], &state(1.5));
        store.insert(2, &[0.0, 0.1], &state(3.0));
        // (0.1, 0.1) = (0.1, 0) + (0, 0.1) − (0, 0)
        let (j, k, l) = store.parallelogram(&[0.1, 0.1], 8).expect("closes");
        assert_eq!(l, 0);
        assert_eq!([j.min(k), j.max(k)], [1, 2]);
        let s = store.combined(j, k, l).expect("stored");
        assert_eq!((s.subs[0].f[0], s.subs[0].w[0]), (3.5, 7.0));
        // nothing closes a parallelogram with (0.2, 0.2)
        assert!(store.parallelogram(&[0.2, 0.2], 8).is_none());
    }
}
