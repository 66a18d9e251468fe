//! The values of the compiled code that depend on the parameters alone, kept per thread for
//! the last parameter set: a solver calls with the same parameters thousands of times, and
//! these values (a mass matrix's constant part, a transformation's inverse for a model that
//! gives its rows, the parameters' products) are then computed once. A thread's cache is its
//! own: no lock, and any number of threads call at once.

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
        let same = self.valid
            && self
                .parameters
                .iter()
                .zip(parameters)
                .all(|(a, b)| a.to_bits() == b.to_bits());
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
}
