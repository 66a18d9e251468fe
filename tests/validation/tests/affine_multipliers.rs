//! Affine, time-dependent constraint rows against an independent formulation: Lagrange's
//! equations with multipliers, reduced to their index-1 linear system
//! (`common/affine_multipliers.rs`), at seeded random states and times.
//!
//! Four mechanisms, each re-derived here for the reference (nothing of the models' role
//! functions is called):
//!
//! * `hamel::models::BallOnTurntable`: the rows A(q, t) q̇ + a(q, t) carry the table's rate
//!   Ω(t) = Ω₀ + εt; B by LU (the projected route). Also `BallWithInverse`, the same roles
//!   with a closed-form `#[velocities]` (Hamel's route). The reference takes the ball's
//!   angular velocity from its rotation matrix (the axial vector of Ṙ Rᵀ), not from the
//!   model's component formulas.
//! * A steered sleigh on a turntable on a moving platform, written below with
//!   `#[hamel_system]` twice: with a closed-form `#[velocities]` (Hamel's route, L̃ composed at
//!   compile time) and without (B by LU, the projected route). Its blade is steered by a
//!   prescribed δ(t), so A itself depends on t; the table turns at Ω(t), so the constraint
//!   and a quasi-velocity carry parts a(q, t) without velocities; the platform moves, so the
//!   kinetic and potential energies depend on t (and T is not a quadratic form in q̇); a
//!   torque input and drags give forces that depend on t.
//! * Two models whose λ comes from one solve with Aᵀ (B derived from A): the catalogue's
//!   `NTrailer2` (a closed-form 2 × 2 block for the tractor, then one row per trailer, B
//!   filling in along the train), and Bloch's nonholonomic particle with a second coordinate
//!   chained to it (A triangular up to permutation, B by the run-time LU).
//!
//! Compared, norm-wise relative (max|a − b| over the vector's own max|b|): q̇ and ẇ of `rhs`;
//! the multipliers λ of `constraint_forces` (same sign convention, d/dt ∂L/∂q̇ − ∂L/∂q =
//! f + A_cᵀλ, and the same rows, so the same scaling) against the larger of their own size
//! and that of the forces they balance — λ can be nearly zero while those are not, and then
//! its rounding is relative to them; the power and the energy against the size of their
//! terms (both are sums that may cancel). A last test freezes one prescribed motion at a
//! time in the reference, to show that every explicit time derivative changes the result
//! by far more than the tolerance. Run with `--nocapture` for the figures.

use crate::common::affine_multipliers::{Mechanism, Real, Reference, reference};
use crate::common::xorshift::XorShift;
use hamel::models::{BallOnTurntable, NTrailer2};
use hamel::{HamelSystem, Vector, hamel_system};
use std::f64::consts::PI;

/// Two formulations of the same equations differ by rounding: a few hundred ulps of each
/// quantity's scale, amplified by the conditioning of the solves.
const TOLERANCE: f64 = 1e-12;
/// Random states and times per parameter set.
const RANDOM_POINTS: usize = 200;

// ---------------------------------------------------------------------------------------
// The ball on the turntable, re-derived
// ---------------------------------------------------------------------------------------

type Matrix3<T> = [[T; 3]; 3];

fn product<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> Matrix3<T> {
    std::array::from_fn(|i| {
        std::array::from_fn(|j| a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j])
    })
}

fn sum<T: Real>(a: &Matrix3<T>, b: &Matrix3<T>) -> Matrix3<T> {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] + b[i][j]))
}

fn scaled<T: Real>(a: &Matrix3<T>, k: T) -> Matrix3<T> {
    a.map(|row| row.map(|x| x * k))
}

fn transposed<T: Real>(a: &Matrix3<T>) -> Matrix3<T> {
    std::array::from_fn(|i| std::array::from_fn(|j| a[j][i]))
}

/// The rotation by `angle` about z, and its derivative with respect to the angle.
fn about_z<T: Real>(angle: T) -> (Matrix3<T>, Matrix3<T>) {
    let (s, c) = angle.sin_cos();
    let (o, l) = (T::zero(), T::one());
    (
        [[c, -s, o], [s, c, o], [o, o, l]],
        [[-s, -c, o], [c, -s, o], [o, o, o]],
    )
}

/// The rotation by `angle` about x, and its derivative with respect to the angle.
fn about_x<T: Real>(angle: T) -> (Matrix3<T>, Matrix3<T>) {
    let (s, c) = angle.sin_cos();
    let (o, l) = (T::zero(), T::one());
    (
        [[l, o, o], [o, c, -s], [o, s, c]],
        [[o, o, o], [o, -s, -c], [o, c, -s]],
    )
}

fn cross<T: Real>(a: [T; 3], b: [T; 3]) -> [T; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The ball's angular velocity in the inertial frame for ZXZ Euler angles (φ, θ, ψ):
/// R = R_z(φ) R_x(θ) R_z(ψ), Ṙ by the product rule, and ω the axial vector of the
/// skew-symmetric Ṙ Rᵀ (its antisymmetric part, so that rounding off the skew form averages).
fn angular_velocity<T: Real>(angles: [T; 3], rates: [T; 3]) -> [T; 3] {
    let (z1, z1d) = about_z(angles[0]);
    let (x2, x2d) = about_x(angles[1]);
    let (z3, z3d) = about_z(angles[2]);
    let rotation = product(&product(&z1, &x2), &z3);
    let terms = [
        scaled(&product(&product(&z1d, &x2), &z3), rates[0]),
        scaled(&product(&product(&z1, &x2d), &z3), rates[1]),
        scaled(&product(&product(&z1, &x2), &z3d), rates[2]),
    ];
    let rate = sum(&sum(&terms[0], &terms[1]), &terms[2]);
    let s = product(&rate, &transposed(&rotation));
    let half = T::from(0.5);
    [
        (s[2][1] - s[1][2]) * half,
        (s[0][2] - s[2][0]) * half,
        (s[1][0] - s[0][1]) * half,
    ]
}

/// The prescribed motions that make the mechanisms depend on the time.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drive {
    /// The turntable's rate Ω(t): the part a(q, t) of the rows.
    Table,
    /// The blade's steering δ(t): A(q, t) itself.
    Steering,
    /// The platform's motion U(t), X(t): the kinetic and potential energies.
    Platform,
}

