//! The C boundary: every exported function runs its body through [`guard`], which catches a
//! panic (none may unwind into C), turns an error into a nonzero status and keeps its message
//! for `<model>_last_error` (per thread: two threads calling at once see their own). The
//! checks of what comes from C — null pointers, lengths, values that are not finite — are
//! here too, each naming what it refused.
//!
//! Nothing on the success path allocates: the message is formatted only when there is an
//! error.

use core::ffi::{c_char, c_int};
use std::cell::RefCell;
use std::ffi::CString;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, Ordering};

/// The status codes every exported function that can fail returns (also in the header).
#[repr(i32)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    /// A pointer that must not be null was null.
    NullPointer = 1,
    /// An array's length is not the one the function takes, or an index is out of range.
    BadDimension = 2,
    /// An argument is NaN or infinite.
    NonFinite = 3,
    /// The model met a singularity (a singular transformation or mass matrix).
    Singular = 4,
    /// An internal error: a panic caught at the boundary (a bug; please report it).
    Internal = 5,
}

/// An error with the status it returns and its message.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    pub status: Status,
    pub message: String,
}

impl Failure {
    pub fn new(status: Status, message: impl Into<String>) -> Failure {
        Failure {
            status,
            message: message.into(),
        }
    }
}

thread_local! {
    /// `None` after a success. Initialized by a constant: a call's access to it is a load
    /// (no first-use check), which every successful call of every function makes.
    static LAST_ERROR: RefCell<Option<CString>> = const { RefCell::new(None) };
}

/// Whether any thread ever kept an error. Until one does, a success has no message to clear
/// and skips the thread-local (whose address a shared library asks the loader for, at every
/// call of every function).
static ANY_ERROR: AtomicBool = AtomicBool::new(false);

/// Keep `message` as this thread's last error (interior NULs, which C cannot show, become
/// spaces).
#[cold]
pub fn set_last_error(message: &str) {
    ANY_ERROR.store(true, Ordering::Relaxed);
    let clean: Vec<u8> = message
        .bytes()
        .map(|b| if b == 0 { b' ' } else { b })
        .collect();
    let text = CString::new(clean).unwrap_or_default();
    LAST_ERROR.with(|e| *e.borrow_mut() = Some(text));
}

/// This thread's last error message: empty after a success; valid until the next call from
/// this thread that fails.
pub fn last_error() -> *const c_char {
    LAST_ERROR.with(|e| match &*e.borrow() {
        Some(message) => message.as_ptr(),
        None => c"".as_ptr(),
    })
}

/// Run `body`: its status as a C int, its message kept, a panic caught and reported as
/// [`Status::Internal`]. A success clears the last error only if there was one (no
/// allocation on the success path).
#[inline(always)]
pub fn guard(function: &str, body: impl FnOnce() -> Result<(), Failure>) -> c_int {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => {
            if ANY_ERROR.load(Ordering::Relaxed) {
                clear_last_error();
            }
            Status::Ok as c_int
        }
        Ok(Err(failure)) => refuse(function, failure),
        Err(panic) => internal(function, panic),
    }
}

/// After a success: no message, if this thread kept one.
#[inline(never)]
fn clear_last_error() {
    LAST_ERROR.with(|e| {
        if let Ok(mut e) = e.try_borrow_mut() {
            if e.is_some() {
                *e = None;
            }
        }
    });
}

/// A failure's status, its message kept.
#[cold]
#[inline(never)]
fn refuse(function: &str, failure: Failure) -> c_int {
    set_last_error(&format!("{function}: {}", failure.message));
    failure.status as c_int
}

/// A panic caught: [`Status::Internal`], its message kept.
#[cold]
#[inline(never)]
fn internal(function: &str, panic: Box<dyn std::any::Any + Send>) -> c_int {
    let what = panic
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| panic.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic".to_string());
    set_last_error(&format!("{function}: internal error (a bug): {what}"));
    Status::Internal as c_int
}

/// Run `body` for a function that returns a value rather than a status (a count, a
/// pointer): `fallback` if it panics, with the message kept.
pub fn guard_value<T>(function: &str, fallback: T, body: impl FnOnce() -> T) -> T {
    match catch_unwind(AssertUnwindSafe(body)) {
        Ok(value) => value,
        Err(_) => {
            set_last_error(&format!("{function}: internal error (a bug)"));
            fallback
        }
    }
}

