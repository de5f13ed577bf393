//! The browser's worker link as bytes: every event the solver side sends comes back equal
//! from its encoding (fields, contact histories, reports, stored pictures), damaged bytes
//! become a clear error on either side instead of a panic, a scene the solver side cannot
//! open is reported by name, and a folder's worth of events stays compact (a field message is
//! its floats plus a few bytes). The solves over the link are checked in `resolve.rs`.

use lopin_explorer::protocol::Event;
use lopin_explorer::remote::{thread_connector, Host};
use lopin_explorer::wire::{decode_event, encode_event, Start};
use lopin_explorer::worker::Worker;
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
