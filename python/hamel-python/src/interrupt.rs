//! A Python error met inside a run — Ctrl-C, or an exception raised by an input or event
//! function — kept until the run returns, and raised then in place of whatever the run made of
//! it: the run is stopped at once (a cancel, or a NaN that ends it), and the Python error is
//! what the user sees.

use std::ops::ControlFlow;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::prelude::*;

/// The first Python error of a run (or of an ensemble's runs).
#[derive(Default)]
pub struct Failure {
    error: Mutex<Option<PyErr>>,
    set: AtomicBool,
}

impl Failure {
    /// Keeps `e` unless an error is kept already.
    pub fn set(&self, e: PyErr) {
        let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
        if slot.is_none() {
            *slot = Some(e);
        }
        self.set.store(true, Ordering::Relaxed);
    }

    /// Whether an error is kept: every run and case then stops.
    pub fn is_set(&self) -> bool {
        self.set.load(Ordering::Relaxed)
    }

    /// The error kept, if any.
    pub fn take(&self) -> Option<PyErr> {
        self.error.lock().unwrap_or_else(|p| p.into_inner()).take()
    }

    /// A run's progress callback: checks for Ctrl-C (Python runs its signal handlers, on the
    /// main thread) and cancels the run if a Python error is kept.
    pub fn progress(&self) -> ControlFlow<()> {
        if !self.is_set()
            && let Err(e) = Python::attach(|py| py.check_signals())
        {
            self.set(e);
        }
        if self.is_set() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}

impl Failure {
    /// A case's progress callback in an ensemble (on a worker thread, where Python's signal
    /// handlers do not run: the thread that waits for the ensemble checks for Ctrl-C).
    pub fn stop_if_set(&self) -> ControlFlow<()> {
        if self.is_set() {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    }
}