/// The time each prescribed motion of a reference mechanism sees: `t`, or for the one that
/// is frozen at `at`, the constant `at` — the same values at t = `at` without that motion's
/// explicit time derivatives. The sensitivity check compares the models against partly
/// frozen references to show that each of those terms matters.
#[derive(Clone, Copy, Debug, Default)]
struct Clock {
    frozen: Option<(Drive, f64)>,
}

impl Clock {
    fn time<T: Real>(self, drive: Drive, t: T) -> T {
        match self.frozen {
            Some((frozen, at)) if frozen == drive => T::from(at),
            _ => t,
        }
    }
}

/// The ball as the reference sees it: q = (x, y, φ, θ, ψ).
struct Ball<'p> {
    p: &'p BallOnTurntable,
    clock: Clock,
}

impl Mechanism<5> for Ball<'_> {
    const P: usize = 2;

    fn lagrangian<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> T {
        let omega = angular_velocity([q[2], q[3], q[4]], [qd[2], qd[3], qd[4]]);
        let spin = omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2];
        (qd[0] * qd[0] + qd[1] * qd[1]) * (0.5 * self.p.m) + spin * (0.5 * self.p.inertia)
    }

    /// The contact point's velocity ṙ + ω × (−ρ e_z) minus the table's there, Ω e_z × r
    /// (horizontal components), then ω.
    fn rows<T: Real>(&self, t: T, q: &[T; 5], qd: &[T; 5]) -> [T; 5] {
        let (p, t) = (self.p, self.clock.time(Drive::Table, t));
        let omega = angular_velocity([q[2], q[3], q[4]], [qd[2], qd[3], qd[4]]);
        let o = T::zero();
        let down = [o, o, T::from(-p.radius)];
        let rolling = cross(omega, down);
        let table = cross([o, o, t * p.epsilon + p.omega0], [q[0], q[1], o]);
        [
            qd[0] + rolling[0] - table[0],
            qd[1] + rolling[1] - table[1],
            omega[0],
            omega[1],
            omega[2],
        ]
    }

    fn forces(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], _u: &[f64]) -> [f64; 5] {
        [0.0; 5]
    }
}

/// The catalogue's ball with the inverse in closed form (Hamel's route, where the catalogue
/// takes B by LU): the same roles, copied, and `#[velocities]`.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct BallWithInverse {
    /// mass of the ball (kg)
    pub m: f64,
    /// radius of the ball (m)
    pub radius: f64,
    /// moment of inertia of the ball about any axis through its centre (kg m²)
    pub inertia: f64,
    /// rate of the table at t = 0 (rad/s)
    pub omega0: f64,
    /// angular acceleration of the table (rad/s²)
    pub epsilon: f64,
}

impl From<&BallOnTurntable> for BallWithInverse {
    fn from(b: &BallOnTurntable) -> Self {
        let BallOnTurntable {
            m,
            radius,
            inertia,
            omega0,
            epsilon,
        } = *b;
        BallWithInverse {
            m,
            radius,
            inertia,
            omega0,
            epsilon,
        }
    }
}

#[hamel_system(coordinates(x, y, phi, theta, psi), speeds(omega_x, omega_y, omega_z))]
impl BallWithInverse {
    fn angular_velocity(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let [_, _, phi, theta, _] = *q;
        let [_, _, phid, thetad, psid] = *qd;
        let (sp, cp) = phi.sin_cos();
        let (st, ct) = theta.sin_cos();
        [
            thetad * cp + psid * st * sp,
            thetad * sp - psid * st * cp,
            phid + psid * ct,
        ]
    }

    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let w = self.angular_velocity(q, qd);
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.inertia * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    }

    #[constraints]
    fn rolling(&self, t: f64, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let w = self.angular_velocity(q, qd);
        let table = self.omega0 + self.epsilon * t;
        [
            qd[0] - self.radius * w[1] + table * q[1],
            qd[1] + self.radius * w[0] - table * q[0],
        ]
    }

    #[quasi_velocities]
    fn spin(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        self.angular_velocity(q, qd)
    }

    /// The Euler angles' rates from ω (θ̇ = ω_x cos φ + ω_y sin φ, ψ̇ sin θ = ω_x sin φ −
    /// ω_y cos φ, φ̇ = ω_z − ψ̇ cos θ), the centre's velocity from the rolling rows.
    #[velocities]
    fn inverse(&self, t: f64, q: &[f64; 5], w: &[f64; 5]) -> [f64; 5] {
        let (sp, cp) = q[2].sin_cos();
        let (st, ct) = q[3].sin_cos();
        let table = self.omega0 + self.epsilon * t;
        let psid = (w[2] * sp - w[3] * cp) / st;
        [
            w[0] + self.radius * w[3] - table * q[1],
            w[1] - self.radius * w[2] + table * q[0],
            w[4] - psid * ct,
            w[2] * cp + w[3] * sp,
            psid,
        ]
    }
}

// ---------------------------------------------------------------------------------------
// A steered sleigh on a turntable on a moving platform
// ---------------------------------------------------------------------------------------

