//! A Python error met inside a run — Ctrl-C, or an exception raised by an input or event
//! function — kept until the run returns, and raised then in place of whatever the run made of
//! it: the run is stopped at once (it unwinds, see [`Stopped`]), and the Python error is what
//! the user sees.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

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

    /// Checks for Ctrl-C (Python runs its signal handlers, on the main thread, when asked):
    /// a `KeyboardInterrupt` is kept.
    pub fn check_signals(&self) {
        if self.is_set() {
            return;
        }
        if let Err(e) = Python::attach(|py| py.check_signals()) {
            self.set(e);
        }
    }
}

impl Failure {
    /// A run's progress callback, `elapsed` into the run: looks for Ctrl-C (a single run, on
    /// the main thread, once it has run for [`FIRST_LOOK`]) and cancels the run if a Python
    /// error is kept.
    pub fn progress(&self, watch: Watch, elapsed: Duration) -> std::ops::ControlFlow<()> {
        if watch == Watch::Signals && elapsed >= FIRST_LOOK {
            self.check_signals();
        }
        if self.is_set() {
            std::ops::ControlFlow::Break(())
        } else {
            std::ops::ControlFlow::Continue(())
        }
    }
}

/// Who looks for Ctrl-C during a run: the run itself, on the main thread, every so many
/// evaluations of its inputs (a single run), or the thread that waits for the run's thread
/// (an ensemble's or a study's cases, which only look at the failure).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Watch {
    Signals,
    Flag,
}

/// How long a single run goes before it first looks for Ctrl-C. The runtime calls the progress
/// callback at a run's first sample and at its end as well as every 50 ms; taking the
/// interpreter's lock at those two costs a short run (the robot's 10 s, 0.6 ms) about 1 %, and
/// is not needed: a Ctrl-C before the call was raised before it, and one during a run shorter
/// than this is raised by the interpreter as soon as the call returns.
pub const FIRST_LOOK: Duration = Duration::from_millis(20);

/// Evaluations of the inputs between two looks for Ctrl-C in a single run: one look (taking
/// the interpreter's lock and asking it for signals, about a microsecond) per 1024
/// evaluations of the right-hand side costs well under 1 % of the robot's run, and comes
/// within a millisecond of computing for models whose right-hand side takes a microsecond.
pub const CHECK_EVERY: u32 = 1024;

/// The payload a run unwinds with when a Python error stops it (Ctrl-C, an exception in an
/// input function): the run's caller catches it and raises the Python error kept. Unwinding
/// stops the run at once, inside a step, and costs the run nothing until then (a cancel
/// through `Simulation::on_progress` waits for the next progress call, up to 50 ms).
pub struct Stopped;

/// Stops the run by unwinding (see [`Stopped`]), without the panic hook's message.
pub fn stop() -> ! {
    std::panic::resume_unwind(Box::new(Stopped))
}
