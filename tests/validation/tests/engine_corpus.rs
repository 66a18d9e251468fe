//! Engine corpus: a fixed set of ordinary Rust functions over `f64`, differentiated by
//! `#[hamel::differentiate]`, each checked at pseudo-random points against two independent
//! references:
//!
//! * the value of `f_generic::<f64>` (the engine's lowering, emitted back to Rust) against
//!   the function itself as rustc compiled it;
//! * every generated derivative (`f_tangent`, `f_gradient`/`f_adjoint`, `f_jacobian`,
//!   `f_hessian`, `f_second`) against num-dual's hyper-dual numbers run through
//!   `f_generic::<D>`.
//!
//! All comparisons are norm-wise relative at 1e-12 (`support::harness::Report::compare`).
//! Random directions and weights are redrawn where contracting the derivatives with them
//! would lose more than two digits to cancellation (`support::harness::MAX_CONDITION`):
//! there the reference's own rounding would approach the tolerance.
//! The corpus covers every form of the engine's subset at least once, the paper's mobile
//! robot (`hamel::docs::design`, "Worked example") and a 20-link pendulum chain; the last two
//! also get the cheap-gradient check on the generated operation counts.

use crate::support::dual::D;
use crate::support::harness::{Case, POINTS, Report, Rng, run_case};
use crate::support::shapes::{Arg, flat};
use std::f64::consts;
use std::f64::consts::FRAC_PI_4;
use std::time::Instant;

/// Gravity: a module-level constant that bodies read by its bare name.
const G: f64 = 9.81;

// ---------------------------------------------------------------------------------------
// The corpus: language forms
// ---------------------------------------------------------------------------------------

/// Parameters of the language-form corpus, read as `self.field`.
struct Corpus {
    a: f64,
    b: f64,
    c: f64,
}

const CORPUS: Corpus = Corpus {
    a: 1.3,
    b: -0.7,
    c: 0.45,
};

// The subset indexes arrays by loop counters, which is what `needless_range_loop` dislikes.
#[hamel::differentiate]
#[allow(clippy::needless_range_loop)]
impl Corpus {
    const SCALE: f64 = 1.5;
    const HALF_SCALE: f64 = Self::SCALE / 2.0;
    const TERMS: usize = 4;

    /// Literals (`1e-3`, `2f64`), `+ - * /`, unary minus and parentheses.
    fn arithmetic(&self, x: f64, y: f64) -> f64 {
        3.0 * x * x - (x - y) / (2.0 + y * y) + -x * 0.5 - -(y / 4.0)
            + 1e-3 * x * y
            + 2f64 * (x + 1.0) * (y - 0.25)
    }

    /// `const` items in the body, associated consts (one defined through another) and a
    /// module-level const read by its bare name.
    fn constants(&self, x: f64) -> f64 {
        const K: f64 = 2.5;
        const TWICE_K: f64 = 2.0 * K;
        K * x + Self::SCALE * x * x - Self::HALF_SCALE / (1.0 + x * x) + G * x * x * x / TWICE_K
    }

    /// Parameters `self.field`, and arguments by reference (`&f64`), dereferenced or not.
    fn parameters(&self, x: &f64, y: &f64) -> f64 {
        self.a * *x * *x + self.b * x * y + self.c * (*y - self.a) / (self.a + x * x)
    }

    /// `let mut` with `=`, `+=`, `-=`, `*=`, `/=`; a typed `let`; shadowing.
    fn compound_assignment(&self, x: f64, y: f64) -> f64 {
        let mut s = x;
        s += y * y;
        s -= 0.5 * x;
        s *= 1.0 + y;
        s /= 2.0 + x * x;
        let mut t: f64 = s * y;
        t = t * t - s;
        let s = s + t;
        s * self.a
    }

    /// Element assignment (`=` and compound) on a `let mut` array started from `[0.0; 3]`.
    fn array_elements(&self, v: [f64; 3]) -> [f64; 3] {
        let mut a = [0.0; 3];
        a[0] = v[0] * v[1];
        a[1] = v[2] - v[0];
        a[2] = self.c;
        a[2] += v[1] * v[2];
        a[1] -= a[0];
        a[0] *= v[2];
        a[2] /= 1.0 + v[0] * v[0];
        a
    }

    /// Array and tuple destructuring (with `_`), tuple literals and fields, `sin_cos`.
    fn destructuring(&self, q: &[f64; 2]) -> f64 {
        let [a, b] = *q;
        let (s, c) = a.sin_cos();
        let [_, last] = *q;
        let pair = (a * b, last);
        let (sb, _) = b.sin_cos();
        s * b + c * c * pair.1 - sb * pair.0 + (a + b).sin_cos().1
    }

    /// Block expressions as values, with scopes of their own.
    fn blocks(&self, x: f64, y: f64) -> f64 {
        let r = {
            let t = x * y;
            let x = t + 1.0; // shadows the argument inside this block only
            t * x
        };
        let s = {
            let mut acc = r;
            acc -= x;
            acc * acc
        };
        r + s + x
    }

    /// An array literal as the result.
    fn array_result(&self, x: f64, y: f64) -> [f64; 3] {
        let (s, c) = (self.a * y).sin_cos();
        [x * c - y * s, x * s + y * c, x * y]
    }

    /// `for i in 0..K`: the counter as an index (also in integer arithmetic) and as a number
    /// (`i as f64`); bounds from a literal, an associated const and `len()`; an `if` on the
    /// counter, decided at compile time.
    fn indexed_loops(&self, v: &[f64; 4]) -> f64 {
        const LAST: usize = 3;
        let mut s = 0.0;
        for i in 0..4 {
            s += v[i] * (i as f64 + 1.0);
        }
        for i in 0..Self::TERMS {
            s += v[LAST - i] * v[(i + 1) % 4] * 0.5;
        }
        for i in 0..v.len() - 1 {
            if i % 2 == 0 {
                s -= v[i] * v[i + 1];
            } else {
                s += (v[i] - v[i + 1]) * self.b;
            }
        }
        s
    }

