//! The single-axle mobile robot of Franke, Zaiczek and Röbenack (the paper's section 4):
//! a body pitching about the axle of two independently driven wheels that roll without
//! slipping on a horizontal plane. n = 5 coordinates q = (x, y, α, φ₁, φ₂), p = 2
//! constraints, so the reduced ODE has 2n − p = 8 states.
//!
//! Two models of the same robot, written the two ways hamel accepts:
//!
//! * [`MobileRobot`] — the everyday form: kinetic and potential energy from the bodies'
//!   3D motion, the constraints and the quasi-velocities; B = A⁻¹ is computed numerically.
//! * [`MobileRobotPaper`] — the paper's form: L̃(q, ω) of its eq. (12) with A and B given.
//!
//! Both have the same parameters and give the same motion (the test suite checks it).
//!
//! [`MobileRobot`] also states its three bodies by hand ([`Mechanism`]), so that
//! `hamel::scene` can draw it: the chassis and the two wheels, placed as its kinetic energy
//! says (a test checks the bodies' kinetic energy against the model's at random states).

use crate::geometry::{Body, Contact, Inertia, Mechanism, Rotation3, Vector3};
use crate::hamel_system;

/// Parameters of the mobile robot. Defaults: a 10 kg body on 1 kg wheels of 0.1 m radius.
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct MobileRobot {
    /// mass of the body (kg)
    pub m0: f64,
    /// mass of one wheel (kg)
    pub mw: f64,
    /// body's principal moment of inertia about its x axis (forward) (kg m²)
    pub jx: f64,
    /// body's principal moment of inertia about its y axis (the axle) (kg m²)
    pub jy: f64,
    /// body's principal moment of inertia about its z axis (vertical) (kg m²)
    pub jz: f64,
    /// wheel radius (m)
    pub r: f64,
    /// axle length, wheel to wheel (m)
    pub b: f64,
    /// distance of the body's centre of gravity from the axle (m)
    pub l: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
}

impl Default for MobileRobot {
    fn default() -> Self {
        MobileRobot {
            m0: 10.0,
            mw: 1.0,
            jx: 0.4,
            jy: 0.3,
            jz: 0.2,
            r: 0.1,
            b: 0.5,
            l: 0.2,
            g: 9.81,
        }
    }
}

#[hamel_system(
    coordinates(x, y, alpha, phi1, phi2),
    speeds(w3, w4, w5),
    inputs(tau1, tau2),
    constraints(no_side_slip, no_slip),
    units(
        t = "s",
        x = "m",
        y = "m",
        alpha = "rad",
        phi1 = "rad",
        phi2 = "rad",
        w3 = "rad/s",
        w4 = "m/s",
        w5 = "rad/s",
        tau1 = "N m",
        tau2 = "N m",
        energy = "J"
    )
)]
impl MobileRobot {
    /// T of the body and the wheels. The body's centre of gravity sits l·(sin α e_f + cos α e_z)
    /// from the axle's centre (e_f: forward, e_a: along the axle, to the left); the yaw
    /// ϑ = r(φ₁ − φ₂)/b follows from the wheel angles; wheel i spins at α̇ + φ̇ᵢ.
    #[kinetic_energy]
    pub fn kinetic_energy(&self, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let [_, _, alpha, phi1, phi2] = *q;
        let [xd, yd, alphad, phi1d, phi2d] = *qd;
        let theta = self.r * (phi1 - phi2) / self.b;
        let thetad = self.r * (phi1d - phi2d) / self.b;
        let (s, c) = theta.sin_cos();
        let (sa, ca) = alpha.sin_cos();
        // Body: translation of its centre of gravity, rotation about the axle and the vertical.
        let vx = xd + self.l * alphad * ca * c - self.l * sa * thetad * s;
        let vy = yd + self.l * alphad * ca * s + self.l * sa * thetad * c;
        let vz = -self.l * alphad * sa;
        let body = 0.5 * self.m0 * (vx * vx + vy * vy + vz * vz)
            + 0.5 * (self.jx * sa * sa + self.jz * ca * ca) * thetad * thetad
            + 0.5 * self.jy * alphad * alphad;
        // Wheels: centres at ±b/2 along the axle (wheel 1 on the right), ideal disks.
        let half = 0.5 * self.b * thetad;
        let (c1x, c1y) = (xd + half * c, yd + half * s);
        let (c2x, c2y) = (xd - half * c, yd - half * s);
        // ½·(½ m_w r²)·spin² per wheel, ½·(¼ m_w r²)·ϑ̇² per wheel for the yaw.
        let quarter = 0.25 * self.mw * self.r * self.r;
        let wheels = 0.5 * self.mw * (c1x * c1x + c1y * c1y + c2x * c2x + c2y * c2y)
            + quarter * ((alphad + phi1d).powi(2) + (alphad + phi2d).powi(2))
            + quarter * thetad * thetad;
        body + wheels
    }

