//! Linearization, reduction and modes on hand-written systems whose answers are known in
//! closed form: a damped mass–spring chain, a cart with a pendulum (its position is cyclic),
//! and a crank held by a spring whose height a holonomic constraint determines, against the
//! same crank in minimal coordinates.
//!
//! Run with `--nocapture` to see the measured figures and the printed tables.

use crate::common;

use hamel_runtime::{
    Error, HamelSystem, Linearization, Mode, Num, Parameters, Scalar, Singularity,
    jacobian_by_duals,
};
use nalgebra::{Complex, DMatrix};
use std::f64::consts::PI;

/// `Parameters` for a struct of `f64` fields.
macro_rules! parameters {
    (impl[$($generics:tt)*] $ty:ty { $($field:ident: $doc:literal),* $(,)? }) => {
        impl<$($generics)*> Parameters for $ty {
            const NAMES: &'static [&'static str] = &[$(stringify!($field)),*];
            const DOCS: &'static [&'static str] = &[$($doc),*];

            fn get(&self, name: &str) -> Option<f64> {
                match name {
                    $(stringify!($field) => Some(self.$field),)*
                    _ => None,
                }
            }

            fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
                match name {
                    $(stringify!($field) => self.$field = value,)*
                    _ => {
                        return Err(Error::UnknownParameter {
                            name: name.into(),
                            known: Self::NAMES.join(", "),
                        })
                    }
                }
                Ok(())
            }
        }
    };
}

/// `value` as the mass-matrix pivot of speed number `speed`, or the singularity if it is not
/// positive.
fn positive(value: f64, speed: usize) -> Result<f64, Singularity> {
    if value.is_nan() || value <= 0.0 {
        return Err(Singularity::MassMatrix { speed, value });
    }
    Ok(value)
}

// ---------------------------------------------------------------------------------------
// A damped chain: three masses m between two walls, joined by four springs k and four
// dampers c (a damping proportional to the stiffness). With K = k·tridiag(−1, 2, −1) the
// modes of K/m are φⱼ(i) = sin(ijπ/4) with ωⱼ² = (4k/m) sin²(jπ/8), and each gives the pair
// λ = −ζⱼωⱼ ± iωⱼ√(1 − ζⱼ²), ζⱼ = (c/k)ωⱼ/2, of A = [0 I; −K/m −C/m] with the eigenvector
// (φⱼ, λφⱼ). A force pushes the first mass.
// ---------------------------------------------------------------------------------------

struct Chain {
    mass: f64,
    stiffness: f64,
    damping: f64,
}

parameters!(impl[] Chain {
    mass: "mass of each body",
    stiffness: "stiffness of each spring",
    damping: "damping coefficient of each damper",
});

const CHAIN: Chain = Chain {
    mass: 1.5,
    stiffness: 2.0,
    damping: 0.3,
};

impl Chain {
    /// k·tridiag(−1, 2, −1) · q for a coordinate (or velocity) vector.
    fn tridiagonal(q: &[f64]) -> [f64; 3] {
        [
            2.0 * q[0] - q[1],
            -q[0] + 2.0 * q[1] - q[2],
            -q[1] + 2.0 * q[2],
        ]
    }
}

impl HamelSystem for Chain {
    type Coordinates = [f64; 3];
    type Speeds = [f64; 3];
    type Constraints = [f64; 0];
    type State = [f64; 6];
    type Inputs = [f64; 1];
    type Holonomic = [f64; 0];
    type HolonomicJacobian = [f64; 0];
    type Extended = [f64; 7];
    type MassMatrix = [[f64; 3]; 3];
    type Gamma = [[[f64; 3]; 3]; 3];
    type StateJacobian = [f64; 36];
    type InputJacobian = [f64; 6];

    const N: usize = 3;
    const P: usize = 0;
    const M: usize = 1;
    const K: usize = 0;
    const COORDINATES: &'static [&'static str] = &["q1", "q2", "q3"];
    const SPEEDS: &'static [&'static str] = &["v1", "v2", "v3"];
    const CONSTRAINTS: &'static [&'static str] = &[];
    const INPUTS: &'static [&'static str] = &["push"];
    const STATE: &'static [&'static str] = &["q1", "q2", "q3", "v1", "v2", "v3"];
    const DEPENDENT: &'static [usize] = &[];
    const CONSERVATIVE: bool = false;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 6],
        u: &[f64; 1],
        dx: &mut [f64; 6],
    ) -> Result<(), Singularity> {
        let m = positive(self.mass, 0)?;
        let (kq, cv) = (Self::tridiagonal(&x[..3]), Self::tridiagonal(&x[3..]));
        dx[..3].copy_from_slice(&x[3..]);
        for i in 0..3 {
            let push = if i == 0 { u[0] } else { 0.0 };
            dx[3 + i] = (push - self.stiffness * kq[i] - self.damping * cv[i]) / m;
        }
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 6]) -> Result<[f64; 3], Singularity> {
        Ok([x[3], x[4], x[5]])
    }

    fn energy(&self, _t: f64, x: &[f64; 6]) -> Result<f64, Singularity> {
        let kq = Self::tridiagonal(&x[..3]);
        let kinetic: f64 = x[3..].iter().map(|v| 0.5 * self.mass * v * v).sum();
        let potential: f64 = (0..3).map(|i| 0.5 * self.stiffness * x[i] * kq[i]).sum();
        Ok(kinetic + potential)
    }

    /// The push's power minus the dampers' dissipation vᵀCv.
    fn power(&self, _t: f64, x: &[f64; 6], u: &[f64; 1]) -> Result<f64, Singularity> {
        let cv = Self::tridiagonal(&x[3..]);
        let dissipated: f64 = (0..3).map(|i| self.damping * x[3 + i] * cv[i]).sum();
        Ok(u[0] * x[3] - dissipated)
    }

    fn multipliers(&self, _t: f64, _x: &[f64; 6], _u: &[f64; 1]) -> Result<[f64; 0], Singularity> {
        Ok([])
    }

    fn constraint_residual(&self, _t: f64, _q: &[f64; 3], _qd: &[f64; 3]) -> [f64; 0] {
        []
    }

    fn speeds(&self, _t: f64, _q: &[f64; 3], qd: &[f64; 3]) -> [f64; 3] {
        *qd
    }

    fn holonomic_residual(&self, _t: f64, _q: &[f64; 3]) -> [f64; 0] {
        []
    }

    fn holonomic_jacobian(&self, _t: f64, _q: &[f64; 3]) -> [f64; 0] {
        []
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 6]) -> Result<[[f64; 3]; 3], Singularity> {
        let m = positive(self.mass, 0)?;
        Ok([[m, 0.0, 0.0], [0.0, m, 0.0], [0.0, 0.0, m]])
    }

    /// The speeds are the velocities (B = I): no γ.
    fn gamma(&self, _t: f64, _q: &[f64; 3]) -> Result<[[[f64; 3]; 3]; 3], Singularity> {
        Ok([[[0.0; 3]; 3]; 3])
    }

    fn inverse_defect(&self, _t: f64, _q: &[f64; 3]) -> Result<f64, Singularity> {
        Ok(0.0)
    }

    /// A = [0 I; −(k/m)T −(c/m)T] with T = tridiag(−1, 2, −1); B = e₄/m.
    fn jacobian(
        &self,
        _t: f64,
        _x: &[f64; 6],
        _u: &[f64; 1],
    ) -> Result<([f64; 36], [f64; 6]), Singularity> {
        let m = positive(self.mass, 0)?;
        let mut a = [0.0; 36];
        for i in 0..3 {
            a[i * 6 + 3 + i] = 1.0;
            for j in 0..3 {
                let t = match i.abs_diff(j) {
                    0 => 2.0,
                    1 => -1.0,
                    _ => 0.0,
                };
                a[(3 + i) * 6 + j] = -self.stiffness * t / m;
                a[(3 + i) * 6 + 3 + j] = -self.damping * t / m;
            }
        }
        let mut b = [0.0; 6];
        b[3] = 1.0 / m;
        Ok((a, b))
    }
}

