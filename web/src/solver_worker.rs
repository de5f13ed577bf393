//! The page's solver in a Web Worker, both ends. The page's end, [`connector`], starts a module
//! worker (`lopin_worker.js`; the first one as early as the page starts, [`start_early`]),
//! sends it this very WebAssembly module (compiled once, by the page) and then the explorer's
//! messages ([`lopin_explorer::wire`]) as transferred byte buffers; the worker's answers go to
//! the explorer's [`Inbox`] (queued until the explorer has started). The worker's end,
//! [`solver_worker`], runs the explorer's [`Host`] there: iterations back to back, yielding to
//! the worker's event loop between two units of work (a `MessageChannel` hop, no timer delay)
//! so a newer slider move reaches the solver within one iteration; a timer when the background
//! study waits for the user to be idle. No shared memory: the page needs no special headers.

use lopin_explorer::remote::{Host, Inbox, Next, Port};
use lopin_explorer::wire::{self, Start};
use lopin_explorer::Connector;
use std::cell::RefCell;
use std::rc::Rc;
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

/// The worker's script, next to index.html.
const SCRIPT: &str = "./lopin_worker.js";

/// Bytes in a fresh `ArrayBuffer`, and the one-element transfer list that moves it.
fn transferable(bytes: &[u8]) -> (js_sys::ArrayBuffer, js_sys::Array) {
    let buffer = js_sys::Uint8Array::from(bytes).buffer();
    let transfer = js_sys::Array::of1(&buffer);
    (buffer, transfer)
}

/// The bytes of a message's data (an `ArrayBuffer`).
fn bytes_of(event: &web_sys::MessageEvent) -> Vec<u8> {
    js_sys::Uint8Array::new(&event.data()).to_vec()
}

/// Where the page's end sends the worker's messages: the explorer's inbox, or, before the
/// explorer has started, a queue (and the worker's failure, if it failed meanwhile).
#[derive(Default)]
struct Receiver {
    inbox: Option<Inbox>,
    queue: Vec<Vec<u8>>,
    failure: Option<String>,
}

impl Receiver {
    fn take(&mut self, bytes: Vec<u8>) {
        match &self.inbox {
            Some(inbox) => inbox.deliver(&bytes),
            None => self.queue.push(bytes),
        }
    }

    fn fail(&mut self, reason: String) {
        match &self.inbox {
            Some(inbox) => inbox.failed(&reason),
            None => self.failure = Some(reason),
        }
    }

    /// The explorer's inbox, given what came before it.
    fn attach(&mut self, inbox: Inbox) {
        for bytes in self.queue.drain(..) {
            inbox.deliver(&bytes);
        }
        if let Some(reason) = self.failure.take() {
            inbox.failed(&reason);
        }
        self.inbox = Some(inbox);
    }
}

/// A started worker and where its messages go.
struct Started {
    port: PagePort,
    receiver: Rc<RefCell<Receiver>>,
}

thread_local! {
    /// The worker [`start_early`] started, until the explorer connects to it.
    static EARLY: RefCell<Option<Started>> = const { RefCell::new(None) };
}

/// Starts a worker and sends it this module.
fn start_worker() -> Result<Started, String> {
    let options = web_sys::WorkerOptions::new();
    options.set_type(web_sys::WorkerType::Module);
    let worker = web_sys::Worker::new_with_options(SCRIPT, &options)
        .map_err(|e| format!("cannot start the solver's worker: {e:?}"))?;
    let receiver = Rc::new(RefCell::new(Receiver::default()));
    let receiving = receiver.clone();
    let on_message =
        Closure::<dyn FnMut(web_sys::MessageEvent)>::new(move |e: web_sys::MessageEvent| {
            receiving.borrow_mut().take(bytes_of(&e))
        });
    let failing = receiver.clone();
    // an error in the worker's code is an ErrorEvent; a script that cannot be loaded, a plain
    // Event
    let on_error = Closure::<dyn FnMut(web_sys::Event)>::new(move |e: web_sys::Event| {
        let reason = match e.dyn_ref::<web_sys::ErrorEvent>() {
            Some(e) => e.message(),
            None => "the script could not be loaded".to_string(),
        };
        failing.borrow_mut().fail(format!("{SCRIPT}: {reason}"))
    });
    worker.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    worker.set_onerror(Some(on_error.as_ref().unchecked_ref()));
    worker
        .post_message(&wasm_bindgen::module())
        .map_err(|e| format!("cannot send the solver its module: {e:?}"))?;
    Ok(Started {
        port: PagePort {
            worker,
            _on_message: on_message,
            _on_error: on_error,
        },
        receiver,
    })
}

/// Starts the solver's worker on `scene` while the page itself starts (its drawing context,
/// its first frame): the explorer's first connection takes it, its scene already open.
pub fn start_early(scene: &str) {
    if let Ok(mut started) = start_worker() {
        let start = Start {
            scene: scene.to_string(),
            two_scale: None,
        };
        started.port.post(wire::encode_start(&start));
        EARLY.with(|early| *early.borrow_mut() = Some(started));
    }
}

