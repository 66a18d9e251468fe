//! A ball rolling without slipping on a turntable whose rate changes with time: the classic
//! affine, time-dependent (rheonomic) constraint. The contact point of the ball moves with the
//! table, so the constraint rows carry a part without velocities, Ω(t)·(y, −x).
//!
//! Coordinates: the centre (x, y) in the inertial frame (the table turns about the origin)
//! and the ball's orientation as ZXZ Euler angles (φ, θ, ψ). Speeds: the ball's angular
//! velocity in the inertial frame (ω_x, ω_y, ω_z). The table turns at Ω(t) = Ω₀ + ε t.
//!
//! For any ball with a centre of mass at its centre and moment of inertia I about it, the
//! centre obeys z̈ = i k d/dt(Ω z) with z = x + i y and k = I/(I + mρ²): a homogeneous ball
//! (I = 2/5 mρ², k = 2/7) on a uniformly turning table circles at 2/7 of the table's rate
//! (Burns, *Ball rolling on a turntable: analog for charged particle dynamics*, Am. J. Phys.
//! 49, 56 (1981); Weltner, Am. J. Phys. 47, 984 (1979)). The validation suite checks the
//! simulated path against the closed form, for ε = 0 and, through Fresnel integrals, ε ≠ 0.

use crate::hamel_system;

/// Parameters of the ball and the table. Defaults: a homogeneous 1 kg ball of radius 0.5 m
/// on a table turning at 1 rad/s, speeding up by 0.1 rad/s².
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct BallOnTurntable {
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

impl Default for BallOnTurntable {
    fn default() -> Self {
        let (m, radius) = (1.0, 0.5);
        BallOnTurntable {
            m,
            radius,
            inertia: 0.4 * m * radius * radius,
            omega0: 1.0,
            epsilon: 0.1,
        }
    }
}

#[hamel_system(
    coordinates(x, y, phi, theta, psi),
    speeds(omega_x, omega_y, omega_z),
    constraints(contact_x, contact_y),
    units(
        t = "s",
        x = "m",
        y = "m",
        phi = "rad",
        theta = "rad",
        psi = "rad",
        omega_x = "rad/s",
        omega_y = "rad/s",
        omega_z = "rad/s",
        energy = "J"
    )
)]
impl BallOnTurntable {
    /// The ball's angular velocity in the inertial frame from the ZXZ Euler angles' rates.
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

    /// T = ½ m |ṙ|² + ½ I |ω|² (the ball's inertia is the same about every axis).
    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let w = self.angular_velocity(q, qd);
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.inertia * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    }

    /// The contact point moves with the table: ṙ + ω × (−ρ e_z) = Ω(t) e_z × r.
    #[constraints]
    fn rolling(&self, t: f64, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let w = self.angular_velocity(q, qd);
        let table = self.omega0 + self.epsilon * t;
        [
            qd[0] - self.radius * w[1] + table * q[1],
            qd[1] + self.radius * w[0] - table * q[0],
        ]
    }

    /// The angular velocity in the inertial frame.
    #[quasi_velocities]
    fn spin(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        self.angular_velocity(q, qd)
    }
}