/// The chain's eigenvalues in closed form, with the mode shape each belongs to.
fn chain_modes() -> Vec<(Complex<f64>, [f64; 3])> {
    let mut modes = Vec::new();
    for j in 1..=3 {
        let j = j as f64;
        let omega = (4.0 * CHAIN.stiffness / CHAIN.mass).sqrt() * (j * PI / 8.0).sin();
        let zeta = CHAIN.damping / CHAIN.stiffness * omega / 2.0;
        let shape = [1.0, 2.0, 3.0].map(|i: f64| (i * j * PI / 4.0).sin());
        let damped = omega * (1.0 - zeta * zeta).sqrt();
        for sign in [1.0, -1.0] {
            modes.push((Complex::new(-zeta * omega, sign * damped), shape));
        }
    }
    modes
}

/// ‖(A − λI)v‖₂ of a mode.
fn residual(a: &DMatrix<f64>, mode: &Mode) -> f64 {
    let v: Vec<Complex<f64>> = mode.vector.iter().map(|(_, c)| *c).collect();
    (0..a.nrows())
        .map(|i| {
            let av: Complex<f64> = (0..a.ncols()).map(|j| v[j] * a[(i, j)]).sum();
            (av - mode.value * v[i]).norm_sqr()
        })
        .sum::<f64>()
        .sqrt()
}

/// Checks the modes of `linearization`: each residual ‖(A − λI)v‖ ≤ 10⁻¹²‖A‖, each vector's
/// largest component exactly 1, the order (real part, then imaginary part, descending), and
/// that conjugate eigenvalues have conjugate vectors. Returns the largest residual/‖A‖.
fn check_modes(linearization: &Linearization, modes: &[Mode]) -> f64 {
    let a = linearization.a_matrix();
    let norm = a.norm();
    let mut worst = 0.0f64;
    for mode in modes {
        let r = residual(a, mode) / norm;
        worst = worst.max(r);
        assert!(r <= 1e-12, "{mode}: residual {r:e}");
        let largest = mode
            .vector
            .iter()
            .map(|(_, c)| c.norm())
            .fold(0.0, f64::max);
        assert!(largest <= 1.0 + 1e-9, "{mode}");
        assert!(
            mode.vector
                .iter()
                .any(|(_, c)| *c == Complex::new(1.0, 0.0)),
            "{mode}"
        );
        let names: Vec<&str> = mode.vector.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, linearization.states());
    }
    for pair in modes.windows(2) {
        let (x, y) = (pair[0].value, pair[1].value);
        assert!(
            x.re > y.re || (x.re == y.re && x.im >= y.im),
            "order: {x} before {y}"
        );
    }
    // A lower mode of a conjugate pair has the conjugate vector of an upper one.
    for (i, mode) in modes.iter().enumerate().filter(|(_, m)| m.value.im < 0.0) {
        let conjugate: Vec<(String, Complex<f64>)> = mode
            .vector
            .iter()
            .map(|(n, c)| (n.clone(), c.conj()))
            .collect();
        assert!(
            modes[..i]
                .iter()
                .any(|m| m.value == mode.value.conj() && m.vector == conjugate),
            "{mode}"
        );
    }
    worst
}

#[test]
fn the_chains_modes_are_its_closed_form_ones() {
    let linearization = CHAIN.linearize(0.0, &[0.0; 6], &[0.0]).unwrap();
    println!("{linearization}");
    let modes = linearization.modes().unwrap();
    let worst = check_modes(&linearization, &modes);
    let mut exact = chain_modes();
    exact.sort_by(|x, y| y.0.re.total_cmp(&x.0.re).then(y.0.im.total_cmp(&x.0.im)));
    let scale = linearization.a_matrix().norm();
    let mut worst_value = 0.0f64;
    let mut worst_vector = 0.0f64;
    for (mode, (value, shape)) in modes.iter().zip(&exact) {
        println!("{mode}");
        worst_value = worst_value.max((mode.value - value).norm() / scale);
        // The closed-form vector (φ, λφ), compared up to a complex factor: the component of
        // the computed vector orthogonal to it.
        let w: Vec<Complex<f64>> = shape
            .iter()
            .map(|s| Complex::new(*s, 0.0))
            .chain(shape.iter().map(|s| value * *s))
            .collect();
        let v: Vec<Complex<f64>> = mode.vector.iter().map(|(_, c)| *c).collect();
        let dot: Complex<f64> = w.iter().zip(&v).map(|(w, v)| w.conj() * v).sum();
        let ww: f64 = w.iter().map(|w| w.norm_sqr()).sum();
        let off: f64 = w
            .iter()
            .zip(&v)
            .map(|(w, v)| (v - dot / ww * w).norm_sqr())
            .sum();
        let vv: f64 = v.iter().map(|v| v.norm_sqr()).sum();
        worst_vector = worst_vector.max((off / vv).sqrt());
        let zeta = CHAIN.damping / CHAIN.stiffness * value.norm() / 2.0;
        assert!((mode.damping_ratio().unwrap() - zeta).abs() <= 1e-12);
        assert!((mode.natural_frequency() - value.norm()).abs() <= 1e-12 * scale);
    }
    println!(
        "eigenvalues within {worst_value:.1e}·‖A‖ of the closed form, vectors within \
         {worst_vector:.1e}, residuals ≤ {worst:.1e}·‖A‖"
    );
    assert!(worst_value <= 1e-13, "{worst_value:e}");
    assert!(worst_vector <= 1e-12, "{worst_vector:e}");
    // Every mode decays: the chain is damped.
    assert!(modes.iter().all(|m| m.value.re < 0.0));
}

#[test]
fn the_chains_matrices_are_named() {
    let x = [0.1, -0.2, 0.3, 0.0, 0.5, 0.0];
    let linearization = CHAIN.linearize(2.0, &x, &[0.7]).unwrap();
    let (k, c, m) = (CHAIN.stiffness, CHAIN.damping, CHAIN.mass);
    assert_eq!(linearization.a("v2", "q1").unwrap(), k / m);
    assert_eq!(linearization.a("v2", "q2").unwrap(), -2.0 * k / m);
    assert_eq!(linearization.a("v2", "v3").unwrap(), c / m);
    assert_eq!(linearization.a("q3", "v3").unwrap(), 1.0);
    assert_eq!(linearization.a("q1", "q3").unwrap(), 0.0);
    assert_eq!(linearization.b("v1", "push").unwrap(), 1.0 / m);
    assert_eq!(linearization.b("v2", "push").unwrap(), 0.0);
    let point = linearization.operating_point().unwrap();
    assert_eq!(point.t, 2.0);
    assert_eq!(point.state.get("q3"), Some(0.3));
    assert_eq!(point.inputs.get("push"), Some(0.7));
    assert!(linearization.holonomic().is_empty());
}