/// The page's end: a Web Worker per scene (terminated with its port); the first is the one
/// [`start_early`] started, if any.
pub fn connector() -> Connector {
    Connector::new(|inbox: Inbox| {
        let started = match EARLY.with(|early| early.borrow_mut().take()) {
            Some(s) => s,
            None => start_worker()?,
        };
        started.receiver.borrow_mut().attach(inbox);
        Ok(Box::new(started.port) as Box<dyn Port>)
    })
}

/// The page's end of the link.
struct PagePort {
    worker: web_sys::Worker,
    _on_message: Closure<dyn FnMut(web_sys::MessageEvent)>,
    _on_error: Closure<dyn FnMut(web_sys::Event)>,
}

impl Port for PagePort {
    fn post(&mut self, bytes: Vec<u8>) {
        let (buffer, transfer) = transferable(&bytes);
        let _ = self.worker.post_message_with_transfer(&buffer, &transfer);
    }
}

impl Drop for PagePort {
    fn drop(&mut self) {
        self.worker.set_onmessage(None);
        self.worker.set_onerror(None);
        self.worker.terminate();
    }
}

/// The worker's scheduler: the host, the hop that resumes work at once, and the pending timer.
struct Worker {
    host: Host,
    scope: web_sys::DedicatedWorkerGlobalScope,
    hop: web_sys::MessagePort,
    hop_posted: bool,
    timer: Option<i32>,
    resume: Option<Closure<dyn FnMut()>>,
}

/// Milliseconds of work before the worker lets its messages in.
const SLICE_MS: f64 = 8.0;

impl Worker {
    /// Work is due at once.
    fn now(&mut self) {
        self.cancel_timer();
        if !self.hop_posted {
            self.hop_posted = true;
            let _ = self.hop.post_message(&JsValue::NULL);
        }
    }

    /// Work is due after `ms` (or at once when a message comes).
    fn after(&mut self, ms: f64) {
        self.cancel_timer();
        if let Some(resume) = &self.resume {
            self.timer = self
                .scope
                .set_timeout_with_callback_and_timeout_and_arguments_0(
                    resume.as_ref().unchecked_ref(),
                    ms.ceil() as i32,
                )
                .ok();
        }
    }

    fn cancel_timer(&mut self) {
        if let Some(t) = self.timer.take() {
            self.scope.clear_timeout_with_handle(t);
        }
    }

    /// Units of work for up to [`SLICE_MS`], then the next turn booked.
    fn run(&mut self) {
        self.hop_posted = false;
        self.timer = None;
        let t0 = now_ms(&self.scope);
        let next = loop {
            let next = self.host.work();
            if next != Next::Now || now_ms(&self.scope) - t0 >= SLICE_MS {
                break next;
            }
        };
        match next {
            Next::Now => self.now(),
            Next::After(d) | Next::Wait(Some(d)) => self.after(d.as_secs_f64() * 1e3),
            Next::Wait(None) => {}
        }
    }
}

fn now_ms(scope: &web_sys::DedicatedWorkerGlobalScope) -> f64 {
    scope.performance().map_or(0.0, |p| p.now())
}

/// The worker's end, called by `lopin_worker.js` once the module is instantiated there, with
/// the messages that came meanwhile.
#[wasm_bindgen]
pub fn solver_worker(early: js_sys::Array) -> Result<(), JsValue> {
    let scope: web_sys::DedicatedWorkerGlobalScope = js_sys::global().dyn_into()?;
    let poster = scope.clone();
    let host = Host::new(move |bytes: Vec<u8>| {
        let (buffer, transfer) = transferable(&bytes);
        let _ = poster.post_message_with_transfer(&buffer, &transfer);
    });
    let channel = web_sys::MessageChannel::new()?;
    let worker = Rc::new(RefCell::new(Worker {
        host,
        scope: scope.clone(),
        hop: channel.port2(),
        hop_posted: false,
        timer: None,
        resume: None,
    }));
    let w = worker.clone();
    let resume = Closure::<dyn FnMut()>::new(move || w.borrow_mut().run());
    channel
        .port1()
        .set_onmessage(Some(resume.as_ref().unchecked_ref()));
    worker.borrow_mut().resume = Some(resume);
    let w = worker.clone();
    let on_message =
        Closure::<dyn FnMut(web_sys::MessageEvent)>::new(move |e: web_sys::MessageEvent| {
            let mut w = w.borrow_mut();
            w.host.receive(&bytes_of(&e));
            w.now();
        });
    {
        let mut w = worker.borrow_mut();
        for data in early.iter() {
            w.host.receive(&js_sys::Uint8Array::new(&data).to_vec());
        }
        w.now();
    }
    scope.set_onmessage(Some(on_message.as_ref().unchecked_ref()));
    // the worker lives as long as its page's port: its handlers are never dropped
    on_message.forget();
    Ok(())
}
