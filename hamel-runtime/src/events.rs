//! Events: named functions g(t, x) of a simulation whose sign changes are located on the
//! integrator's dense output, recorded with their time and state, and — for a terminal
//! event — end the run at that time (scipy's `solve_ivp` events, DifferentialEquations.jl's
//! `ContinuousCallback`).
//!
//! After every accepted step each event function is evaluated at the step's end and compared
//! with its value at the start; a sign change in the event's direction is located by
//! Brent's method on the continuous extension, to a time tolerance relative to the step. A
//! zero at which g does not change sign (a tangency) within one step is not seen — as in
//! every such scheme; a smaller largest step makes it less likely.

use crate::error::Error;
use crate::integrate::StepView;
use crate::named::NamedValues;
use crate::roots::brent;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// A scalar function of time and state, boxed: an event function or an output column.
pub(crate) type StateFunction<'s, S> = Box<dyn Fn(f64, &<S as HamelSystem>::State) -> f64 + 's>;

/// Which sign changes of an event function count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// From negative to positive (g increases through zero).
    Rising,
    /// From positive to negative.
    Falling,
    /// Either way.
    Either,
}

/// The default time tolerance of event location, relative to the step it falls in.
pub const EVENT_TOLERANCE: f64 = 1e-12;

/// A named event function g(t, x) of the state, with the direction that counts and whether it
/// ends the run.
pub struct Event<'s, S: HamelSystem> {
    name: String,
    g: StateFunction<'s, S>,
    direction: Direction,
    terminal: bool,
}

impl<'s, S: HamelSystem> Event<'s, S> {
    /// An event of the model `system` that records every sign change of g (either way) and
    /// lets the run go on. The model fixes the state's type, so that g needs no annotation:
    /// `Event::on(&bike, "fallen", |_, x| x[WhippleBicycle::PHI].abs() - 1.0).terminal()`
    /// (`hamel::docs::running` has a runnable example).
    pub fn on(
        system: &'s S,
        name: impl Into<String>,
        g: impl Fn(f64, &S::State) -> f64 + 's,
    ) -> Self {
        let _ = system;
        Event::new(name, g)
    }

    /// An event that records every sign change of g (either way) and lets the run go on.
    /// Where the model is not otherwise fixed, g's state needs its type written
    /// (`|t, x: &[f64; 8]| ..`); [`Event::on`] takes it from the model.
    pub fn new(name: impl Into<String>, g: impl Fn(f64, &S::State) -> f64 + 's) -> Self {
        Event {
            name: name.into(),
            g: Box::new(g),
            direction: Direction::Either,
            terminal: false,
        }
    }

    /// Only sign changes from negative to positive count.
    pub fn rising(mut self) -> Self {
        self.direction = Direction::Rising;
        self
    }

    /// Only sign changes from positive to negative count.
    pub fn falling(mut self) -> Self {
        self.direction = Direction::Falling;
        self
    }

    /// The run ends at the first occurrence, at its exact time (the trajectory's last sample).
    pub fn terminal(mut self) -> Self {
        self.terminal = true;
        self
    }

    /// The event's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Whether a change of sign from `before` to `after` counts.
    fn crossed(&self, before: f64, after: f64) -> bool {
        let (rising, falling) = (before < 0.0 && after >= 0.0, before > 0.0 && after <= 0.0);
        match self.direction {
            Direction::Rising => rising,
            Direction::Falling => falling,
            Direction::Either => rising || falling,
        }
    }
}

/// An event that happened: its name, time and the state then.
#[derive(Clone, Debug, PartialEq)]
pub struct EventRecord {
    pub name: String,
    pub t: f64,
    /// The state at the event, with its names.
    pub state: NamedValues,
    /// Whether the event ended the run.
    pub terminal: bool,
}

/// The events of a run with their values at the start of the current step.
pub(crate) struct Watch<'e, 's, S: HamelSystem> {
    events: &'e [Event<'s, S>],
    previous: Vec<f64>,
    relative_tolerance: f64,
}

impl<'e, 's, S: HamelSystem> Watch<'e, 's, S> {
    /// Watching `events` from (t0, x0).
    pub fn new(
        events: &'e [Event<'s, S>],
        relative_tolerance: f64,
        t0: f64,
        x0: &S::State,
    ) -> Result<Self, Error> {
        let mut previous = Vec::with_capacity(events.len());
        for event in events {
            let g = (event.g)(t0, x0);
            check_value::<S>(&event.name, t0, g, x0)?;
            previous.push(g);
        }
        Ok(Watch {
            events,
            previous,
            relative_tolerance,
        })
    }

    /// The events of one accepted step, in time order, up to and including the first terminal
    /// one (the later ones did not happen: the run ends there). `state` gives the system's
    /// state of an integrator state (which may carry more, such as the work).
    pub fn step<V: Vector>(
        &mut self,
        view: &StepView<'_, V>,
        state: impl Fn(&V) -> S::State,
    ) -> Result<Vec<EventRecord>, Error> {
        let mut found: Vec<EventRecord> = Vec::new();
        let x1 = state(view.x1);
        let tolerance = self.relative_tolerance * (view.t1 - view.t);
        for (event, previous) in self.events.iter().zip(self.previous.iter_mut()) {
            let after = (event.g)(view.t1, &x1);
            check_value::<S>(&event.name, view.t1, after, &x1)?;
            if event.crossed(*previous, after) {
                let t = locate(event, view, &state, tolerance)?;
                let at = state(&view.dense.at(t));
                found.push(EventRecord {
                    name: event.name.clone(),
                    t,
                    state: S::named_state(&at),
                    terminal: event.terminal,
                });
            }
            *previous = after;
        }
        found.sort_by(|a, b| a.t.total_cmp(&b.t));
        if let Some(first) = found.iter().position(|e| e.terminal) {
            found.truncate(first + 1);
        }
        Ok(found)
    }
}

/// The time in the step where the event's function changes sign, by Brent's method on the
/// step's continuous extension.
fn locate<S: HamelSystem, V: Vector>(
    event: &Event<'_, S>,
    view: &StepView<'_, V>,
    state: &impl Fn(&V) -> S::State,
    tolerance: f64,
) -> Result<f64, Error> {
    let (t, t1) = (view.t, view.t1);
    let mut g = |s: f64| {
        let x = if s == t1 {
            state(view.x1)
        } else {
            state(&view.dense.at(s))
        };
        Ok((event.g)(s, &x))
    };
    // The bracket's ends are the step's; at the start the function may be exactly zero from
    // the last event, which `crossed` did not count, so the search starts just after it.
    match brent("an event function", &mut g, t, t1, tolerance) {
        Ok(root) => Ok(root),
        // A function that leaves zero at the step's start only to come back: the crossing is
        // at the start.
        Err(Error::RootNotBracketed { .. }) => Ok(t),
        Err(e) => Err(e),
    }
}

/// An event function must be finite where it is evaluated.
fn check_value<S: HamelSystem>(name: &str, t: f64, g: f64, x: &S::State) -> Result<(), Error> {
    if g.is_finite() {
        return Ok(());
    }
    Err(Error::NonFiniteEvent {
        name: name.to_string(),
        t,
        value: g,
        state: S::named_state(x),
    })
}
