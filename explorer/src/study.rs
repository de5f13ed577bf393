//! The explorer's parametric study on the solver side (METHOD §8): the friction values
//! the background study covers (the slider's range at [`GRID_STEP`]), which of them to solve
//! next (the unsolved value nearest the user's, so each solve starts close to a stored one), and
//! the library of converged configurations: their interface states s and solutions ŝ in f32
//! ([`StateStore`]), iterations and quantities of interest, from which a configuration is shown
//! again without solving or warm-started by the study engine's predictor (between two stored
//! ones, their interpolation, [`Predictor::Bracket`]; else the nearest; beside the newest
//! solve's state, [`Predictor::bracket_start_beside`] decides which is nearer). Every stored
//! configuration shares the other parameters (the library's base); a change of any of them
//! empties it.

use crate::params::Params;
use lopin_core::state::{InterfaceState, TraceHistory};
use lopin_core::study::path::nearest_open;
pub use lopin_core::study::predictor::SAME;
use lopin_core::study::{Chain, Predictor, Quantities, StateStore};
use lopin_core::Solution;

/// Step of the background study's grid over the friction slider's range.
pub const GRID_STEP: f64 = 0.05;
/// The friction slider's range.
pub const GRID_RANGE: (f64, f64) = (0.0, 1.0);
/// The background study stops before its stored states would pass this many bytes (two-blocks
/// keeps about 1 MB per configuration).
pub const MEMORY_BUDGET: usize = 256 << 20;

/// The friction values the background study covers.
pub fn grid() -> Vec<f64> {
    let (lo, hi) = GRID_RANGE;
    let n = ((hi - lo) / GRID_STEP).round() as usize;
    (0..=n).map(|i| lo + i as f64 * GRID_STEP).collect()
}

/// The parameters a library's configurations share: all but the friction coefficient.
pub fn base(params: &Params) -> Params {
    Params {
        friction: None,
        ..params.clone()
    }
}

/// A start from the library: the state, the friction value it is (the nearer of two) and, for
/// an interpolation, the two values it lies between.
pub type StoredStart = (InterfaceState, f64, Option<(f64, f64)>);

/// What is kept of one converged configuration besides its states.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Friction coefficient.
    pub value: f64,
    /// Iterations of its solve.
    pub iterations: usize,
    /// Its last η.
    pub eta: f64,
    /// Its quantities of interest.
    pub quantities: Quantities,
    /// The time step of the picture the UI holds of it.
    pub pictured_step: usize,
}

/// Converged configurations of one base.
#[derive(Debug, Clone)]
pub struct Library {
    base: Option<Params>,
    /// The converged states s, started from by the study engine ([`Predictor::Bracket`]).
    states: Chain,
    hats: StateStore,
    /// Sides of each interface (the shape of ŝ).
    sides: Vec<usize>,
    entries: Vec<Entry>,
    /// Grid values whose background solve failed or did not converge: not tried again.
    given_up: Vec<f64>,
}

impl Default for Library {
    fn default() -> Self {
        Self {
            base: None,
            states: Chain::new(Predictor::Bracket),
            hats: StateStore::default(),
            sides: Vec::new(),
            entries: Vec::new(),
            given_up: Vec::new(),
        }
    }
}

impl Library {
    /// Whether configurations of `params` belong here; if not, the library is emptied and
    /// takes their base. Returns whether it was emptied.
    pub fn adopt(&mut self, params: &Params) -> bool {
        let b = base(params);
        if self.base.as_ref() == Some(&b) {
            return false;
        }
        *self = Library {
            base: Some(b),
            ..Library::default()
        };
        true
    }

    /// Whether `params` has this library's base.
    pub fn holds_base_of(&self, params: &Params) -> bool {
        self.base.as_ref() == Some(&base(params))
    }

    /// The stored configuration at exactly `value`.
    pub fn exact(&self, value: f64) -> Option<usize> {
        self.entries
            .iter()
            .position(|e| (e.value - value).abs() < SAME)
    }

    /// The warm start of `value` from the stored configurations, beside the newest solve's
    /// state at `held`: the study engine's [`Predictor::bracket_start_beside`] (between two
    /// stored ones their states interpolated linearly in the friction coefficient, admissible
    /// as each is, METHOD §8; else the nearest stored one where it is nearer than the newest).
    /// Returns the state, the value of the stored configuration it starts nearest to and the
    /// bracket's two values; None: start from the newest solve's state.
    pub fn start_beside(&self, value: f64, held: Option<f64>) -> Option<StoredStart> {
        let held = held.map(|h| [h]);
        let start = Predictor::bracket_start_beside(
            self.states.store(),
            &[value],
            held.as_ref().map(|h| &h[..]),
        )?;
        let near = self.entries.get(start.from?)?.value;
        let between = start.between.map(|((_, lo), (_, hi))| (lo, hi));
        Some((start.state?, near, between))
    }