    /// V: the body's centre of gravity is l cos α above the axle.
    #[potential_energy]
    pub fn potential_energy(&self, q: &[f64; 5]) -> f64 {
        self.m0 * self.g * self.l * q[2].cos()
    }

    /// No slip sideways (ω¹) and no slip along the path (ω²).
    #[constraints]
    pub fn no_slip(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        let (s, c) = theta.sin_cos();
        [
            qd[0] * s - qd[1] * c,
            self.r * qd[2] + 0.5 * self.r * (qd[3] + qd[4]) - (qd[0] * c + qd[1] * s),
        ]
    }

    /// ω³ = α̇ (pitch rate), ω⁴ = path velocity, ω⁵ = ϑ̇ (yaw rate).
    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        [
            qd[2],
            qd[0] * theta.cos() + qd[1] * theta.sin(),
            self.r / self.b * (qd[3] - qd[4]),
        ]
    }

    /// The motor torques act between the body and each wheel, on the relative angles φᵢ.
    #[forces]
    pub fn torques(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64; 2]) -> [f64; 5] {
        [0.0, 0.0, 0.0, u[0], u[1]]
    }
}

/// The robot's bodies, written by hand from the kinetic energy above (the model states its
/// energy, not its bodies): the chassis turned by the yaw ϑ = r(φ₁ − φ₂)/b and pitched by α
/// about the axle, its centre of gravity l along its z axis from the axle's centre r above
/// (x, y); the wheels, disks of radius r (inertia ¼ m_w r² about a diameter, ½ m_w r² about
/// the axle), b/2 to either side of it along the axle, turned by α + φᵢ about it (wheel 1 on
/// the right). Each rolls on the ground below its centre.
impl Mechanism for MobileRobot {
    const BODIES: &'static [&'static str] = &["chassis", "right_wheel", "left_wheel"];

    fn bodies_at(&self, _t: f64, q: &[f64; 5]) -> Vec<Body> {
        let [x, y, alpha, phi1, phi2] = *q;
        let heading = Rotation3::about_z(self.r * (phi1 - phi2) / self.b);
        let axle = Vector3::new(x, y, self.r);
        let pitched = heading * Rotation3::about_y(alpha);
        let (diameter, spin) = (
            0.25 * self.mw * self.r * self.r,
            0.5 * self.mw * self.r * self.r,
        );
        // The y axis of the heading points left: wheel 1 is at −b/2 along it.
        let wheel = |side: f64, angle: f64| {
            Body::new(
                self.mw,
                Inertia::principal(diameter, spin, diameter),
                axle + heading * Vector3::new(0.0, 0.5 * side * self.b, 0.0),
                heading * Rotation3::about_y(alpha + angle),
            )
        };
        vec![
            Body::new(
                self.m0,
                Inertia::principal(self.jx, self.jy, self.jz),
                axle + pitched * Vector3::new(0.0, 0.0, self.l),
                pitched,
            ),
            wheel(-1.0, phi1),
            wheel(1.0, phi2),
        ]
    }

    fn contacts_at(&self, t: f64, q: &[f64; 5]) -> Vec<Contact> {
        self.bodies_at(t, q)[1..]
            .iter()
            .map(|&wheel| Contact::ground(wheel, wheel.centre - Vector3::new(0.0, 0.0, self.r)))
            .collect()
    }

    fn gravity_vector(&self, _t: f64) -> Option<Vector3> {
        Some(Vector3::new(0.0, 0.0, -self.g))
    }
}

/// The same robot in the paper's input form: L̃(q, ω) of eq. (12), with A and B given.
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct MobileRobotPaper {
    /// mass of the body (kg)
    pub m0: f64,
    /// mass of one wheel (kg)
    pub mw: f64,
    /// body's principal moment of inertia about its x axis (kg m²)
    pub jx: f64,
    /// body's principal moment of inertia about its y axis (the axle) (kg m²)
    pub jy: f64,
    /// body's principal moment of inertia about its z axis (kg m²)
    pub jz: f64,
    /// wheel radius (m)
    pub r: f64,
    /// axle length (m)
    pub b: f64,
    /// distance of the body's centre of gravity from the axle (m)
    pub l: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
}