/// Writes the sleigh model twice, with and without a closed-form inverse: the same parameter
/// struct and role functions, so that the two routes of the macro see the same mechanism.
///
/// A body of mass m and inertia I about its centre of mass (x, y) at heading θ, its only
/// skate a distance `a` behind the centre, steered to δ(t) = δ₀ + δ₁ sin νt from the body's
/// axis. The skate rests on a table that turns at Ω(t) = Ω₀ + εt about the origin of a
/// platform; the platform translates (without turning) with velocity U(t) =
/// (drive·t, sway·sin(ν_s t)), displacement X(t) = (drive·t²/2, sway(1 − cos ν_s t)/ν_s).
/// Coordinates are the platform's, so T = ½ m |ṙ + U|² + ½ I θ̇²; a spring k ties the centre
/// to an anchor fixed in the inertial frame at the platform's initial origin,
/// V = ½ k |r + X|². Forces: a torque u on θ, a turning drag −d θ̇ and a drag −c (ṙ + U).
///
/// The skate's point P = r − a e_θ does not slide across the blade relative to the table
/// (the blade's direction e_β, β = θ + δ(t), normal n_β):
/// (Ṗ − Ω e_z × P)·n_β = 0. The speeds: the centre's velocity along the blade relative to
/// the table, (ṙ − Ω e_z × r)·e_β, and θ̇.
macro_rules! steered_sleigh {
    ($(#[$doc:meta])* $name:ident { $($inverse:tt)* }) => {
        $(#[$doc])*
        #[hamel_system]
        #[derive(Clone, Debug)]
        pub struct $name {
            /// mass (kg)
            pub m: f64,
            /// moment of inertia about the centre of mass (kg m²)
            pub inertia: f64,
            /// distance of the skate behind the centre of mass (m)
            pub a: f64,
            /// table rate at t = 0 (rad/s)
            pub omega0: f64,
            /// table angular acceleration (rad/s²)
            pub epsilon: f64,
            /// mean steering angle (rad)
            pub delta0: f64,
            /// steering amplitude (rad)
            pub delta1: f64,
            /// steering frequency (rad/s)
            pub nu: f64,
            /// platform acceleration along x (m/s²)
            pub drive: f64,
            /// amplitude of the platform's sideways velocity (m/s)
            pub sway: f64,
            /// frequency of the platform's sway (rad/s)
            pub sway_rate: f64,
            /// stiffness of the spring to the fixed anchor (N/m)
            pub k: f64,
            /// translational drag (N s/m)
            pub c: f64,
            /// turning drag (N m s)
            pub d: f64,
        }

        #[hamel_system(coordinates(x, y, theta), speeds(along, turn), inputs(torque))]
        impl $name {
            fn steering(&self, t: f64) -> f64 {
                self.delta0 + self.delta1 * (self.nu * t).sin()
            }

            fn table_rate(&self, t: f64) -> f64 {
                self.omega0 + self.epsilon * t
            }

            fn platform_velocity(&self, t: f64) -> [f64; 2] {
                [self.drive * t, self.sway * (self.sway_rate * t).sin()]
            }

            #[kinetic_energy]
            fn kinetic_energy(&self, t: f64, _q: &[f64; 3], qd: &[f64; 3]) -> f64 {
                let [ux, uy] = self.platform_velocity(t);
                let (vx, vy) = (qd[0] + ux, qd[1] + uy);
                0.5 * self.m * (vx * vx + vy * vy) + 0.5 * self.inertia * qd[2] * qd[2]
            }

            #[potential_energy]
            fn potential_energy(&self, t: f64, q: &[f64; 3]) -> f64 {
                let dx = q[0] + 0.5 * self.drive * t * t;
                let dy = q[1] + self.sway * (1.0 - (self.sway_rate * t).cos()) / self.sway_rate;
                0.5 * self.k * (dx * dx + dy * dy)
            }

            /// (Ṗ − Ω e_z × P)·n_β, expanded: Ṗ·n_β = ṙ·n_β − a cos δ θ̇, (e_z × P)·n_β = P·e_β.
            #[constraints]
            fn skate(&self, t: f64, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 1] {
                let delta = self.steering(t);
                let (sb, cb) = (q[2] + delta).sin_cos();
                let (st, ct) = q[2].sin_cos();
                let (px, py) = (q[0] - self.a * ct, q[1] - self.a * st);
                [-qd[0] * sb + qd[1] * cb
                    - self.a * delta.cos() * qd[2]
                    - self.table_rate(t) * (px * cb + py * sb)]
            }

            /// (ṙ − Ω e_z × r)·e_β with (e_z × r)·e_β = x sin β − y cos β; θ̇.
            #[quasi_velocities]
            fn speeds(&self, t: f64, q: &[f64; 3], qd: &[f64; 3]) -> [f64; 2] {
                let (sb, cb) = (q[2] + self.steering(t)).sin_cos();
                [
                    qd[0] * cb + qd[1] * sb - self.table_rate(t) * (q[0] * sb - q[1] * cb),
                    qd[2],
                ]
            }

            #[forces]
            fn forces(&self, t: f64, _q: &[f64; 3], qd: &[f64; 3], u: &[f64; 1]) -> [f64; 3] {
                let [ux, uy] = self.platform_velocity(t);
                [
                    -self.c * (qd[0] + ux),
                    -self.c * (qd[1] + uy),
                    u[0] - self.d * qd[2],
                ]
            }

            $($inverse)*
        }
    };
}

steered_sleigh! {
    /// The steered sleigh with its inverse in closed form: Hamel's route.
    SteeredSleigh {
        /// ṙ from its components along the blade and across it: ṙ·e_β = w₁ + Ω (x sin β −
        /// y cos β), ṙ·n_β = w₀ + a cos δ θ̇ + Ω P·e_β; θ̇ = w₂.
        #[velocities]
        fn inverse(&self, t: f64, q: &[f64; 3], w: &[f64; 3]) -> [f64; 3] {
            let delta = self.steering(t);
            let omega = self.table_rate(t);
            let (sb, cb) = (q[2] + delta).sin_cos();
            let (st, ct) = q[2].sin_cos();
            let (px, py) = (q[0] - self.a * ct, q[1] - self.a * st);
            let along = w[1] + omega * (q[0] * sb - q[1] * cb);
            let across = w[0] + self.a * delta.cos() * w[2] + omega * (px * cb + py * sb);
            [cb * along - sb * across, sb * along + cb * across, w[2]]
        }
    }
}

steered_sleigh! {
    /// The same sleigh without an inverse: B by LU, Lagrange's equations projected.
    SteeredSleighByLu {}
}

impl From<&SteeredSleigh> for SteeredSleighByLu {
    fn from(s: &SteeredSleigh) -> Self {
        let SteeredSleigh {
            m,
            inertia,
            a,
            omega0,
            epsilon,
            delta0,
            delta1,
            nu,
            drive,
            sway,
            sway_rate,
            k,
            c,
            d,
        } = s.clone();
        SteeredSleighByLu {
            m,
            inertia,
            a,
            omega0,
            epsilon,
            delta0,
            delta1,
            nu,
            drive,
            sway,
            sway_rate,
            k,
            c,
            d,
        }
    }
}

/// The sleigh as the reference sees it, from vectors in the platform's frame: q = (x, y, θ).
struct Sleigh<'p> {
    p: &'p SteeredSleigh,
    clock: Clock,
}

impl Sleigh<'_> {
    /// U(t) and X(t), the platform's velocity and displacement.
    fn platform<T: Real>(&self, t: T) -> ([T; 2], [T; 2]) {
        let (p, t) = (self.p, self.clock.time(Drive::Platform, t));
        let (s, c) = (t * p.sway_rate).sin_cos();
        (
            [t * p.drive, s * p.sway],
            [
                t * t * (0.5 * p.drive),
                (T::one() - c) * (p.sway / p.sway_rate),
            ],
        )
    }

    /// The velocity of the table's material at the point `at`, relative to the platform.
    fn table<T: Real>(&self, t: T, at: [T; 2]) -> [T; 2] {
        let rate = self.clock.time(Drive::Table, t) * self.p.epsilon + self.p.omega0;
        [-at[1] * rate, at[0] * rate]
    }
}

