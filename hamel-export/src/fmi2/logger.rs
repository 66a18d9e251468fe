//! Messages to the importer, through the logger callback it gave `fmi2Instantiate`.
//!
//! The callback takes a printf format and arguments. This FMU formats its messages itself
//! and passes each as the format with every `%` doubled and no arguments: an importer that
//! formats (FMPy does, in C) shows the message as written, one that prints the format as it
//! is shows it with `%%`, and none reads an argument that is not there.

use super::description::LOG_CATEGORIES;
use super::types::{ComponentEnvironment, Logger as Callback, Status};
use std::ffi::CString;

/// The logger of one instance: the importer's callback, its environment pointer, the
/// instance's name and which categories are on.
pub struct Logger {
    callback: Option<Callback>,
    environment: ComponentEnvironment,
    instance: CString,
    /// `fmi2SetDebugLogging`'s switch and categories (all of them when it named none).
    debug: bool,
    categories: Vec<bool>,
}

/// A message's category: one of [`LOG_CATEGORIES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Category {
    Events = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
}

impl Category {
    /// The category of a status.
    pub fn of(status: Status) -> Category {
        match status {
            Status::Warning => Category::Warning,
            Status::Discard => Category::Discard,
            Status::Error | Status::Fatal => Category::Error,
            Status::Ok | Status::Pending => Category::Events,
        }
    }

    fn name(self) -> &'static str {
        LOG_CATEGORIES[self as usize].0
    }
}

/// A C string from any text: interior NULs, which C cannot carry, become spaces.
pub fn c_string(text: &str) -> CString {
    CString::new(text.replace('\0', " ")).unwrap_or_default()
}

impl Logger {
    pub fn new(
        callback: Option<Callback>,
        environment: ComponentEnvironment,
        instance: &str,
        debug: bool,
    ) -> Logger {
        Logger {
            callback,
            environment,
            instance: c_string(instance),
            debug,
            categories: vec![true; LOG_CATEGORIES.len()],
        }
    }

    /// `fmi2SetDebugLogging`: debug logging on or off, for the categories named (all when
    /// none is named). An unknown category is an error that lists the known ones.
    pub fn set_debug(&mut self, on: bool, names: &[String]) -> Result<(), String> {
        let mut chosen = vec![names.is_empty(); LOG_CATEGORIES.len()];
        for name in names {
            match LOG_CATEGORIES.iter().position(|(n, _)| n == name) {
                Some(i) => chosen[i] = true,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|(n, _)| *n).collect();
                    return Err(format!(
                        "unknown log category `{name}`; the categories are {}",
                        known.join(", ")
                    ));
                }
            }
        }
        self.debug = on;
        self.categories = chosen;
        Ok(())
    }

    /// Whether a message of this status and category reaches the importer: warnings,
    /// discards and errors always (an importer must learn why a call failed), the others
    /// with debug logging on for their category.
    fn wanted(&self, status: Status, category: Category) -> bool {
        status != Status::Ok || (self.debug && self.categories[category as usize])
    }

    /// Send `message` with `status` in its category.
    pub fn log(&self, status: Status, category: Category, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        if !self.wanted(status, category) {
            return;
        }
        let text = c_string(&message.replace('%', "%%"));
        let category = c_string(category.name());
        // SAFETY: the importer's logger, called with its own environment and NUL-terminated
        // strings that live until it returns; the format has no conversion left, so no
        // variadic argument is read.
        unsafe {
            callback(
                self.environment,
                self.instance.as_ptr(),
                status,
                category.as_ptr(),
                text.as_ptr(),
            );
        }
    }
}
