//! Initial states by name: [`StateBuilder`] collects coordinates, speeds or velocities, solves
//! the holonomic constraints for the dependent coordinates and checks the rest.

use crate::error::Error;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// A state of a system built from named values, from `HamelSystem::state_builder`:
///
/// ```text
/// let x0 = system.state_builder().at_time(0.5).set("x", 1.2).set("v", 1.5).build()?;
/// ```
///
/// Values not set are 0; the time is 0 unless set. The dependent coordinates
/// (`HamelSystem::DEPENDENT`) are solved from the holonomic constraints by
/// `HamelSystem::assemble`, with the values set for them (or 0) as Newton's starting point,
/// so set one only to choose the branch. Give either the speeds or, with
/// [`Self::velocities`], the generalized velocities, from which the speeds follow after the
/// constraints are checked. A mistake (an unknown name, speeds and velocities both) is kept
/// and returned by [`Self::build`], the first one if there are several.
pub struct StateBuilder<'s, S: HamelSystem> {
    system: &'s S,
    t: f64,
    q: S::Coordinates,
    speeds: S::Speeds,
    /// The first speed given, for the error when velocities are given too.
    speed_given: Option<&'static str>,
    velocities: Option<S::Coordinates>,
    mistake: Option<Error>,
}

impl<'s, S: HamelSystem> StateBuilder<'s, S> {
    /// A builder for a state of `system` at time 0 with every value 0.
    pub fn new(system: &'s S) -> Self {
        StateBuilder {
            system,
            t: 0.0,
            q: S::Coordinates::zeros(),
            speeds: S::Speeds::zeros(),
            speed_given: None,
            velocities: None,
            mistake: None,
        }
    }

    /// The time of the state (the constraints may depend on it).
    pub fn at_time(mut self, t: f64) -> Self {
        self.t = t;
        self
    }

    /// Sets the coordinate or speed called `name` (for a dependent coordinate: Newton's
    /// starting value). Any other name is the error [`Error::UnknownStateName`] from
    /// [`Self::build`].
    pub fn set(mut self, name: &str, value: f64) -> Self {
        if let Some(i) = S::COORDINATES.iter().position(|n| *n == name) {
            self.q.as_mut()[i] = value;
        } else if let Some(i) = S::SPEEDS.iter().position(|n| *n == name) {
            self.speeds.as_mut()[i] = value;
            self.speed_given.get_or_insert(S::SPEEDS[i]);
        } else if self.mistake.is_none() {
            self.mistake = Some(Error::UnknownStateName {
                name: name.to_string(),
                known: format!(
                    "coordinates ({}) and speeds ({})",
                    S::COORDINATES.join(", "),
                    S::SPEEDS.join(", ")
                ),
            });
        }
        self
    }

    /// Sets all coordinates (those of the dependent ones are Newton's starting values).
    pub fn coordinates(mut self, q: &S::Coordinates) -> Self {
        self.q = *q;
        self
    }

    /// Sets all speeds (the free quasi-velocities).
    pub fn speeds(mut self, speeds: &S::Speeds) -> Self {
        self.speeds = *speeds;
        if let Some(first) = S::SPEEDS.first() {
            self.speed_given.get_or_insert(first);
        }
        self
    }

    /// Gives the generalized velocities q̇ instead of the speeds: `build` checks them against
    /// the constraints at the solved configuration and computes the speeds from them.
    pub fn velocities(mut self, qd: &S::Coordinates) -> Self {
        self.velocities = Some(*qd);
        self
    }

    /// The state: the first mistake made while setting values, or the dependent coordinates
    /// solved ([`Error::Assembly`] if they cannot be) and the state made by
    /// `state_from_speeds` or `state_from_velocities`, with their checks.
    pub fn build(&self) -> Result<S::State, Error> {
        if let Some(mistake) = &self.mistake {
            return Err(mistake.clone());
        }
        if let (Some(_), Some(speed)) = (self.velocities, self.speed_given) {
            return Err(Error::AmbiguousState {
                speed: speed.to_string(),
            });
        }
        if !self.t.is_finite() {
            return Err(Error::InvalidSetting {
                name: "time",
                value: self.t,
                reason: "the time of a state must be a finite number",
            });
        }
        let q = self.system.assemble(self.t, &self.q)?;
        match &self.velocities {
            Some(qd) => self.system.state_from_velocities(self.t, &q, qd),
            None => self.system.state_from_speeds(self.t, &q, &self.speeds),
        }
    }
}
