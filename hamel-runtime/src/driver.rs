//! What the integrator reports to during one simulation: the samples go to the recorder;
//! accepted steps, when anything watches them, to the events, the singular-crossing watch and
//! the progress callback, which may end the run.

use std::ops::ControlFlow;
use std::time::{Duration, Instant};

use crate::crossing::CrossingWatch;
use crate::error::Error;
use crate::events::Watch;
use crate::integrate::{Control, Observer, Stats, StepView};
use crate::recorder::Recorder;
use crate::simulation::{PROGRESS_INTERVAL, Progress};
use crate::system::HamelSystem;
use crate::trajectory::Summary;

/// A progress callback: `ControlFlow::Break(())` cancels the run.
pub(crate) type ProgressFn<'s> = Box<dyn Fn(&Progress) -> ControlFlow<()> + 's>;

/// How often, about, a run with a progress callback reads the clock: a read costs about as
/// much as a step of a small model or a recorded sample, so it is not made at each of them
/// but after as many as take about this long, which keeps a cancel's delay far below the
/// progress interval.
const CLOCK_PERIOD: Duration = Duration::from_millis(1);

/// The most steps and samples between two reads of the clock (a step may hold billions of
/// samples, each taking nanoseconds).
const MAX_BETWEEN_READS: u32 = 4096;

/// When to read the clock: after `between` steps and samples, a number adapted at each read so
/// that reads come about every [`CLOCK_PERIOD`].
struct Clock {
    since_read: u32,
    between: u32,
    last_read: Instant,
}

impl Clock {
    fn new() -> Self {
        Clock {
            since_read: 0,
            between: 1,
            last_read: Instant::now(),
        }
    }

    /// One more step or sample: whether to read the clock now.
    #[inline]
    fn tick(&mut self) -> bool {
        self.since_read += 1;
        self.since_read >= self.between
    }

    /// The clock, read now; the number of steps and samples before the next read adapted to
    /// how long these took.
    fn read(&mut self) -> Instant {
        let now = Instant::now();
        let took = now.duration_since(self.last_read);
        if took < CLOCK_PERIOD / 2 {
            self.between = (self.between * 2).min(MAX_BETWEEN_READS);
        } else if took > CLOCK_PERIOD * 2 {
            self.between = (self.between / 2).max(1);
        }
        self.since_read = 0;
        self.last_read = now;
        now
    }
}

/// The observer of one run: the recorder, the events, the crossing watch and the progress.
pub(crate) struct Driver<'a, 's, 'e, S: HamelSystem, F> {
    system: &'s S,
    recorder: Recorder<'a, 's, S, F>,
    watch: Watch<'e, 's, S>,
    watching_events: bool,
    crossings: Option<CrossingWatch>,
    progress: Option<&'a ProgressFn<'s>>,
    started: Instant,
    /// When the progress callback was last called; `None` before the first call, which the
    /// first sample makes (so that a run cancelled at once does not run).
    reported: Option<Instant>,
    /// When to read the clock (runs with a progress callback only).
    clock: Clock,
    span: (f64, f64),
    steps: usize,
}

