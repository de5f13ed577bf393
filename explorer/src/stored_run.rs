//! A run opened from its stored step fields (`lopin run --out DIR --fields`), without the scene:
//! what the run folder's reader hands the explorer ([`StoredRun`]: the scene's facts, its fixed
//! geometry, the run's parameters and contact histories) and the [`FieldStore`] it reads the
//! fields of one step, or one node's history, from on demand. Nothing is factorized and no step
//! is replayed: a result at the seed's size opens in the time it takes to read its geometry, and
//! a scrub to another step reads that step alone. The fields are the converged ones of METHOD
//! §6 "at convergence", computed when the run wrote them; the parameters cannot move here.

use crate::app::SceneInfo;
use crate::fields::SubStepFields;
use crate::geometry::SceneGeometry;
use crate::params::{FrictionTargets, Params};
use lopin_core::post::ContactHistory;
use std::path::PathBuf;
use std::sync::Arc;

/// One node's history, as stored.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NodeSeries {
    /// Velocity per step m = 0..=N, m/s.
    pub velocity: Vec<[f64; 3]>,
    /// Node-averaged von Mises stress per step, Pa.
    pub von_mises: Vec<f64>,
}

/// Reads a stored run's fields on demand; every error names the file and says why.
pub trait FieldStore: Send + Sync {
    /// The fields of every substructure at step `step`.
    fn step(&self, step: usize) -> Result<Vec<SubStepFields>, String>;
    /// The history of node `node` of substructure `sub`.
    fn node(&self, sub: usize, node: usize) -> Result<NodeSeries, String>;
}

/// How the stored run's solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StoredOutcome {
    /// LATIN iterations.
    pub iterations: usize,
    /// Last η.
    pub eta: f64,
    /// Whether η < tol was reached.
    pub converged: bool,
}

/// A run folder opened from its stored fields.
pub struct StoredRun {
    /// The folder.
    pub path: PathBuf,
    /// The scene's facts.
    pub info: SceneInfo,
    /// Its fixed geometry.
    pub geometry: SceneGeometry,
    /// The run's parameter values and settings.
    pub params: Params,
    /// Each friction target's value (every contact, then each zone).
    pub friction_targets: FrictionTargets,
    /// The run's contact histories.
    pub contact: Arc<Vec<ContactHistory>>,
    /// How its solve ended.
    pub outcome: StoredOutcome,
    /// Reads its fields.
    pub store: Arc<dyn FieldStore>,
}

impl std::fmt::Debug for StoredRun {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StoredRun")
            .field("path", &self.path)
            .field("scene", &self.info.name)
            .finish()
    }
}
