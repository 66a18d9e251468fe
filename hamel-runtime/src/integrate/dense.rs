//! The square linear systems of an implicit method, n × n for a state of n components: LU
//! factorization with partial pivoting and solves in place, sized at compile time.
//!
//! For n up to [`FIXED_LIMIT`] the matrix and its row permutation are nalgebra's statically
//! sized storage (`SMatrix`, `PermutationSequence<Const<N>>`), in one block allocated with
//! the integration and reused by every factorization after it; above it the same steps run on
//! nalgebra's dynamically sized storage, whose matrix a large n would not fit on a stack.
//! Either way the steps are nalgebra's: the partial-pivoting Gauss steps of `LU::new`
//! (`linalg::gauss_step`, `gauss_step_swap`) and the triangular solves of `LU::solve_mut`
//! (for a complex entry taken one by one, see `subtract_multiple`).
//! nalgebra's `LU` type itself cannot be named for a statically sized matrix in code generic
//! over the size: its `DimMin` bound holds for `Const<N>` only through typenum, that is for
//! each literal N, not for every N at once.
//!
//! The Gauss steps skip what changes nothing. A stiff problem's Jacobian is mostly zeros
//! (POLLU's 20 × 20 has 82 non-zero entries of 400), and the iteration matrices γ/h·I − J
//! keep them. A Gauss step updates each column right of the pivot by its pivot-row entry
//! times the multipliers, an `axpy`; where that entry is 0 the update adds ±0 to each entry,
//! which changes nothing but the sign of a zero entry. So `Factors::eliminate` is
//! nalgebra's step, its `axpy` and all (for a complex entry the `axpy` without its products
//! by 1 + 0i, see `subtract_multiple`), with the columns of a zero pivot-row entry left out
//! (and for a complex entry the rows of a zero multiplier, which likewise subtract ±0):
//! the factors (and so the solutions) are nalgebra's to the bit up to signs of zeros, wherever
//! the skipped products are finite (an infinite multiplier times 0 would have made NaN; the
//! Jacobians factored here are checked finite before). Fill-in under partial pivoting limits
//! the gain: POLLU's factors hold about 260 non-zero entries.
//!
//! Which path a state takes is decided by its type ([`crate::Vector::Lu`]): the branch on N
//! is a constant, so each state's code holds one path.

use nalgebra::allocator::Allocator;
use nalgebra::linalg::{gauss_step, gauss_step_swap};
use nalgebra::{
    Complex, ComplexField, Const, DefaultAllocator, Dim, Dyn, Matrix, OMatrix, OVector,
    PermutationSequence, StorageMut, U1,
};

/// The largest n whose matrices are sized at compile time. Above it the storage is dynamic
/// (an n × n complex matrix of 32² entries is 16 KiB, a size still comfortable on a thread's
/// stack when the method forms its matrices; the catalogue's models have at most 20 states).
pub const FIXED_LIMIT: usize = 32;

/// The smallest n whose Gauss steps skip the updates by a zero pivot-row entry. Below, a step
/// has at most two columns right of its pivot and nalgebra's own steps (unrolled by the
/// compiler) cost less: skipping took 10–13 % more instructions in ROBER's and OREGO's dense LU
/// and solves (n = 3), against 18 % fewer in POLLU's (n = 20) and 11 % in HIRES's (n = 8),
/// with Radau5 (`benches/work_precision.rs`, under callgrind).
const SKIP_FROM: usize = 4;

/// The smallest n whose complex Gauss steps update only the rows of non-zero multipliers
/// (`Factors::eliminate`): listing them cost 1.4 % more of HIRES's whole Radau5 run (n = 8)
/// and saved 1.6 % of POLLU's (n = 20).
const LIST_FROM: usize = 12;

/// A matrix entry: `f64`, or `Complex<f64>` for Radau5's complex system.
pub trait Entry: ComplexField<RealField = f64> + Copy {
    /// Whether nalgebra's `axpy` pays for its factors 1 (see `subtract_multiple`), and a
    /// modulus is a `hypot` rather than an `abs` (see `smallest_modulus`).
    const COMPLEX: bool;
}

impl Entry for f64 {
    const COMPLEX: bool = false;
}
impl Entry for Complex<f64> {
    const COMPLEX: bool = true;
}

