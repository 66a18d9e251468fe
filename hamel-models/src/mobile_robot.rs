//! The single-axle mobile robot of Franke, Zaiczek and Röbenack (the paper's section 4):
//! a body pitching about the axle of two independently driven wheels that roll without
//! slipping on a horizontal plane. n = 5 coordinates q = (x, y, α, φ₁, φ₂), p = 2
//! constraints, so the reduced ODE has 2n − p = 8 states.
//!
//! Two models of the same robot, written the two ways hamel accepts:
//!
//! * [`MobileRobot`] — stated from geometry: the body and its two wheels, both wheels
//!   rolling on the ground (`Contact::rolling`); the macro derives the energy and the
//!   rolling constraints, finds that the second wheel's rows repeat the first's and keeps two;
//!   B = A⁻¹ is computed numerically.
//! * [`MobileRobotPaper`] — the paper's form: L̃(q, ω) of its eq. (12) with A and B given.
//!
//! Both have the same parameters and give the same motion (the test suite checks it).

use crate::hamel_system;
use hamel::geometry::{Body, Contact, Inertia, Rotation3, Shape, Surface, Vector3};

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
    constraints(no_slip, no_side_slip),
    bodies(body, right_wheel, left_wheel),
    outputs(px, py),
    control(order = 2, brackets = 3),
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
    /// The body pitches by α about the axle, whose centre is at (x, y, r); its centre of
    /// gravity is l from the axle. The yaw ϑ = r(φ₁ − φ₂)/b follows from the wheel angles (the
    /// coordinates build in what the difference of the wheels' rolling gives). Wheel 1 is on
    /// the right; wheel i turns by φᵢ relative to the body.
    #[bodies]
    pub fn bodies(&self, q: &[f64; 5]) -> [Body; 3] {
        let heading = Rotation3::about_z(self.r * (q[3] - q[4]) / self.b);
        let frame = heading * Rotation3::about_y(q[2]);
        let centre = Vector3::new(q[0], q[1], self.r) + frame * Vector3::new(0.0, 0.0, self.l);
        let inertia = Inertia::principal(self.jx, self.jy, self.jz);
        let (right, left) = (self.wheel(q, -0.5, q[3]), self.wheel(q, 0.5, q[4]));
        [Body::new(self.m0, inertia, centre, frame), right, left]
    }

    /// A wheel, a thin disk on the axle (its y axis), `side` · b to the left of its centre.
    fn wheel(&self, q: &[f64; 5], side: f64, angle: f64) -> Body {
        let heading = Rotation3::about_z(self.r * (q[3] - q[4]) / self.b);
        let centre = Vector3::new(q[0], q[1], self.r) + side * self.b * (heading * Vector3::y());
        let orientation = heading * Rotation3::about_y(q[2] + angle);
        let d = 0.25 * self.mw * self.r * self.r;
        let inertia = Inertia::principal(d, 2.0 * d, d);
        let wheel = Body::new(self.mw, inertia, centre, orientation);
        wheel.with_shape(Shape::disk(self.r, Vector3::y()))
    }

    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, -self.g)
    }

    /// The paper's potential is zero with the body's centre of gravity at the axle's height.
    #[potential_energy]
    fn datum(&self, _q: &[f64; 5]) -> f64 {
        -(self.m0 + 2.0 * self.mw) * self.g * self.r
    }

    /// Both wheels roll on the ground. On one axle, the second wheel's rows repeat the
    /// first's (`Mechanism::NOTES`): `no_slip` and `no_side_slip` are both wheels' forces
    /// along the heading and the axle.
    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 2] {
        let [_, right, left] = self.bodies(q);
        let road = Surface::ground();
        [Contact::rolling(right, road), Contact::rolling(left, road)]
    }

    /// ω³ = α̇ (pitch rate), ω⁴ = path velocity, ω⁵ = ϑ̇ (yaw rate). The yaw is written as in
    /// `bodies`, so that the macro sees sin² + cos² of the same angle.
    #[quasi_velocities]
    pub fn speeds(&self, q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        let (s, c) = (self.r * (q[3] - q[4]) / self.b).sin_cos();
        let yaw_rate = self.r / self.b * (qd[3] - qd[4]);
        [qd[2], qd[0] * c + qd[1] * s, yaw_rate]
    }

    /// The look-ahead point, 0.3 m ahead of the axle's centre along the heading: the point
    /// `robot_tracking` steers (the axle's centre itself has a singular decoupling matrix:
    /// it cannot move sideways).
    #[outputs]
    pub fn look_ahead(&self, q: &[f64; 5]) -> [f64; 2] {
        let (s, c) = (self.r * (q[3] - q[4]) / self.b).sin_cos();
        [q[0] + 0.3 * c, q[1] + 0.3 * s]
    }

    /// The motor torques act between the body and each wheel, on the relative angles φᵢ.
    #[forces]
    pub fn torques(&self, _t: f64, _q: &[f64; 5], _qd: &[f64; 5], u: &[f64; 2]) -> [f64; 5] {
        [0.0, 0.0, 0.0, u[0], u[1]]
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
