//! Configurations where A(q, t) — the constraint rows over the quasi-velocity rows — is
//! singular, crossed between two checks.
//!
//! Hamel's equations need B = A⁻¹. Where A is singular the quasi-velocities do not determine
//! q̇, and B (with it the right-hand side) is unbounded nearby. An adaptive integrator can
//! still step across such a configuration when the motion itself is regular there — the knife
//! edge described by ẋ instead of its forward speed, turning through φ = ±π/2, where ẏ = ẋ tan φ
//! is 0·∞ — and the run then returns `Ok` with an error far above its tolerance (relative
//! energy drift 10³ times larger than elsewhere in that example). A crossing changes the sign
//! of det A, so the sign is compared after every accepted step; where it changed, the time is
//! located by Brent's method on the step's dense output and the run's summary flags it.
//! (A configuration touched without a sign change, or two crossings within one step, go
//! unseen.)

use core::fmt;

use crate::error::Num;
use crate::integrate::StepView;
use crate::named::NamedValues;
use crate::roots::brent;
use crate::system::HamelSystem;
use crate::vector::Vector;

/// A run crossed a configuration where A(q, t) is singular, at about time `t`: the results
/// after it are much less accurate than the tolerance asks (or meaningless). Use
/// quasi-velocities that stay independent of the constraints along the motion, or stop the run
/// before it (an event on the configuration).
#[derive(Clone, Debug, PartialEq)]
pub struct SingularCrossing {
    /// Where det A(q, t) changed sign, located on the dense output.
    pub t: f64,
    /// The configuration there.
    pub configuration: NamedValues,
}

impl fmt::Display for SingularCrossing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "crossed a configuration where the constraints and quasi-velocities are dependent \
             (A(q) singular) at t = {}: results after it are unreliable; choose \
             quasi-velocities independent of the constraints there; configuration: {}",
            Num(self.t),
            self.configuration
        )
    }
}

/// det A(q, t), A's columns read off the rows as A eⱼ = rows(eⱼ) − rows(0) (the rows are
/// affine in q̇); NaN if the rows are not n in all.
pub fn transformation_determinant<S: HamelSystem>(system: &S, t: f64, q: &S::Coordinates) -> f64 {
    let n = S::Coordinates::LEN;
    if S::Constraints::LEN + S::Speeds::LEN != n {
        return f64::NAN;
    }
    let rows = |qd: &S::Coordinates| {
        let c = system.constraint_residual(t, q, qd);
        let s = system.speeds(t, q, qd);
        (c, s)
    };
    let (c0, s0) = rows(&S::Coordinates::zeros());
    let mut a = nalgebra::DMatrix::<f64>::zeros(n, n);
    let mut e = S::Coordinates::zeros();
    for j in 0..n {
        e.as_mut()[j] = 1.0;
        let (c, s) = rows(&e);
        e.as_mut()[j] = 0.0;
        let column = c
            .as_ref()
            .iter()
            .zip(c0.as_ref())
            .chain(s.as_ref().iter().zip(s0.as_ref()))
            .map(|(v, v0)| v - v0);
        for (i, value) in column.enumerate() {
            a[(i, j)] = value;
        }
    }
    a.determinant()
}

/// The sign of det A at the last check, and the crossings found so far.
pub(crate) struct CrossingWatch {
    sign: f64,
    pub crossings: Vec<SingularCrossing>,
}

impl CrossingWatch {
    pub fn new<S: HamelSystem>(system: &S, t0: f64, x0: &S::State) -> Self {
        CrossingWatch {
            sign: sign(transformation_determinant(
                system,
                t0,
                &S::coordinates_of(x0),
            )),
            crossings: Vec::new(),
        }
    }

    /// Checks the end of one accepted step; a sign change is located in the step.
    pub fn step<S: HamelSystem, V: Vector>(
        &mut self,
        system: &S,
        view: &StepView<'_, V>,
        state: impl Fn(&V) -> S::State,
    ) {
        let det =
            |t: f64, x: &S::State| transformation_determinant(system, t, &S::coordinates_of(x));
        let after = sign(det(view.t1, &state(view.x1)));
        // A zero (or NaN) determinant at a step's end keeps the last sign: the next nonzero
        // one tells whether the configuration was crossed or only touched.
        if after == 0.0 {
            return;
        }
        if self.sign != 0.0 && after != self.sign {
            let tolerance = 1e-12 * (view.t1 - view.t);
            let mut g = |s: f64| Ok(det(s, &state(&view.dense.at(s))));
            // The sign change within the step is certain, so a failure to bracket it on the
            // dense output (a NaN there) leaves the step's start as the best estimate.
            let t = brent("det A(q)", &mut g, view.t, view.t1, tolerance).unwrap_or(view.t);
            let x = state(&view.dense.at(t));
            self.crossings.push(SingularCrossing {
                t,
                configuration: NamedValues::new(S::COORDINATES, S::coordinates_of(&x).as_ref()),
            });
        }
        self.sign = after;
    }
}

/// −1, 1, or 0 for a zero or NaN.
fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}
