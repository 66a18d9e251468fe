//! Radau IIA's stage equations solved as RADAU5 solves them (Hairer & Wanner, *Solving
//! Ordinary Differential Equations II*, IV.8, "Transformation to block diagonal form"): with
//! A⁻¹ = T Λ T⁻¹, Λ = diag(γ, [[α, −β], [β, α]]), the simplified Newton iteration for
//! W = (T⁻¹ ⊗ I) Z decouples into one real system (γ/h I − J) ΔW₁ = … and one complex system
//! ((α + iβ)/h I − J)(ΔW₂ + iΔW₃) = … of size n, instead of one real system of size 3n: two
//! factorizations of about (1 + 4)·n³/3 operations instead of 9n³, and solves to match — on
//! the 20 species of the pollution problem the difference between a fast stiff solver and a
//! slow one. The real matrix is also that of RADAU5's error estimate, which shares its LU.
//!
//! T is computed here from the eigenvectors of A⁻¹, normalized as RADAU5's T (the iterates
//! are those in Z, transformed, but the convergence test measures the corrections of W, so
//! its scaling matters); the test checks it against RADAU5's constants.

use nalgebra::{Complex, DMatrix, DVector, Dyn, LU, Matrix3};

use super::collocation::Tableau;
use super::newton::{Convergence, Criterion, Outcome, stage_slopes};
use super::singular::{
    SUSPICIOUS_PIVOT, growing_mode, method_eigenvalues, relative_pivot, smallest_pivot,
};
use super::{Ode, Stats};
use crate::error::Error;
use crate::vector::Vector;

/// The block diagonalization of A⁻¹ for Radau IIA with three stages.
#[derive(Clone, Debug)]
pub(crate) struct Transformation {
    /// A⁻¹'s real eigenvalue γ (RADAU5's U1 inverted back: 3.6378…).
    pub gamma: f64,
    /// Its complex pair α ± iβ (β > 0).
    pub alpha: f64,
    pub beta: f64,
    /// T and T⁻¹, with A⁻¹ T = T Λ.
    pub t: [[f64; 3]; 3],
    pub t_inv: [[f64; 3]; 3],
}

impl Transformation {
    pub fn new(tableau: &Tableau<3>) -> Self {
        let a = Matrix3::from_fn(|i, j| tableau.a[i][j]);
        let a_inv = a.try_inverse().expect("Radau IIA's A is invertible");
        let eigen = a_inv.complex_eigenvalues();
        let real = eigen
            .iter()
            .min_by(|x, y| x.im.abs().total_cmp(&y.im.abs()))
            .copied()
            .expect("three eigenvalues");
        let pair = eigen
            .iter()
            .find(|l| l.im > 0.0)
            .copied()
            .expect("a complex pair");
        // The real eigenvector: the null space of A⁻¹ − γ I.
        // RADAU5's normalization, which its convergence test (on the corrections of W)
        // depends on: the real eigenvector of unit length with a positive last component, the
        // complex one with last component 1.
        let v1 = null_vector(&a_inv.map(Complex::from), Complex::from(real.re));
        let length = v1.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
        let sign = v1[2].re.signum();
        let v1 = v1.map(|c| c * (sign / length));
        // The complex one for α − iβ (RADAU5's): A⁻¹ (vr + i vi) = (α − iβ)(vr + i vi), so
        // that A⁻¹ [vr vi] = [vr vi] [[α, −β], [β, α]].
        let v = null_vector(&a_inv.map(Complex::from), pair.conj());
        let last = v[2];
        let v = v.map(|c| c / last);
        let t = Matrix3::from_fn(|i, j| match j {
            0 => v1[i].re,
            1 => v[i].re,
            _ => v[i].im,
        });
        let t_inv = t.try_inverse().expect("T is invertible");
        Transformation {
            gamma: real.re,
            alpha: pair.re,
            beta: pair.im,
            t: core::array::from_fn(|i| core::array::from_fn(|j| t[(i, j)])),
            t_inv: core::array::from_fn(|i| core::array::from_fn(|j| t_inv[(i, j)])),
        }
    }
}