impl From<&MobileRobot> for MobileRobotPaper {
    fn from(p: &MobileRobot) -> Self {
        MobileRobotPaper {
            m0: p.m0,
            mw: p.mw,
            jx: p.jx,
            jy: p.jy,
            jz: p.jz,
            r: p.r,
            b: p.b,
            l: p.l,
            g: p.g,
        }
    }
}

impl Default for MobileRobotPaper {
    fn default() -> Self {
        (&MobileRobot::default()).into()
    }
}

#[hamel_system(
    coordinates(x, y, alpha, phi1, phi2),
    speeds(w3, w4, w5),
    inputs(tau1, tau2),
    constraints(no_side_slip, no_slip),
    units(
        t = "s",
        x = "m",
        y = "m",
        alpha = "rad",
        phi1 = "rad",
        phi2 = "rad",
        w3 = "rad/s",
        w4 = "m/s",
        w5 = "rad/s",
        tau1 = "N m",
        tau2 = "N m",
        energy = "J"
    )
)]
impl MobileRobotPaper {
    /// The paper's eq. (12), ω indexed from 0 here (`w[0]` is ω¹), with its terms in ω²
    /// (the constrained slip along the path) as the bodies give them: ½ m_w (ω²)² + m_w ω²ω⁴,
    /// where the paper prints m_w (ω²)² − m_w ω²ω⁴. The motion is the same either way (ω² ≡ 0
    /// and every γ² vanishes), but the constraint forces see the difference: the printed terms
    /// put (−2 m_w ω⁴ω⁵, −2 m_w ω̇⁴) into λ.
    #[quasi_lagrangian]
    pub fn lagrangian(&self, q: &[f64; 5], w: &[f64; 5]) -> f64 {
        let alpha = q[2];
        let (sa, ca) = alpha.sin_cos();
        let ml2 = self.m0 * self.l * self.l;
        let j5 = (self.jx + ml2) * sa * sa
            + self.jz * ca * ca
            + 0.75 * self.mw * self.b * self.b
            + 0.5 * self.mw * self.r * self.r;
        0.5 * (self.m0 + 2.0 * self.mw) * w[0] * w[0]
            + 0.5 * self.mw * w[1] * w[1]
            + 0.5 * (self.jy + ml2) * w[2] * w[2]
            + 0.5 * (self.m0 + 3.0 * self.mw) * w[3] * w[3]
            + 0.5 * j5 * w[4] * w[4]
            + self.m0 * self.l * (w[2] * w[3] * ca - w[0] * w[4] * sa)
            + self.mw * w[1] * w[3]
            - self.m0 * self.l * self.g * ca
    }

