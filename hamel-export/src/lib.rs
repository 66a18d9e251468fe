//! A hamel model as a C library: the layer between a model's generated code and a C caller,
//! and CasADi's external-function convention on top of it, so that CasADi (and through it
//! IPOPT, acados, …) loads a model with its exact derivatives:
//!
//! ```ignore
//! // In a crate of type cdylib:
//! hamel_export::model!(Robot => hamel::models::MobileRobot);
//! hamel_export::c_api!(Robot, "mobile_robot");   // mobile_robot_rhs, mobile_robot_last_error…
//! hamel_export::casadi!(Robot, "mobile_robot");  // mobile_robot_f, jac_mobile_robot_f, …
//! // and its header, from a build step or a small binary:
//! std::fs::write("mobile_robot.h", hamel_export::header::header::<Robot>("mobile_robot"))?;
//! ```
//!
//! Layers, one module each:
//! - [`abi`]: the boundary. No panic crosses it (every entry is caught), failures are status
//!   codes with a per-thread message (`<model>_last_error`); null pointers, lengths and
//!   values that are not finite are checked and named.
//! - [`model`]: a model as the export sees it, its functions on one flat argument vector
//!   z = (x, u, p, t) over any scalar type ([`model!`] implements it from what
//!   `#[hamel_system]` generates); [`primal`]: those functions with their inputs and the
//!   dependencies the generated code's graph gives (the sparsity of every derivative);
//!   [`passes`]: one evaluation in `f64`, dual or hyper-dual numbers.
//! - [`c_api`]: the plain C functions; [`casadi`]: CasADi's convention; [`header`]: the C
//!   header, from the names, units and doc comments the model carries; [`fmi2`]: the model as
//!   an FMU of FMI 2.0 (Model Exchange and Co-Simulation), with [`fmi2!`].
//!
//! `hamel::docs::export` is the guide; `cargo run --release --example export -- casadi
//! mobile_robot OUTDIR` builds the library and header of any catalogue model.

pub mod abi;
pub mod c_api;
mod cache;
pub mod casadi;
pub mod fmi2;
pub mod header;
pub mod hyper;
mod macros;
pub mod model;
pub mod passes;
pub mod primal;

pub use model::{Model, Sizes};
pub use primal::Which;

/// What the macros' expansions name, from the crate that uses them.
#[doc(hidden)]
pub mod __private {
    pub use crate::cache::Cache;
    pub use crate::casadi::sparsity::CasadiInt;
    pub use core::ffi::{c_char, c_int};
    pub use hamel_runtime::{HamelSystem, Parameters, Scalar, Singularity};

    /// For each of `wanted`, its position in `names`: the parameters the generated code reads,
    /// in the order of the struct's fields. A name that is not there (a model whose generated
    /// code reads a parameter its struct does not list: a bug) stops the build.
    pub const fn positions<const K: usize>(names: &[&str], wanted: &[&str]) -> [usize; K] {
        let mut out = [0; K];
        let mut k = 0;
        while k < K {
            let mut i = 0;
            loop {
                if i == names.len() {
                    panic!("hamel-export: a parameter the model reads is not in Parameters::NAMES");
                }
                if equal(names[i].as_bytes(), wanted[k].as_bytes()) {
                    break;
                }
                i += 1;
            }
            out[k] = i;
            k += 1;
        }
        out
    }

    pub const fn max(a: usize, b: usize) -> usize {
        if a > b { a } else { b }
    }

    /// The first `N` values of `values` as an array; `None` when there are fewer.
    #[inline(always)]
    pub fn array<const N: usize>(values: &[f64]) -> Option<&[f64; N]> {
        values.get(..N)?.try_into().ok()
    }

    /// The first `N` values of `values` as an array to write; `None` when there are fewer.
    #[inline(always)]
    pub fn array_mut<const N: usize>(values: &mut [f64]) -> Option<&mut [f64; N]> {
        values.get_mut(..N)?.try_into().ok()
    }

    const fn equal(a: &[u8], b: &[u8]) -> bool {
        if a.len() != b.len() {
            return false;
        }
        let mut i = 0;
        while i < a.len() {
            if a[i] != b[i] {
                return false;
            }
            i += 1;
        }
        true
    }
}