// ---------------------------------------------------------------------------------------
// A cart of mass M on a rail at s with a pendulum of mass m and length ℓ at angle θ from the
// downward vertical, a viscous friction b at the pivot and a force F on the cart:
//   (M + m) s̈ + mℓ cos θ θ̈ = F + mℓ θ̇² sin θ,   mℓ cos θ s̈ + mℓ² θ̈ = −mgℓ sin θ − b θ̇.
// The right-hand side is generic over `Scalar` and solves the mass matrix by LDLᵀ, as
// generated code does, so that its Jacobian comes from dual numbers through the solve
// (`jacobian_by_duals`). The cart's position s is cyclic.
// ---------------------------------------------------------------------------------------

struct CartPendulum {
    cart: f64,
    bob: f64,
    length: f64,
    gravity: f64,
    friction: f64,
}

parameters!(impl[] CartPendulum {
    cart: "mass of the cart",
    bob: "mass of the pendulum's bob",
    length: "length of the pendulum",
    gravity: "gravitational acceleration",
    friction: "viscous friction at the pivot",
});

const CART: CartPendulum = CartPendulum {
    cart: 2.0,
    bob: 0.5,
    length: 0.8,
    gravity: 9.81,
    friction: 0.1,
};

impl CartPendulum {
    /// The rates (v, ω, v̇, ω̇) in any scalar type: the LDLᵀ factors of the mass matrix
    /// [[M + m, mℓ cos θ], [mℓ cos θ, mℓ²]] with their pivots checked, then the solve.
    fn rhs_generic<T: Scalar>(
        &self,
        x: &[T; 4],
        u: &[T; 1],
        dx: &mut [T; 4],
    ) -> Result<(), Singularity> {
        let c = T::from_f64;
        let [_, theta, v, omega] = *x;
        let (m, l) = (self.bob, self.length);
        let d0 = c(self.cart + m);
        positive(d0.re(), 0)?;
        let l10 = c(m * l) * theta.cos() / d0;
        let d1 = c(m * l * l) - l10 * l10 * d0;
        positive(d1.re(), 1)?;
        let r0 = u[0] + c(m * l) * omega * omega * theta.sin();
        let r1 = -c(m * self.gravity * l) * theta.sin() - c(self.friction) * omega;
        let omega_dot = (r1 - l10 * r0) / d1;
        let v_dot = r0 / d0 - l10 * omega_dot;
        *dx = [v, omega, v_dot, omega_dot];
        Ok(())
    }
}

impl HamelSystem for CartPendulum {
    type Coordinates = [f64; 2];
    type Speeds = [f64; 2];
    type Constraints = [f64; 0];
    type State = [f64; 4];
    type Inputs = [f64; 1];
    type Holonomic = [f64; 0];
    type HolonomicJacobian = [f64; 0];
    type Extended = [f64; 5];
    type MassMatrix = [[f64; 2]; 2];
    type Gamma = [[[f64; 2]; 2]; 2];
    type StateJacobian = [f64; 16];
    type InputJacobian = [f64; 4];

    const N: usize = 2;
    const P: usize = 0;
    const M: usize = 1;
    const K: usize = 0;
    const COORDINATES: &'static [&'static str] = &["s", "theta"];
    const SPEEDS: &'static [&'static str] = &["v", "omega"];
    const CONSTRAINTS: &'static [&'static str] = &[];
    const INPUTS: &'static [&'static str] = &["force"];
    const STATE: &'static [&'static str] = &["s", "theta", "v", "omega"];
    const DEPENDENT: &'static [usize] = &[];
    const CONSERVATIVE: bool = false;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 4],
        u: &[f64; 1],
        dx: &mut [f64; 4],
    ) -> Result<(), Singularity> {
        self.rhs_generic(x, u, dx)
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 4]) -> Result<[f64; 2], Singularity> {
        Ok([x[2], x[3]])
    }

    fn energy(&self, _t: f64, x: &[f64; 4]) -> Result<f64, Singularity> {
        let [_, theta, v, omega] = *x;
        let (m, l) = (self.bob, self.length);
        let kinetic = 0.5 * (self.cart + m) * v * v
            + m * l * v * omega * theta.cos()
            + 0.5 * m * l * l * omega * omega;
        Ok(kinetic - m * self.gravity * l * theta.cos())
    }

    fn power(&self, _t: f64, x: &[f64; 4], u: &[f64; 1]) -> Result<f64, Singularity> {
        Ok(u[0] * x[2] - self.friction * x[3] * x[3])
    }

    fn multipliers(&self, _t: f64, _x: &[f64; 4], _u: &[f64; 1]) -> Result<[f64; 0], Singularity> {
        Ok([])
    }

    fn constraint_residual(&self, _t: f64, _q: &[f64; 2], _qd: &[f64; 2]) -> [f64; 0] {
        []
    }

    fn speeds(&self, _t: f64, _q: &[f64; 2], qd: &[f64; 2]) -> [f64; 2] {
        *qd
    }

    fn holonomic_residual(&self, _t: f64, _q: &[f64; 2]) -> [f64; 0] {
        []
    }

    fn holonomic_jacobian(&self, _t: f64, _q: &[f64; 2]) -> [f64; 0] {
        []
    }

    fn mass_matrix(&self, _t: f64, x: &[f64; 4]) -> Result<[[f64; 2]; 2], Singularity> {
        let (m, l) = (self.bob, self.length);
        let coupling = m * l * x[1].cos();
        Ok([[self.cart + m, coupling], [coupling, m * l * l]])
    }

    /// The speeds are the velocities (B = I): no γ.
    fn gamma(&self, _t: f64, _q: &[f64; 2]) -> Result<[[[f64; 2]; 2]; 2], Singularity> {
        Ok([[[0.0; 2]; 2]; 2])
    }

    fn inverse_defect(&self, _t: f64, _q: &[f64; 2]) -> Result<f64, Singularity> {
        Ok(0.0)
    }

    fn jacobian(
        &self,
        t: f64,
        x: &[f64; 4],
        u: &[f64; 1],
    ) -> Result<([f64; 16], [f64; 4]), Singularity> {
        jacobian_by_duals(t, x, u, &[0, 1, 2, 3, 4], |_, x, u, dx| {
            self.rhs_generic(x, u, dx)
        })
    }
}

/// At a point where every term of the nonlinear right-hand side matters, the dual-number
/// Jacobian that `linearize` returns agrees with central differences of `rhs`.
#[test]
fn linearize_agrees_with_central_differences() {
    let (x, u) = ([0.3, 0.7, -0.4, 1.1], [0.5]);
    let linearization = CART.linearize(1.5, &x, &u).unwrap();
    let (a, b) = common::central_differences(&CART, 1.5, &x, &u);
    let row_major = |m: &DMatrix<f64>| -> Vec<f64> { m.transpose().iter().copied().collect() };
    let (da, db) = (
        common::relative_difference(&row_major(linearization.a_matrix()), &a),
        common::relative_difference(&row_major(linearization.b_matrix()), &b),
    );
    println!("linearization vs central differences: A {da:.1e}, B {db:.1e} relative");
    assert!(da <= 1e-6 && db <= 1e-6, "{da:e} {db:e}");
    // The entries are where the names say.
    assert_eq!(linearization.a("s", "v").unwrap(), 1.0);
    assert!((linearization.a("v", "theta").unwrap() - a[2 * 4 + 1]).abs() <= 1e-6);
    assert!((linearization.b("omega", "force").unwrap() - b[3]).abs() <= 1e-6);
}

