//! Where the model's code is optimized: one function per kind of call, each in a module of
//! its own and never inlined, which calls the model's code of one family (`RHS`, `OUTPUTS`,
//! `LIE`) through [`Model`].
//!
//! Why: an exporting crate is mostly this code (straight-line, hundreds of thousands of
//! instructions for the bicycle's second derivatives), and rustc splits a crate into
//! codegen units by module, here by the module of the generic function an instance comes
//! from. Inlined into the exported functions (all of which reach every family, chosen at run
//! time), it was optimized once per caller, in one codegen unit, on one core: the bicycle's
//! library took 6-7 min to build. Reached from these functions only, each piece is
//! optimized once, and the pieces on as many cores as there are. A call costs a few
//! instructions; the work inside is hundreds to thousands.

use crate::layout::Destinations;
use crate::model::Model;
use core::mem::MaybeUninit;
use hamel_runtime::{Scalar, Singularity};

/// The right-hand side's family.
pub const RHS: u8 = 0;
/// The outputs' family.
pub const OUTPUTS: u8 = 1;
/// The Lie derivatives' family.
pub const LIE: u8 = 2;

/// A compiled call's result in a register: an `Option<Result<(), Singularity>>` is
/// returned through memory, written by the callee and read back by the caller (4
/// instructions of `adj1_f`, `hamel-export/bench/instructions.sh`); the singularity, when
/// there is one, is written where the caller says.
#[derive(Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Outcome {
    Done,
    Singular,
    NotCompiled,
}

impl Outcome {
    #[inline(always)]
    fn of(result: Option<Result<(), Singularity>>, error: &mut MaybeUninit<Singularity>) -> Self {
        match result {
            Some(Ok(())) => Outcome::Done,
            Some(Err(e)) => {
                error.write(e);
                Outcome::Singular
            }
            None => Outcome::NotCompiled,
        }
    }

    /// # Safety
    /// `error` is written if `self` is `Singular`.
    #[inline(always)]
    unsafe fn result(self, error: MaybeUninit<Singularity>) -> Option<Result<(), Singularity>> {
        match self {
            Outcome::Done => Some(Ok(())),
            // SAFETY: the caller's contract.
            Outcome::Singular => Some(Err(unsafe { error.assume_init() })),
            Outcome::NotCompiled => None,
        }
    }
}

/// The compiled values.
pub mod value {
    use super::*;

    #[inline(never)]
    pub fn call<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        out: &mut [f64],
    ) -> Option<Result<(), Singularity>> {
        M::value_of::<W>(prepared, z, out)
    }
}

/// The compiled Jacobian.
pub mod jacobian {
    use super::*;

    /// # Safety
    /// As [`Model::jacobian_of`].
    #[inline(never)]
    pub unsafe fn call<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        parameters: bool,
        to: &Destinations,
    ) -> Option<Result<bool, Singularity>> {
        // SAFETY: the caller's contract.
        unsafe { M::jacobian_of::<W>(prepared, z, parameters, to) }
    }
}

/// The right-hand side's forward derivatives as products of its compiled Jacobian.
pub mod products {
    use super::*;
    use core::mem::MaybeUninit;

    /// # Safety
    /// As [`Model::products_of`].
    #[inline(never)]
    pub unsafe fn call<M: Model, const N: usize>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        directions: &M::Array<MaybeUninit<[f64; N]>>,
        out: &mut M::Array<MaybeUninit<[f64; N]>>,
    ) -> Option<Result<bool, Singularity>> {
        // SAFETY: the caller's contract.
        unsafe { M::products_of::<N>(prepared, z, directions, out) }
    }
}

/// The compiled forward derivative.
pub mod forward {
    use super::*;

    #[inline(never)]
    pub fn call<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        direction: &[f64],
        parameters: bool,
        out: &mut [f64],
    ) -> Option<Result<(), Singularity>> {
        M::forward_of::<W>(prepared, z, direction, parameters, out)
    }
}

/// The compiled adjoint derivative.
pub mod adjoint {
    use super::*;

    #[inline(always)]
    pub fn call<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        weights: &[f64],
        parameters: bool,
        out: &mut M::Array<MaybeUninit<f64>>,
    ) -> Option<Result<(), Singularity>> {
        let mut error = MaybeUninit::uninit();
        let outcome = compiled::<M, W>(prepared, z, weights, parameters, out, &mut error);
        // SAFETY: `compiled` wrote the singularity if it says so.
        unsafe { outcome.result(error) }
    }

    #[inline(never)]
    fn compiled<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        weights: &[f64],
        parameters: bool,
        out: &mut M::Array<MaybeUninit<f64>>,
        error: &mut MaybeUninit<Singularity>,
    ) -> Outcome {
        Outcome::of(
            M::adjoint_of::<W>(prepared, z, weights, parameters, out),
            error,
        )
    }
}

/// The compiled second derivatives (and the Jacobian).
pub mod second {
    use super::*;

    /// # Safety
    /// As [`Model::second_of`].
    #[inline(never)]
    pub unsafe fn call<M: Model, const W: u8>(
        prepared: &M::Prepared,
        z: &M::Array<f64>,
        weights: &[f64],
        parameters: bool,
        to: &Destinations,
    ) -> Option<Result<bool, Singularity>> {
        // SAFETY: the caller's contract.
        unsafe { M::second_of::<W>(prepared, z, weights, parameters, to) }
    }
}

/// The right-hand side over any scalar (the dual-number passes).
pub mod rhs {
    use super::*;

    #[inline(never)]
    pub fn call<M: Model, S: Scalar>(
        z: &M::Array<S>,
        out: &mut M::Array<S>,
    ) -> Result<(), Singularity> {
        M::rhs(z, out)
    }
}

/// The outputs over any scalar.
pub mod outputs {
    use super::*;

    #[inline(never)]
    pub fn call<M: Model, S: Scalar>(z: &M::Array<S>, out: &mut M::Array<S>) {
        M::outputs(z, out)
    }
}

/// The Lie derivatives over any scalar.
pub mod lie {
    use super::*;

    #[inline(never)]
    pub fn call<M: Model, S: Scalar>(
        z: &M::Array<S>,
        out: &mut M::Array<S>,
    ) -> Result<(), Singularity> {
        M::lie(z, out)
    }
}