    /// `for k in 0..=K`: the exponential series.
    fn inclusive_loop(&self, x: f64) -> f64 {
        let mut term = 1.0;
        let mut sum = 1.0;
        for k in 0..=7 {
            term *= x / (k as f64 + 1.0);
            sum += term;
        }
        sum
    }

    /// `(0..K).rev()`: Horner's scheme and a suffix recurrence.
    fn reversed_loops(&self, c: &[f64; 5], x: f64) -> [f64; 2] {
        let mut horner = 0.0;
        for i in (0..5).rev() {
            horner = horner * x + c[i];
        }
        let mut suffix = [0.0; 5];
        suffix[4] = c[4];
        for i in (0..4).rev() {
            suffix[i] = suffix[i + 1] * x + c[i] * c[i];
        }
        [horner, suffix[0]]
    }

    /// `for x in arr` over the elements: by value, by reference and through `iter()`.
    fn element_loops(&self, v: [f64; 3]) -> f64 {
        let mut squares = 0.0;
        for x in v {
            squares += x * x;
        }
        let mut product = 1.0;
        for x in &v {
            product *= 1.0 + *x;
        }
        let mut weighted = 0.0;
        for &x in v.iter() {
            weighted += self.a * x;
        }
        squares * product + weighted
    }

    /// Nested arrays `[[f64; 2]; 2]` in and out: the matrix square minus a rank-one term.
    fn nested_arrays(&self, m: [[f64; 2]; 2], v: &[f64; 2]) -> [[f64; 2]; 2] {
        let mut r = [[0.0; 2]; 2];
        for i in 0..2 {
            for j in 0..2 {
                for k in 0..2 {
                    r[i][j] += m[i][k] * m[k][j];
                }
                r[i][j] -= v[i] * v[j] * self.c;
            }
        }
        r
    }

    /// A nested array by reference and a loop over its rows: ½ vᵀMv plus det(M)².
    fn quadratic_form(&self, m: &[[f64; 2]; 2], v: [f64; 2]) -> f64 {
        let mut energy = 0.0;
        let mut i = 0.0;
        for row in m {
            let vi = if i < 0.5 { v[0] } else { v[1] };
            energy += 0.5 * vi * (row[0] * v[0] + row[1] * v[1]);
            i += 1.0;
        }
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        energy + det * det
    }

    /// Trigonometric functions, method form (a `[f64; N]` result, so `f_adjoint`).
    fn trig_methods(&self, x: f64, y: f64) -> [f64; 7] {
        [
            x.sin() * y,
            (x * y).cos(),
            x.tan(),
            (0.5 * x).asin(),
            (0.5 * y).acos(),
            (x - y).atan(),
            y.atan2(x) + (-1.5_f64).atan2(x),
        ]
    }

    /// Trigonometric functions, path form.
    fn trig_paths(&self, x: f64, y: f64) -> [f64; 7] {
        [
            f64::sin(x) * y,
            f64::cos(x * y),
            f64::tan(x),
            f64::asin(0.5 * x),
            f64::acos(0.5 * y),
            f64::atan(x - y),
            f64::atan2(y, x) + f64::atan2(-1.5, x),
        ]
    }

    /// Hyperbolic functions, exponential and logarithms, method form.
    fn exp_log_methods(&self, x: f64, y: f64) -> [f64; 6] {
        [
            x.sinh(),
            (x * y).cosh(),
            (x - y).tanh(),
            (0.5 * x).exp() * y,
            (x + y).ln(),
            (x * y).log10(),
        ]
    }

    /// Hyperbolic functions, exponential and logarithms, path form.
    fn exp_log_paths(&self, x: f64, y: f64) -> [f64; 6] {
        [
            f64::sinh(x),
            f64::cosh(x * y),
            f64::tanh(x - y),
            f64::exp(0.5 * x) * y,
            f64::ln(x + y),
            f64::log10(x * y),
        ]
    }

    /// Roots and powers, method form (cube root of a negative number, negative `powi`
    /// exponent, real exponent constant and variable, a literal receiver).
    fn power_methods(&self, x: f64, y: f64) -> [f64; 8] {
        [
            x.sqrt(),
            (x - 2.0 * y - 1.5).cbrt(),
            x.powi(3) * y.powi(-2),
            x.powf(1.7),
            x.powf(y) + 2.0_f64.powf(y),
            x.hypot(y),
            (x + y).recip(),
            x.mul_add(y, self.a),
        ]
    }

    /// Roots and powers, path form.
    fn power_paths(&self, x: f64, y: f64) -> [f64; 8] {
        [
            f64::sqrt(x),
            f64::cbrt(x - 2.0 * y - 1.5),
            f64::powi(x, 3) * f64::powi(y, -2),
            f64::powf(x, 1.7),
            f64::powf(x, y) + f64::powf(2.0, y),
            f64::hypot(x, y),
            f64::recip(x + y),
            f64::mul_add(x, y, self.a),
        ]
    }

    /// `abs`, `signum`, `min`, `max`, method form (smooth away from their kinks, where the
    /// random points land).
    fn nonsmooth_methods(&self, x: f64, y: f64) -> [f64; 4] {
        [
            (x - y).abs() * x,
            (x - 0.5).signum() * x * x,
            x.min(y) * y,
            (x * y).max(0.3 * x),
        ]
    }

    /// `abs`, `signum`, `min`, `max`, path form.
    fn nonsmooth_paths(&self, x: f64, y: f64) -> [f64; 4] {
        [
            f64::abs(x - y) * x,
            f64::signum(x - 0.5) * x * x,
            f64::min(x, y) * y,
            f64::max(x * y, 0.3 * x),
        ]
    }