/// The `len` values at `ptr`, refused if `ptr` is null (unless `len` is 0).
///
/// # Safety
/// A non-null `ptr` must point to `len` readable values that stay valid and unaliased by
/// writes for the returned lifetime.
#[inline(always)]
pub unsafe fn slice<'a>(ptr: *const f64, len: usize, name: &str) -> Result<&'a [f64], Failure> {
    if len == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(null(name));
    }
    // SAFETY: non-null and, by the caller's contract, `len` readable values.
    Ok(unsafe { core::slice::from_raw_parts(ptr, len) })
}

/// The `len` values at `ptr` to write, refused if `ptr` is null (unless `len` is 0).
///
/// # Safety
/// A non-null `ptr` must point to `len` writable values not otherwise accessed for the
/// returned lifetime.
#[inline(always)]
pub unsafe fn slice_mut<'a>(
    ptr: *mut f64,
    len: usize,
    name: &str,
) -> Result<&'a mut [f64], Failure> {
    if len == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(null(name));
    }
    // SAFETY: non-null and, by the caller's contract, `len` writable values.
    Ok(unsafe { core::slice::from_raw_parts_mut(ptr, len) })
}

/// The refusal of a null `name`: out of line, so that the checks inline into every call.
#[cold]
#[inline(never)]
fn null(name: &str) -> Failure {
    Failure::new(Status::NullPointer, format!("`{name}` is a null pointer"))
}

/// A length given by the caller must be the one the function takes.
pub fn check_len(name: &str, given: usize, expected: usize) -> Result<(), Failure> {
    if given == expected {
        Ok(())
    } else {
        Err(Failure::new(
            Status::BadDimension,
            format!("`{name}` has {given} entries; the model's has {expected}"),
        ))
    }
}

/// Whether every value is zero (+0 or −0). Without a branch per value: CasADi gives
/// `fwd8_f` the directions in p as zeros when the parameters are fixed, 72 values for the
/// paper's robot, and a check value by value cost about 360 instructions a call (the
/// parking solve: 30,640 calls). On x86-64 two values at a time with SSE2: the bitwise or
/// of all of them, without the sign bits, is zero exactly when each is ±0 (a NaN or any
/// other value has a bit set besides its sign).
#[inline]
pub fn all_zero(values: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{
            _mm_cvtsi128_si64, _mm_loadu_si128, _mm_or_si128, _mm_setzero_si128, _mm_slli_epi64,
            _mm_unpackhi_epi64,
        };
        let pairs = values.chunks_exact(2);
        let last = pairs.remainder().first().map_or(0, |v| v.to_bits() << 1);
        // SAFETY: SSE2 is part of x86-64; each load reads one pair, two values of `values`
        // (unaligned).
        unsafe {
            let mut any = _mm_setzero_si128();
            for pair in pairs {
                any = _mm_or_si128(any, _mm_loadu_si128(pair.as_ptr().cast()));
            }
            let any = _mm_slli_epi64(any, 1);
            let both = _mm_or_si128(any, _mm_unpackhi_epi64(any, any));
            _mm_cvtsi128_si64(both) == 0 && last == 0
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        values.iter().all(|&v| v == 0.0)
    }
}

/// Whether every value is finite. Without a branch per value (the check runs on every call
/// of every exported function, where `position(|v| !v.is_finite())` cost more than a small
/// model's arithmetic).
///
/// On x86-64, two values at a time with SSE2 (which every x86-64 has): v·0 is ±0 for a
/// finite v and NaN for NaN and the infinities, so the bitwise or of the products is ±0
/// exactly when every value is finite (a NaN's exponent bits are all set and its mantissa's
/// are not all clear, which an or keeps); three instructions per pair, the products
/// independent and the or one cycle each (the exported crates are built at opt-level 2,
/// where nothing pairs the scalar check). Elsewhere, NaN and the infinities are the values
/// whose exponent bits are all set.
#[inline]
pub fn all_finite(values: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{
            _mm_cvtsd_f64, _mm_loadu_pd, _mm_mul_pd, _mm_or_pd, _mm_setzero_pd, _mm_unpackhi_pd,
        };
        let pairs = values.chunks_exact(2);
        let last = pairs.remainder().first().map_or(0.0, |&v| v * 0.0);
        // SAFETY: SSE2 is part of x86-64; each load reads one pair, two values of `values`
        // (unaligned).
        unsafe {
            let zero = _mm_setzero_pd();
            let mut any = zero;
            for pair in pairs {
                any = _mm_or_pd(any, _mm_mul_pd(_mm_loadu_pd(pair.as_ptr()), zero));
            }
            let any = _mm_or_pd(any, _mm_unpackhi_pd(any, any));
            _mm_cvtsd_f64(any) == 0.0 && last == 0.0
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        const EXPONENT: u64 = 0x7ff0_0000_0000_0000;
        !values
            .iter()
            .fold(false, |any, v| any | (v.to_bits() & EXPONENT == EXPONENT))
    }
}

