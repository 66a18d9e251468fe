//! Chaplygin's ball: a sphere whose centre of mass is its geometric centre but whose
//! principal moments of inertia differ, rolling without slipping on a horizontal plane
//! (Chaplygin, *On a ball's rolling on a horizontal plane*, Mat. Sbornik 24, 1903; Borisov &
//! Mamaev, *Rolling of a rigid body on a plane and sphere*, Regul. Chaotic Dyn. 7, 2002).
//! Stated from geometry: the centre at height r above (x, y), the orientation by proper
//! Euler angles about y, z and y, R = R_y(α) R_z(β) R_y(γ). Gravity does no work on it (its
//! centre of mass stays at height r), so the model has none.
//!
//! n = 5 coordinates, two rolling constraints, three speeds: 8 states. Besides the energy,
//! the motion keeps the angular momentum about the contact point, M = I ω + m r² (ω −
//! ⟨ω, γ⟩ γ) for the upward vertical γ: its vertical component ⟨M, γ⟩ (Jellett's integral)
//! and its magnitude |M|² (Chaplygin's). The validation suite checks all three.
//!
//! The Euler angles are singular where the body's y axis is vertical (β = 0 or π): a ball
//! that turns mostly about an axis near the horizontal (a rolling ball, for example) keeps
//! far from it.

use crate::hamel_system;
use hamel::geometry::{Body, Contact, Inertia, Rotation3, Vector3};

#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct ChaplyginBall {
    /// mass (kg)
    pub m: f64,
    /// radius (m)
    pub r: f64,
    /// principal moments of inertia about the body's x, y and z axes (kg m²)
    pub i1: f64,
    pub i2: f64,
    pub i3: f64,
}

impl Default for ChaplyginBall {
    /// A ball of 10 cm radius and 1 kg whose moments differ by up to a factor of two.
    fn default() -> Self {
        ChaplyginBall {
            m: 1.0,
            r: 0.1,
            i1: 0.002,
            i2: 0.003,
            i3: 0.004,
        }
    }
}

#[hamel_system(
    coordinates(x, y, alpha, beta, gamma),
    speeds(alpha_rate, beta_rate, gamma_rate),
    constraints(slip_x, slip_y),
    bodies(ball),
    units(
        t = "s",
        x = "m",
        y = "m",
        alpha = "rad",
        beta = "rad",
        gamma = "rad",
        alpha_rate = "rad/s",
        beta_rate = "rad/s",
        gamma_rate = "rad/s",
        energy = "J"
    )
)]
impl ChaplyginBall {
    #[bodies]
    fn bodies(&self, q: &[f64; 5]) -> [Body; 1] {
        let orientation =
            Rotation3::about_y(q[2]) * Rotation3::about_z(q[3]) * Rotation3::about_y(q[4]);
        [Body::new(
            self.m,
            Inertia::principal(self.i1, self.i2, self.i3),
            Vector3::new(q[0], q[1], self.r),
            orientation,
        )]
    }

    /// The ball touches the ground straight below its centre.
    #[contacts]
    fn contacts(&self, q: &[f64; 5]) -> [Contact; 1] {
        let [ball] = self.bodies(q);
        [Contact::ground(ball, Vector3::new(q[0], q[1], 0.0))]
    }

    #[quasi_velocities]
    fn rates(&self, _q: &[f64; 5], qd: &[f64; 5]) -> [f64; 3] {
        [qd[2], qd[3], qd[4]]
    }
}