    /// `std::f64::consts` by full path (also through `core` and an imported `consts`),
    /// `f64::EPSILON`, and `FRAC_PI_4` imported by its bare name.
    fn math_constants(&self, x: f64) -> f64 {
        std::f64::consts::PI * x * x + core::f64::consts::E.ln() * x - consts::TAU / (1.0 + x * x)
            + consts::SQRT_2 * consts::FRAC_PI_2.sin() * x
            + consts::LN_2 * consts::LN_10
            + FRAC_PI_4.tan() * consts::FRAC_1_SQRT_2 * x * x * x
            + f64::EPSILON * x
    }

    /// A helper without `self`, called as `Self::square(..)`.
    fn square(x: f64) -> f64 {
        x * x
    }

    /// A helper with an array argument, called as `self.norm(..)`.
    fn norm(&self, v: &[f64; 3]) -> f64 {
        (Self::square(v[0]) + v[1] * v[1] + v[2] * v[2]).sqrt()
    }

    /// A helper returning an array.
    fn rotate(&self, x: f64, y: f64) -> [f64; 2] {
        let (s, c) = self.b.sin_cos();
        [c * x - s * y, s * x + c * y]
    }

    /// A helper with an integer argument: inlined where called, no derivatives of its own.
    fn weight(&self, i: usize, x: f64) -> f64 {
        (i as f64 + 1.0) * self.a * x.sin()
    }

    /// Calls of the other functions of the impl, `weight(i, ..)` inside a loop among them.
    fn calls(&self, v: &[f64; 3]) -> f64 {
        let mut s = 0.0;
        for i in 0..3 {
            s += self.weight(i, v[i]);
        }
        let [p, q] = self.rotate(v[0], v[1]);
        s + Self::square(self.norm(v)) * p + self.norm(&[q, 1.0, v[2]])
    }

    /// A value-producing `if`, also as an operand.
    fn select_value(&self, x: f64, y: f64) -> f64 {
        let s = if x > y { x * y } else { x + y * y };
        s * s + if s < 0.2 { s } else { -s }
    }

    /// Statement `if` without `else`, mutating locals and an array element.
    fn statement_if(&self, x: f64, y: f64) -> f64 {
        let mut s = x * x;
        let mut a = [x, y];
        if y < 0.3 {
            s += y;
        }
        if x >= y {
            s *= 2.0;
            a[1] = -y * x;
        }
        if x <= 0.0 {
            a[0] = 0.5;
        }
        s + a[0] * a[1]
    }

    /// An `else if` chain: a piecewise function (its `ln` branch is NaN where untaken).
    fn else_if_chain(&self, x: f64) -> f64 {
        if x < -0.5 {
            -x * x
        } else if x < 0.0 {
            x.sin()
        } else if x <= 0.5 {
            x.exp() - 1.0
        } else {
            x.ln() + 2.0
        }
    }

    /// Conditions combined with `&&`, `||`, `!` and `==` on booleans; a boolean local
    /// changed by an `if`.
    fn logical_conditions(&self, x: f64, y: f64) -> f64 {
        let inside = x * x + y * y < 0.36;
        let r = if x > 0.0 && y > 0.0 {
            x * y
        } else if !inside || x < -0.8 {
            x - y * y
        } else {
            (x + y).sin()
        };
        let mut s = r;
        if !(inside && y < x) {
            s += 0.5 * x * y;
        }
        let mut flag = x > y;
        if y > 0.5 {
            flag = !flag;
        }
        if inside == flag {
            s *= 1.5;
        }
        s
    }

    /// The textbook domain guard: √x is NaN in the untaken branch.
    fn sqrt_guard(&self, x: f64) -> f64 {
        if x > 0.0 { x.sqrt() } else { 0.0 }
    }

    /// Domain guards whose guarded values are computed before the `if` (so they are NaN on
    /// the wrong side whether or not the branch is taken): √, ln and `powf`.
    fn guarded_logs(&self, x: f64, y: f64) -> f64 {
        let root = x.sqrt();
        let log = (x * y).ln();
        let a = if x > 0.0 { root * y } else { -x * y };
        let b = if x > 0.0 && y > 0.0 {
            log + x.powf(y)
        } else {
            x + y
        };
        a * b + a
    }

    /// Guards inside a loop: only the positive entries contribute their square roots.
    fn loop_with_guards(&self, v: &[f64; 5]) -> f64 {
        let mut s = 0.0;
        for i in 0..5 {
            if v[i] > 0.0 {
                s += v[i].sqrt() * (i as f64 + 1.0);
            } else {
                s -= v[i] * v[i];
            }
        }
        s
    }

    /// The Rosenbrock function, a classic of optimization tests.
    fn rosenbrock(&self, v: &[f64; 6]) -> f64 {
        let mut s = 0.0;
        for i in 0..5 {
            let a = v[i + 1] - v[i] * v[i];
            let b = 1.0 - v[i];
            s += 100.0 * a * a + b * b;
        }
        s
    }

    /// The Kepler problem's Hamiltonian ½|p|² − 1/|q|.
    fn kepler(&self, q: &[f64; 2], p: &[f64; 2]) -> f64 {
        0.5 * (p[0] * p[0] + p[1] * p[1]) - 1.0 / q[0].hypot(q[1])
    }
}

// ---------------------------------------------------------------------------------------
// The corpus: the paper's mobile robot (`hamel::docs::design`, "Worked example")
// ---------------------------------------------------------------------------------------

/// A two-wheeled robot with a pendulum body: mass and inertias of the body, mass of a wheel,
/// wheel radius, track width, distance of the body's centre of mass from the axle, gravity.
struct Robot {
    m0: f64,
    mw: f64,
    jx: f64,
    jy: f64,
    jz: f64,
    r: f64,
    b: f64,
    l: f64,
    g: f64,
}