/// Values copied with a check that they are finite folded into the copy: their sum, which
/// is finite only if each value is (an infinity or a NaN among them makes it an infinity or
/// a NaN, and so does any sum it enters). One addition per pair of values on x86-64 (SSE2,
/// which every x86-64 has), where testing each copy again (`all_finite`) cost a load and
/// two operations a pair: the point of every fast call is copied through this (19 values
/// for the robot). A sum that is not finite only says "maybe": finite values whose sum overflows
/// are told apart by the exact check of whoever takes the call then (the general path),
/// which names the value that is not finite or computes the call.
#[derive(Clone, Copy)]
pub struct FiniteSum {
    #[cfg(target_arch = "x86_64")]
    pairs: core::arch::x86_64::__m128d,
    last: f64,
}

impl FiniteSum {
    #[inline(always)]
    pub fn new() -> FiniteSum {
        FiniteSum {
            // SAFETY: SSE2 is part of x86-64.
            #[cfg(target_arch = "x86_64")]
            pairs: unsafe { core::arch::x86_64::_mm_setzero_pd() },
            last: 0.0,
        }
    }

    /// `from` into `to` (as many values as the shorter has), added to the sum.
    #[inline(always)]
    pub fn copy(&mut self, from: &[f64], to: &mut [core::mem::MaybeUninit<f64>]) {
        let n = from.len().min(to.len());
        let (from, to) = (&from[..n], &mut to[..n]);
        #[cfg(target_arch = "x86_64")]
        {
            use core::arch::x86_64::{_mm_add_pd, _mm_loadu_pd, _mm_storeu_pd};
            let pairs = n / 2;
            for k in 0..pairs {
                // SAFETY: SSE2 as above; 2k + 1 < n, so both values are in both slices
                // (unaligned loads and stores).
                unsafe {
                    let v = _mm_loadu_pd(from.as_ptr().add(2 * k));
                    _mm_storeu_pd(to.as_mut_ptr().add(2 * k).cast::<f64>(), v);
                    self.pairs = _mm_add_pd(self.pairs, v);
                }
            }
            if n % 2 == 1 {
                to[n - 1].write(from[n - 1]);
                self.last += from[n - 1];
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for (to, &v) in to.iter_mut().zip(from) {
            to.write(v);
            self.last += v;
        }
    }

    /// `values` added to the sum, not copied.
    #[inline(always)]
    pub fn add(&mut self, values: &[f64]) {
        #[cfg(target_arch = "x86_64")]
        {
            use core::arch::x86_64::{_mm_add_pd, _mm_loadu_pd};
            let pairs = values.chunks_exact(2);
            if let Some(&last) = pairs.remainder().first() {
                self.last += last;
            }
            for pair in pairs {
                // SAFETY: SSE2 as above; an unaligned load of the pair's two values.
                self.pairs = unsafe { _mm_add_pd(self.pairs, _mm_loadu_pd(pair.as_ptr())) };
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        for &v in values {
            self.last += v;
        }
    }

    /// Whether the sum of everything copied is finite (every value finite, and no overflow).
    #[inline(always)]
    pub fn finite(self) -> bool {
        #[cfg(target_arch = "x86_64")]
        let sum = {
            use core::arch::x86_64::{_mm_add_sd, _mm_cvtsd_f64, _mm_unpackhi_pd};
            // SAFETY: SSE2 as above.
            let pairs = unsafe { _mm_add_sd(self.pairs, _mm_unpackhi_pd(self.pairs, self.pairs)) };
            // SAFETY: SSE2 as above.
            unsafe { _mm_cvtsd_f64(pairs) + self.last }
        };
        #[cfg(not(target_arch = "x86_64"))]
        let sum = self.last;
        // ±0 for a finite sum, NaN for an infinite or NaN one: two instructions fewer than
        // `is_finite`'s test of the exponent's bits in an integer register.
        sum * 0.0 == 0.0
    }
}

impl Default for FiniteSum {
    fn default() -> Self {
        Self::new()
    }
}

/// Every value must be finite; the first that is not is named (`x[2] (alpha) = NaN`).
#[inline(always)]
pub fn check_finite(name: &str, values: &[f64], labels: &[&str]) -> Result<(), Failure> {
    if all_finite(values) {
        return Ok(());
    }
    name_not_finite(name, values, labels)
}

/// The refusal of `check_finite`, out of line.
#[cold]
#[inline(never)]
fn name_not_finite(name: &str, values: &[f64], labels: &[&str]) -> Result<(), Failure> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => {
            let label = labels.get(i).map(|l| format!(" ({l})")).unwrap_or_default();
            Err(Failure::new(
                Status::NonFinite,
                format!("{name}[{i}]{label} = {} is not a finite number", values[i]),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::ffi::CStr;

    fn last() -> String {
        // SAFETY: `last_error` points at this thread's NUL-terminated message.
        unsafe { CStr::from_ptr(last_error()) }
            .to_string_lossy()
            .into_owned()
    }

    #[test]
    fn all_zero_is_the_plain_check_of_plus_and_minus_zero() {
        let odd = [0.0, -0.0, 0.0];
        for len in 0..=odd.len() {
            assert!(all_zero(&odd[..len]));
        }
        let tiny = f64::from_bits(1);
        for bad in [
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            1.0,
            -tiny,
            tiny,
            f64::MIN,
        ] {
            for at in 0..5 {
                let mut values = [0.0, -0.0, 0.0, 0.0, -0.0];
                values[at] = bad;
                for len in at + 1..=values.len() {
                    assert!(!all_zero(&values[..len]), "{bad} at {at} of {len}");
                    assert!(all_zero(&values[..at]));
                }
            }
        }
    }

    #[test]
    fn a_finite_sum_is_the_copy_of_finite_values_that_do_not_overflow() {
        use core::mem::MaybeUninit;
        let copied = |values: &[f64]| {
            let mut sum = FiniteSum::new();
            let mut to = vec![MaybeUninit::new(7.0); values.len()];
            // Two blocks, as a point's x and u: the second one's pairs start anywhere.
            let split = values.len() / 2;
            sum.copy(&values[..split], &mut to[..split]);
            sum.copy(&values[split..], &mut to[split..]);
            let bits: Vec<u64> = to
                .iter()
                .map(|v| unsafe { v.assume_init() }.to_bits())
                .collect();
            assert_eq!(bits, values.iter().map(|v| v.to_bits()).collect::<Vec<_>>());
            let mut added = FiniteSum::new();
            added.add(values);
            assert_eq!(added.finite(), sum.finite());
            sum.finite()
        };
        for len in 0..=7 {
            let mut values = vec![-0.0, 1.5, -2.0, 1e300, 3.0, 5e-324, -1e300][..len].to_vec();
            assert!(copied(&values));
            for at in 0..len {
                for bad in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let good = values[at];
                    values[at] = bad;
                    assert!(!copied(&values), "{bad} at {at} of {len}");
                    values[at] = good;
                }
            }
        }
        // Finite values whose sum overflows: "maybe not finite" (the exact check decides).
        assert!(!copied(&[f64::MAX, 1.0, f64::MAX]));
    }

    #[test]
    fn a_panic_becomes_a_status_and_a_message() {
        let status = guard("f", || panic!("boom"));
        assert_eq!(status, Status::Internal as c_int);
        assert!(last().contains("boom"), "{}", last());
        assert_eq!(guard("f", || Ok(())), 0);
        assert_eq!(last(), "");
    }

    #[test]
    fn errors_name_what_they_refuse() {
        let status = guard("f", || {
            check_finite("x", &[1.0, f64::NAN], &["a", "b"])?;
            Ok(())
        });
        assert_eq!(status, Status::NonFinite as c_int);
        assert_eq!(last(), "f: x[1] (b) = NaN is not a finite number");
        for bad in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let values = [0.0, -0.0, f64::MAX, f64::MIN_POSITIVE, 5e-324, bad, 1.0];
            assert!(!all_finite(&values), "{bad}");
            assert_eq!(
                check_finite("u", &values, &[]).unwrap_err().message,
                format!("u[5] = {bad} is not a finite number")
            );
            assert!(all_finite(&values[..5]));
            // The bad value at every place of slices of even and odd lengths (pairs and
            // the last value alone).
            for len in 1..=6 {
                for at in 0..len {
                    let mut v = [f64::MAX; 6];
                    v[at] = bad;
                    assert!(!all_finite(&v[..len]), "{bad} at {at} of {len}");
                }
            }
        }
        assert!(all_finite(&[]));
        // SAFETY: a null pointer is refused before it is read.
        let null = unsafe { slice(core::ptr::null(), 3, "u") };
        assert_eq!(null.unwrap_err().status, Status::NullPointer);
        assert_eq!(
            check_len("p", 8, 9).unwrap_err().status,
            Status::BadDimension
        );
    }

    #[test]
    fn messages_are_per_thread() {
        let _ = guard("here", || Err(Failure::new(Status::Singular, "one")));
        std::thread::spawn(|| assert_eq!(last(), ""))
            .join()
            .unwrap();
        assert_eq!(last(), "here: one");
    }
}