/// Hanging down and at rest, the cart's position is cyclic: the kept (θ, v, ω) do not depend
/// on it, and the reduced A is [[0, 0, 1], [mg/M, 0, b/(Mℓ)], [−(M+m)g/(Mℓ), 0,
/// −(M+m)b/(Mmℓ²)]]: eigenvalues 0 and the roots of λ² + (M+m)b/(Mmℓ²) λ + (M+m)g/(Mℓ).
#[test]
fn the_carts_position_is_cyclic_and_drops_out() {
    let linearization = CART.linearize(0.0, &[0.4, 0.0, 0.0, 0.0], &[0.0]).unwrap();
    let reduced = linearization.reduce(&["theta", "v", "omega"]).unwrap();
    println!("{reduced}");
    assert_eq!(reduced.states(), ["theta", "v", "omega"]);
    assert_eq!(reduced.operating_point().unwrap().state.0.len(), 3);
    let CartPendulum {
        cart: big,
        bob: m,
        length: l,
        gravity: g,
        friction: b,
    } = CART;
    let exact = DMatrix::from_row_slice(
        3,
        3,
        &[
            0.0,
            0.0,
            1.0,
            m * g / big,
            0.0,
            b / (big * l),
            -(big + m) * g / (big * l),
            0.0,
            -(big + m) * b / (big * m * l * l),
        ],
    );
    // Rounding: a few dozen operations through the LDLᵀ solve, each within ε.
    let difference = (reduced.a_matrix() - &exact).amax() / exact.amax();
    println!("reduced A vs closed form: {difference:.1e} relative");
    assert!(difference <= 1e-14, "{difference:e}\n{reduced}");
    let b_exact = [0.0, 1.0 / big, -1.0 / (big * l)];
    for (row, value) in ["theta", "v", "omega"].iter().zip(b_exact) {
        assert!((reduced.b(row, "force").unwrap() - value).abs() <= 1e-15);
    }
    let modes = reduced.modes().unwrap();
    check_modes(&reduced, &modes);
    let (half, square) = (
        (big + m) * b / (2.0 * big * m * l * l),
        (big + m) * g / (big * l),
    );
    let root = Complex::new(-half, (square - half * half).sqrt());
    for (mode, value) in modes
        .iter()
        .zip([Complex::new(0.0, 0.0), root, root.conj()])
    {
        println!("{mode}");
        assert!(
            (mode.value - value).norm() <= 1e-13 * square.sqrt(),
            "{mode}"
        );
    }
    // The mode at 0 is the cart's uniform motion: θ = ω = 0, v free.
    assert_eq!(modes[0].component("v").unwrap(), Complex::new(1.0, 0.0));
    assert!(modes[0].component("theta").unwrap().norm() <= 1e-15);
}

/// Upright (θ = π) the pendulum falls: a real eigenvalue > 0, the least stable mode, first.
/// The full A has a double, defective eigenvalue 0 (s and v: a Jordan block), whose modes
/// share their one eigenvector.
#[test]
fn the_upright_pendulum_is_unstable_and_the_cart_defective() {
    let linearization = CART.linearize(0.0, &[0.0, PI, 0.0, 0.0], &[0.0]).unwrap();
    let modes = linearization.modes().unwrap();
    check_modes(&linearization, &modes);
    for mode in &modes {
        println!("{mode}");
    }
    let CartPendulum {
        cart: big,
        bob: m,
        length: l,
        gravity: g,
        friction: b,
    } = CART;
    // λ² + (M+m)b/(Mmℓ²) λ − (M+m)g/(Mℓ) = 0 upright (cos θ = −1 flips the coupling's sign,
    // which the quadratic does not see, and the gravity's).
    let (half, square) = (
        (big + m) * b / (2.0 * big * m * l * l),
        (big + m) * g / (big * l),
    );
    let growing = -half + (half * half + square).sqrt();
    assert!((modes[0].value - Complex::new(growing, 0.0)).norm() <= 1e-12 * growing);
    assert!(modes[0].damping_ratio().unwrap() == -1.0);
    let zeros: Vec<&Mode> = modes.iter().filter(|m| m.value.norm() <= 1e-12).collect();
    assert_eq!(zeros.len(), 2, "{modes:?}");
    assert_eq!(zeros[0].vector, zeros[1].vector);
    assert_eq!(zeros[0].component("s").unwrap(), Complex::new(1.0, 0.0));
    assert_eq!(zeros[0].damping_ratio(), None);
}

