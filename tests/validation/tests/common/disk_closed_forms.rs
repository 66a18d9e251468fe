//! Closed-form motions of the vertical rolling disk (`hamel::models::VerticalDisk`), free and
//! tied to a stiff torsional spring and damper: the known answers of the implicit
//! integrators' tests and of the long-run and stiff benchmarks.
//!
//! * The free disk (Bloch, *Nonholonomic Mechanics and Control*, §1.4): q = (x, y, θ, φ),
//!   L = ½m(ẋ² + ẏ²) + ½I θ̇² + ½J φ̇², rows ẋ − R cos φ θ̇ = 0, ẏ − R sin φ θ̇ = 0. The
//!   Lagrange–d'Alembert equations are m ẍ = λ₁, m ÿ = λ₂, I θ̈ = −R cos φ λ₁ − R sin φ λ₂,
//!   J φ̈ = 0; differentiating the rows, ẍ = R cos φ θ̈ − R sin φ θ̇ φ̇ (and ÿ alike), which
//!   in the θ equation gives (I + mR²) θ̈ = 0. So θ̇ = ω_θ and φ̇ = ω_φ are constant, and
//!   x = x₀ + (R ω_θ/ω_φ)(sin φ − sin φ₀), y = y₀ − (R ω_θ/ω_φ)(cos φ − cos φ₀),
//!   λ₁ = −m R ω_θ ω_φ sin φ, λ₂ = m R ω_θ ω_φ cos φ.
//!
//! * The stiff disk ([`StiffDisk`]): the same disk with a torsional spring k and a damper c
//!   acting on the rolling angle, f_θ = −k θ − c θ̇. The rows are unchanged, so φ̇ = ω_φ and,
//!   as above, (I + mR²) θ̈ = −k θ − c θ̇: a damped oscillator. With I + mR² = 1, k = 10⁶ and
//!   c = 10⁶ + 1 its characteristic polynomial is λ² + (10⁶ + 1) λ + 10⁶ = (λ + 1)(λ + 10⁶):
//!   a slow mode e^(−t) and a fast one e^(−10⁶ t), so θ = a e^(−t) + b e^(−10⁶ t) with
//!   a + b = θ₀, −a − 10⁶ b = θ̇₀. The contact point integrates R θ̇ along the heading:
//!   x = x₀ + R Σ_μ μ c_μ ∫₀ᵗ e^(μs) cos(φ₀ + ω_φ s) ds (μ = −1, −10⁶; c_μ = a, b), with
//!   ∫ e^(μs) cos(φ₀ + ωs) ds = e^(μs)(μ cos(φ₀ + ωs) + ω sin(φ₀ + ωs))/(μ² + ω²), and y with
//!   sin in place of cos, ∫ e^(μs) sin(φ₀ + ωs) ds = e^(μs)(μ sin(φ₀ + ωs) − ω cos(φ₀ + ωs))
//!   /(μ² + ω²) (elementary integrals; derived here, checked by differences in the tests).

use hamel::hamel_system;

/// The free disk's motion from (x₀, y₀, θ₀, φ₀) with speeds (ω_θ, ω_φ), ω_φ ≠ 0.
#[derive(Clone, Copy, Debug)]
pub struct FreeDisk {
    pub m: f64,
    pub r: f64,
    pub start: [f64; 4],
    pub roll: f64,
    pub turn: f64,
}

impl FreeDisk {
    /// The state (x, y, θ, φ, ω_θ, ω_φ) at time t.
    pub fn state(&self, t: f64) -> [f64; 6] {
        let [x0, y0, theta0, phi0] = self.start;
        let phi = phi0 + self.turn * t;
        let radius = self.r * self.roll / self.turn;
        [
            x0 + radius * (phi.sin() - phi0.sin()),
            y0 - radius * (phi.cos() - phi0.cos()),
            theta0 + self.roll * t,
            phi,
            self.roll,
            self.turn,
        ]
    }

    /// The multipliers (λ₁, λ₂) of the rows ẋ − R cos φ θ̇, ẏ − R sin φ θ̇ at time t.
    pub fn multipliers(&self, t: f64) -> [f64; 2] {
        let phi = self.start[3] + self.turn * t;
        let scale = self.m * self.r * self.roll * self.turn;
        [-scale * phi.sin(), scale * phi.cos()]
    }
}