const ROBOT: Robot = Robot {
    m0: 4.0,
    mw: 0.5,
    jx: 0.08,
    jy: 0.1,
    jz: 0.06,
    r: 0.1,
    b: 0.4,
    l: 0.15,
    g: 9.81,
};

#[hamel::differentiate]
impl Robot {
    /// The heading ϑ = r(φ₁ − φ₂)/b of the axle, and likewise its rate from the wheel rates.
    fn heading(&self, phi1: f64, phi2: f64) -> f64 {
        self.r * (phi1 - phi2) / self.b
    }

    /// L(q, q̇) = T − V, q = (x, y, α, φ₁, φ₂), from the energies of the body and the wheels.
    fn lagrangian(&self, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let [_, _, alpha, phi1, phi2] = *q;
        let [xd, yd, alphad, phi1d, phi2d] = *qd;
        let theta = self.heading(phi1, phi2);
        let thetad = self.heading(phi1d, phi2d);
        let (st, ct) = theta.sin_cos();
        let (sa, ca) = alpha.sin_cos();
        // Forward and lateral directions of the axle.
        let ef = [ct, st];
        let ea = [-st, ct];

        // The body: its centre of mass moves with the axle, pitches with α and yaws with ϑ.
        let mut v = [xd, yd, -self.l * alphad * sa];
        for k in 0..2 {
            v[k] += self.l * alphad * ca * ef[k] + self.l * sa * thetad * ea[k];
        }
        let body = 0.5 * self.m0 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            + 0.5
                * (self.jx * sa * sa * thetad * thetad
                    + self.jy * alphad * alphad
                    + self.jz * ca * ca * thetad * thetad);

        // The wheels: centres at ±b/2 along the axle, spinning relative to the body.
        let half = 0.5 * self.b * thetad;
        let c1 = [xd + half * ef[0], yd + half * ef[1]];
        let c2 = [xd - half * ef[0], yd - half * ef[1]];
        let spin = 0.25 * self.mw * self.r * self.r;
        let wheels =
            0.5 * self.mw * (c1[0] * c1[0] + c1[1] * c1[1] + c2[0] * c2[0] + c2[1] * c2[1])
                + spin * ((alphad + phi1d).powi(2) + (alphad + phi2d).powi(2))
                + spin * thetad * thetad;

        let potential = self.m0 * self.g * self.l * ca;
        body + wheels - potential
    }

    /// ω = A(q) q̇: the two constraint rows (rolling without slipping), then the three
    /// quasi-velocities (pitch rate, forward speed, yaw rate).
    fn velocity_rows(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 5] {
        let (s, c) = self.heading(q[3], q[4]).sin_cos();
        let [xd, yd, alphad, phi1d, phi2d] = *qd;
        let forward = xd * c + yd * s;
        [
            xd * s - yd * c,
            self.r * alphad + 0.5 * self.r * (phi1d + phi2d) - forward,
            alphad,
            forward,
            self.r / self.b * (phi1d - phi2d),
        ]
    }
}

// ---------------------------------------------------------------------------------------
// The corpus: a planar 20-link pendulum chain
// ---------------------------------------------------------------------------------------

/// Identical uniform links of a planar pendulum chain hanging from the origin.
struct Chain {
    mass: f64,
    length: f64,
    /// Moment of inertia of a link about its centre.
    inertia: f64,
}

const CHAIN: Chain = Chain {
    mass: 0.3,
    length: 0.25,
    inertia: 0.3 * 0.25 * 0.25 / 12.0,
};

#[hamel::differentiate]
#[allow(clippy::needless_range_loop)]
impl Chain {
    const LINKS: usize = 20;

    /// L(q, q̇) with q the links' absolute angles from the downward vertical: the joints'
    /// positions and velocities are accumulated link by link, each link's centre lying
    /// half a length beyond its upper joint.
    fn lagrangian(&self, q: &[f64; 20], qd: &[f64; 20]) -> f64 {
        let half = 0.5 * self.length;
        let mut joint = [0.0; 2];
        let mut joint_velocity = [0.0; 2];
        let mut kinetic = 0.0;
        let mut potential = 0.0;
        for i in 0..Self::LINKS {
            let (s, c) = q[i].sin_cos();
            let centre = [joint[0] + half * s, joint[1] - half * c];
            let centre_velocity = [
                joint_velocity[0] + half * c * qd[i],
                joint_velocity[1] + half * s * qd[i],
            ];
            kinetic += 0.5
                * self.mass
                * (centre_velocity[0] * centre_velocity[0]
                    + centre_velocity[1] * centre_velocity[1])
                + 0.5 * self.inertia * qd[i] * qd[i];
            potential += self.mass * G * centre[1];
            joint = [joint[0] + self.length * s, joint[1] - self.length * c];
            joint_velocity[0] += self.length * c * qd[i];
            joint_velocity[1] += self.length * s * qd[i];
        }
        kinetic - potential
    }
}

// ---------------------------------------------------------------------------------------
// The cases: each corpus function with its generated companions over flat vectors
// ---------------------------------------------------------------------------------------

