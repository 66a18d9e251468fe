//! Moving between the corpus functions' typed arguments and results and flat vectors x ∈ ℝᴺ,
//! y ∈ ℝᴹ (arguments in order, arrays row-major: the engine's own convention), for any
//! scalar type S (f64 or the reference dual number).

use super::dual::D;

/// An argument type of a corpus function, written over `f64` (`f64`, `[f64; 3]`,
/// `&[[f64; 2]; 2]`...). `Owned<S>` is the same type over S without the reference;
/// `Passed<S>` is what the function takes.
pub trait Arg {
    /// Number of reals in the argument.
    const LEN: usize;
    type Owned<S: Copy + 'static>: Copy + 'static;
    type Passed<'a, S: Copy + 'static>;
    /// The argument from the first `LEN` reals of `xs`.
    fn build<S: Copy + 'static>(xs: &[S]) -> Self::Owned<S>;
    fn pass<S: Copy + 'static>(owned: &Self::Owned<S>) -> Self::Passed<'_, S>;
}

impl Arg for f64 {
    const LEN: usize = 1;
    type Owned<S: Copy + 'static> = S;
    type Passed<'a, S: Copy + 'static> = S;

    fn build<S: Copy + 'static>(xs: &[S]) -> S {
        xs[0]
    }

    fn pass<S: Copy + 'static>(owned: &S) -> S {
        *owned
    }
}

impl<T: Arg, const N: usize> Arg for [T; N] {
    const LEN: usize = N * T::LEN;
    type Owned<S: Copy + 'static> = [T::Owned<S>; N];
    type Passed<'a, S: Copy + 'static> = [T::Owned<S>; N];

    fn build<S: Copy + 'static>(xs: &[S]) -> Self::Owned<S> {
        std::array::from_fn(|i| T::build(&xs[i * T::LEN..]))
    }

    fn pass<S: Copy + 'static>(owned: &Self::Owned<S>) -> Self::Passed<'_, S> {
        *owned
    }
}

impl<T: Arg> Arg for &T {
    const LEN: usize = T::LEN;
    type Owned<S: Copy + 'static> = T::Owned<S>;
    type Passed<'a, S: Copy + 'static> = &'a T::Owned<S>;

    fn build<S: Copy + 'static>(xs: &[S]) -> Self::Owned<S> {
        T::build(xs)
    }

    fn pass<S: Copy + 'static>(owned: &Self::Owned<S>) -> Self::Passed<'_, S> {
        owned
    }
}

/// A result (or derivative) over S, flattened row-major.
pub trait Flat<S> {
    fn push_into(&self, out: &mut Vec<S>);
}

impl Flat<f64> for f64 {
    fn push_into(&self, out: &mut Vec<f64>) {
        out.push(*self);
    }
}

impl Flat<D> for D {
    fn push_into(&self, out: &mut Vec<D>) {
        out.push(*self);
    }
}

impl<S, T: Flat<S>, const N: usize> Flat<S> for [T; N] {
    fn push_into(&self, out: &mut Vec<S>) {
        for item in self {
            item.push_into(out);
        }
    }
}

pub fn flat<S, T: Flat<S>>(value: &T) -> Vec<S> {
    let mut out = Vec::new();
    value.push_into(&mut out);
    out
}
