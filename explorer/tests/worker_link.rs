//! The browser's worker link as bytes: every event the solver side sends comes back equal
//! from its encoding (fields, contact histories, reports, stored pictures), damaged bytes
//! become a clear error on either side instead of a panic, a scene the solver side cannot
//! open is reported by name, a field message is its floats plus a few bytes, and a start sent
//! again (a page starts its worker early) keeps the open scene. The solves over the link are checked in `resolve.rs`.

use lopin_explorer::protocol::Event;
use lopin_explorer::remote::{thread_connector, Host, Port};
use lopin_explorer::wire::{decode_event, encode_event, Start};
use lopin_explorer::worker::Worker;
use lopin_explorer::Connector;
use std::sync::Arc;
use std::time::Duration;

fn linked(scene: &str) -> Worker {
    let start = Start {
        scene: scene.into(),
        two_scale: None,
    };
    Worker::spawn_remote(start, Arc::new(|_| {}), &thread_connector()).expect("worker link")
}

/// Every event of a cold solve and a warm re-solve over the link, in arrival order, and each
/// one's encoding decoded again.
#[test]
fn every_event_of_a_solve_survives_its_encoding() {
    let mut worker = linked("two-blocks");
    let problem = lopin_core::scene::open(
        "two-blocks",
        &lopin_core::scene::Overrides::for_task(lopin_core::window_choice::Task::Interactive),
    )
    .expect("two-blocks opens");
    let mut params = lopin_explorer::params::Params::of(&problem.problem, &problem.settings);
    let mut seen = [0usize; 4];
    for f in [None, Some(0.2)] {
        if f.is_some() {
            params.friction = f;
        }
        let g = worker.solve(params.clone());
        loop {
            let e = worker
                .wait(Duration::from_secs(120))
                .expect("an event within 120 s");
            let bytes = encode_event(&e);
            let back = decode_event(&bytes).expect("decodes");
            match (&e, &back) {
                (Event::Progress { eta, .. }, Event::Progress { eta: b, .. }) => {
                    assert_eq!(eta.to_bits(), b.to_bits());
                    seen[0] += 1;
                }
                (Event::Fields(a), Event::Fields(b)) => {
                    assert_eq!(a, b);
                    let floats: usize = a
                        .subs
                        .iter()
                        .map(|s| s.u.len() + s.v.len() + s.von_mises.len())
                        .sum();
                    assert!(
                        bytes.len() >= 8 * floats && bytes.len() < 8 * floats + 64,
                        "{} bytes for {floats} floats",
                        bytes.len()
                    );
                    seen[1] += 1;
                }
                (Event::Contact { histories: a, .. }, Event::Contact { histories: b, .. }) => {
                    assert_eq!(a, b);
                    assert!(!a.is_empty() && !a[0].pressure.is_empty());
                    seen[2] += 1;
                }
                (Event::Finished(a), Event::Finished(b)) => {
                    assert_eq!(a, b);
                    seen[3] += 1;
                    if a.generation == g {
                        assert!(a.converged && a.params.friction == params.friction, "{a:?}");
                        break;
                    }
                }
                (Event::Stored(a), Event::Stored(b)) => assert_eq!(a, b),
                (Event::Error(e), _) => panic!("solver error: {e}"),
                _ => {}
            }
        }
    }
    assert!(
        seen.iter().all(|&n| n > 0),
        "progress, fields, contact, reports: {seen:?}"
    );
}

#[test]
fn damaged_bytes_are_an_error_on_either_side() {
    // the UI side: a cut field message
    let e = Event::Error("x".repeat(40));
    let bytes = encode_event(&e);
    let err = decode_event(&bytes[..10]).expect_err("a cut message is refused");
    assert!(
        err.to_string().contains("unreadable message") && err.to_string().contains("10 bytes"),
        "{err}"
    );
    // the solver side: bytes that are no message
    let posted = Arc::new(std::sync::Mutex::new(Vec::new()));
    let sink = posted.clone();
    let mut host = Host::new(move |b| sink.lock().expect("lock").push(b));
    host.receive(&[250, 251, 252, 253]);
    let out = posted.lock().expect("lock");
    assert_eq!(out.len(), 1);
    match decode_event(&out[0]).expect("an event") {
        Event::Error(m) => assert!(m.contains("unreadable message"), "{m}"),
        other => panic!("expected an error, got {other:?}"),
    }
}

#[test]
fn a_scene_the_solver_side_cannot_open_is_named() {
    let mut worker = linked("no-such-scene");
    match worker.wait(Duration::from_secs(30)) {
        Some(Event::Error(m)) => assert!(m.contains("no-such-scene"), "{m}"),
        other => panic!("expected an error naming the scene, got {other:?}"),
    }
}

/// A port that sends the solver side's first message (its start) again before every later
/// one, as a page that started its worker early and then its explorer does.
struct RepeatStart {
    inner: Box<dyn Port>,
    start: Option<Vec<u8>>,
}

impl Port for RepeatStart {
    fn post(&mut self, bytes: Vec<u8>) {
        match &self.start {
            None => self.start = Some(bytes.clone()),
            Some(start) => self.inner.post(start.clone()),
        }
        self.inner.post(bytes);
    }
}

/// The same start again keeps the open scene and its solver state: the next solve starts warm.
#[test]
fn a_repeated_start_keeps_the_open_scene() {
    let inner = thread_connector();
    let connector = Connector::new(move |inbox| {
        Ok(Box::new(RepeatStart {
            inner: inner.connect(inbox)?,
            start: None,
        }) as Box<dyn Port>)
    });
    let start = Start {
        scene: "two-blocks".into(),
        two_scale: None,
    };
    let mut worker =
        Worker::spawn_remote(start, Arc::new(|_| {}), &connector).expect("worker link");
    let opened = lopin_core::scene::open(
        "two-blocks",
        &lopin_core::scene::Overrides::for_task(lopin_core::window_choice::Task::Interactive),
    )
    .expect("two-blocks opens");
    let mut params = lopin_explorer::params::Params::of(&opened.problem, &opened.settings);
    let mut reports = Vec::new();
    for f in [None, Some(0.2)] {
        if f.is_some() {
            params.friction = f;
        }
        let g = worker.solve(params.clone());
        loop {
            match worker.wait(Duration::from_secs(120)) {
                Some(Event::Finished(r)) if r.generation == g => {
                    reports.push(r);
                    break;
                }
                Some(Event::Error(e)) => panic!("solver error: {e}"),
                Some(_) => {}
                None => panic!("no report within 120 s"),
            }
        }
    }
    assert!(reports[0].converged && !reports[0].warm, "{:?}", reports[0]);
    assert!(
        reports[1].converged && reports[1].warm && reports[1].start == Some(0.3),
        "{:?}",
        reports[1]
    );
}