fn dot2<T: Real>(a: [T; 2], b: [T; 2]) -> T {
    a[0] * b[0] + a[1] * b[1]
}

impl Mechanism<3> for Sleigh<'_> {
    const P: usize = 1;

    fn lagrangian<T: Real>(&self, t: T, q: &[T; 3], qd: &[T; 3]) -> T {
        let p = self.p;
        let (u, x) = self.platform(t);
        let v = [qd[0] + u[0], qd[1] + u[1]];
        let stretch = [q[0] + x[0], q[1] + x[1]];
        dot2(v, v) * (0.5 * p.m) + qd[2] * qd[2] * (0.5 * p.inertia)
            - dot2(stretch, stretch) * (0.5 * p.k)
    }

    fn rows<T: Real>(&self, t: T, q: &[T; 3], qd: &[T; 3]) -> [T; 3] {
        let p = self.p;
        let steering = self.clock.time(Drive::Steering, t);
        let beta = q[2] + (steering * p.nu).sin() * p.delta1 + p.delta0;
        let (sb, cb) = beta.sin_cos();
        let (e, n) = ([cb, sb], [-sb, cb]);
        let (st, ct) = q[2].sin_cos();
        let skate = [q[0] - ct * p.a, q[1] - st * p.a];
        let skate_velocity = [qd[0] + st * qd[2] * p.a, qd[1] - ct * qd[2] * p.a];
        let table_at_skate = self.table(t, skate);
        let table_at_centre = self.table(t, [q[0], q[1]]);
        let slip = [
            skate_velocity[0] - table_at_skate[0],
            skate_velocity[1] - table_at_skate[1],
        ];
        let relative = [qd[0] - table_at_centre[0], qd[1] - table_at_centre[1]];
        [dot2(slip, n), dot2(relative, e), qd[2]]
    }

    fn forces(&self, t: f64, _q: &[f64; 3], qd: &[f64; 3], u: &[f64]) -> [f64; 3] {
        let p = self.p;
        let (platform, _) = self.platform(t);
        [
            -p.c * (qd[0] + platform[0]),
            -p.c * (qd[1] + platform[1]),
            u[0] - p.d * qd[2],
        ]
    }
}

// ---------------------------------------------------------------------------------------
// The comparison
// ---------------------------------------------------------------------------------------

/// A time, a configuration, the free speeds and the inputs.
struct Sample<const N: usize> {
    t: f64,
    q: [f64; N],
    w: Vec<f64>,
    u: Vec<f64>,
}

/// max_k |a_k − b_k| / max_k |b_k|: each vector judged against its own scale, so that a
/// component near zero does not demand digits that rounding elsewhere cannot give.
fn normwise_error(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale.max(f64::MIN_POSITIVE)
}

/// max_k |a_k − b_k| / max(max_k |b_k|, scale): a vector that may be small against the
/// terms it comes from, judged against those terms' size.
fn scaled_error(a: &[f64], b: &[f64], scale: f64) -> f64 {
    let own = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    normwise_error(a, b) * own.max(f64::MIN_POSITIVE) / own.max(scale).max(f64::MIN_POSITIVE)
}

/// Relative differences between a model and the reference, per quantity (also the worst
/// over many points).
#[derive(Clone, Copy, Debug, Default)]
struct Differences {
    qd: f64,
    wdot: f64,
    /// λ against the larger of its own size and that of the forces it balances.
    lambda: f64,
    /// λ against its own size only: printed, not asserted (λ may be nearly zero while the
    /// forces it balances are not).
    lambda_alone: f64,
    power: f64,
    energy: f64,
    /// Not a difference: the reference's own residual in the differentiated constraints.
    reference: f64,
}

impl Differences {
    fn max(self, o: Differences) -> Differences {
        Differences {
            qd: self.qd.max(o.qd),
            wdot: self.wdot.max(o.wdot),
            lambda: self.lambda.max(o.lambda),
            lambda_alone: self.lambda_alone.max(o.lambda_alone),
            power: self.power.max(o.power),
            energy: self.energy.max(o.energy),
            reference: self.reference.max(o.reference),
        }
    }

