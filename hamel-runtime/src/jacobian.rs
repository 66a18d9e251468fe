//! The Jacobian of a generated right-hand side by dual numbers (num-dual's `DualSVec64`)
//! run through its generic form `rhs_generic`: forward-mode derivatives, exact to rounding,
//! through everything the generated code does, its unrolled factorizations and their pivot
//! choices included (a comparison of dual numbers compares their values, so the branch the
//! `f64` code takes is the branch the dual code takes).
//!
//! The directions are the state's and the inputs' unit vectors, `LANES` of them per pass:
//! one instantiation of the right-hand side for one dual type, however large the system.

use crate::error::Singularity;
use crate::scalar::Scalar;
use nalgebra::{Const, U1};
use num_dual::{Derivative, DualNum, DualSVec64};

/// Directions per pass. Wider passes amortize the value part of every operation over more
/// directions but make each operation, and the instantiated code, larger.
pub const LANES: usize = 4;

/// The dual number the Jacobian passes compute in.
pub type JacobianDual = DualSVec64<LANES>;

macro_rules! forward {
    ($($name:ident),*) => {
        $(
            #[inline(always)]
            fn $name(self) -> Self {
                DualNum::$name(&self)
            }
        )*
    };
}

impl<const N: usize> Scalar for DualSVec64<N> {
    #[inline(always)]
    fn from_f64(value: f64) -> Self {
        DualSVec64::from_re(value)
    }

    #[inline(always)]
    fn re(self) -> f64 {
        self.re
    }

    forward!(
        sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, ln, log10, sqrt, cbrt
    );

    #[inline(always)]
    fn abs(self) -> Self {
        abs_taken_branch(self)
    }

    #[inline(always)]
    fn signum(self) -> Self {
        DualSVec64::from_re(self.re.signum())
    }

    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        DualNum::powi(&self, n)
    }

    #[inline(always)]
    fn powf(self, exponent: Self) -> Self {
        DualNum::powd(&self, exponent)
    }

    #[inline(always)]
    fn atan2(self, other: Self) -> Self {
        DualNum::atan2(&self, other)
    }

    /// √(a² + b²) (num-dual has no `hypot`; the scaling that protects `f64::hypot` from
    /// overflow does not matter to a derivative).
    #[inline(always)]
    fn hypot(self, other: Self) -> Self {
        DualNum::sqrt(&(self * self + other * other))
    }
}

/// |x| with the derivative of the branch taken (−x for x < 0), as `f64::abs` is
/// differentiated by the engine.
#[inline(always)]
fn abs_taken_branch<const N: usize>(x: DualSVec64<N>) -> DualSVec64<N> {
    if x.re < 0.0 { -x } else { x }
}

/// ∂F/∂x (row-major, S × S) and ∂F/∂u (row-major, S × M) of `rhs` at (t, x, u). `SS` and
/// `SM` are S·S and S·M (the generated code's array lengths).
pub fn jacobian_by_duals<const S: usize, const M: usize, const SS: usize, const SM: usize>(
    t: f64,
    x: &[f64; S],
    u: &[f64; M],
    mut rhs: impl FnMut(
        JacobianDual,
        &[JacobianDual; S],
        &[JacobianDual; M],
        &mut [JacobianDual; S],
    ) -> Result<(), Singularity>,
) -> Result<([f64; SS], [f64; SM]), Singularity> {
    let mut state = [0.0; SS];
    let mut input = [0.0; SM];
    let directions = S + M;
    let t = JacobianDual::from_re(t);
    for start in (0..directions).step_by(LANES) {
        let seed = |value: f64, direction: usize| {
            let d = JacobianDual::from_re(value);
            match direction.checked_sub(start) {
                Some(lane) if lane < LANES => d.derivative(lane),
                _ => d,
            }
        };
        let xd: [JacobianDual; S] = core::array::from_fn(|i| seed(x[i], i));
        let ud: [JacobianDual; M] = core::array::from_fn(|i| seed(u[i], S + i));
        let mut dx = [JacobianDual::from_re(0.0); S];
        rhs(t, &xd, &ud, &mut dx)?;
        for (row, value) in dx.iter().enumerate() {
            let lanes = Derivative::unwrap_generic(value.eps, Const::<LANES>, U1);
            for (lane, d) in lanes.iter().enumerate() {
                let column = start + lane;
                let slot = if column < S {
                    state.get_mut(row * S + column)
                } else if column < directions {
                    input.get_mut(row * M + column - S)
                } else {
                    None
                };
                if let Some(slot) = slot {
                    *slot = *d;
                }
            }
        }
    }
    Ok((state, input))
}