    #[constraints]
    pub fn no_slip(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 2] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        let (s, c) = theta.sin_cos();
        [
            qd[0] * s - qd[1] * c,
            self.r * qd[2] + 0.5 * self.r * (qd[3] + qd[4]) - (qd[0] * c + qd[1] * s),
        ]
    }

    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        [
            qd[2],
            qd[0] * theta.cos() + qd[1] * theta.sin(),
            self.r / self.b * (qd[3] - qd[4]),
        ]
    }

    /// q̇ = B(q) ω, the inverse of the five rows above.
    #[velocities]
    pub fn velocities(&self, q: &[f64; 5], w: &[f64; 5]) -> [f64; 5] {
        let theta = self.r * (q[3] - q[4]) / self.b;
        let (s, c) = theta.sin_cos();
        let roll = (w[1] + w[3]) / self.r - w[2];
        let turn = 0.5 * self.b / self.r * w[4];
        [
            w[0] * s + w[3] * c,
            -w[0] * c + w[3] * s,
            w[2],
            roll + turn,
            roll - turn,
        ]
    }

    #[forces]
    pub fn torques(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64; 2]) -> [f64; 5] {
        [0.0, 0.0, 0.0, u[0], u[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::HamelSystem;

    /// The bodies' kinetic energy Σ ½ m |ċ|² + ½ Ωᵀ I Ω, the velocities by central
    /// differences of the bodies' poses along q̇.
    fn bodies_kinetic_energy(robot: &MobileRobot, q: &[f64; 5], qd: &[f64; 5]) -> f64 {
        let h = 1e-5;
        let at = |s: f64| robot.bodies_at(0.0, &core::array::from_fn(|k| q[k] + s * qd[k]));
        let (ahead, behind, now) = (at(h), at(-h), at(0.0));
        let mut energy = 0.0;
        for ((a, b), body) in ahead.iter().zip(&behind).zip(&now) {
            let velocity = (a.centre - b.centre) / (2.0 * h);
            // Ω in the body's axes: the skew part of Rᵀ Ṙ.
            let (ra, rb, r) = (
                a.orientation.matrix(),
                b.orientation.matrix(),
                body.orientation.matrix(),
            );
            let w = |i: usize, j: usize| {
                (0..3)
                    .map(|k| r[k][i] * (ra[k][j] - rb[k][j]) / (2.0 * h))
                    .sum::<f64>()
            };
            let omega = [
                0.5 * (w(2, 1) - w(1, 2)),
                0.5 * (w(0, 2) - w(2, 0)),
                0.5 * (w(1, 0) - w(0, 1)),
            ];
            let inertia = body.inertia.matrix();
            let rotation: f64 = (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| omega[i] * inertia[i][j] * omega[j])
                .sum();
            energy += 0.5 * body.mass * velocity.norm_squared() + 0.5 * rotation;
        }
        energy
    }

    #[test]
    fn the_bodies_have_the_models_kinetic_energy() {
        let robot = MobileRobot::default();
        // A fixed sequence of pseudo-random numbers in [−1, 1] (a linear congruential one).
        let mut seed: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..20 {
            let q: [f64; 5] =
                core::array::from_fn(|k| 3.0 * next() * if k < 2 { 1.0 } else { 2.0 });
            let x: [f64; 8] = core::array::from_fn(|k| if k < 5 { q[k] } else { 2.0 * next() });
            let qd = robot.generalized_velocities(0.0, &x).unwrap();
            let model = robot.energy(0.0, &x).unwrap() - robot.potential_energy(&q);
            let bodies = bodies_kinetic_energy(&robot, &q, &qd);
            assert!(
                (bodies - model).abs() <= 1e-7 * model.abs().max(1e-3),
                "at q = {q:?}, q̇ = {qd:?}: bodies {bodies}, model {model}"
            );
        }
        // Gravity's potential of the bodies is the model's: m₀ g times the chassis' height
        // above the axle, plus a constant.
        let q = [0.3, -0.2, 0.7, 1.0, -2.0];
        let chassis = robot.bodies_at(0.0, &q)[0];
        let height = chassis.centre.z - robot.r;
        assert!((robot.m0 * robot.g * height - robot.potential_energy(&q)).abs() < 1e-12);
    }

    #[test]
    fn the_wheels_roll_without_slipping_on_the_ground_below_their_centres() {
        let robot = MobileRobot::default();
        let q = [0.3, -0.2, 0.7, 1.0, -2.0];
        let x = [q[0], q[1], q[2], q[3], q[4], 0.4, -0.7, 1.3];
        let qd = robot.generalized_velocities(0.0, &x).unwrap();
        let h = 1e-5;
        let at = |s: f64| robot.bodies_at(0.0, &core::array::from_fn(|k| q[k] + s * qd[k]));
        let (ahead, behind) = (at(h), at(-h));
        for (j, contact) in robot.contacts_at(0.0, &q).iter().enumerate() {
            assert_eq!(contact.point.z, 0.0);
            assert!((contact.body.centre - contact.point).norm() - robot.r < 1e-15);
            // The wheel's material point at the contact is at rest: ċ + ω × (P − c) = 0, ω in
            // the ground's axes the skew part of Ṙ Rᵀ.
            let (a, b, wheel) = (ahead[j + 1], behind[j + 1], contact.body);
            let (ra, rb, r) = (
                a.orientation.matrix(),
                b.orientation.matrix(),
                wheel.orientation.matrix(),
            );
            let w = |i: usize, k: usize| {
                (0..3)
                    .map(|m| (ra[i][m] - rb[i][m]) / (2.0 * h) * r[k][m])
                    .sum::<f64>()
            };
            let omega = Vector3::new(
                0.5 * (w(2, 1) - w(1, 2)),
                0.5 * (w(0, 2) - w(2, 0)),
                0.5 * (w(1, 0) - w(0, 1)),
            );
            let slip =
                (a.centre - b.centre) / (2.0 * h) + omega.cross(&(contact.point - wheel.centre));
            assert!(slip.norm() < 1e-8, "wheel {j} slips at {slip}");
        }
    }
}