    /// Every asserted quantity with its name.
    fn asserted(self) -> [(&'static str, f64); 6] {
        [
            ("q̇", self.qd),
            ("ẇ", self.wdot),
            ("λ", self.lambda),
            ("power", self.power),
            ("energy", self.energy),
            ("reference's d/dt r_c", self.reference),
        ]
    }
}

/// The model's state and inputs for a sample.
fn state_of<S: HamelSystem<Coordinates = [f64; N]>, const N: usize>(
    s: &Sample<N>,
) -> (S::State, S::Inputs) {
    let x: Vec<f64> = s.q.iter().chain(&s.w).copied().collect();
    (
        S::State::from_slice(&x).expect("n coordinates and n − p speeds"),
        S::Inputs::from_slice(&s.u).expect("one value per input"),
    )
}

/// The value of a generated method, which must not meet a singularity at the samples.
fn regular<T, E: std::fmt::Debug>(result: Result<T, E>, t: f64, x: &impl std::fmt::Debug) -> T {
    result.unwrap_or_else(|e| panic!("singular at t = {t}, x = {x:?}: {e:?}"))
}

/// The model and the reference at one sample.
fn differences<S, M, const N: usize>(system: &S, mechanism: &M, s: &Sample<N>) -> Differences
where
    S: HamelSystem<Coordinates = [f64; N]>,
    M: Mechanism<N>,
{
    let r: Reference<N> = reference(mechanism, s.t, &s.q, &s.w, &s.u);
    let (x, u) = state_of::<S, N>(s);
    let mut dx = S::State::zeros();
    regular(system.rhs(s.t, &x, &u, &mut dx), s.t, &x);
    let lambda = regular(system.constraint_forces(s.t, &x, &u), s.t, &x);
    let power = regular(system.power(s.t, &x, &u), s.t, &x);
    let energy = regular(system.energy(s.t, &x), s.t, &x);
    Differences {
        qd: normwise_error(&dx.as_ref()[..N], r.qd.as_slice()),
        wdot: normwise_error(&dx.as_ref()[N..], &r.omega_dot.as_slice()[M::P..]),
        lambda: scaled_error(lambda.as_ref(), r.lambda.as_slice(), r.multiplier_scale),
        lambda_alone: normwise_error(lambda.as_ref(), r.lambda.as_slice()),
        power: (power - r.power).abs() / r.power_scale.max(f64::MIN_POSITIVE),
        energy: (energy - r.energy).abs() / r.energy_scale.max(f64::MIN_POSITIVE),
        reference: r.constraint_rate,
    }
}

/// The worst differences over `RANDOM_POINTS` samples, each asserted against `TOLERANCE`.
fn worst_differences<S, M, const N: usize>(
    name: &str,
    system: &S,
    mechanism: &M,
    mut sample: impl FnMut() -> Sample<N>,
) -> Differences
where
    S: HamelSystem<Coordinates = [f64; N]>,
    M: Mechanism<N>,
{
    let mut worst = Differences::default();
    for _ in 0..RANDOM_POINTS {
        let s = sample();
        let d = differences(system, mechanism, &s);
        for (quantity, value) in d.asserted() {
            assert!(
                value <= TOLERANCE,
                "{name}: {quantity} differs by {value:e} (relative) at t = {}, q = {:?}, \
                 w = {:?}, u = {:?}",
                s.t,
                s.q,
                s.w,
                s.u
            );
        }
        worst = worst.max(d);
    }
    let figures: Vec<String> = worst
        .asserted()
        .iter()
        .map(|(quantity, value)| format!("{quantity} {value:.1e}"))
        .collect();
    println!(
        "{name}: worst relative differences over {RANDOM_POINTS} states: {} (λ against |λ| \
         alone {:.1e})",
        figures.join(", "),
        worst.lambda_alone
    );
    worst
}

// ---------------------------------------------------------------------------------------
// λ by one solve with Aᵀ: the N-trailer and a triangular A
// ---------------------------------------------------------------------------------------
//
// Where B is derived from A, hamel takes λ = B_cᵀR (R Lagrange's residual in q) from one
// solve with Aᵀ, block by block in reverse order. Two models whose A exercises both kinds of
// blocks: the N-trailer (a 2 × 2 rotation block for the tractor, inverted in closed form,
// then one row per trailer, and columns of B that fill in along the train), and Bloch's
// nonholonomic particle (ż = y ẋ; A triangular up to permutation, so B by the run-time LU).

/// `hamel::models::NTrailer2` re-derived: axle centres P₀ = (x, y) and
/// Pᵢ = Pᵢ₋₁ − dᵢ (cos θᵢ, sin θᵢ), point masses and moments at the axles, each axle rolling
/// (Ṗᵢ · (−sin θᵢ, cos θᵢ) = 0), the free speeds v = Ṗ₀ · (cos θ₀, sin θ₀) and ω = θ̇₀, a drive
/// force along the tractor's heading and a steering torque.
struct Train<'p> {
    p: &'p NTrailer2,
}

impl Train<'_> {
    /// Ṗᵢ, from differentiating Pᵢ = Pᵢ₋₁ − dᵢ (cos θᵢ, sin θᵢ).
    fn axle_velocities<T: Real>(&self, q: &[T; 5], qd: &[T; 5]) -> [[T; 2]; 3] {
        let mut p = [[qd[0], qd[1]]; 3];
        for i in 1..3 {
            let (s, c) = q[2 + i].sin_cos();
            p[i][0] = p[i - 1][0] + qd[2 + i] * s * self.p.d[i];
            p[i][1] = p[i - 1][1] - qd[2 + i] * c * self.p.d[i];
        }
        p
    }
}

impl Mechanism<5> for Train<'_> {
    const P: usize = 3;

    fn lagrangian<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> T {
        let p = self.axle_velocities(q, qd);
        (0..3).fold(T::zero(), |sum, i| {
            let speed2 = p[i][0] * p[i][0] + p[i][1] * p[i][1];
            sum + speed2 * (0.5 * self.p.m[i]) + qd[2 + i] * qd[2 + i] * (0.5 * self.p.inertia[i])
        })
    }

    fn rows<T: Real>(&self, _t: T, q: &[T; 5], qd: &[T; 5]) -> [T; 5] {
        let p = self.axle_velocities(q, qd);
        let across = |i: usize| {
            let (s, c) = q[2 + i].sin_cos();
            -p[i][0] * s + p[i][1] * c
        };
        let (s, c) = q[2].sin_cos();
        [
            across(0),
            across(1),
            across(2),
            qd[0] * c + qd[1] * s,
            qd[2],
        ]
    }

    fn forces(&self, _t: f64, q: &[f64; 5], _qd: &[f64; 5], u: &[f64]) -> [f64; 5] {
        let (s, c) = q[2].sin_cos();
        [u[0] * c, u[0] * s, u[1], 0.0, 0.0]
    }
}