/// An n × n matrix and its LU factors, for one size n (the state's).
#[doc(hidden)]
pub trait SquareLu<T: Entry> {
    /// Storage for the matrix of the state's size, nothing factored yet (all it allocates,
    /// once).
    fn new() -> Self;

    /// Forms the matrix by `fill`, which writes its n² entries column by column (column-major
    /// order: entry (r, c) at c·n + r), and factors it in place; its smallest pivot in
    /// modulus (infinite for n = 0), for the singularity test (`super::singular`; the caller
    /// knows the largest entry more cheaply than a modulus of every entry, which for a
    /// complex one is a `hypot`).
    fn factor(&mut self, fill: impl FnOnce(&mut [T])) -> f64 {
        self.form(fill);
        self.smallest_pivot()
    }

    /// Forms and factors the matrix as [`SquareLu::factor`] does, without measuring its
    /// pivots.
    fn form(&mut self, fill: impl FnOnce(&mut [T]));

    /// The smallest pivot in modulus of the factors (infinite for n = 0): what
    /// [`SquareLu::factor`] returns.
    fn smallest_pivot(&self) -> f64;

    /// The smallest squared modulus of the pivots, |uᵢᵢ|², where every one is finite and the
    /// least above [`SQUARE_FLOOR`] (so that each carries its full precision); `None`
    /// otherwise. For a complex matrix it is at hand from the factorization, where the
    /// modulus itself is a `hypot` a pivot: enough to settle a comparison of the smallest
    /// pivot that is not a near-tie.
    fn smallest_pivot_square(&self) -> Option<f64>;

    /// Solves the factored system in place, `b` of length n; `false` when a pivot is zero.
    fn solve(&self, b: &mut [T]) -> bool;
}

/// The LU factors of an n × n matrix: the packed L and U and the row interchanges.
#[doc(hidden)]
pub struct Factors<T: Entry, D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    lu: OMatrix<T, D, D>,
    p: PermutationSequence<D>,
    /// For a complex entry, the squared moduli of U's diagonal, |uᵢᵢ|² (left at zero for a
    /// real one): the denominators of the back substitution's divisions, formed once for
    /// all the solves of a factorization.
    squares: OVector<f64, D>,
    /// The rows below a Gauss step's pivot whose multipliers are non-zero, gathered for the
    /// step (capacity n, allocated once with the storage).
    rows: Vec<usize>,
    dim: D,
}

