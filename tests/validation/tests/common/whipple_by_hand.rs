//! The Whipple bicycle of Meijaard et al. (2007) written by hand, as the catalogue had it
//! before models could be stated from geometry: every body's position, velocity and
//! angular velocity derived in ordinary Rust (v = v_O + ω × r, ½ Ωᵀ I Ω in body axes), the
//! rolling constraints from the wheels' contact points. It is the reference the catalogue's
//! `hamel::models::WhippleBicycle`, stated from its bodies and contacts, is checked
//! against (`tests/bicycle.rs`), and benchmarked against (`benches/speed.rs`).
//!
//! Coordinates, speeds, inputs and constraints are the catalogue model's, in the same order.

use hamel::hamel_system;
use hamel::models::WhippleBicycle;

/// The benchmark's parameters (Table 1), as the catalogue model has them.
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct WhippleByHand {
    pub w: f64,
    pub c: f64,
    pub lambda: f64,
    pub g: f64,
    pub r_r: f64,
    pub m_r: f64,
    pub i_rxx: f64,
    pub i_ryy: f64,
    pub x_b: f64,
    pub z_b: f64,
    pub m_b: f64,
    pub i_bxx: f64,
    pub i_byy: f64,
    pub i_bzz: f64,
    pub i_bxz: f64,
    pub x_h: f64,
    pub z_h: f64,
    pub m_h: f64,
    pub i_hxx: f64,
    pub i_hyy: f64,
    pub i_hzz: f64,
    pub i_hxz: f64,
    pub r_f: f64,
    pub m_f: f64,
    pub i_fxx: f64,
    pub i_fyy: f64,
}

impl From<&WhippleBicycle> for WhippleByHand {
    fn from(b: &WhippleBicycle) -> Self {
        WhippleByHand {
            w: b.w,
            c: b.c,
            lambda: b.lambda,
            g: b.g,
            r_r: b.r_r,
            m_r: b.m_r,
            i_rxx: b.i_rxx,
            i_ryy: b.i_ryy,
            x_b: b.x_b,
            z_b: b.z_b,
            m_b: b.m_b,
            i_bxx: b.i_bxx,
            i_byy: b.i_byy,
            i_bzz: b.i_bzz,
            i_bxz: b.i_bxz,
            x_h: b.x_h,
            z_h: b.z_h,
            m_h: b.m_h,
            i_hxx: b.i_hxx,
            i_hyy: b.i_hyy,
            i_hzz: b.i_hzz,
            i_hxz: b.i_hxz,
            r_f: b.r_f,
            m_f: b.m_f,
            i_fxx: b.i_fxx,
            i_fyy: b.i_fyy,
        }
    }
}

