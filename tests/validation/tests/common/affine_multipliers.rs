//! Lagrange's equations with multipliers for constraints that are affine in the velocities
//! and depend on the time — the index-1 form of the constrained (DAE) equations — as an
//! independent reference for Hamel's equations with affine, time-dependent rows.
//!
//! A mechanism gives its Lagrangian L(t, q, q̇), its generalized forces f(t, q, q̇, u) and
//! its rows ω = r(t, q, q̇) = A(q, t) q̇ + a(q, t): the first P are the constraints
//! r_c = A_c q̇ + a_c (zero on every motion), the others the free quasi-velocities
//! w = r_f = A_f q̇ + a_f, the velocity part of hamel's state x = (q, w).
//!
//! **Sign convention** (that of `HamelSystem::constraint_forces`):
//!
//! ```text
//! d/dt ∂L/∂q̇ − ∂L/∂q = f + A_cᵀ λ.
//! ```
//!
//! With d/dt ∂L/∂q̇ = H_vv q̈ + H_vq q̇ + ∂_t∇_vL (H_vv = ∂²L/∂q̇∂q̇, H_vq = ∂²L/∂q̇∂q) and the
//! constraints differentiated along the motion, 0 = d/dt r_c = A_c q̈ + D_q r_c[q̇] + ∂_t r_c
//! (D_q r_c[q̇] the derivative in q along q̇ with q̇ held), q̈ and λ solve
//!
//! ```text
//! [ H_vv  A_cᵀ ] [  q̈ ]   [ f + ∇_qL − H_vq q̇ − ∂_t∇_vL   ]
//! [ A_c   0    ] [ −λ ] = [ −(D_q r_c[q̇] + ∂_t r_c)       ]
//! ```
//!
//! (−λ as the unknown keeps the matrix symmetric). Then, in hamel's terms,
//!
//! * q̇ solves A q̇ = (0, w) − a (the constraints hold, the free rows give w);
//! * ẇ = A_f q̈ + D_q r_f[q̇] + ∂_t r_f (the free rows differentiated along the motion);
//! * the power dE/dt = f·q̇ − λᵀa_c − ∂_tL, from E = q̇·∂L/∂q̇ − L: along the motion
//!   dE/dt = q̇·(d/dt ∂L/∂q̇ − ∂L/∂q) − ∂_tL = q̇·(f + A_cᵀλ) − ∂_tL, and A_c q̇ = −a_c.
//!
//! Nothing comes from hamel: the rows and the Lagrangian are the mechanism's own (written in
//! the test, not the model's role functions), every derivative is taken here with num-dual's
//! dual and hyper-dual numbers, and every linear solve is nalgebra's LU with full pivoting.

use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use num_dual::{Dual64, DualNum, HyperDual64};

/// The number types the Lagrangian and the rows are evaluated on: f64 and num-dual's duals.
pub trait Real: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Real for T {}

/// A mechanism with n = `N` coordinates and affine, time-dependent rows.
pub trait Mechanism<const N: usize> {
    /// The number of constraint rows, the first ones of [`Mechanism::rows`].
    const P: usize;

    /// L(t, q, q̇).
    fn lagrangian<T: Real>(&self, t: T, q: &[T; N], qd: &[T; N]) -> T;

    /// ω = r(t, q, q̇): the constraints, then the free quasi-velocities. Must be affine in q̇.
    fn rows<T: Real>(&self, t: T, q: &[T; N], qd: &[T; N]) -> [T; N];

    /// The generalized forces f(t, q, q̇, u).
    fn forces(&self, t: f64, q: &[f64; N], qd: &[f64; N], u: &[f64]) -> [f64; N];
}