/// Headings within 1 rad of each other (a train in any pose short of jackknifing), speeds
/// of order 1–2, drive and steering of order 1.
fn train_sample(rng: &mut XorShift) -> Sample<5> {
    let theta0 = rng.uniform(-PI, PI);
    let q = [
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
        theta0,
        theta0 + rng.uniform(-1.0, 1.0),
        theta0 + rng.uniform(-1.0, 1.0),
    ];
    Sample {
        t: 0.0,
        q,
        w: vec![rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)],
        u: vec![rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)],
    }
}

/// The catalogue's default train and one with every mass, moment and length different.
fn trains() -> Vec<NTrailer2> {
    vec![
        NTrailer2::default(),
        NTrailer2 {
            m: [3.0, 0.7, 1.6],
            inertia: [0.4, 0.02, 0.3],
            d: [0.0, 1.3, 0.35],
        },
    ]
}

/// Bloch's nonholonomic particle (Bloch, *Nonholonomic Mechanics and Control*, §1.4: the
/// constraint ż = y ẋ), its row scaled by 1 + x², with a second coordinate s chained to it
/// by ṡ = x ż, in a spring's potential, under gravity along z and pushed in x and y: unit
/// masses, L = ½(ẋ² + ẏ² + ż² + ṡ²) − ½k(x² + y²) − g z. The rows (1 + x²)(ż − y ẋ),
/// ṡ − x ż, ẋ, ẏ give an A that is triangular up to permutation (B by the run-time LU), and
/// λ₁ needs what λ₂ contributes to the z column of Aᵀ.
#[hamel_system]
#[derive(Clone, Debug)]
pub struct NonholonomicParticle {
    /// spring stiffness (N/m per kg)
    pub k: f64,
    /// gravity along z (m/s²)
    pub g: f64,
}

#[hamel_system(coordinates(x, y, z, s), speeds(vx, vy), inputs(fx, fy))]
impl NonholonomicParticle {
    #[kinetic_energy]
    fn kinetic_energy(&self, _q: &[f64; 4], qd: &[f64; 4]) -> f64 {
        0.5 * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2] + qd[3] * qd[3])
    }

    #[potential_energy]
    fn potential_energy(&self, q: &[f64; 4]) -> f64 {
        0.5 * self.k * (q[0] * q[0] + q[1] * q[1]) + self.g * q[2]
    }

    #[constraints]
    fn chained(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [
            (1.0 + q[0] * q[0]) * (qd[2] - q[1] * qd[0]),
            qd[3] - q[0] * qd[2],
        ]
    }

    #[quasi_velocities]
    fn speeds(&self, _q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [qd[0], qd[1]]
    }

    #[forces]
    fn push(&self, _t: f64, _q: &[f64; 4], _qd: &[f64; 4], u: &[f64; 2]) -> [f64; 4] {
        [u[0], u[1], 0.0, 0.0]
    }
}

impl Mechanism<4> for NonholonomicParticle {
    const P: usize = 2;

    fn lagrangian<T: Real>(&self, _t: T, q: &[T; 4], qd: &[T; 4]) -> T {
        let kinetic = qd.iter().fold(T::zero(), |sum, &v| sum + v * v) * 0.5;
        kinetic - (q[0] * q[0] + q[1] * q[1]) * (0.5 * self.k) - q[2] * self.g
    }

    fn rows<T: Real>(&self, _t: T, q: &[T; 4], qd: &[T; 4]) -> [T; 4] {
        let scale = q[0] * q[0] + 1.0;
        [
            (qd[2] - q[1] * qd[0]) * scale,
            qd[3] - q[0] * qd[2],
            qd[0],
            qd[1],
        ]
    }

    fn forces(&self, _t: f64, _q: &[f64; 4], _qd: &[f64; 4], u: &[f64]) -> [f64; 4] {
        [u[0], u[1], 0.0, 0.0]
    }
}

/// Anywhere within 2 of the origin, speeds of order 1–2, forces of order 1.
fn particle_sample(rng: &mut XorShift) -> Sample<4> {
    Sample {
        t: 0.0,
        q: [0; 4].map(|_| rng.uniform(-2.0, 2.0)),
        w: vec![rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)],
        u: vec![rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)],
    }
}

// ---------------------------------------------------------------------------------------
// Samples and parameter sets
// ---------------------------------------------------------------------------------------

/// A time in the first 10 s; the centre within 2 m of the table's axis; any orientation
/// with the nutation θ away from the Euler angles' singular 0 and π; spins of order 1–3.
fn ball_sample(rng: &mut XorShift) -> Sample<5> {
    let t = rng.uniform(0.0, 10.0);
    let q = [
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
        rng.uniform(-PI, PI),
        rng.uniform(0.3, PI - 0.3),
        rng.uniform(-PI, PI),
    ];
    let w = (0..3).map(|_| rng.uniform(-3.0, 3.0)).collect();
    Sample {
        t,
        q,
        w,
        u: Vec::new(),
    }
}

/// The catalogue's default ball; the large ball of `turntable.rs`; a heavy hollow ball
/// (I = 2/3 mρ²) on a table turning the other way and slowing down; a ball with its mass
/// near the centre on a table speeding up fast.
fn balls() -> Vec<BallOnTurntable> {
    let ball = |m: f64, radius: f64, share: f64, omega0, epsilon| BallOnTurntable {
        m,
        radius,
        inertia: share * m * radius * radius,
        omega0,
        epsilon,
    };
    vec![
        BallOnTurntable::default(),
        ball(1.0, 10.0, 0.4, 1.0, 0.1),
        ball(3.0, 0.2, 2.0 / 3.0, -2.0, -0.3),
        ball(0.5, 1.5, 0.1, 0.5, 1.0),
    ]
}

