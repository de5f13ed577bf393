//! The explorer's worker: the UI sends it parameter changes and field, probe and record
//! requests, and receives η, live fields at the displayed step, contact histories and solve
//! reports as events, so nothing on the UI thread waits for the solver. The solver side is
//! [`crate::service::Service`]: on the desktop it runs on its own thread; in the browser (no
//! threads) [`Worker::poll`] advances it for a few milliseconds per frame, one LATIN iteration
//! at a time, so the page stays responsive while a re-solve converges (and, when the user is
//! idle, while the background study solves), or, better, [`Worker::spawn_remote`] runs it in a
//! Web Worker behind a byte link ([`crate::remote`]), where iterations run back to back
//! whatever the frame rate. The messages are those of [`crate::protocol`].

use crate::params::Params;
use crate::protocol::{DisplayStep, Event, Request, StudyControl};
use crate::recorder::RecorderSlot;
use crate::remote::{Connector, Inbox, Port, Wake};
use crate::result_folder::RowSource;
#[cfg(not(target_arch = "wasm32"))]
use crate::schedule::{serve, Next};
use crate::service::Service;
#[cfg(not(target_arch = "wasm32"))]
use crate::stored_side::StoredSide;
use crate::wire::{self, Start, ToSolver};
use lopin_core::counters::Instant;
use lopin_core::Problem;
use std::sync::mpsc::{channel, Receiver};
use std::sync::Arc;

/// The UI side of the worker: send changes, receive events.
pub struct Worker {
    events: Receiver<Event>,
    /// Events taken from the service but not handed out yet ([`Worker::wait`] in the inline mode).
    pending: std::collections::VecDeque<Event>,
    display_step: DisplayStep,
    generation: u64,
    link: Link,
}

/// How requests reach the service.
enum Link {
    /// A solver thread (desktop).
    #[cfg(not(target_arch = "wasm32"))]
    Thread(std::sync::mpsc::Sender<Request>),
    /// A solver side behind a byte link (the browser's Web Worker), with the displayed step
    /// it was last told.
    Remote { port: Box<dyn Port>, shown: usize },
    /// The service itself, advanced from [`Worker::poll`] (browser without a Web Worker).
    Inline {
        service: Option<Box<Service>>,
        queue: Vec<Request>,
        /// Budget of the next poll, ms (see [`Worker::set_frame_interval`]).
        budget_ms: f64,
        /// Time the last poll spent in the solver, ms.
        spent_ms: f64,
    },
}

/// Least milliseconds of solver work per [`Worker::poll`] when the solver runs on the UI thread
/// (the browser): about two frames at 60 Hz, and always at least one iteration.
const INLINE_BUDGET_MS: f64 = 30.0;
/// Most milliseconds per poll: the page answers input at least a few times a second.
const INLINE_BUDGET_MAX_MS: f64 = 250.0;

impl Worker {
    /// Starts the worker for a built problem; `wake` is called after each event so the UI can
    /// repaint. Converged solves go to the recorder in `recorder` whenever it holds one. On the
    /// desktop the factorizations are computed on the solver thread, so the UI never waits for
    /// them; a failure arrives as [`Event::Error`]. In the browser this is
    /// [`Worker::spawn_inline`].
    pub fn spawn(
        problem: Problem,
        settings: lopin_core::Settings,
        wake: Arc<dyn Fn() + Send + Sync>,
        recorder: RecorderSlot,
    ) -> lopin_core::Result<Worker> {
        Self::spawn_with_rows(problem, settings, wake, recorder, None)
    }

    /// [`Worker::spawn`] on an opened result folder whose rows `rows` describes (see
    /// [`Worker::show_row`]).
    pub fn spawn_with_rows(
        problem: Problem,
        settings: lopin_core::Settings,
        wake: Arc<dyn Fn() + Send + Sync>,
        recorder: RecorderSlot,
        rows: Option<RowSource>,
    ) -> lopin_core::Result<Worker> {
        #[cfg(not(target_arch = "wasm32"))]
        return Self::with_link(problem, settings, wake, recorder, rows, thread_link);
        #[cfg(target_arch = "wasm32")]
        return Self::with_link(problem, settings, wake, recorder, rows, inline_link);
    }

