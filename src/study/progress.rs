//! A study's progress bar: on standard error, drawn only when it is a terminal (indicatif
//! hides it in a pipe, a file, a batch engine's log).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// A bar over a run's cases, or nothing.
pub(crate) struct Bar {
    bar: Option<ProgressBar>,
}

impl Bar {
    /// A bar of `total` cases if `show`.
    pub(crate) fn new(total: usize, show: bool) -> Bar {
        let bar = show.then(|| {
            let bar =
                ProgressBar::with_draw_target(Some(total as u64), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(
                "{wide_bar} {pos}/{len} cases, {elapsed} (about {eta} left)",
            ) {
                bar.set_style(style);
            }
            bar
        });
        Bar { bar }
    }

    /// `done` cases finished.
    pub(crate) fn set(&self, done: usize) {
        if let Some(bar) = &self.bar {
            bar.set_position(done as u64);
        }
    }

    /// Removes the bar.
    pub(crate) fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