    /// Keeps a converged configuration (replacing one at the same value); returns its index.
    pub fn insert(
        &mut self,
        value: f64,
        sol: &Solution,
        quantities: Quantities,
        pictured_step: usize,
    ) -> usize {
        let entry = Entry {
            value,
            iterations: sol.iterations,
            eta: sol.eta,
            quantities,
            pictured_step,
        };
        if let Some(i) = self.exact(value) {
            // a second solve of a stored value (after a change away and back) keeps the first
            self.entries[i].pictured_step = pictured_step;
            return i;
        }
        let index = self.entries.len();
        self.sides = sol.hats.iter().map(Vec::len).collect();
        self.states.converged(index, &[value], &sol.state);
        let hats = InterfaceState {
            steps: sol.state.steps,
            subs: sol.hats.iter().flatten().cloned().collect(),
        };
        self.hats.insert(index, &[value], &hats);
        self.entries.push(entry);
        index
    }

    /// Configuration `index` as a converged solution (its s and ŝ back from f32): enough to
    /// draw any step, probe a node or record it.
    pub fn solution(&self, index: usize) -> Option<Solution> {
        let e = self.entries.get(index)?;
        let state = self.states.store().state(index)?;
        let flat = self.hats.state(index)?.subs;
        let mut it = flat.into_iter();
        let hats: Vec<Vec<TraceHistory>> = self
            .sides
            .iter()
            .map(|&n| it.by_ref().take(n).collect())
            .collect();
        Some(Solution {
            state,
            hats,
            iterations: e.iterations,
            eta: e.eta,
            eta_smooth: None,
            eta_history: Vec::new(),
            converged: true,
            cancelled: false,
            end: None,
        })
    }

    /// The stored configurations, in the order they were stored.
    pub fn entries(&self) -> &[Entry] {
        &self.entries
    }

    /// Notes that the UI's picture of configuration `index` is now at `step`.
    pub fn pictured(&mut self, index: usize, step: usize) {
        if let Some(e) = self.entries.get_mut(index) {
            e.pictured_step = step;
        }
    }

    /// Bytes of the stored states (s and ŝ, f32).
    pub fn bytes(&self) -> usize {
        self.states.bytes() + self.hats.bytes()
    }

    /// Gives up a grid value (its solve failed or did not converge).
    pub fn give_up(&mut self, value: f64) {
        self.given_up.push(value);
    }

    /// The grid value to solve next, in the study engine's order ([`nearest_open`]): the
    /// unstored one nearest `current` (ties: the lower), never one given up or `busy` (being
    /// solved); None once the configurations being solved and one more would pass
    /// [`MEMORY_BUDGET`].
    pub fn next_value(&self, current: f64, busy: &[f64]) -> Option<f64> {
        let n = self.entries.len();
        if n > 0 && self.bytes() / n * (n + 1 + busy.len()) > MEMORY_BUDGET {
            return None;
        }
        let near = |v: f64, among: &[f64]| among.iter().any(|g| (g - v).abs() < SAME);
        let open = |v: f64| self.exact(v).is_none() && !near(v, &self.given_up) && !near(v, busy);
        nearest_open(&grid(), open, current)
    }

    /// The stored configuration nearest `current` whose picture is not at `step`.
    pub fn next_picture(&self, current: f64, step: usize) -> Option<usize> {
        self.entries
            .iter()
            .enumerate()
            .filter(|(_, e)| e.pictured_step != step)
            .min_by(|a, b| {
                (a.1.value - current)
                    .abs()
                    .total_cmp(&(b.1.value - current).abs())
            })
            .map(|(i, _)| i)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_covers_the_slider_and_the_next_value_is_the_nearest_unstored() {
        let g = grid();
        assert_eq!(g.len(), 21);
        assert!((g[20] - 1.0).abs() < 1e-12 && g[0] == 0.0);
        let mut lib = Library::default();
        assert!((lib.next_value(0.31, &[]).expect("a value") - 0.3).abs() < 1e-12);
        assert!((lib.next_value(2.0, &[]).expect("a value") - 1.0).abs() < 1e-12);
        lib.give_up(0.3);
        assert!((lib.next_value(0.31, &[]).expect("a value") - 0.35).abs() < 1e-12);
        // values being solved are skipped like stored ones
        assert!((lib.next_value(0.31, &[0.35]).expect("a value") - 0.25).abs() < 1e-12);
        assert!((lib.next_value(0.31, &[0.35, 0.25]).expect("a value") - 0.4).abs() < 1e-12);
    }
}