    /// The worker the browser uses, on any platform: no thread; the solver is advanced inside
    /// [`Worker::poll`] for up to [`INLINE_BUDGET_MS`] at a time (the factorizations are
    /// computed here, before it returns: a page has no other thread).
    pub fn spawn_inline(
        problem: Problem,
        settings: lopin_core::Settings,
        wake: Arc<dyn Fn() + Send + Sync>,
        recorder: RecorderSlot,
    ) -> lopin_core::Result<Worker> {
        Self::with_link(problem, settings, wake, recorder, None, inline_link)
    }

    /// The worker whose solver side runs behind a byte link that `connector` makes (in the
    /// browser, a Web Worker): the solver side opens `start`'s scene itself and factorizes
    /// there, so the UI never waits for it; a failure arrives as [`Event::Error`]. `wake` is
    /// called after each event, with a delay for a running solve's progress.
    pub fn spawn_remote(start: Start, wake: Wake, connector: &Connector) -> Result<Worker, String> {
        let (events, erx) = channel();
        let mut port = connector.connect(Inbox::new(events, wake))?;
        port.post(wire::encode_start(&start));
        Ok(Worker::on(
            erx,
            DisplayStep::default(),
            Link::Remote { port, shown: 0 },
        ))
    }

    /// The worker of a run opened from its stored fields: a thread that answers from the
    /// run's [`crate::stored_run::FieldStore`] ([`StoredSide`]); nothing is factorized. Not in
    /// the browser, which opens scenes only.
    pub fn spawn_stored(
        run: &crate::stored_run::StoredRun,
        wake: Arc<dyn Fn() + Send + Sync>,
    ) -> lopin_core::Result<Worker> {
        #[cfg(target_arch = "wasm32")]
        {
            let _ = (run, wake);
            Err(lopin_core::LopinError::setting(
                "folder",
                "stored results open in the desktop explorer",
            ))
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            let (events, erx) = channel();
            let display_step = DisplayStep::default();
            let side = StoredSide::new(run, display_step.clone(), events, wake);
            Ok(Worker::on(erx, display_step, stored_link(side)?))
        }
    }

    /// Whether the solver runs behind a byte link ([`Worker::spawn_remote`]).
    pub fn is_remote(&self) -> bool {
        matches!(self.link, Link::Remote { .. })
    }

    /// The worker whose service `link` starts (where it runs is the link's choice).
    fn with_link(
        problem: Problem,
        settings: lopin_core::Settings,
        wake: Arc<dyn Fn() + Send + Sync>,
        recorder: RecorderSlot,
        rows: Option<RowSource>,
        link: impl FnOnce(StartService) -> lopin_core::Result<Link>,
    ) -> lopin_core::Result<Worker> {
        settings.validate()?;
        let (events, erx) = channel();
        let display_step = DisplayStep::default();
        let shown = display_step.clone();
        let start: StartService = Box::new(move || {
            Service::start(problem, settings, recorder, shown, events, wake, rows)
        });
        Ok(Worker::on(erx, display_step, link(start)?))
    }

    /// The UI side of `link`, receiving on `events`, nothing requested yet.
    fn on(events: Receiver<Event>, display_step: DisplayStep, link: Link) -> Worker {
        Worker {
            events,
            pending: Default::default(),
            display_step,
            generation: 0,
            link,
        }
    }

    fn send(&mut self, c: Request) {
        self.tell_display_step();
        match &mut self.link {
            #[cfg(not(target_arch = "wasm32"))]
            Link::Thread(tx) => {
                let _ = tx.send(c);
            }
            Link::Remote { port, .. } => port.post(wire::encode_to_solver(&ToSolver::Request(c))),
            Link::Inline { queue, .. } => queue.push(c),
        }
    }