#[test]
fn dropping_a_state_the_kept_ones_depend_on_is_an_error() {
    let linearization = CART.linearize(0.0, &[0.4, 0.3, 0.2, 0.1], &[0.0]).unwrap();
    match linearization.reduce(&["s", "v", "omega"]) {
        Err(e @ Error::NotCyclic { .. }) => {
            let message = e.to_string();
            println!("{message}");
            let Error::NotCyclic {
                name,
                kept,
                derivative,
                tolerance,
            } = e
            else {
                unreachable!()
            };
            assert_eq!((name.as_str(), kept.as_str()), ("theta", "v"));
            assert_eq!(derivative, linearization.a("v", "theta").unwrap());
            assert!(tolerance > 0.0 && tolerance < 1e-10);
            assert!(message.contains("cannot drop `theta`"), "{message}");
            assert!(message.contains("`v` depends on it"), "{message}");
            assert!(!message.contains("  "), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn unknown_and_repeated_names_are_errors_listing_the_known_ones() {
    let linearization = CART.linearize(0.0, &[0.0; 4], &[0.0]).unwrap();
    let expect_unknown =
        |result: Result<f64, Error>, kind: &str, name: &str, known: &str| match result {
            Err(e @ Error::UnknownName { .. }) => {
                let message = e.to_string();
                assert_eq!(
                    message,
                    format!("unknown {kind} `{name}`; the {kind}s are: {known}")
                );
            }
            other => panic!("{other:?}"),
        };
    let states = "s, theta, v, omega";
    expect_unknown(linearization.a("phi", "s"), "state", "phi", states);
    expect_unknown(linearization.a("s", "x"), "state", "x", states);
    expect_unknown(
        linearization.b("omega", "torque"),
        "input",
        "torque",
        "force",
    );
    let modes = linearization.modes().unwrap();
    expect_unknown(
        modes[0].component("vel").map(|c| c.re),
        "state",
        "vel",
        states,
    );
    match linearization.reduce(&["theta", "speed"]) {
        Err(Error::UnknownName { name, known, .. }) => {
            assert_eq!((name.as_str(), known.as_str()), ("speed", states))
        }
        other => panic!("{other:?}"),
    }
    match linearization.reduce(&["theta", "v", "omega", "v"]) {
        Err(Error::DuplicateName { kind, name, .. }) => {
            assert_eq!((kind, name.as_str()), ("state", "v"))
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_bad_operating_point_is_an_error_naming_the_value() {
    let x = [0.0, 0.1, 0.0, 0.0];
    let cases: [(f64, [f64; 4], [f64; 1], &str); 3] = [
        (f64::NAN, x, [0.0], "t"),
        (0.0, [0.0, 0.1, f64::INFINITY, 0.0], [0.0], "v"),
        (0.0, x, [f64::NEG_INFINITY], "force"),
    ];
    for (t, x, u, expected) in cases {
        match CART.linearize(t, &x, &u) {
            Err(e @ Error::NonFiniteOperatingPoint { .. }) => {
                let message = e.to_string();
                let Error::NonFiniteOperatingPoint { name, value } = e else {
                    unreachable!()
                };
                assert_eq!(name, expected);
                assert!(!value.is_finite());
                assert!(message.starts_with(&format!("the operating point's `{expected}` is ")));
            }
            other => panic!("{expected}: {other:?}"),
        }
    }
    // A crank whose end is not where the crank puts it: the elimination of y would assume a
    // constraint that does not hold.
    match spring_crank::<1>().linearize(0.0, &[0.3, 0.2, 0.0], &[0.0]) {
        Err(Error::HolonomicViolation {
            constraint,
            coordinate,
            residual,
            ..
        }) => {
            assert_eq!(
                (constraint.as_str(), coordinate.as_str()),
                ("crank[0]", "y")
            );
            assert!((residual - (0.2 - 0.5 * 0.3f64.sin())).abs() <= 1e-16);
        }
        other => panic!("{other:?}"),
    }
    let broken = CartPendulum {
        gravity: f64::NAN,
        ..CART
    };
    match broken.linearize(0.0, &x, &[0.0]) {
        Err(Error::InvalidParameter { name, .. }) => assert_eq!(name, "gravity"),
        other => panic!("{other:?}"),
    }
}

/// Without a cart (M = 0), the pendulum hanging straight down cannot move sideways relative to
/// the cart: the mass matrix [[m, mℓ], [mℓ, mℓ²]] is singular there, and only there.
#[test]
fn a_singular_configuration_is_an_error_naming_time_and_state() {
    let no_cart = CartPendulum { cart: 0.0, ..CART };
    let x = [0.25, 0.0, 0.5, 0.0];
    match no_cart.linearize(3.0, &x, &[0.0]) {
        Err(e @ Error::SingularMassMatrix { .. }) => {
            let message = e.to_string();
            println!("{message}");
            let Error::SingularMassMatrix {
                t, speed, state, ..
            } = e
            else {
                unreachable!()
            };
            assert_eq!((t, speed.as_str()), (3.0, "omega"));
            assert_eq!(state, CartPendulum::named_state(&x));
            assert!(message.contains("s = 0.25"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    assert!(
        no_cart
            .linearize(3.0, &[0.25, 0.2, 0.5, 0.0], &[0.0])
            .is_ok()
    );
}

// ---------------------------------------------------------------------------------------
// A crank of inertia I at angle θ whose end, at height y = ℓ sin θ, is held by a spring k to
// y = 0; a torque τ drives it. Coordinates (θ, y), the holonomic constraint
// f = y − ℓ sin θ = 0 with the dependent coordinate D (1: y, 0: θ), the free speed ω = θ̇:
//   θ̇ = ω,   ẏ = ℓ cos θ ω,   I ω̇ = τ − kℓ y cos θ   (the spring's force k y through the lever).
// In minimal coordinates (θ, ω): I ω̇ = τ − kℓ² sin θ cos θ.
// ---------------------------------------------------------------------------------------

struct SpringCrank<const D: usize> {
    inertia: f64,
    stiffness: f64,
    length: f64,
}

parameters!(impl[const D: usize] SpringCrank<D> {
    inertia: "moment of inertia of the crank",
    stiffness: "stiffness of the spring",
    length: "length of the crank",
});

const fn spring_crank<const D: usize>() -> SpringCrank<D> {
    SpringCrank {
        inertia: 0.4,
        stiffness: 3.0,
        length: 0.5,
    }
}

impl<const D: usize> HamelSystem for SpringCrank<D> {
    type Coordinates = [f64; 2];
    type Speeds = [f64; 1];
    type Constraints = [f64; 1];
    type State = [f64; 3];
    type Inputs = [f64; 1];
    type Holonomic = [f64; 1];
    type HolonomicJacobian = [f64; 2];
    type Extended = [f64; 4];
    type MassMatrix = [[f64; 1]; 1];
    type Gamma = [[[f64; 1]; 1]; 2];
    type StateJacobian = [f64; 9];
    type InputJacobian = [f64; 3];

    const N: usize = 2;
    const P: usize = 1;
    const M: usize = 1;
    const K: usize = 1;
    const COORDINATES: &'static [&'static str] = &["theta", "y"];
    const SPEEDS: &'static [&'static str] = &["omega"];
    const CONSTRAINTS: &'static [&'static str] = &["crank[0]"];
    const INPUTS: &'static [&'static str] = &["torque"];
    const STATE: &'static [&'static str] = &["theta", "y", "omega"];
    const DEPENDENT: &'static [usize] = &[D];
    const CONSERVATIVE: bool = false;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 3],
        u: &[f64; 1],
        dx: &mut [f64; 3],
    ) -> Result<(), Singularity> {
        let inertia = positive(self.inertia, 0)?;
        let [theta, y, omega] = *x;
        let c = theta.cos();
        *dx = [
            omega,
            self.length * c * omega,
            (u[0] - self.stiffness * self.length * y * c) / inertia,
        ];
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 3]) -> Result<[f64; 2], Singularity> {
        Ok([x[2], self.length * x[0].cos() * x[2]])
    }

    fn energy(&self, _t: f64, x: &[f64; 3]) -> Result<f64, Singularity> {
        Ok(0.5 * self.inertia * x[2] * x[2] + 0.5 * self.stiffness * x[1] * x[1])
    }

    fn power(&self, _t: f64, x: &[f64; 3], u: &[f64; 1]) -> Result<f64, Singularity> {
        Ok(u[0] * x[2])
    }

    /// The massless end: 0 − ∂L/∂y = k y = λ, the spring's force carried by the constraint.
    fn multipliers(&self, _t: f64, x: &[f64; 3], _u: &[f64; 1]) -> Result<[f64; 1], Singularity> {
        Ok([self.stiffness * x[1]])
    }

    fn constraint_residual(&self, _t: f64, q: &[f64; 2], qd: &[f64; 2]) -> [f64; 1] {
        [qd[1] - self.length * q[0].cos() * qd[0]]
    }

    fn speeds(&self, _t: f64, _q: &[f64; 2], qd: &[f64; 2]) -> [f64; 1] {
        [qd[0]]
    }

    fn holonomic_residual(&self, _t: f64, q: &[f64; 2]) -> [f64; 1] {
        [q[1] - self.length * q[0].sin()]
    }

    fn holonomic_jacobian(&self, _t: f64, q: &[f64; 2]) -> [f64; 2] {
        [-self.length * q[0].cos(), 1.0]
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 3]) -> Result<[[f64; 1]; 1], Singularity> {
        Ok([[positive(self.inertia, 0)?]])
    }

    /// One free speed: the γ, antisymmetric in it, vanish.
    fn gamma(&self, _t: f64, _q: &[f64; 2]) -> Result<[[[f64; 1]; 1]; 2], Singularity> {
        Ok([[[0.0]]; 2])
    }

    /// A = [[−ℓ cos θ, 1], [1, 0]] (rows ḟ and ω) and B = A⁻¹ = [[0, 1], [1, ℓ cos θ]].
    fn inverse_defect(&self, _t: f64, q: &[f64; 2]) -> Result<f64, Singularity> {
        let lever = self.length * q[0].cos();
        let (a, b) = ([[-lever, 1.0], [1.0, 0.0]], [[0.0, 1.0], [1.0, lever]]);
        let entries = [
            a[0][0] * b[0][0] + a[0][1] * b[1][0] - 1.0,
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1] - 1.0,
        ];
        Ok(entries.iter().fold(0.0, |m, e| m.max(e.abs())))
    }

    fn jacobian(
        &self,
        _t: f64,
        x: &[f64; 3],
        _u: &[f64; 1],
    ) -> Result<([f64; 9], [f64; 3]), Singularity> {
        let inertia = positive(self.inertia, 0)?;
        let [theta, y, omega] = *x;
        let (s, c) = theta.sin_cos();
        let (k, l) = (self.stiffness, self.length);
        let a = [
            0.0,
            0.0,
            1.0,
            -l * s * omega,
            0.0,
            l * c,
            k * l * y * s / inertia,
            -k * l * c / inertia,
            0.0,
        ];
        Ok((a, [0.0, 0.0, 1.0 / inertia]))
    }
}

/// The crank in minimal coordinates (θ, ω).
struct MinimalCrank(SpringCrank<1>);

impl Parameters for MinimalCrank {
    const NAMES: &'static [&'static str] = SpringCrank::<1>::NAMES;
    const DOCS: &'static [&'static str] = SpringCrank::<1>::DOCS;

    fn get(&self, name: &str) -> Option<f64> {
        self.0.get(name)
    }

    fn set(&mut self, name: &str, value: f64) -> Result<(), Error> {
        self.0.set(name, value)
    }
}

