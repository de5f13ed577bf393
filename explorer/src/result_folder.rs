//! A result folder as the explorer opens it: a run (`lopin run --out`, also an MPI run's folder,
//! gathered on rank 0), a sweep or a study, read by whoever can (the desktop binary reads the
//! folder's files; the explorer knows only what this module holds): the scene rebuilt with the
//! run's settings, the table of its configurations (parameter values and quantities of interest,
//! as the folder stores them) and a loader that reads one configuration's stored state on the
//! solver side. A run's stored solution (s and ŝ) is shown as it is, without an iteration; a
//! sweep value's or a study configuration's converged interface state s is the start of a warm
//! solve of its own parameters (METHOD §8), which converges in the iterations its windows need
//! to see that nothing changed, and gives every field of every step.

use crate::app::Loaded;
use crate::params::Params;
use lopin_core::state::InterfaceState;
use lopin_core::{scene, Parameter, Problem, Solution};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What kind of folder it is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FolderKind {
    /// `lopin run --out`: one converged solution.
    Run,
    /// `lopin sweep --out`: one parameter's values along a chain.
    Sweep,
    /// `lopin study --out`: configurations of one or more parameters.
    Study,
}

impl FolderKind {
    /// Its name in the window.
    pub fn name(self) -> &'static str {
        match self {
            FolderKind::Run => "run",
            FolderKind::Sweep => "sweep",
            FolderKind::Study => "study",
        }
    }
}

/// One parameter value of a configuration, as the folder names it (`f`, `gap`, `f@upper`).
#[derive(Debug, Clone, PartialEq)]
pub struct Assigned {
    /// The parameter.
    pub parameter: Parameter,
    /// The zone it is set on (an index into the scene's zones; None: every interface).
    pub zone: Option<usize>,
    /// Its value.
    pub value: f64,
}

/// One configuration of the folder.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultRow {
    /// What the folder calls it (`run`, `value 3`, `config 12`).
    pub name: String,
    /// Its parameter values, in the table's parameter column order.
    pub assigned: Vec<Assigned>,
    /// Its quantities, in the table's quantity column order (NaN: not stored).
    pub quantities: Vec<f64>,
    /// Iterations of its solve, where stored.
    pub iterations: Option<usize>,
    /// Whether it converged.
    pub converged: bool,
}

/// The configurations of a folder, as columns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ResultTable {
    /// Names of the parameter columns.
    pub parameters: Vec<String>,
    /// Names of the quantity columns (with units).
    pub quantities: Vec<String>,
    /// One per configuration, in the folder's order.
    pub rows: Vec<ResultRow>,
}

impl ResultTable {
    /// The table of a run folder: its one row, `run`, solved in `iterations`.
    pub fn single_run(iterations: usize, converged: bool) -> ResultTable {
        ResultTable {
            parameters: Vec::new(),
            quantities: Vec::new(),
            rows: vec![ResultRow {
                name: "run".into(),
                assigned: Vec::new(),
                quantities: Vec::new(),
                iterations: Some(iterations),
                converged,
            }],
        }
    }

    /// Column `c` of row `r`: parameters first, then quantities, then iterations.
    pub fn cell(&self, r: usize, c: usize) -> f64 {
        let row = &self.rows[r];
        let np = self.parameters.len();
        let nq = self.quantities.len();
        if c < np {
            row.assigned.get(c).map_or(f64::NAN, |a| a.value)
        } else if c < np + nq {
            row.quantities.get(c - np).copied().unwrap_or(f64::NAN)
        } else {
            row.iterations.map_or(f64::NAN, |i| i as f64)
        }
    }

    /// Number of columns [`Self::cell`] knows.
    pub fn columns(&self) -> usize {
        self.parameters.len() + self.quantities.len() + 1
    }

    /// Column names, in [`Self::cell`] order.
    pub fn column_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self.parameters.clone();
        names.extend(self.quantities.iter().cloned());
        names.push("iterations".into());
        names
    }

    /// The rows ordered by column `c` (NaN last), ascending or not; ties keep the folder's
    /// order.
    pub fn sorted(&self, c: usize, ascending: bool) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.rows.len()).collect();
        order.sort_by(|&a, &b| {
            let (x, y) = (self.cell(a, c), self.cell(b, c));
            match (x.is_nan(), y.is_nan()) {
                (true, true) => std::cmp::Ordering::Equal,
                (true, false) => std::cmp::Ordering::Greater,
                (false, true) => std::cmp::Ordering::Less,
                _ if ascending => x.total_cmp(&y),
                _ => y.total_cmp(&x),
            }
        });
        order
    }
}

