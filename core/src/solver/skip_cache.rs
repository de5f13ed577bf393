//! The skip cache of the single-scale linear stage over the whole interval (METHOD §4, §11): the
//! linear stage of a substructure is a pure function of its interface inputs ŝ once k, Δt and the
//! mesh are fixed, so a substructure whose ŝ did not change (to a relative 1e-12 of its largest
//! entry) since its last solve reuses that solve's output, η sums and end state instead of
//! marching again. Late in a solve most substructures far from the active contacts are skipped.
//!
//! The check reads ŝ where it lies (the interface sides) and compares it in place with the
//! stored copy: nothing is gathered or allocated unless the substructure is solved again.

use crate::stages::indicator::IndicatorSums;
use crate::stages::linear_stage::{LinearWork, SubState};
use crate::state::TraceHistory;
use crate::substructure::Substructure;

/// Relative change below which a substructure's inputs count as unchanged.
pub const UNCHANGED: f64 = 1e-12;

/// What one substructure's last whole-interval linear stage read and wrote.
#[derive(Debug, Clone)]
struct CachedSolve {
    /// ŝ of every side of the substructure, all steps: each side's F̂ then Ŵ, in trace order.
    hat: Vec<f64>,
    /// s_new it wrote.
    out: TraceHistory,
    /// Its η sums.
    sums: IndicatorSums,
    /// The substructure's state at the last step.
    end: SubState,
}

/// The cache entry of one substructure (empty until its first whole-interval solve).
#[derive(Debug, Clone, Default)]
pub struct SkipCache(Option<CachedSolve>);

impl SkipCache {
    /// Forgets the stored solve (the next one marches).
    pub fn clear(&mut self) {
        self.0 = None;
    }

    /// If `sub`'s inputs in `hats` equal the stored ones, writes the stored output into `out`
    /// and the stored end state into `work`, and returns the stored η sums.
    pub fn replay(
        &self,
        sub: &Substructure,
        hats: &[Vec<TraceHistory>],
        work: &mut LinearWork,
        out: &mut TraceHistory,
    ) -> Option<IndicatorSums> {
        let cached = self.0.as_ref()?;
        if !unchanged(sub, hats, &cached.hat) {
            return None;
        }
        out.f.copy_from_slice(&cached.out.f);
        out.w.copy_from_slice(&cached.out.w);
        work.state.clone_from(&cached.end);
        Some(cached.sums)
    }

    /// Stores the solve that just read `hats` and wrote `out` and `work.state` (reusing the
    /// entry's buffers).
    pub fn store(
        &mut self,
        sub: &Substructure,
        hats: &[Vec<TraceHistory>],
        work: &LinearWork,
        out: &TraceHistory,
        sums: IndicatorSums,
    ) {
        let cached = self.0.get_or_insert_with(|| CachedSolve {
            hat: Vec::new(),
            out: out.clone(),
            sums,
            end: work.state.clone(),
        });
        cached.hat.clear();
        for side in inputs(sub, hats) {
            cached.hat.extend_from_slice(&side.f);
            cached.hat.extend_from_slice(&side.w);
        }
        cached.out.clone_from(out);
        cached.sums = sums;
        cached.end.clone_from(&work.state);
    }
}

/// The ŝ histories `sub`'s linear stage reads, in trace order.
fn inputs<'a>(
    sub: &'a Substructure,
    hats: &'a [Vec<TraceHistory>],
) -> impl Iterator<Item = &'a TraceHistory> + 'a {
    sub.sides.iter().map(|s| &hats[s.interface][s.side])
}

/// Whether `sub`'s inputs agree with `stored` entry by entry to [`UNCHANGED`] times their
/// largest magnitude.
fn unchanged(sub: &Substructure, hats: &[Vec<TraceHistory>], stored: &[f64]) -> bool {
    let len: usize = inputs(sub, hats).map(|h| h.f.len() + h.w.len()).sum();
    if len != stored.len() {
        return false;
    }
    let values = || inputs(sub, hats).flat_map(|h| h.f.iter().chain(&h.w));
    let scale = values().fold(0.0f64, |m, x| m.max(x.abs()));
    values()
        .zip(stored)
        .all(|(x, y)| (x - y).abs() <= UNCHANGED * scale)
}
