//! The mobile robot's equations of motion by a second, independent route: Lagrange's
//! equations in q, projected on the admissible directions B_k (`hamel::docs::design`,
//! "B from a numeric LU: the projected-Lagrange form"):
//!
//!   Bᵣᵀ (M_full q̈ + (∂²L/∂q̇∂q) q̇ − ∂L/∂q − f) = 0,   q̈ = Bᵣ ω̇ + Ḃω,   Ḃω = −B (D_q̇A) q̇.
//!
//! Nothing here comes from the crate except the parameter struct: the Lagrangian is built
//! from the bodies' 3D motion with vectors (not the model's hand-simplified formulas), the
//! transformation A(q) from its rows, every derivative by num-dual's dual and hyper-dual
//! numbers, and B = A⁻¹ and the reduced solve by nalgebra.

use hamel::models::MobileRobot;
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual64, DualNum, HyperDual64};

type Vec3 = SVector<f64, 3>;
type Vec5 = SVector<f64, 5>;
type Mat5 = SMatrix<f64, 5, 5>;

/// The number types the Lagrangian and the transformation rows are evaluated on: f64 and
/// num-dual's duals.
pub trait Real: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Real for T {}

/// A 3-vector of any `Real`, with just the operations the kinematics needs.
#[derive(Clone, Copy)]
struct V<T>([T; 3]);

impl<T: Real> V<T> {
    fn dot(self, o: V<T>) -> T {
        self.0[0] * o.0[0] + self.0[1] * o.0[1] + self.0[2] * o.0[2]
    }

    fn norm2(self) -> T {
        self.dot(self)
    }

    fn scale(self, k: T) -> V<T> {
        V(self.0.map(|c| c * k))
    }

    fn add(self, o: V<T>) -> V<T> {
        V([self.0[0] + o.0[0], self.0[1] + o.0[1], self.0[2] + o.0[2]])
    }
}

/// L = T − V of the robot from its bodies' motion (see the doc comments of
/// `hamel-models/src/mobile_robot.rs` for the geometry).
pub fn lagrangian<T: Real>(p: &MobileRobot, q: &[T; 5], qd: &[T; 5]) -> T {
    let [_, _, alpha, phi1, phi2] = *q;
    let [xd, yd, alphad, phi1d, phi2d] = *qd;
    let (zero, one) = (T::zero(), T::one());

    // The axle's heading ϑ follows from how far the wheels have rolled relative to each
    // other; its frame: e_f forward, e_a along the axle to the left, e_z up, with
    // d/dt e_f = ϑ̇ e_a and d/dt e_a = −ϑ̇ e_f.
    let theta = (phi1 - phi2) * p.r / p.b;
    let thetad = (phi1d - phi2d) * p.r / p.b;
    let (s, c) = theta.sin_cos();
    let e_f = V([c, s, zero]);
    let e_a = V([-s, c, zero]);
    let e_z = V([zero, zero, one]);
    let v_axle = V([xd, yd, zero]);

    // Body: pitched by α about e_a, so its principal axes are b_x = cos α e_f − sin α e_z,
    // b_y = e_a, b_z = sin α e_f + cos α e_z; its centre of gravity is l b_z from the axle
    // centre; its angular velocity is ϑ̇ e_z + α̇ e_a.
    let (sa, ca) = alpha.sin_cos();
    let b_x = e_f.scale(ca).add(e_z.scale(-sa));
    let b_y = e_a;
    let b_z = e_f.scale(sa).add(e_z.scale(ca));
    // d/dt (l b_z) = l (α̇ b_x + sin α ϑ̇ e_a).
    let v_cg = v_axle.add(b_x.scale(alphad * p.l).add(e_a.scale(sa * thetad * p.l)));
    let spin_body = e_z.scale(thetad).add(e_a.scale(alphad));
    let body = v_cg.norm2() * (0.5 * p.m0)
        + spin_body.dot(b_x).powi(2) * (0.5 * p.jx)
        + spin_body.dot(b_y).powi(2) * (0.5 * p.jy)
        + spin_body.dot(b_z).powi(2) * (0.5 * p.jz);

    // Wheels: ideal disks (½ m_w r² about the axle, ¼ m_w r² about a diameter) centred at
    // ∓(b/2) e_a (wheel 1 on the right), spinning at α̇ + φ̇ᵢ about e_a on top of the yaw:
    // φᵢ is measured from the body, which itself turns at α̇ about the axle.
    let mut wheels = zero;
    for (side, phid) in [(-1.0, phi1d), (1.0, phi2d)] {
        let v_centre = v_axle.add(e_f.scale(thetad * (-side * 0.5 * p.b)));
        let spin = e_z.scale(thetad).add(e_a.scale(alphad + phid));
        let axial = spin.dot(e_a);
        let diametral2 = spin.norm2() - axial * axial;
        let rr = p.mw * p.r * p.r;
        wheels += v_centre.norm2() * (0.5 * p.mw)
            + axial * axial * (0.25 * rr)
            + diametral2 * (0.125 * rr);
    }

    // Only the body's centre of gravity changes height: l cos α above the axle.
    let potential = b_z.dot(e_z) * (p.m0 * p.g * p.l);
    body + wheels - potential
}