/// What the multiplier formulation gives at one state.
#[derive(Clone, Debug)]
pub struct Reference<const N: usize> {
    /// q̇, the admissible velocity of the state.
    pub qd: SVector<f64, N>,
    /// q̈.
    pub qdd: SVector<f64, N>,
    /// ω̇ of every row: the constrained entries are rounding (the solve's own check), the
    /// others are ẇ.
    pub omega_dot: SVector<f64, N>,
    /// λ, one per constraint row, in the convention above.
    pub lambda: DVector<f64>,
    /// What rounding in the force balance does to λ: see [`multiplier_scale`].
    pub multiplier_scale: f64,
    /// dE/dt = f·q̇ − λᵀa_c − ∂_tL.
    pub power: f64,
    /// Σ|f_i q̇_i| + Σ|λ_j a_j| + |∂_tL|: the size of the power's terms, which sets its
    /// rounding.
    pub power_scale: f64,
    /// E = q̇·∂L/∂q̇ − L.
    pub energy: f64,
    /// Σ|q̇_i ∂L/∂q̇_i| + |L|: the size of the energy's terms.
    pub energy_scale: f64,
    /// The solve's own check: max over the constraint rows of |ω̇_c| = |A_c q̈ + D_q r_c[q̇] +
    /// ∂_t r_c|, relative to the size of its terms.
    pub constraint_rate: f64,
}

/// A point (t, q, q̇), or a direction in that space: the seeds of one dual sweep.
#[derive(Clone, Copy)]
struct Phase<const N: usize> {
    t: f64,
    q: [f64; N],
    qd: [f64; N],
}

impl<const N: usize> Phase<N> {
    const NONE: Phase<N> = Phase {
        t: 0.0,
        q: [0.0; N],
        qd: [0.0; N],
    };

    fn along_q(direction: [f64; N]) -> Self {
        Phase {
            q: direction,
            ..Self::NONE
        }
    }

    fn along_qd(direction: [f64; N]) -> Self {
        Phase {
            qd: direction,
            ..Self::NONE
        }
    }

    /// ∂/∂t plus the derivative in q along q̇, q̇ held: the total time derivative of a
    /// function of (t, q, q̇) but for its q̈ part.
    fn drift(qd: [f64; N]) -> Self {
        Phase {
            t: 1.0,
            q: qd,
            qd: [0.0; N],
        }
    }

    fn unit(i: usize) -> [f64; N] {
        let mut e = [0.0; N];
        e[i] = 1.0;
        e
    }
}

type DualPoint<T, const N: usize> = (T, [T; N], [T; N]);

/// `at` with the first-order parts `d`.
fn dual<const N: usize>(at: &Phase<N>, d: &Phase<N>) -> DualPoint<Dual64, N> {
    (
        Dual64::new(at.t, d.t),
        std::array::from_fn(|i| Dual64::new(at.q[i], d.q[i])),
        std::array::from_fn(|i| Dual64::new(at.qd[i], d.qd[i])),
    )
}

/// `at` with the first-order parts `d1` and `d2`: the ε₁ε₂ part of a function of it is its
/// second derivative along d1 and d2.
fn hyper<const N: usize>(at: &Phase<N>, d1: &Phase<N>, d2: &Phase<N>) -> DualPoint<HyperDual64, N> {
    let h = |x: f64, a: f64, b: f64| HyperDual64::new(x, a, b, 0.0);
    (
        h(at.t, d1.t, d2.t),
        std::array::from_fn(|i| h(at.q[i], d1.q[i], d2.q[i])),
        std::array::from_fn(|i| h(at.qd[i], d1.qd[i], d2.qd[i])),
    )
}

/// The derivative of L at `at` along `d`.
fn lagrangian_along<M: Mechanism<N>, const N: usize>(m: &M, at: &Phase<N>, d: &Phase<N>) -> f64 {
    let (t, q, qd) = dual(at, d);
    m.lagrangian(t, &q, &qd).eps
}

/// The second derivative of L at `at` along `d1` and `d2`.
fn lagrangian_second<M: Mechanism<N>, const N: usize>(
    m: &M,
    at: &Phase<N>,
    d1: &Phase<N>,
    d2: &Phase<N>,
) -> f64 {
    let (t, q, qd) = hyper(at, d1, d2);
    m.lagrangian(t, &q, &qd).eps1eps2
}

