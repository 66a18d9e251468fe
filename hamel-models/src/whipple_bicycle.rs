//! The Whipple bicycle of the benchmark of Meijaard, Papadopoulos, Ruina and Schwab
//! (*Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and
//! review*, Proc. R. Soc. A 463, 1955–1982, 2007): four rigid bodies — the rear wheel R, the
//! rear frame B with the rider, the front frame H (fork and handlebar) and the front wheel F —
//! hinged at the wheel axles and the steer axis, on knife-edge wheels that roll without
//! slipping on a level plane.
//!
//! Written from geometry: the model states its four bodies (mass, inertia in their own axes,
//! centre of mass and orientation as functions of the coordinates), gravity, and the two
//! wheels' contacts with the ground. The macro derives the velocities, the kinetic and
//! potential energy, the rolling constraints (from the velocity of each wheel's material
//! point at its contact) and, since the front contact's height varies with the coordinates,
//! the holonomic constraint that determines the rear frame's pitch (`hamel::docs::geometry`
//! explains each step). Axes as in the paper: x forward, y to the right, z down; the
//! parameters (Table 1) are given in the reference configuration, upright with the steer
//! straight and the rear contact point at the origin.
//!
//! Coordinates: the rear contact point (x, y), the rear frame's yaw ψ, roll φ and pitch θ (a
//! yaw–roll–pitch sequence, R_B = R_z(ψ) R_x(φ) R_y(θ)), the steer angle δ about the steer
//! axis, and the wheels' rotations relative to their frames. Roll and steer are positive to
//! the right. n = 8; four rolling constraints and the holonomic one, p = 5; the free speeds are
//! the roll rate, the steer rate and the rear wheel's rate: 2n − p = 11 states. Inputs: a
//! torque on the roll coordinate (between the ground and the rear frame) and the steer torque
//! between the rear and front frames.
//!
//! Linearized about upright straight running at speed v it gives the paper's
//! M q̈ + v C₁ q̇ + (g K₀ + v² K₂) q = f for q = (φ, δ), its eigenvalues (Table 2) and the
//! weave and capsize speeds; the validation suite checks all of them, from this nonlinear
//! model.

use crate::hamel_system;
use hamel::geometry::{Body, Contact, Inertia, Rotation3, Vector3, disk_contact};

/// The benchmark's parameters (the paper's Table 1).
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct WhippleBicycle {
    /// wheelbase (m)
    pub w: f64,
    /// trail (m)
    pub c: f64,
    /// steer axis tilt from the vertical (rad)
    pub lambda: f64,
    /// gravitational acceleration (m/s²)
    pub g: f64,
    /// rear wheel radius (m)
    pub r_r: f64,
    /// rear wheel mass (kg)
    pub m_r: f64,
    /// rear wheel moment of inertia about a diameter (kg m²)
    pub i_rxx: f64,
    /// rear wheel moment of inertia about its axle (kg m²)
    pub i_ryy: f64,
    /// rear frame centre of mass, forward of the rear contact (m)
    pub x_b: f64,
    /// rear frame centre of mass, z (negative: above the ground) (m)
    pub z_b: f64,
    /// rear frame mass (kg)
    pub m_b: f64,
    /// rear frame inertia I_xx about its centre of mass (kg m²)
    pub i_bxx: f64,
    /// rear frame inertia I_yy (kg m²)
    pub i_byy: f64,
    /// rear frame inertia I_zz (kg m²)
    pub i_bzz: f64,
    /// rear frame product of inertia I_xz (kg m²)
    pub i_bxz: f64,
    /// front frame centre of mass, forward of the rear contact (m)
    pub x_h: f64,
    /// front frame centre of mass, z (m)
    pub z_h: f64,
    /// front frame mass (kg)
    pub m_h: f64,
    /// front frame inertia I_xx about its centre of mass (kg m²)
    pub i_hxx: f64,
    /// front frame inertia I_yy (kg m²)
    pub i_hyy: f64,
    /// front frame inertia I_zz (kg m²)
    pub i_hzz: f64,
    /// front frame product of inertia I_xz (kg m²)
    pub i_hxz: f64,
    /// front wheel radius (m)
    pub r_f: f64,
    /// front wheel mass (kg)
    pub m_f: f64,
    /// front wheel moment of inertia about a diameter (kg m²)
    pub i_fxx: f64,
    /// front wheel moment of inertia about its axle (kg m²)
    pub i_fyy: f64,
}

impl Default for WhippleBicycle {
    /// The benchmark bicycle of Meijaard et al. (2007), Table 1.
    fn default() -> Self {
        WhippleBicycle {
            w: 1.02,
            c: 0.08,
            lambda: std::f64::consts::PI / 10.0,
            g: 9.81,
            r_r: 0.3,
            m_r: 2.0,
            i_rxx: 0.0603,
            i_ryy: 0.12,
            x_b: 0.3,
            z_b: -0.9,
            m_b: 85.0,
            i_bxx: 9.2,
            i_byy: 11.0,
            i_bzz: 2.8,
            i_bxz: 2.4,
            x_h: 0.9,
            z_h: -0.7,
            m_h: 4.0,
            i_hxx: 0.05892,
            i_hyy: 0.06,
            i_hzz: 0.00708,
            i_hxz: -0.00756,
            r_f: 0.35,
            m_f: 3.0,
            i_fxx: 0.1405,
            i_fyy: 0.28,
        }
    }
}