impl HamelSystem for MinimalCrank {
    type Coordinates = [f64; 1];
    type Speeds = [f64; 1];
    type Constraints = [f64; 0];
    type State = [f64; 2];
    type Inputs = [f64; 1];
    type Holonomic = [f64; 0];
    type HolonomicJacobian = [f64; 0];
    type Extended = [f64; 3];
    type MassMatrix = [[f64; 1]; 1];
    type Gamma = [[[f64; 1]; 1]; 1];
    type StateJacobian = [f64; 4];
    type InputJacobian = [f64; 2];

    const N: usize = 1;
    const P: usize = 0;
    const M: usize = 1;
    const K: usize = 0;
    const COORDINATES: &'static [&'static str] = &["theta"];
    const SPEEDS: &'static [&'static str] = &["omega"];
    const CONSTRAINTS: &'static [&'static str] = &[];
    const INPUTS: &'static [&'static str] = &["torque"];
    const STATE: &'static [&'static str] = &["theta", "omega"];
    const DEPENDENT: &'static [usize] = &[];
    const CONSERVATIVE: bool = false;

    fn rhs(
        &self,
        _t: f64,
        x: &[f64; 2],
        u: &[f64; 1],
        dx: &mut [f64; 2],
    ) -> Result<(), Singularity> {
        let SpringCrank {
            inertia,
            stiffness: k,
            length: l,
        } = self.0;
        let (s, c) = x[0].sin_cos();
        *dx = [x[1], (u[0] - k * l * l * s * c) / positive(inertia, 0)?];
        Ok(())
    }

    fn generalized_velocities(&self, _t: f64, x: &[f64; 2]) -> Result<[f64; 1], Singularity> {
        Ok([x[1]])
    }

    fn energy(&self, _t: f64, x: &[f64; 2]) -> Result<f64, Singularity> {
        let SpringCrank {
            inertia,
            stiffness: k,
            length: l,
        } = self.0;
        let height = l * x[0].sin();
        Ok(0.5 * inertia * x[1] * x[1] + 0.5 * k * height * height)
    }

    fn power(&self, _t: f64, x: &[f64; 2], u: &[f64; 1]) -> Result<f64, Singularity> {
        Ok(u[0] * x[1])
    }

    fn multipliers(&self, _t: f64, _x: &[f64; 2], _u: &[f64; 1]) -> Result<[f64; 0], Singularity> {
        Ok([])
    }

    fn constraint_residual(&self, _t: f64, _q: &[f64; 1], _qd: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn speeds(&self, _t: f64, _q: &[f64; 1], qd: &[f64; 1]) -> [f64; 1] {
        *qd
    }

    fn holonomic_residual(&self, _t: f64, _q: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn holonomic_jacobian(&self, _t: f64, _q: &[f64; 1]) -> [f64; 0] {
        []
    }

    fn mass_matrix(&self, _t: f64, _x: &[f64; 2]) -> Result<[[f64; 1]; 1], Singularity> {
        Ok([[positive(self.0.inertia, 0)?]])
    }

    fn gamma(&self, _t: f64, _q: &[f64; 1]) -> Result<[[[f64; 1]; 1]; 1], Singularity> {
        Ok([[[0.0]]])
    }

    fn inverse_defect(&self, _t: f64, _q: &[f64; 1]) -> Result<f64, Singularity> {
        Ok(0.0)
    }

    /// d/dθ (−kℓ² sin θ cos θ) = −kℓ² cos 2θ.
    fn jacobian(
        &self,
        _t: f64,
        x: &[f64; 2],
        _u: &[f64; 1],
    ) -> Result<([f64; 4], [f64; 2]), Singularity> {
        let SpringCrank {
            inertia,
            stiffness: k,
            length: l,
        } = self.0;
        let inertia = positive(inertia, 0)?;
        Ok((
            [0.0, 1.0, -k * l * l * (2.0 * x[0]).cos() / inertia, 0.0],
            [0.0, 1.0 / inertia],
        ))
    }
}

/// Eliminating the crank end's height y through δy = ℓ cos θ δθ gives the linearization in
/// minimal coordinates, away from equilibrium too (where ω̇ depends on y and θ both).
#[test]
fn a_dependent_coordinate_is_eliminated_through_its_constraint() {
    let crank = spring_crank::<1>();
    let x = crank
        .state_builder()
        .set("theta", 0.3)
        .set("omega", 0.8)
        .build()
        .unwrap();
    let full = crank.linearize(0.0, &x, &[0.2]).unwrap();
    println!("{full}");
    assert_eq!(full.holonomic(), [("crank[0]", "y")]);
    // ω̇ depends on y: y is not cyclic, it is eliminated.
    assert!(full.a("omega", "y").unwrap().abs() > 1.0);
    let reduced = full.reduce(&["theta", "omega"]).unwrap();
    let minimal = MinimalCrank(spring_crank())
        .linearize(0.0, &[0.3, 0.8], &[0.2])
        .unwrap();
    println!("{reduced}{minimal}");
    let difference = (reduced.a_matrix() - minimal.a_matrix()).amax() / minimal.a_matrix().amax();
    println!("reduced vs minimal coordinates: A differs by {difference:.1e} relative");
    // Rounding: a few ε of the terms kℓ²cos²θ/I ≈ 1.7 and kℓ²sin²θ/I ≈ 0.16 that make up
    // the entry −kℓ²cos 2θ/I ≈ −1.5.
    assert!(difference <= 4e-15, "{difference:e}");
    assert_eq!(reduced.b_matrix(), minimal.b_matrix());
    assert_eq!(reduced.states(), minimal.states());
    assert!(reduced.holonomic().is_empty(), "the constraint is used up");
    // Reordered but complete, the linearization keeps its constraint, on the moved y.
    let reordered = full.reduce(&["omega", "y", "theta"]).unwrap();
    assert_eq!(reordered.holonomic(), [("crank[0]", "y")]);
    assert_eq!(
        reordered.a("omega", "y").unwrap(),
        full.a("omega", "y").unwrap()
    );
    assert_eq!(
        reordered.reduce(&["theta", "omega"]).unwrap().a_matrix(),
        reduced.a_matrix()
    );

    // At equilibrium the modes are ±iℓ√(k/I), the same in both.
    let rest = crank.state_builder().build().unwrap();
    let modes = crank
        .linearize(0.0, &rest, &[0.0])
        .unwrap()
        .reduce(&["theta", "omega"])
        .unwrap()
        .modes()
        .unwrap();
    let frequency = 0.5 * (3.0f64 / 0.4).sqrt();
    assert_eq!(modes.len(), 2);
    for (mode, sign) in modes.iter().zip([1.0, -1.0]) {
        println!("{mode}");
        assert!((mode.value - Complex::new(0.0, sign * frequency)).norm() <= 1e-15 * frequency);
        assert_eq!(mode.damping_ratio(), Some(0.0));
    }
}

/// With θ the dependent coordinate, it is eliminated through δθ = δy/(ℓ cos θ): the reduced
/// (y, ω) system is the crank in the minimal coordinate y, ẏ = √(ℓ² − y²) ω and
/// I ω̇ = τ − k y √(ℓ² − y²), whose A is [[−ω tan θ, ℓ cos θ], [(k y tan θ − kℓ cos θ)/I, 0]].
/// (Off equilibrium that is not similar to the A in θ: the change of coordinates moves with
/// the operating point.) At rest at θ = 0 the eigenvalues are those in θ.
#[test]
fn a_dependent_angle_is_eliminated_through_its_constraint() {
    let crank = spring_crank::<0>();
    let SpringCrank {
        inertia,
        stiffness: k,
        length: l,
    } = crank;
    let (theta, omega) = (0.3f64, 0.8);
    let y = l * theta.sin();
    let x = crank
        .state_builder()
        .set("theta", 0.1)
        .set("y", y)
        .set("omega", omega)
        .build()
        .unwrap();
    assert!((x[0] - theta).abs() <= 1e-15, "{x:?}");
    let reduced = crank
        .linearize(0.0, &x, &[0.0])
        .unwrap()
        .reduce(&["y", "omega"])
        .unwrap();
    println!("{reduced}");
    let exact = DMatrix::from_row_slice(
        2,
        2,
        &[
            -omega * theta.tan(),
            l * theta.cos(),
            (k * y * theta.tan() - k * l * theta.cos()) / inertia,
            0.0,
        ],
    );
    let difference = (reduced.a_matrix() - &exact).amax() / exact.amax();
    println!("reduced in y vs minimal coordinate y: A differs by {difference:.1e} relative");
    // Rounding: a few ε of the terms, none much larger than the entries.
    assert!(difference <= 4e-15, "{difference:e}");

    let rest = crank.state_builder().set("theta", 0.1).build().unwrap();
    let at_rest = crank.linearize(0.0, &rest, &[0.0]).unwrap();
    let in_y = at_rest
        .reduce(&["y", "omega"])
        .unwrap()
        .eigenvalues()
        .unwrap();
    let in_theta = MinimalCrank(spring_crank())
        .linearize(0.0, &[0.0, 0.0], &[0.0])
        .unwrap()
        .eigenvalues()
        .unwrap();
    let frequency = l * (k / inertia).sqrt();
    for (p, q) in in_y.iter().zip(&in_theta) {
        assert!((p - q).norm() <= 1e-15 * frequency, "{p} vs {q}");
    }

    // With θ the dependent coordinate, y is an ordinary state, which ω̇ depends on through
    // the lever ℓ cos θ: it cannot be dropped (but see the dead centre below).
    match crank
        .linearize(0.0, &x, &[0.0])
        .unwrap()
        .reduce(&["theta", "omega"])
    {
        Err(Error::NotCyclic { name, kept, .. }) => {
            assert_eq!((name.as_str(), kept.as_str()), ("y", "omega"))
        }
        other => panic!("{other:?}"),
    }
}

/// At the dead centre θ = π/2 the constraint does not determine θ (∂f/∂θ = 0): eliminating it
/// is an error, though the motion itself is regular there. The lever ℓ cos θ through which
/// ω̇ depends on y vanishes there too, so y is cyclic.
#[test]
fn at_the_dead_centre_the_angle_cannot_be_eliminated_but_the_height_drops_out() {
    let crank = spring_crank::<0>();
    let SpringCrank {
        inertia,
        stiffness: k,
        length: l,
    } = crank;
    let dead_centre = [PI / 2.0, l, 0.8];
    let full = crank.linearize(0.0, &dead_centre, &[0.0]).unwrap();
    match full.reduce(&["y", "omega"]) {
        Err(e @ Error::SingularElimination { .. }) => {
            let message = e.to_string();
            println!("{message}");
            assert!(
                message.contains("keep `theta`") && !message.contains("  "),
                "{message}"
            );
            let Error::SingularElimination {
                coordinate,
                constraint,
                pivot,
            } = e
            else {
                unreachable!()
            };
            assert_eq!(
                (coordinate.as_str(), constraint.as_str()),
                ("theta", "crank[0]")
            );
            assert!(pivot.abs() <= 1e-16, "{pivot:e}");
        }
        other => panic!("{other:?}"),
    }
    // y is cyclic here, and the constraint, which involves the dropped y, says nothing about
    // θ alone any more.
    let kept = full.reduce(&["theta", "omega"]).unwrap();
    assert!(kept.holonomic().is_empty());
    // ω̇ = (τ − kℓ y cos θ)/I still depends on θ there: ∂/∂θ = kℓ y sin θ/I with y = ℓ.
    let expected = k * l * l / inertia;
    assert!((kept.a("omega", "theta").unwrap() - expected).abs() <= 1e-15 * expected);
}

// ---------------------------------------------------------------------------------------
// Linearizations from given matrices: repeated eigenvalues, errors, and the printed forms.
// ---------------------------------------------------------------------------------------

/// Two identical oscillators, seen in coordinates that mix them (A = Q·diag(O, O)·Qᵀ for an
/// orthogonal Q): every eigenvalue is double, computed as two values that differ by rounding,
/// and each of a pair gets its own eigenvector from the two-dimensional eigenspace.
#[test]
fn repeated_eigenvalues_get_independent_vectors() {
    let oscillator = [[0.0, 1.0], [-4.0, -0.4]];
    let blocks = DMatrix::from_fn(4, 4, |i, j| {
        if i / 2 == j / 2 {
            oscillator[i % 2][j % 2]
        } else {
            0.0
        }
    });
    let q = DMatrix::from_fn(4, 4, |i, j| ((4 * i + j) as f64 * 0.7 + 0.3).sin())
        .qr()
        .q();
    let a = &q * blocks * q.transpose();
    let linearization =
        Linearization::new(&["a", "b", "c", "d"], &[], a, DMatrix::zeros(4, 0)).unwrap();
    let modes = linearization.modes().unwrap();
    check_modes(&linearization, &modes);
    let value = Complex::new(-0.2, (4.0f64 - 0.04).sqrt());
    let upper: Vec<&Mode> = modes.iter().filter(|m| m.value.im > 0.0).collect();
    assert_eq!(upper.len(), 2);
    for mode in &upper {
        println!("{mode}");
        assert!((mode.value - value).norm() <= 1e-14);
    }
    println!(
        "the pair differs by {:.1e}",
        (upper[0].value - upper[1].value).norm()
    );
    // Independent: the cosine of the angle between the two vectors is well below 1.
    let vector = |m: &Mode| -> Vec<Complex<f64>> { m.vector.iter().map(|(_, c)| *c).collect() };
    let (v, w) = (vector(upper[0]), vector(upper[1]));
    let norm = |v: &[Complex<f64>]| v.iter().map(|c| c.norm_sqr()).sum::<f64>().sqrt();
    let dot: Complex<f64> = v.iter().zip(&w).map(|(v, w)| v.conj() * w).sum();
    let cosine = dot.norm() / (norm(&v) * norm(&w));
    println!("cosine between the pair's vectors: {cosine:.1e}");
    assert!(cosine <= 1e-12, "{cosine}");

    // A triple eigenvalue 2 of a symmetric matrix, computed as three values that differ by
    // rounding: three orthogonal eigenvectors.
    let a = &q
        * DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![2.0, 2.0, -1.0, 2.0]))
        * q.transpose();
    let linearization =
        Linearization::new(&["a", "b", "c", "d"], &[], a, DMatrix::zeros(4, 0)).unwrap();
    let modes = linearization.modes().unwrap();
    check_modes(&linearization, &modes);
    let values: Vec<Complex<f64>> = modes.iter().map(|m| m.value).collect();
    println!("{values:?}");
    let worst = (0..3)
        .flat_map(|i| (0..i).map(move |j| (i, j)))
        .map(|(i, j)| {
            let (v, w) = (vector(&modes[i]), vector(&modes[j]));
            let dot: Complex<f64> = v.iter().zip(&w).map(|(v, w)| v.conj() * w).sum();
            dot.norm() / (norm(&v) * norm(&w))
        })
        .fold(0.0, f64::max);
    println!("largest cosine between the triple's vectors: {worst:.1e}");
    assert!(worst <= 1e-12, "{worst}");
}