/// Positions, orientations and velocities of the bodies at (q, q̇), in the ground frame:
/// velocities of points follow from a reference point's velocity and the body's angular
/// velocity, v_X = v_O + ω × (X − O).
#[hamel_system(
    coordinates(x, y, psi, phi, theta, delta, theta_r, theta_f),
    speeds(roll_rate, steer_rate, rear_wheel_rate),
    inputs(roll_torque, steer_torque),
    constraints(rear_x, rear_y, front_x, front_y, front_z)
)]
impl WhippleByHand {
    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
    }

    fn scale(s: f64, a: [f64; 3]) -> [f64; 3] {
        [s * a[0], s * a[1], s * a[2]]
    }

    /// R v.
    fn apply(r: [[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
        [
            r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
            r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
            r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
        ]
    }

    /// Rᵀ v: a vector of the ground frame in the body's axes.
    fn apply_transposed(r: [[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
        [
            r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
            r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
            r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
        ]
    }

    fn product(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
            }
        }
        m
    }

    /// The yaw–roll frame R_z(ψ) R_x(φ): the wheel planes' tilt, without the pitch.
    fn yaw_roll(psi: f64, phi: f64) -> [[f64; 3]; 3] {
        let (sp, cp) = psi.sin_cos();
        let (sf, cf) = phi.sin_cos();
        [
            [cp, -sp * cf, sp * sf],
            [sp, cp * cf, -cp * sf],
            [0.0, sf, cf],
        ]
    }

    /// The rear frame: R_B = R_z(ψ) R_x(φ) R_y(θ).
    fn rear_frame(psi: f64, phi: f64, theta: f64) -> [[f64; 3]; 3] {
        let (st, ct) = theta.sin_cos();
        Self::product(
            Self::yaw_roll(psi, phi),
            [[ct, 0.0, st], [0.0, 1.0, 0.0], [-st, 0.0, ct]],
        )
    }

    /// The steer axis in the rear frame: tilted back by λ from the vertical, pointing down.
    fn steer_axis(&self) -> [f64; 3] {
        [self.lambda.sin(), 0.0, self.lambda.cos()]
    }

    /// The rotation by δ about the steer axis (Rodrigues' formula), in the rear frame.
    fn steer(&self, delta: f64) -> [[f64; 3]; 3] {
        let e = self.steer_axis();
        let (s, c) = delta.sin_cos();
        let k = 1.0 - c;
        [
            [
                c + k * e[0] * e[0],
                k * e[0] * e[1] - s * e[2],
                k * e[0] * e[2] + s * e[1],
            ],
            [
                k * e[1] * e[0] + s * e[2],
                c + k * e[1] * e[1],
                k * e[1] * e[2] - s * e[0],
            ],
            [
                k * e[2] * e[0] - s * e[1],
                k * e[2] * e[1] + s * e[0],
                c + k * e[2] * e[2],
            ],
        ]
    }

    /// The rear wheel's centre and its velocity: a distance r_R above the contact point, in
    /// the wheel's plane.
    fn rear_centre(&self, q: &[f64; 8], qd: &[f64; 8]) -> [[f64; 3]; 2] {
        let (sp, cp) = q[2].sin_cos();
        let (sf, cf) = q[3].sin_cos();
        let r = self.r_r;
        [
            [q[0] - r * sp * sf, q[1] + r * cp * sf, -r * cf],
            [
                qd[0] - r * (cp * sf * qd[2] + sp * cf * qd[3]),
                qd[1] + r * (-sp * sf * qd[2] + cp * cf * qd[3]),
                r * sf * qd[3],
            ],
        ]
    }

    /// The rear frame's and the front frame's orientations, R_B and R_H = R_B R_steer(δ).
    fn frames(&self, q: &[f64; 8]) -> [[[f64; 3]; 3]; 2] {
        let rb = Self::rear_frame(q[2], q[3], q[4]);
        [rb, Self::product(rb, self.steer(q[5]))]
    }

    /// The rear frame's angular velocity, ψ̇ e_z + φ̇ R_z e_x + θ̇ R_z R_x e_y, and the front
    /// frame's, which adds δ̇ about the steer axis.
    fn angular_velocities(&self, q: &[f64; 8], qd: &[f64; 8]) -> [[f64; 3]; 2] {
        let (sp, cp) = q[2].sin_cos();
        let (sf, cf) = q[3].sin_cos();
        let rear = [
            qd[3] * cp - qd[4] * sp * cf,
            qd[3] * sp + qd[4] * cp * cf,
            qd[2] + qd[4] * sf,
        ];
        let rb = Self::rear_frame(q[2], q[3], q[4]);
        let steering = Self::scale(qd[5], Self::apply(rb, self.steer_axis()));
        [rear, Self::add(rear, steering)]
    }

    /// The position and velocity of a point fixed in a body that turns by `r` at the rate
    /// `omega` about a point `origin` moving at `velocity`, at `local` from it in the body's
    /// reference axes.
    fn carried(
        origin: [[f64; 3]; 2],
        r: [[f64; 3]; 3],
        omega: [f64; 3],
        local: [f64; 3],
    ) -> [[f64; 3]; 2] {
        let arm = Self::apply(r, local);
        [
            Self::add(origin[0], arm),
            Self::add(origin[1], Self::cross(omega, arm)),
        ]
    }

    /// Positions and velocities of the four centres of mass, [rear wheel, rear frame, front
    /// frame, front wheel], from the rear wheel's centre (at (0, 0, −r_R) in the reference
    /// configuration) through the steer axis, which meets the ground a trail c ahead of the
    /// front contact point.
    fn centres(&self, q: &[f64; 8], qd: &[f64; 8]) -> [[[f64; 3]; 2]; 4] {
        let [rb, rh] = self.frames(q);
        let [omega_b, omega_h] = self.angular_velocities(q, qd);
        let rear = self.rear_centre(q, qd);
        let body = Self::carried(rear, rb, omega_b, [self.x_b, 0.0, self.z_b + self.r_r]);
        let hinge = Self::carried(rear, rb, omega_b, [self.w + self.c, 0.0, self.r_r]);
        let fork = Self::carried(
            hinge,
            rh,
            omega_h,
            [self.x_h - self.w - self.c, 0.0, self.z_h],
        );
        let front = Self::carried(hinge, rh, omega_h, [-self.c, 0.0, -self.r_f]);
        [rear, body, fork, front]
    }

    /// ½ ωᵀ I ω of a frame with inertia (I_xx, I_yy, I_zz, I_xz) in its own axes.
    fn frame_rotation(r: [[f64; 3]; 3], omega: [f64; 3], i: [f64; 4]) -> f64 {
        let w = Self::apply_transposed(r, omega);
        0.5 * (i[0] * w[0] * w[0] + i[1] * w[1] * w[1] + i[2] * w[2] * w[2]) + i[3] * w[0] * w[2]
    }

    /// ½ ωᵀ I ω of a wheel, symmetric about its axle `axle`: I_yy about the axle, I_xx about
    /// every diameter.
    fn wheel_rotation(omega: [f64; 3], axle: [f64; 3], i_xx: f64, i_yy: f64) -> f64 {
        let spin = Self::dot(omega, axle);
        0.5 * i_xx * (Self::dot(omega, omega) - spin * spin) + 0.5 * i_yy * spin * spin
    }

    /// T of the four bodies.
    #[kinetic_energy]
    fn kinetic_energy(&self, q: &[f64; 8], qd: &[f64; 8]) -> f64 {
        let [rb, rh] = self.frames(q);
        let [omega_b, omega_h] = self.angular_velocities(q, qd);
        let [rear, body, fork, front] = self.centres(q, qd);
        let rear_axle = Self::apply(rb, [0.0, 1.0, 0.0]);
        let front_axle = Self::apply(rh, [0.0, 1.0, 0.0]);
        let omega_r = Self::add(omega_b, Self::scale(qd[6], rear_axle));
        let omega_f = Self::add(omega_h, Self::scale(qd[7], front_axle));
        let translation = 0.5
            * (self.m_r * Self::dot(rear[1], rear[1])
                + self.m_b * Self::dot(body[1], body[1])
                + self.m_h * Self::dot(fork[1], fork[1])
                + self.m_f * Self::dot(front[1], front[1]));
        let frames = Self::frame_rotation(
            rb,
            omega_b,
            [self.i_bxx, self.i_byy, self.i_bzz, self.i_bxz],
        ) + Self::frame_rotation(
            rh,
            omega_h,
            [self.i_hxx, self.i_hyy, self.i_hzz, self.i_hxz],
        );
        let wheels = Self::wheel_rotation(omega_r, rear_axle, self.i_rxx, self.i_ryy)
            + Self::wheel_rotation(omega_f, front_axle, self.i_fxx, self.i_fyy);
        translation + frames + wheels
    }

    /// V = −g Σ m z (z points down).
    #[potential_energy]
    fn potential_energy(&self, q: &[f64; 8]) -> f64 {
        let [rear, body, fork, front] = self.centres(q, &[0.0; 8]);
        -self.g
            * (self.m_r * rear[0][2]
                + self.m_b * body[0][2]
                + self.m_h * fork[0][2]
                + self.m_f * front[0][2])
    }

    /// The front wheel's lowest point: its centre plus r_F along the wheel plane's steepest
    /// downward direction, (e_z − (e_z·a) a)/|…| for the axle a.
    fn front_contact_offset(&self, rh: [[f64; 3]; 3]) -> [f64; 3] {
        let a = Self::apply(rh, [0.0, 1.0, 0.0]);
        let down = [-a[2] * a[0], -a[2] * a[1], 1.0 - a[2] * a[2]];
        let length = (1.0 - a[2] * a[2]).sqrt();
        Self::scale(self.r_f / length, down)
    }

    /// The front wheel touches the ground: the height of its lowest point is zero. It
    /// determines the rear frame's pitch.
    #[holonomic(determines(theta))]
    fn front_contact(&self, q: &[f64; 8]) -> [f64; 1] {
        let [_, rh] = self.frames(q);
        let [_, _, _, front] = self.centres(q, &[0.0; 8]);
        let offset = self.front_contact_offset(rh);
        [front[0][2] + offset[2]]
    }

    /// Both wheels roll without slipping: the horizontal velocity of each wheel's material
    /// point at its contact is zero. (Its vertical velocity vanishes with the contact's:
    /// the holonomic constraint for the front wheel, the geometry for the rear one.)
    #[constraints]
    fn rolling(&self, q: &[f64; 8], qd: &[f64; 8]) -> [f64; 4] {
        let [_, rh] = self.frames(q);
        let [_, omega_h] = self.angular_velocities(q, qd);
        let [_, _, _, front] = self.centres(q, qd);
        let (sp, cp) = q[2].sin_cos();
        // Rear: v_P = ṙ_P + r_R (θ̇ + θ̇_R) (cos ψ, sin ψ, 0).
        let rear_spin = self.r_r * (qd[4] + qd[6]);
        let front_axle = Self::apply(rh, [0.0, 1.0, 0.0]);
        let omega_f = Self::add(omega_h, Self::scale(qd[7], front_axle));
        let contact = Self::add(
            front[1],
            Self::cross(omega_f, self.front_contact_offset(rh)),
        );
        [
            qd[0] + rear_spin * cp,
            qd[1] + rear_spin * sp,
            contact[0],
            contact[1],
        ]
    }

    /// The roll rate, the steer rate and the rear wheel's rate (forward speed −r_R θ̇_R
    /// when upright).
    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 8], qd: &[f64; 8]) -> [f64; 3] {
        [qd[3], qd[5], qd[6]]
    }

    /// The roll torque acts on the roll coordinate, the steer torque on the steer angle.
    #[forces]
    fn torques(&self, _t: f64, _q: &[f64; 8], _qd: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
        [0.0, 0.0, 0.0, u[0], 0.0, u[1], 0.0, 0.0]
    }
}
