//! The explorer's solver side behind a byte link (the browser's Web Worker, where the solver
//! shares no memory with the page): [`Host`] runs the [`Service`] from the messages of
//! [`crate::wire`] and posts its events as bytes; the UI side's [`Inbox`] decodes them into the
//! [`crate::worker::Worker`]'s event queue, and a [`Port`] carries the UI's messages the other
//! way. What carries the bytes is the platform's ([`Connector`]): a Web Worker in the browser,
//! [`thread_connector`] (a thread and two channels) on the desktop, where it checks that the
//! link gives what the solver thread gives.

use crate::app::{load_scene, Options};
use crate::protocol::{DisplayStep, Event, Request};
use crate::schedule::serve;
pub use crate::schedule::Next;
use crate::service::Service;
use crate::wire::{self, Start, ToSolver};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// Carries the UI's messages to the solver side.
pub trait Port {
    /// Sends one message.
    fn post(&mut self, bytes: Vec<u8>);
}

/// Wakes the UI: at once, or within a while (`Some`: the progress of a running solve, drawn a
/// few times a second so that drawing does not take the cores from the solver).
pub type Wake = Arc<dyn Fn(Option<Duration>) + Send + Sync>;

/// How often the UI draws a running solve's progress (η, live fields) at most.
pub const PROGRESS_PERIOD: Duration = Duration::from_millis(250);

/// The UI side's end of the link: decodes the solver side's messages into the worker's events
/// and wakes the UI.
pub struct Inbox {
    events: Sender<Event>,
    wake: Wake,
}

impl Inbox {
    pub(crate) fn new(events: Sender<Event>, wake: Wake) -> Inbox {
        Inbox { events, wake }
    }

    /// One message of the solver side (an unreadable one becomes [`Event::Error`]).
    pub fn deliver(&self, bytes: &[u8]) {
        let event = wire::decode_event(bytes).unwrap_or_else(|e| Event::Error(e.to_string()));
        self.pass(event);
    }

    /// The solver side stopped (its script failed to load, or it crashed): the message says why.
    pub fn failed(&self, reason: &str) {
        self.pass(Event::Error(format!("the solver stopped: {reason}")));
    }

    fn pass(&self, event: Event) {
        let progress = match &event {
            Event::Progress { .. } => true,
            Event::Fields(f) => f.live,
            _ => false,
        };
        let _ = self.events.send(event);
        (self.wake)(progress.then_some(PROGRESS_PERIOD));
    }
}

/// Makes the link to a solver side: given the UI's [`Inbox`], starts the solver side and
/// returns the [`Port`] to it.
#[derive(Clone)]
pub struct Connector(Arc<Connect>);

/// What a [`Connector`] calls.
type Connect = dyn Fn(Inbox) -> Result<Box<dyn Port>, String> + Send + Sync;

impl Connector {
    /// Wraps a closure.
    pub fn new(
        connect: impl Fn(Inbox) -> Result<Box<dyn Port>, String> + Send + Sync + 'static,
    ) -> Self {
        Connector(Arc::new(connect))
    }

    /// Starts a solver side.
    pub fn connect(&self, inbox: Inbox) -> Result<Box<dyn Port>, String> {
        (self.0)(inbox)
    }
}

impl std::fmt::Debug for Connector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Connector")
    }
}

impl PartialEq for Connector {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The solver side: the service, the requests not served yet, and where its events go.
pub struct Host {
    service: Option<Service>,
    /// The scene the service holds.
    started: Option<Start>,
    queue: Vec<Request>,
    events: Receiver<Event>,
    display_step: DisplayStep,
    post: Box<dyn FnMut(Vec<u8>)>,
}

impl Host {
    /// A solver side that posts each event, encoded, with `post`; it opens its scene when the
    /// [`ToSolver::Start`] message comes.
    pub fn new(post: impl FnMut(Vec<u8>) + 'static) -> Host {
        let (_, events) = channel();
        Host {
            service: None,
            started: None,
            queue: Vec::new(),
            events,
            display_step: DisplayStep::default(),
            post: Box::new(post),
        }
    }

    /// One message from the UI side.
    pub fn receive(&mut self, bytes: &[u8]) {
        match wire::decode_to_solver(bytes) {
            Ok(ToSolver::Start(start)) => self.start(&start),
            Ok(ToSolver::Request(r)) => self.queue.push(r),
            Ok(ToSolver::DisplayStep(step)) => self.display_step.set(step),
            Err(e) => (self.post)(wire::encode_event(&Event::Error(e.to_string()))),
        }
        self.flush();
    }

    /// Opens the scene and factorizes; a failure is posted as [`Event::Error`]. The scene it
    /// holds already is not opened again (a page may send its start early, while it starts,
    /// and again when its explorer starts).
    fn start(&mut self, start: &Start) {
        if self.service.is_some() && self.started.as_ref() == Some(start) {
            return;
        }
        self.started = Some(start.clone());
        self.queue.clear();
        let options = Options {
            two_scale: start.two_scale,
            ..Options::scene(&start.scene)
        };
        let (events, erx) = channel();
        self.events = erx;
        match load_scene(&options) {
            Ok(opened) => {
                self.service = Service::start(
                    opened.problem,
                    opened.settings,
                    Arc::new(Mutex::new(None)),
                    self.display_step.clone(),
                    events,
                    Arc::new(|| {}),
                    None,
                );
                // the UI draws progress every PROGRESS_PERIOD: live fields more often are lost
                if let Some(service) = &mut self.service {
                    service.set_live_period(PROGRESS_PERIOD);
                }
            }
            Err(e) => {
                let _ = events.send(Event::Error(e.to_string()));
            }
        }
    }

    /// Does one unit of work ([`Service::tick`]) and posts the events it gave.
    pub fn work(&mut self) -> Next {
        let Some(service) = &mut self.service else {
            return Next::Wait(None);
        };
        let next = service.work(&mut self.queue);
        self.flush();
        next
    }

    fn flush(&mut self) {
        for e in self.events.try_iter() {
            (self.post)(wire::encode_event(&e));
        }
    }
}

/// The link of the browser on the desktop: the solver side runs its [`Host`] on a thread and
/// every message crosses as bytes, as it does between a page and its Web Worker.
pub fn thread_connector() -> Connector {
    Connector::new(|inbox: Inbox| {
        let (to_solver, from_ui) = channel::<Vec<u8>>();
        std::thread::Builder::new()
            .name("lopin-solver-host".into())
            .spawn(move || {
                let mut host = Host::new(move |bytes| inbox.deliver(&bytes));
                serve(
                    &from_ui,
                    &mut host,
                    Next::Wait(None),
                    |host, bytes: Vec<u8>| host.receive(&bytes),
                    Host::work,
                );
            })
            .map_err(|e| format!("cannot start the solver thread: {e}"))?;
        Ok(Box::new(to_solver) as Box<dyn Port>)
    })
}

impl Port for Sender<Vec<u8>> {
    fn post(&mut self, bytes: Vec<u8>) {
        let _ = self.send(bytes);
    }
}
