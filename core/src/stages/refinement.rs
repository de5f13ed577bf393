//! The guesses a single-precision solve is refined from (METHOD §4; the refinement itself is in
//! [`super::linear_stage`]: v_m = g + S̃⁻¹ (rhs_m − S g)): one slot a step of the time window
//! (slot m − m0), each holding the v_m and c_K K v_m of the last linear stage that marched step m
//! of a window starting at m0. At LATIN's fixed point every step's guess is its own converged
//! v_m, so the refined solve is exact on windows of any length; a slot not filled yet takes
//! v_{m−1} from the march.

/// The guesses of one substructure.
#[derive(Debug, Default)]
pub struct Guesses {
    /// The step each slot holds (None: empty).
    steps: Vec<Option<usize>>,
    /// v of each slot, n entries a slot.
    v: Vec<f64>,
    /// c_K K v of each slot.
    ckv: Vec<f64>,
    /// The slot of the solve under way.
    current: Option<usize>,
}

impl Guesses {
    /// Empties every slot: a new solve starts from none.
    pub fn forget(&mut self) {
        self.steps.iter_mut().for_each(|s| *s = None);
        self.current = None;
    }

    /// The guess of step m in a window starting at m0, (v, c_K K v): its slot's, or `fallback`
    /// copied into the slot when the slot does not hold step m. The slot becomes the current one.
    pub fn take(&mut self, m: usize, m0: usize, fallback: (&[f64], &[f64])) -> (&[f64], &[f64]) {
        let slot = self.slot(m, m0, fallback.0.len());
        let n = fallback.0.len();
        let range = slot * n..(slot + 1) * n;
        if self.steps[slot] != Some(m) {
            self.v[range.clone()].copy_from_slice(fallback.0);
            self.ckv[range.clone()].copy_from_slice(fallback.1);
            self.steps[slot] = Some(m);
        }
        self.current = Some(slot);
        (&self.v[range.clone()], &self.ckv[range])
    }

    /// Stores step m's v and c_K K v (window start m0) for the next linear stage.
    pub fn store(&mut self, m: usize, m0: usize, v: &[f64], ckv: &[f64]) {
        let n = v.len();
        let slot = self.slot(m, m0, n);
        self.v[slot * n..(slot + 1) * n].copy_from_slice(v);
        self.ckv[slot * n..(slot + 1) * n].copy_from_slice(ckv);
        self.steps[slot] = Some(m);
    }

    /// The v of the guess [`Self::take`] gave last, once (None: none since).
    pub fn take_current(&mut self) -> Option<&[f64]> {
        let slot = self.current.take()?;
        let n = self.v.len() / self.steps.len();
        Some(&self.v[slot * n..(slot + 1) * n])
    }

    /// The slot of step m in a window starting at m0 for vectors of n entries, made room for.
    fn slot(&mut self, m: usize, m0: usize, n: usize) -> usize {
        let slot = m - m0;
        if self.steps.len() <= slot {
            self.steps.resize(slot + 1, None);
            self.v.resize((slot + 1) * n, 0.0);
            self.ckv.resize((slot + 1) * n, 0.0);
        }
        slot
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slot keeps its step's vectors across marches, the fallback fills a slot that holds
    /// another step, and forgetting empties them all.
    #[test]
    fn slots_hold_their_steps_until_forgotten() {
        let mut g = Guesses::default();
        let (a, b) = ([1.0, 2.0], [3.0, 4.0]);
        // a window of steps 5..=6: the first march falls back on the state
        assert_eq!(g.take(5, 5, (&a, &b)), (&a[..], &b[..]));
        assert_eq!(g.take_current(), Some(&a[..]));
        assert_eq!(g.take_current(), None);
        g.store(5, 5, &[5.0, 6.0], &[7.0, 8.0]);
        g.store(6, 5, &[9.0, 10.0], &[11.0, 12.0]);
        // the next march of that window takes them
        assert_eq!(
            g.take(6, 5, (&a, &b)),
            (&[9.0, 10.0][..], &[11.0, 12.0][..])
        );
        assert_eq!(g.take(5, 5, (&a, &b)), (&[5.0, 6.0][..], &[7.0, 8.0][..]));
        // a window starting at step 6 maps step 6 to slot 0, which holds step 5: fallback
        assert_eq!(g.take(6, 6, (&a, &b)), (&a[..], &b[..]));
        g.forget();
        assert_eq!(g.take_current(), None);
        assert_eq!(g.take(6, 5, (&b, &a)), (&b[..], &a[..]));
    }
}
