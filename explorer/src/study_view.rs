//! The study as the UI sees it: the friction values the background study covers, every stored
//! configuration with its quantities of interest and picture (the curve of the study panel),
//! what the background study is solving, the "pause" toggle, the quantity plotted, the stand-in
//! shown after a slider move (the nearest stored picture until the re-solve converges), the
//! configuration pinned as "A" and how it is compared with the current one (difference field,
//! or side by side), and A's picture at the displayed step, drawn.

use crate::field_cache::FieldCache;
use crate::fields::StepFields;
use crate::params::Params;
use crate::picture::Picture;
use crate::protocol::{StoredConfig, StudyControl};
use crate::study;
use crate::worker::Worker;
use lopin_core::post::ContactHistory;
use std::sync::Arc;

/// One stored configuration, as the UI keeps it.
#[derive(Debug, Clone)]
pub struct StoredPoint {
    /// Friction coefficient.
    pub value: f64,
    /// Iterations of its solve.
    pub iterations: usize,
    /// Whether the background study solved it.
    pub background: bool,
    /// Its quantities of interest, in [`lopin_core::study::Quantities::NAMES`] order.
    pub quantities: [f64; 6],
    /// Its picture at one time step.
    pub picture: Arc<Picture>,
}

/// What the view shows in place of the newest request's solution until it converges.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StandIn {
    /// The request's generation.
    pub generation: u64,
    /// The stored value whose picture is shown.
    pub value: f64,
    /// Whether it is the requested value itself (no solve needed).
    pub exact: bool,
}

/// How the pinned configuration is compared with the current one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Compare {
    /// Only the current configuration.
    Off,
    /// The current field minus A's, on a symmetric colour range.
    Difference,
    /// A's picture and the current one in two viewports, with the same camera and one colour
    /// range.
    SideBySide,
}

/// Fields and contact histories drawn from a picture.
pub type Drawn = (Arc<StepFields>, Arc<Vec<ContactHistory>>);

/// The study's UI state.
pub struct StudyView {
    grid: Vec<f64>,
    /// Stored configurations, by increasing value.
    points: Vec<StoredPoint>,
    /// The base of the stored configurations (every parameter but friction).
    base: Option<Params>,
    /// The values the background study is solving.
    running: Vec<f64>,
    /// Configurations and bytes of their states on the solver side.
    stored: usize,
    store_bytes: usize,
    /// No background solve while paused.
    pub paused: bool,
    /// The control last sent to the worker.
    sent: Option<StudyControl>,
    /// Index into `Quantities::NAMES` of the plotted quantity.
    pub quantity: usize,
    /// The stand-in on screen, if any.
    pub stand_in: Option<StandIn>,
    /// The pinned configuration "A" (its friction coefficient).
    pub pinned: Option<f64>,
    /// How A is compared with the current configuration.
    pub compare: Compare,
    /// A's picture at the displayed step, drawn (kept so the mesh is not rebuilt every frame).
    pinned_drawn: Option<(u64, usize, Drawn)>,
}

impl StudyView {
    /// The study of a session that starts with `params`.
    pub fn new(params: &Params) -> Self {
        StudyView {
            grid: Vec::new(),
            points: Vec::new(),
            base: Some(study::base(params)),
            running: Vec::new(),
            stored: 0,
            store_bytes: 0,
            paused: false,
            sent: None,
            quantity: 0,
            stand_in: None,
            pinned: None,
            compare: Compare::Off,
            pinned_drawn: None,
        }
    }

    /// The friction values the background study covers (empty: the scene has no contact).
    pub fn grid(&self) -> &[f64] {
        &self.grid
    }

    /// Stored configurations, by increasing value.
    pub fn points(&self) -> &[StoredPoint] {
        &self.points
    }

    /// The values the background study is solving.
    pub fn running(&self) -> &[f64] {
        &self.running
    }

    /// How many grid values are stored.
    pub fn grid_stored(&self) -> usize {
        self.grid
            .iter()
            .filter(|&&g| self.find(g).is_some())
            .count()
    }

    /// Whether every grid value is stored.
    pub fn complete(&self) -> bool {
        !self.grid.is_empty() && self.grid_stored() == self.grid.len()
    }

    /// Bytes kept: the solver side's states (s and ŝ, f32) and the UI's pictures (f32).
    pub fn memory(&self) -> (usize, usize) {
        let pictures = self.points.iter().map(|p| p.picture.bytes()).sum();
        (self.store_bytes, pictures)
    }

    /// Configurations stored on the solver side.
    pub fn stored(&self) -> usize {
        self.stored
    }

    fn find(&self, value: f64) -> Option<usize> {
        self.points
            .iter()
            .position(|p| (p.value - value).abs() < study::SAME)
    }