    /// Tells a solver side behind a byte link where the displayed step moved (the other links
    /// share it).
    fn tell_display_step(&mut self) {
        if let Link::Remote { port, shown } = &mut self.link {
            let step = self.display_step.get();
            if *shown != step {
                *shown = step;
                port.post(wire::encode_to_solver(&ToSolver::DisplayStep(step)));
            }
        }
    }

    /// Asks for a (warm) re-solve with these parameters; cancels a running one. Returns its
    /// generation.
    pub fn solve(&mut self, params: Params) -> u64 {
        self.request_solve(params, false)
    }

    /// [`Worker::solve`], held: the running solve is cancelled at once, the new one begins only
    /// after [`Worker::release`] (the UI releases it when the next frame starts, the one with
    /// the new value's first picture being drawn).
    pub fn solve_held(&mut self, params: Params) -> u64 {
        self.request_solve(params, true)
    }

    /// Lets the held solve of `generation` begin (nothing if it is not the held one).
    pub fn release(&mut self, generation: u64) {
        self.send(Request::Release { generation });
    }

    /// Shows row `row` of the opened result folder with its parameters `params` (its stored
    /// solution, or a warm solve from its stored state); cancels a running solve. Returns its
    /// generation.
    pub fn show_row(&mut self, params: Params, row: usize) -> u64 {
        self.request(params, false, Some(row))
    }

    fn request_solve(&mut self, params: Params, held: bool) -> u64 {
        self.request(params, held, None)
    }

    fn request(&mut self, params: Params, held: bool, row: Option<usize>) -> u64 {
        self.generation += 1;
        self.send(Request::Solve {
            generation: self.generation,
            params: Box::new(params),
            held,
            row,
        });
        self.generation
    }

    /// The step shown on screen (live fields are computed there).
    pub fn set_display_step(&self, step: usize) {
        self.display_step.set(step);
    }

    /// A handle on the step shown on screen, for the UI state that moves it.
    pub fn display_step(&self) -> DisplayStep {
        self.display_step.clone()
    }

    /// Asks for the fields of the latest solution at `step`.
    pub fn request_fields(&mut self, step: usize) {
        self.send(Request::Fields { step });
    }

    /// Asks for the history of one node.
    pub fn request_probe(&mut self, sub: usize, node: usize) {
        self.send(Request::Probe { sub, node });
    }

    /// Asks to record the newest converged solution (when recording is switched on).
    pub fn request_record(&mut self) {
        self.send(Request::Record);
    }

    /// Pauses or resumes the background study and sets how long the user must be idle before
    /// it runs.
    pub fn set_study(&mut self, control: StudyControl) {
        self.send(Request::Study(control));
    }

    /// Tells the inline solver how long the last frame took, s: it then gets about as much
    /// time per frame as drawing and the UI took (half the frame), between [`INLINE_BUDGET_MS`]
    /// and [`INLINE_BUDGET_MAX_MS`]. With fast drawing the page keeps its frame rate; with slow
    /// (software) drawing the solver does not wait a whole frame per iteration.
    pub fn set_frame_interval(&mut self, seconds: f64) {
        if let Link::Inline {
            budget_ms,
            spent_ms,
            ..
        } = &mut self.link
        {
            let others_ms = seconds * 1e3 - *spent_ms;
            *budget_ms = others_ms.clamp(INLINE_BUDGET_MS, INLINE_BUDGET_MAX_MS);
        }
    }

    /// Events received since the last call. When the solver runs on this thread (browser), it
    /// first advances it for its budget (at least [`INLINE_BUDGET_MS`]; see
    /// [`Worker::set_frame_interval`]).
    pub fn poll(&mut self) -> Vec<Event> {
        self.tell_display_step();
        if let Link::Inline {
            service: Some(service),
            queue,
            budget_ms,
            spent_ms,
        } = &mut self.link
        {
            let t0 = Instant::now();
            while service.tick(queue) {
                if t0.elapsed().as_secs_f64() * 1e3 >= *budget_ms {
                    break;
                }
            }
            *spent_ms = t0.elapsed().as_secs_f64() * 1e3;
        }
        let mut out: Vec<Event> = self.pending.drain(..).collect();
        out.extend(self.events.try_iter());
        out
    }