/// The derivative of every row at `at` along `d`.
fn rows_along<M: Mechanism<N>, const N: usize>(
    m: &M,
    at: &Phase<N>,
    d: &Phase<N>,
) -> SVector<f64, N> {
    let (t, q, qd) = dual(at, d);
    SVector::from(m.rows(t, &q, &qd).map(|r| r.eps))
}

/// A(q, t) column by column (∂r/∂q̇_σ, exact for affine rows) and a(q, t) = r(t, q, 0).
fn transformation<M: Mechanism<N>, const N: usize>(
    m: &M,
    t: f64,
    q: &[f64; N],
) -> (SMatrix<f64, N, N>, SVector<f64, N>) {
    let at = Phase {
        t,
        q: *q,
        qd: [0.0; N],
    };
    let mut a = SMatrix::<f64, N, N>::zeros();
    for sigma in 0..N {
        let column = rows_along(m, &at, &Phase::along_qd(Phase::unit(sigma)));
        a.set_column(sigma, &column);
    }
    (a, SVector::from(m.rows(t, q, &[0.0; N])))
}

/// What the equations need of L at (t, q, q̇).
struct LagrangianTerms<const N: usize> {
    value: f64,
    grad_q: SVector<f64, N>,
    grad_v: SVector<f64, N>,
    /// ∂L/∂t.
    rate: f64,
    /// H_vv.
    hessian: SMatrix<f64, N, N>,
    /// H_vq q̇ + ∂_t∇_vL: d/dt ∂L/∂q̇ but for its H_vv q̈ part.
    drift: SVector<f64, N>,
}

fn lagrangian_terms<M: Mechanism<N>, const N: usize>(m: &M, at: &Phase<N>) -> LagrangianTerms<N> {
    let mut terms = LagrangianTerms {
        value: m.lagrangian(at.t, &at.q, &at.qd),
        grad_q: SVector::zeros(),
        grad_v: SVector::zeros(),
        rate: lagrangian_along(
            m,
            at,
            &Phase {
                t: 1.0,
                ..Phase::NONE
            },
        ),
        hessian: SMatrix::zeros(),
        drift: SVector::zeros(),
    };
    let drift = Phase::drift(at.qd);
    for i in 0..N {
        let (along_qi, along_vi) = (
            Phase::along_q(Phase::unit(i)),
            Phase::along_qd(Phase::unit(i)),
        );
        terms.grad_q[i] = lagrangian_along(m, at, &along_qi);
        terms.grad_v[i] = lagrangian_along(m, at, &along_vi);
        terms.drift[i] = lagrangian_second(m, at, &along_vi, &drift);
        for j in 0..N {
            let along_vj = Phase::along_qd(Phase::unit(j));
            terms.hessian[(i, j)] = lagrangian_second(m, at, &along_vi, &along_vj);
        }
    }
    terms
}

/// The admissible velocity of the state (t, q, w): A q̇ = (0, w) − a.
pub fn velocities<M: Mechanism<N>, const N: usize>(
    m: &M,
    t: f64,
    q: &[f64; N],
    w: &[f64],
) -> SVector<f64, N> {
    assert_eq!(w.len(), N - M::P, "one speed per free row");
    let (a, offset) = transformation(m, t, q);
    let mut omega = SVector::<f64, N>::zeros();
    omega.as_mut_slice()[M::P..].copy_from_slice(w);
    // nalgebra's LU wants a dimension it can name at compile time; N is generic here.
    let a = DMatrix::from_fn(N, N, |i, j| a[(i, j)]);
    let solved = a
        .full_piv_lu()
        .solve(&DVector::from_column_slice((omega - offset).as_slice()))
        .expect("the rows determine q̇");
    SVector::from_column_slice(solved.as_slice())
}

