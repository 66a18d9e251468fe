//! The bodies of the CasADi symbols [`crate::casadi!`] exports, one function each: the
//! macro's wrappers only name them. Each is guarded: an index out of range is a null pointer
//! (or −1) with the message kept for `<model>_last_error`, never a panic across the boundary.

use super::sparsity::CasadiInt;
use super::{Family, Kind};
use crate::abi::{guard_value, set_last_error};
use core::ffi::{c_char, c_int};

pub fn n_in(family: &Family, kind: Kind) -> CasadiInt {
    family.function(kind).inputs.len() as CasadiInt
}

pub fn n_out(family: &Family, kind: Kind) -> CasadiInt {
    family.function(kind).outputs.len() as CasadiInt
}

fn out_of_range<T>(what: &str, i: CasadiInt, n: usize, none: T) -> T {
    set_last_error(&format!("{what}: index {i} is out of range (0..{n})"));
    none
}

pub fn name_in(family: &Family, kind: Kind, i: CasadiInt) -> *const c_char {
    guard_value("name_in", core::ptr::null(), || {
        let ports = &family.function(kind).inputs;
        match usize::try_from(i).ok().and_then(|i| ports.get(i)) {
            Some(port) => port.name.as_ptr(),
            None => out_of_range("name_in", i, ports.len(), core::ptr::null()),
        }
    })
}

pub fn name_out(family: &Family, kind: Kind, i: CasadiInt) -> *const c_char {
    guard_value("name_out", core::ptr::null(), || {
        let ports = &family.function(kind).outputs;
        match usize::try_from(i).ok().and_then(|i| ports.get(i)) {
            Some((port, _)) => port.name.as_ptr(),
            None => out_of_range("name_out", i, ports.len(), core::ptr::null()),
        }
    })
}

pub fn sparsity_in(family: &Family, kind: Kind, i: CasadiInt) -> *const CasadiInt {
    guard_value("sparsity_in", core::ptr::null(), || {
        let ports = &family.function(kind).inputs;
        match usize::try_from(i).ok().and_then(|i| ports.get(i)) {
            Some(port) => port.pattern.compressed.as_ptr(),
            None => out_of_range("sparsity_in", i, ports.len(), core::ptr::null()),
        }
    })
}

pub fn sparsity_out(family: &Family, kind: Kind, i: CasadiInt) -> *const CasadiInt {
    guard_value("sparsity_out", core::ptr::null(), || {
        let ports = &family.function(kind).outputs;
        match usize::try_from(i).ok().and_then(|i| ports.get(i)) {
            Some((port, _)) => port.pattern.compressed.as_ptr(),
            None => out_of_range("sparsity_out", i, ports.len(), core::ptr::null()),
        }
    })
}

/// The work arrays CasADi must pass: as many argument and result pointers as ports, and no
/// integer or real work (the passes work on the stack).
///
/// # Safety
/// Each pointer is null or points to a writable `casadi_int`.
pub unsafe fn work(
    family: &Family,
    kind: Kind,
    sz_arg: *mut CasadiInt,
    sz_res: *mut CasadiInt,
    sz_iw: *mut CasadiInt,
    sz_w: *mut CasadiInt,
) -> c_int {
    let f = family.function(kind);
    let sizes = [f.inputs.len(), f.outputs.len(), 0, 0];
    for (ptr, size) in [sz_arg, sz_res, sz_iw, sz_w].into_iter().zip(sizes) {
        if !ptr.is_null() {
            // SAFETY: non-null and writable (the caller's contract).
            unsafe { *ptr = size as CasadiInt };
        }
    }
    0
}

/// The default of every input: zero.
pub fn default_in(_i: CasadiInt) -> f64 {
    0.0
}
