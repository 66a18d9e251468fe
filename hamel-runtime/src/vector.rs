//! Fixed-size vectors: the state, coordinates and inputs of a system live on the stack.

use core::fmt::Debug;

use nalgebra::Complex;

use crate::integrate::dense::{Lu, SquareLu};

/// A fixed-size array of `f64` (`[f64; N]` for every `N`): what generated systems use for
/// states, coordinates and inputs, so that no evaluation touches the heap.
pub trait Vector:
    Copy + Debug + PartialEq + AsRef<[f64]> + AsMut<[f64]> + Send + Sync + 'static
{
    const LEN: usize;

    /// The LU factors of an n × n real matrix, n = `LEN`, sized at compile time for small n
    /// (the implicit integrators' linear algebra: `integrate::dense`).
    #[doc(hidden)]
    type Lu: SquareLu<f64>;

    /// [`Vector::Lu`] for a complex matrix (Radau5's complex system).
    #[doc(hidden)]
    type ComplexLu: SquareLu<Complex<f64>>;

    fn zeros() -> Self;

    /// The vector with these components, or `None` if the length is wrong.
    fn from_slice(values: &[f64]) -> Option<Self> {
        let mut v = Self::zeros();
        (values.len() == Self::LEN).then(|| {
            v.as_mut().copy_from_slice(values);
            v
        })
    }

    /// The vector that the first `LEN` of `values` are, borrowed in place (`None` if there
    /// are fewer): a state inside a longer one, read without a copy.
    fn head(values: &[f64]) -> Option<&Self>;

    /// [`Vector::head`], to write.
    fn head_mut(values: &mut [f64]) -> Option<&mut Self>;
}

impl<const N: usize> Vector for [f64; N] {
    const LEN: usize = N;
    type Lu = Lu<f64, N>;
    type ComplexLu = Lu<Complex<f64>, N>;

    fn zeros() -> Self {
        [0.0; N]
    }

    fn head(values: &[f64]) -> Option<&Self> {
        values.get(..N)?.try_into().ok()
    }

    fn head_mut(values: &mut [f64]) -> Option<&mut Self> {
        values.get_mut(..N)?.try_into().ok()
    }
}

#[cfg(test)]
mod tests {
    use super::Vector;

    #[test]
    fn heads_borrow_the_leading_components() {
        let mut values = [1.0, 2.0, 3.0];
        assert_eq!(<[f64; 2]>::head(&values), Some(&[1.0, 2.0]));
        assert_eq!(<[f64; 4]>::head(&values), None);
        if let Some(head) = <[f64; 3]>::head_mut(&mut values) {
            head[2] = 5.0;
        }
        assert_eq!(values, [1.0, 2.0, 5.0]);
        assert_eq!(<[f64; 4]>::head_mut(&mut values), None);
    }
}