/// q̈ and λ from the index-1 system of the module's documentation.
fn accelerations<const N: usize>(
    h_vv: &SMatrix<f64, N, N>,
    a_c: &DMatrix<f64>,
    force_side: &SVector<f64, N>,
    constraint_side: &DVector<f64>,
) -> (SVector<f64, N>, DVector<f64>) {
    let p = a_c.nrows();
    let mut kkt = DMatrix::<f64>::zeros(N + p, N + p);
    kkt.view_mut((0, 0), (N, N)).copy_from(h_vv);
    kkt.view_mut((0, N), (N, p)).copy_from(&a_c.transpose());
    kkt.view_mut((N, 0), (p, N)).copy_from(a_c);
    let mut side = DVector::<f64>::zeros(N + p);
    side.rows_mut(0, N).copy_from(force_side);
    side.rows_mut(N, p).copy_from(constraint_side);
    let solution = kkt
        .full_piv_lu()
        .solve(&side)
        .expect("the index-1 system is regular: H_vv definite on the admissible velocities");
    let qdd = SVector::<f64, N>::from_iterator(solution.rows(0, N).iter().copied());
    let lambda = -solution.rows(N, p).into_owned();
    (qdd, lambda)
}

/// The size of the generalized forces the multipliers balance, A_cᵀλ = H_vv q̈ − (f + ∇_qL −
/// H_vq q̇ − ∂_t∇_vL), carried over to the multipliers: ‖G‖₂/σ_min(A_c), G the sum of the
/// terms' magnitudes, component by component. Rounding in those terms moves λ by about ε
/// times this, however small λ itself is.
fn multiplier_scale<const N: usize>(
    l: &LagrangianTerms<N>,
    f: &SVector<f64, N>,
    qdd: &SVector<f64, N>,
    a_c: &DMatrix<f64>,
) -> f64 {
    let terms = l.hessian.abs() * qdd.abs() + f.abs() + l.grad_q.abs() + l.drift.abs();
    let smallest = a_c.singular_values().min();
    terms.norm() / smallest
}

/// The multiplier formulation at the state (t, q, w) with inputs u.
pub fn reference<M: Mechanism<N>, const N: usize>(
    m: &M,
    t: f64,
    q: &[f64; N],
    w: &[f64],
    u: &[f64],
) -> Reference<N> {
    let p = M::P;
    let qd = velocities(m, t, q, w);
    let at = Phase {
        t,
        q: *q,
        qd: qd.into(),
    };
    let (a, offset) = transformation(m, t, q);
    let a_c = DMatrix::from_fn(p, N, |i, j| a[(i, j)]);
    // D_q r[q̇] + ∂_t r, every row: ω̇ = A q̈ + this.
    let rows_drift = rows_along(m, &at, &Phase::drift(at.qd));
    let l = lagrangian_terms(m, &at);
    let f = SVector::from(m.forces(t, q, &at.qd, u));

    let force_side = f + l.grad_q - l.drift;
    let constraint_side = -DVector::from_iterator(p, rows_drift.iter().take(p).copied());
    let (qdd, lambda) = accelerations(&l.hessian, &a_c, &force_side, &constraint_side);

    let a_constrained = DVector::from_iterator(p, offset.iter().take(p).copied());
    let legendre = qd.dot(&l.grad_v);
    let omega_dot = a * qdd + rows_drift;
    let term_size = a.abs() * qdd.abs() + rows_drift.abs();
    Reference {
        qd,
        qdd,
        omega_dot,
        power: f.dot(&qd) - lambda.dot(&a_constrained) - l.rate,
        // The scales of the sums: their terms' magnitudes, which set what rounding leaves.
        power_scale: f.abs().dot(&qd.abs()) + lambda.abs().dot(&a_constrained.abs()) + l.rate.abs(),
        multiplier_scale: multiplier_scale(&l, &f, &qdd, &a_c),
        lambda,
        energy: legendre - l.value,
        energy_scale: qd.abs().dot(&l.grad_v.abs()) + l.value.abs(),
        constraint_rate: (0..p)
            .map(|i| omega_dot[i].abs() / term_size[i].max(f64::MIN_POSITIVE))
            .fold(0.0, f64::max),
    }
}
