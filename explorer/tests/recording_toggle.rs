//! The "record to Rerun" toggle, with a recorder that keeps what it is given: switching it on
//! records the converged solve on screen, each later converged solve follows with its
//! iterations and parameters, switching it off closes the recorder, and a build without a
//! recorder shows the toggle disabled.

use common::{harness, harness_with, settle};
use egui::Role;
use egui_kittest::kittest::{NodeT, Queryable};
use lopin_explorer::{Options, RecordedSolve, RecorderFactory, SolveRecorder};
use std::sync::{Arc, Mutex};

mod common;

/// What the test recorder saw of one solve.
#[derive(Debug, Clone, PartialEq)]
struct Seen {
    scene: String,
    iterations: usize,
    records: usize,
    last_eta: f64,
    friction: Option<f64>,
    warm: bool,
    converged: bool,
}

#[derive(Default)]
struct Log {
    seen: Vec<Seen>,
    opened: Vec<String>,
    closed: usize,
}

struct TestRecorder {
    scene: String,
    log: Arc<Mutex<Log>>,
}

impl SolveRecorder for TestRecorder {
    fn target(&self) -> String {
        format!("test:{}", self.scene)
    }

    fn record(&mut self, s: &RecordedSolve<'_>) -> Result<(), String> {
        let mut log = self.log.lock().map_err(|e| e.to_string())?;
        log.seen.push(Seen {
            scene: self.scene.clone(),
            iterations: s.solution.iterations,
            records: s.iterations.len(),
            last_eta: s.iterations.last().map_or(f64::NAN, |r| r.eta),
            friction: s.params.friction,
            warm: s.warm,
            converged: s.solution.converged,
        });
        Ok(())
    }
}

impl Drop for TestRecorder {
    fn drop(&mut self) {
        if let Ok(mut log) = self.log.lock() {
            log.closed += 1;
        }
    }
}

fn wait_for(h: &mut egui_kittest::Harness<'static, lopin_explorer::ExplorerApp>, n: usize) {
    let start = std::time::Instant::now();
    while h.state().recording.solves() < n {
        h.step();
        assert!(
            start.elapsed().as_secs() < 120,
            "{} solves recorded, waiting for {n}; error {:?}",
            h.state().recording.solves(),
            h.state().solve.error()
        );
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
}

#[test]
fn recording_follows_the_toggle_and_every_converged_solve() {
    let log = Arc::new(Mutex::new(Log::default()));
    let l = log.clone();
    let factory = RecorderFactory::new(move |scene| {
        l.lock()
            .map_err(|e| e.to_string())?
            .opened
            .push(scene.to_string());
        Ok(Box::new(TestRecorder {
            scene: scene.to_string(),
            log: l.clone(),
        }) as Box<dyn SolveRecorder>)
    });
    let mut h = harness_with(Options {
        reproducible: true,
        recorder: Some(factory),
        ..Options::scene("two-blocks")
    });
    settle(&mut h);
    assert!(log.lock().expect("log").seen.is_empty(), "off by default");
    // on: the solve on screen is recorded at once
    h.get_by_label("record to Rerun").click();
    h.step();
    assert!(h.state().recording.is_on());
    wait_for(&mut h, 1);
    let first = h.state().solve.reports()[0].clone();
    // a slider move: the warm re-solve follows
    let f0 = h.state().solve.params().friction.expect("contact");
    h.get_by_role_and_label(Role::Slider, "friction f")
        .set_value_accesskit(f0 + 0.05);
    settle(&mut h);
    wait_for(&mut h, 2);
    let second = h.state().solve.reports().last().expect("report").clone();
    {
        let log = log.lock().expect("log");
        assert_eq!(log.opened, vec!["two-blocks".to_string()]);
        let s = &log.seen;
        assert_eq!(s.len(), 2, "{s:?}");
        assert_eq!(
            (s[0].iterations, s[0].warm, s[0].friction),
            (first.iterations, false, Some(f0))
        );
        assert_eq!(s[1].iterations, second.iterations);
        assert!(s[1].warm && s[1].converged);
        assert!((s[1].friction.expect("f") - (f0 + 0.05)).abs() < 1e-12);
        for seen in s {
            // every iteration of the solve is handed over, the last one below tolerance
            assert_eq!(seen.records, seen.iterations);
            assert!(seen.last_eta < 1e-3, "{seen:?}");
        }
        assert_eq!(log.closed, 0);
    }
    assert!(h.state().recording.target() == Some("test:two-blocks"));
    // off: the recorder is closed and later solves are not recorded
    h.get_by_label("record to Rerun").click();
    h.step();
    assert!(!h.state().recording.is_on());
    assert_eq!(log.lock().expect("log").closed, 1);
    h.get_by_role_and_label(Role::Slider, "friction f")
        .set_value_accesskit(f0);
    settle(&mut h);
    assert_eq!(log.lock().expect("log").seen.len(), 2);
}

#[test]
fn without_a_recorder_the_toggle_is_disabled() {
    let mut h = harness("two-blocks");
    h.step();
    let toggle = h.get_by_label("record to Rerun");
    assert!(
        toggle.accesskit_node().is_disabled(),
        "no recorder in this build"
    );
    toggle.click();
    h.step();
    assert!(!h.state().recording.is_on());
}