/// ω = A(q) q̇, all five rows: the two no-slip constraints, then the three quasi-velocities.
pub fn transformation_rows<T: Real>(p: &MobileRobot, q: &[T; 5], qd: &[T; 5]) -> [T; 5] {
    let theta = (q[3] - q[4]) * p.r / p.b;
    let (s, c) = theta.sin_cos();
    let forward = qd[0] * c + qd[1] * s;
    [
        // ω¹: the axle centre does not slide sideways (its velocity along e_a is −ω¹).
        qd[0] * s - qd[1] * c,
        // ω²: it moves forward at r times the wheels' mean absolute spin α̇ + φ̇ᵢ.
        (qd[2] + (qd[3] + qd[4]) * 0.5) * p.r - forward,
        // ω³ = α̇, ω⁴ = forward speed, ω⁵ = ϑ̇.
        qd[2],
        forward,
        (qd[3] - qd[4]) * p.r / p.b,
    ]
}

/// The generalized forces: each motor's torque acts on its wheel and, reversed, on the body,
/// so its virtual work τᵢ (δα + δφᵢ) − τᵢ δα = τᵢ δφᵢ lands on φᵢ alone.
pub fn generalized_forces(u: &[f64; 2]) -> Vec5 {
    Vec5::from([0.0, 0.0, 0.0, u[0], u[1]])
}

/// A(q), column by column: A e_σ.
pub fn transformation_matrix(p: &MobileRobot, q: &[f64; 5]) -> Mat5 {
    let mut a = Mat5::zeros();
    for sigma in 0..5 {
        let mut unit = [0.0; 5];
        unit[sigma] = 1.0;
        a.set_column(sigma, &Vec5::from(transformation_rows(p, q, &unit)));
    }
    a
}

/// (D_q̇A) q̇ = Σ_σ ∂(A q̇)/∂q^σ q̇^σ: one forward-mode sweep with q seeded along q̇ and q̇
/// held constant.
fn transformation_rate_times(p: &MobileRobot, q: &[f64; 5], qd: &[f64; 5]) -> Vec5 {
    let q_dual: [Dual64; 5] = std::array::from_fn(|i| Dual64::new(q[i], qd[i]));
    let qd_const: [Dual64; 5] = qd.map(Dual64::from);
    Vec5::from(transformation_rows(p, &q_dual, &qd_const).map(|r| r.eps))
}

/// Hyper-dual numbers with value `re` and first-order parts `d1`, `d2`.
fn seeded(re: &[f64; 5], d1: &[f64; 5], d2: &[f64; 5]) -> [HyperDual64; 5] {
    std::array::from_fn(|i| HyperDual64::new(re[i], d1[i], d2[i], 0.0))
}

fn unit(i: usize) -> [f64; 5] {
    let mut e = [0.0; 5];
    e[i] = 1.0;
    e
}

/// ∂L/∂q, the Hessian ∂²L/∂q̇² and the mixed term (∂²L/∂q̇∂q) q̇, by hyper-dual numbers:
/// seeding direction 1 with a and direction 2 with b, the ε₁ε₂ part is L''[a, b].
fn lagrangian_derivatives(p: &MobileRobot, q: &[f64; 5], qd: &[f64; 5]) -> (Vec5, Mat5, Vec5) {
    const NONE: [f64; 5] = [0.0; 5];
    let mut grad_q = Vec5::zeros();
    let mut hessian = Mat5::zeros();
    let mut mixed = Vec5::zeros();
    for i in 0..5 {
        grad_q[i] = lagrangian(p, &seeded(q, &unit(i), &NONE), &seeded(qd, &NONE, &NONE)).eps1;
        mixed[i] = lagrangian(p, &seeded(q, &NONE, qd), &seeded(qd, &unit(i), &NONE)).eps1eps2;
        for j in 0..5 {
            hessian[(i, j)] =
                lagrangian(p, &seeded(q, &NONE, &NONE), &seeded(qd, &unit(i), &unit(j))).eps1eps2;
        }
    }
    (grad_q, hessian, mixed)
}

/// ẋ for the state x = (q, ω³, ω⁴, ω⁵) and torques u, from the projected Lagrange equations.
pub fn projected_lagrange_rhs(p: &MobileRobot, x: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
    let q: [f64; 5] = std::array::from_fn(|i| x[i]);
    let a = transformation_matrix(p, &q);
    let b = a
        .try_inverse()
        .expect("A(q) is invertible away from r = 0 or b = 0");
    // The admissible directions: the columns of B belonging to the free quasi-velocities.
    let b_r = b.fixed_columns::<3>(2).into_owned();
    let speeds = Vec3::new(x[5], x[6], x[7]);
    let qd_vec = b_r * speeds;
    let qd: [f64; 5] = std::array::from_fn(|i| qd_vec[i]);
    // d/dt (B ω) = B ω̇ + Ḃ ω, and Ḃ = −B Ȧ B gives Ḃ ω = −B Ȧ q̇.
    let b_dot_omega = -(b * transformation_rate_times(p, &q, &qd));

    let (grad_q, hessian, mixed) = lagrangian_derivatives(p, &q, &qd);
    let f = generalized_forces(u);
    let reduced_mass = b_r.transpose() * hessian * b_r;
    let reduced_force = b_r.transpose() * (f + grad_q - mixed - hessian * b_dot_omega);
    let speeds_dot = reduced_mass
        .cholesky()
        .expect("the reduced mass matrix is positive definite")
        .solve(&reduced_force);

    let mut dx = [0.0; 8];
    dx[..5].copy_from_slice(qd_vec.as_slice());
    dx[5..].copy_from_slice(speeds_dot.as_slice());
    dx
}
