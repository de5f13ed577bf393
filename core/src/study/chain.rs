//! One chain of a study (METHOD §8): the configurations a solver visits one after the other,
//! what it has converged to and where its next configuration starts. A [`Chain`] keeps the
//! converged states its [`Predictor`] reads, the last two in full precision for the predictors
//! that follow the chain (previous, linear, smooth), the [`StateStore`] (f32) for the others,
//! and gives the start of the next configuration ([`Predictor::start`]). A study's chains
//! (`runner`), a sweep (one chain in the order of its values, resumed by seeding it with the
//! stored states of its finished values) and the explorer's slider and background study (one
//! chain of the friction coefficient, bracketed) all keep their states here.

use crate::solver::Solver;
use crate::state::InterfaceState;
use crate::study::{Predictor, Start, StateStore};

/// What a chain has converged to, and its predictor.
#[derive(Debug, Clone, Default)]
pub struct Chain {
    predictor: Predictor,
    /// The last two converged (first coordinate, state) pairs, oldest first: kept for the
    /// predictors that follow the chain.
    recent: Vec<(f64, InterfaceState)>,
    store: StateStore,
}

impl Chain {
    /// An empty chain whose configurations start as `predictor` says.
    pub fn new(predictor: Predictor) -> Self {
        Self {
            predictor,
            ..Self::default()
        }
    }

    /// Keeps the converged state of configuration `index` at scaled point `point` (in the
    /// order the chain solves them; a resumed chain is seeded with its finished ones).
    pub fn converged(&mut self, index: usize, point: &[f64], state: &InterfaceState) {
        if self.predictor.follows_the_chain() {
            self.recent
                .push((point.first().copied().unwrap_or(0.0), state.clone()));
            if self.recent.len() > 2 {
                self.recent.remove(0);
            }
        } else {
            self.store.insert(index, point, state);
        }
    }

    /// The start of the configuration at scaled point `point`, whose parameters `solver`
    /// holds (cold while nothing has converged).
    pub fn start(&self, point: &[f64], solver: &Solver) -> Start {
        let recent: Vec<(f64, &InterfaceState)> =
            self.recent.iter().map(|(v, s)| (*v, s)).collect();
        self.predictor.start(&recent, &self.store, point, solver)
    }

    /// The converged states kept for the predictors that read the store.
    pub fn store(&self) -> &StateStore {
        &self.store
    }

    /// Bytes of the kept states.
    pub fn bytes(&self) -> usize {
        self.store.bytes()
            + self
                .recent
                .iter()
                .map(|(_, s)| s.size() * std::mem::size_of::<f64>())
                .sum::<usize>()
    }
}