    /// Whether the solver runs on the UI thread (browser) and has work left: the UI must ask
    /// for another frame to go on. Background work that waits for the user to be idle
    /// counts (see [`Worker::idle_wait`]).
    pub fn needs_frames(&self) -> bool {
        match &self.link {
            Link::Inline {
                service: Some(service),
                queue,
                ..
            } => service.solving() || !queue.is_empty(),
            _ => false,
        }
    }

    /// When the solver runs on the UI thread (browser) and has background work waiting for
    /// the user to be idle: how long until it starts. The UI asks for a frame then.
    pub fn idle_wait(&self) -> Option<std::time::Duration> {
        match &self.link {
            Link::Inline {
                service: Some(service),
                ..
            } => service.idle_wait(),
            _ => None,
        }
    }

    /// The next event, waiting up to `timeout` for it (tests and benchmarks). In the inline
    /// mode this advances the solver itself, and gives None at once when it has nothing to do.
    pub fn wait(&mut self, timeout: std::time::Duration) -> Option<Event> {
        if matches!(self.link, Link::Inline { .. }) {
            let t0 = Instant::now();
            loop {
                if let Some(e) = self.pending.pop_front() {
                    return Some(e);
                }
                let had_work = self.needs_frames()
                    || self
                        .idle_wait()
                        .is_some_and(|d| d < timeout.saturating_sub(t0.elapsed()));
                let events = self.poll();
                self.pending.extend(events);
                if self.pending.is_empty() && (!had_work || t0.elapsed() >= timeout) {
                    return None;
                }
            }
        }
        if let Some(e) = self.pending.pop_front() {
            return Some(e);
        }
        self.events.recv_timeout(timeout).ok()
    }

    /// Generation of the newest change.
    pub fn generation(&self) -> u64 {
        self.generation
    }
}

/// Starts the service (factorizes); None when that failed (the error was sent as an event).
type StartService = Box<dyn FnOnce() -> Option<Service> + Send>;

/// The browser's link: the service advanced inside [`Worker::poll`].
fn inline_link(start: StartService) -> lopin_core::Result<Link> {
    Ok(Link::Inline {
        service: start().map(Box::new),
        queue: Vec::new(),
        budget_ms: INLINE_BUDGET_MS,
        spent_ms: 0.0,
    })
}

/// A solver thread running the service.
#[cfg(not(target_arch = "wasm32"))]
fn thread_link(start: StartService) -> lopin_core::Result<Link> {
    let (ctx, crx) = channel();
    std::thread::Builder::new()
        .name("lopin-solver".into())
        .spawn(move || {
            if let Some(service) = start() {
                let first = Next::Wait(service.idle_wait());
                let mut state = (service, Vec::new());
                serve(
                    &crx,
                    &mut state,
                    first,
                    |(_, queue), request| queue.push(request),
                    |(service, queue)| service.work(queue),
                );
            }
        })
        .map_err(|e| lopin_core::LopinError::setting("thread", format!("cannot start: {e}")))?;
    Ok(Link::Thread(ctx))
}

/// A thread answering from stored fields.
#[cfg(not(target_arch = "wasm32"))]
fn stored_link(side: StoredSide) -> lopin_core::Result<Link> {
    let (ctx, crx) = channel();
    std::thread::Builder::new()
        .name("lopin-stored".into())
        .spawn(move || {
            let mut side = side;
            serve(
                &crx,
                &mut side,
                Next::Wait(None),
                StoredSide::receive,
                |_| Next::Wait(None),
            );
        })
        .map_err(|e| lopin_core::LopinError::setting("thread", format!("cannot start: {e}")))?;
    Ok(Link::Thread(ctx))
}
