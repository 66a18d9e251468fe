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
    let mut entries = Vec::new();
    if !transformation_matrix(system, t, q, &mut entries) {
        return f64::NAN;
    }
    nalgebra::DMatrix::from_column_slice(n, n, &entries).determinant()
}

/// A(q, t) into `a`, column by column (n² entries), read off the rows; false if the rows
/// are not n in all.
fn transformation_matrix<S: HamelSystem>(
    system: &S,
    t: f64,
    q: &S::Coordinates,
    a: &mut Vec<f64>,
) -> bool {
    let n = S::Coordinates::LEN;
    if S::Constraints::LEN + S::Speeds::LEN != n {
        return false;
    }
    let rows = |qd: &S::Coordinates| {
        let c = system.constraint_residual(t, q, qd);
        let s = system.speeds(t, q, qd);
        (c, s)
    };
    let (c0, s0) = rows(&S::Coordinates::zeros());
    a.clear();
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
        a.extend(column);
    }
    true
}

/// The sign of the determinant of the n × n matrix `a` (column by column), by Gaussian
/// elimination with partial pivoting in place: −1, 1, or 0 for a singular matrix or a NaN.
/// Written here because only the sign is wanted, once per step, and nalgebra's LU of a
/// dynamically sized matrix allocates its permutation at every call.
fn determinant_sign(a: &mut [f64], n: usize) -> f64 {
    let at = |i: usize, j: usize| i + j * n;
    let mut sign = 1.0;
    for k in 0..n {
        let pivot_row = (k..n)
            .max_by(|&i, &r| a[at(i, k)].abs().total_cmp(&a[at(r, k)].abs()))
            .unwrap_or(k);
        let pivot = a[at(pivot_row, k)];
        if pivot == 0.0 || pivot.is_nan() {
            return 0.0;
        }
        if pivot_row != k {
            for j in k..n {
                a.swap(at(k, j), at(pivot_row, j));
            }
            sign = -sign;
        }
        if pivot < 0.0 {
            sign = -sign;
        }
        for i in k + 1..n {
            let factor = a[at(i, k)] / pivot;
            for j in k + 1..n {
                a[at(i, j)] -= factor * a[at(k, j)];
            }
        }
    }
    sign
}

/// The sign of det A at the last check, and the crossings found so far.
pub(crate) struct CrossingWatch {
    sign: f64,
    pub crossings: Vec<SingularCrossing>,
    /// A's entries, reused at every check: no allocation per step.
    entries: Vec<f64>,
}

impl CrossingWatch {
    pub fn new<S: HamelSystem>(system: &S, t0: f64, x0: &S::State) -> Self {
        let n = S::Coordinates::LEN;
        let mut watch = CrossingWatch {
            sign: 0.0,
            crossings: Vec::new(),
            entries: Vec::with_capacity(n * n),
        };
        watch.sign = watch.sign_at(system, t0, &S::coordinates_of(x0));
        watch
    }

    /// The sign of det A(q, t): −1, 1, or 0 where it is zero or NaN (or the rows are not n).
    fn sign_at<S: HamelSystem>(&mut self, system: &S, t: f64, q: &S::Coordinates) -> f64 {
        if !transformation_matrix(system, t, q, &mut self.entries) {
            return 0.0;
        }
        determinant_sign(&mut self.entries, S::Coordinates::LEN)
    }

    /// Checks the end of one accepted step; a sign change is located in the step.
    pub fn step<S: HamelSystem, V: Vector>(
        &mut self,
        system: &S,
        view: &StepView<'_, V>,
        state: impl Fn(&V) -> S::State,
    ) {
        let after = self.sign_at(system, view.t1, &S::coordinates_of(&state(view.x1)));
        // A zero (or NaN) determinant at a step's end keeps the last sign: the next nonzero
        // one tells whether the configuration was crossed or only touched.
        if after == 0.0 {
            return;
        }
        if self.sign != 0.0 && after != self.sign {
            let det =
                |t: f64, x: &S::State| transformation_determinant(system, t, &S::coordinates_of(x));
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

#[cfg(test)]
mod tests {
    use super::determinant_sign;

    #[test]
    fn determinant_signs_by_elimination() {
        // Column by column: [[2, 1], [1, 3]] has det 5; swapping its rows, −5.
        assert_eq!(determinant_sign(&mut [2.0, 1.0, 1.0, 3.0], 2), 1.0);
        assert_eq!(determinant_sign(&mut [1.0, 2.0, 3.0, 1.0], 2), -1.0);
        // A pivot that needs a row swap: [[0, 1, 0], [1, 0, 0], [0, 0, −2]], det 2.
        let mut a = [0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -2.0];
        assert_eq!(determinant_sign(&mut a, 3), 1.0);
        // Singular and NaN.
        assert_eq!(determinant_sign(&mut [1.0, 2.0, 2.0, 4.0], 2), 0.0);
        assert_eq!(determinant_sign(&mut [f64::NAN, 0.0, 0.0, 1.0], 2), 0.0);
        assert_eq!(determinant_sign(&mut [], 0), 1.0);
    }
}