/// A [`Case`] for one corpus function. Syntax:
///
/// `case!(scalar|vector Type::name[receiver](arg: type, ..) in (lo, hi); generic tangent
/// gradient|adjoint jacobian hessian second)`
///
/// The generated names are spelled out because `macro_rules!` cannot paste identifiers.
/// `receiver` is `&MODEL` for methods and empty for associated functions.
macro_rules! case {
    // Build the typed arguments from the flat slice `xs`, call `callee` with them followed by
    // `extra`, and flatten the result.
    (@call $callee:expr, [$($recv:expr)?], $xs:expr, $S:ty, ($($arg:ident : $t:ty),*) $(, $extra:expr)*) => {{
        let xs: &[$S] = $xs;
        let mut at = 0;
        $(
            let $arg = <$t as Arg>::build::<$S>(&xs[at..]);
            at += <$t as Arg>::LEN;
        )*
        assert_eq!(at, xs.len(), "wrong number of inputs");
        flat::<$S, _>(&$callee($($recv,)? $(<$t as Arg>::pass(&$arg),)* $($extra),*))
    }};
    (@case $ty:ident :: $f:ident [$($recv:expr)?] ($($arg:ident : $t:ty),*) in $domain:expr;
     $generic:ident $tangent:ident $jacobian:ident $second:ident;
     gradient: $gradient:expr, hessian: $hessian:expr) => {
        Case {
            name: concat!(stringify!($ty), "::", stringify!($f)),
            n: 0 $(+ <$t as Arg>::LEN)*,
            domain: $domain,
            original: |xs: &[f64]| case!(@call $ty::$f, [$($recv)?], xs, f64, ($($arg: $t),*)),
            generic_f64: |xs: &[f64]| case!(@call $ty::$generic::<f64>, [$($recv)?], xs, f64, ($($arg: $t),*)),
            generic_dual: |xs: &[D]| case!(@call $ty::$generic::<D>, [$($recv)?], xs, D, ($($arg: $t),*)),
            tangent: |xs: &[f64], dir: &[f64]| {
                case!(@call $ty::$tangent, [$($recv)?], xs, f64, ($($arg: $t),*), dir.try_into().unwrap())
            },
            gradient: $gradient,
            jacobian: |xs: &[f64]| case!(@call $ty::$jacobian, [$($recv)?], xs, f64, ($($arg: $t),*)),
            hessian: $hessian,
            second: |xs: &[f64], u: &[f64], v: &[f64]| {
                case!(@call $ty::$second, [$($recv)?], xs, f64, ($($arg: $t),*), u.try_into().unwrap(), v.try_into().unwrap())
            },
        }
    };
    // A function with an `f64` result: `f_gradient(x)`, `f_hessian(x)`.
    (scalar $ty:ident :: $f:ident [$($recv:expr)?] ($($arg:ident : $t:ty),*) in $domain:expr;
     $generic:ident $tangent:ident $gradient:ident $jacobian:ident $hessian:ident $second:ident) => {
        case!(@case $ty::$f [$($recv)?] ($($arg: $t),*) in $domain; $generic $tangent $jacobian $second;
            gradient: |xs: &[f64], _: &[f64]| case!(@call $ty::$gradient, [$($recv)?], xs, f64, ($($arg: $t),*)),
            hessian: |xs: &[f64], _: &[f64]| case!(@call $ty::$hessian, [$($recv)?], xs, f64, ($($arg: $t),*)))
    };
    // A function with an array result: `f_adjoint(x, weights)`, `f_hessian(x, weights)`.
    (vector $ty:ident :: $f:ident [$($recv:expr)?] ($($arg:ident : $t:ty),*) in $domain:expr;
     $generic:ident $tangent:ident $adjoint:ident $jacobian:ident $hessian:ident $second:ident) => {
        case!(@case $ty::$f [$($recv)?] ($($arg: $t),*) in $domain; $generic $tangent $jacobian $second;
            gradient: |xs: &[f64], w: &[f64]| {
                case!(@call $ty::$adjoint, [$($recv)?], xs, f64, ($($arg: $t),*), w.try_into().unwrap())
            },
            hessian: |xs: &[f64], w: &[f64]| {
                case!(@call $ty::$hessian, [$($recv)?], xs, f64, ($($arg: $t),*), w.try_into().unwrap())
            })
    };
}

