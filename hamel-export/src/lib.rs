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
//! - [`model`](mod@model): a model as the export sees it, its functions on one flat argument
//!   vector z = (x, u, p, t) over any scalar type ([`model!`] implements it from what
//!   `#[hamel_system]` generates); [`primal`]: those functions with their inputs and the
//!   dependencies the generated code's graph gives (the sparsity of every derivative);
//!   [`passes`]: one evaluation in `f64`, dual or hyper-dual numbers.
//! - [`c_api`](mod@c_api): the plain C functions; [`casadi`](mod@casadi): CasADi's
//!   convention; [`header`]: the C header, from the names, units and doc comments the model
//!   carries; [`fmi2`](mod@fmi2): the model as an FMU of FMI 2.0 (Model Exchange and
//!   Co-Simulation), with [`fmi2!`].
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
pub mod layout;
mod macros;
pub mod model;
pub mod passes;
pub mod primal;
#[doc(hidden)]
pub mod units;

pub use model::{Model, Sizes};
pub use primal::Which;

/// What the macros' expansions name, from the crate that uses them.
#[doc(hidden)]
pub mod __private {
    pub use crate::cache::{Cache, First};
    pub use crate::casadi::sparsity::CasadiInt;
    pub use core::ffi::{c_char, c_int};
    pub use hamel_runtime::{HamelSystem, Parameters, Scalar, Singularity};

    /// For each of `wanted`, its position in `names`: the parameters the generated code reads,
    /// in the order of the struct's fields. `Err` with the first name that `names` lacks, which
    /// [`model!`](macro@crate::model) turns into a compile error with [`unlisted_parameter`].
    pub const fn positions<const K: usize>(
        names: &[&str],
        wanted: &[&'static str],
    ) -> Result<[usize; K], &'static str> {
        let mut out = [0; K];
        let mut k = 0;
        while k < K {
            let mut i = 0;
            loop {
                if i == names.len() {
                    return Err(wanted[k]);
                }
                if equal(names[i].as_bytes(), wanted[k].as_bytes()) {
                    break;
                }
                i += 1;
            }
            out[k] = i;
            k += 1;
        }
        Ok(out)
    }

    /// The compile error of a model whose generated code reads a parameter (`self.name`)
    /// that its `Parameters::NAMES` does not list: the export passes parameters by those
    /// names, so it cannot give that one a place in `p`. Built in a const evaluation (which
    /// cannot format), as bytes.
    pub const fn unlisted_parameter(name: &str) -> Message {
        Message::new(&[
            "hamel-export: the model's functions read the parameter `",
            name,
            "` (`self.",
            name,
            "`), which `Parameters::NAMES` of its parameter struct does not list. The \
             exported functions take the parameters by those names: make `",
            name,
            "` an `f64` field of the struct under `#[hamel_system]`, or list it in the \
             `NAMES` of an `impl Parameters` written by hand.",
        ])
    }

    /// A message composed in a const evaluation: at most `MESSAGE_CAPACITY` bytes, cut at a
    /// character boundary.
    pub struct Message {
        bytes: [u8; MESSAGE_CAPACITY],
        len: usize,
    }

    /// Room for the message and a parameter's name several hundred bytes long.
    const MESSAGE_CAPACITY: usize = 1024;

    impl Message {
        const fn new(parts: &[&str]) -> Message {
            let mut message = Message {
                bytes: [0; MESSAGE_CAPACITY],
                len: 0,
            };
            let mut p = 0;
            while p < parts.len() {
                let part = parts[p].as_bytes();
                let mut i = 0;
                while i < part.len() && message.len < MESSAGE_CAPACITY {
                    message.bytes[message.len] = part[i];
                    message.len += 1;
                    i += 1;
                }
                p += 1;
            }
            message
        }

        pub const fn as_str(&self) -> &str {
            let (mut text, _) = self.bytes.split_at(self.len);
            // A name longer than the capacity may have been cut inside a character.
            loop {
                match core::str::from_utf8(text) {
                    Ok(s) => return s,
                    Err(e) => text = text.split_at(e.valid_up_to()).0,
                }
            }
        }
    }