/// The vertical disk with a torsional spring (potential ½kθ²) and a damper (force −cθ̇) on
/// its rolling angle.
#[hamel_system]
#[derive(Clone, Debug, PartialEq)]
pub struct StiffDisk {
    /// mass (kg)
    pub m: f64,
    /// moment of inertia about the axle (kg m²)
    pub i_roll: f64,
    /// moment of inertia about the vertical diameter (kg m²)
    pub i_turn: f64,
    /// radius (m)
    pub r: f64,
    /// torsional stiffness on the rolling angle (N m/rad)
    pub k: f64,
    /// torsional damping on the rolling angle (N m s/rad)
    pub c: f64,
}

impl Default for StiffDisk {
    /// I + mR² = 0.75 + 1·0.5² = 1, k = 10⁶, c = 10⁶ + 1: modes e^(−t) and e^(−10⁶ t).
    fn default() -> Self {
        StiffDisk {
            m: 1.0,
            i_roll: 0.75,
            i_turn: 0.0625,
            r: 0.5,
            k: 1e6,
            c: 1e6 + 1.0,
        }
    }
}

#[hamel_system(
    coordinates(x, y, theta, phi),
    speeds(roll, turn),
    constraints(rolling_x, rolling_y)
)]
impl StiffDisk {
    #[kinetic_energy]
    pub fn kinetic_energy(&self, _q: &[f64; 4], qd: &[f64; 4]) -> f64 {
        0.5 * self.m * (qd[0] * qd[0] + qd[1] * qd[1])
            + 0.5 * self.i_roll * qd[2] * qd[2]
            + 0.5 * self.i_turn * qd[3] * qd[3]
    }

    #[potential_energy]
    pub fn spring(&self, q: &[f64; 4]) -> f64 {
        0.5 * self.k * q[2] * q[2]
    }

    #[constraints]
    pub fn rolling(&self, q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        let (s, c) = q[3].sin_cos();
        [qd[0] - self.r * c * qd[2], qd[1] - self.r * s * qd[2]]
    }

    #[quasi_velocities]
    pub fn speeds(&self, _q: &[f64; 4], qd: &[f64; 4]) -> [f64; 2] {
        [qd[2], qd[3]]
    }

    #[forces]
    pub fn damper(&self, _t: f64, _q: &[f64; 4], qd: &[f64; 4], _u: &[f64; 0]) -> [f64; 4] {
        [0.0, 0.0, -self.c * qd[2], 0.0]
    }
}

/// The stiff disk's closed-form motion (module documentation) for the default parameters'
/// modes μ = −1 and −10⁶.
#[derive(Clone, Copy, Debug)]
pub struct StiffMotion {
    pub r: f64,
    pub start: [f64; 4],
    pub turn: f64,
    /// The modes μ and their amplitudes in θ.
    pub modes: [(f64, f64); 2],
}

impl StiffMotion {
    /// From (x₀, y₀, θ₀, φ₀) with θ̇₀ and ω_φ, for a disk whose modes are `slow` and `fast`.
    pub fn new(r: f64, start: [f64; 4], roll0: f64, turn: f64, (slow, fast): (f64, f64)) -> Self {
        // a + b = θ₀, slow·a + fast·b = θ̇₀.
        let theta0 = start[2];
        let b = (roll0 - slow * theta0) / (fast - slow);
        let a = theta0 - b;
        StiffMotion {
            r,
            start,
            turn,
            modes: [(slow, a), (fast, b)],
        }
    }

    /// The state (x, y, θ, φ, θ̇, φ̇) at time t.
    pub fn state(&self, t: f64) -> [f64; 6] {
        let [x0, y0, _, phi0] = self.start;
        let w = self.turn;
        let phi = phi0 + w * t;
        let (mut x, mut y, mut theta, mut roll) = (x0, y0, 0.0, 0.0);
        for (mu, c) in self.modes {
            let e = (mu * t).exp();
            theta += c * e;
            roll += mu * c * e;
            let d = mu * mu + w * w;
            let cos_integral = |s: f64, e: f64| {
                let p = phi0 + w * s;
                e * (mu * p.cos() + w * p.sin()) / d
            };
            let sin_integral = |s: f64, e: f64| {
                let p = phi0 + w * s;
                e * (mu * p.sin() - w * p.cos()) / d
            };
            x += self.r * mu * c * (cos_integral(t, e) - cos_integral(0.0, 1.0));
            y += self.r * mu * c * (sin_integral(t, e) - sin_integral(0.0, 1.0));
        }
        [x, y, theta, phi, roll, w]
    }
}