impl<T: Entry, D: Dim> Factors<T, D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    fn zeros(dim: D) -> Self {
        Factors {
            lu: OMatrix::zeros_generic(dim, dim),
            p: PermutationSequence::identity_generic(dim),
            squares: OVector::zeros_generic(dim, U1),
            rows: Vec::with_capacity(dim.value()),
            dim,
        }
    }

    /// `LU::new`'s steps on the storage in place.
    fn form(&mut self, fill: impl FnOnce(&mut [T])) {
        let n = self.dim.value();
        fill(self.lu.as_mut_slice());
        self.p = PermutationSequence::identity_generic(self.dim);
        for i in 0..n {
            let piv = self.lu.view_range(i.., i).icamax() + i;
            let diag = self.lu[(piv, i)];
            if diag.is_zero() {
                // No non-zero entry below: the pivot stays 0 and solves fail.
                continue;
            }
            if piv != i {
                self.p.append_permutation(i, piv);
                self.lu.columns_range_mut(..i).swap_rows(i, piv);
            }
            if n < SKIP_FROM {
                if piv != i {
                    gauss_step_swap(&mut self.lu, diag, i, piv);
                } else {
                    gauss_step(&mut self.lu, diag, i);
                }
            } else if T::COMPLEX && n >= LIST_FROM {
                self.eliminate_listed(diag, i, piv);
            } else {
                self.eliminate(diag, i, piv);
            }
        }
        if T::COMPLEX {
            for (i, square) in self.squares.iter_mut().enumerate() {
                *square = self.lu[(i, i)].modulus_squared();
            }
        }
    }

    fn smallest_pivot(&self) -> f64 {
        smallest_modulus((0..self.dim.value()).map(|i| self.lu[(i, i)]))
    }

    fn smallest_pivot_square(&self) -> Option<f64> {
        let n = self.dim.value();
        let square = |i: usize| {
            if T::COMPLEX {
                self.squares[i]
            } else {
                self.lu[(i, i)].modulus_squared()
            }
        };
        // A sum of non-negative terms is finite exactly when every term is (NaN included).
        let (least, sum) = (0..n)
            .map(square)
            .fold((f64::INFINITY, 0.0), |(m, s), q| (m.min(q), s + q));
        (sum.is_finite() && least.is_finite() && least > SQUARE_FLOOR).then_some(least)
    }

    /// One Gauss step on column `i` with its pivot in row `piv` ≥ `i`: nalgebra's
    /// `gauss_step_swap` (`gauss_step` for `piv == i`), the multipliers below the pivot
    /// scaled by 1/`diag` and every column right of the pivot, rows swapped, less its
    /// pivot-row entry times them, by the same `axpy`; but a column whose pivot-row entry is 0
    /// is left as it is (the `axpy` would add ±0 to each of its entries).
    fn eliminate(&mut self, diag: T, i: usize, piv: usize) {
        let piv = piv - i;
        let mut submatrix = self.lu.view_range_mut(i.., i..);
        let (mut multipliers, mut right) = submatrix.columns_range_pair_mut(0, 1..);
        multipliers.swap((0, 0), (piv, 0));
        let mut multipliers = multipliers.rows_range_mut(1..);
        multipliers *= T::one() / diag;
        let (mut pivot_row, mut below) = right.rows_range_pair_mut(0, 1..);
        for k in 0..pivot_row.ncols() {
            if piv != 0 {
                std::mem::swap(&mut pivot_row[k], &mut below[(piv - 1, k)]);
            }
            let entry = pivot_row[k];
            if entry.is_zero() {
                continue;
            }
            subtract_multiple(&mut below.column_mut(k), entry, &multipliers);
        }
    }

    /// [`Self::eliminate`] for a complex entry from n = [`LIST_FROM`], each row whose
    /// multiplier is 0 also left as it is (likewise: the entry less ±0). Where some
    /// multipliers are 0 the update runs over the rows of the others alone, 6 % fewer of the
    /// complex factorization's instructions on POLLU (Radau5 at rtol 1e-10, under callgrind);
    /// a real entry's update costs too little for the listing to pay (40 % more there).
    ///
    /// The steps run on the storage's slices (column-major: the multipliers end column i, the
    /// columns right of it follow), the same operations in the same order: slices that cannot
    /// overlap let the compiler keep an entry's update in vector registers whatever the
    /// column's length (14 instructions an entry on POLLU's 20 × 20, against 16 over
    /// nalgebra's views, whose vectorized loop needs 18 rows or more). Below n = 12 the
    /// views' loop costs less (HIRES, n = 8: 3.8 % more of its whole Radau5 run on slices).
    fn eliminate_listed(&mut self, diag: T, i: usize, piv: usize) {
        let n = self.dim.value();
        {
            let mut multipliers = self.lu.view_range_mut(i.., i);
            multipliers.swap((0, 0), (piv - i, 0));
            let mut multipliers = multipliers.rows_range_mut(1..);
            multipliers *= T::one() / diag;
        }
        let (left, right) = self.lu.as_mut_slice().split_at_mut((i + 1) * n);
        let multipliers = &left[i * n + i + 1..(i + 1) * n];
        let rows = &mut self.rows;
        rows.clear();
        rows.extend((0..multipliers.len()).filter(|&r| !multipliers[r].is_zero()));
        // Every multiplier non-zero: the contiguous update costs less than the rows listed.
        let dense = rows.len() == multipliers.len();
        for column in right.chunks_exact_mut(n) {
            let column = &mut column[i..];
            column.swap(0, piv - i);
            let (pivot_entry, below) = column.split_at_mut(1);
            let entry = pivot_entry[0];
            if entry.is_zero() {
                continue;
            }
            // `subtract_multiple`'s operation on each entry.
            if dense {
                for (y, &x) in below.iter_mut().zip(multipliers) {
                    *y -= entry * x;
                }
            } else {
                for &r in rows.iter() {
                    below[r] -= entry * multipliers[r];
                }
            }
        }
    }

    /// `LU::solve_mut`'s steps on one column: nalgebra's triangular solves for `f64`, and for
    /// a complex entry the same steps with [`subtract_multiple`] for their `axpy` (its
    /// right-hand sides are dense: skipping the zero unknowns, and the zero ends of L's and
    /// U's columns, cost more in tests than it saved, up to 1.6 times the solves'
    /// instructions on POLLU's Rodas5P).
    fn solve_column<S: StorageMut<T, D, U1>>(&self, b: &mut Matrix<T, D, U1, S>) -> bool {
        self.p.permute_rows(b);
        if !T::COMPLEX {
            let _ = self.lu.solve_lower_triangular_with_diag_mut(b, T::one());
            return self.lu.solve_upper_triangular_mut(b);
        }
        // L's diagonal is 1: `solve_lower_triangular_with_diag_mut` divides by it, a
        // division by 1 + 0i that is exact for finite values but for the sign of a zero.
        let n = self.dim.value();
        for i in 0..n.saturating_sub(1) {
            let x = b[i];
            subtract_multiple(
                &mut b.rows_range_mut(i + 1..),
                x,
                &self.lu.view_range(i + 1.., i),
            );
        }
        // `solve_upper_triangular_mut`'s steps.
        for i in (0..n).rev() {
            let diag = self.lu[(i, i)];
            if diag.is_zero() {
                return false;
            }
            // b / diag as num-complex divides, (b·conj(diag)) / |diag|², with |diag|² from
            // the factorization: the same operations (b·conj(d) is a·c − b·(−d) and
            // a·(−d) + b·c, num-complex's a·c + b·d and b·c − a·d exactly), so the same bits.
            let x = (b[i] * diag.conjugate()).unscale(self.squares[i]);
            b[i] = x;
            subtract_multiple(&mut b.rows_range_mut(..i), x, &self.lu.view_range(..i, i));
        }
        true
    }
}

