//! When the explorer's solver side works: [`Next`], what it does after one unit of work (work
//! again at once, after a pause, or wait for a message), and [`serve`], the loop that runs a
//! solver side on a thread: it blocks for a message when idle (until background work is due),
//! otherwise takes the messages that came between two units of work, so a newer parameter
//! change cancels the running solve within one iteration; it ends when the UI side hangs up.
//! The desktop's solver thread and the byte link's thread run this loop; the browser's Web
//! Worker schedules the same [`Next`] on its event loop.

use std::sync::mpsc::{Receiver, RecvTimeoutError, TryRecvError};
use std::time::Duration;

/// What the solver side does after a unit of work.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Next {
    /// Work again at once (after taking the messages that came meanwhile).
    Now,
    /// Work again after this pause (the background study gives back as much time as its
    /// iteration took, so that the drawing of frames keeps the cores half the time), or sooner
    /// when a message comes.
    After(Duration),
    /// Nothing to do until a message comes, or until this wait has passed (background work
    /// that waits for the user to be idle).
    Wait(Option<Duration>),
}

/// Runs a solver side held in `state` on the messages of `from_ui`: `receive` takes one,
/// `work` does one unit of work; `next` is what to do first.
pub(crate) fn serve<M, S>(
    from_ui: &Receiver<M>,
    state: &mut S,
    mut next: Next,
    receive: impl Fn(&mut S, M),
    work: impl Fn(&mut S) -> Next,
) {
    loop {
        let message = match next {
            Next::Now => match from_ui.try_recv() {
                Ok(m) => Some(m),
                Err(TryRecvError::Empty) => None,
                Err(TryRecvError::Disconnected) => return,
            },
            Next::After(wait) | Next::Wait(Some(wait)) => match from_ui.recv_timeout(wait) {
                Ok(m) => Some(m),
                Err(RecvTimeoutError::Timeout) => None,
                Err(RecvTimeoutError::Disconnected) => return,
            },
            Next::Wait(None) => match from_ui.recv() {
                Ok(m) => Some(m),
                Err(_) => return,
            },
        };
        if let Some(m) = message {
            receive(state, m);
            loop {
                match from_ui.try_recv() {
                    Ok(m) => receive(state, m),
                    Err(TryRecvError::Empty) => break,
                    Err(TryRecvError::Disconnected) => return,
                }
            }
        }
        next = work(state);
    }
}