/// A time in the first 10 s, the centre within 2 m of the table's axis, any heading, speeds
/// of order 1–3 and a torque of order 1.
fn sleigh_sample(rng: &mut XorShift) -> Sample<3> {
    let t = rng.uniform(0.0, 10.0);
    let q = [
        rng.uniform(-2.0, 2.0),
        rng.uniform(-2.0, 2.0),
        rng.uniform(-PI, PI),
    ];
    let w = (0..2).map(|_| rng.uniform(-3.0, 3.0)).collect();
    Sample {
        t,
        q,
        w,
        u: vec![rng.uniform(-1.0, 1.0)],
    }
}

/// Two sleighs: the skate behind the centre on a table speeding up, and ahead of it
/// (a < 0) on a table turning the other way and slowing, with everything else different.
fn sleighs() -> Vec<SteeredSleigh> {
    vec![
        SteeredSleigh {
            m: 2.0,
            inertia: 0.5,
            a: 0.4,
            omega0: 0.8,
            epsilon: 0.15,
            delta0: 0.2,
            delta1: 0.3,
            nu: 1.3,
            drive: 0.4,
            sway: 0.6,
            sway_rate: 0.9,
            k: 1.5,
            c: 0.2,
            d: 0.1,
        },
        SteeredSleigh {
            m: 0.7,
            inertia: 0.05,
            a: -0.3,
            omega0: -1.5,
            epsilon: -0.2,
            delta0: -0.5,
            delta1: 0.8,
            nu: 2.5,
            drive: -0.3,
            sway: 1.2,
            sway_rate: 2.0,
            k: 4.0,
            c: 0.5,
            d: 0.3,
        },
    ]
}

// ---------------------------------------------------------------------------------------
// The tests
// ---------------------------------------------------------------------------------------

#[test]
fn ball_on_turntable_equals_the_multiplier_equations() {
    let mut rng = XorShift::new(0xda3_0001);
    for (i, ball) in balls().iter().enumerate() {
        let mechanism = Ball {
            p: ball,
            clock: Clock::default(),
        };
        let name = format!("BallOnTurntable #{i} (LU)");
        worst_differences(&name, ball, &mechanism, || ball_sample(&mut rng));
        let with_inverse = BallWithInverse::from(ball);
        let name = format!("BallWithInverse #{i} (closed-form inverse)");
        worst_differences(&name, &with_inverse, &mechanism, || ball_sample(&mut rng));
    }
}

#[test]
fn steered_sleigh_with_its_inverse_equals_the_multiplier_equations() {
    // Damping and a moving platform do work without any input: no run may leave it out.
    const { assert!(!SteeredSleigh::POWER_VANISHES_WITHOUT_INPUTS) };
    let mut rng = XorShift::new(0xda3_0002);
    for (i, sleigh) in sleighs().iter().enumerate() {
        let mechanism = Sleigh {
            p: sleigh,
            clock: Clock::default(),
        };
        let name = format!("SteeredSleigh #{i} (closed-form inverse)");
        worst_differences(&name, sleigh, &mechanism, || sleigh_sample(&mut rng));
    }
}

#[test]
fn steered_sleigh_by_lu_equals_the_multiplier_equations() {
    let mut rng = XorShift::new(0xda3_0003);
    for (i, sleigh) in sleighs().iter().enumerate() {
        let mechanism = Sleigh {
            p: sleigh,
            clock: Clock::default(),
        };
        let by_lu = SteeredSleighByLu::from(sleigh);
        let name = format!("SteeredSleighByLu #{i} (LU)");
        worst_differences(&name, &by_lu, &mechanism, || sleigh_sample(&mut rng));
    }
}

#[test]
fn n_trailer_equals_the_multiplier_equations() {
    let mut rng = XorShift::new(0xda3_0005);
    for (i, train) in trains().iter().enumerate() {
        let mechanism = Train { p: train };
        let name = format!("NTrailer2 #{i} (B in closed form, λ by Aᵀ block by block)");
        worst_differences(&name, train, &mechanism, || train_sample(&mut rng));
    }
}

#[test]
fn nonholonomic_particle_equals_the_multiplier_equations() {
    let mut rng = XorShift::new(0xda3_0006);
    for particle in [
        NonholonomicParticle { k: 1.0, g: 9.81 },
        NonholonomicParticle { k: 0.3, g: -2.0 },
    ] {
        let name = format!("{particle:?} (run-time LU, λ by Aᵀ)");
        worst_differences(&name, &particle, &particle, || particle_sample(&mut rng));
    }
}

/// Samples per model and prescribed motion in the sensitivity check.
const FROZEN_POINTS: usize = 50;
/// What the explicit time terms must change, at least, at every sample (relative): far
/// above `TOLERANCE`, so that a model that dropped them could not pass.
const FROZEN_GAP: f64 = 1e-6;