/// A vector spanning the null space of m − λ I (3 × 3, λ an eigenvalue): the cross product
/// of two of its rows, the pair with the largest product.
fn null_vector(m: &nalgebra::Matrix3<Complex<f64>>, lambda: Complex<f64>) -> [Complex<f64>; 3] {
    let shifted = m - nalgebra::Matrix3::from_diagonal_element(lambda);
    let row = |i: usize| [shifted[(i, 0)], shifted[(i, 1)], shifted[(i, 2)]];
    let cross = |a: [Complex<f64>; 3], b: [Complex<f64>; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let size = |v: &[Complex<f64>; 3]| v.iter().map(|c| c.norm_sqr()).sum::<f64>();
    [
        cross(row(0), row(1)),
        cross(row(0), row(2)),
        cross(row(1), row(2)),
    ]
    .into_iter()
    .max_by(|a, b| size(a).total_cmp(&size(b)))
    .expect("three candidates")
}

/// The two factored matrices of a step size and Jacobian, and the iteration's workspace,
/// allocated with the first factorization and reused by every one after it.
pub(crate) struct TransformedStages {
    n: usize,
    controlled: usize,
    pub transformation: Transformation,
    /// The LU factors of the current matrices, or of the last ones formed (whose storage the
    /// next factorization takes back): valid for the h and Jacobian in `formed`, if any.
    factors: Option<Factors>,
    /// The h and the Jacobian (by its count) the factors are for: none before the first
    /// factorization and after a singular one.
    formed: Option<(f64, usize)>,
    /// The right-hand sides of the two systems, solved in place: ΔW₁, and ΔW₂ + iΔW₃.
    real_rhs: DVector<f64>,
    complex_rhs: DVector<Complex<f64>>,
    /// RADAU5's FACCON, carried from step to step.
    faccon: f64,
}

/// LU of γ/h I − J (the error estimate's matrix too) and of (α + iβ)/h I − J.
struct Factors {
    real: LU<f64, Dyn, Dyn>,
    complex: LU<Complex<f64>, Dyn, Dyn>,
}

/// The largest entries of the two matrices, for the singularity test's relative pivot.
struct Largest {
    real: f64,
    complex: f64,
}

impl TransformedStages {
    pub fn new(n: usize, controlled: usize, tableau: &Tableau<3>) -> Self {
        TransformedStages {
            n,
            controlled: controlled.clamp(1, n.max(1)),
            transformation: Transformation::new(tableau),
            factors: None,
            formed: None,
            real_rhs: DVector::zeros(n),
            complex_rhs: DVector::zeros(n),
            faccon: 1.0,
        }
    }

    /// The LU of γ/h I − J for the current factorization (the error estimate's).
    pub fn real_lu(&self) -> &LU<f64, Dyn, Dyn> {
        match (&self.factors, self.formed) {
            (Some(factors), Some(_)) => &factors.real,
            _ => unreachable!("factored before use"),
        }
    }

    /// Factors both matrices for step h and the Jacobian `jacobian` (number `id` of the
    /// integration), unless done already. `Some(λ)` when one is singular: the eigenvalue of
    /// J that makes it so (a growing mode at the step: [`super::singular`]).
    pub fn factor(
        &mut self,
        jacobian: &DMatrix<f64>,
        (h, id): (f64, usize),
        tableau: &Tableau<3>,
        stats: &mut Stats,
    ) -> Option<(f64, f64)> {
        if self.formed == Some((h, id)) {
            return None;
        }
        let n = self.n;
        // The last factors' storage, taken back: a square LU unpacks into its own buffer
        // (L's fill is overwritten below), so no factorization after the first allocates a
        // matrix.
        let (mut real, mut complex) = match self.factors.take() {
            Some(Factors { real, complex }) => (real.l_unpack(), complex.l_unpack()),
            None => (DMatrix::zeros(n, n), DMatrix::zeros(n, n)),
        };
        let largest = self.form(jacobian, h, &mut real, &mut complex);
        stats.factorizations += 1;
        self.formed = None;
        let factors = Factors {
            real: real.lu(),
            complex: complex.lu(),
        };
        let suspicious = relative_pivot(smallest_pivot(&factors.real), largest.real)
            <= SUSPICIOUS_PIVOT
            || relative_pivot(smallest_pivot(&factors.complex), largest.complex)
                <= SUSPICIOUS_PIVOT;
        self.factors = Some(factors);
        if suspicious {
            if let Some(mode) = growing_mode(jacobian, h, &method_eigenvalues(&tableau.a)) {
                return Some(mode);
            }
        }
        self.formed = Some((h, id));
        None
    }

    /// Fills `real` with γ/h I − J and `complex` with (α + iβ)/h I − J, and returns their
    /// largest entries in modulus. Off the diagonal both hold −J (the complex entries with a
    /// zero imaginary part, whose modulus is |J| exactly), so only the n diagonal entries of
    /// the complex matrix need a modulus of their own.
    fn form(
        &self,
        jacobian: &DMatrix<f64>,
        h: f64,
        real: &mut DMatrix<f64>,
        complex: &mut DMatrix<Complex<f64>>,
    ) -> Largest {
        let tr = &self.transformation;
        let (g, s) = (tr.gamma / h, Complex::new(tr.alpha / h, tr.beta / h));
        let zero = Complex::new(0.0, 0.0);
        let mut off_diagonal = 0.0f64;
        let mut largest = Largest {
            real: 0.0,
            complex: 0.0,
        };
        // Column by column (the matrices' storage order), as slices: no index checks.
        let columns = jacobian
            .as_slice()
            .chunks_exact(self.n)
            .zip(real.as_mut_slice().chunks_exact_mut(self.n))
            .zip(complex.as_mut_slice().chunks_exact_mut(self.n));
        for (c, ((jacobian, real), complex)) in columns.enumerate() {
            let entries = jacobian.iter().zip(real).zip(complex);
            for (r, ((&j, real), complex)) in entries.enumerate() {
                if r == c {
                    let (d, z) = (g - j, s - j);
                    (*real, *complex) = (d, z);
                    largest.real = largest.real.max(d.abs());
                    largest.complex = largest.complex.max(z.norm());
                } else {
                    // As `0.0 - j` and `zero - j` write them (not −j: the sign of a zero).
                    (*real, *complex) = (0.0 - j, zero - j);
                    off_diagonal = off_diagonal.max(j.abs());
                }
            }
        }
        largest.real = largest.real.max(off_diagonal);
        largest.complex = largest.complex.max(off_diagonal);
        largest
    }

    /// Solves the stage equations of the step h from (t, y) from the starting values `z`,
    /// leaving the solution there: RADAU5's iteration in W = (T⁻¹ ⊗ I) Z, its corrections
    /// measured relative to `scale` over the controlled components.
    #[allow(clippy::too_many_arguments)]
    pub fn iterate<O: Ode>(
        &mut self,
        ode: &mut O,
        tableau: &Tableau<3>,
        (t, y, h): (f64, &O::State, f64),
        z: &mut [O::State; 3],
        criterion: Criterion,
        scale: &[f64],
        stats: &mut Stats,
    ) -> Result<Outcome, Error> {
        let n = self.n;
        let tr = self.transformation.clone();
        let mut w = transform(&tr.t_inv, z);
        let mut f = [O::State::zeros(); 3];
        let mut convergence = Convergence::new(criterion, &mut self.faccon);
        for k in 1..=convergence.max_iterations() {
            stage_slopes(ode, &tableau.c, (t, y, h), z, &mut f, stats)?;
            // G = (T⁻¹ ⊗ I) F.
            let gt = transform(&tr.t_inv, &f);
            let solved = self.solve_corrections(&w, &gt, h);
            let increment = self.scaled_norm(scale);
            if let Some(failed) = convergence.judge(k, increment, solved, &mut self.faccon) {
                return Ok(failed);
            }
            for p in 0..n {
                w[0].as_mut()[p] += self.real_rhs[p];
                w[1].as_mut()[p] += self.complex_rhs[p].re;
                w[2].as_mut()[p] += self.complex_rhs[p].im;
            }
            *z = transform(&tr.t, &w);
            if let Some(outcome) = convergence.settled(k, increment, self.faccon) {
                return Ok(outcome);
            }
        }
        Ok(convergence.exhausted())
    }

    /// The corrections ΔW₁ and ΔW₂ + iΔW₃ of the step h from the iterate `w` and
    /// G = (T⁻¹ ⊗ I) F, in `real_rhs` and `complex_rhs`: the two systems solved with the
    /// right-hand sides −(Λ/h ⊗ I) W + G. Whether the solves succeeded.
    fn solve_corrections<V: Vector>(&mut self, w: &[V; 3], gt: &[V; 3], h: f64) -> bool {
        let tr = &self.transformation;
        let (g, a, b) = (tr.gamma / h, tr.alpha / h, tr.beta / h);
        let (real, complex) = (&mut self.real_rhs, &mut self.complex_rhs);
        for p in 0..self.n {
            let (w1, w2, w3) = (w[0].as_ref()[p], w[1].as_ref()[p], w[2].as_ref()[p]);
            real[p] = gt[0].as_ref()[p] - g * w1;
            let r2 = gt[1].as_ref()[p] - (a * w2 - b * w3);
            let r3 = gt[2].as_ref()[p] - (b * w2 + a * w3);
            complex[p] = Complex::new(r2, r3);
        }
        let (Some(factors), Some(_)) = (&self.factors, self.formed) else {
            unreachable!("the matrices are factored before the iteration");
        };
        factors.real.solve_mut(real) && factors.complex.solve_mut(complex)
    }

    /// RADAU5's norm of a correction: √(mean((ΔWᵢ / scale)²)) over the three stages and the
    /// controlled components.
    fn scaled_norm(&self, scale: &[f64]) -> f64 {
        let (real, complex) = (&self.real_rhs, &self.complex_rhs);
        let len = self.controlled;
        let sum: f64 = (0..len)
            .map(|p| {
                let s = scale[p];
                (real[p] / s).powi(2) + (complex[p].re / s).powi(2) + (complex[p].im / s).powi(2)
            })
            .sum();
        (sum / (3 * len) as f64).sqrt()
    }
}

/// (M ⊗ I) applied to three stage vectors.
fn transform<V: Vector>(m: &[[f64; 3]; 3], x: &[V; 3]) -> [V; 3] {
    core::array::from_fn(|i| {
        let mut out = V::zeros();
        for (p, o) in out.as_mut().iter_mut().enumerate() {
            *o = (0..3).map(|j| m[i][j] * x[j].as_ref()[p]).sum();
        }
        out
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Jacobian with entries of every sign and size, zeros of both signs among them.
    fn mixed_jacobian(n: usize) -> DMatrix<f64> {
        DMatrix::from_fn(n, n, |r, c| match (r * n + c) % 5 {
            0 => 0.0,
            1 => -0.0,
            k => (k as f64 - 3.5) * 10f64.powi((r as i32 - c as i32) * 3) / (1.0 + c as f64),
        })
    }

    #[test]
    fn the_matrices_are_formed_as_written_and_their_largest_entries_exactly() {
        let tableau = Tableau::radau_iia();
        let n = 6;
        let stages = TransformedStages::new(n, n, &tableau);
        let jacobian = mixed_jacobian(n);
        // At 1e-20 the diagonal of the complex matrix is its largest entry (|(α + iβ)/h|
        // ≈ 4e20 over |J| ≤ 1e15), at the others an entry of J is.
        for h in [1e-20, 1e-9, 0.3, 7e4] {
            let (mut real, mut complex) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
            let largest = stages.form(&jacobian, h, &mut real, &mut complex);
            // The definitions: each entry as written, the largest by a modulus of each.
            let tr = &stages.transformation;
            let (g, s) = (tr.gamma / h, Complex::new(tr.alpha / h, tr.beta / h));
            let zero = Complex::new(0.0, 0.0);
            let expected_real = DMatrix::from_fn(n, n, |r, c| {
                (if r == c { g } else { 0.0 }) - jacobian[(r, c)]
            });
            let expected_complex = DMatrix::from_fn(n, n, |r, c| {
                (if r == c { s } else { zero }) - jacobian[(r, c)]
            });
            let bits = |v: f64| v.to_bits();
            assert_eq!(real.map(bits), expected_real.map(bits), "h = {h}");
            assert_eq!(
                complex.map(|z| bits(z.re)),
                expected_complex.map(|z| bits(z.re))
            );
            assert_eq!(
                complex.map(|z| bits(z.im)),
                expected_complex.map(|z| bits(z.im))
            );
            assert_eq!(bits(largest.real), bits(expected_real.amax()), "h = {h}");
            let complex_largest = expected_complex
                .iter()
                .map(|z| z.norm())
                .fold(0.0, f64::max);
            assert_eq!(bits(largest.complex), bits(complex_largest), "h = {h}");
        }
    }

    /// The test binary's allocator: the system's, noting the largest block each thread asks
    /// for, so that a test can tell that a call allocated no matrix (a block freed and
    /// allocated again would have the same address, which a comparison of buffers would miss).
    #[global_allocator]
    static ALLOCATOR: NotingLargest = NotingLargest;

    struct NotingLargest;

    std::thread_local! {
        static LARGEST_BLOCK: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
    }

    fn note(size: usize) {
        // `try_with`: allocations while the thread's storage is torn down go unnoted.
        let _ = LARGEST_BLOCK.try_with(|largest| largest.set(largest.get().max(size)));
    }

    // SAFETY: every call is forwarded to the system allocator unchanged.
    unsafe impl std::alloc::GlobalAlloc for NotingLargest {
        unsafe fn alloc(&self, layout: std::alloc::Layout) -> *mut u8 {
            note(layout.size());
            unsafe { std::alloc::System.alloc(layout) }
        }
        unsafe fn alloc_zeroed(&self, layout: std::alloc::Layout) -> *mut u8 {
            note(layout.size());
            unsafe { std::alloc::System.alloc_zeroed(layout) }
        }
        unsafe fn realloc(
            &self,
            ptr: *mut u8,
            layout: std::alloc::Layout,
            new_size: usize,
        ) -> *mut u8 {
            note(new_size);
            unsafe { std::alloc::System.realloc(ptr, layout, new_size) }
        }
        unsafe fn dealloc(&self, ptr: *mut u8, layout: std::alloc::Layout) {
            unsafe { std::alloc::System.dealloc(ptr, layout) }
        }
    }

    #[test]
    fn refactoring_reuses_the_matrices_storage() {
        let tableau = Tableau::radau_iia();
        let n = 6;
        let mut stages = TransformedStages::new(n, n, &tableau);
        // Well conditioned (a step's matrices with a suspicious pivot would be examined for a
        // growing mode, which allocates).
        let jacobian = DMatrix::from_fn(n, n, |r, c| ((r * n + c) % 7) as f64 - 3.0)
            - DMatrix::identity(n, n) * 1e3;
        let mut stats = Stats::default();
        let mut factor = |stages: &mut TransformedStages, key| {
            assert_eq!(stages.factor(&jacobian, key, &tableau, &mut stats), None);
        };
        factor(&mut stages, (0.1, 1));
        // A new h, a new Jacobian, and the same h and Jacobian again (nothing to do): no
        // block as large as a matrix allocated (an LU's row permutation, of n pairs, is).
        LARGEST_BLOCK.with(|largest| largest.set(0));
        for key in [(0.2, 1), (0.2, 2), (0.2, 2)] {
            factor(&mut stages, key);
        }
        let largest = LARGEST_BLOCK.with(|largest| largest.get());
        assert!(
            largest < n * n * size_of::<f64>(),
            "a block of {largest} bytes"
        );
        assert_eq!(stats.factorizations, 3);
        // And the factors are those of the matrices for the last h, to the last bit: no
        // stale entry of the buffers' earlier contents survives.
        let (mut real, mut complex) = (DMatrix::zeros(n, n), DMatrix::zeros(n, n));
        stages.form(&jacobian, 0.2, &mut real, &mut complex);
        let factors = stages.factors.as_ref().expect("factored");
        let bits = |v: f64| v.to_bits();
        assert_eq!(
            factors.real.lu_internal().map(bits),
            real.lu().lu_internal().map(bits)
        );
        let fresh = complex.lu();
        for part in [|z: Complex<f64>| z.re, |z: Complex<f64>| z.im] {
            assert_eq!(
                factors.complex.lu_internal().map(|z| bits(part(z))),
                fresh.lu_internal().map(|z| bits(part(z)))
            );
        }
    }

    // RADAU5's constants below with the digits its source gives.
    #[allow(clippy::excessive_precision)]
    #[test]
    fn the_transformation_block_diagonalizes_the_inverse_of_a() {
        let tableau = Tableau::radau_iia();
        let tr = Transformation::new(&tableau);
        // RADAU5's constants: γ = 1/U1 with U1 = (6 + 81^(1/3) − 9^(1/3))/30, and α ± iβ from
        // ALPH = (12 − 81^(1/3) + 9^(1/3))/60, BETA = (81^(1/3) + 9^(1/3))·√3/60 over
        // ALPH² + BETA².
        let (c81, c9) = (81f64.cbrt(), 9f64.cbrt());
        let gamma = 30.0 / (6.0 + c81 - c9);
        let (alph, beta) = ((12.0 - c81 + c9) / 60.0, (c81 + c9) * 3f64.sqrt() / 60.0);
        let cno = alph * alph + beta * beta;
        assert!((tr.gamma - gamma).abs() < 1e-12);
        assert!((tr.alpha - alph / cno).abs() < 1e-12 && (tr.beta - beta / cno).abs() < 1e-12);
        // T⁻¹ A⁻¹ T = Λ.
        let a = Matrix3::from_fn(|i, j| tableau.a[i][j]);
        let t = Matrix3::from_fn(|i, j| tr.t[i][j]);
        let t_inv = Matrix3::from_fn(|i, j| tr.t_inv[i][j]);
        let lambda = t_inv * a.try_inverse().unwrap() * t;
        let expected = Matrix3::new(
            tr.gamma, 0.0, 0.0, 0.0, tr.alpha, -tr.beta, 0.0, tr.beta, tr.alpha,
        );
        assert!((lambda - expected).amax() < 1e-12, "{lambda}");
        // RADAU5's T (its T11 … T31; T32 = 1, T33 = 0).
        let radau5 = [
            [
                9.1232394870892942792e-2,
                -0.14125529502095420843,
                -3.0029194105147424492e-2,
            ],
            [
                0.24171793270710701896,
                0.20412935229379993199,
                0.38294211275726193779,
            ],
            [0.96604818261509293619, 1.0, 0.0],
        ];
        for (i, (ours, theirs)) in tr.t.iter().zip(&radau5).enumerate() {
            for (j, (a, b)) in ours.iter().zip(theirs).enumerate() {
                assert!((a - b).abs() < 1e-12, "T{i}{j} = {a}");
            }
        }
    }
}
