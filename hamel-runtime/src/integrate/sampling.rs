//! Delivering an integration's samples to its observer: which sample time comes next, the
//! samples an accepted step covers, and the last sample where an observer stops the run.
//! Every method reports the same way; only how it evaluates the solution inside a step (its
//! continuous extension) differs, and that is passed in.

use super::Ode;
use super::observer::{Control, Observer, SampleTimes};
use crate::error::Error;
use crate::vector::Vector;

/// The bookkeeping of sample times for a method whose steps do not land on them: which come
/// next, and reporting those an accepted step covers.
pub(super) struct Samples<'a, T: ?Sized, V> {
    pub times: &'a T,
    pub next: usize,
    pub observer: &'a mut dyn Observer<V>,
}

impl<T: SampleTimes + ?Sized, V: Vector> Samples<'_, T, V> {
    /// The sample time `next` points at, if any is left.
    pub fn upcoming(&self) -> Option<f64> {
        (self.next < self.times.count()).then(|| self.times.time(self.next))
    }

    /// Reports the samples at the start t0, where the state is `x0`; returns the time the
    /// observer stopped at, if it did.
    pub fn report_start(&mut self, t0: f64, x0: &V) -> Result<Option<f64>, Error> {
        while let Some(s) = self.upcoming().filter(|s| *s == t0) {
            let control = self.observer.sample(s, x0)?;
            self.next += 1;
            if let Control::Stop(_) = control {
                return Ok(Some(s));
            }
        }
        Ok(None)
    }

    /// Reports the samples in the accepted step ending at t1 — up to `stop` when the observer
    /// ends the integration within the step: at t1 the step's result as projected, `y1`;
    /// inside the step the continuous extension (`extension`, evaluated only where a sample
    /// falls inside the step), projected; at a stop the extension there, projected, as the
    /// last sample. Returns the time the observer stopped at, if it did: at `stop`, or at a
    /// sample it asked to end with.
    #[inline]
    pub fn report<O: Ode<State = V>>(
        &mut self,
        ode: &mut O,
        (t1, y1): (f64, &V),
        mut extension: impl FnMut(f64) -> V,
        stop: Option<f64>,
    ) -> Result<Option<f64>, Error> {
        let end = stop.unwrap_or(t1);
        while let Some(s) = self
            .upcoming()
            .filter(|s| *s <= end && (stop.is_none() || *s < end))
        {
            let control = if s == t1 {
                self.observer.sample(s, y1)?
            } else {
                let mut value = extension(s);
                ode.project(s, &mut value)?;
                self.observer.sample(s, &value)?
            };
            self.next += 1;
            // A run cancelled while a step holds many samples ends at the sample.
            if let Control::Stop(_) = control {
                return Ok(Some(s));
            }
        }
        if let Some(ts) = stop {
            final_sample(ode, &mut *self.observer, ts, (t1, y1), extension)?;
        }
        Ok(stop)
    }
}

/// Reports the state at `ts`, where an observer stopped the run within the step ending at
/// (t1, x1), as the last sample: x1 at t1, else the step's extension at ts, projected.
pub(super) fn final_sample<O: Ode>(
    ode: &mut O,
    observer: &mut dyn Observer<O::State>,
    ts: f64,
    (t1, x1): (f64, &O::State),
    extension: impl FnOnce(f64) -> O::State,
) -> Result<(), Error> {
    let mut value = if ts == t1 { *x1 } else { extension(ts) };
    ode.project(ts, &mut value)?;
    // The run ends here whatever the observer answers.
    let _ = observer.sample(ts, &value)?;
    Ok(())
}