/// The smallest, over samples, of the largest difference in ẇ, λ or the power — the
/// quantities explicit time derivatives enter — between a model and a reference whose
/// `drive` is frozen at the sample's time.
fn frozen_gap<S, M, const N: usize>(
    system: &S,
    mechanism: impl Fn(Clock) -> M,
    drive: Drive,
    mut sample: impl FnMut() -> Sample<N>,
) -> f64
where
    S: HamelSystem<Coordinates = [f64; N]>,
    M: Mechanism<N>,
{
    (0..FROZEN_POINTS)
        .map(|_| {
            let s = sample();
            let frozen = mechanism(Clock {
                frozen: Some((drive, s.t)),
            });
            let d = differences(system, &frozen, &s);
            d.wdot.max(d.lambda).max(d.power)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Each explicit time dependence matters at the sampled states: with one prescribed motion
/// frozen in the reference (the same values, no time derivative), every sample differs
/// from the models by far more than the tolerance. Without this, a model that dropped a
/// ∂/∂t term could pass where the term happened to be negligible.
#[test]
fn the_comparison_sees_every_explicit_time_term() {
    let mut rng = XorShift::new(0xda3_0004);
    let mut gaps = Vec::new();
    for ball in balls() {
        let mechanism = |clock| Ball { p: &ball, clock };
        let gap = frozen_gap(&ball, mechanism, Drive::Table, || ball_sample(&mut rng));
        gaps.push(("BallOnTurntable", Drive::Table, gap));
        let with_inverse = BallWithInverse::from(&ball);
        let gap = frozen_gap(&with_inverse, mechanism, Drive::Table, || {
            ball_sample(&mut rng)
        });
        gaps.push(("BallWithInverse", Drive::Table, gap));
    }
    for sleigh in sleighs() {
        let by_lu = SteeredSleighByLu::from(&sleigh);
        for drive in [Drive::Table, Drive::Steering, Drive::Platform] {
            let mechanism = |clock| Sleigh { p: &sleigh, clock };
            let gap = frozen_gap(&sleigh, mechanism, drive, || sleigh_sample(&mut rng));
            gaps.push(("SteeredSleigh", drive, gap));
            let gap = frozen_gap(&by_lu, mechanism, drive, || sleigh_sample(&mut rng));
            gaps.push(("SteeredSleighByLu", drive, gap));
        }
    }
    for (name, drive, gap) in gaps {
        println!("{name}, {drive:?} frozen in the reference: smallest gap {gap:.1e}");
        assert!(
            gap > FROZEN_GAP,
            "{name}: freezing {drive:?} changes only {gap:e}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// The reference itself
// ---------------------------------------------------------------------------------------

/// The reference's ball obeys the closed form of the literature: its centre z = x + i y
/// accelerates as z̈ = i k d/dt(Ω z) = i k (ε z + Ω ż), k = I/(I + mρ²) (Burns, Am. J. Phys.
/// 49, 56 (1981); see `turntable.rs`) — a check of the multiplier formulation, time terms
/// included, by a result derived without it.
#[test]
fn reference_ball_centre_follows_the_closed_form() {
    let mut rng = XorShift::new(0xda3_0005);
    let mut worst = 0.0f64;
    for ball in balls() {
        let mechanism = Ball {
            p: &ball,
            clock: Clock::default(),
        };
        let k = ball.inertia / (ball.inertia + ball.m * ball.radius * ball.radius);
        for _ in 0..RANDOM_POINTS {
            let s = ball_sample(&mut rng);
            let r = reference(&mechanism, s.t, &s.q, &s.w, &s.u);
            let rate = ball.omega0 + ball.epsilon * s.t;
            let (z, zd) = ((s.q[0], s.q[1]), (r.qd[0], r.qd[1]));
            // i k (ε z + Ω ż), term by term.
            let inner = (
                ball.epsilon * z.0 + rate * zd.0,
                ball.epsilon * z.1 + rate * zd.1,
            );
            let expected = [-k * inner.1, k * inner.0];
            let scale = k * (ball.epsilon.abs() * z.0.hypot(z.1) + rate.abs() * zd.0.hypot(zd.1));
            let err = scaled_error(&[r.qdd[0], r.qdd[1]], &expected, scale);
            assert!(
                err <= TOLERANCE,
                "centre acceleration off by {err:e} at {:?}",
                s.q
            );
            worst = worst.max(err);
        }
    }
    println!("reference ball vs z̈ = ik d/dt(Ωz): worst relative difference {worst:.1e}");
}

/// The reference's sleigh obeys Newton and Euler, written by hand in the platform's frame:
/// m (r̈ + U̇) = −k (r + X) − c (ṙ + U) + λ (−sin β, cos β) and I θ̈ = u − d θ̇ − λ a cos δ,
/// the reaction λ A_cᵀ of the skate's row. A check of the generic machinery (the hyper-dual
/// derivatives of L, the sign of λ, the time terms of T and V) on the whole mechanism.
#[test]
fn reference_sleigh_obeys_newton_and_euler() {
    let mut rng = XorShift::new(0xda3_0006);
    let mut worst = 0.0f64;
    for sleigh in sleighs() {
        let mechanism = Sleigh {
            p: &sleigh,
            clock: Clock::default(),
        };
        for _ in 0..RANDOM_POINTS {
            let s = sleigh_sample(&mut rng);
            let r = reference(&mechanism, s.t, &s.q, &s.w, &s.u);
            let err = newton_euler_residual(&sleigh, &s, &r);
            assert!(
                err <= TOLERANCE,
                "Newton–Euler residual {err:e} at t = {}, q = {:?}",
                s.t,
                s.q
            );
            worst = worst.max(err);
        }
    }
    println!("reference sleigh vs Newton–Euler: worst relative residual {worst:.1e}");
}

/// The largest residual of the sleigh's Newton–Euler equations with the reference's q̈ and λ,
/// relative to the largest term in them.
fn newton_euler_residual(p: &SteeredSleigh, s: &Sample<3>, r: &Reference<3>) -> f64 {
    let t = s.t;
    let (sway_sin, sway_cos) = (p.sway_rate * t).sin_cos();
    let velocity = [p.drive * t, p.sway * sway_sin];
    let acceleration = [p.drive, p.sway * p.sway_rate * sway_cos];
    let displacement = [
        0.5 * p.drive * t * t,
        p.sway * (1.0 - sway_cos) / p.sway_rate,
    ];
    let delta = p.delta0 + p.delta1 * (p.nu * t).sin();
    let (sb, cb) = (s.q[2] + delta).sin_cos();
    let lambda = r.lambda[0];
    let reaction = [-sb * lambda, cb * lambda, -p.a * delta.cos() * lambda];
    let mut residual = 0.0f64;
    let mut scale = 0.0f64;
    for i in 0..2 {
        let terms = [
            p.m * (r.qdd[i] + acceleration[i]),
            p.k * (s.q[i] + displacement[i]),
            p.c * (r.qd[i] + velocity[i]),
            -reaction[i],
        ];
        residual = residual.max(terms.iter().sum::<f64>().abs());
        scale = terms.iter().fold(scale, |m, x| m.max(x.abs()));
    }
    let terms = [p.inertia * r.qdd[2], -s.u[0], p.d * r.qd[2], -reaction[2]];
    residual = residual.max(terms.iter().sum::<f64>().abs());
    scale = terms.iter().fold(scale, |m, x| m.max(x.abs()));
    residual / scale
}