/// `y −= a·x`: nalgebra's `y.axpy(-a, x, 1)`, which computes `(−a)·x·1 + 1·y`, for `f64`
/// (the compiler drops the factors 1, and the loop it compiles beats `zip_apply`'s); for a
/// complex entry the same without the factors 1 + 0i, most of the cost of an entry's update
/// (some 24 instructions), which change nothing but the sign of a zero for finite values.
#[inline(always)]
fn subtract_multiple<T: Entry, R: Dim, S, R2: Dim, S2>(
    y: &mut Matrix<T, R, U1, S>,
    a: T,
    x: &Matrix<T, R2, U1, S2>,
) where
    S: StorageMut<T, R, U1>,
    S2: nalgebra::Storage<T, R2, U1>,
    nalgebra::constraint::ShapeConstraint: nalgebra::constraint::SameNumberOfRows<R, R2>,
{
    if T::COMPLEX {
        y.zip_apply(x, |y, x| *y -= a * x);
    } else {
        y.axpy(-a, x, T::one());
    }
}

/// The smallest modulus of `entries`, `f64::min` of their `modulus` (NaN ones left out;
/// infinite for none): for a complex entry a `hypot`, some 50 instructions, taken here only
/// of the entries that can be the smallest. An entry whose squared modulus |z|² exceeds the
/// least one's by more than a relative 10⁻¹² has a modulus larger than that entry's by more
/// than any rounding of |z|² or of `hypot` (a few units of 10⁻¹⁶), so leaving it out changes
/// nothing; where |z|² may have overflowed or lost digits to underflow (the least not a
/// normal number above 10⁻²⁹⁰), every modulus is taken.
fn smallest_modulus<T: Entry>(entries: impl Iterator<Item = T> + Clone) -> f64 {
    fn all<T: Entry>(entries: impl Iterator<Item = T>) -> f64 {
        entries.map(|z| z.modulus()).fold(f64::INFINITY, f64::min)
    }
    if !T::COMPLEX {
        return all(entries);
    }
    let least = entries
        .clone()
        .map(|z| z.modulus_squared())
        .fold(f64::INFINITY, f64::min);
    if !(least.is_finite() && least > SQUARE_FLOOR) {
        return all(entries);
    }
    let bound = least * (1.0 + SQUARE_MARGIN);
    all(entries.filter(|z| z.modulus_squared() <= bound))
}

/// The relative margin between squared moduli beyond which their moduli are ordered whatever
/// the rounding ([`smallest_modulus`], and the largest entry of Radau5's complex matrix).
pub(crate) const SQUARE_MARGIN: f64 = 1e-12;

/// The least squared modulus from which |z|² = re² + im² carries its full precision: a term
/// below the smallest normal number is then lost only below 10⁻¹⁸ of the sum.
pub(crate) const SQUARE_FLOOR: f64 = 1e-290;

