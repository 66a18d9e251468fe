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