    /// The library was emptied; the study now covers `grid`.
    pub fn reset(&mut self, grid: Vec<f64>) {
        self.grid = grid;
        self.points.clear();
        self.pinned_drawn = None;
        self.pinned = None;
        self.compare = Compare::Off;
        self.stored = 0;
        self.store_bytes = 0;
    }

    /// Takes a stored configuration (or a new picture of one).
    pub fn receive(&mut self, c: &StoredConfig) {
        if c.stored > 0 {
            self.stored = c.stored;
            self.store_bytes = c.store_bytes;
        }
        let point = StoredPoint {
            value: c.value,
            iterations: c.iterations,
            background: c.background,
            quantities: c.quantities.values(),
            picture: Arc::new(c.picture.clone()),
        };
        match self.find(c.value) {
            Some(i) => {
                let keep = &self.points[i];
                self.points[i] = StoredPoint {
                    iterations: keep.iterations,
                    background: keep.background,
                    ..point
                };
            }
            None => {
                let at = self.points.partition_point(|p| p.value < c.value);
                self.points.insert(at, point);
            }
        }
    }

    /// The values the background study is solving now.
    pub fn set_running(&mut self, values: Vec<f64>) {
        self.running = values;
    }

    /// Unpins A: the current configuration alone again.
    pub fn unpin(&mut self) {
        self.pinned = None;
        self.compare = Compare::Off;
        self.pinned_drawn = None;
    }

    /// A's value when A is pinned and compared with the current configuration.
    pub fn compared(&self) -> Option<f64> {
        self.pinned.filter(|_| self.compare != Compare::Off)
    }

    /// A's value when A and the current configuration are drawn side by side.
    pub fn side_by_side(&self) -> Option<f64> {
        self.pinned.filter(|_| self.compare == Compare::SideBySide)
    }

    /// Sends the pause toggle and the compared configuration (pictured first at each step) to
    /// the worker when they changed.
    pub fn sync(&mut self, worker: &mut Worker) {
        let control = StudyControl {
            paused: self.paused,
            pinned: self.compared(),
            ..StudyControl::default()
        };
        if self.sent != Some(control) {
            worker.set_study(control);
            self.sent = Some(control);
        }
    }

    /// The stored configuration nearest `value` with a picture at `step`.
    pub fn nearest(&self, value: f64, step: usize) -> Option<&StoredPoint> {
        self.points
            .iter()
            .filter(|p| p.picture.step == step)
            .min_by(|a, b| (a.value - value).abs().total_cmp(&(b.value - value).abs()))
    }

    /// A new request (`generation`, `params`) was sent: if it moved only the friction, the
    /// nearest stored picture at `step` goes on screen at once as its stand-in. Returns whether
    /// one did.
    pub fn on_request(
        &mut self,
        generation: u64,
        params: &Params,
        step: usize,
        cache: &mut FieldCache,
    ) -> bool {
        self.stand_in = None;
        let b = study::base(params);
        if self.base.as_ref() != Some(&b) {
            let grid = std::mem::take(&mut self.grid);
            self.reset(grid);
            self.base = Some(b);
            return false;
        }
        let Some(value) = params.friction else {
            return false;
        };
        let Some(p) = self.nearest(value, step) else {
            return false;
        };
        let exact = (p.value - value).abs() < study::SAME;
        // the stored picture of the value itself is its converged picture (to f32 precision)
        let fields = Arc::new(p.picture.fields(generation, !exact));
        let contact = Arc::new(p.picture.contact());
        cache.show_stand_in(fields, contact);
        self.stand_in = Some(StandIn {
            generation,
            value: p.value,
            exact,
        });
        true
    }

    /// The curve of quantity `q` against friction: (value, quantity) by increasing value.
    pub fn curve(&self, q: usize) -> Vec<[f64; 2]> {
        self.points
            .iter()
            .filter_map(|p| Some([p.value, *p.quantities.get(q)?]))
            .collect()
    }

    /// The pinned configuration's picture at `step`, drawn; None if it has none there (yet).
    pub fn pinned_drawn(&mut self, step: usize) -> Option<Drawn> {
        let a = self.pinned?;
        let i = self.find(a)?;
        let p = &self.points[i];
        if p.picture.step != step {
            return None;
        }
        let key = (a.to_bits(), Arc::as_ptr(&p.picture) as usize);
        if let Some((bits, ptr, d)) = &self.pinned_drawn {
            if (*bits, *ptr) == key {
                return Some(d.clone());
            }
        }
        let d: Drawn = (
            Arc::new(p.picture.fields(0, false)),
            Arc::new(p.picture.contact()),
        );
        self.pinned_drawn = Some((key.0, key.1, d.clone()));
        Some(d)
    }
}
