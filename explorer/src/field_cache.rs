//! The fields the screen needs, as they arrive from the worker: the converged fields of the
//! steps already seen (cleared when a newer solution arrives; the oldest dropped past
//! [`STEPS_BUDGET_BYTES`], so a large result scrubbed or played end to end holds a few steps,
//! not all), the live iterate of a running
//! solve (or the stored picture standing in for it), the fields on screen and the step
//! requested, the contact histories of the newest solution or iterate, and the probe (the picked
//! node and its history).

use crate::fields::StepFields;
use crate::protocol::ProbeHistory;
use crate::worker::Worker;
use lopin_core::post::ContactHistory;
use std::collections::HashMap;
use std::sync::Arc;

/// Most bytes of converged step fields kept: a small scene keeps every step, a result of a
/// million dofs (20 MB a step) about 25.
pub const STEPS_BUDGET_BYTES: usize = 512 << 20;

/// Bytes of one step's fields.
fn bytes_of(f: &StepFields) -> usize {
    8 * f
        .subs
        .iter()
        .map(|s| s.u.len() + s.v.len() + s.von_mises.len())
        .sum::<usize>()
}

/// Cached fields, contact histories and the probe.
#[derive(Default)]
pub struct FieldCache {
    /// Converged fields per step, all of generation `generation`.
    steps: HashMap<usize, Arc<StepFields>>,
    /// The cached steps, oldest first.
    order: std::collections::VecDeque<usize>,
    /// Bytes of the cached steps.
    bytes: usize,
    generation: u64,
    /// The newest live iterate of the running solve.
    live: Option<Arc<StepFields>>,
    /// The fields on screen.
    shown: Option<Arc<StepFields>>,
    /// The step whose converged fields were asked for and have not arrived.
    requested_step: Option<usize>,
    /// Contact histories of the newest solution or iterate.
    contact: Option<Arc<Vec<ContactHistory>>>,
    /// Picked node (substructure, node).
    probe: Option<(usize, usize)>,
    /// Its history.
    probe_history: Option<Arc<ProbeHistory>>,
}

impl FieldCache {
    /// The fields on screen, if any have arrived.
    pub fn shown(&self) -> Option<&Arc<StepFields>> {
        self.shown.as_ref()
    }

    /// Contact histories of the newest solution or iterate.
    pub fn contact(&self) -> Option<&Arc<Vec<ContactHistory>>> {
        self.contact.as_ref()
    }

    /// The picked node (substructure, node).
    pub fn probe(&self) -> Option<(usize, usize)> {
        self.probe
    }

    /// The picked node's history, once it has arrived.
    pub fn probe_history(&self) -> Option<&Arc<ProbeHistory>> {
        self.probe_history.as_ref()
    }

    /// Picks a node for the probe and asks the worker for its history.
    pub fn set_probe(&mut self, sub: usize, node: usize, worker: &mut Worker) {
        self.probe = Some((sub, node));
        self.probe_history = None;
        worker.request_probe(sub, node);
    }

    /// Puts on screen the fields of `step`: while the newest request (`newest`) is `busy`, its
    /// live iterate (or stand-in) if there is one; else the converged ones if cached (and of the
    /// newest finished solve, `done_generation`), else the live iterate while `busy`, else asks
    /// the worker for them (once).
    pub fn show_step(
        &mut self,
        step: usize,
        busy: bool,
        done_generation: u64,
        newest: u64,
        worker: &mut Worker,
    ) {
        if busy {
            if let Some(l) = self.live.as_ref().filter(|l| l.generation == newest) {
                self.shown = Some(l.clone());
                return;
            }
        }
        let exact = self
            .steps
            .get(&step)
            .filter(|_| self.generation == done_generation)
            .cloned();
        match exact {
            Some(f) => self.shown = Some(f),
            None => {
                if busy {
                    if let Some(l) = &self.live {
                        self.shown = Some(l.clone());
                    }
                } else if self.requested_step != Some(step) {
                    worker.request_fields(step);
                    self.requested_step = Some(step);
                }
            }
        }
    }

    /// Takes fields from the worker: a live iterate of the `newest` solve, or converged fields
    /// (those of an older solution are dropped).
    pub fn receive_fields(&mut self, f: Arc<StepFields>, newest: u64) {
        if f.live {
            if f.generation == newest {
                self.live = Some(f);
            }
        } else {
            if f.generation != self.generation {
                self.steps.clear();
                self.order.clear();
                self.bytes = 0;
                self.generation = f.generation;
            }
            if self.requested_step == Some(f.step) {
                self.requested_step = None;
            }
            self.bytes += bytes_of(&f);
            if let Some(old) = self.steps.insert(f.step, f.clone()) {
                self.bytes -= bytes_of(&old);
                self.order.retain(|&s| s != f.step);
            }
            self.order.push_back(f.step);
            while self.bytes > STEPS_BUDGET_BYTES && self.order.len() > 1 {
                if let Some(s) = self.order.pop_front() {
                    if let Some(old) = self.steps.remove(&s) {
                        self.bytes -= bytes_of(&old);
                    }
                }
            }
        }
    }

    /// Puts a stored configuration's picture on screen at once in place of the newest request's
    /// live iterate, until the solve sends a newer one or converges (`fields` carry the
    /// request's generation; not live when they are the requested value's own).
    pub fn show_stand_in(&mut self, fields: Arc<StepFields>, contact: Arc<Vec<ContactHistory>>) {
        self.live = Some(fields.clone());
        self.shown = Some(fields);
        self.contact = Some(contact);
    }

    /// Takes the contact histories of the newest solve.
    pub fn receive_contact(&mut self, histories: Arc<Vec<ContactHistory>>) {
        self.contact = Some(histories);
    }

    /// Takes a probe history, if it is the picked node's.
    pub fn receive_probe(&mut self, p: Arc<ProbeHistory>) {
        if Some((p.sub, p.node)) == self.probe {
            self.probe_history = Some(p);
        }
    }

    /// The newest solve ended: the live iterate is dropped, the displayed step is asked for
    /// again and the probe's history is recomputed.
    pub fn solve_finished(&mut self, worker: &mut Worker) {
        self.live = None;
        self.requested_step = None;
        if let Some((s, n)) = self.probe {
            self.probe_history = None;
            worker.request_probe(s, n);
        }
    }
}