impl<'a, 's, 'e, S, F> Driver<'a, 's, 'e, S, F>
where
    S: HamelSystem,
    F: FnMut(f64, &S::State) -> S::Inputs,
{
    pub fn new(
        system: &'s S,
        recorder: Recorder<'a, 's, S, F>,
        (watch, watching_events): (Watch<'e, 's, S>, bool),
        crossings: Option<CrossingWatch>,
        progress: Option<&'a ProgressFn<'s>>,
        span: (f64, f64),
    ) -> Self {
        Driver {
            system,
            recorder,
            watch,
            watching_events,
            crossings,
            progress,
            started: Instant::now(),
            reported: None,
            clock: Clock::new(),
            span,
            steps: 0,
        }
    }

    /// Whether the progress callback is due after one more step or sample: never called
    /// yet, or not for a while (the clock is read only every so many steps and samples).
    /// Called at every step and sample of a watched run, so its common answer — not due, the
    /// clock not to be read — is inlined; the rest is out of line.
    #[inline]
    fn progress_due(&mut self) -> bool {
        if self.progress.is_none() {
            return false;
        }
        match self.reported {
            None => true,
            Some(last) => self.clock.tick() && self.interval_passed(last),
        }
    }

    /// Whether the progress interval has passed since `last`, by the clock read now.
    #[inline(never)]
    fn interval_passed(&mut self, last: Instant) -> bool {
        self.clock.read().duration_since(last) >= PROGRESS_INTERVAL
    }

    /// Calls the progress callback at time t; whether it asked to stop.
    #[inline(never)]
    fn report_progress(&mut self, t: f64) -> bool {
        let Some(progress) = self.progress else {
            return false;
        };
        self.reported = Some(Instant::now());
        let p = Progress {
            t,
            t0: self.span.0,
            t_end: self.span.1,
            steps: self.steps,
            elapsed: self.started.elapsed(),
        };
        progress(&p).is_break()
    }

    /// Whether the run is to be cancelled at t: the progress callback, if due, asked to stop
    /// (the run is then recorded as cancelled at t).
    #[inline]
    fn cancelled_at(&mut self, t: f64) -> bool {
        let cancel = self.progress_due() && self.report_progress(t);
        if cancel {
            self.recorder.cancelled(t);
        }
        cancel
    }

    /// The summary of the integration that ended with `stats`: the progress callback called
    /// a last time, the crossings found before the end.
    pub fn finish(mut self, stats: Stats) -> Result<Summary, Error> {
        let reached = self.span.1.min(stats.stopped.unwrap_or(f64::INFINITY));
        // The run is over: a cancel now changes nothing.
        let _ = self.report_progress(reached);
        let mut summary = self.recorder.finish(stats)?;
        if let Some(mut watch) = self.crossings {
            // A step cut short by a terminal event or a cancel was checked to its end.
            let end = stats.stopped.unwrap_or(f64::INFINITY);
            watch.crossings.retain(|c| c.t <= end);
            summary.singular_crossings = watch.crossings;
        }
        Ok(summary)
    }
}

/// The driver as an observer of the integrator's states (the plain state, or the state and
/// the work), which `split` separates.
pub(crate) struct States<'d, D, G> {
    pub driver: &'d mut D,
    pub split: G,
}

impl<'a, 's, 'e, S, F, V, G> Observer<V> for States<'_, Driver<'a, 's, 'e, S, F>, G>
where
    S: HamelSystem,
    F: FnMut(f64, &S::State) -> S::Inputs,
    V: crate::vector::Vector,
    G: Fn(&V) -> (S::State, f64),
{
    fn sample(&mut self, t: f64, v: &V) -> Result<Control, Error> {
        let (x, work) = (self.split)(v);
        let driver = &mut *self.driver;
        driver.recorder.record(t, &x, work)?;
        // Progress is due at the first sample, and looked at every so many samples: a step
        // may hold billions of them.
        if driver.cancelled_at(t) {
            return Ok(Control::Stop(t));
        }
        Ok(Control::Continue)
    }

    fn watches_steps(&self) -> bool {
        self.driver.watching_events
            || self.driver.progress.is_some()
            || self.driver.crossings.is_some()
    }

    fn reads_inside_steps(&self) -> bool {
        self.driver.watching_events || self.driver.crossings.is_some()
    }

    fn step(&mut self, view: &StepView<'_, V>) -> Result<Control, Error> {
        self.driver.steps += 1;
        // A run watched by its progress callback alone (as every run from Python is) comes
        // here at each step: the events and crossings are out of line, so that this stays a
        // few instructions.
        if self.driver.watching_events || self.driver.crossings.is_some() {
            if let Control::Stop(t) = self.watch_step(view)? {
                return Ok(Control::Stop(t));
            }
        }
        if self.driver.cancelled_at(view.t1) {
            return Ok(Control::Stop(view.t1));
        }
        Ok(Control::Continue)
    }
}

impl<'a, 's, 'e, S, F, G> States<'_, Driver<'a, 's, 'e, S, F>, G>
where
    S: HamelSystem,
    F: FnMut(f64, &S::State) -> S::Inputs,
{
    /// The crossings and events within an accepted step; a terminal event stops the run.
    #[inline(never)]
    fn watch_step<V>(&mut self, view: &StepView<'_, V>) -> Result<Control, Error>
    where
        V: crate::vector::Vector,
        G: Fn(&V) -> (S::State, f64),
    {
        let driver = &mut *self.driver;
        if let Some(crossings) = &mut driver.crossings {
            let split = &self.split;
            crossings.step(driver.system, view, |v| split(v).0);
        }
        if driver.watching_events {
            let split = &self.split;
            for event in driver.watch.step(view, |v| split(v).0)? {
                driver.recorder.event(&event)?;
                if event.terminal {
                    return Ok(Control::Stop(event.t));
                }
            }
        }
        Ok(Control::Continue)
    }
}