/// The factors of an n × n matrix, n = `N`: statically sized up to [`FIXED_LIMIT`], in one
/// block on the heap (so that a `Run` holding it stays small to move), dynamically above.
#[doc(hidden)]
pub enum Lu<T: Entry, const N: usize> {
    Fixed(Box<Factors<T, Const<N>>>),
    General(Factors<T, Dyn>),
}

/// The statically sized storage, formed in a function of its own: its frame, N² entries,
/// exists only when it is called (for N ≤ [`FIXED_LIMIT`]).
#[inline(never)]
fn fixed<T: Entry, const N: usize>() -> Box<Factors<T, Const<N>>> {
    Box::new(Factors::zeros(Const::<N>))
}

impl<T: Entry, const N: usize> SquareLu<T> for Lu<T, N> {
    fn new() -> Self {
        if N <= FIXED_LIMIT {
            Lu::Fixed(fixed())
        } else {
            Lu::General(Factors::zeros(Dyn(N)))
        }
    }

    fn form(&mut self, fill: impl FnOnce(&mut [T])) {
        match self {
            Lu::Fixed(factors) => factors.form(fill),
            Lu::General(factors) => factors.form(fill),
        }
    }

    fn smallest_pivot(&self) -> f64 {
        match self {
            Lu::Fixed(factors) => factors.smallest_pivot(),
            Lu::General(factors) => factors.smallest_pivot(),
        }
    }

    fn smallest_pivot_square(&self) -> Option<f64> {
        match self {
            Lu::Fixed(factors) => factors.smallest_pivot_square(),
            Lu::General(factors) => factors.smallest_pivot_square(),
        }
    }

