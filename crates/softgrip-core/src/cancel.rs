//! Stopping long work (a fit, a sweep, a diagnosis) from another thread.
//!
//! The work runs inside [`scope`] with a [`Cancel`] token; the viewer
//! keeps a clone and calls [`Cancel::cancel`] when the user stops the job
//! or opens another recording. Every settle and time-series replay looks
//! at the token once a step and ends with [`SimError::Cancelled`](crate::error::SimError::Cancelled)
//! (`crate::error::SimError`); `softgrip_lab::sweep::parallel_map` hands the
//! token to its workers and starts no new item once it is set, and the
//! fits and the diagnosis return their own "cancelled" error instead of
//! taking the failed simulations as bad points. Work outside a scope (the
//! CLI, the tests, the viewer's live solver) is never cancelled, and a
//! token never set changes nothing: results stay the same bit for bit.

use std::cell::RefCell;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// A flag shared between the work and whoever may stop it.
#[derive(Debug, Clone, Default)]
pub struct Cancel(Arc<AtomicBool>);

impl Cancel {
    /// A flag not yet raised.
    pub fn new() -> Cancel {
        Cancel::default()
    }

    /// Asks the work to stop (it stops within a simulation step).
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`Cancel::cancel`] was called.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Cancel>> = const { RefCell::new(None) };
}

/// Runs `work` with `token` as this thread's token (the previous one is
/// put back after, also on unwinding).
pub fn scope<R>(token: Option<Cancel>, work: impl FnOnce() -> R) -> R {
    struct Restore(Option<Cancel>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let previous = self.0.take();
            CURRENT.with(|c| *c.borrow_mut() = previous);
        }
    }
    let previous = CURRENT.with(|c| c.replace(token));
    let _restore = Restore(previous);
    work()
}

/// This thread's token, to hand to threads it starts.
pub fn current() -> Option<Cancel> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Whether this thread's work has been asked to stop.
pub fn requested() -> bool {
    CURRENT.with(|c| c.borrow().as_ref().is_some_and(Cancel::is_cancelled))
}

/// `Err(cancelled())` once this thread's token is set: the check the fits
/// and the diagnosis make between simulations, each with its own error.
pub fn check_scope<E>(cancelled: impl FnOnce() -> E) -> Result<(), E> {
    if requested() {
        Err(cancelled())
    } else {
        Ok(())
    }
}

/// `Err(SimError::Cancelled)` once `token` is set: for the step loops,
/// which read the thread's token once ([`current`]) and look every step.
pub fn check(token: Option<&Cancel>) -> Result<(), crate::error::SimError> {
    if token.is_some_and(Cancel::is_cancelled) {
        Err(crate::error::SimError::Cancelled)
    } else {
        Ok(())
    }
}

/// The message of a cancelled fit, sweep or diagnosis.
pub const CANCELLED: &str = "cancelled";
