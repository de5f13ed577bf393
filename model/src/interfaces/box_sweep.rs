//! Bounding boxes sorted along x, so that the boxes whose x-extent can reach an interval are
//! found by binary search: interface detection compares a face or a substructure with its
//! neighbours only, in O(n log n + pairs) for n substructures where comparing every pair was
//! O(n²). Candidates come back in increasing index order, the order a loop over every box
//! visits them, so results do not depend on the search.

use crate::mesh::Vec3;

/// The boxes' indices sorted by their lower x, with the widest x-extent.
#[derive(Debug)]
pub struct BoxSweep {
    /// (lower x, box index), sorted.
    sorted: Vec<(f64, usize)>,
    widest: f64,
}

impl BoxSweep {
    /// Indexes `boxes` (lower and upper corners).
    pub fn new(boxes: &[(Vec3, Vec3)]) -> Self {
        let mut sorted: Vec<(f64, usize)> = boxes.iter().map(|b| b.0[0]).zip(0..).collect();
        sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
        let widest = boxes.iter().map(|b| b.1[0] - b.0[0]).fold(0.0f64, f64::max);
        Self { sorted, widest }
    }

    /// The boxes whose x-extent meets [lo, hi] (and perhaps a few that come within the widest
    /// extent of it), in increasing index order.
    pub fn meeting(&self, lo: f64, hi: f64) -> Vec<usize> {
        let from = lo - self.widest;
        let start = self.sorted.partition_point(|e| e.0 < from);
        let end = self.sorted.partition_point(|e| e.0 <= hi);
        let mut out: Vec<usize> = self.sorted[start..end.max(start)]
            .iter()
            .map(|e| e.1)
            .collect();
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::splitmix::SplitMix64;

    /// Random boxes: every box whose x-extent meets the interval is among the candidates.
    #[test]
    fn meeting_holds_every_box_an_exhaustive_scan_finds() {
        let mut rng = SplitMix64(7);
        let boxes: Vec<(Vec3, Vec3)> = (0..500)
            .map(|_| {
                let lo = [rng.unit() * 10.0, rng.unit(), rng.unit()];
                let w = rng.unit() * 2.0;
                (lo, [lo[0] + w, lo[1] + 1.0, lo[2] + 1.0])
            })
            .collect();
        let sweep = BoxSweep::new(&boxes);
        for _ in 0..200 {
            let lo = rng.unit() * 12.0 - 1.0;
            let hi = lo + rng.unit();
            let found = sweep.meeting(lo, hi);
            assert!(found.windows(2).all(|w| w[0] < w[1]));
            for (i, b) in boxes.iter().enumerate() {
                if b.0[0] <= hi && b.1[0] >= lo {
                    assert!(found.binary_search(&i).is_ok(), "box {i} missed");
                }
            }
        }
    }
}
