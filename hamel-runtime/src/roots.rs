//! A bracketing root finder: Brent's method (R. P. Brent, *Algorithms for Minimization
//! without Derivatives*, 1973, ch. 4, the algorithm `zero`), which combines bisection's
//! guarantee with the speed of secant and inverse quadratic interpolation. Used to locate
//! where a function of one variable changes sign: an event on an integrator's dense output,
//! the speed at which a mode of a linearized system crosses the imaginary axis.
//!
//! Written here rather than taken from a crate: the well-kept numerical crates of the field
//! (nalgebra, num-dual) have none, and the general optimization frameworks that do would
//! bring a dependency tree larger than the whole runtime for forty lines.

use crate::error::{Error, Num};

/// The most iterations Brent's method needs on a bracket it can shrink: bisection alone
/// halves it every other step, so 200 cover any bracket of `f64`s down to its last bit.
const MAX_ITERATIONS: usize = 200;

/// A point x in [a, b] where f changes sign, within `tolerance` of one (absolute, on x; at
/// least a few ulps of x). f(a) and f(b) must have opposite signs (or one be zero); f is
/// only ever evaluated inside the bracket. `what` names the quantity for errors.
pub fn brent(
    what: &'static str,
    mut f: impl FnMut(f64) -> Result<f64, Error>,
    a: f64,
    b: f64,
    tolerance: f64,
) -> Result<f64, Error> {
    let (mut a, mut b) = (a, b);
    let (mut fa, mut fb) = (f(a)?, f(b)?);
    // Written so that a NaN tolerance fails too.
    let usable = fa.is_finite() && fb.is_finite() && tolerance.is_finite() && tolerance >= 0.0;
    if !usable {
        return Err(Error::RootNotBracketed { what, a, b, fa, fb });
    }
    if fa == 0.0 {
        return Ok(a);
    }
    if fb == 0.0 {
        return Ok(b);
    }
    if fa.signum() == fb.signum() {
        return Err(Error::RootNotBracketed { what, a, b, fa, fb });
    }
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    for _ in 0..MAX_ITERATIONS {
        if fb.signum() == fc.signum() {
            (c, fc) = (a, fa);
            (d, e) = (b - a, b - a);
        }
        if fc.abs() < fb.abs() {
            (a, b, c) = (b, c, b);
            (fa, fb, fc) = (fb, fc, fb);
        }
        let tol = 2.0 * f64::EPSILON * b.abs() + 0.5 * tolerance;
        let m = 0.5 * (c - b);
        if m.abs() <= tol || fb == 0.0 {
            return Ok(b);
        }
        if e.abs() < tol || fa.abs() <= fb.abs() {
            (d, e) = (m, m);
        } else {
            let (p, q) = interpolation(a, b, c, fa, fb, fc, m);
            if 2.0 * p < (3.0 * m * q - (tol * q).abs()).min((e * q).abs()) {
                (e, d) = (d, p / q);
            } else {
                (d, e) = (m, m);
            }
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol { d } else { tol.copysign(m) };
        fb = f(b)?;
        if !fb.is_finite() {
            return Err(Error::NonFiniteRootFunction { what, at: b });
        }
    }
    Err(Error::RootNotFound {
        what,
        near: b,
        residual: fb,
    })
}

/// The step of the secant (two distinct points) or inverse quadratic interpolation (three),
/// as p/q with p ≥ 0.
fn interpolation(a: f64, b: f64, c: f64, fa: f64, fb: f64, fc: f64, m: f64) -> (f64, f64) {
    let s = fb / fa;
    let (p, q) = if a == c {
        (2.0 * m * s, 1.0 - s)
    } else {
        let (q, r) = (fa / fc, fb / fc);
        (
            s * (2.0 * m * q * (q - r) - (b - a) * (r - 1.0)),
            (q - 1.0) * (r - 1.0) * (s - 1.0),
        )
    };
    if p > 0.0 { (p, -q) } else { (-p, q) }
}

impl Error {
    /// The message of a root that could not be bracketed, for `Display`.
    pub(crate) fn bracket_message(what: &str, a: f64, b: f64, fa: f64, fb: f64) -> String {
        format!(
            "cannot locate where {what} changes sign between {} and {}: its values there, {} \
             and {}, {}",
            Num(a),
            Num(b),
            Num(fa),
            Num(fb),
            if fa.is_finite() && fb.is_finite() {
                "have the same sign; choose an interval whose ends it has opposite signs at"
            } else {
                "are not both finite"
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_roots_to_the_tolerance() {
        let root = brent("cos x − x", |x| Ok(x.cos() - x), 0.0, 1.0, 1e-15).unwrap();
        assert!((root - 0.739_085_133_215_160_6).abs() < 1e-15, "{root}");
        let cube = brent("x³ − 2", |x| Ok(x * x * x - 2.0), 0.0, 2.0, 0.0).unwrap();
        assert!((cube - 2f64.cbrt()).abs() <= 4.0 * f64::EPSILON, "{cube}");
        // A root at an end.
        assert_eq!(brent("x", Ok, 0.0, 1.0, 1e-12).unwrap(), 0.0);
    }

    #[test]
    fn few_evaluations_on_smooth_functions() {
        let mut calls = 0;
        brent(
            "eˣ − 2",
            |x| {
                calls += 1;
                Ok(x.exp() - 2.0)
            },
            0.0,
            1.0,
            1e-14,
        )
        .unwrap();
        assert!(calls <= 12, "{calls} evaluations");
    }

    #[test]
    fn bad_brackets_are_errors() {
        let e = brent("x² + 1", |x| Ok(x * x + 1.0), -1.0, 1.0, 1e-12).unwrap_err();
        assert!(matches!(e, Error::RootNotBracketed { .. }));
        assert!(e.to_string().contains("x² + 1"), "{e}");
        let e = brent("1/x", |x| Ok(1.0 / x), 0.0, 1.0, 1e-12).unwrap_err();
        assert!(matches!(e, Error::RootNotBracketed { .. }), "{e}");
        let e = brent("x", Ok, -1.0, 1.0, f64::NAN).unwrap_err();
        assert!(matches!(e, Error::RootNotBracketed { .. }), "{e}");
    }
}