/// A configuration's stored state, as the loader reads it.
#[derive(Debug, Clone)]
pub enum StoredResult {
    /// A whole converged solution (s and ŝ): shown as it is.
    Solution(Box<Solution>),
    /// A converged interface state s: the start of a warm solve of its parameters.
    State(InterfaceState),
}

/// Reads configuration `row`'s stored state for `problem`, checked; the error names the file
/// and says why.
pub type StateLoader = Arc<dyn Fn(usize, &Problem) -> Result<StoredResult, String> + Send + Sync>;

/// A result folder opened: the scene rebuilt as the folder's run had it, its table and the
/// loader of its states.
pub struct OpenedFolder {
    /// The folder.
    pub path: PathBuf,
    /// What it holds.
    pub kind: FolderKind,
    /// The scene, built with the run's settings and parameter values.
    pub scene: scene::Opened,
    /// Its configurations.
    pub table: ResultTable,
    /// Reads a configuration's state.
    pub loader: StateLoader,
    /// The row shown first.
    pub first: usize,
}

impl std::fmt::Debug for OpenedFolder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("OpenedFolder")
            .field("path", &self.path)
            .field("kind", &self.kind)
            .field("rows", &self.table.rows.len())
            .finish()
    }
}

/// Opens a result folder (the desktop binary's reader); the error names the file and the reason.
#[derive(Clone)]
pub struct FolderOpener(Arc<OpenFolder>);

/// What a [`FolderOpener`] calls.
type OpenFolder = dyn Fn(&Path) -> Result<Loaded, String> + Send + Sync;

impl FolderOpener {
    /// Wraps a closure.
    pub fn new(open: impl Fn(&Path) -> Result<Loaded, String> + Send + Sync + 'static) -> Self {
        FolderOpener(Arc::new(open))
    }

    /// Opens `path`: a folder whose scene is rebuilt ([`Loaded::Folder`]) or a run with stored
    /// step fields ([`Loaded::Stored`]).
    pub fn open(&self, path: &Path) -> Result<Loaded, String> {
        (self.0)(path)
    }
}

impl std::fmt::Debug for FolderOpener {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("FolderOpener")
    }
}

impl PartialEq for FolderOpener {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The rows' parameter values and the loader, on the solver side.
#[derive(Clone)]
pub struct RowSource {
    /// Each row's parameter values.
    pub rows: Vec<Vec<Assigned>>,
    /// Reads a row's state.
    pub loader: StateLoader,
}

/// The explorer's parameters of a row: `base` (the folder's scene as built) with the row's
/// values; a zone's friction moves the friction slider's target to that zone.
pub fn row_params(base: &Params, assigned: &[Assigned]) -> Params {
    let mut p = base.clone();
    for a in assigned {
        match a.parameter {
            Parameter::Friction => {
                p.friction = Some(a.value);
                p.friction_zone = a.zone;
            }
            Parameter::Gap => p.gap = Some(a.value),
            Parameter::VelocityAmplitude => p.velocity = Some(a.value),
            Parameter::TractionAmplitude => p.traction = Some(a.value),
            Parameter::AccelerationAmplitude => p.acceleration = Some(a.value),
            Parameter::Preload => p.preload = Some(a.value),
            Parameter::PulseDuration => p.duration = Some(a.value),
        }
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(f: f64, q: f64) -> ResultRow {
        ResultRow {
            name: format!("f = {f}"),
            assigned: vec![Assigned {
                parameter: Parameter::Friction,
                zone: None,
                value: f,
            }],
            quantities: vec![q],
            iterations: Some(3),
            converged: true,
        }
    }

    #[test]
    fn rows_sort_by_any_column_with_missing_values_last() {
        let table = ResultTable {
            parameters: vec!["f".into()],
            quantities: vec!["q".into()],
            rows: vec![row(0.3, 2.0), row(0.1, f64::NAN), row(0.2, 1.0)],
        };
        assert_eq!(table.sorted(0, true), vec![1, 2, 0]);
        assert_eq!(table.sorted(0, false), vec![0, 2, 1]);
        assert_eq!(table.sorted(1, true), vec![2, 0, 1]);
        assert_eq!(table.sorted(1, false), vec![0, 2, 1]);
        assert_eq!(table.cell(2, 2), 3.0);
        assert_eq!(table.column_names(), vec!["f", "q", "iterations"]);
    }
}
