//! The paper's mobile robot written by hand from its energy, as the catalogue stated it
//! before it was stated from its two wheels: the kinetic energy of the body and the wheels
//! derived by hand, the constraints and the quasi-velocities of the paper. The catalogue's
//! `MobileRobot`, stated from geometry, must have the same right-hand side.

use hamel::hamel_system;
use hamel::models::MobileRobot;

/// The robot's parameters (the catalogue's).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct MobileRobotByHand {
    pub m0: f64,
    pub mw: f64,
    pub jx: f64,
    pub jy: f64,
    pub jz: f64,
    pub r: f64,
    pub b: f64,
    pub l: f64,
    pub g: f64,
}

impl From<&MobileRobot> for MobileRobotByHand {
    fn from(p: &MobileRobot) -> Self {
        MobileRobotByHand {
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

#[hamel_system(
    coordinates(x, y, alpha, phi1, phi2),
    speeds(w3, w4, w5),
    inputs(tau1, tau2),
    constraints(no_side_slip, no_slip)
)]
impl MobileRobotByHand {
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