    pub const fn max(a: usize, b: usize) -> usize {
        if a > b { a } else { b }
    }

    /// Whether `read` holds every position `0..n` (each parameter read by the generated
    /// code).
    pub const fn reads_all(read: &[usize], n: usize) -> bool {
        let mut i = 0;
        while i < n {
            let mut found = false;
            let mut k = 0;
            while k < read.len() {
                found |= read[k] == i;
                k += 1;
            }
            if !found {
                return false;
            }
            i += 1;
        }
        true
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

    /// Whether a compiled adjoint that writes the columns `writes[0]` always and
    /// `writes[1]` with `parameters` writes every one of its `states + parameters + 1`
    /// columns (x and u, the parameters read, t): those of x, u and t always, the
    /// parameters' at least with `parameters`.
    pub const fn writes_every_column(
        writes: [&[usize]; 2],
        states: usize,
        parameters: usize,
    ) -> bool {
        let [always, also] = writes;
        let mut c = 0;
        while c <= states + parameters {
            let parameter = c >= states && c < states + parameters;
            let written = contains(always, c) || (parameter && contains(also, c));
            if !written {
                return false;
            }
            c += 1;
        }
        true
    }

    const fn contains(list: &[usize], value: usize) -> bool {
        let mut k = 0;
        while k < list.len() {
            if list[k] == value {
                return true;
            }
            k += 1;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::__private::{positions, unlisted_parameter};

    #[test]
    fn positions_are_the_names_places_or_the_first_missing_name() {
        let names = ["m0", "mw", "r", "b"];
        assert_eq!(positions::<3>(&names, &["r", "m0", "b"]), Ok([2, 0, 3]));
        assert_eq!(positions::<0>(&names, &[]), Ok([]));
        assert_eq!(positions::<3>(&names, &["r", "l", "g"]), Err("l"));
    }

    #[test]
    fn reads_all_is_every_position_read() {
        use super::__private::reads_all;
        assert!(reads_all(&[2, 0, 1], 3));
        assert!(reads_all(&[], 0));
        assert!(!reads_all(&[0, 2], 3));
        assert!(!reads_all(&[0, 0, 1], 3));
        assert!(reads_all(&[1, 0], 2));
    }

    #[test]
    fn every_column_written_is_x_u_t_always_and_the_parameters_with_them() {
        use super::__private::writes_every_column;
        // x, u: 0..3; parameters: 3..5; t: 5.
        assert!(writes_every_column([&[0, 1, 2, 5], &[3, 4]], 3, 2));
        assert!(writes_every_column([&[5, 2, 1, 0, 4, 3], &[]], 3, 2));
        assert!(writes_every_column([&[0, 1], &[]], 1, 0));
        // A column of x, the parameters' one, t missing; t only with `parameters`.
        assert!(!writes_every_column([&[0, 2, 5], &[3, 4]], 3, 2));
        assert!(!writes_every_column([&[0, 1, 2, 5], &[3]], 3, 2));
        assert!(!writes_every_column([&[0, 1, 2], &[3, 4]], 3, 2));
        assert!(!writes_every_column([&[0, 1, 2], &[3, 4, 5]], 3, 2));
    }

    #[test]
    fn the_compile_error_names_the_parameter_and_what_to_do() {
        let message = unlisted_parameter("wheel_radius");
        let text = message.as_str();
        assert!(
            text.starts_with(
                "hamel-export: the model's functions read the parameter `wheel_radius` \
                 (`self.wheel_radius`), which `Parameters::NAMES`"
            ),
            "{text}"
        );
        assert!(text.ends_with("written by hand."), "{text}");
    }

    #[test]
    fn a_message_past_its_capacity_is_cut_at_a_character_boundary() {
        // 'é' is two bytes: 600 of them overflow the capacity inside a character.
        let name = "é".repeat(600);
        let message = unlisted_parameter(&name);
        let text = message.as_str();
        assert!(text.len() <= 1024 && text.len() >= 1022, "{}", text.len());
        assert!(text.ends_with('é'), "{text}");
    }
}