    fn solve(&self, b: &mut [T]) -> bool {
        match self {
            Lu::Fixed(factors) => {
                let mut view = nalgebra::SVectorViewMut::<T, N>::from_slice(b);
                factors.solve_column(&mut view)
            }
            Lu::General(factors) => {
                let mut view = nalgebra::DVectorViewMut::from_slice(b, N);
                factors.solve_column(&mut view)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// A matrix that needs row interchanges (a zero leading entry, for n > 1), of any size.
    fn entry(n: usize) -> impl Fn(usize, usize) -> f64 + Copy {
        move |r, c| {
            if r == 0 && c == 0 && n > 1 {
                0.0
            } else {
                ((r * 7 + c * 3) % 11) as f64 - 5.0 + if r == c { 2.0 * n as f64 } else { 0.0 }
            }
        }
    }

    /// Writes the entries `entry(r, c)` column by column.
    fn fill<T>(slice: &mut [T], n: usize, entry: impl Fn(usize, usize) -> T) {
        for (k, v) in slice.iter_mut().enumerate() {
            *v = entry(k % n, k / n);
        }
    }

    /// Both paths give nalgebra's `LU` to the bit: the same steps on other storage.
    fn same_as_nalgebra<const N: usize>() {
        let e = entry(N);
        let mut ours = <Lu<f64, N> as SquareLu<f64>>::new();
        let smallest_pivot = ours.factor(|m| fill(m, N, e));
        let reference = DMatrix::from_fn(N, N, &e).lu();
        let b: Vec<f64> = (0..N).map(|i| 1.0 + i as f64).collect();
        let mut x = b.clone();
        assert!(ours.solve(&mut x));
        let mut y = nalgebra::DVector::from_vec(b);
        assert!(reference.solve_mut(&mut y));
        assert_eq!(
            x.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
            y.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
        );
        let smallest = (0..N)
            .map(|i| reference.lu_internal()[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        assert_eq!(smallest_pivot, smallest);
    }

    #[test]
    fn both_paths_are_nalgebras_lu() {
        same_as_nalgebra::<1>();
        same_as_nalgebra::<3>();
        same_as_nalgebra::<8>();
        same_as_nalgebra::<{ FIXED_LIMIT }>();
        same_as_nalgebra::<{ FIXED_LIMIT + 1 }>();
        assert!(matches!(<Lu<f64, 8> as SquareLu<f64>>::new(), Lu::Fixed(_)));
        assert!(matches!(
            <Lu<f64, { FIXED_LIMIT + 1 }> as SquareLu<f64>>::new(),
            Lu::General(_)
        ));
    }

    /// `a` and `b` to the bit, but for the sign of a zero.
    fn same_up_to_zero_signs(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a == 0.0 && b == 0.0)
    }

    /// A sparse matrix of the form γ·I − J (the iteration matrix of a stiff method): about
    /// four non-zero entries a row, off-diagonal ones up to 40 times the diagonal's, so that
    /// partial pivoting interchanges rows and fills in; with `-0.0` among its zeros.
    fn sparse(n: usize) -> impl Fn(usize, usize) -> f64 + Copy {
        move |r, c| {
            let k = (r * 13 + c * 7 + r * c) % 17;
            if r == c {
                1.0 + 0.25 * r as f64
            } else if k < 3 {
                (k as f64 + 1.0) * if (r + c) % 2 == 0 { 13.0 } else { -7.5 }
            } else if k == 3 && r + 1 < n {
                -0.0
            } else {
                0.0
            }
        }
    }

    /// The skipped updates leave the factors and solutions nalgebra's, on a sparse matrix
    /// with row interchanges, real and complex (whose steps, with zero multipliers among
    /// non-zero ones, update the listed rows alone), solved for right-hand sides with zeros.
    fn sparse_same_as_nalgebra<const N: usize>() {
        let e = sparse(N);
        let zeros = (0..N * N).filter(|&k| e(k % N, k / N) == 0.0).count();
        assert!(zeros > N * N / 2, "{zeros} zeros of {}", N * N);
        let mut ours = <Lu<f64, N> as SquareLu<f64>>::new();
        ours.factor(|m| fill(m, N, e));
        let reference = DMatrix::from_fn(N, N, e).lu();
        // The packed factors and the order of the rows, on either path.
        fn packed<T: Entry, D: Dim>(factors: &Factors<T, D>) -> (Vec<T>, nalgebra::DVector<f64>)
        where
            DefaultAllocator: Allocator<D, D> + Allocator<D>,
        {
            (
                factors.lu.iter().copied().collect(),
                order(&factors.p, factors.dim.value()),
            )
        }
        fn order<D: Dim>(p: &PermutationSequence<D>, n: usize) -> nalgebra::DVector<f64>
        where
            DefaultAllocator: Allocator<D>,
        {
            let mut order = nalgebra::DVector::from_fn(n, |i, _| i as f64);
            p.permute_rows(&mut order);
            order
        }
        let (lu, rows) = match &ours {
            Lu::Fixed(factors) => packed(factors),
            Lu::General(factors) => packed(factors),
        };
        assert_eq!(rows, order(reference.p(), N));
        let moved = rows.iter().enumerate().filter(|(i, r)| **r != *i as f64);
        assert!(moved.count() > 2, "rows interchanged: {rows}");
        for (a, b) in lu.iter().zip(reference.lu_internal().iter()) {
            assert!(same_up_to_zero_signs(*a, *b), "{a:e} against {b:e}");
        }
        let mut rhs: Vec<Vec<f64>> = (0..N)
            .map(|k| (0..N).map(|i| if i == k { 1.0 } else { 0.0 }).collect())
            .collect();
        rhs.push((0..N).map(|i| (i % 3) as f64 - 1.0).collect());
        for b in rhs {
            let mut x = b.clone();
            assert!(ours.solve(&mut x));
            let mut y = nalgebra::DVector::from_vec(b);
            assert!(reference.solve_mut(&mut y));
            for (a, b) in x.iter().zip(y.iter()) {
                assert!(same_up_to_zero_signs(*a, *b), "{a:e} against {b:e}");
            }
        }

        // The complex matrix (α + iβ)·I − J of Radau5, the same pattern.
        let ec = |r: usize, c: usize| {
            let v = e(r, c);
            if r == c {
                Complex::new(v, 0.7 + 0.1 * r as f64)
            } else {
                Complex::new(v, 0.0)
            }
        };
        let mut ours = <Lu<Complex<f64>, N> as SquareLu<Complex<f64>>>::new();
        ours.factor(|m| fill(m, N, ec));
        let reference = DMatrix::from_fn(N, N, ec).lu();
        let (lu, rows) = match &ours {
            Lu::Fixed(factors) => packed(factors),
            Lu::General(factors) => packed(factors),
        };
        assert_eq!(rows, order(reference.p(), N));
        for (a, b) in lu.iter().zip(reference.lu_internal().iter()) {
            assert!(
                same_up_to_zero_signs(a.re, b.re) && same_up_to_zero_signs(a.im, b.im),
                "{a:e} against {b:e}"
            );
        }
        let mut x: Vec<Complex<f64>> = (0..N)
            .map(|i| Complex::new((i % 2) as f64, if i % 3 == 0 { -0.5 } else { 0.0 }))
            .collect();
        let mut y = nalgebra::DVector::from_vec(x.clone());
        assert!(ours.solve(&mut x));
        assert!(reference.solve_mut(&mut y));
        for (a, b) in x.iter().zip(y.iter()) {
            assert!(
                same_up_to_zero_signs(a.re, b.re) && same_up_to_zero_signs(a.im, b.im),
                "{a:e} against {b:e}"
            );
        }
    }

    #[test]
    fn sparse_matrices_are_nalgebras_lu() {
        sparse_same_as_nalgebra::<7>();
        sparse_same_as_nalgebra::<20>();
        sparse_same_as_nalgebra::<{ FIXED_LIMIT + 1 }>();
    }

    /// The smallest modulus taken of the candidates alone is the smallest of all, to the bit:
    /// near-ties (moduli a few ulps apart), zeros, NaN, and sizes whose squares overflow or
    /// underflow.
    #[test]
    fn the_smallest_modulus_is_that_of_every_entry() {
        let all = |z: &[Complex<f64>]| z.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
        let c = Complex::new;
        let tie = 1.0 + 4.0 * f64::EPSILON;
        let cases: Vec<Vec<Complex<f64>>> = vec![
            vec![c(3.0, 4.0), c(4.0, 3.0), c(0.6, 0.8), c(-0.8, 0.6)],
            vec![c(1.0, 1.0), c(tie, 1.0), c(1.0, tie), c(1.0 / tie, 1.0)],
            vec![c(0.0, 0.0), c(1.0, 0.0), c(-0.0, 0.0)],
            vec![c(f64::NAN, 1.0), c(2.0, 2.0), c(2.0, -2.0 * tie)],
            vec![c(f64::NAN, 0.0)],
            vec![c(1e200, 1e200), c(3e199, 1e200), c(2e200, 0.0)],
            vec![c(1e-170, 3e-170), c(3e-170, 1e-170), c(1.0, 0.0)],
            vec![c(f64::INFINITY, 0.0), c(1e300, 1e300)],
            vec![],
        ];
        for z in cases {
            let ours = smallest_modulus(z.iter().copied());
            assert_eq!(ours.to_bits(), all(&z).to_bits(), "{z:?}");
        }
        // Many entries of nearly the same modulus, rotated: every near-tie decided alike.
        for k in 0..200 {
            let z: Vec<Complex<f64>> = (0..5)
                .map(|i| {
                    let angle = 0.37 * (k * 5 + i) as f64;
                    let r = 1.0 + ((k + i) % 3) as f64 * f64::EPSILON;
                    c(r * angle.cos(), r * angle.sin())
                })
                .collect();
            assert_eq!(
                smallest_modulus(z.iter().copied()).to_bits(),
                all(&z).to_bits()
            );
        }
        let real = [3.0, -2.0, f64::NAN, 5.0];
        assert_eq!(smallest_modulus(real.iter().copied()), 2.0);
    }

    #[test]
    fn a_complex_system_is_solved() {
        let mut lu = <Lu<Complex<f64>, 2> as SquareLu<Complex<f64>>>::new();
        // [[i, 1], [1, 0]] x = [1 + i, 1]: x = [1, 1].
        let m = [
            [Complex::new(0.0, 1.0), Complex::new(1.0, 0.0)],
            [Complex::new(1.0, 0.0), Complex::new(0.0, 0.0)],
        ];
        lu.factor(|s| fill(s, 2, |r, c| m[r][c]));
        let mut b = [Complex::new(1.0, 1.0), Complex::new(1.0, 0.0)];
        assert!(lu.solve(&mut b));
        assert!((b[0] - Complex::new(1.0, 0.0)).norm() < 1e-15);
        assert!((b[1] - Complex::new(1.0, 0.0)).norm() < 1e-15);
    }

    #[test]
    fn a_singular_matrix_fails_its_solve() {
        let mut lu = <Lu<f64, 2> as SquareLu<f64>>::new();
        let singular = |r: usize, _| if r == 0 { 1.0 } else { 0.0 };
        assert_eq!(lu.factor(|s| fill(s, 2, singular)), 0.0);
        assert!(!lu.solve(&mut [1.0, 1.0]));
    }
}
