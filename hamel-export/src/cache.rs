//! The values of the compiled code that depend on the parameters alone, kept for the first
//! parameter set any thread asked for (shared by all, read-only once written) and per
//! thread for the last: a solver calls with the same parameters thousands of times, and
//! these values (a mass matrix's constant part, a transformation's inverse for a model that
//! gives its rows, the parameters' products) are then computed once. A thread's cache is its
//! own: no lock, and any number of threads call at once.

use std::sync::OnceLock;

/// The first parameter set and its prepared values, set once (by whichever thread calls
/// first) and only read after: a static of [`crate::model!`] per model. Its look-up is a
/// load and a test of a static's state, where a thread's cache is a call to the loader for
/// the thread-local's address (a shared library's thread-locals are found so) and the
/// borrow of its cell: 20 instructions fewer in every call with that set (the robot's
/// `f`, `hamel-export/bench/instructions.sh`).
pub struct First<const NP: usize, const K: usize>(OnceLock<([f64; NP], [f64; K])>);

impl<const NP: usize, const K: usize> First<NP, K> {
    #[allow(clippy::new_without_default)]
    pub const fn new() -> Self {
        First(OnceLock::new())
    }

    /// The prepared values of `parameters` if they are the first set (which the first call
    /// sets, by `prepare`, out of line); `None` for any other set.
    #[inline(always)]
    pub fn get(
        &self,
        parameters: &[f64; NP],
        prepare: impl FnOnce(&[f64; NP]) -> [f64; K],
    ) -> Option<&[f64; K]> {
        let (first, prepared) = self.0.get_or_init(|| (*parameters, prepare(parameters)));
        same_bits(first, parameters).then_some(prepared)
    }
}

/// The last parameter set (compared bit for bit: −0.0 is not 0.0, whose reciprocals differ)
/// and its prepared values. Declared by [`crate::model!`] as a thread-local per model.
pub struct Cache<const NP: usize, const K: usize> {
    valid: bool,
    parameters: [f64; NP],
    prepared: [f64; K],
}

impl<const NP: usize, const K: usize> Cache<NP, K> {
    pub const EMPTY: Self = Cache {
        valid: false,
        parameters: [0.0; NP],
        prepared: [0.0; K],
    };

    /// The prepared values of `parameters`, computed by `prepare` unless they are the last
    /// set's.
    #[inline]
    pub fn get(
        &mut self,
        parameters: &[f64; NP],
        prepare: impl FnOnce(&[f64; NP]) -> [f64; K],
    ) -> &[f64; K] {
        let same = self.valid && same_bits(&self.parameters, parameters);
        if !same {
            self.refresh(parameters, prepare);
        }
        &self.prepared
    }

    /// The values of a new parameter set: out of line and cold, so that the check above
    /// (every call of every function) is a few instructions in its caller, without the
    /// stack frame of the prepared values' copy.
    #[cold]
    #[inline(never)]
    fn refresh(&mut self, parameters: &[f64; NP], prepare: impl FnOnce(&[f64; NP]) -> [f64; K]) {
        self.prepared = prepare(parameters);
        self.parameters = *parameters;
        self.valid = true;
    }
}

/// Whether `a` and `b` are the same bits, value by value: on x86-64 the bitwise or of their
/// exclusive or, two values at a time with SSE2 (which every x86-64 has), read from memory
/// where they are: a comparison and a flag per value, with the parameters kept in
/// registers across the cache's look-up, were 18 instructions more in each call of the
/// robot's `f` (its 9 parameters; `hamel-export/bench/instructions.sh`).
#[inline(always)]
fn same_bits<const N: usize>(a: &[f64; N], b: &[f64; N]) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use core::arch::x86_64::{
            __m128i, _mm_cvtsi128_si64, _mm_loadu_si128, _mm_or_si128, _mm_setzero_si128,
            _mm_unpackhi_epi64, _mm_xor_si128,
        };
        let last = if N % 2 == 1 {
            a[N - 1].to_bits() ^ b[N - 1].to_bits()
        } else {
            0
        };
        // SAFETY: SSE2 is part of x86-64; each load reads two values of one array (2k + 1 <
        // N), unaligned.
        unsafe {
            let load =
                |v: &[f64; N], k: usize| _mm_loadu_si128(v.as_ptr().add(2 * k).cast::<__m128i>());
            let mut differ = _mm_setzero_si128();
            for k in 0..N / 2 {
                differ = _mm_or_si128(differ, _mm_xor_si128(load(a, k), load(b, k)));
            }
            let differ = _mm_or_si128(differ, _mm_unpackhi_epi64(differ, differ));
            (_mm_cvtsi128_si64(differ) as u64 | last) == 0
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

#[cfg(test)]
mod tests {
    use super::Cache;

    #[test]
    fn prepares_once_per_parameter_set() {
        let mut cache = Cache::<2, 1>::EMPTY;
        let calls = std::cell::Cell::new(0);
        let prepare = |p: &[f64; 2]| {
            calls.set(calls.get() + 1);
            [p[0] / p[1]]
        };
        assert_eq!(cache.get(&[1.0, 2.0], prepare), &[0.5]);
        assert_eq!(cache.get(&[1.0, 2.0], prepare), &[0.5]);
        assert_eq!(cache.get(&[1.0, -0.0], prepare), &[f64::NEG_INFINITY]);
        assert_eq!(cache.get(&[1.0, 0.0], prepare), &[f64::INFINITY]);
        assert_eq!(calls.get(), 3);
    }

    #[test]
    fn the_first_set_is_prepared_once_and_only_it_is_given() {
        let first = super::First::<2, 1>::new();
        let calls = std::cell::Cell::new(0);
        let prepare = |p: &[f64; 2]| {
            calls.set(calls.get() + 1);
            [p[0] / p[1]]
        };
        assert_eq!(first.get(&[1.0, 2.0], prepare), Some(&[0.5]));
        assert_eq!(first.get(&[1.0, 2.0], prepare), Some(&[0.5]));
        assert_eq!(first.get(&[1.0, -2.0], prepare), None);
        assert_eq!(first.get(&[-0.0, 2.0], prepare), None);
        assert_eq!(calls.get(), 1);
    }

    #[test]
    fn same_bits_tells_every_value_apart() {
        let base = [1.0, -0.0, 2.5, f64::MAX, 7.0];
        for len in 0..=base.len() {
            for at in 0..len {
                for other in [0.0, f64::from_bits(base[at].to_bits() ^ 1), -base[at]] {
                    let mut changed = base;
                    changed[at] = other;
                    let (a, b) = (&base[..len], &changed[..len]);
                    let differ = a.iter().zip(b).any(|(x, y)| x.to_bits() != y.to_bits());
                    assert_eq!(same(a, b), !differ, "{other} at {at} of {len}");
                }
            }
        }
    }

    /// `same_bits` for a slice's length (0 to 5).
    fn same(a: &[f64], b: &[f64]) -> bool {
        match a.len() {
            0 => super::same_bits::<0>(&[], &[]),
            1 => super::same_bits::<1>(a.try_into().unwrap(), b.try_into().unwrap()),
            2 => super::same_bits::<2>(a.try_into().unwrap(), b.try_into().unwrap()),
            3 => super::same_bits::<3>(a.try_into().unwrap(), b.try_into().unwrap()),
            4 => super::same_bits::<4>(a.try_into().unwrap(), b.try_into().unwrap()),
            _ => super::same_bits::<5>(a.try_into().unwrap(), b.try_into().unwrap()),
        }
    }
}