/// Every corpus function that gets derivative methods (all but the integer helper `weight`,
/// which is checked through `calls`). Domains keep each function inside its domain of
/// definition (or, for the guards, straddle the boundary on purpose).
fn cases() -> Vec<Case> {
    vec![
        case!(scalar Corpus::arithmetic[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            arithmetic_generic arithmetic_tangent arithmetic_gradient arithmetic_jacobian
            arithmetic_hessian arithmetic_second),
        case!(scalar Corpus::constants[&CORPUS](x: f64) in (-1.5, 1.5);
            constants_generic constants_tangent constants_gradient constants_jacobian
            constants_hessian constants_second),
        case!(scalar Corpus::parameters[&CORPUS](x: &f64, y: &f64) in (-1.0, 1.0);
            parameters_generic parameters_tangent parameters_gradient parameters_jacobian
            parameters_hessian parameters_second),
        case!(scalar Corpus::compound_assignment[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            compound_assignment_generic compound_assignment_tangent compound_assignment_gradient
            compound_assignment_jacobian compound_assignment_hessian compound_assignment_second),
        case!(vector Corpus::array_elements[&CORPUS](v: [f64; 3]) in (-1.0, 1.0);
            array_elements_generic array_elements_tangent array_elements_adjoint
            array_elements_jacobian array_elements_hessian array_elements_second),
        case!(scalar Corpus::destructuring[&CORPUS](q: &[f64; 2]) in (-2.0, 2.0);
            destructuring_generic destructuring_tangent destructuring_gradient destructuring_jacobian
            destructuring_hessian destructuring_second),
        case!(scalar Corpus::blocks[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            blocks_generic blocks_tangent blocks_gradient blocks_jacobian blocks_hessian
            blocks_second),
        case!(vector Corpus::array_result[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            array_result_generic array_result_tangent array_result_adjoint array_result_jacobian
            array_result_hessian array_result_second),
        case!(scalar Corpus::indexed_loops[&CORPUS](v: &[f64; 4]) in (-1.0, 1.0);
            indexed_loops_generic indexed_loops_tangent indexed_loops_gradient indexed_loops_jacobian
            indexed_loops_hessian indexed_loops_second),
        case!(scalar Corpus::inclusive_loop[&CORPUS](x: f64) in (-2.0, 2.0);
            inclusive_loop_generic inclusive_loop_tangent inclusive_loop_gradient
            inclusive_loop_jacobian inclusive_loop_hessian inclusive_loop_second),
        case!(vector Corpus::reversed_loops[&CORPUS](c: &[f64; 5], x: f64) in (-1.0, 1.0);
            reversed_loops_generic reversed_loops_tangent reversed_loops_adjoint
            reversed_loops_jacobian reversed_loops_hessian reversed_loops_second),
        case!(scalar Corpus::element_loops[&CORPUS](v: [f64; 3]) in (-1.0, 1.0);
            element_loops_generic element_loops_tangent element_loops_gradient element_loops_jacobian
            element_loops_hessian element_loops_second),
        case!(vector Corpus::nested_arrays[&CORPUS](m: [[f64; 2]; 2], v: &[f64; 2]) in (-1.0, 1.0);
            nested_arrays_generic nested_arrays_tangent nested_arrays_adjoint nested_arrays_jacobian
            nested_arrays_hessian nested_arrays_second),
        case!(scalar Corpus::quadratic_form[&CORPUS](m: &[[f64; 2]; 2], v: [f64; 2]) in (-1.0, 1.0);
            quadratic_form_generic quadratic_form_tangent quadratic_form_gradient
            quadratic_form_jacobian quadratic_form_hessian quadratic_form_second),
        case!(vector Corpus::trig_methods[&CORPUS](x: f64, y: f64) in (0.2, 1.2);
            trig_methods_generic trig_methods_tangent trig_methods_adjoint trig_methods_jacobian
            trig_methods_hessian trig_methods_second),
        case!(vector Corpus::trig_paths[&CORPUS](x: f64, y: f64) in (0.2, 1.2);
            trig_paths_generic trig_paths_tangent trig_paths_adjoint trig_paths_jacobian
            trig_paths_hessian trig_paths_second),
        case!(vector Corpus::exp_log_methods[&CORPUS](x: f64, y: f64) in (0.2, 1.5);
            exp_log_methods_generic exp_log_methods_tangent exp_log_methods_adjoint
            exp_log_methods_jacobian exp_log_methods_hessian exp_log_methods_second),
        case!(vector Corpus::exp_log_paths[&CORPUS](x: f64, y: f64) in (0.2, 1.5);
            exp_log_paths_generic exp_log_paths_tangent exp_log_paths_adjoint exp_log_paths_jacobian
            exp_log_paths_hessian exp_log_paths_second),
        case!(vector Corpus::power_methods[&CORPUS](x: f64, y: f64) in (0.2, 1.2);
            power_methods_generic power_methods_tangent power_methods_adjoint power_methods_jacobian
            power_methods_hessian power_methods_second),
        case!(vector Corpus::power_paths[&CORPUS](x: f64, y: f64) in (0.2, 1.2);
            power_paths_generic power_paths_tangent power_paths_adjoint power_paths_jacobian
            power_paths_hessian power_paths_second),
        case!(vector Corpus::nonsmooth_methods[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            nonsmooth_methods_generic nonsmooth_methods_tangent nonsmooth_methods_adjoint
            nonsmooth_methods_jacobian nonsmooth_methods_hessian nonsmooth_methods_second),
        case!(vector Corpus::nonsmooth_paths[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            nonsmooth_paths_generic nonsmooth_paths_tangent nonsmooth_paths_adjoint
            nonsmooth_paths_jacobian nonsmooth_paths_hessian nonsmooth_paths_second),
        case!(scalar Corpus::math_constants[&CORPUS](x: f64) in (-1.0, 1.0);
            math_constants_generic math_constants_tangent math_constants_gradient
            math_constants_jacobian math_constants_hessian math_constants_second),
        case!(scalar Corpus::square[](x: f64) in (-2.0, 2.0);
            square_generic square_tangent square_gradient square_jacobian square_hessian
            square_second),
        case!(scalar Corpus::norm[&CORPUS](v: &[f64; 3]) in (-1.0, 1.0);
            norm_generic norm_tangent norm_gradient norm_jacobian norm_hessian norm_second),
        case!(vector Corpus::rotate[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            rotate_generic rotate_tangent rotate_adjoint rotate_jacobian rotate_hessian
            rotate_second),
        case!(scalar Corpus::calls[&CORPUS](v: &[f64; 3]) in (-1.0, 1.0);
            calls_generic calls_tangent calls_gradient calls_jacobian calls_hessian calls_second),
        case!(scalar Corpus::select_value[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            select_value_generic select_value_tangent select_value_gradient select_value_jacobian
            select_value_hessian select_value_second),
        case!(scalar Corpus::statement_if[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            statement_if_generic statement_if_tangent statement_if_gradient statement_if_jacobian
            statement_if_hessian statement_if_second),
        case!(scalar Corpus::else_if_chain[&CORPUS](x: f64) in (-1.0, 1.0);
            else_if_chain_generic else_if_chain_tangent else_if_chain_gradient
            else_if_chain_jacobian else_if_chain_hessian else_if_chain_second),
        case!(scalar Corpus::logical_conditions[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            logical_conditions_generic logical_conditions_tangent logical_conditions_gradient
            logical_conditions_jacobian logical_conditions_hessian logical_conditions_second),
        case!(scalar Corpus::sqrt_guard[&CORPUS](x: f64) in (-1.0, 1.0);
            sqrt_guard_generic sqrt_guard_tangent sqrt_guard_gradient sqrt_guard_jacobian
            sqrt_guard_hessian sqrt_guard_second),
        case!(scalar Corpus::guarded_logs[&CORPUS](x: f64, y: f64) in (-1.0, 1.0);
            guarded_logs_generic guarded_logs_tangent guarded_logs_gradient guarded_logs_jacobian
            guarded_logs_hessian guarded_logs_second),
        case!(scalar Corpus::loop_with_guards[&CORPUS](v: &[f64; 5]) in (-1.0, 1.0);
            loop_with_guards_generic loop_with_guards_tangent loop_with_guards_gradient
            loop_with_guards_jacobian loop_with_guards_hessian loop_with_guards_second),
        case!(scalar Corpus::rosenbrock[&CORPUS](v: &[f64; 6]) in (-1.5, 1.5);
            rosenbrock_generic rosenbrock_tangent rosenbrock_gradient rosenbrock_jacobian
            rosenbrock_hessian rosenbrock_second),
        case!(scalar Corpus::kepler[&CORPUS](q: &[f64; 2], p: &[f64; 2]) in (0.3, 1.5);
            kepler_generic kepler_tangent kepler_gradient kepler_jacobian kepler_hessian
            kepler_second),
        case!(scalar Robot::heading[&ROBOT](phi1: f64, phi2: f64) in (-3.0, 3.0);
            heading_generic heading_tangent heading_gradient heading_jacobian heading_hessian
            heading_second),
        case!(scalar Robot::lagrangian[&ROBOT](q: &[f64; 5], qd: &[f64; 5]) in (-1.5, 1.5);
            lagrangian_generic lagrangian_tangent lagrangian_gradient lagrangian_jacobian
            lagrangian_hessian lagrangian_second),
        case!(vector Robot::velocity_rows[&ROBOT](q: &[f64; 5], qd: &[f64; 5]) in (-1.5, 1.5);
            velocity_rows_generic velocity_rows_tangent velocity_rows_adjoint velocity_rows_jacobian
            velocity_rows_hessian velocity_rows_second),
        case!(scalar Chain::lagrangian[&CHAIN](q: &[f64; 20], qd: &[f64; 20]) in (-1.5, 1.5);
            lagrangian_generic lagrangian_tangent lagrangian_gradient lagrangian_jacobian
            lagrangian_hessian lagrangian_second),
    ]
}

fn case_named(name: &str) -> Case {
    cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no corpus function `{name}`"))
}

// ---------------------------------------------------------------------------------------
// The tests
// ---------------------------------------------------------------------------------------

/// Every corpus function: value against rustc, derivatives against num-dual.
#[test]
fn corpus_agrees_with_rustc_and_num_dual() {
    let start = Instant::now();
    let cases = cases();
    assert!(
        cases.len() >= 30,
        "the corpus must hold at least 30 functions"
    );
    let mut report = Report::default();
    for case in &cases {
        run_case(case, &mut report);
    }
    println!(
        "engine corpus: {} functions × {POINTS} points: {} objects ({} entries) compared in {:.2?}",
        cases.len(),
        report.objects,
        report.entries,
        start.elapsed()
    );
    println!(
        "directions redrawn {} times for conditioning",
        report.redrawn
    );
    let shown: Vec<&String> = report.failures.iter().take(40).collect();
    assert!(
        report.failures.is_empty(),
        "{} entries disagree; the first ones:\n{}",
        report.failures.len(),
        shown
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n")
    );
}

/// The guards are only tested if the points fall on both sides of the boundary, where the
/// untaken branch is NaN.
#[test]
fn domain_guards_are_checked_on_both_sides() {
    for name in [
        "Corpus::sqrt_guard",
        "Corpus::guarded_logs",
        "Corpus::else_if_chain",
        "Corpus::loop_with_guards",
    ] {
        let case = case_named(name);
        let mut report = Report::default();
        let points = run_case(&case, &mut report);
        let negative = points.iter().filter(|x| x[0] < 0.0).count();
        let positive = points.iter().filter(|x| x[0] > 0.0).count();
        assert!(
            negative >= 3 && positive >= 3,
            "{name}: {negative} points below and {positive} above the guard"
        );
        assert!(report.failures.is_empty(), "{name}: {:#?}", report.failures);
    }
    // At x < 0 `sqrt_guard` is identically zero: every derivative must be exactly zero, not NaN.
    let x = -0.25;
    assert_eq!(CORPUS.sqrt_guard_gradient(x), [0.0]);
    assert_eq!(CORPUS.sqrt_guard_hessian(x), [[0.0]]);
    assert_eq!(CORPUS.sqrt_guard_second(x, &[1.0], &[1.0]), [0.0]);
    assert_eq!(CORPUS.sqrt_guard_tangent(x, &[1.0]), [0.0]);
}

/// The cheap-gradient principle on the two mechanical models: one gradient or one tangent
/// costs a small multiple of the function.
#[test]
fn cheap_gradient_principle() {
    let models = [
        ("robot Lagrangian (n = 10)", Robot::LAGRANGIAN_OPS),
        ("20-link chain (n = 40)", Chain::LAGRANGIAN_OPS),
    ];
    println!(
        "{:<26} {:>9} {:>15} {:>15} {:>15} {:>15}",
        "operations", "function", "gradient", "full Hessian", "one second", "tangent"
    );
    for (name, ops) in models {
        let ratio = |count: usize| format!("{count} ({:.1}×)", count as f64 / ops.function as f64);
        println!(
            "{name:<26} {:>9} {:>15} {:>15} {:>15} {:>15}",
            ops.function,
            ratio(ops.gradient),
            ratio(ops.hessian),
            ratio(ops.second),
            ratio(ops.tangent)
        );
    }
    for (name, ops) in models {
        assert!(ops.function > 0, "{name}: no operations counted");
        assert!(
            ops.gradient <= 5 * ops.function,
            "{name}: gradient {} > 5 × {}",
            ops.gradient,
            ops.function
        );
        assert!(
            ops.tangent <= 5 * ops.function,
            "{name}: tangent {} > 5 × {}",
            ops.tangent,
            ops.function
        );
    }
}

/// The comparison itself: just inside the tolerance passes, just outside fails, and so do
/// NaN and a wrong length. A near-zero entry is judged on the object's scale.
#[test]
fn comparison_is_strict() {
    let mut report = Report::default();
    report.compare(
        "self-test",
        0,
        "inside",
        &[1.0 + 0.5e-12, -2.0, 1e-13],
        &[1.0, -2.0, 0.0],
    );
    assert!(report.failures.is_empty(), "{:#?}", report.failures);
    report.compare(
        "self-test",
        0,
        "outside",
        &[1.0, -2.0 - 5e-12],
        &[1.0, -2.0],
    );
    report.compare("self-test", 0, "cancelled", &[1.0, 3e-12], &[1.0, 0.0]);
    report.compare("self-test", 0, "nan", &[f64::NAN], &[1.0]);
    report.compare("self-test", 0, "length", &[1.0], &[1.0, 2.0]);
    assert_eq!(report.failures.len(), 4, "{:#?}", report.failures);
    assert_eq!(report.objects, 5);
}

/// The harness catches a derivative that is off by a relative 1e-11: a case whose
/// generated methods are replaced by slightly wrong ones must fail in each of them.
#[test]
fn harness_detects_wrong_derivatives() {
    const OFF: f64 = 1.0 + 1e-11;
    let mut case = case_named("Corpus::arithmetic");
    case.tangent = |x, d| {
        CORPUS
            .arithmetic_tangent(x[0], x[1], &[d[0], d[1]])
            .map(|t| t * OFF)
            .to_vec()
    };
    case.gradient = |x, _| {
        CORPUS
            .arithmetic_gradient(x[0], x[1])
            .map(|g| g * OFF)
            .to_vec()
    };
    case.hessian = |x, _| {
        let mut h = CORPUS.arithmetic_hessian(x[0], x[1]);
        h[0][1] *= OFF;
        h.iter().flatten().copied().collect()
    };
    case.second =
        |x, u, v| vec![CORPUS.arithmetic_second(x[0], x[1], &[u[0], u[1]], &[v[0], v[1]])[0] * OFF];
    let mut report = Report::default();
    run_case(&case, &mut report);
    for what in ["tangent", "gradient", "hessian", "second"] {
        let count = report
            .failures
            .iter()
            .filter(|f| f.contains(&format!(" {what}[")))
            .count();
        assert!(
            count >= POINTS / 2,
            "a wrong {what} was caught at only {count} of {POINTS} points"
        );
    }
    assert!(
        !report
            .failures
            .iter()
            .any(|f| f.contains(" value[") || f.contains(" jacobian["))
    );
}

/// The corpus robot is the paper's: in the quasi-velocities of `hamel::docs::design`
/// ("Worked example") its mass matrix M_kl = B_kᵀ (∂²L/∂q̇²) B_l (k, l = 3, 4, 5) has the
/// stated entries, and the velocity rows A(q) map those columns B_k of B = A⁻¹ to the unit
/// vectors e_k.
#[test]
fn robot_matches_the_worked_example() {
    let Robot {
        m0,
        mw,
        jx,
        jy,
        jz,
        r,
        b,
        l,
        ..
    } = ROBOT;
    let mut rng = Rng::for_name("robot worked example");
    let mut report = Report::default();
    for p in 0..POINTS {
        let q: [f64; 5] = rng.vector(5, -1.5, 1.5).try_into().unwrap();
        let qd: [f64; 5] = rng.vector(5, -1.5, 1.5).try_into().unwrap();
        let alpha = q[2];
        let (s, c) = ROBOT.heading(q[3], q[4]).sin_cos();
        let k = b / (2.0 * r);
        // q̇ = B₃ω³ + B₄ω⁴ + B₅ω⁵ (`hamel::docs::design`, kinematics).
        let columns = [
            [0.0, 0.0, 1.0, -1.0, -1.0],
            [c, s, 0.0, 1.0 / r, 1.0 / r],
            [0.0, 0.0, 0.0, k, -k],
        ];

        // ∂²L/∂q̇² is the lower right block of the Hessian in (q, q̇).
        let hessian = ROBOT.lagrangian_hessian(&q, &qd);
        let quadratic = |u: &[f64; 5], v: &[f64; 5]| -> f64 {
            (0..5)
                .flat_map(|i| (0..5).map(move |j| u[i] * hessian[5 + i][5 + j] * v[j]))
                .sum()
        };
        let mass: Vec<f64> = columns
            .iter()
            .flat_map(|u| columns.iter().map(|v| quadratic(u, v)))
            .collect();
        let (sa, ca) = alpha.sin_cos();
        let j5 = (jx + m0 * l * l) * sa * sa + jz * ca * ca + 0.75 * mw * b * b + 0.5 * mw * r * r;
        let expected = [
            [jy + m0 * l * l, m0 * l * ca, 0.0],
            [m0 * l * ca, m0 + 3.0 * mw, 0.0],
            [0.0, 0.0, j5],
        ];
        report.compare("robot", p, "mass matrix", &mass, expected.as_flattened());

        // ω = A(q) q̇ is linear in q̇: A is the q̇ block of the rows' Jacobian.
        let jacobian = ROBOT.velocity_rows_jacobian(&q, &qd);
        let images: Vec<f64> = columns
            .iter()
            .flat_map(|u| {
                jacobian
                    .iter()
                    .map(|row| (0..5).map(|j| row[5 + j] * u[j]).sum::<f64>())
            })
            .collect();
        let unit = [
            [0.0, 0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 0.0, 1.0],
        ];
        report.compare("robot", p, "A·B", &images, unit.as_flattened());
    }
    assert!(report.failures.is_empty(), "{:#?}", report.failures);
}