#[test]
fn given_matrices_are_checked() {
    let names = ["a", "b"];
    let good = || DMatrix::from_row_slice(2, 2, &[0.0, 1.0, -1.0, 0.0]);
    match Linearization::new(&names, &["u"], good(), DMatrix::zeros(3, 1)) {
        Err(Error::DimensionMismatch { what }) => assert!(what.contains("B of 2 × 1"), "{what}"),
        other => panic!("{other:?}"),
    }
    match Linearization::new(&["a", "a"], &[], good(), DMatrix::zeros(2, 0)) {
        Err(Error::DuplicateName { name, .. }) => assert_eq!(name, "a"),
        other => panic!("{other:?}"),
    }
    let mut nan = good();
    nan[(1, 0)] = f64::NAN;
    match Linearization::new(&names, &[], nan, DMatrix::zeros(2, 0)) {
        Err(e @ Error::NonFiniteDerivative { .. }) => {
            let message = e.to_string();
            assert!(
                message.starts_with("the rate of `b` has the derivative NaN with respect to `a`"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    // Finite entries whose eigenvalue overflows: 2·10³⁰⁸.
    let huge = DMatrix::from_element(2, 2, 1e308);
    let linearization = Linearization::new(&names, &[], huge, DMatrix::zeros(2, 0)).unwrap();
    match linearization.modes() {
        Err(e @ Error::EigenAnalysis { .. }) => {
            let message = e.to_string();
            println!("{message}");
            // 2·10³⁰⁸ = (2.225…)·2¹⁰²³.
            assert!(
                message.contains("an eigenvalue, (2.225)·2^1023, is too large"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    // No states at all: no modes, and nothing to fail.
    let empty = Linearization::new(&[], &[], DMatrix::zeros(0, 0), DMatrix::zeros(0, 0)).unwrap();
    assert!(empty.modes().unwrap().is_empty());
}

#[test]
fn display_prints_named_aligned_tables_and_debug_a_summary() {
    let linearization = CART
        .linearize(0.5, &[0.4, 0.3, 0.2, -0.1], &[0.25])
        .unwrap();
    let text = linearization.to_string();
    println!("{text}");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "linearized at t = 0.5; state: s = 0.4, theta = 0.3, v = 0.2, omega = -0.1; inputs: force = 0.25"
    );
    assert_eq!(lines[1], "A = ∂F/∂x (rows: the rates of the states)");
    let header: Vec<&str> = lines[2].split_whitespace().collect();
    assert_eq!(header, ["s", "theta", "v", "omega"]);
    let width = lines[2].chars().count();
    for (line, name) in lines[3..7].iter().zip(["s", "theta", "v", "omega"]) {
        assert!(line.starts_with(name), "{line}");
        assert_eq!(line.chars().count(), width, "aligned: {line}");
        // Four significant digits at most: the mantissa's digits after leading zeros.
        for cell in line.split_whitespace().skip(1) {
            let mantissa = cell.split('e').next().unwrap();
            let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
            assert!(digits.trim_start_matches('0').len() <= 4, "{cell}");
        }
    }
    assert_eq!(lines[7], "B = ∂F/∂u");
    assert_eq!(lines[8].split_whitespace().collect::<Vec<_>>(), ["force"]);
    assert_eq!(lines.len(), 13);
    let omega_row: Vec<&str> = lines[6].split_whitespace().collect();
    let value: f64 = omega_row[1].parse().unwrap();
    let exact = linearization.a("omega", "s").unwrap();
    assert_eq!(value, exact, "ω̇ does not depend on s: {exact}");

    let debug = format!("{linearization:?}");
    println!("{debug}");
    assert!(debug.starts_with("Linearization { states: [\"s\", \"theta\", \"v\", \"omega\"], inputs: [\"force\"], t: Some(0.5)"), "{debug}");
    assert!(debug.len() < 250, "a summary, not the matrices: {debug}");

    // The crank's constraint is printed with the state it determines.
    let crank = spring_crank::<1>();
    let x = crank.state_builder().set("theta", 0.3).build().unwrap();
    let text = crank.linearize(0.0, &x, &[0.0]).unwrap().to_string();
    assert!(
        text.contains("holonomic constraints ∂f/∂x (each determines a state)\n"),
        "{text}"
    );
    assert!(text.contains("\ncrank[0] → y  "), "{text}");

    // The least damped mode of the chain, printed with the closed-form figures.
    let mode = &CHAIN
        .linearize(0.0, &[0.0; 6], &[0.0])
        .unwrap()
        .modes()
        .unwrap()[0];
    let shown = mode.to_string();
    println!("{shown}");
    let (value, _) = chain_modes()[0];
    let expected = format!(
        "λ = {} + {}i (ωn = {}, ζ = {}): q1 = ",
        Num(value.re),
        Num(value.im),
        Num(value.norm()),
        Num(-value.re / value.norm())
    );
    assert!(shown.starts_with(&expected), "{shown}\n{expected}");
    for name in Chain::STATE {
        assert!(shown.contains(&format!(" {name} = ")), "{shown}");
    }
}
