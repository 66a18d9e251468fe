//! The panics of a study's cases, summed up instead of printed one by one: each is caught
//! and becomes its row's error (`Ensemble`), but Rust's panic hook would still print every
//! one on the standard error stream (a thousand panicking cases, four thousand lines). While
//! a case runs, its thread records its panic here instead: how many, and the first few by
//! case index with where they panicked, which [`Panics::summary`] prints in a few lines.
//! Panics anywhere else (outside a case, or on a thread the case started) go to the hook
//! that was there before.

use std::cell::RefCell;
use std::panic::PanicHookInfo;
use std::sync::{Arc, Mutex, Once};

/// How many panics the summary names.
const NAMED: usize = 3;

/// A run's panicking cases.
#[derive(Default)]
pub(crate) struct Panics {
    recorded: Mutex<Recorded>,
}

#[derive(Default)]
struct Recorded {
    count: usize,
    /// The first [`NAMED`] by case index: the case, where it panicked, its message's first
    /// line.
    first: Vec<(usize, String, String)>,
}

thread_local! {
    /// The run and the case this thread is computing, if it is computing one.
    static CASE: RefCell<Option<(Arc<Panics>, usize)>> = const { RefCell::new(None) };
}

/// While it lives, a panic on this thread is recorded as case `index`'s.
pub(crate) struct InCase {
    previous: Option<(Arc<Panics>, usize)>,
}

impl InCase {
    pub(crate) fn new(panics: &Arc<Panics>, index: usize) -> InCase {
        install();
        let previous = CASE.with(|c| c.replace(Some((Arc::clone(panics), index))));
        InCase { previous }
    }
}

impl Drop for InCase {
    fn drop(&mut self) {
        let previous = self.previous.take();
        CASE.with(|c| *c.borrow_mut() = previous);
    }
}

/// Puts the recording hook in front of the one there is, once per process.
fn install() {
    static INSTALL: Once = Once::new();
    INSTALL.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !record(info) {
                previous(info);
            }
        }));
    });
}

/// Records the panic if this thread is computing a case; whether it did.
fn record(info: &PanicHookInfo) -> bool {
    let Ok(Some((panics, index))) = CASE.try_with(|c| c.borrow().clone()) else {
        return false;
    };
    let location = info
        .location()
        .map_or_else(String::new, |l| format!(" at {}:{}", l.file(), l.line()));
    let payload = info.payload();
    let message = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(a panic without a message)".into());
    let first_line = message.lines().next().unwrap_or_default().to_string();
    let more = if message.lines().nth(1).is_some() {
        " …"
    } else {
        ""
    };
    let Ok(mut recorded) = panics.recorded.lock() else {
        return false;
    };
    recorded.count += 1;
    let at = recorded.first.partition_point(|(i, _, _)| *i < index);
    if at < NAMED {
        let entry = (index, location, format!("{first_line}{more}"));
        recorded.first.insert(at, entry);
        recorded.first.truncate(NAMED);
    }
    true
}

impl Panics {
    /// How many cases panicked, and the first few: `None` if none did.
    pub(crate) fn summary(&self) -> Option<String> {
        let recorded = self.recorded.lock().ok()?;
        if recorded.count == 0 {
            return None;
        }
        let count = recorded.count;
        let mut text = if count == 1 {
            "1 case panicked (its row's `error` column has the message):".to_string()
        } else {
            format!(
                "{count} cases panicked (each row's `error` column has its message); the first \
                 {}:",
                recorded.first.len()
            )
        };
        for (index, location, message) in &recorded.first {
            text.push_str(&format!("\n  case {index} panicked{location}: {message}"));
        }
        Some(text)
    }
}
