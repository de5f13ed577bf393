//! The "record to Rerun" toggle's state: the factory the host program gave (none: recording is
//! unavailable), the recorder slot the solver side records converged solves into, whether
//! recording is on, where it goes and how many solves went there for this scene.

use crate::recorder::{RecorderFactory, RecorderSlot};
use crate::worker::Worker;
use std::sync::{Arc, Mutex};

/// Recording of converged solves.
pub struct Recording {
    factory: Option<RecorderFactory>,
    /// Scene name the recorders are made for.
    scene: String,
    /// Shared with the solver side, which records into it.
    slot: RecorderSlot,
    on: bool,
    target: Option<String>,
    solves: usize,
}

impl Recording {
    /// Recording off for scene `scene`; `factory` makes the recorders (None: unavailable).
    pub fn new(factory: Option<RecorderFactory>, scene: &str) -> Recording {
        Recording {
            factory,
            scene: scene.into(),
            slot: Arc::new(Mutex::new(None)),
            on: false,
            target: None,
            solves: 0,
        }
    }

    /// The slot the solver side records into.
    pub fn slot(&self) -> RecorderSlot {
        self.slot.clone()
    }

    /// Whether this build can record (a factory was given).
    pub fn available(&self) -> bool {
        self.factory.is_some()
    }

    /// Whether converged solves are recorded.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// Where they go.
    pub fn target(&self) -> Option<&str> {
        self.target.as_deref()
    }

    /// How many solves were recorded for this scene.
    pub fn solves(&self) -> usize {
        self.solves
    }

    /// Switches recording on (a recorder is made for this scene and `worker` is asked to
    /// record the newest converged solution at once, then every later one) or off (the
    /// recording is closed). The message says why it could not be switched on.
    pub fn set(&mut self, on: bool, worker: &mut Worker) -> Result<(), String> {
        if !on {
            self.stop();
            return Ok(());
        }
        let Some(factory) = &self.factory else {
            return Err("recording is not available in this build".into());
        };
        match factory.make(&self.scene) {
            Ok(rec) => {
                self.target = Some(rec.target());
                if let Ok(mut slot) = self.slot.lock() {
                    *slot = Some(rec);
                }
                self.on = true;
                worker.request_record();
                Ok(())
            }
            Err(e) => {
                self.on = false;
                Err(format!("cannot record: {e}"))
            }
        }
    }

    /// Closes the recording (the file is complete once this returns).
    pub fn stop(&mut self) {
        self.on = false;
        let rec = self.slot.lock().ok().and_then(|mut slot| slot.take());
        drop(rec);
    }

    /// The solver side recorded a solve to `target`.
    pub fn recorded(&mut self, target: String) {
        self.solves += 1;
        self.target = Some(target);
    }
}