/// The bicycle from its bodies and contacts.
#[hamel_system(
    coordinates(x, y, psi, phi, theta, delta, theta_r, theta_f),
    speeds(roll_rate, steer_rate, rear_wheel_rate),
    inputs(roll_torque, steer_torque),
    constraints(rear_x, rear_y, front_x, front_y, front_z),
    bodies(rear_wheel, rear_frame, front_frame, front_wheel),
    outputs(roll, steer),
    control(order = 2, brackets = 1),
    units(
        t = "s",
        x = "m",
        y = "m",
        psi = "rad",
        phi = "rad",
        theta = "rad",
        delta = "rad",
        theta_r = "rad",
        theta_f = "rad",
        roll_rate = "rad/s",
        steer_rate = "rad/s",
        rear_wheel_rate = "rad/s",
        roll_torque = "N m",
        steer_torque = "N m",
        energy = "J"
    )
)]
impl WhippleBicycle {
    /// The rear wheel, the rear frame with the rider, the front frame and the front wheel.
    #[bodies]
    fn bodies(&self, q: &[f64; 8]) -> [Body; 4] {
        let [x, y, psi, phi, theta, delta, theta_r, theta_f] = *q;
        // Yaw, then roll: the wheels' planes; then pitch: the rear frame.
        let yaw_roll = Rotation3::about_z(psi) * Rotation3::about_x(phi);
        let rear = yaw_roll * Rotation3::about_y(theta);
        // The steer axis, tilted back by λ from the vertical, pointing down.
        let steer_axis = Vector3::new(self.lambda.sin(), 0.0, self.lambda.cos());
        let front = rear * Rotation3::from_axis_angle(&steer_axis, delta);
        // The rear wheel's centre, r_R above the contact point in the wheel's plane; the
        // steer axis meets the ground a trail c ahead of the front contact.
        let rear_centre = Vector3::new(x, y, 0.0) + yaw_roll * Vector3::new(0.0, 0.0, -self.r_r);
        let hinge = rear_centre + rear * Vector3::new(self.w + self.c, 0.0, self.r_r);
        [
            Body::new(
                self.m_r,
                Inertia::principal(self.i_rxx, self.i_ryy, self.i_rxx),
                rear_centre,
                rear * Rotation3::about_y(theta_r),
            ),
            Body::new(
                self.m_b,
                Inertia::new(self.i_bxx, self.i_byy, self.i_bzz, 0.0, 0.0, self.i_bxz),
                rear_centre + rear * Vector3::new(self.x_b, 0.0, self.z_b + self.r_r),
                rear,
            ),
            Body::new(
                self.m_h,
                Inertia::new(self.i_hxx, self.i_hyy, self.i_hzz, 0.0, 0.0, self.i_hxz),
                hinge + front * Vector3::new(self.x_h - self.w - self.c, 0.0, self.z_h),
                front,
            ),
            Body::new(
                self.m_f,
                Inertia::principal(self.i_fxx, self.i_fyy, self.i_fxx),
                hinge + front * Vector3::new(-self.c, 0.0, -self.r_f),
                front * Rotation3::about_y(theta_f),
            ),
        ]
    }

    /// Gravity points along +z (down).
    #[gravity]
    fn gravity(&self) -> Vector3 {
        Vector3::new(0.0, 0.0, self.g)
    }

    /// Both wheels roll on the ground: the rear one at (x, y), the front one at its lowest
    /// point, whose height fixes the rear frame's pitch θ.
    #[contacts(determines(theta))]
    fn contacts(&self, q: &[f64; 8]) -> [Contact; 2] {
        let [rear_wheel, _, _, front_wheel] = self.bodies(q);
        let axle = front_wheel.orientation * Vector3::y();
        let lowest = disk_contact(front_wheel.centre, axle, self.r_f, -Vector3::z());
        [
            Contact::ground(rear_wheel, Vector3::new(q[0], q[1], 0.0)),
            Contact::ground(front_wheel, lowest),
        ]
    }

    /// The roll rate, the steer rate and the rear wheel's rate (forward speed −r_R θ̇_R
    /// when upright).
    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 8], qd: &[f64; 8]) -> [f64; 3] {
        [qd[3], qd[5], qd[6]]
    }

    /// The roll and steer angles, whose Lie derivatives the control guide reads the
    /// bicycle's relative degrees from (`hamel::docs::control`). The brackets are one deep
    /// only ([f, g_j] and [g_roll_torque, g_steer_torque]): each further level is a tangent
    /// sweep of the whole right-hand side per bracket, and depth 2 would add about 3.5 s of
    /// CPU to every debug build of this library (`benches/control_build_cost.sh`).
    #[outputs]
    fn lean_and_steer(&self, q: &[f64; 8]) -> [f64; 2] {
        [q[3], q[5]]
    }

    /// The roll torque acts on the roll coordinate, the steer torque on the steer angle.
    #[forces]
    fn torques(&self, _t: f64, _q: &[f64; 8], _qd: &[f64; 8], u: &[f64; 2]) -> [f64; 8] {
        [0.0, 0.0, 0.0, u[0], 0.0, u[1], 0.0, 0.0]
    }
}
