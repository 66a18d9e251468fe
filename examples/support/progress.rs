//! The examples' progress bar: a simulation's progress on standard error, drawn only for a
//! run that has already taken more than a second (a short run prints nothing more) and only
//! when standard error is a terminal (indicatif hides it otherwise: in a pipe, a file, CI).

use std::cell::OnceCell;
use std::ops::ControlFlow;
use std::time::Duration;

use hamel::Progress;
use indicatif::{ProgressBar, ProgressStyle};

/// How long a run goes on before its bar appears.
const DELAY: Duration = Duration::from_secs(1);

/// The bar's resolution: a position per thousandth of the run.
const STEPS: u64 = 1000;

/// A bar for one run, created at the first progress report after [`DELAY`] and removed when
/// dropped (or by [`Bar::clear`]).
#[derive(Default)]
pub struct Bar {
    bar: OnceCell<ProgressBar>,
}

impl Bar {
    /// The callback for `Simulation::on_progress`: never cancels the run.
    pub fn update(&self, p: &Progress) -> ControlFlow<()> {
        if self.bar.get().is_none() && p.elapsed < DELAY {
            return ControlFlow::Continue(());
        }
        let bar = self.bar.get_or_init(|| {
            let bar = ProgressBar::new(STEPS);
            if let Ok(style) = ProgressStyle::with_template("{wide_bar} {percent:>3}% {msg}") {
                bar.set_style(style);
            }
            bar
        });
        let fraction = p.fraction();
        bar.set_position((fraction * STEPS as f64) as u64);
        let elapsed = p.elapsed.as_secs_f64();
        let left = if fraction > 0.0 {
            format!(
                ", about {:.0} s left",
                elapsed * (1.0 - fraction) / fraction
            )
        } else {
            String::new()
        };
        bar.set_message(format!("t = {:.3} of {} s{left}", p.t, p.t_end));
        ControlFlow::Continue(())
    }

    /// Removes the bar, if it was drawn.
    pub fn clear(&self) {
        if let Some(bar) = self.bar.get() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.clear();
    }
}
