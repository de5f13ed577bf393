//! The recorder of a `lopin` built without the `rerun` feature: same interface, and opening
//! it says how to get recordings.

use super::target::Target;
use super::StepsSummary;
use lopin_core::counters::IterationRecord;
use lopin_core::post::SubFields;
use lopin_core::{Solution, Solver};
use std::time::Duration;

/// Never opened: see [`Recorder::open`].
pub enum Recorder {}

impl Recorder {
    /// Always an error: this build has no Rerun SDK.
    pub fn open(target: &Target, _name: &str) -> anyhow::Result<Recorder> {
        anyhow::bail!(
            "cannot record to {}: this lopin was built without the `rerun` feature (build with `cargo build --release -p lopin --features rerun`)",
            target.describe()
        )
    }

    pub fn target(&self) -> &Target {
        match *self {}
    }

    pub fn describe(&self, _markdown: &str) -> anyhow::Result<()> {
        match *self {}
    }

    pub fn iteration(&mut self, _r: &IterationRecord) -> anyhow::Result<()> {
        match *self {}
    }

    pub fn eta(&mut self, _eta: f64, _stage_s: Option<(f64, f64)>) -> anyhow::Result<()> {
        match *self {}
    }

    pub fn solution(
        &mut self,
        _solver: &Solver,
        _sol: &Solution,
        _history: &[Vec<SubFields>],
        _context: &[(&'static str, i64)],
        _deform: Option<f64>,
    ) -> anyhow::Result<StepsSummary> {
        match *self {}
    }

    pub fn parameter(&self, _index: usize, _quantities: &[(&str, f64)]) -> anyhow::Result<()> {
        match *self {}
    }

    pub fn solve_parameters(&self, _index: i64, _values: &[(&str, f64)]) -> anyhow::Result<()> {
        match *self {}
    }

    pub fn close(self, _timeout: Duration) -> anyhow::Result<Target> {
        match self {}
    }
}
